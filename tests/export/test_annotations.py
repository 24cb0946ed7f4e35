"""`render LOG.jsonl --out session.eaf` (or .TextGrid): ELAN's and Praat's tiers of a replayed
session (events, handlers, states, said, emotion), on the video's clock, read back with pympi."""

from __future__ import annotations

import json

import pytest

from conftest import ROOT, baxterface, needs

pytestmark = pytest.mark.usefixtures("engine")  # the greeter says hello: espeak-ng

# A greeter of its own, so that the example's growing changes none of the tiers here.
GREETER = """\
state asleep {
  sleep
  on button ok { go awake }
}
state awake {
  wake up
  on person near {
    happy
    one of { say "Hello there!" | say "Hi! Nice to see you." | say "Oh, hello!" }
    follow human
  }
  on face seen cooldown 10s { wink left }
}
go asleep
"""


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    """A node's log by hand: the greeter at 1 s, woken at 3 s, greeting at 5 s, ending at 12 s."""
    folder = tmp_path_factory.mktemp("annotations")
    records = [
        {"type": "start", "t": 0.0, "version": 1, "settings": {"end": "node", "seed": 1}},
        {"type": "script", "t": 1.0, "text": GREETER, "source": "greeter.face"},
        {"type": "event", "t": 3.0, "event": "button ok", "source": "/robot/navigators/x"},
        {"type": "event", "t": 5.0, "event": "person near", "source": "/robot/sonar"},
        {"type": "event", "t": 5.0, "event": "face seen", "source": "/cameras/head_camera/image"},
        {"type": "end", "t": 12.0},
    ]
    path = folder / "session.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in records), encoding="utf-8")
    return path


def test_an_elan_file_has_the_sessions_tiers_on_the_videos_clock(log):
    pympi = needs("pympi")
    out = log.parent / "session.eaf"
    run = baxterface("render", str(log), "--out", str(out))
    assert run.code == 0, run.err
    assert run.err.startswith(f"wrote {out} (ELAN: 2 events, 2 handlers, 2 states, 1 said, ")
    eaf = pympi.Eaf(str(out))
    assert sorted(eaf.get_tier_names()) == sorted(["events", "handlers", "states", "said", "emotion"])
    # The events 1 s before the log's, as the video starts with the first script; two at once, one.
    events = sorted(eaf.get_annotation_data_for_tier("events"))
    assert [(a, text) for a, _, text in events] == [(2000, "button ok"), (4000, "person near | face seen")]
    handlers = [text for _, _, text in sorted(eaf.get_annotation_data_for_tier("handlers"))]
    assert handlers[:2] == ["line 3 'on button ok'", "line 7 'on person near'"]
    states = sorted(eaf.get_annotation_data_for_tier("states"))
    assert [text for _, _, text in states] == ["asleep", "awake"] and states[1][0] == 2000
    (said,) = eaf.get_annotation_data_for_tier("said")
    assert said[2] in ("Hello there!", "Hi! Nice to see you.", "Oh, hello!") and said[0] > 4000
    emotions = [text for _, _, text in sorted(eaf.get_annotation_data_for_tier("emotion"))]
    assert emotions[0] == "sleep" and "happy" in emotions


def test_a_praat_textgrid_has_the_same_tiers(log):
    pympi = needs("pympi")
    out = log.parent / "session.TextGrid"
    run = baxterface("render", str(log), "--out", str(out))
    assert run.code == 0, run.err
    grid = pympi.Praat.TextGrid(str(out))
    assert [t.name for t in grid.get_tiers()] == ["events", "handlers", "states", "said", "emotion"]
    assert grid.xmax == pytest.approx(11.0)
    events = [(a, text) for a, _, text in grid.get_tier("events").get_intervals() if text]
    assert events == [(pytest.approx(2.0), "button ok"), (pytest.approx(4.0), "person near | face seen")]


def test_without_pympi_it_is_one_line_naming_the_extra(log, tmp_path):
    import os

    hidden = tmp_path / "hidden"
    (hidden / "pympi").mkdir(parents=True)
    (hidden / "pympi" / "__init__.py").write_text("raise ImportError('hidden')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(hidden), str(ROOT)]))
    run = baxterface("render", str(log), "--out", str(tmp_path / "s.eaf"), env=env)
    assert run.code == 1
    assert run.err == (
        "baxterface render: an annotation file (.eaf, .TextGrid) needs the 'pympi' module: "
        "pip install 'baxterface[annotate]'\n"
    )
    assert not (tmp_path / "s.eaf").exists()


def test_an_annotation_file_is_made_of_a_log_only(tmp_path):
    run = baxterface("render", "-e", "happy", "--out", str(tmp_path / "s.eaf"))
    assert run.code == 2
    said = f"an ELAN file is made of a session's log: render LOG.jsonl --out {tmp_path / 's.eaf'}"
    assert run.err == f"baxterface render: {said}\n"
