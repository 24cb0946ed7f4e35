"""MP4 (H.264), WebM (VP9) and animated WebP, through PyAV, or an `ffmpeg` program without it.

(WebP only where Pillow has no libwebp: webp.py writes it as frames arrive, where FFmpeg's
animation encoder writes the file only at its end.)

Frames are numbered, 1/fps apart, so a video lasts exactly as many frames as
it was given. Video pixels go out as yuv420p, what every player and browser
plays; WebP is lossless. (Pillow's WebP writer holds every frame in memory
until the end: over a gigabyte for a 20-second show at 1024x600.)
A script's sound (speech) joins as an audio track: `Export.audio`, mono
16-bit samples and their rate, is encoded beside the frames (AAC in MP4,
Opus in WebM).
"""

from __future__ import annotations

import contextlib
import errno
import os
import queue
import shutil
import subprocess
import tempfile
import threading
from fractions import Fraction
from pathlib import Path
from typing import Any, Dict, List, NamedTuple, Optional

import numpy as np

from ..extras import MissingTool
from ..speech.soundtrack import resample, write_wav
from .sink import Export, FileSink, FormatError, FrameSink


class Codec(NamedTuple):
    container: str  # the muxer's name
    video: str  # the encoder
    audio: str  # the encoder for sound, "" for none
    options: Dict[str, str]  # encoder settings: fast, and good enough to share
    ffmpeg: List[str]  # the same, and the muxer's, as ffmpeg arguments
    pix_fmt: str = "yuv420p"  # what every player and browser plays
    muxer: Dict[str, str] = {}
    audio_rate: int = 0  # the rate the sound encoder takes; 0: the sound's own
    # The encoder keeps every frame until the end and writes the file then (libwebp_anim).
    holds_frames: bool = False


# x264's motion search at its cheapest (diamond, one refinement): a face's shapes move little
# between frames, so the picture is as good (PSNR within 0.06 dB, 5 % larger) and a frame that
# changes everywhere, as a mood's skin does, encodes in 0.7 of the time (bench/bench_expression.py).
X264_SEARCH = "me=dia:subme=1"

CODECS = {
    "h264": Codec(
        "mp4",
        "libx264",
        "aac",
        {"preset": "veryfast", "crf": "23", "x264-params": X264_SEARCH},
        ["-preset", "veryfast", "-crf", "23", "-x264-params", X264_SEARCH],
    ),
    "vp9": Codec(
        "webm",
        "libvpx-vp9",
        "libopus",
        {"deadline": "realtime", "cpu-used": "8", "row-mt": "1", "crf": "32", "b": "0"},
        ["-deadline", "realtime", "-cpu-used", "8", "-row-mt", "1", "-crf", "32", "-b:v", "0"],
        audio_rate=48000,  # Opus refuses espeak-ng's 22050
    ),
    # Lossless, from full-colour pixels: no palette, no chroma subsampling.
    "webp": Codec(
        "webp",
        "libwebp_anim",
        "",
        {"lossless": "1", "compression_level": "3"},
        ["-lossless", "1", "-compression_level", "3", "-loop", "0"],
        pix_fmt="bgra",
        muxer={"loop": "0"},
        holds_frames=True,
    ),
}


class RoomCheck:
    """Is there room for a file that its encoder writes only at the end (WebP)?

    Such a file meets a full disk after the last frame, minutes in. The file holds at least its
    first frame, whole and lossless: half of what Pillow's quickest lossless WebP makes of it is a
    size the file cannot be smaller than, so a disk without that much room fails at the first
    frame, and at every second's frames after it (another writer may fill the disk meanwhile).
    A disk that fills later still fails at the end, as every render does, with nothing left.
    """

    def __init__(self, folder: Path, fps: float) -> None:
        self.folder = folder
        self.every = max(1, int(round(fps)))
        self.least = 0
        self.frames = 0

    def add(self, frame_bgr: np.ndarray) -> None:
        if self.frames == 0:
            self.least = _lossless_size(frame_bgr) // 2
        if self.frames % self.every == 0 and _free_bytes(self.folder) < self.least:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        self.frames += 1


