"""The studio against what a hostile tester sent it (issue 35): a real studio over loopback."""

from __future__ import annotations

import json
import os
import stat
import subprocess

import pytest

from baxterface_cli.studio.panel import load_panel
from baxterface_cli.studio.workspace import Workspace
from studio_server import baxterface, running_studio
from waiting import eventually


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "show.face").write_text("happy\nwait 1s\n", encoding="utf-8")
    return tmp_path


def test_a_panel_press_costs_at_the_1000th_what_it_did_at_the_first(folder):
    """Issue 43: a press cost 7 ms at the first and 48 ms at the 1,000th: the part of the session
    it fell in (up to 50 presses) was parsed and compiled again at each one. A press is one input
    to the session's kept run now: it goes on from the last one (bench/bench_hostile_studio.py
    times it)."""
    commands = [b.command for b in load_panel() if ";" not in b.command and "say" not in b.command]
    now = [100.0]
    workspace = Workspace(folder / "show.face", seed=3, idle=False, clock=lambda: now[0])
    handed, steps = [], []
    for i in range(1000):
        now[0] = 100.0 + i * 0.05  # a flood: each takes over from the one before
        before = workspace.preview.run.checkpoints[-1].session.steps
        workspace.press(commands[i % len(commands)])
        run = workspace.preview.run
        handed.append(run.handed)
        steps.append(run.checkpoints[-1].session.steps - before)
    assert set(handed) == {1}  # the press alone handed to the session, never the ones before it
    assert max(steps[900:]) <= max(steps[:100])  # and the steps it took as few at the end
    assert workspace.session()["count"] == 1000 and len(workspace.session()["presses"]) == 200


def test_a_number_of_thousands_of_digits_is_refused_in_the_apis_own_words(folder):
    # Issue 43: Python's own limit on such integers answered, naming set_int_max_str_digits.
    with running_studio(folder / "show.face") as studio:
        code, answer = studio.json("POST", "/api/touch", '{"x": 1' + "0" * 4999 + ', "y": 0.5}')
    assert code == 400
    assert answer["error"] == "the body has a number of 5000 digits; a number here has at most 100"


def test_check_reports_the_recordings_check_reports(folder):
    (folder / "outside").mkdir()
    with running_studio(folder / "show.face") as studio:
        for name in ("nosuch.wav", "../outside/secret.wav", "/etc/passwd"):
            text = f'say file "{name}"\n'
            code, answer = studio.json("POST", "/api/check", text)
            cli = subprocess.run(
                [baxterface(), "check", "-"], input=text, capture_output=True, text=True, cwd=folder
            )
            assert cli.returncode == 1 and ":1:" in cli.stderr, cli.stderr
            assert code == 200 and [(d["line"], d["severity"]) for d in answer] == [(1, "error")], (
                name,
                answer,
            )


def test_every_endpoint_decodes_as_check_does(folder):
    with running_studio(folder / "show.face") as studio:
        status, body = _raw(studio, "/api/check", b"happy\n\xe9\n")
        assert status == 200 and "not a UTF-8" in json.loads(body)[0]["message"]
        status, body = _raw(studio, "/api/check", "\ufeffhappy\n".encode("utf-8"))
        assert status == 200 and json.loads(body) == []
        status, body = _raw(studio, "/api/save", b"happy\n\xe9\n")
        assert status == 400 and "not a UTF-8" in json.loads(body)["error"]
    assert (folder / "show.face").read_bytes() == b"happy\nwait 1s\n"


def test_a_save_the_studio_could_not_load_again_is_refused(folder):
    with running_studio(folder / "show.face") as studio:
        status, body = _raw(studio, "/api/save", b"#" * (256 * 1024 + 1))
        assert status == 413 and "262144" in json.loads(body)["error"]
    assert (folder / "show.face").read_bytes() == b"happy\nwait 1s\n"


def test_a_save_keeps_the_files_permissions(folder):
    script = folder / "show.face"
    os.chmod(script, 0o600)
    with running_studio(script) as studio:
        code, _ = studio.json("POST", "/api/save", "sad\n")
        assert code == 200
    assert stat.S_IMODE(os.stat(script).st_mode) == 0o600 and script.read_text() == "sad\n"


def test_an_edit_on_disk_the_studio_cannot_read_is_told_and_not_overwritten(folder):
    script = folder / "show.face"
    with running_studio(script) as studio:
        version = studio.json("GET", "/api/state")[1]["script"]["version"]
        script.write_bytes("caf\xe9\n".encode("latin-1"))
        eventually(lambda: studio.json("GET", "/api/state")[1]["script"]["version"] > version, timeout=10)
        code, answer = studio.json("POST", f"/api/save?base={version}", "sad\n")
        assert code == 409 and "cannot read" in answer["error"], answer
    assert script.read_bytes() == "caf\xe9\n".encode("latin-1")


def test_deep_json_and_huge_numbers_are_refused_with_a_reason(folder):
    with running_studio(folder / "show.face") as studio:
        code, answer = studio.json("POST", "/api/transport", "[" * 100_000 + "]" * 100_000)
        assert code == 400 and "JSON" in answer["error"]
        code, answer = studio.json("POST", "/api/transport", '{"action": "seek", "t": ' + "9" * 400 + "}")
        assert code == 400 and "400 digits" in answer["error"]


def test_exporting_a_session_again_replaces_its_file(folder):
    with running_studio(folder / "show.face") as studio:
        assert studio.json("POST", "/api/command", "happy")[0] == 200
        names = {studio.json("POST", "/api/session/export")[1]["path"] for _ in range(20)}
        assert len(names) == 1
        studio.json("POST", "/api/session/clear")
        studio.json("POST", "/api/command", "sad")
        names.add(studio.json("POST", "/api/session/export")[1]["path"])
    assert len(names) == 2 and sorted(p.name for p in folder.glob("session-*.jsonl")) == sorted(names)


def _raw(studio, path, data: bytes):
    import urllib.error
    import urllib.request

    headers = {"X-Baxterface-Token": studio.token} if studio.token else {}
    req = urllib.request.Request(studio.base + path, data=data, method="POST", headers=headers)
    try:
        with urllib.request.urlopen(req, timeout=30) as response:
            return response.status, response.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()
