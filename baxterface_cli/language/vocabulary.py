"""The words of the language that are not grammar: what each bare word means.

A bare word is looked up here first, then among the script's definitions.
Legacy underscore spellings sit beside the script's own words and build the
same nodes, which is what makes `human_follow_on` and `follow human` equal.
"""

from __future__ import annotations

from functools import partial
from typing import Any, Callable, Dict, Tuple

from ..core.face_constants import EMOTIONS, FollowTarget
from . import syntax_tree as n
from .statements import KINDS

BARE_WORDS: Dict[str, Callable[..., Any]] = {
    **{name: partial(n.Emotion, name) for name in EMOTIONS if " " not in name},
    "wake_up": partial(n.Emotion, "wake up"),
    **{kind.bare: kind.node for kind in KINDS.values() if kind.bare},  # `blink`, `nod`, `exit`
    "human_follow_on": partial(n.Follow, FollowTarget.HUMAN),
    "dynamic_human_follow_on": partial(n.Follow, FollowTarget.HUMAN, True),
    "left_arm_follow_on": partial(n.Follow, FollowTarget.LEFT_ARM),
    "right_arm_follow_on": partial(n.Follow, FollowTarget.RIGHT_ARM),
    "dynamic_left_arm_follow_on": partial(n.Follow, FollowTarget.LEFT_ARM, True),
    "dynamic_right_arm_follow_on": partial(n.Follow, FollowTarget.RIGHT_ARM, True),
    "face_follow_on": partial(n.Follow, FollowTarget.FACE),
    "dynamic_face_follow_on": partial(n.Follow, FollowTarget.FACE, True),
    "human_follow_off": partial(n.Follow, None),
    "face_follow_off": partial(n.Follow, None),
    "arm_follow_off": partial(n.Follow, None),
}

# The bare words that were commands of the old node (blink, nod and following a face are new).
LEGACY_WORDS = frozenset(BARE_WORDS) - {
    "blink",
    "nod",
    "face_follow_on",
    "dynamic_face_follow_on",
    "face_follow_off",
}

# Legacy commands with numbers: how many numbers each takes, and its usage.
LEGACY_USAGE: Dict[str, Tuple[Tuple[int, ...], str]] = {
    "look": ((2, 3), "look_X_Y or look_X_Y_SECONDS"),
    "dynamic_look": ((2, 3), "dynamic_look_X_Y or dynamic_look_X_Y_SECONDS"),
    "wobble": ((1,), "wobble_RADIANS"),
    "skin": ((1,), "skin_N with N from 0 to 5"),
}
