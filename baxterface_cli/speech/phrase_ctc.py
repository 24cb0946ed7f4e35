"""Phrases heard by hama's phoneme recogniser (a CTC model, the `[lipsync]` extra;
phoneme_recogniser.py), as the word spotter hears them where hama runs.

The recogniser gives, every 20 ms, a likelihood for each of its IPA phonemes and for "nothing new"
(CTC's blank). Its phonemes are gathered into pocketsphinx's phones (`phoneme_recogniser.phones`:
ə and ʌ are both AH), so a phrase is spelled as pocketsphinx's dictionary spells it (each of its
spellings). A phrase's score is the best way its phones, one after another, lay over some stretch
of the frames (a Viterbi alignment that starts and ends anywhere), against the best phone of each
of those frames whatever it is (the "filler"): 0 when the recogniser heard just that phrase, more
negative the worse it fits; per phone, so one threshold suits short and long phrases. A phone may
be heard as one of its kind (`KINDS`, `SIMILAR_PHONE`: R as L, B as D), a vowel as another
(`OTHER_VOWEL`), any phone as another (`OTHER_PHONE`), at a cost: synthetic and accented voices
say "robot" as ɹoʊbət, ɹoʊbɑt or loʊbɑt, and "hello" loses its h. The costs and the threshold
were tuned by bench/bench_words.py on two voices, and measured on five others (docs/speech.md).

The model hears a whole stretch at once (each frame depends on all the sound given), so it is run
on the last `window` seconds every `HOP`, and a phrase is told once it ends `MARGIN` before the
window's end (the model must hear it end), once (`ReportedSpans`).
"""

from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np

from . import phoneme_recogniser

RATE = 16000
FRAME_SAMPLES = 320  # hama's frames: 20 ms at 16 kHz
THRESHOLD = -0.6  # a phrase's score per phone (natural log) to be told: bench/bench_words.py --tune
SIMILAR_PHONE = 1.0  # costs (natural log, against the phone spelled) of hearing another phone
OTHER_VOWEL = 1.5
OTHER_PHONE = 3.0
# Phones that voices and the recogniser trade for one another: "robot" comes out as "lobot" in
# British voices, "hello" as "the low".
KINDS = (
    ("IY", "IH", "EY", "EH", "AE"),
    ("AH", "ER", "AA", "AO", "OW", "UH", "UW"),
    ("L", "R", "W", "Y"),
    ("M", "N", "NG"),
    ("B", "D", "G"),
    ("P", "T", "K"),
    ("F", "V", "TH", "DH", "HH"),
    ("S", "Z", "SH", "ZH", "CH", "JH"),
)
HOP = 0.15  # seconds of sound between two looks
MARGIN = 0.1  # seconds heard after a phrase's end before it is told
LEAD = 0.6  # seconds of sound a window holds before its longest phrase (context for the model)
PHONE_SECONDS = 0.13  # room for each phone of the longest phrase
MOST_WINDOW = 3.0
QUIET = 100.0  # RMS (of int16) under which a hop's sound is silence: no look while the window is all that


def _loudness(samples: np.ndarray) -> float:
    """RMS about the block's mean: a constant offset (a file of zero bytes in 8-bit or mu-law is
    one at full scale) is silence to the ear, and is not looked at for ten minutes as if it spoke."""
    values = samples.astype(np.float64)
    return float(np.sqrt(np.mean((values - values.mean()) ** 2)))


def _classes(tokens: Sequence[str]) -> Tuple[List[str], np.ndarray]:
    """The phones ("-" first: nothing new), and for each of the recogniser's tokens the index of the
    phone it stands for (its first; the blank, word breaks, marks and tones stand for "-")."""
    firsts = [phoneme_recogniser.phones(t)[:1] for t in tokens]
    names = ["-"] + sorted({f[0] for f in firsts if f})
    index = {name: i for i, name in enumerate(names)}
    return names, np.array([index[f[0]] if f else 0 for f in firsts])