def _lossless_size(frame_bgr: np.ndarray) -> int:
    import io

    from PIL import Image

    data = io.BytesIO()
    try:
        rgb = np.ascontiguousarray(frame_bgr[..., ::-1])
        Image.fromarray(rgb, "RGB").save(data, format="WEBP", lossless=True, method=0, quality=0)
    except (OSError, KeyError, ValueError):  # a Pillow without WebP: no bound but "some room"
        return 1
    return len(data.getvalue())


def _free_bytes(folder: Path) -> int:
    try:
        vfs = os.statvfs(str(folder))
    except (OSError, AttributeError):  # no statvfs (Windows): the encoder finds out
        return 1 << 62
    # Root may fill the blocks a file system keeps back for it.
    free = vfs.f_bfree if hasattr(os, "geteuid") and os.geteuid() == 0 else vfs.f_bavail
    return free * vfs.f_frsize


def open_video_writer(path: Path, export: Export, codec: str) -> FrameSink:
    """A writer for `codec`: PyAV's if it is installed, else one that pipes to `ffmpeg`."""
    width, height = export.size
    if CODECS[codec].pix_fmt == "yuv420p" and (width % 2 or height % 2):
        raise FormatError(f"video needs an even width and height, not {width}x{height} (see --size)")
    try:
        import av  # noqa: F401
    except ImportError:
        program = shutil.which("ffmpeg")
        if program is None:
            raise MissingTool(
                f"writing {path.suffix} video needs PyAV (pip install 'baxterface[video]') "
                "or an ffmpeg program on PATH (apt install ffmpeg)"
            ) from None
        return FfmpegVideo(path, export, CODECS[codec], program)
    return PyAvVideo(path, export, CODECS[codec])


def _rate(fps: float) -> Fraction:
    return Fraction(fps).limit_denominator(1001)


class PyAvVideo(FileSink):
    """Frames encoded in this process by PyAV (FFmpeg's libraries), in a thread of their own:
    PyAV lets go of the GIL while FFmpeg converts and encodes, so the next frame is drawn
    meanwhile (a script whose whole face changes every frame renders in about half the time)."""

    QUEUED = 4  # frames waiting for the encoder: enough to ride out a slow one, little memory

    def __init__(self, path: Path, export: Export, codec: Codec) -> None:
        import av

        super().__init__(path)
        self.export = export
        # Written into the file we created, never reopened by its name. (So no
        # `faststart`, which reopens it: the index comes last, as players expect.)
        # FFmpeg writes it through /proc's link to our own descriptor where there
        # is one: through a Python file object, a full disk made PyAV print
        # tracebacks of its write and seek callbacks before our one-line error.
        target: Any = self.file
        if os.path.isdir("/proc/self/fd"):
            target = f"/proc/self/fd/{self.file.fileno()}"
        try:
            self.container = av.open(target, mode="w", format=codec.container, container_options=codec.muxer)
            rate = _rate(export.fps)
            self.stream = self.container.add_stream(codec.video, rate=rate, options=codec.options)
            self.stream.width, self.stream.height = export.size
            self.stream.pix_fmt = codec.pix_fmt
            self.audio = None
            if export.audio is not None and codec.audio:
                samples, rate = export.audio
                self.sound = (resample(samples, rate, codec.audio_rate), codec.audio_rate or rate)
                self.audio = self.container.add_stream(codec.audio, rate=self.sound[1])
        except BaseException:
            self.abort()
            raise
        self.count = 0
        self.room = RoomCheck(path.parent, export.fps) if codec.holds_frames else None
        self._frames: queue.Queue = queue.Queue(maxsize=self.QUEUED)
        self._failure: Optional[BaseException] = None
        # A daemon: whatever stops the render (Ctrl-C) never waits on it to end the program.
        self._encoder = threading.Thread(target=self._encode_frames, name="baxterface-encoder", daemon=True)
        self._encoder.start()

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        import av

        if self.room is not None:
            self.room.add(frame_bgr)
        # Copied into FFmpeg's frame here: the renderer reuses its buffer for the next frame.
        frame = av.VideoFrame.from_ndarray(np.ascontiguousarray(frame_bgr), format="bgr24")
        frame.pts = self.count
        self.count += 1
        self._hand_over(frame)

    def _hand_over(self, item: Any) -> None:
        while True:
            self._raise_failure()
            try:
                self._frames.put(item, timeout=0.1)
                return
            except queue.Full:
                if not self._encoder.is_alive():
                    self._raise_failure()
                    raise OSError("the video encoder stopped") from None

    def _raise_failure(self) -> None:
        if self._failure is not None:
            raise self._failure

    def _encode_frames(self) -> None:
        try:
            while True:
                frame = self._frames.get()
                if frame is None:
                    return
                for packet in self.stream.encode(frame):
                    self.container.mux(packet)
        except BaseException as error:  # a full disk: said where the frames come from
            self._failure = error

    def _encode_audio(self) -> None:
        import av

        samples, rate = self.sound
        stream = self.audio
        size = stream.codec_context.frame_size or 1024
        mono = np.asarray(samples, np.int16)
        layout = "mono"
        for start in range(0, len(mono), size):
            chunk = mono[start : start + size]
            frame = av.AudioFrame.from_ndarray(chunk.reshape(1, -1), format="s16", layout=layout)
            frame.sample_rate = rate
            frame.pts = start
            for packet in stream.encode(frame):
                self.container.mux(packet)
        for packet in stream.encode(None):
            self.container.mux(packet)

    def finish(self) -> None:
        self._hand_over(None)
        self._encoder.join()
        self._raise_failure()
        for packet in self.stream.encode(None):
            self.container.mux(packet)
        if self.audio is not None:
            self._encode_audio()
        self.container.close()

    def release(self) -> None:
        encoder = getattr(self, "_encoder", None)
        if encoder is not None and encoder.is_alive():
            # Frames still waiting are dropped; the one being encoded finishes first.
            with contextlib.suppress(queue.Empty):
                while True:
                    self._frames.get_nowait()
            with contextlib.suppress(queue.Full):
                self._frames.put_nowait(None)
            encoder.join(timeout=10)
        try:
            container = getattr(self, "container", None)
            if container is not None:
                container.close()
        except Exception:  # half-written: closing may fail; the file goes anyway
            pass


