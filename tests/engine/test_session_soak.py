"""A short soak of the live session (bench/bench_reacting.py soak runs the hour): ten minutes of
random events on a fast clock lose no line of the log, and every handler keeps to its policy."""

from __future__ import annotations

import random
import threading
from collections import Counter

from log_soak import SCRIPT  # the soak bench's: every policy, a timer and a forever

from baxterface_cli import parse
from baxterface_cli.engine.live_session import MAX_LOG, LiveSession
from baxterface_cli.engine.session_handlers import MAX_QUEUE
from baxterface_cli.language import syntax_tree as n

EVENTS = {
    "line 1 'on face seen'": n.Event("face seen"),
    "line 2 'on person near'": n.Event("person near"),
    "line 3 'on person gone'": n.Event("person gone"),
    "line 4 'on button ok'": n.Event("button", "left ok"),
    "line 5 'on signal poke'": n.Event("signal", "poke"),
    "": n.Event("button", "left up"),  # for the main script's wait
}


def test_ten_minutes_of_random_events_lose_nothing_and_keep_every_policy():
    rng = random.Random(37)
    session = LiveSession(parse(SCRIPT, "soak.face"), seed=1, idle=True)
    before = set(threading.enumerate())  # others' threads may end meanwhile: only new ones count
    posted, logged_events, seen = Counter(), 0, 0
    now = 0.0
    while now < 600.0:
        now += 1 / 30
        if rng.random() < 0.1:
            label = rng.choice(sorted(EVENTS))
            session.post(EVENTS[label], now, "soak")
            posted[label] += 1
        session.tick(now)
        new = session.lines_since(seen)
        seen = session.logged
        logged_events += sum(1 for line in new if line.text.startswith("event "))
        assert len(session.log) <= MAX_LOG and len(session.pending) <= MAX_QUEUE * 2
    assert logged_events == sum(posted.values())  # every event in the log, none lost
    assert [t for t in threading.enumerate() if t not in before] == []  # the session starts none
    counts = session.counts()
    waiting = Counter(h.label for h, _ in session.pending)
    for label, events in posted.items():
        if label:  # each event ran its handler, waits its turn, or was dropped and counted
            c = counts[label]
            assert c["runs"] + waiting[label] + c["dropped"] == events, label
    assert counts["line 6 'on every 7s'"]["runs"] + counts["line 6 'on every 7s'"]["dropped"] == 600 // 7
