"""Recordings a script says (`say file`): where they may be read from, the mouth found in them, kept.

A `Recordings` is where `say file` names are looked up: a script's own
folder for the command line, where any path the script's author wrote is
read; a folder the path may not leave (`confined`) for the node and the
studio, whose commands come over the network; or nowhere at all (`folder`
None: every `say file` is refused, with `refusal` as the reason).

The phonemes are found once per file content and way of finding them, and
kept in the user's cache folder (`$XDG_CACHE_HOME/baxterface/lipsync`, by
default `~/.cache/...`), so a script plays at once the second time:

- with pocketsphinx: its phonemes, aligned to the words when the script gives
  them (`text`, English only), else to the words hama's phoneme recogniser
  hears (phoneme_recogniser.py; any language), else, for English, decoded by
  pocketsphinx's phoneme loop (without hama: Python 3.8, or no engine for
  the machine);
- otherwise (another language without hama, or no pocketsphinx): the sound's
  loudness and spectrum (sound_mouth.py), after a one-line warning naming
  the extra where pocketsphinx is what is missing.

The mouth then follows them by the same table and rules as `say` (visemes.py).
What does not depend on the words (the sound, its loudness, the phonemes found
without words) is found once a recording, for every `text` said of it.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import math
import os
import threading
from collections import OrderedDict
from pathlib import Path
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Tuple, Union

import numpy as np

from ..core import user_cache
from ..core.partial_files import write_atomic
from ..language import syntax_tree as n
from ..language.checker import check_length, walk
from ..language.diagnostics import Diagnostic
from . import phoneme_recogniser, phones_heard
from .audio_files import ANALYSIS_RATE, EXTRA, AudioError, check_file, probe, read_sound
from .phone_names import espeak_phonemes, frame_loudness, spelled
from .phones_heard import FRAME
from .sound_mouth import spectrum_phonemes
from .synthesis import Phoneme, Recording, Utterance, Word
from .visemes import MOUTH_RULES, MouthKey, MouthRules, mouth_track
from .wav_header import HeaderError, open_recording

# How a recording's phonemes were found, as `explain` says it.
METHODS = {
    "aligned": "phonemes aligned to its words",
    "recognised": "phonemes recognised",
    "heard": "phonemes heard",
    "spectrum": "loudness and spectrum",
}
ANALYSIS_VERSION = 1  # a new one leaves what the old analysis kept unread
# Recordings kept in memory (the studio compiles its script at every edit), by the bytes of their
# sound: a ten-minute one at 48 kHz is 58 MB.
KEPT_BYTES = 128 * 2**20
# Analyses kept on disk, by their bytes and their number; the least recently used go first.
CACHE_BYTES, CACHE_FILES = 32 * 2**20, 2000
RECITALS_KEPT = 32  # the texts (and languages) said of each recording kept in memory
UNALIGNED = "unaligned"  # kept for words that do not fit their recording: not aligned again
NO_POCKETSPHINX = (
    f"lip-sync from a recording hears its phonemes with pocketsphinx: pip install 'baxterface[{EXTRA}]'; "
    "the mouth follows its loudness and spectrum instead"
)
Analysis = Tuple[Tuple[Phoneme, ...], Tuple[Word, ...], str]  # phonemes, words, METHODS key
_warned: List[str] = []
_recent: OrderedDict = OrderedDict()
_LOCK = threading.Lock()


class RecordingError(ValueError):
    """A `say` that cannot be said: a `say file` whose file is missing, unreadable or out of bounds,
    or a text espeak-ng crashed on."""

    def __init__(self, message: str, say: Optional[n.Say] = None) -> None:
        super().__init__(message)
        self.say = say

    def diagnostic(self) -> Diagnostic:
        if self.say is None:
            pos = n.NOWHERE
        else:
            pos = self.say.file_pos if self.say.file is not None else self.say.pos
        return Diagnostic(pos.line, pos.column, str(self))


class Recital(NamedTuple):
    """A recording as the face says it: the utterance and the mouth that goes with it."""

    utterance: Utterance
    mouth: Tuple[MouthKey, ...]


class Recordings:
    """Where `say file` names are looked up, and the recordings said from there."""

    def __init__(
        self,
        folder: Union[None, str, Path],
        confined: bool = False,
        warn: Callable[[str], None] = lambda line: None,
        refusal: str = "this face reads no recordings",
        cache: Optional[Path] = None,
    ) -> None:
        self.folder = Path(os.path.abspath(str(folder))) if folder is not None else None
        self.confined = confined
        self.warn = warn
        self.refusal = refusal
        self.cache = cache

    @classmethod
    def for_script(cls, filename: str, warn: Callable[[str], None] = lambda line: None) -> Recordings:
        """A script file's folder; the current folder for standard input, `-e` and texts without a file."""
        folder = "." if filename.startswith("<") else os.path.dirname(os.path.abspath(filename))
        return cls(folder, warn=warn)

    def path(self, written: str, say: Optional[n.Say] = None) -> str:
        """The file a `say file` names, absolute; RecordingError where it may not be read."""
        if self.folder is None:
            raise RecordingError(f"cannot say recording {written!r}: {self.refusal}", say)
        if not self.confined:
            return os.path.abspath(os.path.join(str(self.folder), os.path.expanduser(written)))
        root = os.path.realpath(str(self.folder))
        real = os.path.realpath(os.path.join(root, written))
        if os.path.commonpath([real, root]) != root:
            raise RecordingError(
                f"recording {written!r} is outside {root}, the folder recordings are read from here", say
            )
        return real

    def check(self, script: n.Script) -> List[Diagnostic]:
        """What is wrong with each recording the script says, where it names it: missing, not sound,
        unreadable without PyAV...; and the script's length with each recording counted as long as
        its header says (the language alone cannot know it), against the limit.
        """
        out: List[Diagnostic] = []
        seen: Dict[str, Union[float, str]] = {}  # a file's length, or why it cannot be read
        lengths: Dict[int, float] = {}
        for say in walk(script.body):
            if not isinstance(say, n.Say) or say.file is None:
                continue
            try:
                path = self.path(say.file, say)
                if path not in seen:
                    try:
                        seen[path] = probe(path)
                    except AudioError as e:
                        seen[path] = str(e)
                found = seen[path]
                if isinstance(found, str):
                    raise RecordingError(_unreadable(say.file, found), say)
                lengths[id(say)] = found
            except RecordingError as e:
                out.append(e.diagnostic())
        if not out and lengths:
            out = check_length(script.body, lambda say: lengths.get(id(say), 0.0))
        return out

    def recite(self, say: n.Say) -> Recital:
        """The recording `say` names, with its mouth; RecordingError if it cannot be read."""
        path = self.path(say.file or "", say)
        try:
            with check_file(path) as file:
                info = os.fstat(file.fileno())
        except (AudioError, OSError) as e:
            raise RecordingError(_unreadable(say.file or "", str(e)), say) from None
        method = _method(say.language, self.warn)
        key, said = (path, info.st_mtime_ns, info.st_size), (say.text, say.language, method)
        with _LOCK:
            heard = _recent.get(key)
            if heard is not None:
                _recent.move_to_end(key)
                recital = heard.recitals.get(said)
                if recital is not None:
                    heard.recitals.move_to_end(said)
                    return recital
        if heard is None:
            heard = self._read(path, say)
        phonemes, words, method = self._analysis(heard, method, say)
        utterance = Utterance(
            say.text,
            say.language or "",
            0,
            heard.sound.samples,
            heard.sound.rate,
            bridged(phonemes, heard.sound.samples, heard.sound.rate, heard.rules),
            words,
            Recording(path, say.file or "", heard.digest, METHODS[method]),
        )
        recital = Recital(utterance, mouth_track(utterance, heard.rules))
        with _LOCK:
            _recent[key] = heard
            heard.recitals[said] = recital
            while len(heard.recitals) > RECITALS_KEPT:
                heard.recitals.popitem(last=False)
            while len(_recent) > 1 and sum(_held(h) for h in _recent.values()) > KEPT_BYTES:
                _recent.popitem(last=False)
        return recital

    def _read(self, path: str, say: n.Say) -> _Heard:
        """What a recording is whatever its words: its sound, content and noise floor."""
        try:
            sound = read_sound(path)
        except AudioError as e:
            raise RecordingError(_unreadable(say.file or "", str(e)), say) from None
        try:
            digest = _digest(path)
        except (HeaderError, OSError) as e:  # swapped since it was read
            raise RecordingError(_unreadable(say.file or "", str(e)), say) from None
        return _Heard(sound, digest, heard_rules(sound.samples, sound.rate), {}, OrderedDict())

    def _analysis(self, heard: _Heard, method: str, say: n.Say) -> Analysis:
        """The phonemes of the recording: its words aligned where `say` gives them and they fit it,
        else what is found in the sound alone, which is found once whatever the words."""
        # analyses are kept in `$XDG_CACHE_HOME/baxterface/lipsync`, or `~/.cache/...`
        folder = self.cache or user_cache.cache_folder("lipsync")
        sound = heard.sound
        # Only an alignment reads the words, in English: a new `text` for a long recording, or for
        # another language, is the same analysis.
        english = _english(say.language)
        aligns = method != "spectrum" and len(sound.analysis) <= phones_heard.ALIGN_SECONDS * ANALYSIS_RATE
        text = say.text if aligns and english else ""
        if text.strip():
            kept = _kept_name(folder, heard.digest, method, say.language, text)
            found = _read_kept(kept)
            if found is None:
                aligned = phones_heard.align(sound.analysis, text, spell)
                found = UNALIGNED
                if aligned is not None:
                    phonemes = espeak_phonemes(aligned.phones, sound.analysis, ANALYSIS_RATE)
                    found = phonemes, tuple(Word(at, text) for at, text in aligned.words), "aligned"
                _keep(folder, kept, found)
            if found is not UNALIGNED:
                return found
        plain = (method, say.language or "")
        if plain not in heard.plain:  # without words: found once a recording, way and language
            heard.plain[plain] = self._plain(folder, heard, method, say.language, english)
        return heard.plain[plain]

    def _plain(
        self, folder: Path, heard: _Heard, method: str, language: Optional[str], english: bool
    ) -> Analysis:
        kept = _kept_name(folder, heard.digest, method, language, "")
        found = _read_kept(kept)
        if found is not None and found is not UNALIGNED:
            return found
        sound = heard.sound
        if method == "spectrum":
            found = spectrum_phonemes(sound.analysis, ANALYSIS_RATE), (), method
        else:
            recognise = None
            if method == "recognised":
                recognise = functools.partial(phoneme_recogniser.recognise, english=english)
            said = phones_heard.hear(sound.analysis, "", spell, recognise)
            phonemes = espeak_phonemes(said.phones, sound.analysis, ANALYSIS_RATE)
            found = phonemes, (), "recognised" if said.recognised else "heard"
        _keep(folder, kept, found)
        return found


