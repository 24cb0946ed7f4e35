"""`play --follow-from`: following a recorded trace or camera images, with no robot."""

from __future__ import annotations

import json
import math

import numpy as np
import pexpect
import pytest

from baxterface_cli import parse
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.play.live_player import LivePlayer
from baxterface_cli.robot.rehearsal import FollowSourceError, Rehearsal, open_source
from conftest import ROOT, baxterface, needs
from playing import FakeClock, spawn_play

FPS = 30.0


def write_trace(path, rows):
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    return str(path)


def person_at(sensors, seconds=4.0, distance=1.0, rate=20.0):
    """A person in front of `sensors` for `seconds`, as a sonar trace's rows."""
    return [
        {"t": k / rate, "sonar": [list(sensors), [distance] * len(sensors)]}
        for k in range(int(seconds * rate))
    ]


def rehearse(script: str, source, seconds: float, **options):
    """The (t, face state, status note) of each frame of `script` played against `source`."""
    timeline = compile_script(parse(script))
    rehearsal = Rehearsal(open_source(source), **options)
    frames = []
    for i in range(int(seconds * FPS)):
        t = i / FPS
        state = rehearsal.look(timeline.sample(t), t, timeline.status(t))
        frames.append((t, state, rehearsal.note()))
    return frames


def test_a_person_on_the_robots_left_draws_the_eyes_there(tmp_path):
    trace = write_trace(tmp_path / "left.jsonl", person_at([9, 10]))  # line positions 3 and 2
    frames = rehearse("follow human; wait 4s", trace, 3.0)
    t, state, note = frames[-1]
    assert state.eye_x > 50 and state.eye_y == 0  # 2.5 of 3 along the line: about 67 pixels
    assert note == "sees the human"


def test_before_following_the_eyes_are_the_scripts_and_after_they_are_recentred(tmp_path):
    trace = write_trace(tmp_path / "left.jsonl", person_at([9, 10], seconds=6))
    frames = rehearse("look right in 0.4s; wait 1s; follow human; wait 2s; follow off; wait 2s", trace, 5.0)
    before = [s.eye_x for t, s, _ in frames if 0.4 <= t < 1.4]
    assert all(x < -60 for x in before)  # looking right as the script says, not at the person
    during = [s.eye_x for t, s, _ in frames if 2.5 <= t < 3.4]
    assert min(during) > 60
    after = [s.eye_x for t, s, _ in frames if t >= 4.0]
    assert all(x == 0 for x in after)  # `follow off` recentres


def test_a_hand_is_followed_up_and_down_too(tmp_path):
    trace = write_trace(tmp_path / "arm.jsonl", [{"t": 0, "left": [0.8, 0.8, 1.55]}])
    t, state, note = rehearse("follow left arm; wait 2s", trace, 2.0)[-1]
    assert state.eye_x == pytest.approx(45.0, abs=1.0)  # atan2(0.8, 0.8): 45 degrees to its left
    assert state.eye_y < -50  # above the face: up
    assert note == "sees the left arm"


def test_following_dynamically_turns_the_head_shown_in_the_status(tmp_path):
    trace = write_trace(tmp_path / "far.jsonl", [{"t": 0, "left": [0.2, 1.0, 0.75]}])
    frames = rehearse("follow left arm dynamic; wait 2s", trace, 2.0)
    assert frames[-1][1].head_pan == pytest.approx(math.atan2(1.0, 0.2) * 57.294 * 3 / 160, abs=0.01)
    assert abs(frames[-1][1].eye_x) < 5  # the head turned, so the eyes look straight ahead


def test_nobody_in_the_trace_says_so(tmp_path):
    trace = write_trace(tmp_path / "empty.jsonl", [{"t": 0, "sonar": [[], []]}])
    t, state, note = rehearse("look left; wait 0.1; follow human; wait 1s", trace, 1.0)[-1]
    assert note == "no human seen" and state.eye_x > 60  # the script's look left stands


