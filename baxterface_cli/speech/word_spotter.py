"""Words heard from a microphone or a recording, offline (the `[lipsync]` extra, whose wheels ship
their models; nothing is downloaded).

A `WordSpotter` is given the phrases a script's `on word "..."` handlers wait for, and takes
audio in blocks (16 kHz mono int16) as it comes. Each phrase it hears is told to `on_word`
with the time it ended, on the caller's clock. It knows no ROS, device or session: a
microphone (sound_device.Microphone), a recording (`spot_file`) or a test feeds it.

Each phrase is spelled by pocketsphinx's dictionary (a word it lacks is a WordError). Where hama's
phoneme recogniser runs (Python 3.9 on), the phrase's phones are found in what it hears
(phrase_ctc.py: about twice as few false alarms as pocketsphinx for as many phrases heard, on
voices nothing was tuned on; docs/speech.md). Elsewhere pocketsphinx's keyphrase search listens
alone; how sure it must be grows with a phrase's length (a product of its phones' likelihoods),
so its threshold is a power of ten per phone (`PER_PHONE`). Both are tuned by
bench/bench_words.py --tune.

The face does not hear itself: a phrase heard while `speaking(at)` says the face was speaking,
at the phrase's start or end or within `ECHO` after the face stopped, is ignored (and counted),
unless `barge_in`.
"""

from __future__ import annotations

import os
import tempfile
import threading
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ..core.face_constants import LIMITS
from ..extras import need
from .audio_files import EXTRA, read_sound

RATE = 16000  # the English model's
FRAME = 0.01  # pocketsphinx's frames: 100 a second
PER_PHONE = 4.0  # kws_threshold = 1e-(PER_PHONE * phones): tuned by bench/bench_words.py --tune
MOST_THRESHOLD = 60.0  # a long phrase's exponent stops here: beyond, anything at all passes
ECHO = 0.3  # seconds after the face stops speaking that its voice still fills the room
RESTART = 20.0  # seconds of sound after which the search starts afresh (between phrases)


class Heard(NamedTuple):
    word: str  # the phrase as the script wrote it
    at: float  # when it ended, on the caller's clock
    start: float


class WordError(ValueError):
    """A phrase the model cannot spot (a word not in its dictionary); the message says which."""


def phrase_of(text: str) -> str:
    """A phrase as it is spotted: lower case, single spaces."""
    return " ".join(text.lower().split())


def threshold(phones: int, per_phone: float = PER_PHONE) -> float:
    """pocketsphinx's kws_threshold for a phrase of `phones` phones."""
    return 10.0 ** -min(MOST_THRESHOLD, per_phone * max(1, phones))


def _pocketsphinx() -> Any:
    return need("pocketsphinx", EXTRA, "hearing words")


class _KeyphraseSearch:
    """pocketsphinx's keyphrase search (where hama cannot run): (phrase, start, end) in samples."""

    def __init__(self, ps: Any, phones: Dict[str, int], per_phone: float) -> None:
        lines = [f"{phrase} /{threshold(n, per_phone):.3g}/\n" for phrase, n in phones.items()]
        handle, path = tempfile.mkstemp(suffix=".kws", prefix="baxterface-")
        try:
            with os.fdopen(handle, "w") as f:
                f.writelines(lines)
            self._decoder = ps.Decoder(kws=path, loglevel="FATAL")
        finally:
            os.unlink(path)
        self._offset = 0  # samples fed before this utterance began
        self._samples = 0  # fed since it began
        self._last_found = 0
        self._told: Dict[tuple, bool] = {}
        self._decoder.start_utt()

    def feed(self, samples: np.ndarray) -> List[Tuple[str, int, int]]:
        self._decoder.process_raw(samples.tobytes(), False, False)
        self._samples += len(samples)
        found = []
        if self._decoder.hyp() is not None:
            for seg in self._decoder.seg():
                key = (seg.word, seg.start_frame)
                if key not in self._told:
                    self._told[key] = True
                    at = [self._offset + int(f * FRAME * RATE) for f in (seg.start_frame, seg.end_frame)]
                    found.append((seg.word, at[0], at[1]))
                    self._last_found = self._samples
        if self._samples > RESTART * RATE and self._samples - self._last_found > RATE:
            # a long search's segments grow; cut where no phrase was just heard
            self._decoder.end_utt()
            self._decoder.start_utt()
            self._offset += self._samples
            self._samples = self._last_found = 0
            self._told.clear()
        return found

    def close(self) -> None:
        self._decoder.end_utt()


