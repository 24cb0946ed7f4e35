"""What the face says, as the pages fetch it: a key for each utterance's sound, and its WAV file.

The page learns the keys from the status the pump sends, asks for
`/api/sound/KEY.wav`, and plays it in step with the face (static/sound.js).
"""

from __future__ import annotations

import hashlib
import io
import re

from ..speech.soundtrack import write_wav
from ..speech.synthesis import Utterance

SOUND_KEY = re.compile(r"[0-9a-f]{16}")  # as `sound_key` makes them


def sound_key(utterance: Utterance) -> str:
    """A name for an utterance's sound that the page can ask for: the same words, voice and rate, one
    key; the same recording (by content), one key."""
    recording = utterance.recording.digest if utterance.recording is not None else ""
    said = f"{utterance.voice}\n{utterance.rate}\n{utterance.text}\n{recording}".encode()
    return hashlib.sha1(said).hexdigest()[:16]


def wav_file(utterance: Utterance) -> bytes:
    """The utterance's sound as a WAV file."""
    wav = io.BytesIO()
    write_wav(wav, utterance.samples, utterance.sample_rate)
    return wav.getvalue()
