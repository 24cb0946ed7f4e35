"""Words transcribed from a stretch of speech by Moonshine tiny-en (the `[hear]` extra).

The model (MIT, 71 MB: an encoder and a decoder in ONNX Runtime's own format, and its tokenizer)
ships inside the wheel of `moonshine-voice` 0.0.4 (later releases download it at run time). That
module itself does not load here (its wheel lacks libraries it links), so only its files are read,
and `onnxruntime` runs them, as the face finder reads MTCNN's files.

The decoder is greedy, token by token, with its cache; `bias` adds to the score of the tokens that
spell the phrases listened for, so that a word said unclearly is read as one of them rather than as
its neighbour ("robot" rather than "road"), within a bound on what it changes in all.
"""

from __future__ import annotations

import importlib.util
import os
import threading
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..extras import MissingTool, need

EXTRA = "hear"
RATE = 16000
PACKAGE = "moonshine_voice"
MODEL = ("assets", "tiny-en")
START, END = 1, 2  # the decoder's first token, and the one that ends the text
TOKENS_A_SECOND = 6.5  # at most, as Moonshine's own decoder bounds a text by its sound
LAYERS, HEADS, HEAD_SIZE = 6, 8, 36
LOOP = 3  # the same tokens said this many times over in a row end the text (once)
SPACE = "\u2581"  # SentencePiece's mark of a word's start
BYTE_TOKENS = range(3, 259)  # <0x00>..<0xFF>: a byte each, for what the vocabulary lacks
_LOCK = threading.Lock()  # one model a process, run by one thread at a time
_MODEL: Optional[Transcriber] = None


def available() -> bool:
    """Are the runtime and the model's package installed?"""
    return all(importlib.util.find_spec(m) is not None for m in ("onnxruntime", PACKAGE))


def model_folder() -> str:
    """Where the model's files are inside the installed package (MissingTool when it is not)."""
    need("onnxruntime", EXTRA, "hearing words with Moonshine")
    spec = importlib.util.find_spec(PACKAGE)
    if spec is None or spec.origin is None:
        raise MissingTool(
            f"hearing words with Moonshine needs the '{PACKAGE}' package: pip install 'baxterface[{EXTRA}]'"
        )
    return os.path.join(os.path.dirname(spec.origin), *MODEL)


def read_tokens(path: str) -> List[bytes]:
    """The tokenizer's vocabulary: each token's bytes, its length first (one byte, or two when the
    first has its high bit set)."""
    with open(path, "rb") as f:
        data = f.read()
    tokens, i = [], 0
    while i < len(data):
        size = data[i]
        i += 1
        if size >= 128:
            size = (size & 0x7F) | (data[i] << 7)
            i += 1
        tokens.append(data[i : i + size])
        i += size
    return tokens


def session(onnxruntime, path: str):
    """An ONNX Runtime session on one thread (listening shares the machine with the face), its
    memory given back after each run."""
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = 1
    options.inter_op_num_threads = 1
    options.log_severity_level = 3
    # Each look's sound has a length of its own: an arena, and plans kept for each length, grew
    # to 555 MB over minutes of babble; without them the listener stays near 250 MB.
    options.enable_cpu_mem_arena = False
    options.enable_mem_pattern = False
    return onnxruntime.InferenceSession(path, options, providers=["CPUExecutionProvider"])


