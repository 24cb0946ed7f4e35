"""The events a script reacts to, as words: which there are, what each names, and which posted
event a handler's event matches.

`on EVENT ...` and `wait until EVENT ...` (reaction_rules.py) and an events file's lines
(event_trace.py) read their events with `read_event`, so the three say the same things about
the same mistakes.
"""

from __future__ import annotations

import re
from typing import Any, Callable, List, Optional, Sequence, Tuple

from lark import Token

from . import syntax_tree as n
from .diagnostics import Hints, one_of

# Every event, as it is written: the two-word ones whole.
KINDS = (
    "face seen",
    "face lost",
    "person near",
    "person gone",
    "button",
    "word",
    "heard",
    "touch",
    "signal",
    "every",
    "idle",
)
TIMERS = ("every", "idle")  # raised by the session's clock, never posted
_SECOND_WORDS = {"face": ("seen", "lost"), "person": ("near", "gone")}

# Baxter's navigators and their buttons, as robot/buttons.json names them, and the wheel.
NAVIGATORS = ("left", "right", "torso_left", "torso_right")
BUTTONS = ("ok", "up", "down")  # in the order of NavigatorState.buttons (index 0, 1, 2)
WHEEL = "wheel"
# The arms' cuffs: the button with a dash, the round one, and the cuff squeezed.
CUFFS = ("left_cuff", "right_cuff")
CUFF_BUTTONS = ("dash", "circle", "squeeze")
# Where on the face a touch lands (the robot's left, as `wink left`); none: anywhere.
PLACES = ("left eye", "right eye", "mouth", "brows")

POLICIES = ("drop", "queue", "interrupt")
MOST_WORDS = 8  # words in a `word "..."`: a phrase to spot, not a speech
MOST_HEARD = 1000  # characters of an utterance heard that an event keeps
ALTERNATIVES = "|"  # between the phrases of `word "hello" | "hi robot"` in its event's arg
MOST_LETTERS = 60
SHORTEST_EVERY = 0.1  # seconds: an `every` faster than this is a storm of the script's own

Error = Callable[[Token, str], None]
Seconds = Callable[[Token, str], float]
Decode = Callable[[Token], Optional[str]]

_PHRASE = re.compile(r"[a-z']+(?: [a-z']+)*")
NUMBER = r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)"  # as the grammar's, before a unit: events files too
_LEADING_NUMBER = re.compile(NUMBER)


def written_zero(token: Token) -> bool:
    """Is the number written at the front of `token` zero (`0s`, `0.0`), not one that was bad?"""
    number = _LEADING_NUMBER.match(str(token))
    return number is not None and float(number.group()) == 0


