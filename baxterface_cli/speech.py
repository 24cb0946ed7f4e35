"""Speech: text to sound, with the time of every phoneme and word, from espeak-ng.

libespeak-ng is a system library (`apt install espeak-ng`), loaded through
ctypes only when something is said. The phoneme times are the synthesizer's
own, counted in samples of the sound it hands back, so a mouth drawn from them
cannot drift from the voice. The same text, voice and rate always give the same
samples. The voices `say` accepts are known without espeak-ng (see `voices`).
"""

from __future__ import annotations

import _ctypes
import bisect
import ctypes
import ctypes.util
import re
import threading
import unicodedata
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Dict, FrozenSet, List, NamedTuple, Optional, Tuple

import numpy as np

from .diagnostics import did_you_mean
from .extras import MissingTool
from .voices import DEFAULT_RATE, DEFAULT_VOICE, RATES, known_voice, voice_names

__all__ = [
    "DEFAULT_RATE",
    "DEFAULT_VOICE",
    "RATES",
    "VOICES",
    "Phoneme",
    "SpeechEngine",
    "Utterance",
    "Word",
    "engine",
    "known_voice",
]

VOICES: FrozenSet[str] = frozenset(voice_names())

INSTALL_HINT = "speech needs the espeak-ng library: apt install espeak-ng"
_LIBRARY_NAMES = ("libespeak-ng.so.1", "libespeak-ng.so", "libespeak-ng.1.dylib", "libespeak-ng.dylib")


class Phoneme(NamedTuple):
    """One phoneme of an utterance; pauses are phonemes too, named "_", "_:", "_!"..."""

    at: float  # seconds from the utterance's first sample
    end: float  # when the next phoneme (or the sound) starts
    name: str  # espeak-ng's mnemonic, e.g. "p", "aI", "_:"


class Word(NamedTuple):
    """A written word and when its sound starts."""

    at: float
    text: str


@dataclass(frozen=True)
class Utterance:
    """Something said: its sound (int16 mono, read-only) and when each phoneme and word starts."""

    text: str
    voice: str
    rate: int
    samples: np.ndarray = field(compare=False, repr=False)
    sample_rate: int
    phonemes: Tuple[Phoneme, ...]
    words: Tuple[Word, ...]

    @property
    def duration(self) -> float:
        return len(self.samples) / self.sample_rate


class Trim(NamedTuple):
    """How the silence around the voice is cut."""

    # Samples at or under this size are silence: espeak-ng's pauses are exact zeros, and
    # its quietest sounds (the start of an "h") are well above it.
    threshold: int = 32
    keep: float = 0.010  # seconds of silence kept at each end, so the sound does not click


TRIM = Trim()
CACHE_SIZE = 32  # utterances remembered: play, render and explain may each ask for the same one


# --- espeak-ng's C interface (speak_lib.h, API revision 12) -----------------------------------------

_AUDIO_OUTPUT_SYNCHRONOUS = 2
_INITIALIZE_PHONEME_EVENTS = 0x0001
_INITIALIZE_DONT_EXIT = 0x8000  # missing data files: return an error rather than exit() the process
_CHARS_UTF8 = 1
_POS_CHARACTER = 1
_RATE = 1  # espeak_PARAMETER espeakRATE
_EE_OK = 0
_SEED = 1  # any fixed number: the same text, voice and rate then give the same samples

_EVENT_END_OF_LIST = 0
_EVENT_WORD = 1
_EVENT_PHONEME = 7
_EVENT_SAMPLERATE = 8


class _EventId(ctypes.Union):
    _fields_ = [("number", ctypes.c_int), ("name", ctypes.c_char_p), ("string", ctypes.c_char * 8)]


class _Event(ctypes.Structure):
    # The pointer makes the struct 40 bytes on 64-bit: 6 ints, a void* at 24, the union at 32.
    _fields_ = [
        ("type", ctypes.c_int),
        ("unique_identifier", ctypes.c_uint),
        ("text_position", ctypes.c_int),  # in characters, from 1
        ("length", ctypes.c_int),
        ("audio_position", ctypes.c_int),  # milliseconds, rounded down
        ("sample", ctypes.c_int),  # the same time in samples: exact
        ("user_data", ctypes.c_void_p),
        ("id", _EventId),
    ]


class _Voice(ctypes.Structure):
    _fields_ = [
        ("name", ctypes.c_char_p),
        ("languages", ctypes.c_char_p),
        ("identifier", ctypes.c_char_p),
        ("gender", ctypes.c_ubyte),
        ("age", ctypes.c_ubyte),
        ("variant", ctypes.c_ubyte),
        ("xx1", ctypes.c_ubyte),
        ("score", ctypes.c_int),
        ("spare", ctypes.c_void_p),
    ]


_SynthCallback = ctypes.CFUNCTYPE(
    ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int, ctypes.POINTER(_Event)
)

# espeak-ng is one synthesizer per process, with global state: every call goes through this lock.
_LOCK = threading.RLock()
_found: Optional[Tuple[str, int, str]] = None  # the library's path, sample rate and version
_engine: Optional[SpeechEngine] = None
# Unloading the library is what resets its state between utterances (see _Session).
_unload = getattr(_ctypes, "dlclose", None) or getattr(_ctypes, "FreeLibrary", None)


