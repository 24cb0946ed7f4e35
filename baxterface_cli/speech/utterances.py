"""Words heard as a person hears them: utterances found, transcribed while they go on, and the
phrases listened for matched in their words (the `[hear]` extra).

Silero's detector (voice_activity.py) gives every 32 ms the chance that someone speaks; an
utterance begins when it passes `ONSET` (with `LEAD` of the sound before, for the first word's
start) and ends after `END_QUIET` under `OFFSET`; a chunk near the room's floor, or far under the
loudest of the last seconds, is quiet whatever the detector says (voices further away are speech,
but not the visitor's). While it goes on, Moonshine (moonshine.py)
transcribes its last `WINDOW` seconds every `HOP`; a phrase found as whole words in two looks in a
row, or in one after `SURE` of quiet (the last word is whole then), is told to `on_word` at once;
a look that finds a phrase not yet told is followed by the next after `CONFIRM`, not `HOP`.
When the utterance ends it is transcribed whole, in `PAD` of silence, the bias reaching the phrases
capitalised too (as said alone, an answer): each phrase is told as many more times as it says it
(`times`), and its words go to `on_heard`.

The looks cost work only while someone speaks; live, they are spaced so that listening takes at
most `CPU_SHARE` of a core (a slower machine looks less often, and hears a phrase later, not less);
in a recording (`--hear`), every `HOP`, so a render hears the same on any machine.

The face does not hear itself: sound heard while `speaking(at)` says the face was speaking, or
within `ECHO` after, is taken as silence, unless `barge_in`; then an utterance the face spoke in
has no phrase told that the face itself was saying then (`saying(start, end)`: its words), and
is not told at all if all its words are the face's.
"""

from __future__ import annotations

import re
import threading
import time
from collections import Counter
from typing import Callable, List, NamedTuple, Optional, Sequence, Set, Tuple
from typing import Counter as Counts

import numpy as np

from . import moonshine
from .voice_activity import CHUNK, VoiceActivity
from .word_spotter import Heard

RATE = 16000
ONSET = 0.5  # a chunk's speech chance that begins an utterance
OFFSET = 0.35  # under this, a chunk is quiet
END_QUIET = 0.5  # seconds of quiet that end an utterance
LEAD = 0.3  # seconds of sound before the onset an utterance keeps
SHORTEST = 0.2  # seconds of speech under which a sound is a cough, not an utterance
LONGEST = 20.0  # seconds after which an utterance is cut (and heard) even if it goes on
WINDOW = 5.0  # seconds of an utterance's end each look transcribes
HOP = 0.2  # seconds of sound between two looks, at least
FLOOR = 5.0  # seconds of sound whose quietest tenth is the room's floor
LOUDER = 10 ** (6 / 20)  # speech is 6 dB over the floor, at least
UNDER = 10 ** (-10 / 20)  # and 10 dB under the loudest, at most
SMOOTH = 0.38  # seconds the level is measured over
CPU_SHARE = 0.5  # of a core, at most, that the looks take while someone speaks
SURE = 0.15  # seconds of quiet after which a look's phrases are told at once, not at the next
CONFIRM = 0.1  # seconds of sound after a look that found a phrase, and the look that confirms it
BIAS = 2.0  # added to the scores of the tokens spelling the phrases: bench/bench_hearing.py --tune
PAD = 0.4  # seconds of silence before and after an utterance transcribed whole
ECHO = 0.3  # seconds after the face stops speaking that its voice still fills the room
ARTICLES = ("a", "an", "the")
WEAK = ("a", "an", "the", "to", "that", "this", "uh")  # what an unstressed article is heard as


class Said(NamedTuple):
    text: str  # the utterance's words, lower case, without punctuation
    at: float  # when it ended
    start: float


def words_of(text: str) -> List[str]:
    """Lower-case words, as a transcript and a phrase are compared: punctuation is a break,
    apostrophes are kept inside a word ("don't")."""
    return re.findall(r"[a-z0-9]+(?:'[a-z0-9]+)*", text.lower())


def forms(phrase: Sequence[str]) -> List[Tuple[str, ...]]:
    """The phrase, and the same with an article heard as another short word or not at all ("tell
    me a joke" is heard as "tell me the joke", "tell me to joke"): said unstressed, it is a schwa
    the recogniser spells as it likes."""
    found = [tuple(phrase)]
    for i, word in enumerate(phrase):
        if word in ARTICLES and len(phrase) > 2:
            found += [
                tuple(phrase[:i]) + (other,) + tuple(phrase[i + 1 :]) for other in WEAK if other != word
            ]
            found.append(tuple(phrase[:i]) + tuple(phrase[i + 1 :]))
    return found


