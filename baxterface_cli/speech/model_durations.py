"""A natural voice's phoneme times, as its own model decides them, named as espeak-ng names phonemes.

The models of natural_voices.py decide how long each phoneme lasts before they make its sound (piper's
durations are its `Ceil` node's output, hibari's its `Round` node's), but do not hand the times out.
`with_output` makes that node's output one of the model's outputs by editing the ONNX file's
protobuf (a ModelProto's graph, field 7, gets one more output, GraphProto field 12, naming it):
what `piper.patch_voice_with_alignment` does with the `onnx` package, without it. The sound is the
same; the times are then the synthesizer's own, as espeak-ng's are for its voices, so the mouth
cannot drift from the voice.

The phonemes are IPA (piper's, from espeak-ng) or misaki's letters (hibari's: A is eI, I aI, O oU,
W aU, Y OI); each is named by the espeak-ng phoneme of the same mouth (visemes.py's table). A stress
mark belongs to the vowel after it, a length mark, a space between words and a diphthong's second half
to the phoneme before; punctuation and the pads at the ends are pauses.
"""

from __future__ import annotations

import itertools
import math
from typing import Iterable, List, Tuple

from .synthesis import Phoneme

_PAIRS = (
    "p=p b=b m=m f=f v=v θ=T ð=D l=l ɫ=l ɬ=l w=w u=u: ʊ=U ɔ=O: o=oU ɒ=0 "  # closed, fv, lth, round
    "i=i: ɪ=I ɛ=E e=eI j=j s=s z=z ʃ=S ʒ=Z ç=h a=a æ=a ɑ=A: ʌ=V "  # wide, open
    "ə=@ ɚ=3: ɜ=3: ɐ=a# ᵻ=I# ᵊ=@ ɾ=t r=r ɹ=r t=t d=d n=n ŋ=N k=k ɡ=g g=g h=h ʔ=? x=x "  # slight
    "A=eI I=aI O=oU W=aU Y=OI Q=oU ʤ=dZ ʧ=tS T=t"  # misaki's letters
)
ESPEAK_NAMES = dict(pair.split("=") for pair in _PAIRS.split(" "))
GLIDES = {"aɪ": "aI", "aʊ": "aU", "eɪ": "eI", "oʊ": "oU", "ɔɪ": "OI"}
STRESS, GOES_ON = "ˈˌ", "ː "
PAUSE = "_"
DIGIT = 4
BAND = 24
MOST = 12  # the most words one is matched with: "1,234,567" is said as eleven
RUN = 1.0  # what matching words in a run costs beyond one to one: a run is only for a good reason


def with_output(model: bytes, op: bytes) -> bytes:
    """The ONNX `model` with the output of its one `op` node as a model output too; ValueError
    where it has none, or more than one."""
    top = _fields(model)
    graphs = [raw for number, wire, raw in top if number == 7 and wire == 2]
    if len(graphs) != 1:
        raise ValueError("not an ONNX model")
    graph = _fields(_payload(graphs[0]))
    found = []
    for number, wire, raw in graph:
        if number == 1 and wire == 2:  # a node: its op_type is field 4, its outputs field 2
            node = _fields(_payload(raw))
            if any(n == 4 and _payload(r) == op for n, _, r in node):
                found += [_payload(r) for n, _, r in node if n == 2]
    if len(found) != 1:
        raise ValueError(f"{len(found)} outputs of {op.decode()} nodes, not one")
    edited = b"".join(raw for _, _, raw in graph) + _field(12, _field(1, found[0]))
    return b"".join(_field(7, edited) if number == 7 else raw for number, _, raw in top)


def timed_phonemes(
    timed: Iterable[Tuple[str, int]], rate: int, offset: int, end: int
) -> Tuple[Tuple[Phoneme, ...], List[List[float]]]:
    """(symbol, samples it lasts) in order as espeak-ng's phonemes, in seconds from sample `offset`
    (where the kept sound starts) to `end` (its length), and the model's words: the starts of each
    one's phonemes."""
    spans: List[List] = []  # [start, end, name], in samples of the whole sound
    words: List[List[int]] = []
    at, stressed, previous, new_word = 0, None, "", True
    for symbol, count in timed:
        start, at = at, at + count
        if symbol in STRESS:
            stressed = start if stressed is None else stressed
            continue
        glide = GLIDES.get(previous + symbol)
        previous = symbol
        if glide is not None and spans:
            spans[-1][1:] = [at, glide]
            continue
        name = ESPEAK_NAMES.get(symbol)
        if name is None and symbol in GOES_ON and spans:
            spans[-1][1] = at
            new_word = new_word or symbol == " "
            continue
        begin, stressed = (start if stressed is None else stressed), None
        if name is None:
            name, new_word = PAUSE, True
        elif new_word or not words:
            words.append([begin])
            new_word = False
        else:
            words[-1].append(begin)
        if spans and spans[-1][2] == name == PAUSE:
            spans[-1][1] = at
        else:
            spans.append([begin, at, name])
    phonemes = tuple(
        Phoneme(max(0, a - offset) / rate, min(b - offset, end) / rate, name)
        for a, b, name in spans
        if min(b - offset, end) > max(0, a - offset)
    )
    return phonemes, [[max(0, at - offset) / rate for at in word] for word in words]


