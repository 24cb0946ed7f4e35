"""Where `play` shows the face: a terminal in truecolor half-blocks or a Tk window, each with
the status line under the face that shows what only the robot could."""

from __future__ import annotations

import os
import shutil
import sys
from typing import Callable, List, Optional, TextIO, Tuple

import numpy as np
from PIL import Image

from ..engine.effects import quoted
from ..engine.timeline import RobotStatus

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
