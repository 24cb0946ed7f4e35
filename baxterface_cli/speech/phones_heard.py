"""The phonemes in a recording of speech, found by pocketsphinx (the `[lipsync]` extra).

With its words, pocketsphinx aligns the words' phonemes, from its own
dictionary (espeak-ng spells the words it lacks), to the sound, and the words
come out timed too. Without them, the words a phoneme recogniser heard
(phoneme_recogniser.py: what it heard, not what they are) are aligned the
same way, in pieces of at most PIECE_SECONDS cut where the sound is
quietest; without the recogniser, or where its words do not fit the sound,
pocketsphinx's phoneme loop decodes the sound straight to phonemes
(`allphone`), which mishears more. All give pocketsphinx's
phones (ARPAbet: AA, AE, ... ZH, SIL), which `phone_names` turns into
espeak-ng's phoneme names, so the mouth follows them by the same table and
rules as it follows `say` (visemes.py). pocketsphinx ships its English
acoustic model, dictionary and phoneme model in its wheel: nothing is
downloaded.
"""

from __future__ import annotations

import contextlib
import re
import threading
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Tuple

import numpy as np

from ..extras import need
from .audio_files import ANALYSIS_RATE, EXTRA

FRAME = 0.01  # pocketsphinx's frames: 100 a second
# Aligning takes memory with the sound's length (about 200 MB a minute): longer ones are heard.
ALIGN_SECONDS = 60.0
# Words recognised without a text are aligned in pieces this long at most (the recogniser's memory
# grows with the length too), each cut at its quietest frame of the last PIECE_SLACK seconds.
PIECE_SECONDS, PIECE_SLACK = 20.0, 5.0
FLAT = 32  # int16: a piece no louder than this (-60 dB) holds nothing said
ADDED_WORDS = 20000  # words heard added to a decoder's dictionary before it is made anew
_LOCK = threading.Lock()  # a decoder is not to be shared between threads
_decoders: Dict[str, Any] = {}
_added: Dict[str, int] = {}  # words heard added to each decoder's dictionary


class Heard(NamedTuple):
    """What pocketsphinx found: ARPAbet phones and the words (as given) with their start times."""

    phones: Tuple[Tuple[float, float, str], ...]  # (start, end, phone), seconds from the sound's start
    words: Tuple[Tuple[float, str], ...]
    aligned: bool  # the words were aligned (False: decoded as phonemes)
    recognised: bool = False  # the words a recogniser heard were aligned, in every piece


def available() -> bool:
    try:
        _pocketsphinx()
    except Exception:
        return False
    return True


def _pocketsphinx() -> Any:
    return need("pocketsphinx", EXTRA, "lip-sync from a recording's phonemes")


def _decoder(kind: str) -> Any:
    """One decoder of each kind a process, made on first use (loading the model takes a moment)."""
    decoder = _decoders.get(kind)
    if decoder is None:
        ps = _pocketsphinx()
        settings: Dict[str, Any] = {"lm": None, "bestpath": False, "loglevel": "FATAL"}
        if kind == "align-wide":  # a long recording: the right path can be pruned in narrower beams
            settings.update(beam=1e-80, pbeam=1e-80, wbeam=1e-60)
        if kind == "allphone":
            # The phoneme model weighs in lightly: heavier, it hears the phonemes it expects.
            model = ps.get_model_path("en-us/en-us-phone.lm.bin")
            settings.update(allphone=model, lw=1.0, beam=1e-8, pbeam=1e-8)
        decoder = _decoders[kind] = ps.Decoder(**settings)
    return decoder


Recogniser = Callable[[np.ndarray, int], List[List[str]]]


