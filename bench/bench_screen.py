"""The screen in headless chromium: how soon a command shows, and what the face costs the network.

    python bench/bench_screen.py [--runs 60] [--seconds 10] [--pages 500] [--page-runs 10] [--before REV]
                                 [--pages-only]

1. A command to the first changed frame on the page (idle off, so nothing
   else changes the face): the page posts `look left in 0.4s` (then right) to
   /api/command and times until the next frame is shown (after one that warms
   up, not counted). Goal: p95 <= 100 ms.
   Baseline, in the same run: a page that fetches /api/frame.jpg 30 times a
   second and shows it when it changed, the way to show the face without the
   push.
2. Bandwidth: what the page receives over its WebSocket (frames and status
   messages) for `--seconds` each of a face left idle (blinks and darts), a
   face talking, and a face moving all the time, at 1024x600 and at 512x300.
   Baseline: the same frames at 30 a second, as a stream that sends every
   frame (MJPEG) would.

3. Many pages: `--pages` WebSocket clients in this process on one screen (bench/many_pages.py):
   `look left in 0.4s` (then right) posted once every page is still, each page's first frame
   after it timed on arrival. Goal: p95 <= 100 ms at 500 pages. Baseline, in the same run: the
   tree at `--before` (its package from `git archive`), served the same way.

1 and 2 are timed and counted inside the page (performance.now, the bytes the
WebSocket delivered), so the browser's own decoding and drawing are in.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

# The tests' browser and server helpers (which take `needs` from tests/conftest.py).
sys.path[:0] = [str(Path(__file__).resolve().parent.parent / "tests" / d) for d in ("support", "")]

from many_pages import many_pages, tree_of  # noqa: E402

from browser import chromium, wait_for  # noqa: E402
from studio_server import running_screen  # noqa: E402

TABLET = (1280, 800)
# The tree before the pages' frames went out unencoded for each (no permessage-deflate, the status once).
BEFORE = "322b013"

COMMANDS = """
const [runs, done] = [arguments[0], arguments[arguments.length - 1]];
const sides = ['look left in 0.4s', 'look right in 0.4s'];
const face = window.screenFace, out = [];
// From the middle, so that the first look changes the face too.
fetch('/api/command', {method: 'POST', body: 'look center'}).then(() => setTimeout(once, 700));
function once() {
  if (out.length >= runs) return done(out);
  const before = face.frames, start = performance.now();
  fetch('/api/command', {method: 'POST', body: sides[out.length % 2]});
  (function look() {
    if (face.frames > before && face.lastFrameAt >= start) {
      out.push(face.lastFrameAt - start);
      setTimeout(once, 700);  // the 0.4 s look is over: the face is still again
    } else setTimeout(look, 1);
  })();
}
"""

# The baseline: a page of its own that polls the frame 30 times a second and shows it when it changed.
POLLING = """
const [runs, done] = [arguments[0], arguments[arguments.length - 1]];
const sides = ['look left in 0.4s', 'look right in 0.4s'];
const img = new Image(), out = [];
let last = null, shownAt = 0, shown = 0, polling = true;
img.onload = () => { shown += 1; shownAt = performance.now(); };
const same = (a, b) => a && b && a.length === b.length && a.every((v, i) => v === b[i]);
async function poll() {
  while (polling) {
    const next = performance.now() + 1000 / 30;
    const bytes = new Uint8Array(await (await fetch('/api/frame.jpg')).arrayBuffer());
    if (!same(bytes, last)) {
      last = bytes;
      img.src = URL.createObjectURL(new Blob([bytes], {type: 'image/jpeg'}));
    }
    await new Promise((r) => setTimeout(r, Math.max(0, next - performance.now())));
  }
}
poll();
function once() {
  if (out.length >= runs) { polling = false; return done(out); }
  const before = shown, start = performance.now();
  fetch('/api/command', {method: 'POST', body: sides[out.length % 2]});
  (function look() {
    if (shown > before && shownAt >= start) {
      out.push(shownAt - start);
      setTimeout(once, 700);
    } else setTimeout(look, 1);
  })();
}
fetch('/api/command', {method: 'POST', body: 'look center'}).then(() => setTimeout(once, 700));
"""

TALK = (
    "say \"The face you see is drawn by the robot's own renderer, and what it says is heard on this "
    "screen, in step with its mouth. It keeps talking for a while, so that the bandwidth of a talking "
    'face can be measured over ten whole seconds, pauses at the commas included."'
)
MOVE = "repeat 20 { look left in 0.5s ease-in-out; look right in 0.5s ease-in-out }"


def p(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(round(q * (len(values) - 1))))]


COUNTS = "const s = window.screenFace; return [s.bytes, s.frameBytes, s.received];"


def received(driver, seconds):
    """(bytes, bytes of frames, frames) the page received over `seconds`."""
    start = driver.execute_script(COUNTS)
    time.sleep(seconds)
    end = driver.execute_script(COUNTS)
    return [b - a for a, b in zip(start, end)]


def open_page(driver, url):
    width, height = TABLET
    driver.execute_cdp_cmd(
        "Emulation.setDeviceMetricsOverride",
        {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
    )
    driver.get(url)
    wait_for(driver, "window.screenFace && window.screenFace.frames >= 1")


def bandwidth(folder, size, seconds):
    """Rows of (what, KB/s, frames/s, KB/s at 30 fps) for idle, talking and moving at `size`."""
    rows = []
    with running_screen(folder, "--size", size) as screen, chromium(*TABLET) as driver:
        open_page(driver, screen.url)
        time.sleep(1.0)  # the first frame and status are in
        for what, command in (("idle (blinks, darts)", None), ("talking", TALK), ("moving", MOVE)):
            if command is not None:
                assert screen.json("POST", "/api/command", command)[0] == 200
            took, in_frames, frames = received(driver, seconds)
            per_frame = in_frames / max(frames, 1)
            rows.append((what, took / seconds / 1000, frames / seconds, per_frame * 30 / 1000))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=60)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--pages", type=int, default=500)
    parser.add_argument("--page-runs", type=int, default=10, help="commands timed at the many pages")
    parser.add_argument("--before", default=BEFORE, help="the tree to compare the many pages with")
    parser.add_argument("--pages-only", action="store_true", help="only the many pages (no browser)")
    options = parser.parse_args()
    if options.pages:
        pages(options.pages, options.page_runs, options.before)
    if not options.pages_only:
        browser(options)


def pages(count: int, runs: int, before: str) -> None:
    here = str(Path(__file__).resolve().parent.parent)
    with tempfile.TemporaryDirectory() as name:
        now = many_pages(Path(name), count, runs, dict(os.environ, PYTHONPATH=here))
        with tree_of(before) as env:
            then = many_pages(Path(name), count, runs, env)
    print(f"bench_screen: {count} pages (WebSockets in one process), {runs} commands each, load {load()}")
    print("command (POST /api/command) -> its first frame at each page")
    for what, values in (("this tree", now), (f"the tree at {before}", then)):
        print(f"  {what:22s} p50 {p(values, 0.5):6.1f} ms  p95 {p(values, 0.95):6.1f} ms", end="")
        print(f"  max {max(values):6.1f} ms")
    print(f"  -> {p(then, 0.95) / p(now, 0.95):.1f}x faster (p95); goal: p95 <= 100 ms")


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def browser(options: argparse.Namespace) -> None:
    runs = options.runs
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        with running_screen(folder, "--no-idle") as screen, chromium(*TABLET) as driver:
            driver.set_script_timeout(600)
            open_page(driver, screen.url)
            pushed = driver.execute_async_script(COMMANDS, runs + 1)[1:]  # the first warms up
            driver.get("about:blank")  # the baseline's page: no WebSocket, only its polling
            driver.get(screen.url.split("?")[0] + "api/frame.jpg")  # same origin for its fetches
            polled = driver.execute_async_script(POLLING, runs + 1)[1:]
        sizes = {size: bandwidth(folder, size, options.seconds) for size in ("1024x600", "512x300")}
    window = f"{TABLET[0]}x{TABLET[1]}"
    print(f"bench_screen: {runs} runs, headless chromium in a {window} window, timed in the page")
    print("command (POST /api/command) -> first changed frame shown on the page")
    print(f"  p50 {p(pushed, 0.5):6.1f} ms  p95 {p(pushed, 0.95):6.1f} ms  max {max(pushed):6.1f} ms", end="")
    print("  (goal: p95 <= 100 ms)")
    print(f"  baseline: a page polling /api/frame.jpg at 30 a second: p50 {p(polled, 0.5):6.1f} ms", end="")
    print(f"  p95 {p(polled, 0.95):6.1f} ms  ->  {p(polled, 0.5) / p(pushed, 0.5):.1f}x faster (p50)")
    print(f"bandwidth: what the page received over its WebSocket, {options.seconds:.0f} s each")
    for size, rows in sizes.items():
        for what, kbs, fps, mjpeg in rows:
            print(
                f"  {size}  {what:22s} {kbs:8.1f} KB/s  {fps:5.1f} frames/s"
                f"   every frame at 30 fps: {mjpeg:7.1f} KB/s  ({100 * kbs / mjpeg:5.1f} % of it)"
            )


if __name__ == "__main__":
    main()
