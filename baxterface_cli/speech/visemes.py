"""Mouth shapes for speech: an utterance's phonemes as a track of timed mouth keys.

Each phoneme has a shape (PHONEME_SHAPES, or a guess from its first letter for
the languages the table leaves out); the track is those shapes, cleaned up by
these rules, whose numbers are in MOUTH_RULES:

- Nothing flickers: a sound shorter than `hold` merges into the neighbouring
  sound nearest its shape (between two closures, into a closure), except p, b
  and m: closed lips matter most for a voice and a mouth to look in sync, so
  they always show "closed", for `closure` at least (more than a frame at 30
  fps), and nothing takes time from them.
- Only far shapes (closed and open, round and wide...: more than `far` apart
  in SHAPE_POSITIONS) tween, over `tween`; near ones cut. Closures always cut,
  so the lips do shut.
- Silence is read from the sound as well as from the pause phonemes, so the
  silent end of a phoneme counts too. Through any silence of `pause` or more
  the mouth is at REST (the emotion's own mouth), and there fully within
  `rest_within` of its start. The first key is not before the voice starts;
  the last is REST, when the voice stops.
"""

from __future__ import annotations

import bisect
import math
from typing import Dict, List, NamedTuple, Optional, Tuple

import numpy as np

from ..core.face_constants import REST
from .synthesis import Utterance


class MouthKey(NamedTuple):
    """From `at` (seconds from the utterance start), the mouth shows `shape`."""

    at: float
    shape: str  # a VISEMES key or REST
    blend: float  # seconds the mouth tweens into this shape from the one before (0: a cut)


class MouthRules(NamedTuple):
    """The numbers in the rules at the top of this module."""

    hold: float = 0.055  # the shortest a shape shows
    closure: float = 0.035  # the shortest p, b and m show "closed"
    tween: float = 0.04  # how long far shapes blend
    far: float = 0.75  # shapes further apart than this in SHAPE_POSITIONS tween
    pause: float = 0.1  # silences this long (or longer) rest the mouth
    rest_within: float = 0.03  # and it is at rest this soon after they start
    window: float = 0.01  # seconds of sound whose RMS tells silence
    silence: float = 50.0  # RMS, in int16 steps (-56 dBFS), under which a window is silent
    loud: int = 32  # the voice starts with the first sample over this and ends with the last


MOUTH_RULES = MouthRules()

# espeak-ng's phoneme mnemonics (as English speaks them: en, en-gb, en-us and their accents) by the
# shape they show. Pauses ("_", "_:", "_!") are REST whatever their name; p/b/m are closures.
_SHAPE_PHONEMES: Dict[str, str] = {
    "closed": "p b m m- p2 b2",
    "fv": "f v",
    "lth": "l l/ @L T D",
    "round": "w w# u: U U@ u@ oU O: O@ o@ O2 OI 0# uI",
    "wide": "i: i I IR E e@ eI i@ i@3 j ; s z S Z tS dZ",
    "open": "a aa a2 A: A@ A# V VR 0 aI aI2 aI3 aI@ aU",
    "slight": "@ @2 @5 @- 3 3: a# I2 I# r r- t t# t2 t[ d d# n n- N k g h ? x",
}
PHONEME_SHAPES: Dict[str, str] = {
    name: shape for shape, names in _SHAPE_PHONEMES.items() for name in names.split()
}
CLOSURES = frozenset(_SHAPE_PHONEMES["closed"].split())

# For phonemes not in the table: the shape by the mnemonic's first letter (espeak-ng's names
# follow the Kirshenbaum ASCII-IPA letters: y is the rounded i, 0 the open o...). Affricates
# go with their fricative; anything else is a consonant, "slight".
_AFFRICATES = ("ts", "tS", "dz", "dZ", "tC", "dJ")
_FIRST_LETTER_SHAPES: Dict[str, str] = {
    **dict.fromkeys("pbm", "closed"),
    **dict.fromkeys("fv", "fv"),
    **dict.fromkeys("lLTD", "lth"),
    **dict.fromkeys("wuUoOyYW", "round"),
    **dict.fromkeys("ieEIj;szSZcCJ", "wide"),
    **dict.fromkeys("aA&V0", "open"),
    **dict.fromkeys("@3", "slight"),
}

