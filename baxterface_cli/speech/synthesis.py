"""Speech: text to sound, with the time of every phoneme and word, from espeak-ng.

libespeak-ng is a system library (`apt install espeak-ng`), loaded through
ctypes only when something is said, in a process of its own (espeak_process.py):
espeak-ng 1.51 crashes on some texts, and that must fail the one `say`, not
the program that asked. The phoneme times are the synthesizer's
own, counted in samples of the sound it hands back, so a mouth drawn from them
cannot drift from the voice. The same text, voice and rate always give the same
samples. The voices `say` accepts are known without espeak-ng (see `voices`).
"""

from __future__ import annotations

import bisect
import re
import threading
import unicodedata
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Dict, FrozenSet, List, NamedTuple, Optional, Tuple

import numpy as np

from ..core.voices import DEFAULT_RATE, DEFAULT_VOICE, RATES, known_voice, voice_names
from ..language.diagnostics import did_you_mean
from .espeak import EE_OK, EVENT_PHONEME, EVENT_SAMPLERATE, EVENT_WORD, Heard
from .espeak_process import EspeakProcess, SynthesisFailed

__all__ = [
    "DEFAULT_RATE",
    "DEFAULT_VOICE",
    "RATES",
    "VOICES",
    "SynthesisFailed",
    "Phoneme",
    "Recording",
    "SpeechEngine",
    "Utterance",
    "Word",
    "engine",
    "known_voice",
]

VOICES: FrozenSet[str] = frozenset(voice_names())


class Phoneme(NamedTuple):
    """One phoneme of an utterance; pauses are phonemes too, named "_", "_:", "_!"..."""

    at: float  # seconds from the utterance's first sample
    end: float  # when the next phoneme (or the sound) starts
    name: str  # espeak-ng's mnemonic, e.g. "p", "aI", "_:"


class Word(NamedTuple):
    """A written word and when its sound starts."""

    at: float
    text: str


class Recording(NamedTuple):
    """Where an utterance's sound came from when it is a recording (`say file`), not espeak-ng."""

    path: str  # the file, absolute
    name: str  # as the script wrote it
    digest: str  # SHA-256 of the file's bytes
    method: str  # how its phonemes were found (recordings.METHODS)


@dataclass(frozen=True)
class Utterance:
    """Something said: its sound (int16 mono, read-only) and when each phoneme and word starts.

    A recording's (`recording` set) has its phonemes found in its sound, named as
    espeak-ng names them; its `voice` is the language it speaks ("" for English) and `rate` 0.
    """

    text: str
    voice: str
    rate: int
    samples: np.ndarray = field(compare=False, repr=False)
    sample_rate: int
    phonemes: Tuple[Phoneme, ...]
    words: Tuple[Word, ...]
    recording: Optional[Recording] = None

    @property
    def duration(self) -> float:
        return len(self.samples) / self.sample_rate

    @property
    def said(self) -> str:
        """What is said, as a status shows it: the text, or a recording's file name when it has none."""
        return self.text or (self.recording.name if self.recording is not None else "")


class Trim(NamedTuple):
    """How the silence around the voice is cut."""

    # Samples at or under this size are silence: espeak-ng's pauses are exact zeros, and
    # its quietest sounds (the start of an "h") are well above it.
    threshold: int = 32
    keep: float = 0.010  # seconds of silence kept at each end, so the sound does not click


TRIM = Trim()
# Utterances remembered (play, render and explain may each ask for the same one; the studio asks
# for its script's at every edit), by the bytes of their sound: one of 1000 characters can be four
# minutes, 10 MB. One asked for only once is among the last ONCE_KEPT: a face sent a new text at
# every command (the node, the screen) keeps no more of them after 150 than after 20.
CACHE_BYTES = 32 * 2**20
ONCE_KEPT = 8
# Texts espeak-ng crashed on, by (text, voice, rate), not tried again: each try costs a new process.
FAILURES_KEPT = 256


_engine: Optional[SpeechEngine] = None


_LOCK = threading.Lock()  # the engine's cache; synthesis itself goes on outside it


