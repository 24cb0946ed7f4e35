"""Sound out of this machine's speakers, and in from its microphone, through PortAudio (the
`sounddevice` module).

One output stream runs for as long as the sound is open; its callback mixes
whatever is playing, so utterances overlap rather than cut each other and
starting one costs no stream. Without the module, the PortAudio library or a
device, `open_sound` says why once and hands back a silent output, so the
picture plays on.
"""

from __future__ import annotations

import contextlib
import os
import queue
import sys
import threading
import time
from typing import Callable, Iterator, List, Optional, Sequence

import numpy as np

from .soundtrack import resample

SPEECH_RATE = 22050  # espeak-ng's: opening the device at it spares a resampling
INSTALL_HINT = "pip install 'baxterface[speech]'"
# How far ahead of the script's clock utterances are handed to the mixer, which then starts them to
# the sample: more than the time between two frames, so none starts late and loses its first sound.
LOOKAHEAD = 0.25
# How long before a script's start its sound is set going, beyond the device's latency: what is
# started at once waits for the next block, up to a block late, while a sound due later is placed.
START_AHEAD = 0.1


class SoundOut:
    """Where sound goes; this base plays nothing (no device, or none wanted)."""

    available = False
    latency = 0.0  # seconds from `play` to the sound leaving the speaker, as the device reports it

    def play(self, samples: np.ndarray, rate: int, skip: float = 0.0) -> None:
        """Start int16 mono `samples` now, mixed with whatever plays.

        `skip` seconds are cut off the start, to catch up when called late; a
        negative `skip` starts the sound that much later instead, to the sample.
        """

    def stop(self) -> None:
        """Silence everything playing or waiting to play."""

    def close(self) -> None:
        """Let go of the device; a sound about to end may finish (a moment at most), the rest stops."""


class _Voice:
    __slots__ = ("samples", "start_at", "pos")

    def __init__(self, samples: np.ndarray, start_at: float) -> None:
        self.samples = samples
        self.start_at = start_at  # monotonic time its first sample should be written out
        self.pos = -1  # samples already mixed; -1 before its first block


class Mixer:
    """Sounds placed in time, summed block by block for an output callback."""

    def __init__(self, rate: int) -> None:
        self.rate = rate
        self._voices: List[_Voice] = []
        self._lock = threading.Lock()  # play/stop on the main thread, `fill` on PortAudio's

    def add(self, samples: np.ndarray, start_at: float) -> None:
        """Mix in int16 `samples` (at the mixer's rate) from monotonic time `start_at`."""
        if len(samples):
            with self._lock:
                self._voices.append(_Voice(samples, start_at))

    def clear(self) -> None:
        with self._lock:
            self._voices = []

    def busy(self) -> bool:
        return bool(self._voices)

    def ends_by(self, when: float) -> bool:
        """Would everything mixed in have been written out by `when`, on time?"""
        with self._lock:
            return all(v.start_at + len(v.samples) / self.rate <= when for v in self._voices)

    def fill(self, out: np.ndarray, now: float) -> None:
        """Write the next block (every column of `out`) whose first sample goes out at `now`."""
        frames = len(out)
        mix = np.zeros(frames, np.int32)
        with self._lock:
            voices = list(self._voices)
        finished = []
        for voice in voices:
            offset = 0
            if voice.pos < 0:
                # Placed by time, not by the block it arrives in; a voice that is late starts at once
                # (the caller's `skip` has already cut what it wanted cut).
                offset = max(0, round((voice.start_at - now) * self.rate))
                if offset >= frames:
                    continue
                voice.pos = 0
            piece = voice.samples[voice.pos : voice.pos + frames - offset]
            mix[offset : offset + len(piece)] += piece
            voice.pos += len(piece)
            if voice.pos >= len(voice.samples):
                finished.append(voice)
        if finished:
            with self._lock:
                self._voices = [v for v in self._voices if v not in finished]
        block = np.clip(mix, -32768, 32767).astype(np.int16)
        out[:] = block.reshape(-1, 1) if out.ndim == 2 else block


