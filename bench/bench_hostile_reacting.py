"""Scripts that pass `check` and would not keep time (issue 43): what each costs, against a plain
script measured in the same run.

- live: a real `baxterface screen`; after each script, 20 events (`POST /api/event touch`) and a
  command: the median answer, and its ratio to the same after `happy; wait 1s` (1.0 is as quick).
  Before the least round, each of these got no answer at all (15 s timeouts).
- recorded: `explain --duration 10` of each, its seconds and peak memory against
  `forever { blink; wait 1s }` (the handler's spin grew 8 MB a second, without end).
- session: 1,000 signals in a row, in-process (a RecursionError before), and handler installs:
  the 256th install's time against the first's.

    python bench/bench_hostile_reacting.py
"""

from __future__ import annotations

import http.client
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_hostile_studio import start

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baxterface_cli import parse  # noqa: E402
from baxterface_cli.engine.live_session import LiveSession  # noqa: E402
from baxterface_cli.language import syntax_tree as n  # noqa: E402

PLAIN = "happy; wait 1s"
SPINS = {
    "wait until, timeout 1 us": "forever { wait until signal x timeout 0.000001s }",
    "wait 10 us": "forever { wait 0.00001s }",
    "a handler's spin": "on signal go { forever { wait until face seen timeout 0.000001s } }\nsignal go",
    "1,000 signals": "on signal x queue { blink }\nrepeat 1000 { signal x }",
}


def post(port: int, path: str, body: str) -> float:
    began = time.perf_counter()
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    connection.request("POST", path, body.encode("utf-8"))
    connection.getresponse().read()
    connection.close()
    return time.perf_counter() - began


def live_phase() -> None:
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-reacting-"))
    (folder / "face.bax").write_text("happy\n", encoding="utf-8")
    process, port = start(folder / "face.bax", folder / "screen.log", ("screen",))
    try:

        def after(script: str) -> float:
            post(port, "/api/command", script)
            return statistics.median(post(port, "/api/event", "touch") for _ in range(20))

        base = after(PLAIN)
        print(f"live (screen): an event's answer after each script; after {PLAIN!r}: {base * 1000:.1f} ms")
        for name, script in SPINS.items():
            took = after(script)
            print(f"  {name:28} {took * 1000:7.1f} ms  {took / base:5.2f}x")
    finally:
        process.terminate()
        process.wait(timeout=30)


def explain(script: str, folder: Path) -> tuple:
    path = folder / "s.face"
    path.write_text(script, encoding="utf-8")
    (folder / "go.events").write_text("0.5 signal go\n", encoding="utf-8")
    command = [sys.executable, "-m", "baxterface_cli", "explain", str(path), "--duration", "10"]
    began = time.perf_counter()
    child = subprocess.run([*command, "--events", str(folder / "go.events")], capture_output=True)
    took = time.perf_counter() - began
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return took, peak, child.returncode


def recorded_phase() -> None:
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-reacting-"))
    base, _, _ = explain("forever { blink; wait 1s }", folder)
    print(f"recorded: explain --duration 10; 'forever {{ blink; wait 1s }}': {base:.2f} s")
    for name, script in SPINS.items():
        took, peak, code = explain(script, folder)
        print(f"  {name:28} {took:6.2f} s  {took / base:5.2f}x  peak so far {peak:.0f} MB, exit {code}")


def session_phase() -> None:
    began = time.perf_counter()
    s = LiveSession(
        parse("on signal x queue { blink }\non touch { repeat 1000 { signal x } }", "t"), idle=False
    )
    s.post(n.Event("touch"), 1.0)
    s.advance(100.0)
    print(f"session: 1,000 signals from a handler: {time.perf_counter() - began:.2f} s, {s.steps} steps")
    s = LiveSession(idle=False)
    times = []
    for i in range(256):
        script = parse(f"on signal s{i} {{ nod }}", "t")
        began = time.perf_counter()
        s.run(script, float(i))
        times.append(time.perf_counter() - began)
    first, last = statistics.median(times[:10]), statistics.median(times[-10:])
    print(
        f"session: a handler's install, the last ten {last * 1e3:.2f} ms against the first ten's "
        f"{first * 1e3:.2f} ms: {last / first:.2f}x"
    )


if __name__ == "__main__":
    session_phase()
    recorded_phase()
    live_phase()