class _Heard(NamedTuple):
    """A recording as read, kept for every `say` of it: what does not depend on its words."""

    sound: Any
    digest: str
    rules: MouthRules
    plain: Dict[Tuple[str, str], Analysis]  # found without words, by (method, language)
    recitals: OrderedDict  # by (text, language, method)


def _kept_name(folder: Path, digest: str, method: str, language: Optional[str], text: str) -> Path:
    name = f"{ANALYSIS_VERSION}\n{digest}\n{method}\n{language or ''}\n{text}"
    return folder / (hashlib.sha256(name.encode("utf-8")).hexdigest() + ".json")


def _keep(folder: Path, kept: Path, found: Union[Analysis, str]) -> None:
    """Write an analysis (or that the words did not fit) to the cache folder, trimmed to its bounds."""
    if found is UNALIGNED:
        record: Dict[str, Any] = {"method": UNALIGNED}
    else:
        phonemes, words, method = found
        record = {
            "method": method,
            "phonemes": [[p.at, p.end, p.name] for p in phonemes],  # as they are: JSON keeps every bit
            "words": [[w.at, w.text] for w in words],
        }
    try:
        user_cache.make_private(folder)
        write_atomic(kept, json.dumps(record).encode("utf-8"))
        user_cache.trim(folder, "*.json", CACHE_BYTES, CACHE_FILES)
    except OSError:  # a cache that cannot be written only costs the next run the analysis
        pass


