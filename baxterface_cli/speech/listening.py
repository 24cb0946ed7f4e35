"""Which listener hears words, chosen in this one place for every live end (`play --listen`, the
node's ears) and for `--hear`.

Where the `[hear]` extra is installed, Moonshine transcribes what people say and the phrases are
found in its words (utterances.py): it also tells each whole utterance, for `heard "..."`. Elsewhere
the word spotter of the `[lipsync]` extra listens for the phrases alone (word_spotter.py: hama's
phonemes, or pocketsphinx's keyphrase search where hama does not run). The environment variable
BAXTERFACE_LISTENER=spotter chooses the spotter even so (=moonshine: Moonshine, as by default).
"""

from __future__ import annotations

import importlib.util
import os
from typing import Any, Callable, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ..core.face_constants import LIMITS
from ..extras import MissingTool
from . import moonshine, voice_activity
from .audio_files import probe
from .word_spotter import RATE, Heard, WordError, WordSpotter, read_recording
from .word_spotter import listenable as spotter_listenable

MOONSHINE = "moonshine"
SPOTTER = "spotter"  # the word spotter, hama's or pocketsphinx's as it finds them
CHOICE = "BAXTERFACE_LISTENER"


class Listened(NamedTuple):
    words: List[Heard]  # the phrases heard, in order
    said: List[Any]  # the utterances heard (utterances.Said), where the listener tells them


def default_method() -> str:
    """The listener chosen (CHOICE), else Moonshine where it is installed, else the spotter."""
    chosen = os.environ.get(CHOICE, "")
    if chosen:
        if chosen not in (MOONSHINE, SPOTTER):
            raise WordError(f"{CHOICE}={chosen}: the listener is '{MOONSHINE}' or '{SPOTTER}'")
        return chosen
    return MOONSHINE if moonshine.available() and voice_activity.available() else SPOTTER


def check() -> None:
    """MissingTool, in one line naming the extras, when no listener is installed at all."""
    if default_method() == MOONSHINE:
        return
    if importlib.util.find_spec("pocketsphinx") is None:
        raise MissingTool(
            "hearing words needs Moonshine or pocketsphinx: pip install 'baxterface[hear]' "
            "(or 'baxterface[lipsync]')"
        )


def listener(
    words: Sequence[str],
    on_word: Callable[[str, float], None],
    clock: Optional[Callable[[], float]] = None,
    speaking: Optional[Callable[[float], bool]] = None,
    barge_in: bool = False,
    on_heard: Optional[Callable[[str, float], None]] = None,
    saying: Optional[Callable[[float, float], str]] = None,
    method: Optional[str] = None,
    live: bool = True,
    **options: Any,
) -> Any:
    """A listener for `words` (see the module's docstring); `options` are its own settings. `live`:
    sound as it comes, whose looks Moonshine spaces by their cost; a recording's are on a fixed
    beat, so what is heard in it is the same on any machine, however busy."""
    check()
    method = method or default_method()
    if method == MOONSHINE:
        from .utterances import UtteranceListener

        if not any(w.strip() for w in words):
            raise WordError("no words to listen for")
        return UtteranceListener(
            words, on_word, clock, speaking, barge_in, on_heard=on_heard, saying=saying, paced=live, **options
        )
    spotter = None if method == SPOTTER else method  # it chooses between hama and pocketsphinx
    return WordSpotter(words, on_word, clock, speaking, barge_in, method=spotter, **options)


def listenable(words: Sequence[str]) -> Tuple[List[str], List[Tuple[str, str]], List[str]]:
    """The phrases the listener may listen for at once; those it cannot, with why; and those past
    its bound (see word_spotter.listenable). Moonshine hears any words, as many as are given."""
    if default_method() == MOONSHINE:
        return list(dict.fromkeys(" ".join(w.lower().split()) for w in words if w.strip())), [], []
    return spotter_listenable(words)


def spot_samples(
    samples: np.ndarray,
    words: Sequence[str],
    block: float = 0.05,
    speaking: Optional[Callable[[float], bool]] = None,
    barge_in: bool = False,
    **options: Any,
) -> Listened:
    """What is heard in 16 kHz mono samples, fed as a microphone would, in blocks of `block`
    seconds; times from the recording's start. `options`: `listener`'s."""
    heard = listener(
        words, lambda word, at: None, speaking=speaking, barge_in=barge_in, live=False, **options
    )
    step = max(1, int(block * RATE))
    for i in range(0, len(samples), step):
        piece = samples[i : i + step]
        heard.feed(piece, end=(i + len(piece)) / RATE)
    # A phrase at the very end is decided by silence after it, as a microphone would hear.
    heard.feed(np.zeros(int(1.0 * RATE), np.int16), end=len(samples) / RATE + 1.0)
    heard.close()
    return Listened(heard.heard, list(getattr(heard, "said", [])))


def spot_file(path: str, words: Sequence[str], **options: Any) -> Listened:
    """What is heard in a recording (see `spot_samples`). The spotter's work grows with each phone
    of the phrases in each second of sound, so their product is bounded, from the recording's
    header before it is read (WordError past LIMITS.max_phone_seconds); Moonshine's does not."""
    seconds = probe(path)
    method = options.get("method") or default_method()
    if method != MOONSHINE:
        spotter = WordSpotter(words, lambda word, at: None, **options)
        spotter.close()
        work = spotter.phones * seconds
        if work > LIMITS.max_phone_seconds:
            phrases = f"{len(spotter.words)} phrase" + ("" if len(spotter.words) == 1 else "s")
            raise WordError(
                f"{phrases} of {spotter.phones} phones, every spelling counted, over "
                f"{seconds:.0f} s of sound is too much to listen for ({work:,.0f} phone-seconds; the "
                f"limit is {LIMITS.max_phone_seconds:,})"
            )
    return spot_samples(read_recording(path), words, **options)
