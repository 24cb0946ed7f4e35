"""The face that reacts, measured (issue 37): the face node's event latency and storm, and a soak.

    PYTHON bench/bench_reacting.py latency 1|2 [COUNT]   event to the first changed frame
    PYTHON bench/bench_reacting.py storm 1|2 [RATE SECONDS]   events at RATE a second at the node
    PYTHON bench/bench_reacting.py soak [HOURS]   random events against the session alone
    PYTHON bench/bench_reacting.py word [COUNT [LISTENER]]   ROS 1: a word's end to the first changed frame

`latency` and `storm` start the face node (`baxterface node --ros N`, idle off) and talk to it
through a Link of their own, as any ROS program would: run them with the Python that has that
ROS (.venv-ros for 1, with ROS_MASTER_URI set or a roscore of the bench's own; .venv for 2, with
ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST set). `latency` sends handlers on
display_chatter, then presses a navigator button (a real baxter_core_msgs/NavigatorState on the
left navigator's topic; a ROS 2 without baxter_core_msgs has no navigators: `signal up` and
`signal down` on display_chatter instead) and times each press to the first frame received on
/robot/xdisplay after it; beside it, in the same run, a plain command on display_chatter (the
baseline the node had before it reacted). `storm` raises `signal` events on display_chatter at
RATE a second (1,000) for SECONDS (10) and reports the longest gap between frames received,
each handler's runs and drops (read from ~state), and the node's resident memory before, after,
and after a second storm. `soak` runs a LiveSession on a fast clock (no threads, no waiting)
for HOURS (1) of random events, and reports memory (tracemalloc) and threads each simulated ten
minutes and whether the log lost a line. `word` starts the node COUNT (20) times for each
LISTENER named (both by default: Moonshine's, the [hear] extra's, and then the spotter's,
BAXTERFACE_LISTENER=spotter),
with `_listen:=` "look at that robot" said by piper's joe and hibari's heart in turn (recordings
in tests/ros/visitor/, after 1 to 1.3 s of silence, so that the word ends at another point of
the 50 ms blocks each run), and `on word "robot" { skin 3 }` sent to it once both skins were
shown: the word's end is the recording's last sample above 5 % of its loudest, after the wall
time the node logs for the recording's start, and the frame's time is when it reached this
process (wall time too); p50 and p95 of each listener, its node's resident memory once it heard
and how late its ears logged the word, each run; beside them, in the same run, plain commands on
display_chatter (the baseline). Each node's log is kept beside its recording in the run's folder.
Prints JSON.
"""

from __future__ import annotations

import json
import os
import random
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import tracemalloc
from pathlib import Path

from node_latency import Frames  # the frames a subscriber receives, with their times

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "tests" / "support")]

HANDLERS = (
    "on button up { skin 3 }\non button down { skin 1 }\non signal up { skin 3 }\non signal down { skin 1 }"
)
STORM_SCRIPT = (
    "on signal poke { look left in 0.1s; look right in 0.1s }\n"
    "on signal bump queue { blink }\n"
    "default\n"  # the node starts asleep: a blink on closed lids shows nothing
    "forever { look up in 0.2s; look down in 0.2s }"
)


class State:
    def __init__(self, link) -> None:
        self.last = {}
        self.sub = link.subscribe("/baxter_face/state", "std_msgs/String", self._got, latched=True)

    def _got(self, msg) -> None:
        self.last = json.loads(msg.data)


def node_args(version):
    if version == 1:
        return ["_idle:=false", "_audio:=none"]
    return ["--ros-args", "-p", "idle:=false", "-p", "audio:=none"]


def rss_kib(pid) -> int:
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS"))


def until(check, timeout, what):
    deadline = time.monotonic() + timeout
    while not check():
        if time.monotonic() > deadline:
            raise SystemExit(f"bench_reacting: {what} did not happen in {timeout:g} s")
        time.sleep(0.05)


