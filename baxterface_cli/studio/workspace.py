"""Everything the studio works on, without the web: the script file, the preview, the panel, the robot.

The page edits the script; the workspace checks it (with `check`'s very
diagnostics), plays its last good version in the preview, saves it
atomically, notices when it changes on disk, plays events and presses in its
one live session (reacting.py), sends presses to the robot when that is
switched on, and writes the session out beside the script. The only files it
reads or writes are the script, the panel the user named, and session files in
the script's folder: no request names a path.
"""

from __future__ import annotations

import os
import stat
import threading
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

from ..core.face_constants import LIMITS
from ..core.partial_files import PartialFile, write_atomic
from ..engine.session_log_file import SessionLogFile
from ..engine.timeline import Timeline
from ..extras import MissingTool
from ..language.checker import walk
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.parser import decode, parse, read_bounded
from ..language.syntax_tree import Say, Script
from ..speech import phones_heard
from ..speech.recordings import NO_POCKETSPHINX, RecordingError, Recordings
from ..web.answers import diagnostics_json, problem
from ..web.sounds import sound_key, wav_file
from .chained import Chained
from .event_run import Command
from .lanes import lanes
from .page_tables import feelings, vocabulary
from .panel import Button, PanelError, load_panel
from .preview import Preview
from .reacting import Reacting, listens, with_pressed
from .robot_switch import RobotSwitch
from .studio_log import StudioRecord, exported

MAX_SESSION_FILES = 100  # session files one run writes; each session has one, replaced by its exports
SHOWN_SPANS = 400  # spans of a long run the page lists, around the preview's position
SHOWN_PRESSES = 200  # the latest presses a press's answer lists (the export has them all)


def _write_keeping_mode(path: Path, data: bytes) -> None:
    """`data` as the file `path`, atomically, with the permissions the file had (a new one: the umask's)."""
    try:
        mode: Optional[int] = stat.S_IMODE(os.stat(str(path)).st_mode)
    except OSError:
        mode = None
    partial = PartialFile(path)
    try:
        if mode is not None:  # before a byte is written: never readable by more than the file was
            os.fchmod(partial.file.fileno(), mode)
        partial.file.write(data)
        partial.commit()
    except BaseException:
        partial.discard()
        raise


def check_text(
    text: Union[str, bytes], filename: str = "<script>", recordings: Optional[Recordings] = None
) -> List[Dict[str, Any]]:
    """What `baxterface check` says of `text` (bytes are decoded as `check` reads a file), with its
    recordings looked up in `recordings` when given, as JSON records."""
    try:
        script = parse(decode(text, filename) if isinstance(text, bytes) else text, filename)
    except ScriptError as e:
        return diagnostics_json(e.diagnostics)
    problems = recordings.check(script) if recordings is not None and "file" in script.source.lower() else []
    if problems:  # as `check`: the recordings' errors, and then no warnings
        return diagnostics_json(ScriptError(problems, filename, script.source).diagnostics)
    return diagnostics_json(list(script.warnings))


def timeline_json(timeline: Timeline, t: float = 0.0) -> Dict[str, Any]:
    """The timeline `explain` prints (each statement's span), and the sounds it will want; of a long
    run of events, the `SHOWN_SPANS` around `t` (`spans_before`: how many come before them)."""
    found, before, speech = (
        timeline.near(t, SHOWN_SPANS)
        if isinstance(timeline, Chained)
        else (timeline.spans, 0, timeline.speech)
    )
    spans = [
        {"start": round(s.start, 3), "end": round(s.end, 3), "line": s.line, "text": s.text} for s in found
    ]
    sounds = sorted({sound_key(said.utterance) for said in speech})
    return {"duration": round(timeline.duration, 3), "spans": spans, "sounds": sounds, "spans_before": before}


class TooLargeToSave(ValueError):
    """A save the studio could not load again: over the size limit scripts are read with."""


class TooManySessions(Exception):
    """The studio has written as many session files as it writes in one run."""


class SaveConflict(Exception):
    """The script changed on disk since the version a save was based on."""

    def __init__(self, message: str, version: int) -> None:
        super().__init__(message)
        self.version = version