# Where each shape sits: (how open, how spread: +1 spread wide .. -1 pursed round). REST, the
# emotion's own mouth, is taken as a loosely closed smile.
SHAPE_POSITIONS: Dict[str, Tuple[float, float]] = {
    "closed": (0.0, 0.0),
    "fv": (0.15, 0.3),
    "slight": (0.3, 0.2),
    "lth": (0.45, 0.2),
    "wide": (0.45, 0.8),
    "round": (0.5, -0.8),
    "open": (1.0, 0.2),
    REST: (0.2, 0.3),
}


def phoneme_shape(name: str) -> str:
    """The mouth shape for an espeak-ng phoneme mnemonic: the table's, or a guess for other languages."""
    if not name or name.startswith("_"):
        return REST
    shape = PHONEME_SHAPES.get(name)
    if shape is not None:
        return shape
    if name.startswith(_AFFRICATES):
        return "wide"
    return _FIRST_LETTER_SHAPES.get(name[0], "slight")


def distance(a: str, b: str) -> float:
    (x1, y1), (x2, y2) = SHAPE_POSITIONS[a], SHAPE_POSITIONS[b]
    return math.hypot(x1 - x2, y1 - y2)


# --- the track ----------------------------------------------------------------------------------------

_SOUND, _CLOSURE, _PAUSE = 0, 1, 2  # what a span is, in the order that wins when two merge


class _Span(NamedTuple):
    start: float
    end: float
    shape: str
    kind: int
    # For a pause: by when the mouth must be fully at rest. Spans before it may run into it
    # until then, when they would otherwise be too short to see.
    due: float = math.inf

    @property
    def length(self) -> float:
        return self.end - self.start


def mouth_track(utterance: Utterance, rules: MouthRules = MOUTH_RULES) -> Tuple[MouthKey, ...]:
    """The mouth keys for an utterance, in time order; () when it makes no sound."""
    voice, pauses = _silences(utterance, rules)
    if voice is None:
        return ()
    start, end = voice
    spans = _phoneme_spans(utterance, start, end)
    spans = _carve(spans, pauses)
    spans = _lengthen_closures(spans, rules)
    spans = _merge_short(spans, rules)
    return _keys(spans, rules)


def _silences(u: Utterance, rules: MouthRules) -> Tuple[Optional[Tuple[float, float]], List[_Span]]:
    """When the voice starts and stops, and the pauses between: silences of `pause` or more.

    The voice is from its first sample over `loud` to its last. Inside it, a millisecond is
    silent when some window of `window` seconds around it is, so a silence is found to its
    edges, not to the nearest window.
    """
    rate = u.sample_rate
    loud = np.abs(np.asarray(u.samples, dtype=np.int32)) > rules.loud
    if not loud.any():
        return None, []
    voice = (int(np.argmax(loud)) / rate, (len(loud) - int(np.argmax(loud[::-1]))) / rate)
    step = max(1, round(rate / 1000))  # samples in a millisecond
    width = max(1, round(rules.window * rate / step))  # milliseconds in a window
    count = len(u.samples) // step
    silences = []
    if count >= width:
        blocks = u.samples[: count * step].astype(np.float64).reshape(count, step)
        energy = np.concatenate(([0.0], np.cumsum((blocks * blocks).sum(axis=1))))
        quiet = (energy[width:] - energy[:-width]) < rules.silence**2 * width * step  # by first millisecond
        # Millisecond i is in the windows that start from i - width + 1 to i.
        quiet_before = np.concatenate(([0], np.cumsum(quiet)))
        index = np.arange(count)
        first, last = np.clip(index - width + 1, 0, len(quiet)), np.clip(index + 1, 0, len(quiet))
        silent = (quiet_before[last] - quiet_before[first]) > 0
        silences = [
            (a * step / rate, b * step / rate) for a, b in _runs(silent) if b - a >= rules.pause * 1000
        ]
    silences += [(p.at, p.end) for p in u.phonemes if p.name.startswith("_") and p.end - p.at >= rules.pause]
    pauses: List[_Span] = []
    for a, b in sorted((max(a, voice[0]), min(b, voice[1])) for a, b in silences):
        if b <= a:
            continue
        if pauses and a <= pauses[-1].end:
            pauses[-1] = pauses[-1]._replace(end=max(b, pauses[-1].end))
        else:
            pauses.append(_Span(a, b, REST, _PAUSE, a + rules.rest_within))
    # The rest after the voice lasts on; the mouth is there by the end of the sound.
    due = min(voice[1] + rules.rest_within, max(voice[1], u.duration))
    pauses.append(_Span(voice[1], math.inf, REST, _PAUSE, due))
    return voice, pauses