class DeviceSound(SoundOut):
    """The default output device, with a mixing callback running from open to close."""

    available = True
    # How fast the stream's time may slip later than its earliest callbacks showed: audio clocks
    # drift from the system's by well under 0.1 %.
    DRIFT = 0.001

    def __init__(self, stream, rate: int, clock: Callable[[], float] = time.monotonic) -> None:
        self.stream = stream
        self.rate = rate
        self.latency = float(stream.latency)
        self.mixer = Mixer(rate)
        self.clock = clock
        self.written = 0  # samples handed to the device so far
        self._offset: Optional[float] = None  # clock time of sample 0, as the stream runs
        self._last = 0.0

    def callback(self, outdata, frames: int, timing, status) -> None:
        now = self.clock()
        ahead = timing.outputBufferDacTime - timing.currentTime if timing is not None else 0.0
        if 0.0 < ahead < 2.0:  # the device tells when this block is heard
            block_at = now + ahead - self.latency
        else:
            # Callbacks come late, never early, and some in bursts: the stream's own clock is the
            # sample count from the earliest of them (slipping with drift). At the start, and after
            # an underflow, the device is empty: what is written now is heard at once, not after
            # the latency, while the burst that fills it is written.
            offset = now - self.written / self.rate
            underflow = status is not None and getattr(status, "output_underflow", False)
            if self._offset is None or underflow:
                self._offset = offset - self.latency
            else:
                self._offset = min(offset, self._offset + self.DRIFT * (now - self._last))
            self._last = now
            block_at = self._offset + self.written / self.rate
        self.written += frames
        self.mixer.fill(outdata, block_at)

    def settle(self, timeout: float = 1.0) -> None:
        """Wait out the burst of blocks that fills a device just started, so its clock is steady."""
        deadline = time.monotonic() + timeout
        while not self.written and time.monotonic() < deadline:
            time.sleep(0.005)
        time.sleep(0.05)

    def play(self, samples: np.ndarray, rate: int, skip: float = 0.0) -> None:
        start_at = self.clock() + max(0.0, -skip)
        cut = max(0, round(skip * rate))
        self.mixer.add(resample(np.asarray(samples, np.int16)[cut:], rate, self.rate), start_at)

    def stop(self) -> None:
        self.mixer.clear()

    def close(self) -> None:
        # Sounds due to end about now may still be on their last blocks when callbacks lag: they finish.
        deadline = self.clock() + self.latency + 0.2
        if self.mixer.ends_by(deadline):
            while self.mixer.busy() and self.clock() < deadline:
                time.sleep(0.005)
        self.mixer.clear()
        with contextlib.suppress(Exception):
            # Stopping (not aborting) lets out what the device holds: the end of the last words.
            self.stream.stop(ignore_errors=True)
        with contextlib.suppress(Exception):
            self.stream.close(ignore_errors=True)


@contextlib.contextmanager
def _quiet_stderr() -> Iterator[None]:
    """Hide what ALSA and JACK print while PortAudio looks for devices (it is not for the user)."""
    try:
        saved = os.dup(2)
    except OSError:
        yield
        return
    try:
        sys.stderr.flush()
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 2)
        os.close(null)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def open_sound(warn: Callable[[str], None]) -> SoundOut:
    """The default sound device, playing; a silent SoundOut (after one `warn`) when there is none."""
    try:
        with _quiet_stderr():
            import sounddevice
    except ImportError:
        warn(f"sound needs the sounddevice module: {INSTALL_HINT}; playing silently")
        return SoundOut()
    except OSError:  # the module is there, the library it loads is not
        warn("sound needs the PortAudio library: apt install libportaudio2; playing silently")
        return SoundOut()
    try:
        with _quiet_stderr():
            return _open_device(sounddevice)
    except Exception as e:  # PortAudio's errors, and whatever a broken device raises
        warn(f"no sound device ({_why(e)}): playing silently")
        return SoundOut()


def _open_device(sd, clock: Callable[[], float] = time.monotonic) -> DeviceSound:
    device = sd.query_devices(kind="output")  # raises when there is no default output
    tried: List[str] = []
    for rate in dict.fromkeys((SPEECH_RATE, int(device["default_samplerate"]))):
        for channels in (1, 2):
            holder: List[Optional[DeviceSound]] = [None]

            def callback(outdata, frames, timing, status, holder=holder) -> None:
                sound = holder[0]
                if sound is None:
                    outdata.fill(0)
                else:
                    sound.callback(outdata, frames, timing, status)

            try:
                stream = sd.OutputStream(samplerate=rate, channels=channels, dtype="int16", callback=callback)
            except sd.PortAudioError as e:
                tried.append(str(e))
                continue
            sound = holder[0] = DeviceSound(stream, rate, clock)
            try:
                stream.start()
            except Exception:
                stream.close(ignore_errors=True)
                raise
            sound.settle()
            return sound
    raise RuntimeError(tried[-1] if tried else "it opens no stream")


