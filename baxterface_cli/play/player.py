"""Play an animation in real time on this machine: in a Tk window or a terminal.

Frames are scheduled on absolute times from the start (frame i at i/fps),
so a slow frame makes the next one come sooner, never the whole show later:
a late frame is dropped rather than delaying the rest. A script that speaks
starts each utterance on the same clock (see `audio.SpeechCues`).
"""

from __future__ import annotations

import os
import shutil
import sys
import time
from typing import Callable, List, Optional, TextIO, Tuple

import numpy as np
from PIL import Image

from ..drawing.renderer import Renderer
from ..engine.animation import Animation
from ..engine.effects import quoted
from ..engine.timeline import RobotStatus
from ..robot.rehearsal import Rehearsal
from ..speech.sound_device import START_AHEAD, SoundOut, SpeechCues

UPPER_HALF = "\u2580"


def status_line(t: float, duration: float, status: RobotStatus, head_pan: float, note: str = "") -> str:
    """What only the robot could show, in one line."""
    parts = [f"{t:5.1f}/{duration:.1f}s", f"head {head_pan:+.2f} rad"]
    if status.enabled is not None:
        parts.append("enabled" if status.enabled else "disabled")
    if status.following:
        parts.append(f"following {status.following}" + (" (dynamic)" if status.follow_dynamic else ""))
    if status.nodding(t):
        parts.append("nodding")
    saying = status.speaking(t)
    if saying is not None:
        parts.append(f"saying {quoted(saying)}")
    if note:
        parts.append(note)
    return "  ".join(parts)


