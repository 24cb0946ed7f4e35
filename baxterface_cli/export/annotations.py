"""Annotation files of a replayed session: `render LOG.jsonl --out session.eaf` (ELAN) or
`--out session.TextGrid` (Praat), through pympi-ling (the `annotate` extra), never by hand.

Their tiers are on the video's clock (`render LOG.jsonl --out session.mp4` of the same log): the
replay's 0 is its first script's start. `events`: each event that came, `EVENT_MARK` long (or to
the next event), those at one instant together; `handlers`: each handler's run, from its start to
its end (or the line that cut it); `states`: each state the face was in, from its entering; `said`:
what the face said, for as long as it was heard; `emotion`: the emotion the face showed, sampled
at `FPS` as the video is drawn.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from typing import Any, Dict, List, Sequence, Tuple

from ..engine.session_records import Logged, LogKind
from ..extras import need

EVENT_MARK = 0.1  # seconds an event's annotation lasts
FPS = 30.0  # the emotion is sampled as often as the video's frames are, by default
TIERS = ("events", "handlers", "states", "said", "emotion")
# A handler's run ends at the first of these after it began (one runs at a time).
_CLOSING = {LogKind.ENDED, LogKind.INTERRUPTED, LogKind.TAKEN_OVER, LogKind.STOPPED, LogKind.EXITED}
SUFFIXES = {".eaf": "ELAN", ".textgrid": "Praat"}

Interval = Tuple[float, float, str]


def annotation_kind(out: str) -> str:
    """'ELAN' or 'Praat' for an annotation file's name, '' for any other."""
    return SUFFIXES.get(os.path.splitext(out)[1].lower(), "")


def tiers_of(run: Any, trace: Any, end: float, fps: float = FPS) -> Dict[str, List[Interval]]:
    """The tiers (see above) of `run`, a SessionRun of the replay whose events were `trace`."""
    tiers = log_tiers(run.log, trace.events, run.timeline.speech, end)
    tiers["emotion"] = _apart(_emotions(run.timeline, end, fps))
    return tiers


def log_tiers(
    log: Sequence[Logged], events: Sequence[Any], speech: Sequence[Any], end: float
) -> Dict[str, List[Interval]]:
    """The tiers a run's log, its events (each `Posted`) and its speech (each `Said`) make, up to
    `end`: all but `emotion`, which needs its frames (the studio's timeline shows these)."""
    tiers = {
        "events": _events(events, end),
        "handlers": _handlers(log, end),
        "states": _states(log, end),
        "said": [(s.at, min(s.end, end), s.utterance.said) for s in speech if s.at < end],
    }
    return {name: _apart(spans) for name, spans in tiers.items()}


def _apart(spans: List[Interval]) -> List[Interval]:
    """One after another, as a tier holds them: each cut where the next begins (a `together`'s
    two utterances), none of no length."""
    spans = sorted(spans, key=lambda s: s[0])
    cut = [(a, min(b, spans[i + 1][0]) if i + 1 < len(spans) else b, x) for i, (a, b, x) in enumerate(spans)]
    return [(a, b, x) for a, b, x in cut if b > a]


def _events(events: Sequence[Any], end: float) -> List[Interval]:
    from ..language.events import in_words

    at_once: List[Tuple[float, List[str]]] = []
    for posted in events:
        if posted.at > end:
            break
        if at_once and at_once[-1][0] == posted.at:
            at_once[-1][1].append(in_words(posted.event))
        else:
            at_once.append((posted.at, [in_words(posted.event)]))
    marks = []
    for i, (at, names) in enumerate(at_once):
        until = min(at + EVENT_MARK, at_once[i + 1][0] if i + 1 < len(at_once) else at + EVENT_MARK)
        marks.append((at, until, " | ".join(names)))
    return marks


def _handlers(log: Sequence[Logged], end: float) -> List[Interval]:
    runs: List[Interval] = []
    running = None  # (since, the line that began it)
    for line in log:
        if running is not None and (line.kind in _CLOSING or line.kind == LogKind.STARTED):
            runs.append((running[0], line.at, running[1]))
            running = None
        if line.kind == LogKind.STARTED:  # "line 3 'on touch mouth' runs": the handler's label
            running = (line.at, line.text[: -len(" runs")] if line.text.endswith(" runs") else line.text)
    if running is not None:
        runs.append((running[0], end, running[1]))
    return [(a, b, text) for a, b, text in runs if b > a]


def _states(log: Sequence[Logged], end: float) -> List[Interval]:
    entered = [(line.at, line.text.split(":", 1)[0]) for line in log if line.kind == LogKind.ENTERED]
    spans = []
    for i, (at, text) in enumerate(entered):
        until = entered[i + 1][0] if i + 1 < len(entered) else end
        name = text[len("state ") :].rsplit(" entered", 1)[0] if text.startswith("state ") else text
        if until > at:
            spans.append((at, until, name))
    return spans


def _emotions(timeline: Any, end: float, fps: float) -> List[Interval]:
    spans: List[Interval] = []
    frames = int(end * fps + 1e-9)
    for i in range(frames + 1):
        t = min(i / fps, end)
        emotion = timeline.sample(t).emotion or ""
        if spans and spans[-1][2] == emotion:
            spans[-1] = (spans[-1][0], t, emotion)
        else:
            if spans:
                spans[-1] = (spans[-1][0], t, spans[-1][2])
            spans.append((t, t, emotion))
    if spans:
        spans[-1] = (spans[-1][0], end, spans[-1][2])
    return [(a, b, e) for a, b, e in spans if e and b > a]


def write_annotations(tiers: Dict[str, List[Interval]], end: float, out: str, media: str = "") -> None:
    """Write `tiers` to `out`, an ELAN .eaf or a Praat .TextGrid, through pympi-ling; the file
    appears only once written. MissingTool naming the `annotate` extra without it."""
    pympi = need("pympi", "annotate", "an annotation file (.eaf, .TextGrid)")
    kind = annotation_kind(out)
    folder = os.path.dirname(os.path.abspath(out))
    handle, partial = tempfile.mkstemp(prefix=f".{os.path.basename(out)}.", suffix=".partial", dir=folder)
    os.close(handle)
    try:
        if kind == "ELAN":
            _eaf(pympi, tiers, media).to_file(partial)
        else:
            _textgrid(pympi, tiers, end).to_file(partial)
        os.replace(partial, out)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.remove(partial)


def _eaf(pympi: Any, tiers: Dict[str, List[Interval]], media: str) -> Any:
    eaf = pympi.Eaf(author="baxterface")
    eaf.remove_tier("default")
    if media:
        eaf.add_linked_file(os.path.abspath(media), relpath=os.path.basename(media))
    for name in TIERS:
        eaf.add_tier(name)
        for start, stop, text in tiers.get(name, []):
            a, b = round(start * 1000), round(stop * 1000)
            if b > a:
                eaf.add_annotation(name, a, b, text)
    return eaf


def _textgrid(pympi: Any, tiers: Dict[str, List[Interval]], end: float) -> Any:
    grid = pympi.Praat.TextGrid(xmin=0, xmax=end)
    for name in TIERS:
        tier = grid.add_tier(name)
        for start, stop, text in tiers.get(name, []):
            if stop > start:
                tier.add_interval(start, min(stop, end), text)
    return grid
