"""`baxterface state` reading a real screen and a real studio over loopback, and saying why it cannot."""

from __future__ import annotations

import json

import pytest

from conftest import baxterface, free_port
from studio_server import running_screen, running_studio
from waiting import eventually

pytestmark = pytest.mark.xdist_group("state_command")


@pytest.fixture(scope="module")
def screen(tmp_path_factory):
    with running_screen(tmp_path_factory.mktemp("screen"), "--no-idle") as server:
        yield server


def state_line(url, emotion):
    """`baxterface state --url URL`'s line once it shows `emotion` (its result on standard output,
    nothing on standard error); None before."""
    run = baxterface("state", "--url", url)
    assert run.code == 0 and run.err == "", run.err
    return run.out if run.out.startswith(f"{emotion} (") else None


def test_state_reads_a_screen_in_one_line_and_as_json(screen):
    status, _ = screen.request("POST", "/api/command", "happy; look left in 0.3s")
    assert status == 200
    line = eventually(lambda: state_line(screen.url, "happy"))
    assert line.count("\n") == 1 and "; eyes " in line and "lids 1" in line
    as_json = baxterface("state", "--url", screen.url, "--json")
    assert as_json.code == 0 and as_json.err == ""
    found = json.loads(as_json.out)
    assert found["face"]["emotion"] == "happy" and found["screens"] == 0


def test_state_reads_a_studios_preview(tmp_path):
    script = tmp_path / "show.face"
    script.write_text("sad\n", encoding="utf-8")
    with running_studio(script, "--no-idle") as studio:
        status, _ = studio.request("POST", "/api/command", "confused")
        assert status == 200
        assert eventually(lambda: state_line(studio.url, "confused"))
        found = json.loads(baxterface("state", "--url", studio.url, "--json").out)
    assert found["face"]["emotion"] == "confused" and found["kind"] == "status"


def test_nothing_serving_is_one_line_naming_the_address():
    port = free_port()
    run = baxterface("state", "--url", f"http://127.0.0.1:{port}/", "--timeout", "5")
    assert run.code == 1 and run.out == ""
    assert (
        run.err.strip()
        == f"baxterface state: cannot reach http://127.0.0.1:{port}/api/state: Connection refused"
    )


@pytest.mark.parametrize("url", ["ftp://127.0.0.1/", "127.0.0.1:8081", "http://"])
def test_a_url_that_is_not_http_is_a_usage_error(url):
    run = baxterface("state", "--url", url)
    assert run.code == 2 and run.err.startswith("baxterface state: --url must be an http:// address")


def test_a_server_that_is_not_a_face_says_so(tmp_path):
    import http.server
    import threading

    class NotAFace(http.server.BaseHTTPRequestHandler):
        def do_GET(self):  # noqa: N802 (the standard library's name)
            self.send_response(200)
            self.end_headers()
            self.wfile.write(b"<html>hello</html>")

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), NotAFace)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        run = baxterface("state", "--url", f"http://127.0.0.1:{server.server_address[1]}/")
    finally:
        server.shutdown()
    assert run.code == 1 and "is not a screen or a studio" in run.err and "Traceback" not in run.err
