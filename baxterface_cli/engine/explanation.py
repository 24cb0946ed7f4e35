"""`explain`'s words: a compiled timeline as lines of text, in time order or grouped; and the
times of its frames, which `explain --json` lists and `render` draws."""

from __future__ import annotations

from typing import Any, List, Sequence, Tuple

from .effects import EffectWords

# At one instant: what the session did (an event, a handler that runs or drops it), the face an
# earlier statement arrived at, the statement that starts, what it asks of the robot, the words said.
_SESSION, _FACE, _STATEMENT, _ROBOT, _WORD = range(5)
_GROUPS = {_STATEMENT: 0, _SESSION: 1, _FACE: 2, _ROBOT: 3, _WORD: 4}  # --grouped: the statements first


def frame_times(duration: float, fps: float) -> List[float]:
    """When each frame of a script `duration` seconds long is shown, at `fps`.

    Frames last 1/fps each, so there are as many as last the script to within half a frame (a
    1 s script at 30 fps is 30 frames, as a player counts them), and the last one shows the end
    itself: where the script leaves the face. Every format `render` writes (videos, GIFs, folders
    of PNGs) and `explain --json` count by this one rule.
    """
    count = max(1, round(duration * fps))
    return [i / fps for i in range(count - 1)] + [duration]


def _row(start: float, end: float, what: str) -> str:
    when = f"{start:6.2f} s" if end == start else f"{start:6.2f} - {end:6.2f} s"
    return f"  {when:<19} {what}"


def explained(timeline: Any, grouped: bool = False, session: Sequence[Tuple[float, str]] = ()) -> List[str]:
    """One line per statement, face change, robot cue and spoken word (and, for a script run by
    the live session, per line of its log: `session`, (time, what) pairs, all of them, in order).

    In time order by default; `grouped` lists the statements, then the session's lines, the face
    changes, the robot cues and the words, each group in time order. Lines at one time read in the
    order things happened, where the session's run says it (a stitched timeline's `marks`): a
    handler's statement that takes no time comes after the handler runs and before it ends.
    """
    rows: List[Tuple[float, int, int, int, str]] = []  # (time, step, kind, order of appearance, line)

    def add(start: float, end: float, step: int, kind: int, what: str) -> None:
        rows.append((start, step, kind, len(rows), _row(start, end, what)))

    marks = getattr(timeline, "marks", None)
    pieces = getattr(timeline, "pieces", [timeline])  # a stitched timeline's, each as it played
    # The session's line i and each timeline it began, in the order they came: the timeline begun
    # after the first `mark` lines of the log reads after line mark - 1 and before line mark.
    steps = [0] * len(pieces) if marks is None else [2 * m for m in marks]
    for i, (at, what) in enumerate(session):
        add(at, at, 0 if marks is None else 2 * i + 1, _SESSION, f"react {what}")
    words = EffectWords()
    for step, piece in zip(steps, pieces):
        for span in piece.spans:
            add(span.start, span.end, step, _STATEMENT, f"line {span.line:<4} {span.text}")
        for change in piece.parts:
            p = change.parts
            add(change.at, change.at, step, _FACE, f"face  skin {p.skin}, mouth {p.mouth}, brows {p.brows}")
        for cue in piece.cues:
            add(cue.at, cue.at, step, _ROBOT, f"robot {cue.effect.visit(words, cue.at)}")
        for said in piece.speech:
            for word in said.utterance.words:
                add(said.at + word.at, said.at + word.at, step, _WORD, f"word  {word.text}")
    by_group = lambda r: (_GROUPS[r[2]], r[0], r[1], r[3])  # noqa: E731
    lines, last_face = [], None
    for row in sorted(rows, key=by_group if grouped else None):
        if row[2] == _FACE and row[4] == last_face:
            continue  # the face one step left, which the next begins from: said once
        last_face = row[4] if row[2] == _FACE else last_face
        lines.append(row[4])
    return lines
