"""The face node on ROS 2 (`baxterface node --ros 2`), talked to through real rclpy topics.

One node process serves the module (on loopback, in a domain of the module's
own); this process listens and publishes through a Link, as the screen and
any other ROS 2 program would. They run in the 3.11 suite (marker `ros2`).
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from baxterface_cli.ros.connect import open_link
from conftest import ROOT, baxterface, needs
from playing import paced
from ros2_world import Heard
from waiting import PATIENCE, eventually

pytestmark = [pytest.mark.ros2, pytest.mark.xdist_group("ros2_node")]

CAMERA = "/usb_cam/image_raw"  # any sensor_msgs/Image topic


class NodeProcess:
    """`baxterface node --ros 2 ARGS` in a process of its own, its log lines kept as they come."""

    def __init__(self, env, *args):
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "baxterface_cli", "node", "--ros", "2", *args],
            cwd=str(ROOT),
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        self.lines = []
        self.said = threading.Condition()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.proc.stdout:
            with self.said:
                self.lines.append(line.rstrip("\n"))
                self.said.notify_all()

    def wait_for_line(self, part, timeout=PATIENCE):
        deadline = time.monotonic() + timeout
        with self.said:
            while not any(part in line for line in self.lines):
                left = deadline - time.monotonic()
                assert left > 0, f"the node never said {part!r}: {self.lines}"
                self.said.wait(left)

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        code = self.proc.wait(timeout=30)
        self.reader.join(timeout=PATIENCE)  # its last lines: it ends at the end of the output
        return code, "\n".join(self.lines)


@pytest.fixture(scope="module")
def world(ros2):
    """The module's node (default topics, a camera of our own) and this process's link."""
    link = open_link(2, "pytest_ears", anonymous=True)
    state = Heard(
        link, "/baxter_face/state", "std_msgs/String", latched=True, keep=lambda m: json.loads(m.data)
    )
    node = NodeProcess(ros2, "--ros-args", "-p", "idle:=false", "-p", f"camera:={CAMERA}")
    try:
        state.wait_for(timeout=60)  # up: its state is latched at start
        yield link, node, state
    finally:
        code, out = node.stop()
        link.close()
    assert code == 0 and "Traceback" not in out, out


@pytest.fixture
def face(world):
    """The module's node, brought back to a still face that follows nothing before each test."""
    link, node, state = world
    commands = chatter(link)
    seen = state.count()
    commands.publish(data="follow off; mood 0 0 in 0s; look 0 0 in 0s; skin 3")
    state.wait_for(lambda r: r["following"] is None and r["eye_x"] == 0 and not r["playing"], after=seen)
    commands.close()
    return world


def screen_of(link, topic="/robot/xdisplay"):
    """Frames on the screen topic, each kept as its sizes and the pixel at the face's centre."""

    def keep(m):
        offset = m.height // 2 * m.step + 3 * (m.width // 2)
        b, g, r = bytes(m.data[offset : offset + 3])
        return {"size": (m.width, m.height, m.step, len(m.data)), "encoding": m.encoding, "rgb": (r, g, b)}

    return Heard(link, topic, "sensor_msgs/Image", latched=True, keep=keep)


def chatter(link, topic="/display_chatter"):
    publisher = link.publisher(topic, "std_msgs/String")
    deadline = time.monotonic() + 30
    while publisher.listeners() == 0:
        assert time.monotonic() < deadline, f"nothing listens on {topic}"
        time.sleep(0.02)
    return publisher


def test_send_happy_changes_the_screen_to_a_warm_bgr8_face_and_the_state_says_so(face, ros2):
    link, node, state = face
    screen = screen_of(link)
    kept = screen.wait_for()  # latched: the face as it was before we came
    assert kept["size"] == (1024, 600, 3072, 1024 * 600 * 3) and kept["encoding"] == "bgr8"
    commands = chatter(link)
    commands.publish(data="sleep")
    screen.wait_for(lambda f: f["rgb"][2] > f["rgb"][0])  # the sleepy skin is lavender
    commands.close()
    seen = screen.count()
    sent = baxterface("send", "--ros", "2", "happy", env=ros2)
    assert sent.code == 0, sent.err
    assert sent.out.strip() == "sent 'happy' to /display_chatter (1 listener)"
    screen.wait_for(lambda f: f["rgb"][0] > f["rgb"][2] + 60, after=seen)  # warm: happy's skin
    shown = state.wait_for(lambda r: r["emotion"] == "happy" and r["mouth"] in ("teeth", "smile-open"))
    assert shown["skin"] == 2
    screen.close()


