"""One step of a live session's run, compiled from the face as it is, and how long it holds the face.

A step is one statement (session_program.Play) compiled by the engine's compiler with the
definitions it calls and nothing else, starting from the face at that instant: what was begun
finishes (`Carry`), unless an `interrupt` cut it, and speech that was cut leaves the mouth at
rest. A `forever`'s round that would take less than `LIMITS.least_round` waits out the rest
without compiling anything (`round_rest`).
"""

from __future__ import annotations

import dataclasses
import random
from typing import TYPE_CHECKING, Optional, Tuple

from ..core.face_constants import LIMITS
from ..core.face_state import FaceState
from ..language import syntax_tree as n
from ..language.borrowing import called
from ..language.diagnostics import ScriptError
from . import effects as fx
from .compiler import Carry, compile_script
from .session_program import Play, _Frame
from .session_records import Run
from .timeline import Timeline

if TYPE_CHECKING:
    from ..speech.recordings import Recordings


def compile_step(
    run: Run,
    step: Play,
    playing: Timeline,
    into: float,
    rng: random.Random,
    crossfade: Optional[float],
    recordings: Optional[Recordings],
) -> Tuple[Timeline, float, bool]:
    """`step` of `run`, compiled from `into` seconds into the timeline `playing`: the timeline,
    how long it holds the face, and whether the face exits at its end."""
    from ..speech.recordings import RecordingError

    script = n.Script(
        called((step.statement,), run.runner.definitions) + (step.statement,),
        run.script.filename,
        source=run.script.source,
        legacy=run.script.legacy,  # the old node's commands cut, as the old node did
    )
    carry = Carry(playing, into) if run.carry else None
    seed = rng.randrange(2**32)
    try:
        timeline = compile_script(
            script, seed, at_rest(playing, into), crossfade, recordings=recordings, carry=carry
        )
    except RecordingError as e:  # found only in saying it: a text espeak-ng crashed on
        raise ScriptError([e.diagnostic()], script.filename, script.source) from None
    exits = any(isinstance(c.effect, fx.ShutDown) for c in timeline.cues)
    length = timeline.duration if exits else max((s.end for s in timeline.spans), default=0.0)
    return timeline, length, exits


def round_rest(frame: _Frame, at: float) -> Optional[Play]:
    """A `forever`'s round begins at `at`: the wait that makes its last round `LIMITS.least_round`
    long (one that timed out at once, `wait 0.001s`), or None if it was long enough."""
    least = LIMITS.least_round
    if frame.lap is None or at >= frame.lap + least:
        frame.lap = at
        return None
    rest = frame.lap + least - at
    frame.lap += least
    return Play(n.Wait(rest, pos=frame.forever.pos))  # type: ignore[union-attr]


def at_rest(timeline: Timeline, t: float) -> FaceState:
    """The face at `t` with its speech stopped: the mouth as the expression has it, at rest."""
    if not timeline.sounding(t):
        return timeline.sample(t)
    return dataclasses.replace(timeline, speech=[]).sample(t)
