"""The face's constants: emotions, parts, directions, units, limits, as data.

Everything that names or times something lives here, so the parser, the
checker and (later) the compiler read one table instead of growing if-chains.
Numbers come from the original node (see docs/language.md).
"""

from __future__ import annotations

import math
from enum import Enum
from typing import Dict, NamedTuple, Optional, Tuple

# Original index order: the legacy `skin_<n>` command and stable names.
MOUTHS: Tuple[str, ...] = (
    "angry",
    "bored",
    "confused",
    "sad",
    "teeth",
    "smile",
    "smile-open",
)
BROWS: Tuple[str, ...] = ("normal", "raised", "skeptical", "angry", "worried")

# Mouth shapes for speech (visemes). While the face speaks, its mouth is one of
# these, or "rest": the emotion's own mouth. Each is drawn as the mouth layer
# "speak-<shape>"; a theme without that layer shows the existing mouth given here.
VISEMES: Dict[str, str] = {
    "closed": "bored",  # p, b, m: lips pressed together
    "slight": "smile",  # most consonants, unstressed vowels: lips a little apart
    "open": "smile-open",  # a as in "father", "cat"
    "wide": "teeth",  # e and i: lips spread, teeth showing
    "round": "smile-open",  # o, u, w: lips rounded
    "fv": "teeth",  # f, v: upper teeth on the lower lip
    "lth": "smile-open",  # l and th: tongue at the teeth
}
REST = "rest"


def viseme_mouth(shape: str) -> str:
    """The mouth layer that draws a speech shape."""
    return f"speak-{shape}"


SKINS = range(6)  # 0..4 pale yellow to red, 5 sleepy with a "Zzz"


class EmotionSpec(NamedTuple):
    """One row of the emotion table: the parts an emotion may pick from."""

    skin: int
    mouths: Tuple[str, ...]
    brows: Tuple[str, ...]
    eyelids: float  # openness the lids move to: 1 open .. 0 closed
    lid_seconds: float  # the lids move first, over this time

    @property
    def variants(self) -> Tuple[Tuple[str, str], ...]:
        """The (mouth, brows) pairs the emotion picks from, in table order."""
        return tuple((m, b) for m in self.mouths for b in self.brows)


EMOTIONS: Dict[str, EmotionSpec] = {
    "default": EmotionSpec(2, ("smile",), ("normal",), 1.0, 0.3),
    "happy": EmotionSpec(2, ("teeth", "smile-open"), ("normal", "raised"), 1.0, 0.3),
    "angry": EmotionSpec(4, ("angry", "sad"), ("skeptical", "angry"), 1.0, 0.3),
    "confused": EmotionSpec(3, ("confused",), ("normal", "raised"), 1.0, 0.3),
    "sad": EmotionSpec(1, ("bored", "sad"), ("worried",), 1.0, 0.3),
    "panic": EmotionSpec(0, ("confused",), ("raised",), 1.0, 0.3),
    # The original's half-closed lid sat 150 of its 330 pixels above closed.
    "bored": EmotionSpec(2, ("bored",), ("normal", "skeptical", "angry"), 150 / 330, 0.3),
    "crafty": EmotionSpec(3, ("teeth", "smile-open"), ("skeptical", "angry"), 1.0, 0.3),
    "sleep": EmotionSpec(5, ("bored",), ("raised",), 0.0, 0.6),
    "wake up": EmotionSpec(3, ("smile",), ("normal",), 1.0, 0.8),
}

# The variant (an index into EmotionSpec.variants) an intensity, a blend, a morph or a mood
# shows of each emotion unless the script names one: the one that reads most as the emotion
# (`sad in 1.5s` ends in a frown whatever the seed). A bare emotion picks at random, as ever.
USUAL_VARIANT: Dict[str, int] = {name: 0 for name in EMOTIONS}
USUAL_VARIANT.update({"angry": 1, "sad": 1})  # (angry mouth, angry brows); (sad mouth, worried)

# Named look directions, in eye coordinates at 1024x600 (x positive = the
# robot's left = the viewer's right; y positive = down). "left" is the old
# voice command's `dynamic_look_65_0`; the others keep the same proportion of
# the eye ellipse.
DIRECTIONS: Dict[str, Tuple[float, float]] = {
    "left": (65.0, 0.0),
    "right": (-65.0, 0.0),
    "up": (0.0, -97.5),
    "down": (0.0, 97.5),
    "center": (0.0, 0.0),
    "centre": (0.0, 0.0),
    "ahead": (0.0, 0.0),
    "up-left": (46.0, -69.0),
    "up-right": (-46.0, -69.0),
    "down-left": (46.0, 69.0),
    "down-right": (-46.0, 69.0),
}