LONG_SAY = "Hi, this is the face on the robot's screen, saying a whole sentence."


@pytest.mark.parametrize(
    "command, check",
    [
        ("sad", lambda r: r["emotion"] == "sad" and r["skin"] == 1),
        ("look_40_-20_0.5", lambda r: (r["eye_x"], r["eye_y"]) == (40.0, -20.0)),
        ("look 200 0 in 0.2s", lambda r: r["eye_x"] == 80.0),
        ("dynamic_human_follow_on", lambda r: r["following"] == "human" and r["follow_dynamic"]),
        ("mood -1 0 in 0.2s", lambda r: r["mood"] == [-1.0, 0.0] and r["expression"]["mouth_curve"] < 0),
        # Long enough to be seen speaking: a state goes out every 0.1 s at most, and a busy machine
        # may hold the node's loop up past all of a short "Hi" (its `saying` alone is told at once).
        (f'say "{LONG_SAY}"', lambda r: r["saying"] == LONG_SAY and r["mouth"].startswith("speak")),
    ],
)
def test_each_command_shows_on_state(face, command, check):
    link, node, state = face
    commands = chatter(link)
    seen = state.count()
    commands.publish(data=command)
    assert check(state.wait_for(check, after=seen))
    commands.close()


def test_the_state_is_latched_with_transient_local_durability(face):
    link, node, state = face
    latecomer = open_link(2, "latecomer", anonymous=True)
    try:
        late = Heard(latecomer, "/baxter_face/state", "std_msgs/String", latched=True, keep=lambda m: m.data)
        assert "emotion" in json.loads(late.wait_for())  # nothing was sent: it was kept for us
        from rclpy.qos import DurabilityPolicy

        # Discovery may tell of the publisher before it tells whose it is: wait for its name.
        def named():
            (offered,) = latecomer.node.get_publishers_info_by_topic("/baxter_face/state")
            return offered if offered.node_name != "_NODE_NAME_UNKNOWN_" else None

        offered = eventually(named, timeout=20)
        assert offered.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
        assert offered.node_name == "baxter_face"
    finally:
        latecomer.close()


def test_queued_scripts_play_after_the_current_one(face, ros2):
    link, node, state = face
    now, later = chatter(link), chatter(link, "/baxter_face/queue")
    seen = state.count()
    now.publish(data="look 40 0 in 3s")
    state.wait_for(lambda r: r["playing"] and r["eye_x"] > 0, after=seen)
    later.publish(data="skin 0")
    first = state.wait_for(lambda r: r["queued"] == 1, after=seen)
    assert first["skin"] != 0 and first["eye_x"] < 40
    assert state.wait_for(lambda r: r["skin"] == 0 and r["queued"] == 0, after=seen)["eye_x"] == 40.0
    sent = baxterface("send", "--ros", "2", "--queue", "skin 4", env=ros2)
    assert sent.out.strip() == "sent 'skin 4' to /baxter_face/queue (1 listener)"
    state.wait_for(lambda r: r["skin"] == 4, after=seen)
    now.close()
    later.close()


def test_send_stdin_sends_each_good_line_in_order_over_one_connection(face, ros2):
    link, node, state = face
    seen = state.count()
    lines = "skin 1\nhapy\n" + "".join(f"look {i} 0\n" for i in range(30)) + "look 33 -7\n"
    run = baxterface("send", "--ros", "2", "--stdin", stdin=lines, env=ros2)
    assert run.code == 1 and "<stdin>:2:1: error: unknown command 'hapy'" in run.err
    sent = run.out.splitlines()
    assert len(sent) == 32 and sent[-1] == "sent 'look 33 -7' to /display_chatter (1 listener)"
    assert state.wait_for(lambda r: r["eye_x"] == 33.0, after=seen)["eye_y"] == -7.0


