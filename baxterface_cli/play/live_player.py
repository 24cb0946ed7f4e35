"""`play`: a live session's frames on a screen in real time, every script, reacting or not.

The session (engine/live_session.py) runs on the player's clock, ticked a frame at a time. Frames
are scheduled on absolute times from the start (frame i at i/fps), so a slow frame makes the next
one come sooner, never the whole show later: a late frame is dropped rather than shown late.
Events come as they happen: words from the microphone (a WordSpotter on the microphone's thread,
whose words wait in a queue for the next frame), touches from clicks in the window (the place
found on the face as it was shown: drawing/touch_places.py), and an events file's lines at their
times. A show that is not live (no window clicks or microphone to wait for) ends where its
recorded run would (engine/session_run.py): once the session rests after the file's last event
and the face has finished moving; `--loop` then starts a fresh session from the beginning.

What the face says is heard with the frame that says it: a script that speaks opens the sound
device before the clock starts, and the session runs that device's latency ahead of the picture,
so each step's speech is known, and started, before the frame that begins it is shown.
"""

from __future__ import annotations

import contextlib
import math
import queue
import time
from typing import Any, Callable, List, Optional, Tuple

from ..core.face_state import FaceState
from ..drawing.renderer import Renderer
from ..drawing.touch_places import touched_place
from ..engine.effects import RobotStatus
from ..engine.live_session import LiveSession
from ..engine.session_log_file import SessionLogFile
from ..engine.session_run import resting
from ..engine.speaking_times import SpeakingTimes
from ..language import syntax_tree as n
from ..language.events import MOST_HEARD
from ..robot.rehearsal import Rehearsal
from ..speech.sound_device import START_AHEAD, SoundOut, SpeechCues
from .screens import status_line

Clock = Callable[[], float]
Polled = Callable[[], Optional[LiveSession]]  # a new session to play, or None to go on


