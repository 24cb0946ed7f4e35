"""Speech: text to sound, with the time of every phoneme and word, from espeak-ng.

libespeak-ng is a system library (`apt install espeak-ng`), loaded through
ctypes only when something is said. The phoneme times are the synthesizer's
own, counted in samples of the sound it hands back, so a mouth drawn from them
cannot drift from the voice. The same text, voice and rate always give the same
samples. The voices `say` accepts are known without espeak-ng (see `voices`).
"""

from __future__ import annotations

import bisect
import ctypes
import ctypes.util
import re
import unicodedata
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Dict, FrozenSet, List, NamedTuple, Optional, Tuple

import numpy as np

from ..core.voices import DEFAULT_RATE, DEFAULT_VOICE, RATES, known_voice, voice_names
from ..language.diagnostics import did_you_mean
from .espeak import (
    _CHARS_UTF8,
    _EE_OK,
    _EVENT_END_OF_LIST,
    _EVENT_PHONEME,
    _EVENT_SAMPLERATE,
    _EVENT_WORD,
    _LOCK,
    _POS_CHARACTER,
    _RATE,
    _event_sample,
    _library,
    _select,
    _Session,
    _SynthCallback,
)

__all__ = [
    "DEFAULT_RATE",
    "DEFAULT_VOICE",
    "RATES",
    "VOICES",
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
# Utterances remembered (play, render and explain may each ask for the same one), by the bytes of
# their sound: one of 1000 characters can be four minutes, 10 MB.
CACHE_BYTES = 32 * 2**20


_engine: Optional[SpeechEngine] = None


class _Heard(NamedTuple):
    """One event the synthesizer reported, in the raw."""

    kind: int
    sample: int  # samples from the start of its audio; the sample rate, for a sample rate event
    text_position: int
    name: str  # a phoneme's mnemonic; empty for other events


def unknown_voice_message(voice: str) -> str:
    """Why `voice` is refused, with the nearest known name when one is close."""
    hint = did_you_mean(voice, VOICES) or "; 'baxterface voices' lists them"
    return f"unknown voice '{voice}'{hint}"


class SpeechEngine:
    """Says text with espeak-ng. Use `engine()`, the one shared engine."""

    def __init__(self) -> None:
        self._path, self.sample_rate, _ = _library()
        self._chunks: List[bytes] = []
        self._heard: List[_Heard] = []
        # Kept on the object: espeak-ng holds only a pointer to it.
        self._callback = _SynthCallback(self._collect)
        self._cache: OrderedDict[Tuple[str, str, int], Utterance] = OrderedDict()

    def say(self, text: str, voice: str = DEFAULT_VOICE, rate: int = DEFAULT_RATE) -> Utterance:
        """`text` spoken, trimmed to the voice; ValueError for an unknown voice or a rate out of RATES."""
        if not known_voice(voice):
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
            utterance = self._synthesize(*key)
            self._cache[key] = utterance
            held = sum(u.samples.nbytes for u in self._cache.values())
            while len(self._cache) > 1 and held > CACHE_BYTES:
                held -= self._cache.popitem(last=False)[1].samples.nbytes
            return utterance

    def voice_file(self, voice: str) -> str:
        """The espeak-ng voice file a voice name selects, e.g. "gmw/en-US" for "en-us"."""
        with _Session(self._path) as (lib, _):
            _select(lib, voice)
            return (lib.espeak_GetCurrentVoice().contents.identifier or b"").decode("utf-8", "replace")

    def _synthesize(self, text: str, voice: str, rate: int) -> Utterance:
        # A NUL would end the C string early; a space keeps every character where it was.
        data = text.replace("\0", " ").encode("utf-8", "replace") + b"\0"
        with _Session(self._path) as (lib, _):
            _select(lib, voice)
            lib.espeak_SetParameter(_RATE, rate, 0)
            lib.espeak_SetSynthCallback(self._callback)
            self._chunks, self._heard = [], []
            status = lib.espeak_Synth(data, len(data), 0, _POS_CHARACTER, 0, _CHARS_UTF8, None, None)
            chunks, heard = self._chunks, self._heard
            self._chunks, self._heard = [], []
        if status != _EE_OK:
            raise RuntimeError(f"espeak-ng could not say {text!r} (error {status})")
        sample_rate = next((h.sample for h in heard if h.kind == _EVENT_SAMPLERATE), self.sample_rate)
        samples = np.frombuffer(b"".join(chunks), dtype=np.int16)
        return _utterance(text, voice, rate, samples, sample_rate, heard)

    def _collect(self, wav: Any, count: int, events: Any) -> int:
        # Runs inside espeak_Synth, under the lock. An exception here cannot reach the caller, so
        # this only copies what it is given.
        if wav and count > 0:
            self._chunks.append(ctypes.string_at(wav, count * 2))
        i = 0
        while events and events[i].type != _EVENT_END_OF_LIST:
            e = events[i]
            if e.type == _EVENT_SAMPLERATE:
                self._heard.append(_Heard(e.type, e.id.number, 0, ""))
            elif e.type in (_EVENT_WORD, _EVENT_PHONEME):
                name = e.id.string.decode("utf-8", "replace") if e.type == _EVENT_PHONEME else ""
                self._heard.append(_Heard(e.type, _event_sample(e, self.sample_rate), e.text_position, name))
            i += 1
        return 0


def _utterance(
    text: str, voice: str, rate: int, samples: np.ndarray, sample_rate: int, heard: List[_Heard]
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

    starts = [(seconds(h.sample), h.name) for h in heard if h.kind == _EVENT_PHONEME]
    # At the top rate espeak-ng speeds its sound up afterwards, and a clause's closing pause
    # can then be reported up to 20 ms after the next phoneme's start: no phoneme starts after
    # the next one does.
    for i in range(len(starts) - 2, -1, -1):
        if starts[i][0] > starts[i + 1][0]:
            starts[i] = (starts[i + 1][0], starts[i][1])
    ends = [at for at, _ in starts[1:]] + [end / sample_rate]
    # A phoneme with no time left (the final "_", or one cut off with the silence) is not heard.
    phonemes = tuple(Phoneme(at, stop, name) for (at, name), stop in zip(starts, ends) if stop > at)
    spoken = [(seconds(h.sample), h.text_position) for h in heard if h.kind == _EVENT_WORD]
    return Utterance(text, voice, rate, samples, sample_rate, phonemes, _words(text, spoken, phonemes))


def _written_words(text: str) -> List[Tuple[int, str]]:
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
    written = _written_words(text)
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