def heard_rules(samples: np.ndarray, rate: int, rules: MouthRules = MOUTH_RULES) -> MouthRules:
    """The mouth's rules with silence set above the recording's own noise floor.

    espeak-ng's pauses are exact zeros; a recording's hiss and hum are not.
    """
    loudness = frame_loudness(samples, rate)
    floor = float(np.percentile(loudness, 5)) if len(loudness) else 0.0
    return rules._replace(silence=max(rules.silence, 1.5 * floor), loud=int(max(rules.loud, 6.0 * floor)))


def bridged(
    phonemes: Tuple[Phoneme, ...], samples: np.ndarray, rate: int, rules: MouthRules = MOUTH_RULES
) -> Tuple[Phoneme, ...]:
    """The pauses heard inside continuous speech joined to the sound before them.

    A decoder hears a pause in the closure of a stop or between run-together words, where
    the voice goes on; each would rest the mouth for a moment, a flicker. A pause between
    two sounds stays one only where the recording is quiet for `rules.pause` or more.
    """
    loudness = frame_loudness(samples, rate)
    out: List[Phoneme] = []
    for i, phoneme in enumerate(phonemes):
        between = out and not out[-1].name.startswith("_") and i + 1 < len(phonemes)
        if (
            between
            and phoneme.name.startswith("_")
            and not phonemes[i + 1].name.startswith("_")
            and _quiet_run(loudness, phoneme.at, phoneme.end, rules.silence) < rules.pause
        ):
            out[-1] = out[-1]._replace(end=phoneme.end)
        else:
            out.append(phoneme)
    return tuple(out)