class WordSpotter:
    """Phrases heard in audio fed block by block (see the module's docstring).

    `clock()` gives the time at which the block being fed ended (the sound's last sample was
    heard); `feed(block, end=...)` may say it instead (a recording's own time). `method` is
    "ctc" (hama's recogniser: the default where it runs) or "keyphrase" (pocketsphinx alone).
    """

    def __init__(
        self,
        words: Sequence[str],
        on_word: Callable[[str, float], None],
        clock: Optional[Callable[[], float]] = None,
        speaking: Optional[Callable[[float], bool]] = None,
        barge_in: bool = False,
        per_phone: float = PER_PHONE,
        method: Optional[str] = None,
        ctc_threshold: Optional[float] = None,
    ) -> None:
        ps = _pocketsphinx()
        self.words = list(dict.fromkeys(phrase_of(w) for w in words if w.strip()))
        if not self.words:
            raise WordError("no words to listen for")
        self.on_word = on_word
        self.clock = clock
        self.speaking = speaking
        self.barge_in = barge_in
        self.heard: List[Heard] = []  # everything told to on_word, in order
        self.ignored: List[Heard] = []  # heard while the face spoke
        self._lock = threading.Lock()  # a microphone's thread feeds; `close` may come from another
        spellings = _spellings(ps.Decoder(lm=None, loglevel="FATAL"), self.words)
        self.phones = sum(len(s) for spelled in spellings.values() for s in spelled)
        if self.phones > LIMITS.max_phones:
            raise WordError(
                f"too much to listen for: {_phrases(self.words)} of {self.phones} phones, every "
                f"spelling counted (the limit is {LIMITS.max_phones})"
            )
        if method is None:
            from . import phoneme_recogniser

            method = "ctc" if phoneme_recogniser.available() else "keyphrase"
        self.method = method
        if method == "ctc":
            from .phrase_ctc import THRESHOLD, CtcSearch

            self._search: Any = CtcSearch(
                list(spellings.items()), THRESHOLD if ctc_threshold is None else ctc_threshold
            )
        else:
            phones = {phrase: len(spelled[0]) for phrase, spelled in spellings.items()}
            self._search = _KeyphraseSearch(ps, phones, per_phone)
        self._samples = 0  # fed in all

    def feed(self, block: np.ndarray, end: Optional[float] = None) -> List[Heard]:
        """Take a block of 16 kHz mono int16 samples; the phrases it completed (also told to
        `on_word`, unless the face was speaking)."""
        if end is None:
            end = self.clock() if self.clock is not None else (self._samples + len(block)) / RATE
        samples = np.ascontiguousarray(block, dtype=np.int16).reshape(-1)
        with self._lock:
            found = self._search.feed(samples) if len(samples) else []
            self._samples += len(samples)
            fed_end = self._samples
        told = []
        for phrase, first, last in found:
            ago = (fed_end - last) / RATE
            heard = Heard(phrase_of(phrase), end - ago, end - ago - (last - first) / RATE)
            if self._muted(heard):
                self.ignored.append(heard)
            else:
                self.heard.append(heard)
                told.append(heard)
                self.on_word(heard.word, heard.at)
        return told

    def _muted(self, heard: Heard) -> bool:
        if self.barge_in or self.speaking is None:
            return False
        return any(self.speaking(t) for t in (heard.start, heard.at, heard.start - ECHO))

    def close(self) -> None:
        with self._lock:
            if hasattr(self._search, "close"):
                self._search.close()


def _spellings(lookup: Any, phrases: Sequence[str]) -> Dict[str, List[List[str]]]:
    """Each phrase's spellings in pocketsphinx's phones: its words' first spellings one after another,
    and the phrase with each word's other spellings in turn ("hello": HH AH L OW, HH EH L OW)."""
    out = {}
    for phrase in phrases:
        words = []
        for word in phrase.split():
            found = lookup.lookup_word(word)
            if found is None:
                raise WordError(f"'{word}' is not a word the speech model knows (in \"{phrase}\")")
            spelled = [found.split()]
            for i in range(2, 6):
                other = lookup.lookup_word(f"{word}({i})")
                if other is None:
                    break
                spelled.append(other.split())
            words.append(spelled)
        first = [w[0] for w in words]
        variants = [first] + [first[:i] + [s] + first[i + 1 :] for i, w in enumerate(words) for s in w[1:]]
        out[phrase] = [[p for w in v for p in w] for v in variants]
    return out


def read_recording(path: str) -> np.ndarray:
    """A recording's samples as 16 kHz mono int16, read as `say file` reads one: any format FFmpeg
    takes, bounded in size, length and time (AudioError, saying why, otherwise)."""
    return read_sound(path).analysis


def _phrases(words: Sequence[str]) -> str:
    return f"{len(words)} phrase" + ("" if len(words) == 1 else "s")


def listenable(words: Sequence[str]) -> Tuple[List[str], List[Tuple[str, str]], List[str]]:
    """The phrases a spotter may listen for at once, in order: those the model can spot while their
    phones stay within LIMITS.max_phones; each it cannot, with why; and those past the phones."""
    lookup = _pocketsphinx().Decoder(lm=None, loglevel="FATAL")
    kept: List[str] = []
    unknown: List[Tuple[str, str]] = []
    over: List[str] = []
    phones = 0
    for phrase in dict.fromkeys(phrase_of(w) for w in words if w.strip()):
        try:
            count = sum(len(s) for s in _spellings(lookup, [phrase])[phrase])
        except WordError as e:
            unknown.append((phrase, str(e)))
            continue
        if phones + count > LIMITS.max_phones:
            over.append(phrase)
        else:
            kept.append(phrase)
            phones += count
    return kept, unknown, over