class Workspace(Reacting):
    """The studio's state; every method may be called from any thread."""

    def __init__(
        self,
        path: Path,
        panel: Optional[Path] = None,
        seed: Optional[int] = None,
        idle: bool = True,
        clock: Callable[[], float] = time.monotonic,
        topic: str = "display_chatter",
        record: Optional[SessionLogFile] = None,
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
        self.preview = Preview(seed, idle, recordings=self.recordings)
        self.robot = RobotSwitch(topic)
        self.buttons: List[Button] = load_panel(panel)
        self.preview_note = ""
        self.unreadable = ""  # why the file on disk, changed since, cannot be read
        self._exported: Dict[int, Path] = {}  # each session's file, by its number
        self._sessions = 0  # sessions cleared so far: the number of the one going on
        self.saved = self._read() if self.path.exists() else ""
        self.text = self.saved
        # Counts the versions of the file: each save here and each change seen on disk. A page
        # saves "over version N"; when the disk has moved on since, it is asked before overwriting.
        self.version = 0
        self._disk_stamp = self._stamp(self.path)
        self._panel_stamp = self._stamp(panel) if panel else None
        self.record = StudioRecord(record)  # the session's log file (`studio --log`), if any
        self._start_reacting()
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

    def check(self, text: Union[str, bytes]) -> List[Dict[str, Any]]:
        """What `baxterface check` says of `text` as this script: recordings from its folder."""
        return check_text(text, self.name, self.recordings)

    def update(self, text: Union[str, bytes]) -> Dict[str, Any]:
        """The editor's text: checked, and played by the preview when it is good.

        Everything slow (reading and analysing recordings, synthesising speech,
        compiling) is done before the lock the frames wait on is taken; each
        recording is opened once.
        """
        try:
            text = decode(text, self.name) if isinstance(text, bytes) else text
            script = parse(text, self.name)
        except ScriptError as e:
            if isinstance(text, str):
                with self.lock:
                    self.text = text
            return {"diagnostics": diagnostics_json(e.diagnostics), "timeline": self.timeline()}
        diagnostics = diagnostics_json(list(script.warnings))
        unsaid, english = self._recite(script)
        if unsaid:  # a recording missing or unreadable: an error, where it is named, as check says
            with self.lock:
                self.text = text
            return {"diagnostics": diagnostics_json(unsaid) + diagnostics, "timeline": self.timeline()}
        if english and not phones_heard.available():  # the rougher mouth: say so
            diagnostics.append(problem(NO_POCKETSPHINX, "warning"))
        prepared, note = None, self.preview_note
        with self.firing:  # over the events fired so far: one fired meanwhile is not lost
            try:
                # With the handlers pressed in the panel, as the export writes it.
                played = with_pressed(script, self.pressed)
                prepared, note = self.preview.prepare(played), ""
            except MissingTool as e:  # `say` with no speech engine: check is content, play is not
                note = str(e)
                diagnostics.append(problem(str(e), "warning"))
            except RecordingError as e:  # changed on disk since it was read
                diagnostics = diagnostics_json([e.diagnostic()]) + diagnostics
            except ScriptError as e:  # a statement the session found bad only in running it
                diagnostics = diagnostics_json(e.diagnostics) + diagnostics
            with self.lock:
                self.text, self.preview_note = text, note
                if prepared is not None:
                    self.editor = script
                    self.preview.show(played, *prepared)
                    self.record.script(self.clock(), played, self.name, prepared[0], prepared[2])
        return {"diagnostics": diagnostics, "timeline": self.timeline()}

    def _recite(self, script: Any) -> Tuple[List[Diagnostic], bool]:
        """Read each recording the script says, once, and find its mouth (kept: compiling then finds
        it), without the lock: the first time, a long one takes seconds. What cannot be said, at
        each `say file`; and whether one of them is English, whose phonemes pocketsphinx hears."""
        english, unsaid = False, []
        for say in walk(script.body):
            if isinstance(say, Say) and say.file is not None:
                english = english or not say.language or say.language.startswith("en")
                try:
                    self.recordings.recite(say)
                except RecordingError as e:
                    unsaid.append(e.diagnostic())
                except MissingTool:  # without the lipsync extra: only that the file is there
                    unsaid.extend(self.recordings.check(Script((say,), self.name, (), "")))
        return unsaid, english

    def timeline(self) -> Dict[str, Any]:
        with self.lock:
            t, preview = self.preview.position(self.clock()), self.preview
            shown = {**timeline_json(preview.animation.timeline, t), "lanes": lanes(preview, t)}
            fired = len(preview.inputs) - preview.commands
            return {**shown, "listens": listens(preview.script), "fired": fired}

    def save(self, text: Union[str, bytes], base: Optional[int] = None) -> Dict[str, Any]:
        """Write `text` as the script; SaveConflict if the file changed since version `base`.

        The file is looked at here as well as every half second, so a change
        made just before the save is not overwritten unseen. Without `base`
        (a forced save, or a client that does not track versions) it writes.
        Bytes are decoded as `check` reads a file (ScriptError where they are
        not UTF-8); TooLargeToSave past the size the studio reads a script
        at; the file keeps its permissions.
        """
        text = decode(text, self.name) if isinstance(text, bytes) else text
        data = text.encode("utf-8", "surrogatepass")
        if len(data) > LIMITS.max_bytes:
            raise TooLargeToSave(
                f"not saved: the script is {len(data)} bytes; the studio, like every command, reads a "
                f"script of at most {LIMITS.max_bytes} bytes"
            )
        with self.lock:
            if base is not None and (base != self.version or self._changed_on_disk()):
                why = f"{self.name} changed on disk since it was loaded"
                if self.unreadable:
                    why = f"{self.name} changed on disk, and the studio cannot read it ({self.unreadable})"
                raise SaveConflict(why, self.version)
            _write_keeping_mode(self.path, data)
            self.saved = self.text = text
            self._disk_stamp = self._stamp(self.path)
            self.unreadable = ""
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
        """What changed on disk since last asked: the script (as `play --watch` sees it) and the panel.

        A change the studio cannot read (not UTF-8, too large) is told to the
        page, and counts as a new version: a save based on the one before is
        refused rather than overwriting it unseen.
        """
        changes: List[Dict[str, Any]] = []
        stamp = self._stamp(self.path)
        if stamp is not None and stamp != self._disk_stamp:
            self._disk_stamp = stamp
            try:
                text: Optional[str] = self._read()
            except ScriptError as e:
                text = None
                with self.lock:
                    self.unreadable = e.diagnostics[0].message if e.diagnostics else "unreadable"
                    self.version += 1
                    version = self.version
                message = f"{self.name} changed on disk and cannot be read: {self.unreadable}"
                changes.append({"kind": "notice", "message": message, "unreadable": True, "version": version})
            if text is not None and text != self.saved:
                with self.lock:
                    unsaved = self.text != self.saved
                    self.saved, self.unreadable = text, ""
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

    def status(self, now: float) -> Dict[str, Any]:
        with self.lock:
            status = self.preview.status(now)
        status["note"] = self.preview_note
        return status

    def sound(self, key: str) -> Optional[bytes]:
        """The WAV file of an utterance the script or the session says (None for any other key)."""
        with self.lock:
            utterance = self.preview.utterance(key)
        if utterance is None:
            return None
        return wav_file(utterance)

    def step(self, now: float) -> None:
        """Nothing here moves with time by itself: the preview is sampled where its transport says."""

    def face(self, now: float):
        """The face to show at `now` (an immutable FaceState): a read."""
        with self.lock:
            return self.preview.at(now)[1]

    # -- the session

    def session(self, whole: bool = False) -> Dict[str, Any]:
        """The commands pressed in the session, the latest `SHOWN_PRESSES` (`whole`: all), their
        count and the seed: a press is answered with the latest only, so that it costs the same
        however long the session has grown."""
        with self.lock:
            inputs, seed, count = self.preview.inputs, self.preview.seed, self.preview.commands
        shown: List[Command] = []
        for item in reversed(inputs):  # the latest first, as far back as shown
            if not whole and len(shown) == SHOWN_PRESSES:
                break
            if isinstance(item, Command):
                shown.append(item)
        presses = [{"at": p.at, "command": p.script.source.strip()} for p in reversed(shown)]
        return {"presses": presses, "count": count, "seed": seed}

    def clear_session(self) -> Dict[str, Any]:
        with self.lock:
            self._sessions += 1
        self.clear_events()
        return self.session()

    def export_session(self) -> Dict[str, Any]:
        """Write the session beside the script, as a log `render` and `explain` replay: one file a
        session, named after the time of its first export, which each later export of the same
        session replaces. A new file for each export filled the folder (2,000 in 5 s); past
        `MAX_SESSION_FILES` sessions in one run, refused."""
        with self.lock:
            key = self._sessions
            target = self._exported.get(key)
            if target is None:
                if len(self._exported) >= MAX_SESSION_FILES:
                    raise TooManySessions(
                        f"the studio has written {MAX_SESSION_FILES} session files in this run, the most "
                        "it writes; each session's later exports replace its own file"
                    )
                stamp = time.strftime("%Y%m%d-%H%M%S")
                target = self.folder / f"session-{stamp}.jsonl"
                number = 1
                while target.exists() or target in self._exported.values():
                    number += 1
                    target = self.folder / f"session-{stamp}-{number}.jsonl"
                self._exported[key] = target
            preview = self.preview
            text = exported(preview.script, self.name, preview.inputs, preview.seed)
        write_atomic(target, text.encode("utf-8", "surrogatepass"))
        return {"path": target.name, "text": text, **self.export_events(target)}

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
            "session": self.session(whole=True),
            "status": self.status(self.clock()),
            "robot_link": self.robot.as_json(),
        }
