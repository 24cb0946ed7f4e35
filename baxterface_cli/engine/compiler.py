"""Script -> timeline: `compile_script` walks the AST with a clock.

Each statement becomes changes on the timeline's tracks (timeline.py): eyes
(x, y), lids, head pan, the expression's numbers (a named skin, mouth or brows is a
point of them, reached over a short crossfade), the emotion's name, speech (its
mouth shapes over the face's mouth), and cues of robot effects (see `effects`).
Changes are applied in time order, each starting from wherever its track is at
that moment, so `together` blocks and interrupted moves compose. The named parts
that themes of pictures show are read off the numbers afterwards (pictures.py).
"""

from __future__ import annotations

import random
from typing import TYPE_CHECKING, Any, Callable, Dict, List, NamedTuple, Optional, Sequence, Tuple

from ..core.expression import BROW_FIELDS, CONTROLS, Expression, with_fields
from ..core.face_constants import EMOTIONS, HEAD_SPEED_RATIO, HEAD_TOP_SPEED, TIMING, USUAL_VARIANT
from ..core.face_state import FaceState, Parts
from ..core.geometry import clamp_pan, clamp_to_ellipse, dynamic_look, to_radians
from ..core.presets import (
    FACE_FIELDS,
    PART_FIELDS,
    blend,
    blend_lids,
    from_parts,
    mood_weights,
)
from ..language import syntax_tree as n
from ..language.statements import KINDS, describe, move_seconds, statement_seconds
from . import effects as fx
from .effects import Cue
from .session_program import not_here
from .shape_tracks import ShapeTracks
from .take_over import Carry, carry_over
from .timeline import CROSSFADE, Said, Span, TextToSpeech, Timeline, Track
from .tracks import Owner

if TYPE_CHECKING:
    from ..speech.recordings import Recordings
    from ..speech.synthesis import Utterance


class _Event(NamedTuple):
    at: float
    order: int
    apply: Callable[[float], None]
    owner: float  # when the statement that queued it began