def hear(
    sound: np.ndarray, words: str = "", spell: Optional[Any] = None, recognise: Optional[Recogniser] = None
) -> Heard:
    """The phones in int16 mono `sound` at ANALYSIS_RATE; aligned to `words` when given (and the
    sound is at most ALIGN_SECONDS long), else to the words `recognise(sound, rate)` hears.

    `spell(word)` gives ARPAbet phones for a word the dictionary lacks (None: it is left out).
    Words that do not fit the sound are dropped, and the phonemes decoded instead.
    """
    aligned = align(sound, words, spell)
    if aligned is not None:
        return aligned
    if recognise is not None:
        return _recognised(sound, recognise)
    if _flat(sound):
        return Heard(_contiguous([], len(sound) / ANALYSIS_RATE), (), False)  # nothing said
    with _LOCK:
        phones = _phone_loop(np.asarray(sound, "<i2").tobytes())
    return Heard(_contiguous(phones, len(sound) / ANALYSIS_RATE), (), False)


def align(sound: np.ndarray, words: str, spell: Optional[Any] = None) -> Optional[Heard]:
    """`words` aligned to int16 mono `sound` at ANALYSIS_RATE, as `hear` aligns them; None where
    there are none, they do not fit the sound, or it is longer than ALIGN_SECONDS."""
    if not words.strip() or len(sound) > ALIGN_SECONDS * ANALYSIS_RATE:
        return None
    data = np.asarray(sound, "<i2").tobytes()
    with _LOCK:
        for kind in ("align", "align-wide"):
            aligned = _align(_decoder(kind), data, words, spell)
            if aligned is not None:
                return aligned
    return None


def _phone_loop(data: bytes) -> List[Tuple[float, float, str]]:
    decoder = _decoder("allphone")
    _decode(decoder, data)
    return [(s.start_frame * FRAME, (s.end_frame + 1) * FRAME, s.word) for s in decoder.seg()]


def _recognised(sound: np.ndarray, recognise: Recogniser) -> Heard:
    """The words `recognise` hears in each piece of the sound, aligned to it; a piece whose words
    do not fit, by the phoneme loop."""
    phones: List[Tuple[float, float, str]] = []
    every = True
    for start, end in pieces(sound):
        piece = sound[start:end]
        if _flat(piece):
            continue  # nothing said: silence (SIL) without the recogniser's and the aligner's work
        heard: Optional[List[List[str]]] = None
        with contextlib.suppress(RuntimeError):  # the recogniser's engine failed: the loop hears it
            heard = [word for word in recognise(piece, ANALYSIS_RATE) if word]
        data = np.asarray(piece, "<i2").tobytes()
        found = None
        with _LOCK:
            for kind in ("align", "align-wide") if heard else ():
                found = _align_heard(kind, data, heard or [])
                if found is not None:
                    break
            if heard is None or (heard and found is None):
                every, found = False, _phone_loop(data)
        at = start / ANALYSIS_RATE
        phones += [(a + at, b + at, name) for a, b, name in found or ()]
    return Heard(_contiguous(phones, len(sound) / ANALYSIS_RATE), (), False, every)


def _flat(piece: np.ndarray) -> bool:
    """A piece no louder than FLAT anywhere, about its median (a constant offset, a file of zero bytes
    in 8-bit or mu-law, is silence too)."""
    if not len(piece):
        return True
    values = np.asarray(piece, np.int32)
    return int(np.abs(values - int(np.median(values))).max()) <= FLAT


def pieces(sound: np.ndarray) -> List[Tuple[int, int]]:
    """(start, end) samples of pieces of at most PIECE_SECONDS, end to end, each ending at the
    quietest FRAME of its last PIECE_SLACK seconds."""
    step, most = round(FRAME * ANALYSIS_RATE), round(PIECE_SECONDS * ANALYSIS_RATE)
    out: List[Tuple[int, int]] = []
    start = 0
    while len(sound) - start > most:
        low = start + most - round(PIECE_SLACK * ANALYSIS_RATE)
        count = (start + most - low) // step
        frames = np.asarray(sound[low : low + count * step], np.float64).reshape(count, step)
        cut = low + int(np.argmin((frames * frames).sum(axis=1))) * step + step // 2
        out.append((start, cut))
        start = cut
    return out + [(start, len(sound))]


