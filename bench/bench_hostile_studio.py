"""The studio (and the screen) under hostile traffic: does the preview keep moving, stay up, stop.

    python bench/bench_hostile_studio.py [flood] [presses] [rebinding] [half-open] [pages]

With no phase named, all five run, in that order.

flood:

Starts `baxterface studio` (idle off) on a two-line script, with a page (a
WebSocket client here) watching a face kept moving for the whole run, then
floods it for 10 s from a process of its own, over 8 keep-alive connections:
good commands, typos, bodies at, over and far over the 256 KB limit, the
largest valid script to check, bad JSON, another site's Origin, no Origin,
unknown paths. Measures:

- requests a second: answered (2xx), refused (4xx), failed (5xx, connection
  errors, timeouts: there should be none);
- the largest gap between frames reaching the page during the flood, and the
  median interval; the baseline is the same face in the 3 s before the flood
  (1/fps would be 33 ms at the default 30 fps);
- the studio's memory before the flood, after it, and after 2 s of rest;
- its log: lines other than the one it writes for each refused request;
- with a page connected to a moving face, the time to stop on SIGINT and on
  SIGTERM, and the exit codes (130 and 143 expected).

rebinding: at the studio and at the screen, requests with the Host (and a
matching Origin) a rebinding page sends, a wrong port, no port, and Origins
that do not parse: the answer to GET /api/state, POST /api/save (studio) and
a WebSocket upgrade of /api/live (403 expected for each; 200 and 101 for
the good ones).

half-open: at the studio and at the screen, started with `ulimit -n 1024`,
1,100 connections that never send a byte; then a well-behaved client asks
GET /api/state once a second for 40 s: how many answers it gets, the first
one after how long, and how much the server wrote to its log.

presses (issue 43: 9a): the studio (idle off) and 1,000 presses of the default panel's buttons
(PRESSES=10000 in the environment for 10,000, the most a session holds) posted back to back over
one keep-alive connection: the median time of the 20 presses around the 1st, 100th, 500th,
1,000th and 10,000th, each as a ratio to the first 20's (the baseline, measured in the same run),
and the p95 over all of them.

pages: the screen at --fps 30 with 250 pages (WebSockets) open, commands
posted back to back for 10 s: frames a second each page receives, and the
time from a command's posting to the next frame at a page (p50, p95).
"""

from __future__ import annotations

import concurrent.futures
import http.client
import multiprocessing
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "support"))