class _Compiler:
    """Walks the AST with a clock, queueing track changes to apply in time order."""

    def __init__(
        self,
        script: n.Script,
        rng: random.Random,
        start: FaceState,
        crossfade: float,
        speak: TextToSpeech,
        recordings: Optional[Recordings] = None,
    ) -> None:
        self.definitions = script.definitions
        self.speak = speak
        self.filename = script.filename
        self.recordings = recordings
        self.rng = rng
        self.crossfade = crossfade
        self.owner = Owner()  # the statement being compiled, then the one whose event is applied
        self.eyes = Track((start.eye_x, start.eye_y), self.owner)
        self.lids = Track(start.eyelids, self.owner)
        self.head = Track(start.head_pan, self.owner)
        self.shape = ShapeTracks(start.expression, self.owner)
        self.moods: List[Tuple[float, float, float]] = []
        self.emotions: List[Tuple[float, str]] = []
        self.cues: List[Cue] = []
        self.spans: List[Span] = []
        self.speech: List[Said] = []
        self.events: List[_Event] = []
        self.exit_at: Optional[float] = None

    def later(self, at: float, apply: Callable[[float], None]) -> None:
        self.events.append(_Event(at, len(self.events), apply, self.owner.at))

    def run(self, events: List[_Event]) -> None:
        for event in sorted(events, key=lambda e: (e.at, e.order)):
            self.owner.at = event.owner
            event.apply(event.at)

    def sequence(self, body: Sequence[Any], t: float) -> float:
        for statement in body:
            if self.exit_at is not None:
                break
            t = self.statement(statement, t)
        return t

    def statement(self, s: n.Statement, t: float) -> float:
        self.owner.at = t
        end = COMPILE_STEPS[type(s)](self, s, t)
        if not isinstance(s, (n.Block, n.Call)):  # a block's statements have spans of their own
            self.spans.append(Span(t, end, s.pos.line, describe(s)))
        return end

    # -- blocks

    def do_repeat(self, s: n.Repeat, t: float) -> float:
        for _ in range(s.count):
            t = self.sequence(s.body, t)
        return t

    def do_together(self, s: n.Together, t: float) -> float:
        return max([self.sequence((child,), t) for child in s.body], default=t)

    def do_call(self, s: n.Call, t: float) -> float:
        return self.sequence(self.definitions[s.name].body, t)

    def do_define(self, s: n.Define, t: float) -> float:
        return t

    def do_use(self, s: n.Use, t: float) -> float:  # its definitions were read when it was parsed
        return t

    # -- the face

    def do_emotion(self, s: n.Emotion, t: float) -> float:
        spec = EMOTIONS[s.name]
        mouth, brows = self.rng.choice(spec.variants)  # drawn even when named: later picks stay the same
        if s.variant is not None:
            mouth, brows = spec.variants[s.variant - 1]

        def lids_first(at: float) -> None:
            self.emotions.append((at, s.name))
            self.lids.move(at, spec.lid_seconds, spec.eyelids)

        self.later(t, lids_first)
        end = t + statement_seconds(s)
        self.change_shape(end, from_parts(Parts(spec.skin, mouth, brows)), FACE_FIELDS)
        return end

    def do_feeling(self, s: n.Feeling, t: float) -> float:
        seconds = statement_seconds(s)
        self.express(s.weights, s.timing.duration, s.timing.easing, t, seconds, s.variants)
        return t + statement_seconds(s)

    def do_mood(self, s: n.Mood, t: float) -> float:
        duration = move_seconds(s)
        weights = mood_weights(s.valence, s.arousal) or (("default", 1.0),)
        self.later(t, lambda at: self.moods.append((at, s.valence, s.arousal)))
        self.express(weights, duration, s.timing.easing, t, duration)
        return t + duration

    def express(
        self,
        weights: Sequence[Tuple[str, float]],
        duration: Optional[float],
        easing: str,
        t: float,
        lids: float,
        variants: Sequence[Optional[int]] = (),
    ) -> None:
        """Morph to a blend of emotions, the lids with the rest, over `duration` or (None) the
        lids' own time: an intensity shows at once, where a bare emotion moves its lids first.
        Each emotion shows its `variants` entry (from 1), or else its usual variant."""
        presets = []
        for i, (name, weight) in enumerate(weights):
            spec = EMOTIONS[name]
            self.rng.choice(spec.variants)  # drawn as it always was, so later bare emotions pick the same
            written = variants[i] if i < len(variants) else None
            mouth, brows = spec.variants[USUAL_VARIANT[name] if written is None else written - 1]
            presets.append((from_parts(Parts(spec.skin, mouth, brows)), weight))
        target = blend(presets)
        label = max(weights, key=lambda w: w[1])[0]

        seconds = lids if duration is None else duration

        def start(at: float) -> None:
            self.emotions.append((at, label))
            self.lids.move(at, seconds, blend_lids(tuple(weights)), easing)

        self.later(t, start)
        self.change_shape(t, target, FACE_FIELDS, seconds, easing)

    def change_shape(
        self,
        t: float,
        target: Expression,
        fields: Sequence[str],
        duration: Optional[float] = None,
        easing: str = "linear",
    ) -> None:
        """Morph `fields` of the expression to `target`'s (a part swap by default: over the
        crossfade); themes of pictures crossfade to the named parts nearest where it ends."""

        def apply(at: float) -> None:
            seconds = self.crossfade if duration is None else duration
            goal = with_fields(self.shape.value(at), target, fields)
            self.shape.move(at, seconds, goal, easing, fields)

        self.later(t, apply)

    def do_wink(self, s: n.Wink, t: float) -> float:
        field = f"lid_{s.side}"

        def wink(at: float) -> None:
            before = self.shape.value(at)
            shut = before._replace(**{field: 0.0})
            self.shape.move(at, TIMING.wink_close, shut, fields=(field,))
            self.shape.move(
                at + TIMING.wink_close + TIMING.wink_hold, TIMING.wink_open, before, fields=(field,)
            )

        self.later(t, wink)
        return t + statement_seconds(s)

    def do_adjust(self, s: n.Adjust, t: float) -> float:
        duration = move_seconds(s)
        fields = CONTROLS[(s.part, s.control)].sides[s.side]
        target = Expression()._replace(**{f: s.value for f in fields})
        if s.part in ("eyelids", "pupils", "eyes"):  # the eyes: no named part to change
            self.later(t, lambda at: self.shape.move(at, duration, target, s.timing.easing, fields))
        else:
            self.change_shape(t, target, fields, duration, s.timing.easing)
        return t + duration

    def do_look(self, s: n.Look, t: float) -> float:
        duration, easing = move_seconds(s), s.timing.easing
        if not s.dynamic:
            target = clamp_to_ellipse(s.x, s.y)
            self.later(t, lambda at: self.eyes.move(at, duration, target, easing))
            return t + duration

        def dynamic(at: float) -> None:
            pan, eye_x = dynamic_look(to_radians(s.x), self.head.value(at))
            if pan is not None:
                self.pan_head(at, pan, duration, easing)
            self.eyes.move(at, duration, clamp_to_ellipse(eye_x, s.y), easing)

        self.later(t, dynamic)
        return t + duration

    def pan_head(self, at: float, target: float, duration: float, easing: str) -> None:
        """Move the head track, and cue the robot with the speed that keeps pace with it."""
        start = self.head.value(at)
        self.head.move(at, duration, target, easing)
        self.cues.append(Cue(at, fx.HeadPan(target, head_speed(start, target, duration), duration)))

    def do_blink(self, s: n.Blink, t: float) -> float:
        def blink(at: float) -> None:
            before = self.lids.value(at)
            self.lids.move(at, TIMING.blink_close, 0.0)
            self.lids.move(at + TIMING.blink_close, TIMING.blink_open, before)

        self.later(t, blink)
        return t + statement_seconds(s)

    def do_eyelids(self, s: n.Eyelids, t: float) -> float:
        duration = move_seconds(s)
        self.later(t, lambda at: self.lids.move(at, duration, s.openness, s.timing.easing))
        return t + duration

    # A named part is a point of the numbers: the drawn face morphs to it over the crossfade,
    # themes of pictures crossfade to it.

    def do_skin(self, s: n.Skin, t: float) -> float:
        self.change_shape(t, from_parts(Parts(skin=s.index)), PART_FIELDS["skin"])
        return t

    def do_mouth(self, s: n.Mouth, t: float) -> float:
        self.change_shape(t, from_parts(Parts(mouth=s.name)), PART_FIELDS["mouth"])
        return t

    def do_brows(self, s: n.Brows, t: float) -> float:
        self.change_shape(
            t, from_parts(Parts(brows=s.name)), BROW_FIELDS[s.side] if s.side else PART_FIELDS["brows"]
        )
        return t

    def do_wait(self, s: n.Wait, t: float) -> float:
        return t + statement_seconds(s)

    # -- the robot

    def do_wobble(self, s: n.Wobble, t: float) -> float:
        duration = move_seconds(s)
        self.later(t, lambda at: self.pan_head(at, clamp_pan(s.angle), duration, s.timing.easing))
        return t + duration

    def cue(self, t: float, effect: fx.Effect) -> None:
        self.later(t, lambda at: self.cues.append(Cue(at, effect)))

    def do_nod(self, s: n.Nod, t: float) -> float:
        seconds = statement_seconds(s)
        self.cue(t, fx.HeadNod(seconds))
        return t + seconds

    def do_enable(self, s: n.Enable, t: float) -> float:
        self.cue(t, fx.SetEnabled(True))
        return t

    def do_disable(self, s: n.Disable, t: float) -> float:
        self.cue(t, fx.SetEnabled(False))
        return t

    def do_follow(self, s: n.Follow, t: float) -> float:
        self.cue(t, fx.SetFollowing(s.target, s.dynamic))
        if s.target is None:  # stopping recentres the eyes, as the original did
            self.later(t, lambda at: self.eyes.move(at, TIMING.look, (0.0, 0.0)))
        return t

    def do_say(self, s: n.Say, t: float) -> float:
        from ..speech.natural_voices import mouth

        if s.file is not None:
            if self.recordings is None:
                from ..speech.recordings import Recordings

                self.recordings = Recordings.for_script(self.filename)
            utterance, keys = self.recordings.recite(s)
        else:
            from ..speech.espeak_process import SynthesisFailed
            from ..speech.recordings import RecordingError

            try:
                utterance = self.speak(s.text, s.voice, s.rate)
            except SynthesisFailed as e:  # espeak-ng crashed on this text: this `say` cannot be said
                raise RecordingError(str(e), s) from None
            keys = mouth(utterance)
        said = Said(t, utterance, keys)
        self.later(t, lambda at: self.speech.append(said))
        self.cue(t, fx.Speech(utterance))
        return t + utterance.duration

    def do_exit(self, s: n.Exit, t: float) -> float:
        # The sleep face, fully faded in, is the last thing shown.
        end = self.do_emotion(n.Emotion("sleep", pos=s.pos), t) + self.crossfade
        self.cue(end, fx.ShutDown())
        self.exit_at = end
        return end