def _quiet_run(loudness: np.ndarray, start: float, end: float, silence: float) -> float:
    """The longest run of quiet FRAMEs between `start` and `end`, in seconds."""
    quiet = loudness[int(start / FRAME) : int(math.ceil(end / FRAME))] < silence
    longest = run = 0
    for frame_is_quiet in quiet:
        run = run + 1 if frame_is_quiet else 0
        longest = max(longest, run)
    return longest * FRAME


def _english(language: Optional[str]) -> bool:
    return language is None or language.startswith("en")


def _method(language: Optional[str], warn: Callable[[str], None]) -> str:
    """How the phonemes are to be found: any language is recognised (hama hears many, and
    pocketsphinx's English phones place theirs well enough), else English is heard by the
    phoneme loop, and the rest followed by its loudness and spectrum."""
    if phones_heard.available() and phoneme_recogniser.available():
        return "recognised"
    if not _english(language):
        return "spectrum"
    if phones_heard.available():
        return "heard"
    with _LOCK:
        first = not _warned
        _warned.append(NO_POCKETSPHINX)
    if first:
        warn(NO_POCKETSPHINX)
    return "spectrum"


def _unreadable(written: str, reason: str) -> str:
    return f"cannot read recording {written!r}: {reason}"


def _held(heard: _Heard) -> int:
    """The bytes a recording keeps: its sound (and the same at the analysis rate), and about 64
    for each phoneme and mouth shape of its recitals."""
    shapes = sum(len(r.mouth) + len(r.utterance.phonemes) for r in heard.recitals.values())
    return heard.sound.samples.nbytes + heard.sound.analysis.nbytes + 64 * shapes


def _digest(path: str) -> str:
    sha = hashlib.sha256()
    with open_recording(path) as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            sha.update(block)
    return sha.hexdigest()


def _read_kept(path: Path) -> Union[None, Analysis, str]:
    """A kept analysis (UNALIGNED: words that did not fit); None when there is none, or it is not
    one (then it is made again). Read, it is recently used: kept the longest."""
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
        with contextlib.suppress(OSError):
            os.utime(path)
        if record["method"] == UNALIGNED:
            return UNALIGNED
        phonemes = tuple(Phoneme(float(a), float(b), str(name)) for a, b, name in record["phonemes"])
        words = tuple(Word(float(at), str(text)) for at, text in record["words"])
        method = str(record["method"])
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if method not in METHODS:
        return None
    return phonemes, words, method


def spell(word: str) -> Optional[List[str]]:
    """pocketsphinx's phones for a word its dictionary lacks, as espeak-ng (American) says it."""
    from ..extras import MissingTool
    from .synthesis import engine

    try:
        said = engine().say(word, "en-us")
    except (MissingTool, ValueError, RuntimeError):
        return None
    return spelled([p.name for p in said.phonemes if not p.name.startswith("_")]) or None