# Eye ellipse at 1024x600: semi-axes in pixels.
EYE_RADIUS_X = 80.0
EYE_RADIUS_Y = 120.0
HEAD_PAN_LIMIT = 1.5  # radians; wobble clamps to +-this
# A head pan's speed ratio is its radians per second over this, within the
# bounds below: the mapping the face node has always used.
HEAD_TOP_SPEED = 1.0  # radians a second at speed ratio 1
HEAD_SPEED_RATIO = (0.05, 1.0)


class DefaultDurations(NamedTuple):
    """Durations, in seconds, of moves a script does not time itself."""

    look: float = 0.5
    wobble: float = 0.5
    eyelids: float = 0.3
    blink_close: float = 0.3
    blink_open: float = 0.2
    nod: float = 1.0
    wink_close: float = 0.15
    wink_hold: float = 0.25
    wink_open: float = 0.2
    mood: float = 1.0
    adjust: float = 0.3  # a control of the expression: `mouth curve 0.5`


TIMING = DefaultDurations()

# Units a number may carry, by what the number means. The empty unit is the
# legacy one (seconds, radians, pixels).
UNITS: Dict[str, Dict[str, float]] = {
    "seconds": {"": 1.0, "s": 1.0, "ms": 0.001},
    "radians": {"": 1.0, "rad": 1.0, "deg": math.pi / 180.0},
    "pixels": {"": 1.0, "px": 1.0},
    "openness": {"": 1.0, "%": 0.01},
    "count": {"": 1.0},
    "rate": {"": 1.0, "wpm": 1.0},  # words a minute
    "index": {"": 1.0},
}


class Limits(NamedTuple):
    """Bounds that keep any script cheap to check, compile and play."""

    max_bytes: int = 256 * 1024  # a script's text
    # Words, numbers, separators and comments, counted before parsing: what
    # parsing costs grows with them, and this keeps any text under a second.
    max_pieces: int = 60_000
    max_depth: int = 32  # nested { } blocks, as written
    # Blocks and calls nested through definitions, as compiling recurses: at
    # about four Python frames a level, 64 stays under a third of Python's
    # default recursion limit of 1000.
    max_nesting: int = 64
    max_repeat: int = 10_000  # one repeat's count
    max_seconds: float = 3600.0  # a script's total length
    max_steps: int = 100_000  # statements once repeats and definitions unroll
    # Steps a recorded run of a script that reacts takes (render, explain, the studio): each keeps
    # its timeline, about 11 KB, and a `forever` of 1 ms rounds would take a million an hour.
    max_run_steps: int = 50_000
    # A round of a `forever` lasts this at least (a frame at 50 per second): a shorter one waits out
    # the rest, so no loop can take more rounds than a screen shows frames.
    least_round: float = 0.02
    # Handlers one face keeps installed, and how many of them may run by the clock (`every`): each
    # event looks at its kind's, and each `every` dispatches up to ten times a second.
    max_handlers: int = 256
    max_every: int = 16
    # How far a live face may fall behind its clock, doing steps that were due, before the run doing
    # them is stopped: its steps are too short for this machine to keep time.
    max_lag: float = 1.0
    max_say: int = 1000  # characters one `say` speaks: about a minute at the default rate
    max_recorded_text: int = 10_000  # the words of one recording (`say file ... text`): ten minutes' worth
    # Hearing words (`on word`, `wait until word`; docs/speech.md): each second of sound heard costs
    # work for every phrase, and for every phone of every way the dictionary spells it.
    max_phrases: int = 32  # distinct phrases a script listens for
    max_phones: int = 1000  # the phones of all the phrases listened for at once, every spelling counted
    # `--hear FILE`: those phones times the recording's seconds (200 phones, about 20 short
    # phrases, over ten minutes), about 20 s of the phrases' own work over the recogniser's.
    max_phone_seconds: int = 120_000
    max_shown: int = 50  # diagnostics kept and printed; the rest are only counted


LIMITS = Limits()


class FollowTarget(str, Enum):
    """What the eyes may follow. A member is its own name as a string (`"left arm"`), so it
    compares, hashes, prints and turns into JSON as the words a script writes."""

    HUMAN = "human"  # the nearest person, by the head sonar
    FACE = "face"  # the nearest face, by the head camera
    LEFT_ARM = "left arm"
    RIGHT_ARM = "right arm"

    def __str__(self) -> str:
        return self.value

    def __hash__(self) -> int:
        return hash(self.value)

    @property
    def hand(self) -> Optional[str]:
        """ "left" or "right" for an arm, else None."""
        return {FollowTarget.LEFT_ARM: "left", FollowTarget.RIGHT_ARM: "right"}.get(self)
