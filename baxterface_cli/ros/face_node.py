"""`baxterface node`: the face node on ROS 1 or ROS 2, replacing the old screen_listener.py.

It listens on `display_chatter` (old commands and scripts alike), draws with
the same engine as `play`, publishes changed frames on /robot/xdisplay as
bgr8 through one latched publisher, drives the head, nod and enable
topics through the core `Robot` (robot_link), speaks through the `audio`
mode's speaker, and reports what the face is doing on `~state` (JSON,
latched). All work happens in one loop; subscriber callbacks only hand
messages over. The head camera (`camera` parameter) is subscribed to only
while a face is followed, and its images are looked at on the camera
watch's own thread, never on the loop. The camera's focal length comes from
its `camera_info` (beside the image topic) when it publishes one, unless the
`camera_hfov` parameter gives the field of view. ROS itself is behind a
`Link` (link.py): the same node runs on either version.

Scripts run on one live session (engine/live_session.py): a handler sent on `display_chatter`
installs itself, other commands take over, `signal NAME` raises the signal. The loop, the
session's intake and the robot's senses are face_loop.py's and robot_senses.py's, which `stream`
of a script that reacts runs too: the node adds its settings, its command topics and ~state. It
raises the events its topics give (robot/event_sensors.py): the navigators' and the cuffs'
buttons, the head sonar's `person near`/`person gone`, the camera's `face seen`/`face lost`, and
words from `_listen` (node_ears.py).
"""

from __future__ import annotations

import random
import time
from typing import Any, List

from ..core.face_constants import BROWS, MOUTHS, SKINS
from ..drawing.renderer import Renderer
from ..engine.live_face import sleep_face
from ..engine.live_session import LiveSession
from ..engine.log_backlog import Backlog
from ..language.diagnostics import ScriptError
from ..language.event_line import read_event_line
from ..language.parser import parse, parse_file
from ..language.syntax_tree import Script
from ..robot.mtcnn_detector import detector_note
from ..speech.recordings import Recordings
from ..speech.warm_start import start_in_background
from .connect import open_link
from .face_loop import FaceLoop
from .link import CHATTER, EVENT, NODE_NAME, QUEUE, Link
from .node_settings import NodeSettings, SettingError, theme_layers
from .speakers import UnknownAudio, default_audio, open_speaker
from .transport import PARAMETER, TransportError, from_ros_args


def selftest_script() -> str:
    """Every layer once, then the sleep face: the original's start-up flash."""
    steps = [f"skin {i}; wait 0.12s" for i in SKINS]
    steps += [f"mouth {m}; wait 0.12s" for m in MOUTHS] + [f"brows {b}; wait 0.12s" for b in BROWS]
    steps += ["look left in 0.2s", "look right in 0.3s", "look center in 0.2s", "blink", "sleep"]
    return "; ".join(steps)


def recordings_hint(version: int) -> str:
    """How a node of ROS `version` is told where recordings may be read."""
    return "_recordings:=FOLDER" if version == 1 else "--ros-args -p recordings:=FOLDER"


class FaceNode:
    """The node: its settings, its command topics, and the face loop."""

    def __init__(self, link: Link) -> None:
        self.link = link
        try:
            get = link.param
            settings = NodeSettings.read(get, NodeSettings(audio=default_audio(link.version)))
            layers = theme_layers(settings)
            self.log = Backlog(link.log)  # never logs from the loop
            self.speaker = open_speaker(settings.audio, link, self.log.warn)
        except UnknownAudio as e:
            raise SettingError("audio", str(e).split(" ", 1)[1]) from None
        except SettingError as e:
            kept = link.forget_bad(e.name)
            raise e if kept is None else SettingError(e.name, f"{e.problem} ({kept})") from None
        renderer = Renderer(layers)
        renderer.prepare_in_background()
        # Commands come from anyone on the ROS network: `say file` reads only under ~recordings.
        recordings = Recordings(
            settings.recordings,
            confined=True,
            warn=self.log.warn,
            refusal=f"this face node reads no recordings; start it with {recordings_hint(link.version)}",
        )
        # Drawn here, not left to the session: the log says it, and a replay chooses as the face did.
        seed = random.randrange(2**31)
        self.session = LiveSession(
            start=sleep_face(),
            idle=settings.idle,
            now=time.monotonic(),
            recordings=recordings,
            seed=seed,
            keep_up=True,
        )
        self.loop = FaceLoop(link, self.session, settings, renderer, self.speaker, self.log, seed=seed)
        self.intake = self.loop.intake
        link.subscribe(CHATTER, "std_msgs/String", lambda msg: self._heard(msg, False), queue=100)
        link.subscribe(QUEUE, "std_msgs/String", lambda msg: self._heard(msg, True), queue=100)
        link.subscribe(EVENT, "std_msgs/String", self._event, queue=100)
        if settings.selftest:
            self.intake.take(parse(selftest_script(), "selftest"))  # the worker starts it
        if settings.script is not None:  # after the selftest, as a script sent to ~queue waits
            self.intake.take(_started_with(settings.script), queued=True)

    def _event(self, msg: Any) -> None:
        """~event: an event raised by hand (`baxterface send --event 'button ok'`), as the robot's."""
        try:
            event = read_event_line(msg.data, "~event")
        except ScriptError as e:
            self.log.warn(f"bad event: {e.summary()}")
            return
        refusal = self.intake.post(event, "~event")
        if refusal is not None:
            self.log.warn(refusal)

    def _heard(self, msg: Any, queued: bool) -> None:  # display_chatter and ~queue: hand over
        refusal = self.intake.submit(msg.data, queued)  # parsed off the frame loop
        if refusal:
            self.log.warn(refusal)

    def run(self) -> int:
        self.link.leaving = "face node finished"
        with self.link:
            carried = f"; ROS 2 transport: {self.link.transport}" if self.link.transport else ""
            self.link.log("info", f"baxterface face node: listening on {self.link.resolve(CHATTER)}{carried}")
            self.link.log("info", f"baxterface face node: {detector_note()}")
            self.link.stay_connected(self.log.info)
            self.loop.run()
            self.log.close()
        return 0


def _started_with(path: str) -> Script:
    """The script of the `script` parameter, or the setting's one-line error."""
    try:
        return parse_file(path)
    except ScriptError as e:
        raise SettingError("script", f"cannot be played: {e.summary()}") from None


def run_node(argv: List[str], version: int = 1) -> int:
    """Run the face node on ROS `version` with the command line's ROS arguments `argv`."""
    # The speech process starts beside the node's own start (ROS, the theme), not at the first
    # `say`, which would wait for it: seconds on a robot busy with other nodes.
    start_in_background()
    if version == 2:
        try:
            from_ros_args(argv)  # read again as the link joins; a bad one is a bad parameter
        except TransportError as e:
            raise SettingError(PARAMETER, e.problem) from None
    link = open_link(version, NODE_NAME, argv, node=True)
    try:
        node = FaceNode(link)
    except BaseException:  # closed here only if the node cannot start; else `run` closes it
        link.close("the face node could not start")
        raise
    return node.run()