def _align_heard(kind: str, data: bytes, heard: List[List[str]]) -> Optional[List[Tuple[float, float, str]]]:
    """The phones of the words heard (each a list of phones), aligned to the sound by the decoder
    of `kind`; None if they do not fit it."""
    if _added.get(kind, 0) > ADDED_WORDS:  # a few bytes each, but a server may run for months
        del _decoders[kind]
        _added[kind] = 0
    decoder = _decoder(kind)
    names = []
    for word in heard:
        name = "heard:" + "_".join(word).lower()  # one name a pronunciation: added once
        if decoder.lookup_word(name) is None:
            decoder.add_word(name, " ".join(word), True)
            _added[kind] = _added.get(kind, 0) + 1
        names.append(name)
    alignment = _alignment(decoder, data, " ".join(names))
    if alignment is None:
        return None
    return [(p.start * FRAME, (p.start + p.duration) * FRAME, p.name) for p in alignment.phones()]


def _decode(decoder: Any, data: bytes) -> None:
    decoder.start_utt()
    decoder.process_raw(data, full_utt=True)
    decoder.end_utt()


def spoken_words(text: str) -> List[Tuple[str, List[str]]]:
    """Each written word of `text`, with the tokens pocketsphinx looks up for it ("Hello," -> hello)."""
    out = []
    for word in text.split():
        tokens = [t.strip("'") for t in re.findall(r"[a-z0-9']+", word.lower())]
        out.append((word.strip('.,;:!?"()[]{}'), [t for t in tokens if t]))
    return [(word, tokens) for word, tokens in out if tokens]


def _align(decoder: Any, data: bytes, text: str, spell: Optional[Any]) -> Optional[Heard]:
    written = spoken_words(text)
    tokens: List[str] = []
    for _, pieces in written:
        for token in pieces:
            if decoder.lookup_word(token) is None:
                phones = spell(token) if spell is not None else None
                if not phones:
                    continue
                decoder.add_word(token, " ".join(phones), True)
            tokens.append(token)
    if not tokens:
        return None
    alignment = _alignment(decoder, data, " ".join(tokens))
    if alignment is None:
        return None
    phones = [(p.start * FRAME, (p.start + p.duration) * FRAME, p.name) for p in alignment.phones()]
    starts = [(w.start * FRAME, w.name) for w in alignment if not w.name.startswith("<")]
    return Heard(_contiguous(phones, len(data) / 2 / ANALYSIS_RATE), _written_times(written, starts), True)


def _alignment(decoder: Any, data: bytes, text: str) -> Any:
    """pocketsphinx's alignment of `text`, words of its dictionary, to the sound; None if they do
    not fit it."""
    try:
        decoder.set_align_text(text)
        _decode(decoder, data)  # the words' times
        decoder.set_alignment()
        _decode(decoder, data)  # and their phones'
        return decoder.get_alignment()
    except RuntimeError:
        return None


def _written_times(
    written: List[Tuple[str, List[str]]], starts: List[Tuple[float, str]]
) -> Tuple[Tuple[float, str], ...]:
    """Each written word at the start of its first token the alignment placed."""
    out = []
    index = 0
    for word, tokens in written:
        found = None
        for token in tokens:
            for j in range(index, len(starts)):
                if re.sub(r"\(\d+\)$", "", starts[j][1]) == token:
                    found = starts[j][0] if found is None else found
                    index = j + 1
                    break
        if found is not None:
            out.append((found, word))
    return tuple(out)


def _contiguous(
    phones: List[Tuple[float, float, str]], duration: float
) -> Tuple[Tuple[float, float, str], ...]:
    """The phones end to end: each ends where the next starts, the last with the sound; a gap is silence."""
    out: List[Tuple[float, float, str]] = []
    at = 0.0
    for start, end, name in sorted(phones):
        start, end = max(start, at), min(end, duration)
        if start > at + 1e-9:
            out.append((at, start, "SIL"))
        if end > start:
            out.append((start, end, name))
            at = end
    if duration > at + 1e-9:
        if out and out[-1][2] == "SIL":
            out[-1] = (out[-1][0], duration, "SIL")
        else:
            out.append((at, duration, "SIL"))
    return tuple(out)
