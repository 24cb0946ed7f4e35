"""Speech started as a live face starts, so that its first `say` waits for nothing."""

from __future__ import annotations

import contextlib
import threading

from ..core.voices import default_voice, natural
from ..extras import MissingTool
from . import natural_voices
from .synthesis import engine


def start_in_background() -> threading.Thread:
    """Start the shared engine, its speech process with it, on a thread of its own; the thread.

    A live face (the node, the screen, the studio, play, stream) calls this as it starts: its first
    `say` then finds the process running rather than waiting for one to start, which a loaded
    machine takes seconds over. A `say` that comes sooner waits for this start (`engine()`'s
    lock), never starts a second one. Without espeak-ng this says nothing: the first `say` does.
    Where the default voice is a natural one, its model is loaded too (a second or so).
    """

    def start() -> None:
        with contextlib.suppress(MissingTool):
            engine()
        voice = default_voice()
        if natural(voice):  # the default voice a natural one ($BAXTERFACE_VOICE): its model too
            with contextlib.suppress(MissingTool):
                natural_voices.load(voice)

    thread = threading.Thread(target=start, name="baxterface-speech-start", daemon=True)
    thread.start()
    return thread