def _compile_steps() -> Dict[type, Callable[[_Compiler, Any, float], float]]:
    """Each statement's compile step, by its node: `do_<name>` (language/statements.py names it)."""
    missing = [f"do_{kind.name}" for kind in KINDS.values() if not hasattr(_Compiler, f"do_{kind.name}")]
    if missing:
        raise TypeError(f"statements without a compile step: write _Compiler.{', '.join(missing)}")
    return {node: getattr(_Compiler, f"do_{kind.name}") for node, kind in KINDS.items()}


COMPILE_STEPS = _compile_steps()


def head_speed(start: float, target: float, duration: float) -> float:
    """The speed ratio that pans the head from `start` to `target` in `duration` seconds."""
    if duration <= 0:
        return HEAD_SPEED_RATIO[1]
    low, high = HEAD_SPEED_RATIO
    return min(high, max(low, abs(target - start) / duration / HEAD_TOP_SPEED))


def compile_script(
    script: n.Script,
    seed: Optional[int] = 0,
    start: Optional[FaceState] = None,
    crossfade: Optional[float] = None,
    speak: Optional[TextToSpeech] = None,
    recordings: Optional[Recordings] = None,
    carry: Optional[Carry] = None,
    rng: Optional[random.Random] = None,
) -> Timeline:
    """Compile a parsed script; the same script and seed give the same timeline.

    Part swaps blend over `crossfade` seconds: by default CROSSFADE for a
    script and none (a cut, as the old node did) for legacy commands. `say`
    speaks through `speak`, by default the espeak-ng engine, which is only
    loaded when a script says something (`extras.MissingTool` without it).
    `say file` reads from `recordings`, by default the script's folder, any
    path in it (`speech.recordings.RecordingError` for a file it cannot say):
    give texts from elsewhere (a network) a confined one. `carry` lets the statements begun in
    a timeline this one takes over from finish what they started (a live face's commands).
    `rng`, in place of `seed`: the random stream to draw on, left where this script's draws end
    (a script compiled in pieces, as the studio's session is, draws what it would whole).
    """
    refused = not_here(script, "a timeline compiled alone (compile_script)")
    if refused is not None:  # handlers and waits need the live session (engine/live_session.py)
        raise refused
    if crossfade is None:
        crossfade = 0.0 if script.legacy else CROSSFADE
    compiler = _Compiler(
        script, rng or random.Random(seed), start or FaceState(), crossfade, speak or engine_say, recordings
    )
    if carry is not None:
        carry_over(compiler, carry)
    end = compiler.sequence(script.body, 0.0)
    compiler.run(compiler.events)
    tails = [end, compiler.eyes.end, compiler.lids.end, compiler.head.end, compiler.shape.end]
    tails += [c.at + c.effect.duration for c in compiler.cues]
    duration = max(tails)
    if compiler.exit_at is not None:
        duration = compiler.exit_at
    compiler.spans.sort(key=lambda s: (s.start, s.line))
    return Timeline(
        compiler.eyes,
        compiler.lids,
        compiler.head,
        compiler.emotions,
        compiler.cues,
        compiler.spans,
        duration,
        start or FaceState(),
        compiler.speech,
        compiler.shape,
        sorted(compiler.moods),
    )


def engine_say(text: str, voice: Optional[str], rate: Optional[int]) -> Utterance:
    from ..core.voices import DEFAULT_RATE, default_voice, natural

    voice, rate = voice or default_voice(), rate or DEFAULT_RATE
    if natural(voice):
        from ..speech import natural_voices

        try:
            return natural_voices.say(text, voice, rate)
        except natural_voices.VoiceMissing:  # said once; espeak-ng speaks in its place
            voice = natural_voices.FALLBACK
    from ..speech.synthesis import engine

    return engine().say(text, voice, rate)
