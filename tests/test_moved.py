"""Old import paths of modules that were split in two still give every name the old module had."""

from __future__ import annotations

import importlib
import sys
import warnings


def test_the_old_timeline_gives_the_timeline_and_the_compiler_with_a_warning():
    sys.modules.pop("baxterface_cli.timeline", None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        old = importlib.import_module("baxterface_cli.timeline")
    said = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
    assert said == [
        "baxterface_cli.timeline is now baxterface_cli.engine.timeline and baxterface_cli.engine.compiler;"
        " the old name goes in the next release"
    ]
    from baxterface_cli.engine import compiler, timeline
    from baxterface_cli.language.parser import parse

    # The timeline's own names come from engine.timeline, the compiling from engine.compiler ...
    assert old.Timeline is timeline.Timeline and old.state_record is timeline.state_record
    assert old.compile_script is compiler.compile_script
    # ... and together they still work as the old module did.
    compiled = old.compile_script(parse("look 40 0 in 1s"))
    assert isinstance(compiled, old.Timeline) and compiled.duration == 1.0


def test_a_name_the_old_timeline_never_had_is_an_attribute_error():
    import pytest

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        old = importlib.import_module("baxterface_cli.timeline")
    with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
        old.no_such_name  # noqa: B018


def test_the_effects_old_names_are_the_new_ones_with_a_warning():
    from baxterface_cli.engine import effects

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert effects.Follow is effects.SetFollowing and effects.Exit is effects.ShutDown
    said = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
    assert said == [
        "baxterface_cli.engine.effects.Follow is now SetFollowing; the old name goes in the next release",
        "baxterface_cli.engine.effects.Exit is now ShutDown; the old name goes in the next release",
    ]
