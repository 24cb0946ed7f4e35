"""espeak-ng's C library through ctypes: loaded when something is said, one synthesizer per process.

speak_lib.h's structures and calls, the lock every call goes through, a
session that loads the library, reads its sample rate and version, and
unloads it, and one synthesis in the raw (sound and events). Only the speech
process (espeak_child.py) calls it: espeak-ng 1.51 crashes on some texts, and
must take no more than that process down. The engine is in synthesis.py.
"""

from __future__ import annotations

import _ctypes
import ctypes
import ctypes.util
import threading
from typing import Any, List, NamedTuple, Optional, Tuple

from ..extras import MissingTool

INSTALL_HINT = "speech needs the espeak-ng library: apt install espeak-ng"
_LIBRARY_NAMES = ("libespeak-ng.so.1", "libespeak-ng.so", "libespeak-ng.1.dylib", "libespeak-ng.dylib")


# --- espeak-ng's C interface (speak_lib.h, API revision 12) -----------------------------------------

_AUDIO_OUTPUT_SYNCHRONOUS = 2
_INITIALIZE_PHONEME_EVENTS = 0x0001
_INITIALIZE_DONT_EXIT = 0x8000  # missing data files: return an error rather than exit() the process
_CHARS_UTF8 = 1
_POS_CHARACTER = 1
_RATE = 1  # espeak_PARAMETER espeakRATE
EE_OK = 0
_SEED = 1  # any fixed number: the same text, voice and rate then give the same samples

EVENT_END_OF_LIST = 0
EVENT_WORD = 1
EVENT_PHONEME = 7
EVENT_SAMPLERATE = 8


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


def espeak_library() -> Tuple[str, int, str]:
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
    return espeak_library()[2]


def _select(lib: ctypes.CDLL, voice: str) -> None:
    """Make `voice` (a lower-case name from VOICES) the current voice, as `espeak-ng -v` does."""
    name = voice.encode("utf-8")
    # By name or file first ("en-us" is the file gmw/en-US); then by language ("fr-fr" is roa/fr).
    if lib.espeak_SetVoiceByName(name) == EE_OK:
        return
    spec = _Voice(languages=name)
    if lib.espeak_SetVoiceByProperties(ctypes.byref(spec)) != EE_OK:
        raise ValueError(f"voice '{voice}' is not in this espeak-ng; espeak-ng --voices lists what is")


def _event_sample(event: _Event, sample_rate: int) -> int:
    """An event's time in samples: its exact sample count, unless that disagrees with its milliseconds."""
    # `sample` is documented "for internal use"; audio_position (ms) is the public time, so it
    # is the check, and the fallback should a future espeak-ng count samples differently.
    if abs(event.sample * 1000 // sample_rate - event.audio_position) <= 1:
        return event.sample
    return event.audio_position * sample_rate // 1000


class Heard(NamedTuple):
    """One event the synthesizer reported, in the raw."""

    kind: int
    sample: int  # samples from the start of its audio; the sample rate, for a sample rate event
    text_position: int
    name: str  # a phoneme's mnemonic; empty for other events


class Spoken(NamedTuple):
    """What one espeak_Synth call gave: its status, its sound (int16 mono, native order) and events."""

    status: int
    pcm: bytes
    heard: List[Heard]


def synthesize(path: str, text: str, voice: str, rate: int) -> Spoken:
    """`text` said by the library at `path` in `voice` at `rate` words a minute; ValueError for a voice
    it lacks."""
    # A NUL would end the C string early; a space keeps every character where it was.
    data = text.replace("\0", " ").encode("utf-8", "replace") + b"\0"
    chunks: List[bytes] = []
    heard: List[Heard] = []
    with _Session(path) as (lib, sample_rate):

        def collect(wav: Any, count: int, events: Any) -> int:
            # Runs inside espeak_Synth. An exception here cannot reach the caller, so this only
            # copies what it is given.
            if wav and count > 0:
                chunks.append(ctypes.string_at(wav, count * 2))
            i = 0
            while events and events[i].type != EVENT_END_OF_LIST:
                e = events[i]
                if e.type == EVENT_SAMPLERATE:
                    heard.append(Heard(e.type, e.id.number, 0, ""))
                elif e.type in (EVENT_WORD, EVENT_PHONEME):
                    name = e.id.string.decode("utf-8", "replace") if e.type == EVENT_PHONEME else ""
                    heard.append(Heard(e.type, _event_sample(e, sample_rate), e.text_position, name))
                i += 1
            return 0

        callback = _SynthCallback(collect)  # kept until the call returns: espeak-ng holds only a pointer
        _select(lib, voice)
        lib.espeak_SetParameter(_RATE, rate, 0)
        lib.espeak_SetSynthCallback(callback)
        status = lib.espeak_Synth(data, len(data), 0, _POS_CHARACTER, 0, _CHARS_UTF8, None, None)
    return Spoken(status, b"".join(chunks), heard)


def voice_file(path: str, voice: str) -> str:
    """The espeak-ng voice file a voice name selects, e.g. "gmw/en-US" for "en-us"."""
    with _Session(path) as (lib, _):
        _select(lib, voice)
        return (lib.espeak_GetCurrentVoice().contents.identifier or b"").decode("utf-8", "replace")