def test_baxterface_state_reads_the_nodes_state_as_a_line_and_as_json(face, ros2):
    link, node, state = face
    commands = chatter(link)
    seen = state.count()
    commands.publish(data="sad; look 30 -10")
    state.wait_for(lambda r: r["emotion"] == "sad" and r["eye_x"] == 30.0, after=seen)
    commands.close()
    line = baxterface("state", "--ros", "2", env=ros2)
    assert line.code == 0 and line.err == "", line.err
    assert line.out.startswith("sad (skin 1, ") and "; eyes 30 -10, lids " in line.out
    as_json = json.loads(baxterface("state", "--ros", "2", "--json", env=ros2).out)
    assert as_json["emotion"] == "sad" and as_json["eye_x"] == 30.0


def test_without_ros_version_send_takes_the_ros_this_python_can_import(face, ros2):
    from baxterface_cli.ros.connect import importable_ros

    if importable_ros() != [2]:
        pytest.skip("this Python does not have rclpy alone (the ros2 extra without ROS 1)")
    env = {k: v for k, v in ros2.items() if k != "ROS_VERSION"}
    run = baxterface("send", "--topic", "/nobody_listens", "--timeout", "0.5", "happy", env=env)
    # ROS 2 joined and found nothing on that topic; ROS 1 would have said that rospy is missing
    assert run.code == 1 and run.out == ""
    assert run.err.strip() == "baxterface send: nothing listens on /nobody_listens: is the face node running?"
    run = baxterface("send", "happy", env=env)
    assert run.code == 0 and run.out.strip() == "sent 'happy' to /display_chatter (1 listener)"


def test_baxterface_state_without_a_node_says_so(ros2):
    run = baxterface("state", "--ros", "2", "--topic", "/nobody/state", "--timeout", "1", env=ros2)
    assert run.code == 1
    assert (
        run.err.strip() == "baxterface state: nothing on /nobody/state within 1 s: is the face node running?"
    )


def test_enable_and_nod_go_out_as_std_msgs_bool_and_a_head_pan_says_it_has_no_type(face):
    link, node, state = face
    enable = Heard(link, "/robot/set_super_enable", "std_msgs/Bool", keep=lambda m: m.data)
    nod = Heard(link, "/robot/head/command_head_nod", "std_msgs/Bool", keep=lambda m: m.data)
    commands = chatter(link)
    commands.publish(data="enable; nod")
    assert enable.wait_for() is True and nod.wait_for() is True
    commands.publish(data="wobble 0.3")  # Baxter's HeadPanCommand is not installed here
    node.wait_for_line("not sent on /robot/head/command_head_pan: its type baxter_core_msgs/HeadPanCommand")
    for heard in (enable, nod, commands):
        heard.close()


def camera_fields(centre, face=True):
    """A 640x400 bgr8 camera image, grey, with an astronaut's head (a real photo) centred at `centre`."""
    astronaut = needs("skimage.data").astronaut
    canvas = np.full((400, 640, 3), 128, np.uint8)
    if face:
        head = astronaut()[30:200, 140:310, ::-1]  # her head, with some margin, as BGR
        top, left = centre[1] - head.shape[0] // 2, centre[0] - head.shape[1] // 2
        canvas[top : top + head.shape[0], left : left + head.shape[1]] = head
    return {"height": 400, "width": 640, "encoding": "bgr8", "step": 1920, "data": canvas.tobytes()}


def test_a_face_on_any_image_topic_draws_the_eyes_to_it(face):
    needs("cv2")
    link, node, state = face
    camera = link.publisher(CAMERA, "sensor_msgs/Image", queue=1)
    commands = chatter(link)
    seen = state.count()
    commands.publish(data="follow face")
    state.wait_for(lambda r: r["following"] == "face", after=seen)
    image = camera_fields((160, 120))  # up and to the image's left, the robot's left: eyes right and up
    deadline = time.monotonic() + 30
    while True:
        camera.publish(**image)
        latest = state.messages[-1][1]
        if latest["eye_x"] > 12 and latest["eye_y"] < -8 and latest["follow_seen"]:
            break
        assert time.monotonic() < deadline, latest
        time.sleep(1 / 30)
    commands.publish(data="follow off")
    state.wait_for(lambda r: r["following"] is None, after=seen)
    camera.close()
    commands.close()


