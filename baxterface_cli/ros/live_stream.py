"""`baxterface stream` of a script that reacts: the face node's loop and senses, here.

A script with handlers, waits, signals, `forever` or `one of` runs on a live session as the node
runs it (face_loop.py, robot_senses.py: the same code, not a copy), with the same robot events:
the navigators, the cuffs, the head sonar, the camera, `signal NAME` on display_chatter and,
with `listen`, words. It runs until the script has nothing left to do and no handlers, `duration`
seconds, or Ctrl-C. Only `signal NAME` is taken from display_chatter: other commands there are the
face node's, if one runs.
"""

from __future__ import annotations

import random
import time
from typing import Any, List, Optional

from ..drawing.renderer import Renderer
from ..engine.live_session import LiveSession
from ..engine.log_backlog import Backlog
from ..engine.session_intake import SIGNAL_ALONE
from ..language import syntax_tree as n
from .connect import open_link
from .effect_messages import DISPLAY_TOPICS
from .face_loop import FaceLoop
from .link import CHATTER
from .node_settings import NodeSettings
from .send import wait_for_screen
from .speakers import default_audio, open_speaker


class Deaf(Exception):
    """`--listen` cannot hear: the microphone, its module or the speech model is missing."""


def stream_live(
    script: n.Script,
    renderer: Renderer,
    robot: str,
    fps: float,
    argv: List[str],
    audio: Optional[str] = None,
    version: int = 1,
    duration: Optional[float] = None,
    listen: bool = False,
    barge_in: bool = False,
    session_options: Optional[dict] = None,
    log: Optional[str] = None,
    log_size: float = 100.0,
) -> float:
    """Run `script` on the robot, reacting, until it is done (see the module's docstring); the
    seconds it ran. `session_options` go to the LiveSession (seed, idle, recordings, crossfade);
    `log`, a file for the session's record, rotated past `log_size` MB."""
    settings = NodeSettings(
        fps=fps,
        display_topic=DISPLAY_TOPICS[robot],
        listen="default" if listen else "",
        barge_in=barge_in,
        log=log,
        log_size=log_size,
    )
    with open_link(version, "baxterface_stream", argv, anonymous=True, leaving="streamed") as link:
        backlog = Backlog(link.log)
        speaker = open_speaker(audio or default_audio(version), link, backlog.warn, "--audio")
        options = dict(session_options or {})
        if options.get("seed") is None:  # drawn here: the log says it, and a replay chooses as this did
            options["seed"] = random.randrange(2**31)
        session = LiveSession(now=time.monotonic(), keep_up=True, **options)
        loop = FaceLoop(
            link, session, settings, renderer, speaker, backlog, filename=script.filename, end="stream",
            seed=options["seed"],
        )  # fmt: skip

        def heard(msg: Any) -> None:  # display_chatter: the signals only
            if SIGNAL_ALONE.fullmatch(msg.data):
                loop.intake.submit(msg.data)

        link.subscribe(CHATTER, "std_msgs/String", heard, queue=100)
        wait_for_screen(loop.image_pub, version)
        start = time.monotonic()
        taken = loop.intake.take(script)  # the worker starts it, as a command that takes over

        def done(now: float) -> bool:
            if taken.done() and taken.exception() is not None:
                raise taken.exception()  # a `say` espeak-ng cannot say, a recording gone: ScriptError
            if duration is not None:
                return now >= start + duration
            s = session  # read without its lock: its worker swaps what `free` reads whole
            finished = not s.handlers and s.free and loop.intake.idle() and s.face.finished(now)
            return taken.done() and finished

        def deaf(problem: str) -> None:
            raise Deaf(problem)

        try:
            ended = loop.run(done, deaf if listen else None)
        finally:
            backlog.close()
    return ended - start