class PhraseScorer:
    """Scores phrases, spelled in pocketsphinx's phones, in hama's view of a sound."""

    def __init__(self) -> None:
        self._model = phoneme_recogniser._model()
        self.names, self._of_token = _classes(self._model.decoder_tokens)
        self._index = {name: i for i, name in enumerate(self.names)}
        self._vowels = np.array([n in phoneme_recogniser.VOWELS for n in self.names])
        kind = {phone: i for i, phones in enumerate(KINDS) for phone in phones}
        self._similar = {
            name: np.array([o != name and kind.get(o, -1) == kind.get(name, -2) for o in self.names])
            for name in self.names
        }

    def frames(self, samples: np.ndarray) -> np.ndarray:
        """Each 20 ms frame's log-likelihood of each phone against the best ("-" first), given
        int16 samples at 16 kHz."""
        wav = (np.asarray(samples, np.float32) / 32768.0).reshape(1, -1)
        with phoneme_recogniser._LOCK:
            log_probs, lengths = self._model.session.run(
                ["log_probs", "out_lengths"],
                {"waveform": wav, "waveform_lengths": np.array([wav.shape[1]], np.int64)},
            )
        tokens = np.asarray(log_probs[0][: int(np.asarray(lengths).reshape(-1)[0])], np.float64)
        probs = np.exp(tokens - tokens.max(axis=1, keepdims=True))
        grouped = np.zeros((len(self.names), len(tokens)))
        np.add.at(grouped, self._of_token, probs.T)
        grouped = np.log(grouped.T + 1e-30)
        return grouped - grouped.max(axis=1, keepdims=True)

    def fit(self, frames: np.ndarray, phones: Sequence[str], ends: Tuple[int, int]) -> Tuple[float, int, int]:
        """(score per phone, first frame, frame after the last) of the best alignment of `phones`
        over `frames` that ends within `ends` (frames; see the module's docstring)."""
        if len(frames) == 0 or not phones:
            return -np.inf, 0, 0
        best_vowel = np.where(self._vowels, frames, -np.inf).max(axis=1) - OTHER_VOWEL
        best_other = frames[:, 1:].max(axis=1) - OTHER_PHONE
        columns = []
        for phone in phones:
            own = frames[:, self._index[phone]]
            if phone in phoneme_recogniser.VOWELS:
                own = np.maximum(own, best_vowel)
            if self._similar[phone].any():
                own = np.maximum(own, frames[:, self._similar[phone]].max(axis=1) - SIMILAR_PHONE)
            columns.append(np.maximum(own, best_other))
        emit = np.stack(columns, axis=1).tolist()  # plain floats: the loop below is over a few states
        blank = frames[:, 0].tolist()
        n = len(phones)
        distinct = [k > 0 and phones[k] != phones[k - 1] for k in range(n)]
        inf = float("-inf")
        on = [inf] * n  # the best path's score and start on phone k, or on the blank after it
        after = [inf] * n
        on_start = [0] * n
        after_start = [0] * n
        best = (inf, 0, 0)
        for t in range(min(len(blank), ends[1])):
            new_on, new_after = [0.0] * n, [0.0] * n
            new_on_start, new_after_start = [0] * n, [0] * n
            for k in range(n):
                if k == 0:
                    score, start = 0.0, t  # a fresh start beats staying on the first phone (scores <= 0)
                else:
                    score, start = on[k], on_start[k]
                    if after[k - 1] > score:
                        score, start = after[k - 1], after_start[k - 1]
                    if distinct[k] and on[k - 1] > score:
                        score, start = on[k - 1], on_start[k - 1]
                new_on[k], new_on_start[k] = score + emit[t][k], start
                score, start = (on[k], on_start[k]) if on[k] > after[k] else (after[k], after_start[k])
                new_after[k], new_after_start[k] = score + blank[t], start
            on, after, on_start, after_start = new_on, new_after, new_on_start, new_after_start
            if t + 1 >= ends[0] and on[n - 1] > best[0]:
                best = (on[n - 1], on_start[n - 1], t + 1)
        return best[0] / n, best[1], best[2]


class ReportedSpans:
    """Where each phrase was last told, so that the overlapping looks tell it once."""

    def __init__(self) -> None:
        self._last_end: dict = {}

    def new(self, phrase: str, start: int, end: int) -> bool:
        if start < self._last_end.get(phrase, -1):
            return False
        self._last_end[phrase] = end
        return True


class CtcSearch:
    """Phrases found in sound fed as it comes: `feed(samples)` gives (phrase, start, end) of each
    one completed, in samples since the first fed."""

    def __init__(
        self, spellings: Sequence[Tuple[str, Sequence[Sequence[str]]]], threshold: float = THRESHOLD
    ) -> None:
        self.scorer = PhraseScorer()
        self.spellings = [(phrase, [list(s) for s in spelled]) for phrase, spelled in spellings]
        longest = max(len(s) for _, spelled in self.spellings for s in spelled)
        self.window = int(min(MOST_WINDOW, LEAD + PHONE_SECONDS * longest) * RATE)
        self.threshold = threshold
        self._sound = np.zeros(0, np.int16)
        self._fed = 0  # samples fed in all
        self._looked = 0  # samples fed at the last look
        self._heard_until = 0  # the last sample of the last hop with sound over QUIET
        self._told = ReportedSpans()

    def feed(self, samples: np.ndarray) -> List[Tuple[str, int, int]]:
        self._sound = np.concatenate([self._sound, samples])[-self.window :]
        self._fed += len(samples)
        if len(samples) and _loudness(samples) > QUIET:
            self._heard_until = self._fed
        if self._fed - self._looked < HOP * RATE:
            return []
        looked, self._looked = self._looked, self._fed
        if self._fed - self._heard_until > self.window:
            return []  # nothing but silence in the window
        return self._look(looked)

    def _look(self, looked: int) -> List[Tuple[str, int, int]]:
        frames = self.scorer.frames(self._sound)
        first = self._fed - len(self._sound)  # the window's first sample
        margin = int(MARGIN * RATE)
        # what ends after the last look's decided part, and MARGIN before this window's end
        lo = max(0, (looked - margin - first) // FRAME_SAMPLES)
        hi = max(0, (self._fed - margin - first) // FRAME_SAMPLES)
        found = []
        for phrase, spelled in self.spellings:
            score, start, end = max(self.scorer.fit(frames, s, (lo + 1, hi)) for s in spelled)
            if score >= self.threshold and end > lo:
                at = (first + start * FRAME_SAMPLES, first + end * FRAME_SAMPLES)
                if self._told.new(phrase, *at):
                    found.append((phrase, at[0], at[1]))
        return found
