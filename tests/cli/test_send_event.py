"""`baxterface send --event`: an event raised by hand at a real screen over loopback (the node's
~event is tested with ROS, tests/ros/test_ros.py), and its mistakes in one line."""

from __future__ import annotations

from conftest import baxterface
from studio_server import running_screen
from waiting import eventually


def test_an_event_sent_to_a_screen_runs_its_handler_and_says_what_it_did(tmp_path):
    # Piloting without a robot: `send 'button ok'` was two errors, and a 20-line rospy publisher.
    (tmp_path / "greet.face").write_text("on button ok { happy }\n", encoding="utf-8")
    with running_screen(tmp_path, str(tmp_path / "greet.face"), "--no-idle") as screen:
        screen.json("POST", "/api/command", "on button ok { happy }")
        run = baxterface("send", "--event", "button ok", "--url", screen.url)
        assert run.code == 0 and run.err == "", run.err
        assert run.out == f"raised 'button ok' at {screen.url} (1 runs, 0 dropped, 0 queued)\n"
        eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["emotion"] == "happy")


def test_a_bad_event_is_one_error_where_it_is_and_nothing_is_sent():
    run = baxterface("send", "--event", "butn ok", "--url", "http://127.0.0.1:9/")
    assert run.code == 1 and run.out == ""
    assert run.err.splitlines()[0] == "<event>:1:1: error: unknown event 'butn'; did you mean 'button'?"
    both = baxterface("send", "happy", "--event", "button ok")
    assert both.code == 2 and both.err == "baxterface send: give --event or a command, not both\n"
    alone = baxterface("send", "--url", "http://127.0.0.1:9/")
    assert alone.code == 2 and alone.err == "baxterface send: --url goes with --event\n"