def _runs(mask: np.ndarray) -> List[Tuple[int, int]]:
    """(start, end) of each run of True."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    return list(zip(edges[0::2].tolist(), edges[1::2].tolist()))


def _phoneme_spans(u: Utterance, start: float, end: float) -> List[_Span]:
    spans = []
    for p in u.phonemes:
        a, b = max(p.at, start), min(p.end, end)
        if b > a:
            shape = phoneme_shape(p.name)
            spans.append(_Span(a, b, shape, _CLOSURE if shape == "closed" else _SOUND))
    return spans


def _carve(spans: List[_Span], pauses: List[_Span]) -> List[_Span]:
    """The spans with the pauses cut out of them and put in their place."""
    result: List[_Span] = []
    for span in spans:
        pieces = [span]
        for pause in pauses:
            if pause.start >= span.end or pause.end <= span.start:
                continue
            cut = []
            for piece in pieces:
                if piece.start < pause.start:
                    cut.append(piece._replace(end=min(piece.end, pause.start)))
                if piece.end > pause.end:
                    cut.append(piece._replace(start=max(piece.start, pause.end)))
            pieces = cut
        result.extend(p for p in pieces if p.end > p.start)
    result.extend(pauses)
    result.sort(key=lambda s: (s.start, s.end))
    return _joined(result)


def _joined(spans: List[_Span]) -> List[_Span]:
    """Neighbours with the same shape as one span; a pause or a closure keeps its kind."""
    result: List[_Span] = []
    for span in spans:
        if result and result[-1].shape == span.shape and span.start <= result[-1].end + 1e-9:
            before = result[-1]
            kind, due = max((before.kind, before.due), (span.kind, span.due), key=lambda k: k[0])
            result[-1] = _covering(before, span)._replace(kind=kind, due=due)
        else:
            result.append(span)
    return result


def _covering(span: _Span, other: _Span) -> _Span:
    """`span` grown over `other`, its neighbour."""
    return span._replace(start=min(span.start, other.start), end=max(span.end, other.end))


def _take(spans: List[_Span], i: int, j: int, wanted: float, rules: MouthRules) -> float:
    """Move the border between span i and its neighbour j so that i grows by up to `wanted`.

    A sound gives all it has (it may merge away later); a pause only its start, until it is
    due; a closure nothing, as every p, b and m in it must show. Returns the time taken.
    """
    other = spans[j]
    if other.kind == _SOUND:
        spare = other.length
    elif other.kind == _PAUSE and j > i:
        spare = other.due - other.start
    else:
        spare = 0.0
    taken = max(0.0, min(wanted, spare))
    if taken <= 0:
        return 0.0
    if j > i:
        spans[i] = spans[i]._replace(end=spans[i].end + taken)
        spans[j] = other._replace(start=other.start + taken)
    else:
        spans[i] = spans[i]._replace(start=spans[i].start - taken)
        spans[j] = other._replace(end=other.end - taken)
    return taken


def _lengthen_closures(spans: List[_Span], rules: MouthRules) -> List[_Span]:
    spans = list(spans)
    for i, span in enumerate(spans):
        if span.kind != _CLOSURE or span.length >= rules.closure:
            continue
        wanted = rules.closure - span.length
        # The lips shut for the closure and open for the release: grow into what follows first.
        for j in (i + 1, i - 1):
            if 0 <= j < len(spans) and spans[j].kind != _CLOSURE:
                wanted -= _take(spans, i, j, wanted, rules)
    return _joined([s for s in spans if s.end > s.start + 1e-9])


def _merge_short(spans: List[_Span], rules: MouthRules) -> List[_Span]:
    """Merge every sound shorter than `hold` into a neighbour until none flickers."""
    spans = list(spans)
    stuck = set()  # starts of spans that cannot be helped: between pauses, too short
    while True:
        short = [
            i
            for i, s in enumerate(spans)
            if s.kind == _SOUND and s.length < rules.hold - 1e-9 and s.start not in stuck
        ]
        if not short:
            return spans
        i = min(short, key=lambda k: (spans[k].length, k))
        span = spans[i]
        neighbours = [j for j in (i - 1, i + 1) if 0 <= j < len(spans)]
        sounds = [j for j in neighbours if spans[j].kind == _SOUND]
        if sounds:
            j = min(sounds, key=lambda k: (distance(span.shape, spans[k].shape), -spans[k].length))
            spans[j] = _covering(spans[j], span)
            del spans[i]
            spans = _joined(spans)
            continue
        # Between closures and pauses: run on into a pause, else stay closed with the closure.
        wanted = rules.hold - span.length
        for j in sorted(neighbours, reverse=True):
            wanted -= _take(spans, i, j, wanted, rules)
        closures = [j for j in neighbours if spans[j].kind == _CLOSURE]
        if wanted > 1e-9 and closures:
            spans[closures[0]] = _covering(spans[closures[0]], spans[i])
            del spans[i]
        elif wanted > 1e-9:
            stuck.add(spans[i].start)
        spans = _joined([s for s in spans if s.end > s.start + 1e-9])


def _keys(spans: List[_Span], rules: MouthRules) -> Tuple[MouthKey, ...]:
    keys: List[MouthKey] = []
    shape = REST
    for span in spans:
        if span.shape == shape:
            continue
        blend = 0.0
        if span.kind != _CLOSURE and distance(shape, span.shape) > rules.far:
            blend = min(rules.tween, span.length, max(0.0, span.due - span.start))
        keys.append(MouthKey(span.start, span.shape, blend))
        shape = span.shape
    return tuple(keys)


def shape_at(track: Tuple[MouthKey, ...], t: float) -> Tuple[str, Optional[str], float]:
    """The mouth at t: (shape, the shape it is tweening from or None, progress 0..1).

    REST before the first key; a track ends with REST, so it is REST after its end too.
    """
    # Keys at or before t come before this probe: it sorts after any key at exactly t.
    i = bisect.bisect_right(track, (t, "\U0010ffff", math.inf)) - 1
    if i < 0:
        return REST, None, 1.0
    key = track[i]
    if key.blend > 0 and t < key.at + key.blend:
        return key.shape, track[i - 1].shape if i > 0 else REST, (t - key.at) / key.blend
    return key.shape, None, 1.0


COARTICULATION = 0.04  # seconds the drawn mouth moves into each new shape, as lips do between sounds


def coarticulated_at(track: Tuple[MouthKey, ...], t: float) -> Tuple[str, Optional[str], float]:
    """As `shape_at`, for a mouth drawn from numbers: every shape is moved into, over its own
    tween or COARTICULATION (at most its length), except "closed", which cuts, so the lips of
    p, b and m do shut."""
    i = bisect.bisect_right(track, (t, "\U0010ffff", math.inf)) - 1
    if i < 0:
        return REST, None, 1.0
    key = track[i]
    if key.shape == "closed" or i == 0:
        return shape_at(track, t)
    length = track[i + 1].at - key.at if i + 1 < len(track) else COARTICULATION
    # Into a pause, no slower than the rules' promise that the mouth is at rest within rest_within.
    most = MOUTH_RULES.rest_within if key.shape == REST else COARTICULATION
    blend = key.blend or min(most, length)
    if blend > 0 and t < key.at + blend:
        return key.shape, track[i - 1].shape, (t - key.at) / blend
    return key.shape, None, 1.0