def _why(error: Exception) -> str:
    text = str(error).strip() or type(error).__name__
    if "querying device -1" in text:  # PortAudio's words for "there is no default output"
        return "PortAudio finds no output device"
    return text.splitlines()[0]


class SpeechCues:
    """A timeline's utterances (`Said`s) started on a SoundOut as the script's clock reaches them.

    `origin` is the clock time at which script time 0 is shown, and so must be
    heard; the sound goes out `sound.latency` ahead to meet it. With
    `loop_every`, the script starts again every that many seconds.
    """

    def __init__(self, sound: SoundOut, speech: Sequence, origin: float, loop_every: float = 0.0) -> None:
        self.sound = sound
        self.speech = list(speech)
        self.origin = origin
        self.loop_every = loop_every
        self.index = 0  # the next utterance to start

    def tick(self, now: float) -> None:
        """Start every utterance due before `now` plus the lookahead; a late one skips what it missed."""
        heard_now = now + self.sound.latency  # what starts now is heard then
        while self.speech:
            if self.index == len(self.speech):
                if self.loop_every <= 0:
                    return
                # The next lap, or the one the clock is already in after a long stall.
                self.origin += self.loop_every * max(1, int((heard_now - self.origin) // self.loop_every))
                self.index = 0
            said = self.speech[self.index]
            if self.origin + said.at > heard_now + LOOKAHEAD:
                return
            self.index += 1
            skip = heard_now - (self.origin + said.at)
            if skip < said.utterance.duration:
                self.sound.play(said.utterance.samples, said.utterance.sample_rate, skip)


class MicrophoneError(RuntimeError):
    """No microphone to listen with; the message says why, in one line."""


class Microphone:
    """The default input device, 16 kHz mono int16, its blocks handed to `take(block)` on a thread
    of its own (PortAudio's callback only queues them, so a slow listener drops no sound).

        with Microphone(spotter.feed):
            ...

    MicrophoneError, in one line, when the module, the library or an input device is missing.
    """

    RATE = 16000  # the speech model's
    BLOCK = 0.05  # seconds a block: what a word waits, at most, to reach the listener

    def __init__(self, take: Callable[[np.ndarray], object]) -> None:
        self.take = take
        self._queue: queue.Queue[Optional[np.ndarray]] = queue.Queue(maxsize=200)
        self._stream = None
        self._thread: Optional[threading.Thread] = None
        self.dropped = 0  # blocks lost because the listener fell 10 s behind

    def __enter__(self) -> Microphone:
        try:
            with _quiet_stderr():
                import sounddevice as sd
        except ImportError:
            raise MicrophoneError(f"listening needs the sounddevice module: {INSTALL_HINT}") from None
        except OSError:
            raise MicrophoneError(
                "listening needs the PortAudio library: apt install libportaudio2"
            ) from None

        def callback(indata, frames, timing, status) -> None:
            try:
                self._queue.put_nowait(indata[:, 0].copy())
            except queue.Full:
                self.dropped += 1

        try:
            with _quiet_stderr():
                sd.query_devices(kind="input")  # raises when there is no default input
                stream = sd.InputStream(
                    samplerate=self.RATE,
                    channels=1,
                    dtype="int16",
                    blocksize=int(self.BLOCK * self.RATE),
                    callback=callback,
                )
                stream.start()
        except Exception as e:  # PortAudio's errors, and whatever a broken device raises
            text = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            if "querying device -1" in text:
                text = "PortAudio finds no input device"
            raise MicrophoneError(f"no microphone ({text})") from None
        self._stream = stream
        self._thread = threading.Thread(target=self._listen, name="microphone", daemon=True)
        self._thread.start()
        return self

    def _listen(self) -> None:
        while True:
            block = self._queue.get()
            if block is None:
                return
            self.take(block)

    def __exit__(self, *exc: object) -> None:
        stream, self._stream = self._stream, None
        if stream is not None:
            with contextlib.suppress(Exception):
                stream.abort(ignore_errors=True)
            with contextlib.suppress(Exception):
                stream.close(ignore_errors=True)
        if self._thread is not None:
            with contextlib.suppress(queue.Full):
                self._queue.put(None, timeout=1.0)
            self._thread.join(timeout=5.0)