def test_a_loop_starts_the_trace_again(tmp_path):
    rows = person_at([9], seconds=1) + person_at([3], seconds=1)
    for row in rows[20:]:
        row["t"] += 1.0
    trace = write_trace(tmp_path / "walk.jsonl", rows)
    timeline = compile_script(parse("follow human; wait 2s"))
    rehearsal = Rehearsal(open_source(trace))
    eyes = []
    for _lap in range(2):
        for i in range(int(0.9 * FPS)):
            t = i / FPS
            eyes.append(rehearsal.look(timeline.sample(t), t, timeline.status(t)).eye_x)
    first_lap, second_lap = eyes[: len(eyes) // 2], eyes[len(eyes) // 2 :]
    assert second_lap == pytest.approx(first_lap)  # the same trace from its start, not its end


@pytest.mark.parametrize(
    "line, message",
    [
        ("{nope", "trace.jsonl:2: not JSON"),
        ("[1, 2]", "trace.jsonl:2: a line must be a JSON object"),
        ('{"sonar": [[0], [1.0]]}', "trace.jsonl:2: 't' must be a time in seconds"),
        ('{"t": -1, "left": [1, 0, 0]}', "trace.jsonl:2: 't' must be a time in seconds"),
        ('{"t": 1, "sonar": [[0], ["far"]]}', "trace.jsonl:2: 'sonar' must be [[sensor ids], [distances]]"),
        ('{"t": 1, "left": [1, 0]}', "trace.jsonl:2: 'left' must be [x, y, z] in metres"),
        ('{"t": 1}', "trace.jsonl:2: a line needs one of 'sonar', 'left' or 'right'"),
    ],
)
def test_a_bad_trace_line_is_named_by_file_and_line(tmp_path, line, message):
    path = tmp_path / "trace.jsonl"
    path.write_text('{"t": 0, "right": [1, 0, 1]}\n' + line + "\n")
    with pytest.raises(FollowSourceError) as caught:
        open_source(str(path))
    assert str(caught.value).startswith(str(tmp_path / message))
    assert "\n" not in str(caught.value)


def play_following(source, script):
    """What `play --follow-from source -e script` printed in a terminal, and its exit status."""
    child = spawn_play("--follow-from", str(source), "-e", script)
    child.expect(pexpect.EOF)
    child.close()
    return child.before, child.exitstatus


def test_play_follow_from_a_file_that_is_not_there_is_one_line_and_exit_1(tmp_path):
    printed, status = play_following(tmp_path / "gone.jsonl", "follow human")
    assert printed.strip() == f"baxterface play: {tmp_path / 'gone.jsonl'}: no such file"
    assert status == 1


def test_play_follow_from_shows_what_is_followed_in_the_status_line(tmp_path):
    trace = write_trace(tmp_path / "left.jsonl", person_at([9, 10], seconds=2))
    printed, status = play_following(trace, "follow human; wait 1s")
    assert "following human  sees the human" in printed and status == 0


def test_play_warns_when_the_script_follows_nothing(tmp_path):
    trace = write_trace(tmp_path / "left.jsonl", person_at([9], seconds=1))
    printed, status = play_following(trace, "happy")
    assert "the script follows nothing, so --follow-from changes nothing" in printed and status == 0


def test_the_player_hands_each_frame_to_the_rehearsal(tmp_path):
    trace = write_trace(tmp_path / "left.jsonl", person_at([9, 10], seconds=3))
    session = LiveSession(parse("follow human; wait 2s"), seed=0, idle=False)
    clock = FakeClock()
    shown = []

    class Screen:
        name = "fake"

        def show(self, frame, status):
            shown.append(status)

        def alive(self):
            return True

    renderer = Renderer(Theme.default().layers((64, 38)))
    follow = Rehearsal(open_source(trace))
    player = LivePlayer(session, renderer, Screen(), FPS, clock=clock, sleep=clock.sleep, follow=follow)
    player.run()
    assert "sees the human" in shown[-1] and "following human" in shown[-1]


def test_a_face_in_a_picture_is_followed_and_a_dynamic_follow_turns_the_head_to_it_once():
    needs("cv2")
    picture = str(ROOT / "scripts_examples" / "someone.jpg")  # a face about 26 degrees to the left
    frames = rehearse("follow face; wait 2s", picture, 2.0)
    t, state, note = frames[-1]
    assert state.eye_x == pytest.approx(25.6, abs=2.0) and abs(state.eye_y) < 3
    assert note == "sees the face" and state.head_pan == 0
    frames = rehearse("follow face dynamic; wait 3s", picture, 3.0)
    pans = {round(s.head_pan, 2) for t, s, _ in frames if t > 1.0}
    assert pans == {round(25.6 * 3 / 160, 2)}  # turned once, and held: the picture does not turn
    assert abs(frames[-1][1].eye_x) < 3  # the head looks at the face, so the eyes look ahead


def test_a_face_that_leaves_a_video_is_let_go(tmp_path):
    cv2 = needs("cv2")
    needs("skimage")
    from face_streams import leaving

    stream = leaving()
    video = str(tmp_path / "leaving.avi")
    writer = cv2.VideoWriter(video, cv2.VideoWriter_fourcc(*"MJPG"), stream.fps, (640, 400))
    for frame in stream.frames():
        writer.write(frame.image)
    writer.release()
    frames = rehearse(f"follow face; wait {stream.seconds}s", video, stream.seconds)
    seen = [t for t, _, note in frames if note == "sees the face"]
    assert seen and min(seen) < 1.0  # found within a second
    gone = [t for t, _, note in frames if t > stream.left_at and note == "no face seen"]
    assert gone and min(gone) < stream.left_at + 1.0  # let go within a second of leaving


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
def test_the_face_policy_chooses_which_of_three_faces_in_a_video_is_followed(tmp_path):
    cv2 = needs("cv2")
    needs("skimage")
    from far_streams import crowd

    stream = crowd()  # three faces: off the middle to the right, large on the left, central
    video = str(tmp_path / "crowd.avi")
    writer = cv2.VideoWriter(video, cv2.VideoWriter_fourcc(*"MJPG"), stream.fps, (640, 400))
    for frame in stream.frames():
        writer.write(frame.image)
    writer.release()
    script = f"follow face; wait {stream.seconds}s"
    eyes = {
        policy: rehearse(script, video, stream.seconds, face_policy=policy)[-1][1].eye_x
        for policy in ("nearest", "central", "longest")
    }
    # The image's left is the robot's left: positive eye x.
    assert eyes["nearest"] > 15 and abs(eyes["central"]) < 3 and eyes["longest"] < -15, eyes


def test_a_face_policy_that_does_not_exist_or_without_a_file_is_a_usage_error(tmp_path):
    out = str(tmp_path / "x.png")
    picture = str(ROOT / "scripts_examples" / "someone.jpg")
    wrong = baxterface(
        "render", "-e", "follow face", "--follow-from", picture, "--face-policy", "tallest", "--out", out
    )
    said = " ".join(word for word in wrong.err.split() if word not in "│╭╮╰╯─")
    assert wrong.code == 2 and "--face-policy: must be nearest, central or longest, not 'tallest'" in said
    alone = baxterface("render", "-e", "follow face", "--face-policy", "central", "--out", out)
    said = " ".join(word for word in alone.err.split() if word not in "│╭╮╰╯─")
    assert alone.code == 2 and "--face-policy: chooses among the faces in --follow-from FILE" in said
    assert not (tmp_path / "x.png").exists()


def test_a_file_that_is_neither_trace_video_nor_picture_is_one_line(tmp_path):
    needs("cv2")
    junk = tmp_path / "notes.txt"
    junk.write_text("hello")
    with pytest.raises(
        FollowSourceError, match=r"notes.txt: cannot read it as a video \(or a .jsonl trace\)$"
    ):
        open_source(str(junk))


def test_render_follow_from_draws_what_play_shows(tmp_path):
    from PIL import Image

    trace = write_trace(tmp_path / "arm.jsonl", [{"t": 0, "left": [0.8, 0.8, 1.55]}])
    script = "follow left arm; wait 2s"
    size, at = (256, 150), 1.5
    followed = baxterface(
        "render",
        "-e",
        script,
        "--follow-from",
        trace,
        "--out",
        str(tmp_path / "f.png"),
        "--at",
        str(at),
        "--size",
        "256x150",
    )
    assert followed.code == 0, followed.err
    plain = baxterface(
        "render", "-e", script, "--out", str(tmp_path / "p.png"), "--at", str(at), "--size", "256x150"
    )
    assert plain.code == 0, plain.err
    t, state, _ = rehearse(script, trace, at + 1 / FPS)[-1]
    assert t == pytest.approx(at) and state.eye_x == pytest.approx(45.0, abs=1.0)
    wanted = Renderer(Theme.default().layers(size)).render(state)[..., ::-1]
    drawn = np.asarray(Image.open(tmp_path / "f.png").convert("RGB"))
    assert np.array_equal(drawn, wanted)  # the eyes where play puts them, up and to the left
    assert not np.array_equal(drawn, np.asarray(Image.open(tmp_path / "p.png").convert("RGB")))
    # A video follows frame by frame, from the same file.
    video = baxterface(
        "render",
        "-e",
        script,
        "--follow-from",
        trace,
        "--out",
        str(tmp_path / "frames") + "/",
        "--fps",
        "10",
        "--size",
        "256x150",
    )
    assert video.code == 0, video.err
    last = np.asarray(Image.open(sorted((tmp_path / "frames").glob("*.png"))[-1]).convert("RGB"))
    assert not np.array_equal(last, np.asarray(Image.open(tmp_path / "p.png").convert("RGB")))


def test_render_follow_from_a_file_that_is_not_there_is_one_line_and_exit_1(tmp_path):
    run = baxterface(
        "render",
        "-e",
        "follow human",
        "--follow-from",
        str(tmp_path / "none.jsonl"),
        "--out",
        str(tmp_path / "x.png"),
    )
    assert run.code == 1 and run.err.count("\n") == 1 and "none.jsonl" in run.err
    assert not (tmp_path / "x.png").exists()
