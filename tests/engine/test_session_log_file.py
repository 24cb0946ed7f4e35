"""The session's log file: JSON Lines of what a live session did, flushed as it goes, rotated past
its size, and a file that cannot be written one line in the end's log and never a stop."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import time

from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_intake import SessionIntake
from baxterface_cli.engine.session_log_file import VERSION, SessionLogFile
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.parser import parse


def records(path):
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]


def handler_ended(got):
    """Whether the button's handler has ended (the main script ends too, before the event or after)."""
    return any(r.get("kind") == "ended" and "'on button ok'" in r["text"] for r in got)


def wait_for(check, timeout=10.0):
    deadline = time.monotonic() + timeout
    while not check():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.01)


SCRIPT = "on button ok { happy\n wait 0.2s }\non touch mouth { sad }\nconfused"


def test_a_session_at_its_intake_is_kept_record_by_record_as_it_goes(tmp_path):
    path = tmp_path / "session.jsonl"
    clock = time.monotonic
    session = LiveSession(now=clock(), keep_up=True, idle=False)
    record = SessionLogFile(str(path), clock(), {"end": "test"})
    intake = SessionIntake(session, clock, record=record, filename="chatter")
    intake.submit(SCRIPT)
    intake.settled(10)
    intake.post(n.Event("button", "ok"), "/robot/buttons")
    intake.settled(10)
    # Flushed as it goes: the event is in the file while the session still runs.
    wait_for(lambda: path.exists() and any(r["type"] == "event" for r in records(path)))
    wait_for(lambda: handler_ended(records(path)))
    intake.close()
    got = records(path)
    assert got[0]["type"] == "start" and got[0]["version"] == VERSION and got[0]["t"] == 0.0
    assert got[0]["settings"] == {"end": "test"} and "wall" in got[0]
    (script,) = [r for r in got if r["type"] == "script"]
    assert script["text"] == SCRIPT and script["source"] == "chatter"
    (event,) = [r for r in got if r["type"] == "event"]
    assert event["event"] == "button ok" and event["source"] == "/robot/buttons"
    kinds = [r["kind"] for r in got if r["type"] == "log"]
    # The event, then its handler's start (the main script may end before the event or after it:
    # a loaded machine posts the event later).
    first = kinds.index("event")
    assert kinds[first : first + 2] == ["event", "started"] and handler_ended(got)
    assert got[-1]["type"] == "end"
    times = [r["t"] for r in got]
    assert times == sorted(times) and all(t >= 0 for t in times)


def test_what_the_face_says_is_kept_with_its_voice_start_and_length(tmp_path):
    from baxterface_cli.engine.compiler import compile_script
    from baxterface_cli.engine.timeline import Said

    class Utterance:
        said, voice, duration = "hello there", "en-us", 1.25

    timeline = compile_script(parse("happy"))
    timeline.speech.append(Said(0.5, Utterance(), []))
    path = tmp_path / "said.jsonl"
    record = SessionLogFile(str(path), 10.0, {})
    record.begun(timeline, 12.0)
    record.close(13.0)
    (said,) = [r for r in records(path) if r["type"] == "say"]
    assert said == {"type": "say", "t": 2.5, "text": "hello there", "voice": "en-us", "length": 1.25}


def test_past_its_size_the_file_rotates_and_a_session_before_is_kept(tmp_path):
    path = tmp_path / "big.jsonl"
    path.write_text('{"type": "start"}\n')  # a session before this one
    record = SessionLogFile(str(path), 0.0, {}, max_bytes=4096)
    for i in range(200):
        record.script(i, "neutral " * 5, "chatter")
    record.close(300.0)
    assert path.stat().st_size <= 4096
    assert (tmp_path / "big.jsonl.1").exists() and (tmp_path / "big.jsonl.4").exists()
    assert not (tmp_path / "big.jsonl.5").exists()
    first = records(path)[0]
    assert first["type"] == "continued" and first["version"] == VERSION
    assert records(path)[-1]["type"] == "end"


def test_a_log_that_cannot_be_opened_is_one_line_and_the_session_goes_on(tmp_path):
    said = []
    clock = time.monotonic
    session = LiveSession(now=clock(), keep_up=True, idle=False)
    record = SessionLogFile(str(tmp_path), clock(), {}, warn=said.append)  # a folder: never a file
    intake = SessionIntake(session, clock, record=record)
    for _ in range(3):
        intake.submit("happy")
        intake.post(n.Event("button", "ok"))
    intake.settled(10)
    wait_for(lambda: said)
    assert session.face.timeline is not None and not intake._closed
    intake.submit("sad")
    assert intake.settled(10)
    intake.close()
    assert len(said) == 1 and str(tmp_path) in said[0] and "goes on without it" in said[0]


def test_a_full_disk_is_one_line_and_the_session_goes_on(tmp_path):
    # RLIMIT_FSIZE in a child: writing past it fails as a full disk does (Python ignores SIGXFSZ).
    child = textwrap.dedent(
        f"""
        import resource, sys, time
        from baxterface_cli.engine.live_session import LiveSession
        from baxterface_cli.engine.session_intake import SessionIntake
        from baxterface_cli.engine.session_log_file import SessionLogFile
        resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))
        said = []
        session = LiveSession(now=time.monotonic(), keep_up=True, idle=False)
        record = SessionLogFile({str(tmp_path / "full.jsonl")!r}, time.monotonic(), {{}}, said.append)
        intake = SessionIntake(session, time.monotonic, record=record)
        for i in range(100):
            intake.submit("happy" if i % 2 else "sad")
            intake.settled(10)
        time.sleep(0.3)
        intake.submit("angry")
        assert intake.settled(10)
        intake.close()
        print(len(said), said[0] if said else "")
        """
    )
    done = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    count, _, line = done.stdout.strip().partition(" ")
    assert count == "1" and "cannot be written" in line and "goes on without it" in line


def test_a_say_at_the_intake_is_kept_with_its_text_and_length(tmp_path, engine):
    path = tmp_path / "say.jsonl"
    clock = time.monotonic
    session = LiveSession(now=clock(), keep_up=True, idle=False)
    intake = SessionIntake(session, clock, record=SessionLogFile(str(path), clock(), {}))
    intake.submit('happy\nsay "hello there"')
    wait_for(lambda: path.exists() and any(r["type"] == "say" for r in records(path)))
    intake.close()
    (said,) = [r for r in records(path) if r["type"] == "say"]
    (script,) = [r for r in records(path) if r["type"] == "script"]
    assert said["text"] == "hello there" and said["voice"] == "en" and 0.3 < said["length"] < 3
    assert said["t"] >= script["t"]
