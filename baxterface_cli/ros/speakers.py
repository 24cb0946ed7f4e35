"""Where the face's speech goes on a robot: sound_play, this machine's sound device, or nowhere.

`open_speaker` turns an audio mode (the node's `_audio:=`, stream's `--audio`)
into its speaker, for the face node and `stream` alike.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import threading
import time
from collections import deque
from typing import Any, Callable, Deque, Dict, Optional, Tuple

from ..closing import ClosedOnExit
from ..core.run_folders import own_folder
from ..engine.effects import Speech
from ..speech.soundtrack import write_wav
from .effect_messages import COMMAND_TYPES, PLAY_ONCE, PLAY_STOP, SOUND_PLAY_FILE, SOUND_TOPIC


class Speaker(ClosedOnExit):
    """Where speech goes: nowhere (`_audio:=none`: the mouth moves, nothing is heard).

    `speak` runs on the frame loop as a Speech cue falls due, which is when the
    mouth starts moving, so it starts the sound and returns.
    """

    def __init__(self, link: Any, warn: Callable[[str], None]) -> None:
        pass

    def speak(self, effect: Speech) -> None:
        """Start saying the effect's utterance now."""

    def stop(self) -> None:
        """Stop what is being said: a new command took over."""

    def close(self) -> None:
        """Let go of what it holds."""


class SoundPlaySpeaker(Speaker):
    """Each utterance as a WAV file, played by ROS's sound_play (PLAY_FILE on /robotsound).

    sound_play opens the file by its path, so it must run on this machine. The
    files live in a folder of this speaker's own (named with the pid, so a node
    killed outright has it swept by the next: core/run_folders.py), each removed
    by a timer once it has surely been played, the oldest sooner when they take
    more than `MAX_BYTES`, and the folder with them on `close`.
    """

    KEEP = 30.0  # seconds a file outlives its sound: sound_play may open it late
    MAX_BYTES = 64 * 2**20  # the folder's most: beyond it the oldest go, however recent

    def __init__(self, link: Any, warn: Callable[[str], None]) -> None:
        self.warn = warn
        self.publisher = link.publisher(SOUND_TOPIC, COMMAND_TYPES[SOUND_TOPIC])
        self.folder = own_folder("speech")
        self.files: Deque[Tuple[str, float, int]] = deque()  # (path, when it may go, bytes), oldest first
        self.playing: Optional[Tuple[str, float]] = None  # (path, when its sound ends)
        self.said = 0
        self.changed = threading.Condition()
        self.closed = False
        self.remover = threading.Thread(target=self._remove_on_time, name="speech-files", daemon=True)
        self.remover.start()

    def speak(self, effect: Speech) -> None:
        now = time.monotonic()
        if self.said == 0 and self.publisher.listeners() == 0:
            # A request that nobody hears is dropped without a word: only this tells.
            self.warn(
                f"nothing listens on {SOUND_TOPIC}, so the face is not heard: start sound_play on this "
                "machine (rosrun sound_play soundplay_node.py), or choose another audio mode"
            )
        self.said += 1
        utterance = effect.utterance
        path = os.path.join(self.folder, f"say-{self.said:06d}.wav")
        write_wav(path, utterance.samples, utterance.sample_rate)
        self._request(PLAY_ONCE, path)
        self.playing = (path, now + utterance.duration)
        with self.changed:
            self.files.append((path, now + utterance.duration + self.KEEP, _size(path)))
            while len(self.files) > 1 and sum(f[2] for f in self.files) > self.MAX_BYTES:
                _remove(self.files.popleft()[0])
            self.changed.notify()

    def stop(self) -> None:
        if self.playing is not None and self.playing[1] > time.monotonic():
            self._request(PLAY_STOP, self.playing[0])
        self.playing = None

    def close(self) -> None:
        with self.changed:
            self.closed = True
            self.changed.notify()
        self.remover.join(timeout=5.0)
        shutil.rmtree(self.folder, ignore_errors=True)

    def _remove_on_time(self) -> None:
        """Remove each file when it falls due, whether or not anything more is said."""
        with self.changed:
            while not self.closed:
                now = time.monotonic()
                while self.files and self.files[0][1] <= now:
                    _remove(self.files.popleft()[0])
                self.changed.wait(self.files[0][1] - now if self.files else None)

    def _request(self, command: int, path: str) -> None:
        self.publisher.publish(sound=SOUND_PLAY_FILE, command=command, volume=1.0, arg=path, arg2="")


def _size(path: str) -> int:
    try:
        return os.path.getsize(path)
    except OSError:
        return 0


def _remove(path: str) -> None:
    with contextlib.suppress(OSError):  # gone already
        os.remove(path)


class LocalSpeaker(Speaker):
    """The utterance on this machine's own sound device (none there: a warning, once, and silence)."""

    def __init__(self, link: Any, warn: Callable[[str], None]) -> None:
        from ..speech.sound_device import open_sound

        self.sound = open_sound(warn)

    def speak(self, effect: Speech) -> None:
        self.sound.play(effect.utterance.samples, effect.utterance.sample_rate)

    def stop(self) -> None:
        self.sound.stop()

    def close(self) -> None:
        self.sound.close()


# The audio modes (the node's `_audio:=`, stream's `--audio`) and their speakers.
SPEAKERS: Dict[str, Callable[[Any, Callable[[str], None]], Speaker]] = {
    "soundplay": SoundPlaySpeaker,
    "local": LocalSpeaker,
    "none": Speaker,
}
DEFAULT_AUDIO = "soundplay"  # a Baxter lab's speakers are on a workstation running sound_play
# ROS 2 has no sound_play in most installs (and none on PyPI): the face speaks here.
DEFAULT_AUDIO_ROS2 = "local"
AUDIO_CHOICES = ", ".join(list(SPEAKERS)[:-1]) + " or " + list(SPEAKERS)[-1]


class UnknownAudio(ValueError):
    """An audio mode that is not one of SPEAKERS."""


def default_audio(version: int) -> str:
    """The audio mode a node or `stream` on ROS `version` takes when given none."""
    return DEFAULT_AUDIO_ROS2 if version == 2 else DEFAULT_AUDIO


def open_speaker(mode: str, link: Any, warn: Callable[[str], None], name: str = "~audio") -> Speaker:
    """The speaker for audio `mode` on `link`; UnknownAudio, naming the setting `name`, for no
    such mode, or for sound_play where its messages are missing (most ROS 2 installs)."""
    if mode not in SPEAKERS:
        raise UnknownAudio(f"{name} must be {AUDIO_CHOICES}, not {mode!r}")
    if mode == "soundplay" and not link.has(COMMAND_TYPES[SOUND_TOPIC]):
        raise UnknownAudio(
            f"{name} soundplay needs sound_play's messages (sound_play/SoundRequest), which this ROS "
            f"{link.version} does not have: install sound_play, or choose local or none"
        )
    return SPEAKERS[mode](link, warn)
