"""A session of random events on a fast clock, kept in its log file as the live ends keep it (the
intake's calls: each event recorded and posted, the session's lines followed, a tick each frame),
for tests/engine/test_session_log_soak.py (ten minutes) and bench/bench_log_soak.py (an hour)."""

from __future__ import annotations

import random
import tracemalloc
from collections import Counter
from typing import Any, Dict, List

from baxterface_cli import parse
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_log_file import SessionLogFile
from baxterface_cli.language import syntax_tree as n
from waiting import eventually

SCRIPT = """on face seen cooldown 2s { happy }
on person near queue { look left in 0.2s }
on person gone interrupt { sad }
on button ok { blink }
on signal poke queue { wink left }
on every 7s { nod }
forever { look up in 0.5s; look down in 0.5s; wait until button up timeout 3s }"""
EVENTS = (
    n.Event("face seen"),
    n.Event("person near"),
    n.Event("person gone"),
    n.Event("button", "left ok"),
    n.Event("signal", "poke"),
    n.Event("button", "left up"),  # for the main script's wait
)
TICK = 0.25  # seconds between the frames asked for: what falls due between them is done at its own time


def soak(path: str, seconds: float, sample: float, measure: bool = False) -> Dict[str, Any]:
    """`seconds` of the session, an event a second on average at random, logged to `path`: the
    session, the events posted, and (`measure`) the memory every `sample` seconds (tracemalloc's,
    once what was handed to the log's writer is written) with the lines the session's log kept."""
    rng = random.Random(47)
    record = SessionLogFile(path, 0.0, {"end": "soak", "seed": 5})
    session = LiveSession(None, seed=5, idle=False, keep_up=True)
    record.watch(session.face)
    record.script(0.0, SCRIPT, "soak.face")
    session.run(parse(SCRIPT, "soak.face"), 0.0)
    # On a millisecond grid, as a log's times (to 0.1 ms) keep them exactly.
    ms = int(seconds * 1000)
    arrivals = sorted({rng.randrange(1, ms) / 1000 for _ in range(int(seconds))})
    posted: Counter = Counter()
    memory: List[int] = []
    kept: List[int] = []  # the lines the session's own log holds at each sample (MAX_LOG at most)
    if measure:
        tracemalloc.start()
    try:
        now, k = 0.0, 0
        while now < seconds:
            now = round(now + TICK, 3)
            while k < len(arrivals) and arrivals[k] <= now:
                event = rng.choice(EVENTS)
                record.event(arrivals[k], event, "soak")
                session.post(event, arrivals[k], "soak")
                record.follow(session)
                posted[event] += 1
                k += 1
            session.tick(now)
            record.follow(session)
            if now % sample == 0:
                # The writer keeps up with a live face, not always with one on a fast clock: what
                # was handed over is written before going on (nothing skipped, memory comparable).
                eventually(lambda: record.waiting() == 0)
                if measure:
                    memory.append(tracemalloc.get_traced_memory()[0])
                    kept.append(len(session.log))
    finally:
        if measure:
            tracemalloc.stop()
    record.close(seconds)
    return {"session": session, "events": len(arrivals), "posted": posted, "memory": memory, "kept": kept}