class TerminalScreen:
    """The face in truecolor half-block characters, scaled to fit the terminal."""

    name = "terminal"

    def __init__(self, out: TextIO = sys.stdout, columns: int = 0, rows: int = 0) -> None:
        self.out = out
        size = shutil.get_terminal_size((80, 24))
        self.columns = columns or size.columns
        self.rows = rows or size.lines
        self.previous: List[str] = []
        self.started = False
        # The face's rows as last drawn, and the frame they were drawn from: a face that holds
        # still (most frames of most scripts) costs a comparison, not a resize and 3000 cells.
        self._frame: Optional[np.ndarray] = None
        self._face: List[str] = []

    def fit(self, frame_size: Tuple[int, int]) -> Tuple[int, int]:
        """Cells across and pixel rows down that keep the face's shape (2 pixels a cell)."""
        width, height = frame_size
        avail_w, avail_h = self.columns, max(2, (self.rows - 1) * 2)
        scale = min(avail_w / width, avail_h / height)
        return max(1, int(width * scale)), max(2, int(height * scale) // 2 * 2)

    def show(self, frame_bgr: np.ndarray, status: str) -> None:
        if not self.started:
            self.out.write("\x1b[?25l\x1b[2J")
            self.started = True
        if self._frame is None or not np.array_equal(self._frame, frame_bgr):
            w, h = self.fit((frame_bgr.shape[1], frame_bgr.shape[0]))
            rgb = np.asarray(
                Image.fromarray(np.ascontiguousarray(frame_bgr[..., ::-1])).resize((w, h), Image.BOX)
            )
            self._face = [self._row(rgb[y], rgb[y + 1]) for y in range(0, h, 2)]
            self._frame = np.array(frame_bgr)
        lines = self._face + ["\x1b[0m\x1b[2K" + status[: self.columns]]
        chunks = []
        for i, line in enumerate(lines):
            if i >= len(self.previous) or self.previous[i] != line:  # only rows that changed
                chunks.append(f"\x1b[{i + 1};1H{line}")
        self.previous = lines
        if chunks:
            self.out.write("".join(chunks))
            self.out.flush()

    @staticmethod
    def _row(top: np.ndarray, bottom: np.ndarray) -> str:
        cells, last = [], None
        for (r1, g1, b1), (r2, g2, b2) in zip(top.tolist(), bottom.tolist()):
            colour = (r1, g1, b1, r2, g2, b2)
            if colour != last:
                cells.append(f"\x1b[38;2;{r1};{g1};{b1};48;2;{r2};{g2};{b2}m")
                last = colour
            cells.append(UPPER_HALF)
        return "".join(cells)

    def alive(self) -> bool:
        return True

    def close(self) -> None:
        if self.started:
            self.out.write(f"\x1b[0m\x1b[{len(self.previous) + 1};1H\x1b[?25h\n")
            self.out.flush()


class WindowScreen:
    """The face in a Tk window, with a status line under it."""

    name = "window"

    def __init__(self, title: str = "baxterface") -> None:
        import tkinter

        from PIL import ImageTk

        self._photo_class = ImageTk.PhotoImage
        self.root = tkinter.Tk()
        self.root.title(title)
        self.root.configure(background="black")
        self.image_label = tkinter.Label(self.root, borderwidth=0, background="black")
        self.image_label.pack()
        self.status_label = tkinter.Label(self.root, anchor="w", font=("TkFixedFont", 10))
        self.status_label.pack(fill="x")
        self.open = True
        self.root.protocol("WM_DELETE_WINDOW", self._closed)
        self.photo = None

    def _closed(self) -> None:
        self.open = False

    def on_click(self, touch: Callable[[float, float], None]) -> None:
        """Tell `touch` where the face is clicked: fractions of the picture's width and height."""

        def clicked(event) -> None:
            if self.photo is not None:
                touch(event.x / self.photo.width(), event.y / self.photo.height())

        self.image_label.bind("<Button-1>", clicked)

    def show(self, frame_bgr: np.ndarray, status: str) -> None:
        image = Image.fromarray(np.ascontiguousarray(frame_bgr[..., ::-1]), "RGB")
        if self.photo is None or self.photo.width() != image.width or self.photo.height() != image.height:
            self.photo = self._photo_class(image)
            self.image_label.configure(image=self.photo)
        else:
            self.photo.paste(image)
        self.status_label.configure(text=status)
        self.root.update()

    def alive(self) -> bool:
        if self.open:
            self.root.update()
        return self.open

    def close(self) -> None:
        if self.open:
            self.root.destroy()
            self.open = False


def window_available() -> Optional[str]:
    """None if a Tk window can open here, else why not."""
    if not os.environ.get("DISPLAY") and sys.platform.startswith("linux"):
        return "DISPLAY is not set"
    try:
        import tkinter  # noqa: F401
    except ImportError:
        return "this Python has no tkinter"
    return None


class Player:
    """Shows an animation on a screen in real time."""

    def __init__(
        self,
        animation: Animation,
        renderer: Renderer,
        screen,
        fps: float = 30.0,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
        on_time: Optional[Callable[[float], None]] = None,
        sound: Optional[Callable[[], SoundOut]] = None,
        follow: Optional[Rehearsal] = None,
    ) -> None:
        self.animation = animation
        self.renderer = renderer
        self.screen = screen
        self.fps = fps
        self.clock = clock
        self.sleep = sleep
        self.frames_shown = 0
        self.position = 0.0  # the script time of the last frame shown
        self.began: Optional[float] = None
        self.note = ""
        self.on_time = on_time  # told each frame's time first: for robot actions
        self.open_sound = sound  # called once, when the first script that speaks starts
        self.sound: Optional[SoundOut] = None
        self.cues: Optional[SpeechCues] = None
        self.follow = follow  # following against a recorded source (`play --follow-from`)

    def run(
        self, loop: bool = False, hold: bool = False, poll: Optional[Callable[[], Optional[Animation]]] = None
    ) -> float:
        """Play to the end (again and again with `loop`; then keep the last frame with `hold`).

        A script that takes no time, looped, is held rather than spun.

        `poll`, called between frames, may hand over a new animation, which
        starts from its beginning. Returns the seconds played.
        """
        self.began = self.clock()
        ended = False
        try:
            start = self._begin(loop)
            while self.screen.alive():
                if poll is not None:
                    fresh = poll()
                    if fresh is not None:
                        self.animation = fresh
                        start = self._begin(loop)
                elapsed = self.clock() - start
                duration = self.animation.duration
                if elapsed > duration:
                    if loop and duration > 0:
                        start += duration * int(elapsed // duration)
                        continue
                    self._show(duration)
                    if not hold and not loop:
                        ended = True  # the last words are out but for what the device still holds
                        break
                    self.sleep(1.0 / self.fps)  # keep the last frame, and keep polling
                    continue
                # Before `start`, the first frame; a hair over each tick counts as there (float rounding).
                index = int(max(0.0, min(elapsed, duration)) * self.fps + 1e-9)
                self._show(index / self.fps)
                if self.cues is not None:
                    self.cues.tick(self.clock())
                wait = start + (index + 1) / self.fps - self.clock()
                if wait > 0:
                    self.sleep(wait)
        finally:
            if self.sound is not None and not ended:  # stopped early: not a word more
                self.sound.stop()
        return self.clock() - self.began

    def _begin(self, loop: bool) -> float:
        """Start the animation from its beginning, its sound with it; returns the clock time of t=0."""
        speech = self.animation.timeline.speech
        if speech and self.sound is None and self.open_sound is not None:
            self.sound = self.open_sound()  # before the clock starts: finding a device takes a while
        if self.sound is not None:
            self.sound.stop()  # a reloaded or restarted script does not talk over its old self
        self.cues = None
        if not speech or self.sound is None or not self.sound.available:
            return self.clock()
        # The picture waits out the device's latency, so the first words are heard with their frame.
        start = self.clock() + self.sound.latency + START_AHEAD
        self.cues = SpeechCues(self.sound, speech, start, self.animation.duration if loop else 0.0)
        self.cues.tick(self.clock())
        return start

    def elapsed(self) -> float:
        """Seconds since `run` began (0 before)."""
        return 0.0 if self.began is None else self.clock() - self.began

    def _show(self, t: float) -> None:
        self.position = t
        if self.on_time is not None:
            self.on_time(t)
        state = self.animation.sample(t)
        robot = self.animation.timeline.status(t)
        note = self.note
        if self.follow is not None:
            state = self.follow.look(state, t, robot)
            note = "  ".join(filter(None, (self.follow.note(), note)))
        status = status_line(t, self.animation.duration, robot, state.head_pan, note)
        self.screen.show(self.renderer.render(state), status)
        self.frames_shown += 1