def placed_words(written: List[str], spoken: List[List[float]]) -> List[float]:
    """When each written word starts, given the model's words (each its phonemes' starts).

    The model may run words together ("I am" as one) or say one as several (a number): the written
    words and the spoken ones are matched in runs, one to one, several written to one spoken or one
    written to several spoken, the runs whose sizes (letters against phonemes, at the utterance's
    own ratio) agree best. Several written words in one spoken word start as far through its phonemes
    as they are through its letters."""
    if len(written) == len(spoken):
        return [word[0] for word in spoken]
    if not written or not spoken:
        return []
    # A digit is said as a word or so: about as many phonemes as DIGIT letters.
    letters = [max(1, sum(DIGIT if char.isdigit() else char.isalpha() for char in word)) for word in written]
    sounds = [len(word) for word in spoken]
    ratio = sum(sounds) / sum(letters)
    letters_before = [0, *itertools.accumulate(letters)]
    sounds_before = [0, *itertools.accumulate(sounds)]
    best = {(0, 0): (0.0, (0, 0))}  # (written, spoken) matched so far -> cost, where its last run began
    slope = len(spoken) / len(written)
    for i in range(len(written) + 1):
        # The runs keep near the diagonal: BAND words either way of it (a long text stays quick).
        low, high = max(0, int(i * slope) - BAND), min(len(spoken), int(i * slope) + BAND)
        for j in range(low, high + 1):
            if (i, j) not in best:
                continue
            cost = best[(i, j)][0]
            most_spoken, most_written = min(MOST, len(spoken) - j), min(MOST, len(written) - i)
            runs = [(1, b) for b in range(1, most_spoken + 1)] + [(a, 1) for a in range(2, most_written + 1)]
            for a, b in runs:
                if i + a > len(written) or j + b > len(spoken):
                    continue
                said = sounds_before[j + b] - sounds_before[j]
                size = abs(math.log(said / (ratio * (letters_before[i + a] - letters_before[i]))))
                size += RUN if a + b > 2 else 0.0
                key = (i + a, j + b)
                if key not in best or cost + size < best[key][0]:
                    best[key] = (cost + size, (i, j))
    if (len(written), len(spoken)) not in best:  # runs too long to match: the model's words in order
        starts = [word[0] for word in spoken]
        return [starts[min(i, len(starts) - 1)] for i in range(len(written))]
    out: List[float] = []
    key = (len(written), len(spoken))
    while key != (0, 0):
        i, j = best[key][1]
        a = key[0] - i
        phonemes = spoken[j]
        through = 0
        run = []
        for count in letters[i : i + a]:
            run.append(
                phonemes[min(len(phonemes) - 1, round(len(phonemes) * through / sum(letters[i : i + a])))]
            )
            through += count
        out = run + out
        key = (i, j)
    return out


def _fields(data: bytes) -> List[Tuple[int, int, bytes]]:
    """A protobuf message's top-level fields: (number, wire type, its bytes with their key)."""
    out, i = [], 0
    while i < len(data):
        start = i
        key, i = _varint(data, i)
        number, wire = key >> 3, key & 7
        if wire == 0:
            _, i = _varint(data, i)
        elif wire == 1:
            i += 8
        elif wire == 2:
            length, i = _varint(data, i)
            i += length
        elif wire == 5:
            i += 4
        else:
            raise ValueError(f"not an ONNX model (protobuf wire type {wire})")
        if i > len(data):
            raise ValueError("not an ONNX model (cut short)")
        out.append((number, wire, data[start:i]))
    return out


def _varint(data: bytes, i: int) -> Tuple[int, int]:
    value = shift = 0
    while True:
        if i >= len(data):
            raise ValueError("not an ONNX model (cut short)")
        byte = data[i]
        i += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if not byte & 0x80:
            return value, i


def _payload(raw: bytes) -> bytes:
    """A length-delimited field's contents, without its key and length."""
    _, i = _varint(raw, 0)
    _, i = _varint(raw, i)
    return raw[i:]


def _field(number: int, payload: bytes) -> bytes:
    return _varint_bytes((number << 3) | 2) + _varint_bytes(len(payload)) + payload


def _varint_bytes(value: int) -> bytes:
    out = bytearray()
    while True:
        byte, value = value & 0x7F, value >> 7
        out.append(byte | (0x80 if value else 0))
        if not value:
            return bytes(out)