def with_node(version, body):
    from baxterface_cli.ros.connect import open_link

    core = None
    if version == 1 and "ROS_MASTER_URI" not in os.environ:
        from ros_master import start_roscore

        core, env = start_roscore()
        os.environ.update(env)
    link = open_link(version, "bench_reacting", anonymous=True)
    frames, state = Frames(link), State(link)
    argv = [sys.executable, "-m", "baxterface_cli", "node", "--ros", str(version), *node_args(version)]
    proc = subprocess.Popen(argv, cwd=str(ROOT), stdout=subprocess.DEVNULL)
    chatter = link.publisher("display_chatter", "std_msgs/String", queue=1000)
    try:
        up = lambda: chatter.listeners() > 0 and frames.sub.publishers() > 0 and state.last  # noqa: E731
        until(up, 60, "connecting")
        return body(link, proc, frames, state, chatter)
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)
        link.close()
        if core is not None:
            core.send_signal(signal.SIGINT)
            core.wait(timeout=30)


def timed(frames, send, count, gap=0.15):
    """Milliseconds from each `send(i)` (from the time it returns, or from its start) to the next frame."""
    out = []
    for i in range(count):
        frames.event.clear()
        before = time.monotonic()
        sent = send(i) or before
        if frames.event.wait(2.0):
            out.append((frames.times[-1] - sent) * 1000)
        time.sleep(gap)
    return out


def latency(version, count):
    def body(link, proc, frames, state, chatter):
        names = ["0", "1", "2"]
        nav = None
        if link.has("baxter_core_msgs/NavigatorState"):  # else (a ROS 2 without Baxter's messages): signals
            nav = link.publisher("/robot/navigators/left_navigator/state", "baxter_core_msgs/NavigatorState")
            until(lambda: nav.listeners() > 0, 60, "the node hearing the navigator")
        chatter.publish(data=HANDLERS)
        until(lambda: len(state.last.get("handlers", {})) == 4, 30, "the handlers installing")

        def press(i):
            up = i % 2 == 0
            if nav is None:
                sent = time.monotonic()
                chatter.publish(data="signal up" if up else "signal down")
                return sent
            nav.publish(button_names=names, buttons=[False, False, False], wheel=0)
            time.sleep(0.02)  # a release, then the press timed
            frames.event.clear()
            sent = time.monotonic()
            nav.publish(button_names=names, buttons=[False, up, not up], wheel=0)
            return sent

        def command(i):
            chatter.publish(data="skin_3" if i % 2 == 0 else "skin_1")

        plain = timed(frames, command, count)
        events = timed(frames, press, count)
        if nav is not None:
            nav.close()
        return {"command_ms": plain, "event_ms": events, "event": "signal" if nav is None else "button"}

    got = with_node(version, body)
    return {
        "version": version,
        "load": os.getloadavg(),
        "command_p50_ms": statistics.median(got["command_ms"]),
        "event_p50_ms": statistics.median(got["event_ms"]),
        "event_p90_ms": sorted(got["event_ms"])[int(0.9 * len(got["event_ms"]))],
        "answered": f"{len(got['event_ms'])}/{count}",
        "event": got["event"],
    }


def storm(version, rate, seconds):
    def body(link, proc, frames, state, chatter):
        chatter.publish(data=STORM_SCRIPT)
        until(lambda: len(state.last.get("handlers", {})) == 2, 30, "the handlers installing")
        time.sleep(1.0)
        out = {"rss_kib_before": rss_kib(proc.pid)}
        for round_ in (1, 2):
            start = len(frames.times)
            began = time.monotonic()
            sent = 0
            while sent < rate * seconds:
                due = began + sent / rate
                if due > time.monotonic():
                    time.sleep(due - time.monotonic())
                chatter.publish(data="signal poke" if sent % 2 else "signal bump")
                sent += 1
            sent_in = time.monotonic() - began
            time.sleep(8.0)  # the queued blinks (32 at most) play out
            times = frames.times[start:]
            gaps = [b - a for a, b in zip(times, times[1:])]
            counts = state.last.get("handlers", {})
            out[f"round_{round_}"] = {
                "sent": sent,
                "sent_in_s": round(sent_in, 2),
                "frames": len(times),
                "longest_frame_gap_ms": round(max(gaps) * 1000, 1) if gaps else None,
                "handlers": counts,
                "rss_kib_after": rss_kib(proc.pid),
            }
        return out

    got = with_node(version, body)
    return {"version": version, "load": os.getloadavg(), "rate": rate, "seconds": seconds, **got}


