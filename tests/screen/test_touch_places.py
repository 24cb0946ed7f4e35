"""Where a tap lands is found from the face as drawn at that moment, in the renderer's layers."""

from __future__ import annotations

import pytest

from baxterface_cli.drawing.theme import resolve
from baxterface_cli.drawing.touch_places import touched_place
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.language.parser import parse


@pytest.fixture(scope="module")
def layers():
    return resolve(None).layers((1024, 600))


def at_end(text):
    timeline = compile_script(parse(text), seed=1)
    return timeline.sample(timeline.duration)


def test_each_place_is_where_its_part_is_drawn(layers):
    face = at_end("")
    places = {touched_place(layers, face, x / 40, y / 30) for x in range(40) for y in range(30)}
    assert places == {"", "left eye", "right eye", "mouth", "brows"}
    assert touched_place(layers, face, 0.7, 0.4) == "left eye"  # the robot's left: the screen's right
    assert touched_place(layers, face, 0.3, 0.4) == "right eye"
    assert touched_place(layers, face, 0.02, 0.97) == ""
    assert touched_place(layers, face, 5.0, float("nan")) == ""


def test_the_mouth_is_found_where_the_expression_puts_it(layers):
    """An open mouth reaches lower than a closed one: a tap there is the mouth only while it is open."""
    closed, opened = at_end(""), at_end("mouth open 1")
    below = [
        y / 600
        for y in range(430, 600)
        if touched_place(layers, opened, 0.5, y / 600) == "mouth"
        and touched_place(layers, closed, 0.5, y / 600) != "mouth"
    ]
    assert below, "an open mouth should reach where a closed one does not"
