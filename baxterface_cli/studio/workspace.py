"""Everything the studio works on, without the web: the script file, the preview, the panel, the robot.

The page edits the script; the workspace checks it (with `check`'s very
diagnostics), plays its last good version in the preview, saves it
atomically, notices when it changes on disk, plays presses in the session,
sends them to the robot when that is switched on, and writes the session out
beside the script. The only files it reads or writes are the script, the
panel the user named, and session files in the script's folder: no request
names a path.
"""

from __future__ import annotations

import contextlib
import io
import os
import threading
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple

from ..core.easing import EASINGS
from ..core.partial_files import write_atomic
from ..core.presets import MOOD_CIRCLE
from ..core.tables import BROWS, DIRECTIONS, EMOTIONS, MOUTHS
from ..engine.timeline import Timeline
from ..extras import MissingTool
from ..language.checker import walk
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.parser import decode, grammar_words, parse, read_bounded
from ..language.syntax_tree import Say
from ..language.vocabulary import BARE_WORDS
from ..speech import phones_heard
from ..speech.recordings import NO_POCKETSPHINX, RecordingError, Recordings
from ..speech.soundtrack import write_wav
from .panel import Button, PanelError, load_panel
from .preview import Preview, sound_key
from .session import Stale


def diagnostics_json(diagnostics: List[Diagnostic]) -> List[Dict[str, Any]]:
    return [
        {"line": d.line, "column": d.column, "severity": d.severity, "message": d.message}
        for d in diagnostics
    ]


def check_text(text: str, filename: str = "<script>") -> List[Dict[str, Any]]:
    """What `baxterface check` says of `text`, as JSON records."""
    try:
        script = parse(text, filename)
    except ScriptError as e:
        return diagnostics_json(e.diagnostics)
    return diagnostics_json(list(script.warnings))


def timeline_json(timeline: Timeline) -> Dict[str, Any]:
    """The timeline `explain` prints (each statement's span), and the sounds it will want."""
    spans = [
        {"start": round(s.start, 3), "end": round(s.end, 3), "line": s.line, "text": s.text}
        for s in timeline.spans
    ]
    sounds = sorted({sound_key(said.utterance) for said in timeline.speech})
    return {"duration": round(timeline.duration, 3), "spans": spans, "sounds": sounds}


def vocabulary() -> Dict[str, List[str]]:
    """The words the editor highlights, from the tables the parser uses."""
    return {
        "keywords": grammar_words(),
        "words": sorted(BARE_WORDS),
        "emotions": sorted(name for name in EMOTIONS if " " not in name),
        "easings": sorted(EASINGS),
        "mouths": list(MOUTHS),
        "brows": list(BROWS),
        "directions": sorted(DIRECTIONS),
    }


def feelings() -> Dict[str, Any]:
    """What the mood pad and the intensity slider offer: the emotions a script may give an
    intensity (`happy 0.4`; `default` at any intensity is the neutral face, so it is left out),
    and where each emotion sits on the mood circle, in degrees from pleasant (core/presets.py)."""
    return {
        "emotions": [name.replace(" ", "_") for name in EMOTIONS if name != "default"],
        "mood_circle": [{"emotion": name, "degrees": degrees} for name, degrees in MOOD_CIRCLE],
    }


class RobotSwitch:
    """Presses go to the robot too, once switched on and a ROS master answers."""

    def __init__(self, topic: str = "display_chatter") -> None:
        self.topic = topic
        self.link: Optional[Any] = None
        self.on = False
        self.reason = "off"

    def switch(self, on: bool) -> Dict[str, Any]:
        if on and self.link is None:
            from ..ros.connect import RosUnavailable, require_master, require_ros

            try:
                require_ros(1)
                require_master(timeout=1.0)
                from ..ros.chatter import ChatterLink

                self.link = ChatterLink(self.topic)
            except RosUnavailable as e:
                self.reason = str(e)
                return self.as_json()
        self.on = on and self.link is not None
        self.reason = "off" if not on else self.reason
        return self.as_json()

    def send(self, text: str) -> None:
        if self.on and self.link is not None:
            self.link.send(text)

    def as_json(self) -> Dict[str, Any]:
        status = self.link.status() if self.on and self.link is not None else self.reason
        return {"on": self.on, "available": self.link is not None, "status": status}


class SaveConflict(Exception):
    """The script changed on disk since the version a save was based on."""

    def __init__(self, message: str, version: int) -> None:
        super().__init__(message)
        self.version = version