def soak(hours):
    """Random events for `hours` of the session's clock, as fast as it goes (the clock is the
    bench's: nothing sleeps)."""
    from baxterface_cli import parse
    from baxterface_cli.engine.live_session import LiveSession
    from baxterface_cli.language import syntax_tree as n

    script = parse(
        "on face seen cooldown 2s { happy }\non face lost { default }\n"
        "on person near queue { look left in 0.2s }\non person gone interrupt { sad }\n"
        "on button ok { blink }\non signal poke queue { wink left }\non every 7s { nod }\n"
        "on idle 20s { sleep }\n"
        "forever { look up in 0.5s; look down in 0.5s; wait until button up timeout 3s }",
        "soak.face",
    )
    kinds = [
        n.Event("face seen"), n.Event("face lost"), n.Event("person near"), n.Event("person gone"),
        n.Event("button", "left ok"), n.Event("button", "left up"), n.Event("signal", "poke"),
    ]  # fmt: skip
    rng = random.Random(37)
    session = LiveSession(script, seed=1, idle=True)
    tracemalloc.start()
    samples, posted, event_lines, seen = [], 0, 0, 0
    now, end, step = 0.0, hours * 3600.0, 1.0 / 30
    next_sample = 0.0
    began = time.monotonic()
    while now < end:
        now += step
        if rng.random() < 0.05:  # 1.5 events a second on average
            session.post(rng.choice(kinds), now, "soak")
            posted += 1
        session.tick(now)
        new = session.lines_since(seen)
        seen = session.logged
        event_lines += sum(1 for line in new if line.text.startswith("event "))
        if now >= next_sample:
            current, _ = tracemalloc.get_traced_memory()
            threads = threading.active_count()
            samples.append({"at_min": round(now / 60), "kib": current // 1024, "threads": threads})
            next_sample += 600.0
    counts = session.counts()
    return {
        "simulated_hours": hours,
        "wall_s": round(time.monotonic() - began, 1),
        "load": os.getloadavg(),
        "posted": posted,
        "event_lines_logged": event_lines,
        "nothing_lost": event_lines == posted,
        "samples": samples,
        "handlers": counts,
    }


HEARD_AFTER = re.compile(r'heard word "robot", (\d+\.\d+) s after it ended')
STARTS_PLAYING = re.compile(r"listening: listening to .* from (\d+\.\d+) \(seconds since the epoch\)")


class WallFrames(Frames):
    """Frames received, with their wall times (the node's log has wall times)."""

    def _got(self, msg) -> None:
        self.times.append(time.time())
        self.event.set()


def word(count, listeners=("moonshine", "spotter")):
    """Each listener (Moonshine, the [hear] extra's; the spotter, BAXTERFACE_LISTENER=spotter) hears
    "look at that robot" in each natural voice `count` times, one fresh node a time."""
    from baxterface_cli.ros.connect import open_link
    from visitor_voices import placed

    folder = Path(tempfile.mkdtemp(prefix="bench-word-"))
    rng = random.Random(46)
    core = None
    if "ROS_MASTER_URI" not in os.environ:
        from ros_master import start_roscore

        core, env = start_roscore()
        os.environ.update(env)
    link = open_link(1, "bench_reacting", anonymous=True)
    frames, state = WallFrames(link), State(link)
    chatter = link.publisher("display_chatter", "std_msgs/String", queue=100)
    out = {"load_before": os.getloadavg()}
    plain = []
    try:
        # One round first, not counted: what the node draws is kept in the user's cache after its
        # first start (the theme fitted to its screen, the skins' and eyes' palettes: array_cache.py),
        # so the runs measure a node started as on any later day, not the first start after an
        # install or an upgrade, which makes them (its frame a second late, 70 to 130 MB more).
        warm = folder / "warm.wav"
        ended = placed("heart", "look at that robot", 1.0, warm)
        _word_round(warm, ended, frames, state, chatter, listeners[0])
        for listener in listeners:
            words, missed, rss, logged = [], 0, [], []
            for i in range(count):
                voice = ("joe", "heart")[i % 2]
                wav = folder / f"{voice}-{i}.wav"  # the word ends at a new point of the blocks each run
                word_end = placed(voice, "look at that robot", 1.0 + 0.3 * rng.random(), wav)
                round_ = _word_round(wav, word_end, frames, state, chatter, listener)
                heard_after, baseline, kib, told = round_
                rss.append(kib)
                logged.append(told)
                if heard_after is None:
                    missed += 1
                else:
                    words.append(heard_after)
                plain += baseline
            ranked = sorted(words)
            out[listener] = {
                "heard": f"{len(words)}/{count}",
                "word_to_frame_ms": [round(x, 1) for x in words],
                "node_logged_heard_after_s": logged,
                "p50_ms": round(statistics.median(ranked), 1) if ranked else None,
                "p95_ms": round(ranked[min(len(ranked) - 1, int(0.95 * len(ranked)))], 1) if ranked else None,
                "node_rss_mib_after_hearing": [round(kib / 1024) for kib in rss],
            }
    finally:
        link.close()
        if core is not None:
            core.send_signal(signal.SIGINT)
            core.wait(timeout=30)
    out["plain_command_to_frame_p50_ms"] = round(statistics.median(plain), 1)
    out["load_after"] = os.getloadavg()
    return out


def _word_round(wav, word_end, frames, state, chatter, listener):
    """One node hearing the recording: ms from the word's end to its frame (None: not heard in 10
    s), plain commands', the node's resident memory (KiB) after them, and how late its ears logged
    the word (seconds after it ended, by the listener's clock; None: not logged)."""
    argv = [sys.executable, "-m", "baxterface_cli", "node", *node_args(1), f"_listen:={wav}"]
    env = dict(os.environ, BAXTERFACE_LISTENER=listener)
    proc = subprocess.Popen(argv, cwd=str(ROOT), stdout=subprocess.PIPE, text=True, env=env)
    lines = []
    threading.Thread(target=lambda: lines.extend(proc.stdout), daemon=True).start()
    try:
        state.last = {}
        until(lambda: chatter.listeners() > 0 and frames.sub.publishers() > 0 and state.last, 60, "up")
        # Warmed up as the other latencies are: each skin drawn once, the renderer's preparing done.
        for command in ("skin_3", "skin_1"):
            chatter.publish(data=command)
            time.sleep(1.0)
        chatter.publish(data='on word "robot" { skin 3 }')

        def playing():
            return next((float(m.group(1)) for m in map(STARTS_PLAYING.search, lines) if m), None)

        until(lambda: playing() is not None, 60, "the recording playing")
        ended = playing() + word_end
        deadline = time.time() + max(0.0, ended - time.time()) + 10.0
        while not any(t > ended - 0.3 for t in frames.times) and time.time() < deadline:
            time.sleep(0.05)
        after = [t for t in frames.times if t > ended - 0.3]
        heard_after = (after[0] - ended) * 1000 if after else None

        def command(i):  # timed from its wall time, as the frames are
            sent = time.time()
            chatter.publish(data=["skin_1", "skin_3"][i % 2])
            return sent

        told = next((float(m.group(1)) for m in map(HEARD_AFTER.search, lines) if m), None)
        return heard_after, timed(frames, command, 6), rss_kib(proc.pid), told
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)
        wav.with_suffix(f".{listener}.log").write_text("".join(lines))  # the node's log, kept beside


def main() -> None:
    what = sys.argv[1] if len(sys.argv) > 1 else "soak"
    if what == "latency":
        out = latency(int(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else 100)
    elif what == "word":
        listeners = sys.argv[3:] or ["moonshine", "spotter"]
        out = word(int(sys.argv[2]) if len(sys.argv) > 2 else 20, listeners)
    elif what == "storm":
        rate = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
        out = storm(int(sys.argv[2]), rate, float(sys.argv[4]) if len(sys.argv) > 4 else 10.0)
    else:
        out = soak(float(sys.argv[2]) if len(sys.argv) > 2 else 1.0)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