class Transcriber:
    """Moonshine tiny-en: 16 kHz samples in, their words out (see the module's docstring)."""

    def __init__(self, folder: str) -> None:
        ort = need("onnxruntime", EXTRA, "hearing words with Moonshine")
        self.encoder = session(ort, os.path.join(folder, "encoder_model.ort"))
        self.decoder = session(ort, os.path.join(folder, "decoder_model_merged.ort"))
        self.tokens = read_tokens(os.path.join(folder, "tokenizer.bin"))
        self._outputs = [o.name for o in self.decoder.get_outputs()]
        self._index: Dict[bytes, int] = {}
        for i, token in enumerate(self.tokens):
            if i not in BYTE_TOKENS:
                self._index.setdefault(token, i)

    def spelling(self, text: str) -> List[int]:
        """The tokens that spell `text` (each word with its space mark), longest first."""
        ids: List[int] = []
        for word in text.split():
            rest = (SPACE + word).encode("utf-8")
            while rest:
                size = next((k for k in range(len(rest), 0, -1) if rest[:k] in self._index), 0)
                if size == 0:
                    ids.append(3 + rest[0])
                    rest = rest[1:]
                else:
                    ids.append(self._index[rest[:size]])
                    rest = rest[size:]
        return ids

    def spellings(self, text: str) -> List[List[int]]:
        """The tokens of `text` as the decoder writes it mid-sentence, and capitalised as at a
        sentence's start (other tokens: "Go" is not "go"). An answer is most often said alone, so
        the bias has to reach its capitalised spelling: with the lower case alone, joe's fast "go
        on" was heard as "Dillon"."""
        first = text[:1].upper() + text[1:]
        return [self.spelling(text)] + ([self.spelling(first)] if first != text else [])

    def text(self, ids: Sequence[int]) -> str:
        data = b"".join(bytes([i - 3]) if i in BYTE_TOKENS else self.tokens[i] for i in ids)
        return data.decode("utf-8", "replace").replace(SPACE, " ").strip()

    def transcribe(
        self, samples: np.ndarray, favoured: Sequence[Sequence[int]] = (), bias: float = 0.0
    ) -> str:
        """The words said in `samples` (int16 or float in [-1, 1], 16 kHz); `bias` is added to the
        scores of the tokens that begin or go on with a `favoured` spelling (see `lifted`). What it
        may change in a text is bounded by `bias` in all, summed over the tokens it chose against
        the model's own best (their scores' difference): one word said unclearly is read as a
        phrase's, but a phrase is not made up from noise token by token (a chain of lifts heard
        "what is your name" in the first second of "well, no thanks")."""
        scale = 32768.0 if np.issubdtype(np.asarray(samples).dtype, np.integer) else 1.0
        sound = (np.asarray(samples, np.float32) / scale).reshape(1, -1)
        if sound.shape[1] < RATE // 4:  # the encoder needs a quarter of a second at least
            return ""
        with _LOCK:
            return self._decode(sound, favoured, bias)

    def _decode(self, sound: np.ndarray, favoured: Sequence[Sequence[int]], bias: float) -> str:
        whole = np.ones(sound.shape, np.int64)
        hidden = self.encoder.run(None, {"input_values": sound, "attention_mask": whole})[0]
        empty = np.zeros((1, HEADS, 0, HEAD_SIZE), np.float32)
        past = {
            f"past_key_values.{layer}.{part}.{kind}": empty
            for layer in range(LAYERS)
            for part in ("decoder", "encoder")
            for kind in ("key", "value")
        }
        said: List[int] = []
        last, cached = START, False
        spent = 0.0  # what the bias has cost the text so far (see `transcribe`)
        for _ in range(int(sound.shape[1] / RATE * TOKENS_A_SECOND) + 4):
            feed = {
                "input_ids": np.array([[last]], np.int64),
                "encoder_hidden_states": hidden,
                "encoder_attention_mask": whole,  # over the samples: the decoder scales it down
                "use_cache_branch": np.array([cached]),
                **past,
            }
            results = self.decoder.run(None, feed)
            scores = results[0][0, -1]
            last = int(scores.argmax())
            lift = lifted(favoured, said) if bias else []
            if lift:
                raised = scores.copy()
                raised[lift] += bias
                choice = int(raised.argmax())
                cost = float(scores[last] - scores[choice])  # how much less likely the text is for it
                if spent + cost <= bias:
                    last, spent = choice, spent + cost
            for name, value in zip(self._outputs[1:], results[1:]):
                if not cached or ".decoder." in name:  # the encoder's part is the same at every step
                    past[name.replace("present", "past_key_values")] = value
            cached = True
            if last == END:
                break
            said.append(last)
            if looping(said):  # noise read as "♪♪♪♪", a short word as "hello hello hello"
                return self.text(said[: len(said) - 2 * looping(said)])
        return self.text(said)


def looping(said: Sequence[int]) -> int:
    """The length of the tokens the text ends with LOOP times over (0: none): the greedy decoder's
    way of going on where there are no more words."""
    for size in range(1, 5):
        if len(said) >= LOOP * size and all(
            said[len(said) - (k + 1) * size : len(said) - k * size] == said[len(said) - size :]
            for k in range(1, LOOP)
        ):
            return size
    return 0


def lifted(favoured: Sequence[Sequence[int]], said: Sequence[int]) -> List[int]:
    """The tokens that would begin a favoured spelling, or take one further whose start the text
    ends with: the bias follows a phrase token by token ("tell me" then "a", not "the")."""
    lift = set()
    for spelled in favoured:
        lift.add(spelled[0])
        for k in range(1, min(len(spelled), len(said) + 1)):
            if list(said[-k:]) == list(spelled[:k]):
                lift.add(spelled[k])
    return sorted(lift)


def transcriber() -> Transcriber:
    """The model, loaded once a process (MissingTool, naming the extra, when it is missing)."""
    global _MODEL
    with _LOCK:
        if _MODEL is None:
            _MODEL = Transcriber(model_folder())
        return _MODEL