from baxterface_cli.core.face_constants import LIMITS  # noqa: E402
from studio_server import URL_LINE  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SECONDS, CONNECTIONS = 10.0, 8
MOVING = "repeat 100 { look 60 0 in 1s; look -60 0 in 1s }"  # every frame differs, for minutes
HUGE = "look 40 -20 in 0.05s; look -40 20 in 0.05s\n" * (LIMITS.max_pieces // 12)  # largest valid script
# (label, method, path, body, origin): None keeps the page's Origin, "" sends none.
MIX = [
    ("good command", "POST", "/api/command", MOVING, None),
    ("typo", "POST", "/api/command", "hapy", None),
    ("body at the limit", "POST", "/api/command", "x" * LIMITS.max_bytes, None),
    ("300 KB body", "POST", "/api/command", "x" * 300_000, None),
    ("check, largest script", "POST", "/api/check", HUGE, None),
    ("bad JSON", "POST", "/api/transport", '{"action": "seek", "t": ', None),
    ("other site's Origin", "POST", "/api/command", MOVING, "http://evil.example"),
    ("no Origin", "POST", "/api/command", MOVING, ""),
    ("unknown path", "GET", "/api/nothing", None, None),
    ("good command", "POST", "/api/command", MOVING, None),
    ("state", "GET", "/api/state", None, None),
    ("5 MB body", "POST", "/api/command", "x" * 5_000_000, None),
]


def start(script: Path, log: Path, words: tuple = ("studio",), files: int = 0) -> tuple:
    """`baxterface studio SCRIPT` (or WORDS SCRIPT) as its own process; (process, port) once it answers.

    `files`, when given, is the most files the server may hold open (as `ulimit -n`)."""
    env = dict(
        os.environ,
        PYTHONUNBUFFERED="1",
        PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    )
    command = [sys.executable, "-m", "baxterface_cli", *words, str(script), "--no-browser", "--port", "0"]

    def limited() -> None:
        import resource

        resource.setrlimit(resource.RLIMIT_NOFILE, (files, files))

    with open(log, "w", encoding="utf-8") as err:
        process = subprocess.Popen(
            [*command, "--seed", "7", "--no-idle"],
            stdout=subprocess.DEVNULL,
            stderr=err,
            env=env,
            cwd=script.parent,
            preexec_fn=limited if files else None,
        )
    deadline = time.monotonic() + 60
    while not (found := URL_LINE.search(log.read_text(encoding="utf-8"))):
        if process.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError(f"the studio did not start: {log.read_text(encoding='utf-8')}")
        time.sleep(0.05)
    return process, int(re.search(r":(\d+)/", found.group(1)).group(1))


def post(port: int, path: str, body: str) -> int:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    connection.request("POST", path, body=body.encode(), headers={"Origin": f"http://127.0.0.1:{port}"})
    status = connection.getresponse().status
    connection.close()
    return status


class Page:
    """A page's WebSocket: the arrival time of every frame, and how the studio closed it."""

    def __init__(self, port: int) -> None:
        from websockets.sync.client import connect

        self.times: list = []
        self.closed = None
        origin = f"http://127.0.0.1:{port}"
        self.ws = connect(f"ws://127.0.0.1:{port}/api/live", origin=origin, max_size=None)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        from websockets.exceptions import ConnectionClosed

        try:
            for message in self.ws:
                if isinstance(message, bytes):
                    self.times.append(time.monotonic())
        except ConnectionClosed:
            pass
        self.closed = self.ws.close_code


def intervals(times: list, begin: float, end: float) -> list:
    """Milliseconds between the frames that reached the page from `begin` to `end`."""
    inside = [t for t in times if begin <= t <= end]
    return [(b - a) * 1000 for a, b in zip(inside, inside[1:])]


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def flood(port: int, seconds: float) -> tuple:
    """In a process of its own: (began, ended, outcomes by second, answers by kind of request)."""
    began = time.monotonic()
    seconds_seen, answers, lock = Counter(), Counter(), threading.Lock()

    def one_connection(offset: int) -> None:
        connection, i = http.client.HTTPConnection("127.0.0.1", port, timeout=10), offset
        while (now := time.monotonic()) - began < seconds:
            label, method, path, body, origin = MIX[i % len(MIX)]
            i += 1
            headers = {} if origin == "" else {"Origin": origin or f"http://127.0.0.1:{port}"}
            try:
                connection.request(method, path, body=body and body.encode(), headers=headers)
                response = connection.getresponse()
                response.read()
                status, why = response.status, str(response.status)
            except (OSError, http.client.HTTPException) as e:  # a timeout is an OSError
                status, why = 0, type(e).__name__
                connection.close()  # http.client reconnects on the next request
            outcome = "answered" if 200 <= status < 300 else "refused" if 400 <= status < 500 else "failed"
            with lock:
                seconds_seen[int(now - began), outcome] += 1
                answers[label, why] += 1

    threads = [threading.Thread(target=one_connection, args=(k,)) for k in range(CONNECTIONS)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return began, time.monotonic(), dict(seconds_seen), dict(answers)


def stop_time(folder: Path, signum: int) -> tuple:
    """A fresh studio, a page on a moving face, then `signum`: (seconds to exit, exit code, close code)."""
    process, port = start(folder / "face.bax", folder / f"stop-{signum}.log")
    page = Page(port)
    post(port, "/api/command", MOVING)
    time.sleep(1.5)
    sent = time.monotonic()
    process.send_signal(signum)
    try:
        code = process.wait(timeout=30)
    except subprocess.TimeoutExpired:
        process.kill()
        code = f"killed after 30 s (was still running, {process.wait()})"
    took = time.monotonic() - sent
    time.sleep(0.2)
    return took, code, page.closed


def flood_phase() -> None:
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-studio-"))
    (folder / "face.bax").write_text("happy\nwait 1s\n", encoding="utf-8")
    log = folder / "studio.log"
    process, port = start(folder / "face.bax", log)
    try:
        page = Page(port)
        assert post(port, "/api/command", MOVING) == 200
        time.sleep(1.0)
        quiet = time.monotonic()
        time.sleep(3.0)  # the baseline: the same moving face, no flood
        calm = intervals(page.times, quiet, time.monotonic())
        before = rss_mb(process.pid)
        # Spawned, not forked: this process already runs the page's thread.
        context = multiprocessing.get_context("spawn")
        with concurrent.futures.ProcessPoolExecutor(1, mp_context=context) as pool:
            began, ended, by_second, answers = pool.submit(flood, port, SECONDS).result()
        after = rss_mb(process.pid)
        time.sleep(2.0)
        rested = rss_mb(process.pid)
        stormy = intervals(page.times, began, ended)
        alive = process.poll() is None
    finally:
        process.terminate()
        process.wait(timeout=30)
    lines = log.read_text(encoding="utf-8").splitlines()
    size, longest = log.stat().st_size / 2**20, max(map(len, lines), default=0)
    # One line per refused request is by design; anything else is news.
    odd = [line for line in lines if not re.search(r": (40[03-5]|413) |studio: http|stopped", line)]
    stops = {
        name: stop_time(folder, signum)
        for name, signum in (("SIGINT", signal.SIGINT), ("SIGTERM", signal.SIGTERM))
    }
    shutil.rmtree(folder)

    print(f"flood: {SECONDS:.0f} s, {CONNECTIONS} keep-alive connections, from a process of its own")
    for second in range(int(SECONDS)):
        row = {k: by_second.get((second, k), 0) for k in ("answered", "refused", "failed")}
        counts = "  ".join(f"{k} {n:4d}" for k, n in row.items())
        print(f"  second {second + 1:2d}: {counts}")
    total = Counter()
    for (_, outcome), n in by_second.items():
        total[outcome] += n
    print(f"  total: answered {total['answered']}, refused {total['refused']}, failed {total['failed']}")
    print("  answers by kind of request:")
    for label in dict.fromkeys(m[0] for m in MIX):
        got = ", ".join(f"{why} x{n}" for (kind, why), n in sorted(answers.items()) if kind == label)
        print(f"    {label}: {got}")
    for name, gaps in (("3 s before the flood (baseline)", calm), ("during the flood", stormy)):
        print(f"frames reaching the page {name}: {len(gaps) + 1}")
        print(
            f"  median interval {statistics.median(gaps) if gaps else float('nan'):.1f} ms (30 fps: 33.3 ms)"
        )
        print(f"  largest gap {max(gaps, default=float('nan')):.0f} ms")
    print(f"studio memory before the flood: {before:.0f} MB")
    print(f"studio memory after the flood: {after:.0f} MB")
    print(f"studio memory after 2 s of rest: {rested:.0f} MB")
    print(f"studio still running after the flood: {alive}")
    print(f"studio log: {len(lines)} lines, {size:.1f} MB, longest line {longest} characters")
    print(f"studio log lines other than refusals: {len(odd)}")
    for line in odd[:5]:
        print(f"  {line[:160]}")
    for name, (took, code, closed) in stops.items():
        print(f"{name}, a page connected: exited in {took:.2f} s, exit code {code}, page closed {closed}")


def presses_phase() -> None:
    from baxterface_cli.studio.panel import load_panel

    count = int(os.environ.get("PRESSES", "1000"))
    commands = [b.command for b in load_panel() if not b.command.startswith("follow")]
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-presses-"))
    (folder / "face.bax").write_text("happy\n", encoding="utf-8")
    process, port = start(folder / "face.bax", folder / "studio.log")
    took = []
    try:
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        headers = {"Origin": f"http://127.0.0.1:{port}"}
        for i in range(count):
            began = time.perf_counter()
            body = commands[i % len(commands)].encode()
            connection.request("POST", "/api/command", body=body, headers=headers)
            response = connection.getresponse()
            response.read()
            took.append((time.perf_counter() - began) * 1000)
            if response.status == 400:  # the session at its limit: cleared, as a user would
                connection.request("POST", "/api/session/clear", headers=headers)
                connection.getresponse().read()
    finally:
        process.terminate()
        process.wait(timeout=30)
        shutil.rmtree(folder)
    baseline = statistics.median(took[:20])
    print(f"presses: {count} of the default panel's buttons, back to back, one connection")
    print(f"  1st (median of the first 20): {baseline:.1f} ms (the baseline)")
    for n in (100, 500, 1000, 10000):
        if n <= count:
            around = statistics.median(took[max(0, n - 10) : n + 10])
            print(f"  {n}th (median of the 20 around it): {around:.1f} ms, {around / baseline:.2f}x the 1st")
    print(f"  p95 over all: {sorted(took)[int(0.95 * len(took))]:.1f} ms")


PHASES = {"flood": flood_phase, "presses": presses_phase}


def main() -> None:
    from bench_hostile_web import PHASES as WEB_PHASES

    phases = {**PHASES, **WEB_PHASES}
    asked = sys.argv[1:] or list(phases)
    unknown = [name for name in asked if name not in phases]
    if unknown:
        raise SystemExit(f"no phase {unknown[0]!r}: the phases are {', '.join(phases)}")
    for name in asked:
        print(f"== {name}", flush=True)
        phases[name]()


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    main()