def times(words: Sequence[str], phrase: Sequence[str]) -> int:
    """How often `phrase` is said in `words`, as whole words (any of its `forms`); said again
    straight after itself it counts once ("hello hello": the recogniser's echo of a short word, as
    often as a person's)."""
    count, i, after, said = 0, 0, -1, tuple(words)
    variants = forms(phrase) if phrase else []
    while i < len(said):
        size = next((len(v) for v in variants if v and said[i : i + len(v)] == v), 0)
        count += bool(size) and i != after
        after = i + size if size else after
        i += size or 1
    return count


def holds(words: Sequence[str], phrase: Sequence[str]) -> bool:
    return times(words, phrase) > 0


class UtteranceListener:
    """Phrases and utterances heard in audio fed block by block (see the module's docstring);
    the same interface as word_spotter.WordSpotter, and `on_heard(text, at)` besides."""

    method = "moonshine"

    def __init__(
        self,
        words: Sequence[str],
        on_word: Callable[[str, float], None],
        clock: Optional[Callable[[], float]] = None,
        speaking: Optional[Callable[[float], bool]] = None,
        barge_in: bool = False,
        on_heard: Optional[Callable[[str, float], None]] = None,
        saying: Optional[Callable[[float, float], str]] = None,
        bias: float = BIAS,
        paced: bool = True,
    ) -> None:
        """`paced`: looks spaced by their cost, at most `CPU_SHARE` of a core (live sound); else
        every `HOP` (a recording: what is heard in it does not depend on the machine's load)."""
        self.words = list(dict.fromkeys(" ".join(words_of(w)) for w in words if words_of(w)))
        self._phrases = [(w, w.split()) for w in self.words]
        self.on_word = on_word
        self.on_heard = on_heard
        self.clock = clock
        self.speaking = speaking
        self.saying = saying
        self.barge_in = barge_in
        self.heard: List[Heard] = []  # every phrase told to on_word, in order
        self.ignored: List[Heard] = []  # phrases the face itself was saying (with barge-in)
        self.said: List[Said] = []  # every utterance told to on_heard
        self.ignored_said: List[Said] = []  # utterances of the face's own words (with barge-in)
        self.model = moonshine.transcriber()
        # A look favours the phrases as written mid-sentence; the whole utterance, capitalised at
        # its start too (an answer said alone: joe's fast "go on" was "Dillon" at 5 of 14 starts).
        # A look at a sentence's first second, biased to capitals, heard "what is your name" in
        # "well, no th..."; the whole one does not.
        self._favoured = [self.model.spelling(w) for w in self.words]
        self._favoured_whole = [spelled for w in self.words for spelled in self.model.spellings(w)]
        self.bias = bias
        self.paced = paced
        self._vad = VoiceActivity()
        self._powers: List[float] = []  # the last SMOOTH seconds' chunks' mean squares
        # the level at each chunk over the last FLOOR seconds: silence before the first
        self._levels = [0.0] * int(FLOOR * RATE / CHUNK)
        self._lock = threading.Lock()
        self._fed = 0  # samples fed in all
        self._pending = np.zeros(0, np.int16)  # fed, short of a whole chunk
        self._recent = np.zeros(0, np.int16)  # the last LEAD seconds, for an utterance's start
        self._sound: List[np.ndarray] = []  # the utterance going on, chunk by chunk
        self._first = 0  # its first sample (since the first fed)
        self._quiet = 0  # samples of quiet at its end
        self._spoken = 0  # samples of speech in it
        self._looked = 0  # samples fed at the last look
        self._pace = 0.0  # seconds of sound the last look's work spaces the next one by (live)
        self._told: Counts[str] = Counter()  # times each phrase was told in this utterance
        self._seen: Set[str] = set()  # phrases found in the last look

    def feed(self, block: np.ndarray, end: Optional[float] = None) -> List[Heard]:
        """Take a block of 16 kHz mono int16 samples; the phrases told because of it."""
        samples = np.ascontiguousarray(block, dtype=np.int16).reshape(-1)
        if end is None:
            end = self.clock() if self.clock is not None else (self._fed + len(samples)) / RATE
        told: List[Heard] = []
        with self._lock:
            self._fed += len(samples)
            origin = end - self._fed / RATE  # the caller's time of the first sample fed
            sound = np.concatenate([self._pending, samples])
            first = self._fed - len(sound)  # sound[0]'s place among all the samples fed
            whole = len(sound) // CHUNK * CHUNK
            for at in range(0, whole, CHUNK):
                chunk = sound[at : at + CHUNK]
                start = first + at
                if self._muted(origin + start / RATE, origin + (start + CHUNK) / RATE):
                    chunk = np.zeros(CHUNK, np.int16)
                chance = self._vad.chance(chunk) if self._loud(chunk) else 0.0
                told += self._chunk(chunk, chance, start, origin)
                self._recent = np.concatenate([self._recent, chunk])[-int(LEAD * RATE) :]
            self._pending = sound[whole:]
        return told

    def _loud(self, chunk: np.ndarray) -> bool:
        """Is the sound's level (over the last `SMOOTH` seconds) `LOUDER` than the room's floor (the
        quietest tenth of the last `FLOOR` seconds), and no more than `UNDER` below their loudest
        tenth? Other voices under a visitor's (babble) are speech too, but quieter than theirs:
        without this an utterance would never end while they talk."""
        self._powers.append(float(np.mean(chunk.astype(np.float64) ** 2)))
        del self._powers[: -int(SMOOTH * RATE / CHUNK)]
        level = float(np.sqrt(np.mean(self._powers)))
        floor, top = np.percentile(self._levels, [10, 90])
        self._levels.append(level)
        del self._levels[0]
        return level > max(floor * LOUDER, top * UNDER)

    def _muted(self, start: float, end: float) -> bool:
        if self.barge_in or self.speaking is None:
            return False
        return any(self.speaking(t) for t in (start, end, start - ECHO))

    def _chunk(self, chunk: np.ndarray, chance: float, first: int, origin: float) -> List[Heard]:
        if not self._sound:
            if chance < ONSET:
                return []
            lead = self._recent
            self._sound = [lead, chunk]
            self._first = first - len(lead)
            self._quiet = self._spoken = 0
            self._looked = first
            self._told, self._seen = Counter(), set()
            return []
        self._sound.append(chunk)
        if chance < OFFSET:
            self._quiet += CHUNK
        else:
            self._quiet = 0
            self._spoken += CHUNK
        length = sum(len(s) for s in self._sound)
        if self._quiet >= END_QUIET * RATE or length >= LONGEST * RATE:
            return self._end(origin)
        # a phrase the last look found and did not tell is confirmed sooner than the next hop
        gap = max(CONFIRM if any(not self._told[p] for p in self._seen) else HOP, self._pace)
        if first + CHUNK - self._looked >= gap * RATE:
            return self._look(origin, first + CHUNK)
        return []

    def _transcribe(self, sound: np.ndarray, whole: bool = False) -> List[str]:
        # its own thread's CPU time (ONNX Runtime runs on it): the share of a core the looks take,
        # not the wall time a busy machine stretches it to, which spaced the looks a second apart
        began = time.thread_time()
        if whole:  # in silence: a short answer cut close is heard surely (87 of 87 cut points)
            pad = np.zeros(int(PAD * RATE), np.int16)
            sound = np.concatenate([pad, sound, pad])
        text = self.model.transcribe(sound, self._favoured_whole if whole else self._favoured, self.bias)
        cost = time.thread_time() - began
        if self.paced:
            self._pace = cost / CPU_SHARE
        return words_of(text)

    def _look(self, origin: float, upto: int) -> List[Heard]:
        self._looked = upto
        sound = np.concatenate(self._sound)[-int(WINDOW * RATE) :]
        words = self._transcribe(sound)
        seen = {phrase for phrase, spelled in self._phrases if holds(words, spelled)}
        # after a pause the last word is whole: what a look then finds is told at once
        stable = seen if self._quiet >= SURE * RATE else seen & self._seen
        self._seen = seen
        return self._tell([p for p in sorted(stable) if not self._told[p]], origin + upto / RATE, origin)

    def _end(self, origin: float) -> List[Heard]:
        sound = np.concatenate(self._sound)
        self._sound = []
        if self._spoken < SHORTEST * RATE:
            return []
        last = self._first + len(sound) - self._quiet  # the speech's end
        words = self._transcribe(sound[: len(sound) - self._quiet + int(0.1 * RATE)], whole=True)
        more = [p for p, spelled in self._phrases for _ in range(times(words, spelled) - self._told[p])]
        told = self._tell(more, origin + last / RATE, origin)
        said = Said(" ".join(words), origin + last / RATE, origin + self._first / RATE)
        if not words:
            return told
        if set(words) <= set(self._own(said.start, said.at)):  # the face's own voice, heard with barge-in
            self.ignored_said.append(said)
            return told
        self.said.append(said)
        if self.on_heard is not None:
            self.on_heard(said.text, said.at)
        return told

    def _own(self, start: float, end: float) -> List[str]:
        """The words the face said from `start` (and ECHO before) to `end`: with barge-in, what
        the face itself may have been heard saying."""
        return words_of(self.saying(start - ECHO, end)) if self.barge_in and self.saying is not None else []

    def _tell(self, phrases: Sequence[str], at: float, origin: float) -> List[Heard]:
        told = []
        start = origin + self._first / RATE
        own = self._own(start, at)
        for phrase in phrases:
            self._told[phrase] += 1
            heard = Heard(phrase, at, start)
            if holds(own, phrase.split()):
                self.ignored.append(heard)
                continue
            self.heard.append(heard)
            told.append(heard)
            self.on_word(phrase, at)
        return told

    def close(self) -> None:
        """Stop: an utterance still going on is not heard (nothing is listening for it)."""
        with self._lock:
            self._sound = []