def read_event(
    tokens: Sequence[Token], error: Error, seconds: Seconds, decode: Decode, hints: Hints
) -> Tuple[Optional[n.Event], List[Token]]:
    """The event written at the front of `tokens` (NAME, STRING and QUANTITY tokens), and the
    tokens after it (its options); None after an error, which went to `error`."""
    first = tokens[0]
    word = str(first).lower()
    rest = list(tokens[1:])
    pos = n.Pos(first.line, first.column)
    if first.type != "NAME" or (word not in KINDS and word not in _SECOND_WORDS):
        hint = hints(word, [k.split()[0] for k in KINDS] + list(KINDS)) or f"; events are {one_of(KINDS)}"
        error(first, f"unknown event '{first}'{hint}")
        return None, []
    if word in _SECOND_WORDS:
        second = rest.pop(0) if rest else None
        wanted = _SECOND_WORDS[word]
        if second is None or str(second).lower() not in wanted:
            written = f"'{word} {second}'" if second is not None else f"'{word}' alone"
            hint = hints(f"{word} {str(second).lower()}", [f"{word} {w}" for w in wanted]) if second else ""
            error(
                second or first,
                f"unknown event {written}{hint or '; write ' + one_of(f'{word} {w}' for w in wanted)}",
            )
            return None, []
        return n.Event(f"{word} {str(second).lower()}", pos=pos), rest
    if word == "button":
        return _button(first, rest, error, hints, pos)
    if word == "touch":
        place, rest = _place(rest)
        return n.Event("touch", place, pos=pos), rest
    if word == "signal":
        if not rest or rest[0].type != "NAME":
            error(rest[0] if rest else first, "'signal' needs a name: 'signal poke'")
            return None, []
        return n.Event("signal", str(rest[0]).lower(), pos=pos), rest[1:]
    if word == "word":
        return _word(first, rest, error, decode, pos)
    if word == "heard":  # a whole utterance, as a recogniser gives it: `4 heard "yes please"`
        text = decode(rest[0]) if rest and rest[0].type == "STRING" else None
        if text is None:
            if not rest or rest[0].type != "STRING":
                error(
                    rest[0] if rest else first,
                    "'heard' needs what was said in double quotes: 'heard \"yes please\"'",
                )
            return None, []
        return n.Event("heard", " ".join(text.lower().split())[:MOST_HEARD], pos=pos), rest[1:]
    if not rest or rest[0].type != "QUANTITY":
        error(rest[0] if rest else first, f"'{word}' needs a time: '{word} 5s'")
        return None, []
    period = seconds(rest[0], f"an '{word}' time")
    if period <= 0 and not written_zero(rest[0]):  # its number was bad, and said so
        return None, []
    if period <= 0 or (word == "every" and period < SHORTEST_EVERY):
        least = f"{SHORTEST_EVERY:g} s at least" if word == "every" else "more than 0 s"
        error(rest[0], f"an '{word}' time must be {least}, not {rest[0]}")
        return None, []
    return n.Event(word, seconds=period, pos=pos), rest[1:]


def _button(
    first: Token, rest: List[Token], error: Error, hints: Hints, pos: n.Pos
) -> Tuple[Any, List[Token]]:
    names = []
    for token in rest[:2]:
        if token.type != "NAME":
            break
        names.append(str(token).lower())
    if names[:1] == [WHEEL]:
        turned = names[1:2] if names[1:2] in (["up"], ["down"]) else []
        return n.Event("button", " ".join([WHEEL] + turned), pos=pos), rest[1 + len(turned) :]
    if names[:1] and names[0] in BUTTONS + CUFF_BUTTONS:
        return n.Event("button", names[0], pos=pos), rest[1:]
    if names[:1] and names[0] in NAVIGATORS + CUFFS:
        device = names[0]
        own = CUFF_BUTTONS if device in CUFFS else BUTTONS
        if names[1:2] and names[1] in own:
            return n.Event("button", f"{device} {names[1]}", pos=pos), rest[2:]
        which = f"its buttons are {one_of(own)}"
        if names[1:2]:
            hint = hints(names[1], own)
            error(rest[1], f"unknown button '{rest[1]}' on '{device}'{hint or '; ' + which}")
        else:
            error(rest[0], f"'button {device}' needs one of its buttons: {one_of(own)}")
        return None, []
    usage = (
        f"a button: {one_of(BUTTONS + CUFF_BUTTONS)}, a navigator's ('left ok', 'torso_right up'), "
        "a cuff's ('left_cuff dash') or 'wheel'"
    )
    if not names:
        error(rest[0] if rest else first, f"'button' needs {usage}")
    else:
        hint = hints(names[0], BUTTONS + CUFF_BUTTONS + NAVIGATORS + CUFFS + (WHEEL,))
        error(rest[0], f"unknown button '{rest[0]}'{hint or '; ' + usage}")
    return None, []


def _place(rest: List[Token]) -> Tuple[str, List[Token]]:
    words = [str(t).lower() if t.type == "NAME" else "" for t in rest[:2]]
    if " ".join(words) in PLACES:
        return " ".join(words), rest[2:]
    if words[:1] and words[0] in PLACES:
        return words[0], rest[1:]
    return "", rest