def _bound(kept: OrderedDict, most: int) -> None:
    """Forget the least recently used of `kept` until their sounds take at most `most` bytes (the
    newest stays, however big)."""
    held = sum(u.samples.nbytes for u in kept.values())
    while len(kept) > 1 and held > most:
        held -= kept.popitem(last=False)[1].samples.nbytes


def unknown_voice_message(voice: str) -> str:
    """Why `voice` is refused, with the nearest known name when one is close."""
    hint = did_you_mean(voice, VOICES) or "; 'baxterface voices' lists them"
    return f"unknown voice '{voice}'{hint}"


class SpeechEngine:
    """Says text with espeak-ng. Use `engine()`, the one shared engine."""

    def __init__(self, process: Optional[EspeakProcess] = None) -> None:
        self._process = process or EspeakProcess()
        self._process.start()  # MissingTool, said at once, without espeak-ng
        self.sample_rate = self._process.sample_rate
        self._cache: OrderedDict[Tuple[str, str, int], Utterance] = OrderedDict()  # asked for again
        self._once: OrderedDict[Tuple[str, str, int], Utterance] = OrderedDict()  # asked for once
        self._failed: OrderedDict[Tuple[str, str, int], str] = OrderedDict()

    def say(self, text: str, voice: str = DEFAULT_VOICE, rate: int = DEFAULT_RATE) -> Utterance:
        """`text` spoken, trimmed to the voice; ValueError for an unknown voice or a rate out of RATES,
        SynthesisFailed for a text espeak-ng crashed on (or took too long over)."""
        if voice.lower() not in VOICES:  # espeak-ng's; the natural ones are natural_voices.py's
            raise ValueError(unknown_voice_message(voice))
        if isinstance(rate, bool) or int(rate) != rate or not RATES[0] <= rate <= RATES[1]:
            raise ValueError(
                f"rate {rate} is not a whole number of words a minute from {RATES[0]} to {RATES[1]}"
            )
        key = (text, voice.lower(), int(rate))
        with _LOCK:
            cached = self._cache.get(key)
            if cached is not None:
                self._cache.move_to_end(key)
                return cached
            cached = self._once.pop(key, None)
            if cached is not None:  # asked for again: kept with the others that were
                self._cache[key] = cached
                _bound(self._cache, CACHE_BYTES)
                return cached
            if key in self._failed:
                raise SynthesisFailed(self._failed[key], crashed=True)
        try:
            utterance = self._synthesize(*key)
        except SynthesisFailed as e:
            if e.crashed:
                with _LOCK:
                    self._failed[key] = str(e)
                    while len(self._failed) > FAILURES_KEPT:
                        self._failed.popitem(last=False)
            raise
        with _LOCK:
            self._once[key] = utterance
            while len(self._once) > ONCE_KEPT:
                self._once.popitem(last=False)
            _bound(self._once, CACHE_BYTES)
        return utterance

    def voice_file(self, voice: str) -> str:
        """The espeak-ng voice file a voice name selects, e.g. "gmw/en-US" for "en-us"."""
        return self._process.voice_file(voice)

    def close(self) -> None:
        """End the speech process now rather than at exit (a later `say` starts another)."""
        self._process.close()

    def _synthesize(self, text: str, voice: str, rate: int) -> Utterance:
        spoken = self._process.say(text, voice, rate)
        if spoken.status != EE_OK:
            raise RuntimeError(f"espeak-ng could not say {text!r} (error {spoken.status})")
        heard = spoken.heard
        sample_rate = next((h.sample for h in heard if h.kind == EVENT_SAMPLERATE), self.sample_rate)
        samples = np.frombuffer(spoken.pcm, dtype=np.int16)
        return _utterance(text, voice, rate, samples, sample_rate, heard)


