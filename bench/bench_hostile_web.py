"""bench_hostile_studio.py's phases about who may connect: rebinding, half-open connections, many pages.

Run them through bench_hostile_studio.py (`python bench/bench_hostile_studio.py rebinding half-open pages`);
what each measures is said there.
"""

from __future__ import annotations

import asyncio
import http.client
import resource
import shutil
import socket
import statistics
import tempfile
import threading
import time
from pathlib import Path

from bench_hostile_studio import start
from raw_http import HOSTILE_HOSTS, ask, closed_by_server, upgrade

SERVERS = (("studio", ("studio",)), ("screen", ("screen",)))
GOOD_HOSTS = ["127.0.0.1:{port}", "localhost:{port}", "[::1]:{port}"]
BAD_ORIGINS = [
    "http://[",
    "http://127.0.0.1:{port}@evil.example",
    "null",
    "http://localhost:9999",
    "http://[::1",
]


def rebinding_phase() -> None:
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-web-"))
    (folder / "face.bax").write_text("happy\nwait 1s\n", encoding="utf-8")
    try:
        for name, words in SERVERS:
            process, port = start(folder / "face.bax", folder / f"{name}.log", words)
            try:
                print(f"{name}: request -> GET /api/state, POST /api/save, WebSocket (403 = refused)")
                for pattern in GOOD_HOSTS + HOSTILE_HOSTS:
                    host = pattern.format(port=port)
                    same = f"http://{host}"
                    row = [ask(port, "GET", "/api/state", host)[0]]
                    row.append(ask(port, "GET", "/api/state", host, same)[0])
                    if name == "studio":
                        row.append(ask(port, "POST", "/api/save", host, same, b"happy\n")[0])
                    row.append(upgrade(port, host, same))
                    print(f"  Host {host!r:40} (and Origin {same!r}): {row}")
                good = f"127.0.0.1:{port}"
                for pattern in BAD_ORIGINS:
                    origin = pattern.format(port=port)
                    row = [ask(port, "GET", "/api/state", good, origin)[0], upgrade(port, good, origin)]
                    print(f"  Host {good!r}, Origin {origin!r:40}: {row}")
                log = (folder / f"{name}.log").read_text(encoding="utf-8")
                print(f"  tracebacks in the log: {log.count('Traceback')}")
            finally:
                process.terminate()
                process.wait(timeout=30)
    finally:
        shutil.rmtree(folder)


HALF_OPEN, FILES, WATCHED = 1100, 1024, 40.0


def half_open_phase() -> None:
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < HALF_OPEN + 100:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, HALF_OPEN + 200), hard))
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-web-"))
    (folder / "face.bax").write_text("happy\nwait 1s\n", encoding="utf-8")
    try:
        for name, words in SERVERS:
            log = folder / f"{name}.log"
            process, port = start(folder / "face.bax", log, words, files=FILES)
            silent = []
            try:
                for _ in range(HALF_OPEN):
                    silent.append(socket.create_connection(("127.0.0.1", port), timeout=10))
                began = time.monotonic()
                answers, first = 0, None
                while time.monotonic() - began < WATCHED:
                    asked = time.monotonic()
                    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=2)
                    try:
                        connection.request("GET", "/api/state")
                        if connection.getresponse().status == 200:
                            answers += 1
                            first = first if first is not None else time.monotonic() - began
                    except (OSError, http.client.HTTPException):
                        pass
                    finally:
                        connection.close()
                    time.sleep(max(0.0, 1.0 - (time.monotonic() - asked)))
                held = sum(1 for sock in silent if not closed_by_server(sock))
                alive = process.poll() is None
            finally:
                for sock in silent:
                    sock.close()
                process.terminate()
                process.wait(timeout=30)
            lines = log.read_text(encoding="utf-8", errors="replace").splitlines()
            print(f"{name}: {HALF_OPEN} silent connections, ulimit -n {FILES}")
            print(f"  a well-behaved client, once a second for {WATCHED:.0f} s: {answers} answers", end="")
            print(f", the first after {first:.1f} s" if first is not None else ", none")
            print(f"  silent connections the server still held at the end: {held}; still running: {alive}")
            print(f"  log: {len(lines)} lines, {log.stat().st_size / 2**20:.2f} MB")
            for line in lines[:3]:
                print(f"    {line[:150]}")
    finally:
        shutil.rmtree(folder)


PAGES, FLOOD_SECONDS = (1, 250), 10.0


def pages_phase() -> None:
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < max(PAGES) + 200:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, max(PAGES) + 400), hard))
    for pages in PAGES:
        _pages_at_once(pages)


def _pages_at_once(pages: int) -> None:
    folder = Path(tempfile.mkdtemp(prefix="bench-hostile-web-"))
    (folder / "face.bax").write_text("happy\n", encoding="utf-8")
    process, port = start(folder / "face.bax", folder / "screen.log", ("screen", "--fps", "30"))
    try:
        counts, probe, sent, began, ended = asyncio.run(_pages(port, pages))
    finally:
        process.terminate()
        process.wait(timeout=30)
        shutil.rmtree(folder)
    seconds = ended - began
    rates = sorted(n / seconds for n in counts)
    waits = []
    for at in sent:
        after = next((t for t in probe if t >= at), None)
        if after is not None:
            waits.append((after - at) * 1000)
    waits.sort()
    print(f"screen --fps 30, {pages} pages, {len(sent)} commands in {seconds:.1f} s")
    print(
        f"  frames a second a page: median {statistics.median(rates):.1f}, "
        f"lowest {rates[0]:.1f}, highest {rates[-1]:.1f}"
    )
    if waits:
        p95 = waits[min(len(waits) - 1, int(len(waits) * 0.95))]
        p50 = statistics.median(waits)
        print(f"  command to the next frame at a page: p50 {p50:.0f} ms, p95 {p95:.0f} ms")


async def _pages(port: int, pages: int) -> tuple:
    import websockets

    counts = [0] * pages
    probe: list = []
    stop = asyncio.Event()
    began = ended = 0.0

    async def page(k: int) -> None:
        async with websockets.connect(f"ws://127.0.0.1:{port}/api/live", max_size=None) as ws:
            while not stop.is_set():
                try:
                    message = await asyncio.wait_for(ws.recv(), 0.5)
                except asyncio.TimeoutError:
                    continue
                if isinstance(message, bytes) and began and not ended:
                    counts[k] += 1
                    if k == 0:
                        probe.append(time.monotonic())

    tasks = [asyncio.ensure_future(page(k)) for k in range(pages)]
    await asyncio.sleep(3.0)
    sent: list = []
    faces = ["happy", "sad", "look left in 0.3s", "look right in 0.3s", "surprised", "angry"]

    def commands() -> None:
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        k = 0
        while time.monotonic() - began < FLOOD_SECONDS:
            sent.append(time.monotonic())
            connection.request("POST", "/api/command", body=faces[k % len(faces)].encode())
            connection.getresponse().read()
            k += 1
        connection.close()

    began = time.monotonic()
    flooder = threading.Thread(target=commands)
    flooder.start()
    await asyncio.get_running_loop().run_in_executor(None, flooder.join)
    ended = time.monotonic()
    stop.set()
    await asyncio.gather(*tasks, return_exceptions=True)
    return counts, probe, sent, began, ended


PHASES = {"rebinding": rebinding_phase, "half-open": half_open_phase, "pages": pages_phase}
