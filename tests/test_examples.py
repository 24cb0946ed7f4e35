"""Every shipped example checks cleanly; the show is the length it promises."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from baxterface_cli import parse_file
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.checker import measure, walk
from conftest import baxterface

pytestmark = pytest.mark.one_python  # what the examples show is the same under every Python

EXAMPLES = sorted((Path(__file__).resolve().parent.parent / "scripts_examples").glob("*.face"))


def test_there_are_examples():
    assert {p.name for p in EXAMPLES} >= {"show.face", "hello.face", "legacy.face"}


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_checks_without_errors_or_warnings(path):
    script = parse_file(path)
    assert script.warnings == ()


def test_show_is_15_to_30_seconds_and_uses_most_of_the_language():
    script = parse_file(EXAMPLES[[p.name for p in EXAMPLES].index("show.face")])
    called = {name: measure(d.body, {}) for name, d in script.definitions.items()}
    seconds, _ = measure(script.body, called)
    assert 15 <= seconds <= 30, seconds
    kinds = {type(s) for s in walk(script.body)}
    wanted = {n.Emotion, n.Look, n.Blink, n.Wait, n.Wobble, n.Nod, n.Skin, n.Mouth, n.Brows, n.Eyelids}
    wanted |= {n.Repeat, n.Together, n.Define, n.Call}
    assert wanted <= kinds, wanted - kinds
    easings = {s.timing.easing for s in walk(script.body) if isinstance(s, n.Look)}
    assert {"ease-in", "ease-out", "ease-in-out", "linear"} <= easings


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_every_example_explains_and_renders_as_a_user_would(path, tmp_path):
    events = path.with_suffix(".events")  # a script that reacts ships the events its README shows
    given = ["--events", str(events)] if events.exists() else []
    explained = baxterface("explain", str(path), *given)
    assert explained.code == 0 and explained.err == "", explained.err
    assert explained.out.startswith(f"{path}: ")
    rendered = baxterface("render", str(path), *given, "--out", str(tmp_path / "last.png"), "--quiet")
    assert rendered.code == 0 and (tmp_path / "last.png").stat().st_size > 0, rendered.err


def test_the_greeter_reacts_to_each_of_its_events():
    path = EXAMPLES[[p.name for p in EXAMPLES].index("greeter.face")]
    explained = baxterface("explain", str(path), "--events", str(path.with_suffix(".events")))
    assert explained.code == 0, explained.err
    for handler in ("on person near", "on face seen", 'on word "hello"', "on touch", "on person gone"):
        assert f"'{handler}' runs" in explained.out, handler
    assert "'on idle 30s' runs" in explained.out  # nobody came by for half a minute: bored, asleep
    assert "robot follow human" in explained.out and "robot follow off" in explained.out
    assert "state asleep entered" in explained.out.split("'on idle 30s' runs")[1]
    # Asleep, only the button matters: someone walking past before it wakes is not greeted.
    asleep = explained.out.split("state awake entered")[0]
    assert "event person near" in asleep and "'on person near' runs" not in asleep


def test_the_conversation_hears_its_visitor_answer_and_renders_both_voices(tmp_path):
    # The face asks in a natural voice; the visitor's recording (another natural voice) answers
    # after the question; its words are heard, the answer routed, and the video has both voices.
    path = EXAMPLES[[p.name for p in EXAMPLES].index("conversation.face")]
    heard = ["--hear", f"{path.with_name('visitor.wav')}@5s"]
    explained = baxterface("explain", str(path), *heard)
    assert explained.code == 0, explained.err
    assert "answered" in explained.out and "nothing heard" not in explained.out, explained.out
    video = tmp_path / "conversation.mp4"
    rendered = baxterface("render", str(path), *heard, "--out", str(video), "--size", "256x150", "--quiet")
    assert rendered.code == 0, rendered.err
    sound = sound_of(video)
    rate = 16000
    loud = lambda a, b: float(np.sqrt(np.mean(sound[int(a * rate) : int(b * rate)] ** 2)))  # noqa: E731
    assert loud(4.6, 4.9) < 0.01  # between the question and the answer: nobody speaks
    assert loud(5.1, 5.8) > 0.03  # the visitor
    assert loud(6.3, 8.5) > 0.03  # the face's answer to them


def sound_of(video: Path):
    """The video's sound, mono at 16 kHz, as floats (PyAV reads it)."""
    import av

    with av.open(str(video)) as container:
        resampler = av.AudioResampler(format="flt", layout="mono", rate=16000)
        chunks = [
            frame.to_ndarray().reshape(-1)
            for packet in container.demux(audio=0)
            for decoded in packet.decode()
            for frame in resampler.resample(decoded)
        ]
    return np.concatenate(chunks)
