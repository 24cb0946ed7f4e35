"""The greeter's `ask` at the ROS 1 face node, answered by a visitor's recording in a natural voice
(piper's joe, hibari's heart) played as its microphone: each answer routed right, end to end.
bench/bench_conversation.py runs it 20 times over (tests/support/greeter_at_node.py)."""

from __future__ import annotations

import pytest

from baxterface_cli.speech import listening
from greeter_at_node import converse

pytestmark = pytest.mark.ros


@pytest.mark.parametrize(
    "voice, text", [("joe", "sure"), ("heart", "no"), ("joe", "what was that")], ids=lambda v: v
)
def test_the_greeter_takes_the_answer_a_visitor_says(roscore, tmp_path, voice, text):
    if listening.default_method() != listening.MOONSHINE:
        pytest.skip("the [hear] extra is not installed: the word spotter hears no whole utterance")
    conversation = converse(roscore, tmp_path, voice, text)
    assert conversation.routed(text), conversation
