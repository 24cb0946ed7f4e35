"""`render LOG.jsonl` and `explain LOG.jsonl`: a session's log (`--log`, the node's `log`) run
again, its first script with its events and later scripts (engine/log_replay.py)."""

from __future__ import annotations

from typing import Any, List, Optional, Tuple

import typer

from .app import fail, recordings_of
from .events_option import ran

LOG_SUFFIXES = (".jsonl", ".jsonl.1", ".jsonl.2", ".jsonl.3", ".jsonl.4")


def is_log(path: Optional[str]) -> bool:
    """Is `path` a session's log rather than a script (by its name: FILE.jsonl, or a rotated one)?"""
    return path is not None and path.lower().endswith(LOG_SUFFIXES)


def log_animation(
    path: str,
    seed: Optional[int],
    idle: bool,
    crossfade: Optional[float],
    duration: Optional[float],
    command: str,
    given: Tuple[Any, ...] = (),
) -> Tuple[Any, List[Any], Any]:
    """The animation of the log at `path` run again, the run (its session's log lines), and the replay (its
    first script and events); what the log says of itself is said on standard error. `given`:
    --events, --hear or -e, which a log brings itself."""
    from ..engine.animation import Animation
    from ..engine.log_replay import LogError, read_log, run_log

    if any(option is not None for option in given):
        raise fail(
            f"baxterface {command}: a session's log brings its own script and events: give it alone", 2
        )
    try:
        replay = read_log(path)
    except LogError as e:
        raise fail(f"baxterface {command}: {e}") from None
    for note in replay.notes:
        typer.echo(f"baxterface {command}: {note}", err=True)
    if replay.seed is not None:
        seed = replay.seed  # the live session's: its `one of`s choose again as they chose
    chosen = seed
    run = ran(command, lambda: run_log(replay, chosen, duration, crossfade, recordings_of(replay.script)))
    return Animation(run.timeline, idle=idle, seed=seed), run, replay  # type: ignore[arg-type]


def annotated(path: Optional[str], out: str, seed: Optional[int], duration: Optional[float], given) -> None:
    """`render LOG.jsonl --out FILE.eaf` (or .TextGrid): the replay's tiers written, one line said."""
    from ..export.annotations import annotation_kind, tiers_of, write_annotations
    from ..extras import MissingTool

    kind = annotation_kind(out)
    if not is_log(path):
        raise fail(
            f"baxterface render: an {kind} file is made of a session's log: render LOG.jsonl --out {out}", 2
        )
    animation, run, replay = log_animation(path, seed, False, None, duration, "render", given)
    end = animation.duration
    tiers = tiers_of(run, replay.trace, end)
    try:
        write_annotations(tiers, end, out)
    except MissingTool as e:
        raise fail(f"baxterface render: {e}") from None
    except OSError as e:
        raise fail(f"baxterface render: cannot write {out}: {e.strerror or e}") from None
    counted = ", ".join(f"{len(tiers[name])} {name}" for name in tiers)
    typer.echo(f"wrote {out} ({kind}: {counted}; {end:.2f} s)", err=True)