def _utterance(
    text: str, voice: str, rate: int, samples: np.ndarray, sample_rate: int, heard: List[Heard]
) -> Utterance:
    """The utterance with its silent ends cut off and the events moved to match."""
    loud = np.flatnonzero(np.abs(samples.astype(np.int32)) > TRIM.threshold)
    if len(loud) == 0:
        samples = samples[:0].copy()
        samples.flags.writeable = False
        return Utterance(text, voice, rate, samples, sample_rate, (), ())
    keep = round(TRIM.keep * sample_rate)
    first, last = max(0, int(loud[0]) - keep), min(len(samples), int(loud[-1]) + 1 + keep)
    samples = samples[first:last].copy()
    samples.flags.writeable = False
    end = len(samples)

    def seconds(sample: int) -> float:
        return min(max(sample - first, 0), end) / sample_rate

    starts = [(seconds(h.sample), h.name) for h in heard if h.kind == EVENT_PHONEME]
    # At the top rate espeak-ng speeds its sound up afterwards, and a clause's closing pause
    # can then be reported up to 20 ms after the next phoneme's start: no phoneme starts after
    # the next one does.
    for i in range(len(starts) - 2, -1, -1):
        if starts[i][0] > starts[i + 1][0]:
            starts[i] = (starts[i + 1][0], starts[i][1])
    ends = [at for at, _ in starts[1:]] + [end / sample_rate]
    # A phoneme with no time left (the final "_", or one cut off with the silence) is not heard.
    phonemes = tuple(Phoneme(at, stop, name) for (at, name), stop in zip(starts, ends) if stop > at)
    spoken = [(seconds(h.sample), h.text_position) for h in heard if h.kind == EVENT_WORD]
    return Utterance(text, voice, rate, samples, sample_rate, phonemes, _words(text, spoken, phonemes))


def written_words(text: str) -> List[Tuple[int, str]]:
    """(where it starts, the word) for each run of non-space characters, without the punctuation
    around it ('"Hello,"' is Hello), unless that is all it is."""
    words = []
    for match in re.finditer(r"\S+", text):
        token = match.group()
        letters = [i for i, char in enumerate(token) if not unicodedata.category(char).startswith("P")]
        words.append((match.start(), token[letters[0] : letters[-1] + 1] if letters else token))
    return words


def _words(text: str, spoken: List[Tuple[float, int]], phonemes: Tuple[Phoneme, ...]) -> Tuple[Word, ...]:
    """The written words, timed by espeak-ng's word events.

    An event gives where its word starts in the text, counted in characters from 1. Several
    events can point into one written word ("1234" is said as four words, "e-mail" as two,
    an emoji as its name) and some at the space after one: a written word takes the first.
    A word starts with the first sound at or after its event (which comes with the pause
    before it). A few words get no event, run into a neighbour ("am" in "I am a"): they are
    placed between the words around them, by their place in the text, on a phoneme's start.
    Punctuation that is not said ("--", "...") is not a word.
    """
    written = written_words(text)
    if not written or not phonemes:
        return ()
    starts = [start for start, _ in written]
    sounds = [p.at for p in phonemes if not p.name.startswith("_")] or [phonemes[0].at]
    timed: Dict[int, float] = {}
    for at, position in spoken:
        index = max(0, bisect.bisect_right(starts, position - 1) - 1)
        if index not in timed and all(index > i for i in timed):
            i = bisect.bisect_left(sounds, at)
            timed[index] = max(sounds[min(i, len(sounds) - 1)], max(timed.values(), default=0.0))
    # The ends the words between are placed against: the first sound, and the end of the text.
    anchors = [(-1, sounds[0])] + sorted(timed.items()) + [(len(written), sounds[-1])]
    result = []
    for (a, ta), (b, tb) in zip(anchors, anchors[1:]):
        if a >= 0:
            result.append(Word(ta, written[a][1]))
        for index in range(a + 1, b):
            word = written[index][1]
            if not any(char.isalnum() for char in word):
                continue
            low, high = (starts[a] if a >= 0 else 0), (starts[b] if b < len(written) else len(text))
            guess = ta + (tb - ta) * (starts[index] - low) / max(1, high - low)
            near = [t for t in sounds if ta < t < tb] or [ta]
            result.append(Word(min(near, key=lambda t: abs(t - guess)), word))
    return tuple(result)


def engine() -> SpeechEngine:
    """The one shared speech engine; MissingTool, saying how to install it, without espeak-ng."""
    global _engine
    with _LOCK:
        if _engine is None:
            _engine = SpeechEngine()
        return _engine
