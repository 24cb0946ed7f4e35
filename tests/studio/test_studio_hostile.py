"""The studio against what a hostile tester sent it (issue 35): a real studio over loopback."""

from __future__ import annotations

import json
import os
import stat
import subprocess

import pytest

from baxterface_cli.language.source import PIECE
from baxterface_cli.studio.panel import load_panel
from baxterface_cli.studio.presses import PART_MOST, Presses
from studio_server import baxterface, running_studio
from waiting import eventually


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "show.face").write_text("happy\nwait 1s\n", encoding="utf-8")
    return tmp_path


def test_a_panel_press_compiles_at_the_1000th_what_it_did_at_the_first():
    """Issue 43: a press cost 7 ms at the first and 48 ms at the 1,000th: the part of the session
    it fell in (up to 50 presses) was parsed and compiled again at each one."""
    commands = [b.command for b in load_panel() if ";" not in b.command and "say" not in b.command]
    session = Presses(seed=3)
    costs = []
    for i in range(1000):
        before = session.compiled_presses
        session.press(commands[i % len(commands)], 100.0 + i * 0.05)  # a flood: they overlap
        costs.append(session.compiled_presses - before)
    assert costs[999] == costs[0] == 1 and set(costs) == {1}
    assert len(session.presses) == 1000 and session.text.count("repeat 1 {") == 999  # all in one together


def test_a_flood_of_presses_of_several_steps_compiles_at_most_a_part():
    # The panel's head shake is three moves: the next press comes before the last has begun, so
    # it keeps the presses after it in its part, for at most PART_MOST of them.
    shake = next(b.command for b in load_panel() if b.label == "Shake head")
    session = Presses(seed=3)
    costs = []
    for i in range(3 * PART_MOST):
        before = session.compiled_presses
        session.press([shake, "happy", "look left in 0.2s"][i % 3], 100.0 + i * 0.05)
        costs.append(session.compiled_presses - before)
    assert max(costs) <= PART_MOST
    assert len(session.presses) == 3 * PART_MOST and session.text.count("\n") > 3 * PART_MOST


def test_the_session_knows_its_size_without_writing_its_text():
    # What a press checks against the script limits, counted a press at a time, is the export's.
    session = Presses(seed=5)
    times = [0.0, 0.0004, 0.3, 0.31, 2.0, 2.0, 2.1, 9.9, 10.0, 10.0004, 30.0]
    for k, at in enumerate(times):
        session.press(["happy", "look left in 1s\nsad", "blink", "wobble 0.2 in 0.5s; nod"][k % 4], 50.0 + at)
        text = session.text
        body = text.split("\n", 2)[2]
        assert session.size.total[0] == len(body.encode("utf-8"))
        assert session.size.total[1] == sum(1 for _ in PIECE.finditer(body))


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
    assert len(names) == 2 and sorted(p.name for p in folder.glob("session-*.face")) == sorted(names)


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