def _declare(lib: ctypes.CDLL) -> None:
    c_int, c_char_p, c_void_p, c_uint = ctypes.c_int, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_uint
    signatures = {
        "espeak_Initialize": (c_int, [c_int, c_int, c_char_p, c_int]),
        "espeak_Terminate": (c_int, []),
        "espeak_SetSynthCallback": (None, [_SynthCallback]),
        "espeak_SetVoiceByName": (c_int, [c_char_p]),
        "espeak_SetVoiceByProperties": (c_int, [ctypes.POINTER(_Voice)]),
        "espeak_GetCurrentVoice": (ctypes.POINTER(_Voice), []),
        "espeak_SetParameter": (c_int, [c_int, c_int, c_int]),
        "espeak_Synth": (
            c_int,
            [c_void_p, ctypes.c_size_t, c_uint, c_int, c_uint, c_uint, ctypes.POINTER(c_uint), c_void_p],
        ),
        "espeak_Info": (c_char_p, [ctypes.POINTER(c_char_p)]),
    }
    if hasattr(lib, "espeak_ng_SetRandSeed"):
        signatures["espeak_ng_SetRandSeed"] = (c_int, [ctypes.c_long])
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype = restype
        function.argtypes = argtypes


def _seed(lib: ctypes.CDLL) -> None:
    """Make the next synthesis's random noise (breath, some fricatives) the same as every time's.

    espeak-ng 1.52 and later draw it from their own generator, seeded from the clock at
    initialisation; earlier ones from the C library's rand().
    """
    if hasattr(lib, "espeak_ng_SetRandSeed"):
        lib.espeak_ng_SetRandSeed(_SEED)
    else:
        libc = ctypes.CDLL(None)
        libc.srand.argtypes, libc.srand.restype = [ctypes.c_uint], None
        libc.srand(_SEED)


class _Session:
    """libespeak-ng freshly loaded and initialised, for one synthesis; unloaded after it.

    The synthesizer keeps state from one utterance to the next that no call resets (its pitch
    flutter runs on through every voiced sound, for one), so the same text would come out a
    few samples different each time. A library loaded afresh starts from the same state, and
    costs about a millisecond.
    """

    def __init__(self, path: str) -> None:
        self.path = path

    def __enter__(self) -> Tuple[ctypes.CDLL, int]:
        _LOCK.acquire()
        try:
            self.lib = ctypes.CDLL(self.path)
            _declare(self.lib)
            options = _INITIALIZE_PHONEME_EVENTS | _INITIALIZE_DONT_EXIT
            self.rate = self.lib.espeak_Initialize(_AUDIO_OUTPUT_SYNCHRONOUS, 0, None, options)
            _seed(self.lib)
            return self.lib, self.rate
        except BaseException:
            _LOCK.release()
            raise

    def __exit__(self, *exc: Any) -> None:
        try:
            if self.rate > 0:
                self.lib.espeak_Terminate()
            if _unload is not None:
                _unload(self.lib._handle)
        finally:
            del self.lib
            _LOCK.release()


def _library() -> Tuple[str, int, str]:
    """libespeak-ng's path, sample rate and version, found once; MissingTool without it."""
    global _found
    with _LOCK:
        if _found is None:
            found = ctypes.util.find_library("espeak-ng")
            for name in ((found,) if found else ()) + _LIBRARY_NAMES:
                try:
                    with _Session(name) as (lib, rate):
                        version = (lib.espeak_Info(None) or b"").decode("ascii", "replace")
                except OSError:
                    continue
                except AttributeError:
                    raise MissingTool(f"{name} is not a usable espeak-ng; {INSTALL_HINT}") from None
                if rate <= 0:
                    raise MissingTool(
                        f"espeak-ng cannot find its voice data (espeak-ng-data); {INSTALL_HINT}"
                    )
                _found = (name, rate, version)
                break
            else:
                raise MissingTool(INSTALL_HINT)
        return _found


def espeak_version() -> str:
    """The espeak-ng's version, e.g. "1.51"; MissingTool without it."""
    return _library()[2]


# --- the engine ---------------------------------------------------------------------------------------


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
            if len(self._cache) > CACHE_SIZE:
                self._cache.popitem(last=False)
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


def _select(lib: ctypes.CDLL, voice: str) -> None:
    """Make `voice` (a lower-case name from VOICES) the current voice, as `espeak-ng -v` does."""
    name = voice.encode("utf-8")
    # By name or file first ("en-us" is the file gmw/en-US); then by language ("fr-fr" is roa/fr).
    if lib.espeak_SetVoiceByName(name) == _EE_OK:
        return
    spec = _Voice(languages=name)
    if lib.espeak_SetVoiceByProperties(ctypes.byref(spec)) != _EE_OK:
        raise ValueError(f"voice '{voice}' is not in this espeak-ng; espeak-ng --voices lists what is")


def _event_sample(event: _Event, sample_rate: int) -> int:
    """An event's time in samples: its exact sample count, unless that disagrees with its milliseconds."""
    # `sample` is documented "for internal use"; audio_position (ms) is the public time, so it
    # is the check, and the fallback should a future espeak-ng count samples differently.
    if abs(event.sample * 1000 // sample_rate - event.audio_position) <= 1:
        return event.sample
    return event.audio_position * sample_rate // 1000


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
