"""Render an animation to a file or folder, in the format its name asks for (see formats.py)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Callable, List, Optional, Sequence

from ..core.face_state import FaceState
from ..core.partial_files import remove_stale
from ..drawing.renderer import Renderer
from ..engine.animation import Animation
from ..engine.explanation import frame_times as script_frame_times
from ..speech.soundtrack import Placed, soundtrack
from .registry import Format, format_for
from .sink import Export
from .target import check_target

if TYPE_CHECKING:  # following is only imported by those who follow
    from ..robot.rehearsal import Rehearsal

Progress = Callable[[int, int], None]  # (frames done, frames in all)


def palette_times(animation: Animation) -> List[float]:
    """Moments that between them show every colour the animation uses."""
    times = {0.0, animation.duration}
    previous = animation.timeline.initial.skin
    for change in animation.timeline.parts:
        times.add(change.at + change.fade)
        if change.parts.skin != previous:  # blends of two skins have colours of their own
            times.update(change.at + change.fade * k for k in (0.25, 0.5, 0.75))
        previous = change.parts.skin
    return sorted(times)[:40]


def frame_times(fmt: Format, animation: Animation, fps: float, at: Optional[float]) -> List[float]:
    """When each frame is sampled: one still, or the whole script at `fps` (see `explanation.frame_times`)."""
    duration = animation.duration
    if not fmt.frames:
        return []
    if fmt.one_frame:
        return [duration if at is None else min(at, duration)]  # idle runs on past the end
    return script_frame_times(duration, fps)


def render(
    animation: Animation,
    renderer: Renderer,
    out: str,
    fps: float = 30.0,
    at: Optional[float] = None,
    progress: Optional[Progress] = None,
    robot: str = "baxter",
    follow: Optional[Rehearsal] = None,
    heard: Sequence[Placed] = (),
) -> int:
    """Write the animation to `out`; returns the number of frames rendered.

    With `follow`, the eyes follow what it was made from (`--follow-from`),
    frame by frame as `play` shows it. The sounds `heard` (a visitor's voice) are mixed into the
    sound with the face's own.
    """
    fmt = format_for(out)
    path = Path(out)
    # Before a frame is drawn: a render of minutes must not fail at its end for want of a folder.
    check_target(path, folder=fmt.folder)
    remove_stale(path.parent)  # partial files are written beside the target; a folder's, inside it
    export = Export(
        size=renderer.size,
        fps=fps,
        duration=animation.duration,
        cues=animation.timeline.cues,
        robot=robot,
        frame_at=lambda t: renderer.render(animation.sample(t)),
        palette_times=palette_times(animation),
        audio=soundtrack(animation.timeline.speech, animation.duration, heard),
    )
    times = frame_times(fmt, animation, fps, at)

    def state_at(t: float) -> FaceState:
        state = animation.sample(t)
        return state if follow is None else follow.look(state, t, animation.timeline.status(t))

    if follow is not None and fmt.one_frame:  # following has a past: live it up to the still
        for i in range(int(times[0] * fps)):
            state_at(i / fps)
    with fmt.open(path, export) as sink:  # an interrupted render leaves nothing behind
        for i, t in enumerate(times):
            sink.add(renderer.render(state_at(t)), t)
            if progress:
                progress(i + 1, len(times))
    return len(times)