def test_stream_sends_frames_in_real_time(face, ros2):
    link, node, state = face
    screen = Heard(link, "/robot/head_display", "sensor_msgs/Image", keep=lambda m: m.encoding)
    run = baxterface(
        "stream",
        "--ros",
        "2",
        "--robot",
        "sawyer",
        "--no-idle",
        "--audio",
        "none",
        "-e",
        "look 40 0 in 2s",
        env=ros2,
    )
    assert run.code == 0, run.err
    # In real time, not all at once (a busy machine sends fewer, and its first may come late;
    # two seconds, so that some come through when ROS 2 loses frames under load).
    assert paced([t for t, _ in screen.messages])
    assert set(m for _, m in screen.messages) == {"bgr8"}
    screen.close()


def test_settings_as_ros2_parameters_and_a_node_name_of_its_own(ros2, tmp_path):
    """display_topic, fps, log and the node's name from --ros-args; `exit` ends it with status 0."""
    link = open_link(2, "pytest_face2", anonymous=True)
    state = Heard(link, "/face2/state", "std_msgs/String", latched=True, keep=lambda m: json.loads(m.data))
    screen = screen_of(link, "/screen/image")
    node = NodeProcess(
        ros2,
        "--ros-args",
        "-r",
        "__node:=face2",
        "-r",
        "display_chatter:=/face2/commands",
        "-p",
        "display_topic:=/screen/image",
        "-p",
        "fps:=15",
        "-p",
        "idle:=false",
        "-p",
        "size:=512x300",
        "-p",
        f"log:={tmp_path / 'face2.jsonl'}",
        "-p",
        "log_size:=1",
    )
    try:
        assert state.wait_for(timeout=60)["emotion"] == "sleep"
        assert screen.wait_for()["size"][:2] == (512, 300)
        commands = chatter(link, "/face2/commands")
        commands.publish(data="sad")
        state.wait_for(lambda r: r["emotion"] == "sad")
        commands.publish(data="exit")
        assert node.proc.wait(timeout=30) == 0
    finally:
        code, out = node.stop()
        link.close()
    assert "listening on /face2/commands" in out and "Traceback" not in out
    got = [json.loads(line) for line in (tmp_path / "face2.jsonl").read_text(encoding="utf-8").splitlines()]
    assert (
        got[0]["type"] == "start" and got[0]["settings"]["end"] == "node" and got[0]["settings"]["fps"] == 15
    )
    assert [r["text"] for r in got if r["type"] == "script"] == ["sad", "exit"]
    assert "exited" in [r["kind"] for r in got if r["type"] == "log"] and got[-1]["type"] == "end"


@pytest.mark.parametrize(
    "args, message",
    [
        (["--ros-args", "-p", "fps:=abc"], "baxterface node: parameter fps must be a number, not 'abc'"),
        (
            ["--ros-args", "-p", "audio:=loud"],
            "baxterface node: parameter audio must be soundplay, local or none",
        ),
        (["--ros-args", "-p", "audio:=soundplay"], "parameter audio soundplay needs sound_play's messages"),
        (
            ["_fps:=30"],
            "baxterface node: on ROS 2, ROS arguments come after --ros-args: --ros-args -p fps:=30",
        ),
        (["--ros", "3"], "baxterface node: --ros must be 1 or 2, not 3"),
    ],
)
def test_bad_settings_stop_the_node_with_one_line_and_exit_2(ros2, args, message):
    run = baxterface("node", "--ros", "2", *args, env=ros2)
    assert run.code == 2, run.err
    assert len(run.err.strip().splitlines()) == 1 and message in run.err and "Traceback" not in run.err