class LivePlayer:
    """Frames of a live session on a screen, in real time, with the events that reach it."""

    def __init__(
        self,
        session: LiveSession,
        renderer: Renderer,
        screen: Any,
        fps: float = 30.0,
        trace: Any = None,
        duration: Optional[float] = None,
        clock: Clock = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
        sound: Optional[Callable[[], SoundOut]] = None,
        record: Optional[SessionLogFile] = None,
        follow: Optional[Rehearsal] = None,
        live: bool = False,
        speaks: bool = False,
        fresh: Optional[Callable[[], LiveSession]] = None,
    ) -> None:
        """`record`: the session's log file, told of each event and the session's lines as the
        frames take them (it only queues them: its own thread writes). `follow`: following against
        a recorded source (`--follow-from`). `live`: events may come at any time (a window's clicks,
        the microphone), so only the screen, `duration` or the face's exit ends the show.
        `speaks`: the script may say something, so the sound device opens before the clock starts
        (`sound` makes it). `fresh`: a new session of the script from its start, for `--loop`."""
        self.session = session
        self.record = record
        if record is not None:  # its lines from the first (a session made with its script has some)
            record.watch(session.face)
        self.renderer = renderer
        self.screen = screen
        self.fps = fps
        self.posts = tuple(trace.events) if trace is not None else ()
        self.source = trace.source if trace is not None else (lambda posted: "")
        self.duration = duration
        self.clock = clock
        self.sleep = sleep
        self.open_sound = sound
        self.sound: Optional[SoundOut] = None
        self.follow = follow
        self.live = live
        self.speaks = speaks
        self.fresh = fresh
        self.inbox: queue.Queue[Tuple[n.Event, Optional[float], str]] = queue.Queue(maxsize=1000)
        self.began: Optional[float] = None
        self.origin: Optional[float] = None  # the clock's time when the picture shows t = 0
        self.lead = 0.0  # how far the session runs ahead of the picture: the sound's latency
        self.frames_shown = 0
        self.position = 0.0  # the time of the last frame shown
        self._lap_end = 0.0  # with --loop, where the lap before ended: its last frames come at t < 0
        self.note = ""
        self._trace: List[Any] = []  # the file's events still to come
        self._showing: List[Any] = []  # what the face showed since the picture's time, oldest first
        self._robots: List[Tuple[float, RobotStatus]] = []  # and the robot's status, from when
        self._state: Optional[FaceState] = None
        self._cues: Optional[SpeechCues] = None
        self._spoken: Any = None  # the timeline whose speech the sound device plays, and its start
        self._said = SpeakingTimes()  # on the session's clock
        if hasattr(screen, "on_click"):
            screen.on_click(self.touch)

    # -- events in (any thread)

    def now(self) -> float:
        """The session's clock, the spotter's too: seconds since the show began (0 before)."""
        return 0.0 if self.origin is None else max(0.0, self.clock() - self.origin + self.lead)

    def hear(self, word: str, at: float) -> None:
        """A word heard, ending at `at` (the session's clock): the spotter's `on_word`."""
        self._put(n.Event("word", word), at, "microphone")

    def hear_said(self, text: str, at: float) -> None:
        """A whole utterance heard, ending at `at`: the listener's `on_heard`."""
        self._put(n.Event("heard", text[:MOST_HEARD]), at, "microphone")

    def touch(self, x: float, y: float) -> None:
        """A click at (x, y), fractions of the picture's width and height."""
        state = self._state
        place = touched_place(self.renderer.layers, state, x, y) if state is not None else ""
        self._put(n.Event("touch", place), None, "window")

    def speaking(self, at: float) -> bool:
        """Was the face speaking at `at` (the session's clock)? For the spotter, on its thread."""
        return self._said.speaking(at)

    def saying(self, start: float, end: float) -> str:
        """What the face said between `start` and `end`: for the listener, with barge-in."""
        return self._said.saying(start, end)

    def _put(self, event: n.Event, at: Optional[float], source: str) -> None:
        with contextlib.suppress(queue.Full):  # a storm beyond what the frames keep up with is lost
            self.inbox.put_nowait((event, at, source))

    # -- the show

    def run(self, loop: bool = False, hold: bool = False, poll: Optional[Polled] = None) -> float:
        """Play until the show ends (again and again with `loop`, a show that takes no time held
        rather than spun; with `hold`, its last frame kept), the screen closes, or the face exits.
        `poll`, called between frames, may hand over a new session, which starts from its
        beginning (`--watch`). Returns the seconds played."""
        self.began = self.clock()
        ended = False
        try:
            self._start(self.session)
            index = 0
            while self.screen.alive():
                fresh = poll() if poll is not None else None
                if fresh is not None:
                    self._start(fresh)
                    index = 0
                assert self.origin is not None
                t = max(index / self.fps, self.clock() - self.origin)  # a late frame is dropped
                end = self._take(t)
                if loop and end is not None and end > 0 and self.fresh is not None and t + self.lead >= end:
                    self._next_lap(end)  # as the session ahead reaches the end: laps back to back
                    index = math.floor((t - end) * self.fps + 1e-9)
                    continue
                if end is not None and t >= end:
                    self._show(end)
                    if not (loop or hold):
                        ended = True  # the last words are out but for what the device still holds
                        break
                    self.sleep(1.0 / self.fps)  # keep the last frame, and keep polling
                    continue
                # A hair over each tick counts as there (float rounding).
                index = math.floor(t * self.fps + 1e-9)
                self._show(index / self.fps)
                if self._cues is not None:
                    self._cues.tick(self.clock())
                index += 1
                wait = self.origin + index / self.fps - self.clock()
                if wait > 0:
                    self.sleep(wait)
        finally:
            if self.sound is not None and not ended:  # stopped early: not a word more
                self.sound.stop()
        return self.clock() - self.began

    def elapsed(self) -> float:
        """Seconds since `run` began (0 before)."""
        return 0.0 if self.began is None else self.clock() - self.began

    def length(self) -> float:
        """The show's length as far as it is known: `duration`, where it ends once that is known,
        else the end of what the face is doing (at least the time shown)."""
        end = self._end()
        if end is not None:
            return end
        face = self.session.face
        return max(self.position, face.started + face.timeline.duration)

    def _start(self, session: LiveSession, at: Optional[float] = None) -> None:
        """`session` from its beginning, the picture showing its t = 0 at the clock's `at` (now
        if None), later by the sound's latency: the session runs that far ahead, so its words are
        out in time."""
        if self.session is not session:
            self.session = session
            if self.record is not None:
                self.record.watch(session.face)
        if self.speaks and self.sound is None and self.open_sound is not None:
            self.sound = self.open_sound()  # before the clock starts: finding a device takes a while
        if self.sound is not None:
            self.sound.stop()  # a reloaded or restarted script does not talk over its old self
        heard = self.sound is not None and self.sound.available
        self.lead = self.sound.latency + START_AHEAD if heard else 0.0  # type: ignore[union-attr]
        self.origin = (self.clock() if at is None else at) + self.lead
        self._trace = list(self.posts)
        self._showing = [session.face.showing]
        self._robots = [(float("-inf"), session.face.robot)]
        self._cues = self._spoken = None
        self._said = SpeakingTimes()

    def _next_lap(self, end: float) -> None:
        """`--loop`: a fresh session, whose t = 0 is this lap's `end`, taken on from now, when the
        session (run `lead` ahead of the picture) has come to that end: its first words go to the
        sound device in time, so laps follow each other without a gap. The picture still shows this
        lap's last `lead` seconds, at t < 0 on the new lap's clock, from what the face showed."""
        assert self.origin is not None and self.fresh is not None
        session = self.fresh()
        self._showing = [(timeline, started - end, idle) for timeline, started, idle in self._showing]
        self._showing.append(session.face.showing)
        self._robots = [(at - end, robot) for at, robot in self._robots]
        self._robots.append((0.0, session.face.robot))
        self.session, self.origin, self._lap_end = session, self.origin + end, end
        if self.record is not None:
            self.record.watch(session.face)
        self._trace = list(self.posts)
        self._spoken = None  # its first words are followed as they begin; the lap before's are out
        self._said = SpeakingTimes()

    def _take(self, t: float) -> Optional[float]:
        """The session taken on to the picture's time `t` and its lead (events posted on the way);
        where the show ends, once that is known."""
        ahead = t + self.lead if self.duration is None else min(t + self.lead, self.duration)
        self._post_due(ahead)
        self.session.tick(ahead)
        face = self.session.face
        if self.record is not None:
            self.record.follow(self.session)
        if face.showing is not self._showing[-1]:
            self._showing.append(face.showing)
        if face.robot is not self._robots[-1][1]:
            self._robots.append((ahead, face.robot))
        self._follow_speech(ahead)
        return self._end()

    def _end(self) -> Optional[float]:
        """Where the show ends: `duration`, the face's exit, or, for a show that is not live, the
        time its session came to rest after the file's last event and the face's last move (a
        `forever` rests only once an events file has come to its end)."""
        session = self.session
        if session.exited and session.exited_at is not None:
            return session.exited_at if self.duration is None else min(self.duration, session.exited_at)
        if self.duration is not None:
            return self.duration
        if self.live or self._trace or not resting(session):
            return None
        main = session.main
        if main is not None and not main.done and main.runner.forever and not self.posts:
            return None  # nothing will come: it goes round until stopped
        face = session.face
        return max(self.posts[-1].at if self.posts else 0.0, face.started + face.timeline.duration)

    def _post_due(self, t: float) -> None:
        while self._trace and self._trace[0].at <= t:
            posted = self._trace.pop(0)
            self._post(posted.event, posted.at, self.source(posted))
        while True:
            try:
                event, at, source = self.inbox.get_nowait()
            except queue.Empty:
                return
            self._post(event, t if at is None else min(at, t), source)

    def _post(self, event: n.Event, at: float, source: str) -> None:
        if self.record is not None:
            self.record.event(at, event, source)
        self.session.post(event, at, source)

    def _show(self, t: float) -> None:
        lap_t = t + self._lap_end if t < 0 else t  # the lap before's last frames, at its own times
        self.position = lap_t
        # What the face showed at `t`: the session may have begun newer steps in its lead since.
        while len(self._showing) > 1 and self._showing[1][1] <= t:
            self._showing.pop(0)
        while len(self._robots) > 1 and self._robots[1][0] <= t:
            self._robots.pop(0)
        state = self.session.face.at(self._showing[0], t)
        robot = self._robots[0][1]
        note = self.note
        if self.follow is not None:
            state = self.follow.look(state, lap_t, robot)
            note = "  ".join(filter(None, (self.follow.note(), note)))
        self._state = state
        status = status_line(lap_t, self.length(), robot, state.head_pan, note)
        self.screen.show(self.renderer.render(state), status)
        self.frames_shown += 1

    def _follow_speech(self, now: float) -> None:
        """A timeline begun since the last frame: its speech is what the face says from its start
        on; what the one before still had to say is silenced (an interrupt cut it short)."""
        timeline, started = self.session.face.playing
        if not self._said.follow(timeline, started, now):
            return
        if self.sound is not None and self._spoken is not None:
            spoken, since = self._spoken
            if spoken.sounding(started - since):
                self.sound.stop()
        self._cues = None
        self._spoken = (timeline, started)
        if timeline.speech and self.open_sound is not None:
            if self.sound is None:  # a script that speaks where it was not seen to
                self.sound = self.open_sound()
            assert self.origin is not None
            self._cues = SpeechCues(self.sound, timeline.speech, self.origin + started)
            self._cues.tick(self.clock())