def _word(
    first: Token, rest: List[Token], error: Error, decode: Decode, pos: n.Pos
) -> Tuple[Any, List[Token]]:
    """`word "hello"`, or phrases any of which it takes: `word "hello" | "hi robot"` (their arg
    joined by ALTERNATIVES, as `phrases` splits it)."""
    phrases: List[str] = []
    last = first  # where a missing phrase is said to be missing: after `word`, or after a bar
    while True:
        if not rest or rest[0].type != "STRING":
            error(rest[0] if rest else last, "'word' needs the words in double quotes: 'word \"hello\"'")
            return None, []
        text = decode(rest[0])
        if text is None:
            return None, []
        phrase = phrase_of(text)
        if phrase is None:
            error(rest[0], not_a_phrase("'word' spots", text))
            return None, []
        phrases.append(phrase)
        rest = rest[1:]
        if not rest or rest[0].type != "BAR":
            return n.Event("word", ALTERNATIVES.join(dict.fromkeys(phrases)), pos=pos), rest
        last, rest = rest[0], rest[1:]


def phrase_of(text: str) -> Optional[str]:
    """`text` as a phrase to listen for (lower case, single spaces), or None if it cannot be one."""
    phrase = " ".join(text.lower().split())
    if not _PHRASE.fullmatch(phrase) or len(phrase.split()) > MOST_WORDS or len(phrase) > MOST_LETTERS:
        return None
    return phrase


def not_a_phrase(subject: str, text: str) -> str:
    """Why `text` is no phrase, said of `subject` (`'word' spots`, `an answer is`)."""
    return (
        f"{subject} a few words of letters ({MOST_WORDS} at most, {MOST_LETTERS} letters), not {shown(text)}"
    )


def phrases(event: n.Event) -> List[str]:
    """The phrases a `word` event takes: one, or each of its alternatives."""
    return event.arg.split(ALTERNATIVES)


def shown(text: str, most: int = 30) -> str:
    """Text as a message quotes it, shortened."""
    return '"' + (text if len(text) <= most else text[:most] + "...") + '"'


def in_words(event: n.Event) -> str:
    """An event as a script writes it: `face seen`, `button left ok`, `word "hello"`, `every 5s`."""
    if event.kind in TIMERS:
        return f"{event.kind} {event.seconds:g}s"
    if event.kind == "word":
        return "word " + " | ".join(f'"{phrase}"' for phrase in phrases(event))
    if event.kind == "heard":
        return f'heard "{event.arg}"'
    return f"{event.kind} {event.arg}".strip()


def option_words(event: n.Event) -> Tuple[str, ...]:
    """Words a misspelled option may have meant, for its "did you mean"."""
    extra = tuple(w for place in PLACES for w in place.split()) if event.kind == "touch" else ()
    return POLICIES + ("cooldown", "timeout") + extra


def matches(wanted: n.Event, posted: n.Event) -> bool:
    """Does a handler's (or a wait's) event take `posted`? A button without a navigator or cuff
    takes any navigator's (`button dash` any cuff's), `button wheel` either turn, `touch`
    anywhere, `word` any of its phrases; the rest are equal."""
    if wanted.kind != posted.kind:
        return False
    if wanted.kind in TIMERS:
        return wanted.seconds == posted.seconds
    if wanted.arg == posted.arg or (wanted.kind == "touch" and not wanted.arg):
        return True
    if wanted.kind == "word":  # a phrase heard is one; the handler's may be several
        return posted.arg in phrases(wanted)
    if wanted.kind == "button":
        got = posted.arg.split()
        return (wanted.arg == WHEEL and got[0] == WHEEL) or (
            wanted.arg in BUTTONS + CUFF_BUTTONS and got[-1] == wanted.arg and got[0] != WHEEL
        )
    return False