class FfmpegVideo(FileSink):
    """Frames piped as raw BGR to an `ffmpeg` program, which encodes and writes them."""

    named = True  # ffmpeg writes into it by name

    def __init__(self, path: Path, export: Export, codec: Codec, program: str) -> None:
        super().__init__(path)
        self.file.close()
        self.room = RoomCheck(path.parent, export.fps) if codec.holds_frames else None
        self.sound: Optional[str] = None
        width, height = export.size
        args = [program, "-hide_banner", "-loglevel", "error", "-nostdin", "-y"]
        args += ["-f", "rawvideo", "-pix_fmt", "bgr24", "-s", f"{width}x{height}"]
        args += ["-framerate", str(_rate(export.fps)), "-i", "pipe:0"]
        if export.audio is not None and codec.audio:
            self.sound = _wav_file(*export.audio)
            args += ["-i", self.sound, "-c:a", codec.audio]
        args += ["-c:v", codec.video, *codec.ffmpeg, "-pix_fmt", codec.pix_fmt]
        args += ["-f", codec.container, str(self.partial.path)]
        try:
            self.process: Any = subprocess.Popen(
                args, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
            )
        except BaseException:
            self.abort()
            raise

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        if self.room is not None:
            self.room.add(frame_bgr)
        try:
            self.process.stdin.write(np.ascontiguousarray(frame_bgr).tobytes())
        except BrokenPipeError:
            self._finish()  # raises with what ffmpeg said

    def _finish(self) -> None:
        with contextlib.suppress(BrokenPipeError):
            self.process.stdin.close()
        error = self.process.stderr.read().decode("utf-8", "replace").strip()
        if self.process.wait() != 0:
            last = error.splitlines()[-1] if error else f"exit code {self.process.returncode}"
            raise OSError(f"ffmpeg failed: {last}")

    def finish(self) -> None:
        self._finish()
        self._forget_sound()

    def release(self) -> None:
        process = getattr(self, "process", None)
        if process is not None and process.poll() is None:
            process.kill()
            process.wait()
        self._forget_sound()

    def _forget_sound(self) -> None:
        if self.sound:
            os.unlink(self.sound)
            self.sound = None


def _wav_file(samples: np.ndarray, rate: int) -> str:
    """The samples as a mono 16-bit WAV file of our own, for ffmpeg to read."""
    fd, name = tempfile.mkstemp(suffix=".wav", prefix="baxterface-")
    with os.fdopen(fd, "wb") as f:
        write_wav(f, samples, rate)
    return name
