"""The studio's session log: `studio --log FILE` (engine/session_log_file.py, as every live end).

The studio's face is a run of the editor's script over the events fired at it, each at the
preview's position (reacting.py), run again whole when the script changes; so its records say
both clocks: `t`, the studio's, from its start, when it was done; and `at`, the run's, where it
happened on the script the preview plays. `script`: each script the preview plays from then on
(the editor's text with the handlers pressed in the panel; `source` the file's name, or `panel`),
and each press played in the live session (`"press": true`); `event`: each event fired, with
`at`; `log` and `say`: what the run did from that event to the next, with their `at`;
`cleared`: the session's events let go (Clear). A replay of it (`render LOG.jsonl`) is the last
script over the events fired since the last `cleared`, at their `at`: the preview's run.
"""

from __future__ import annotations

from typing import Any, Optional

from ..engine.session_log_file import SessionLogFile
from ..language import syntax_tree as n
from ..language.event_trace import Posted
from ..language.events import in_words


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
        first = run.events[0].at if run is not None and run.events else float("inf")
        self._did(now, run.log if run is not None else (), animation.timeline.speech, 0.0, first)

    def press(self, now: float, text: str) -> None:
        if self.file is not None:
            self.file.note(now, {"type": "script", "text": text, "source": "panel", "press": True})

    def fired(self, now: float, posted: Posted, source: str, animation: Any, run: Any) -> None:
        """`posted` fired at the run `run` (an EventRun; None for a script that reacts to
        nothing), shown as `animation`: the event, and what the run did from it to the next."""
        if self.file is None:
            return
        self.file.note(
            now, {"type": "event", "event": in_words(posted.event), "source": source, "at": posted.at}
        )
        if run is not None:
            later = [e.at for e in run.events if e.at > posted.at]
            self._did(now, run.log, animation.timeline.speech, posted.at, later[0] if later else float("inf"))

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