class Workspace:
    """The studio's state; every method may be called from any thread."""

    def __init__(
        self,
        path: Path,
        panel: Optional[Path] = None,
        seed: Optional[int] = None,
        idle: bool = True,
        clock: Callable[[], float] = time.monotonic,
        topic: str = "display_chatter",
    ) -> None:
        self.path = path.resolve()
        self.folder = self.path.parent
        self.name = self.path.name
        self.panel_path = panel
        self.clock = clock
        self.lock = threading.RLock()
        # The page's text and presses come over the network: `say file` reads only under the
        # script's own folder.
        self.recordings = Recordings(self.folder, confined=True)
        self.preview = Preview(seed, idle, filename="session.face", recordings=self.recordings)
        self.robot = RobotSwitch(topic)
        self.buttons: List[Button] = load_panel(panel)
        self.preview_note = ""
        self.saved = self._read() if self.path.exists() else ""
        self.text = self.saved
        # Counts the versions of the file: each save here and each change seen on disk. A page
        # saves "over version N"; when the disk has moved on since, it is asked before overwriting.
        self.version = 0
        self._disk_stamp = self._stamp(self.path)
        self._panel_stamp = self._stamp(panel) if panel else None
        self.update(self.text)

    # -- the script

    def _read(self) -> str:
        return decode(read_bounded(self.path, self.name), self.name)

    @staticmethod
    def _stamp(path: Optional[Path]) -> Optional[Tuple[int, int, int]]:
        """What tells one version of a file from the next: its modification time, and its size
        and inode beside it, since two writes within one tick of the file system's clock (a few
        milliseconds) get the same time."""
        try:
            found = os.stat(str(path)) if path else None
        except OSError:
            return None
        return (found.st_mtime_ns, found.st_size, found.st_ino) if found else None

    def update(self, text: str) -> Dict[str, Any]:
        """The editor's text: checked, and played by the preview when it is good."""
        try:
            script = parse(text, self.name)
        except ScriptError as e:
            with self.lock:
                self.text = text
            return {"diagnostics": diagnostics_json(e.diagnostics), "timeline": self.timeline()}
        diagnostics = diagnostics_json(list(script.warnings))
        unsaid = self.recordings.check(script) if "file" in text.lower() else []
        if unsaid:  # a recording missing or unreadable: an error, where it is named, as check says
            with self.lock:
                self.text = text
            return {"diagnostics": diagnostics_json(unsaid) + diagnostics, "timeline": self.timeline()}
        if self._hear_recordings(script) and not phones_heard.available():  # the rougher mouth: say so
            diagnostics.append({"line": 0, "column": 0, "severity": "warning", "message": NO_POCKETSPHINX})
        with self.lock:
            self.text = text
            try:
                self.preview.load(script)
                self.preview_note = ""
            except MissingTool as e:  # `say` with no speech engine: check is content, play is not
                self.preview_note = str(e)
                diagnostics.append({"line": 0, "column": 0, "severity": "warning", "message": str(e)})
            except RecordingError as e:  # changed on disk since it was checked
                diagnostics = diagnostics_json([e.diagnostic()]) + diagnostics
        return {"diagnostics": diagnostics, "timeline": self.timeline()}

    def _hear_recordings(self, script: Any) -> bool:
        """Find the mouths of the script's recordings before the lock is taken: the first time, a
        long one takes seconds, and the frame pump must not wait (then they are kept). Whether
        one of them is English, whose phonemes pocketsphinx hears."""
        english = False
        for say in walk(script.body):
            if isinstance(say, Say) and say.file is not None:
                english = english or not say.language or say.language.startswith("en")
                with contextlib.suppress(RecordingError, MissingTool):
                    self.recordings.recite(say)
        return english

    def timeline(self) -> Dict[str, Any]:
        with self.lock:
            return timeline_json(self.preview.animation.timeline)

    def save(self, text: str, base: Optional[int] = None) -> Dict[str, Any]:
        """Write `text` as the script; SaveConflict if the file changed since version `base`.

        The file is looked at here as well as every half second, so a change
        made just before the save is not overwritten unseen. Without `base`
        (a forced save, or a client that does not track versions) it writes.
        """
        with self.lock:
            if base is not None and (base != self.version or self._changed_on_disk()):
                raise SaveConflict(f"{self.name} changed on disk since it was loaded", self.version)
            write_atomic(self.path, text.encode("utf-8"))
            self.saved = self.text = text
            self._disk_stamp = self._stamp(self.path)
            self.version += 1
            return {"saved": True, "name": self.name, "version": self.version}

    def _changed_on_disk(self) -> bool:
        stamp = self._stamp(self.path)
        if stamp is None or stamp == self._disk_stamp:
            return False
        try:
            return self._read() != self.saved
        except ScriptError:
            return True

    def disk_changes(self) -> List[Dict[str, Any]]:
        """What changed on disk since last asked: the script (as `play --watch` sees it) and the panel."""
        changes: List[Dict[str, Any]] = []
        stamp = self._stamp(self.path)
        if stamp is not None and stamp != self._disk_stamp:
            self._disk_stamp = stamp
            try:
                text = self._read()
            except ScriptError:
                text = None
            if text is not None and text != self.saved:
                with self.lock:
                    unsaved = self.text != self.saved
                    self.saved = text
                    self.version += 1
                    version = self.version
                if not unsaved:  # nothing of the user's to lose: play the new version
                    self.update(text)
                changes.append({"kind": "disk", "name": self.name, "text": text, "version": version})
        if self.panel_path is not None:
            stamp = self._stamp(self.panel_path)
            if stamp != self._panel_stamp:
                self._panel_stamp = stamp
                try:
                    self.buttons = load_panel(self.panel_path)
                    changes.append({"kind": "buttons", "buttons": [b.as_json() for b in self.buttons]})
                except PanelError as e:  # keep the panel that works, and say why
                    changes.append({"kind": "notice", "message": f"kept the last good panel: {e}"})
        return changes

    # -- the preview

    def transport(self, action: str, t: float = 0.0, on: bool = False) -> Dict[str, Any]:
        now = self.clock()
        with self.lock:
            if action == "play":
                self.preview.play(now)
            elif action == "pause":
                self.preview.pause(now)
            elif action == "seek":
                self.preview.seek(t, now)
            elif action == "loop":
                self.preview.set_loop(on, now)
            else:
                raise ValueError(f"unknown transport action {action!r}; use play, pause, seek or loop")
            return self.preview.status(now)

    def status(self) -> Dict[str, Any]:
        with self.lock:
            status = self.preview.status(self.clock())
        status["note"] = self.preview_note
        return status

    def sound(self, key: str) -> Optional[bytes]:
        """The WAV file of an utterance the script or the session says (None for any other key)."""
        with self.lock:
            utterance = self.preview.utterance(key)
        if utterance is None:
            return None
        wav = io.BytesIO()
        write_wav(wav, utterance.samples, utterance.sample_rate)
        return wav.getvalue()

    def face(self):
        """The face to show now (an immutable FaceState)."""
        with self.lock:
            return self.preview.at(self.clock())[1]

    # -- the session

    def command(self, text: str) -> float:
        """Play `text` now on the preview and, when switched on, on the robot; ScriptError if bad."""
        now = self.clock()
        while True:
            # Compiled without the lock, which the frame pump needs many times a second: a long
            # session takes a while to compile again, and the preview must not stop meanwhile.
            prepared = self.preview.prepare_press(text, now)
            with self.lock:
                try:
                    at = self.preview.take_press(prepared, now)
                    break
                except Stale:  # another press or a clear came first: prepare it again
                    continue
        self.robot.send(text)
        return at

    def session(self) -> Dict[str, Any]:
        with self.lock:
            return self.preview.session.as_json()

    def clear_session(self) -> Dict[str, Any]:
        with self.lock:
            self.preview.clear_session()
        return self.session()

    def export_session(self) -> Dict[str, Any]:
        """Write the session beside the script, under a name of its own time."""
        stamp = time.strftime("%Y%m%d-%H%M%S")
        target = self.folder / f"session-{stamp}.face"
        number = 1
        while target.exists():
            number += 1
            target = self.folder / f"session-{stamp}-{number}.face"
        with self.lock:
            session = self.preview.session
            text = session.text_of(session.presses, target.name)
        write_atomic(target, text.encode("utf-8"))
        return {"path": target.name, "text": text}

    def state(self) -> Dict[str, Any]:
        """All the page needs when it loads."""
        with self.lock:
            script = {
                "name": self.name,
                "text": self.text,
                "saved": self.text == self.saved,
                "version": self.version,
            }
        return {
            "script": script,
            "vocabulary": vocabulary(),
            "feelings": feelings(),
            "buttons": [b.as_json() for b in self.buttons],
            "timeline": self.timeline(),
            "session": self.session(),
            "status": self.status(),
            "robot_link": self.robot.as_json(),
        }
