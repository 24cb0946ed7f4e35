"""The studio's session log: `studio --log FILE` (engine/session_log_file.py, as every live end).

The studio's face is its one live session: a run of the editor's script over the events fired at
it and the commands pressed in the panel, each at the preview's position (reacting.py, event_run.py),
run again when the script changes; so its records say both clocks: `t`, the studio's, from its
start, when it was done; and `at`, the run's, where it happened on the script the preview plays.
`script`: each script the preview plays from then on (the editor's text with the handlers pressed
in the panel; `source` the file's name, or `panel`), and each command pressed (`"press": true`,
with its `at`); `event`: each event fired, with `at`; `log` and `say`: what the run did from that
input to the next, with their `at`; `cleared`: the session's inputs let go (Clear). A replay of it
(`render LOG.jsonl`, engine/log_replay.py) is the last script over the events and commands since the
last `cleared`, at their `at`: the preview's run. The session's export is such a log, written whole
(`exported`).
"""

from __future__ import annotations

import json
from typing import Any, Dict, List, Optional, Sequence

from ..engine.session_log_file import VERSION, SessionLogFile
from ..language import syntax_tree as n
from ..language.events import in_words
from .event_run import Command, Input


def _input_record(item: Input, source: str = "") -> Dict[str, Any]:
    """The record of an input: an event fired, or a command pressed, at its `at` on the run."""
    if isinstance(item, Command):
        return {"type": "script", "text": item.script.source, "source": "panel", "press": True, "at": item.at}
    return {"type": "event", "event": in_words(item.event), "source": source, "at": item.at}


def exported(script: n.Script, name: str, inputs: Sequence[Input], seed: Optional[int]) -> str:
    """The session as a log `render` and `explain` replay: `script` (as `name`) over `inputs`.
    Each record's `t` is its `at`: an export is not a record of when things were done."""
    records: List[Dict[str, Any]] = [
        {"type": "start", "t": 0, "version": VERSION, "settings": {"end": "studio", "seed": seed}},
        {"type": "script", "t": 0, "text": script.source, "source": name},
    ]
    records += [{**_input_record(item, "POST /api/event"), "t": item.at} for item in inputs]
    return "".join(json.dumps(record) + "\n" for record in records)


class StudioRecord:
    """What the workspace tells its log file, when it has one (else nothing is kept)."""

    def __init__(self, file: Optional[SessionLogFile] = None) -> None:
        self.file = file
        self._played = ""  # the last script recorded: an edit that changes no text is not one

    def script(self, now: float, script: n.Script, source: str, animation: Any, run: Any) -> None:
        """`script` played from now on, as `animation` (and `run`, when it reacts): the script, and
        what the run does before its first event."""
        if self.file is None or script.source == self._played:
            return
        self._played = script.source
        self.file.script(now, script.source, source)
        first = run.inputs[0].at if run is not None and run.inputs else float("inf")
        self._did(now, run.log if run is not None else (), animation.timeline.speech, 0.0, first)

    def took(self, now: float, item: Input, source: str, animation: Any, run: Any) -> None:
        """`item` (an event fired, a command pressed) taken by the run `run` (an EventRun; None for
        an event at a script not running yet), shown as `animation`: the input, and what the run did
        from it to the next."""
        if self.file is None:
            return
        self.file.note(now, _input_record(item, source))
        if run is not None:
            later = [e.at for e in run.inputs if e.at > item.at]
            self._did(now, run.log, animation.timeline.speech, item.at, later[0] if later else float("inf"))

    def _did(self, now: float, log: Any, speech: Any, since: float, until: float) -> None:
        """The run's log lines and what it says from `since` to before `until`, at their `at`."""
        file = self.file
        if file is None:
            return
        for line in log:
            if since <= line.at < until:
                file.note(now, {"type": "log", "kind": line.kind, "text": line.text, "at": round(line.at, 4)})
        for said in speech:
            if since <= said.at < until:
                u = said.utterance
                length = round(u.duration, 4)
                said_at = round(said.at, 4)
                file.note(
                    now, {"type": "say", "text": u.said, "voice": u.voice, "length": length, "at": said_at}
                )

    def cleared(self, now: float) -> None:
        if self.file is not None:
            self.file.note(now, {"type": "cleared"})

    def close(self) -> None:
        if self.file is not None:
            self.file.close()
