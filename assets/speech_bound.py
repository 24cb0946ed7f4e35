"""Measure the most seconds a character takes to say, in every espeak-ng voice: for durations.py.

`check` bounds a `say` without speaking it (language/durations.py, `speech_bound`); this says
characters of each kind that voices spell out by name, in every voice at 80 words a minute
(espeak-ng's slowest), and prints the slowest of each kind beside the bound's figure. One
process per voice: espeak-ng 1.51 crashes on a few texts (`{}[]` in ky, `1234567890` in kl),
which are reported and skipped.

    python assets/speech_bound.py
"""

from __future__ import annotations

import json
import string
import subprocess
import sys
from typing import Dict, List, Optional

KINDS = {
    "letter": ["qwrtzpsdfghjklxcvbnm", "q w r t z p s d f g"],
    "digit": ["1234567890", "7 7 7 7 7 7"],
    "sign": [c * 6 for c in string.punctuation],
    "other": ["我们的中文字符测试", "アイウエオカキクケコ", "ሀሁሂሃሄ", "ཀཁགངཅཆ", "𠀀𠀁𠀂𠀃"]
    + ["\ufdfa" * 3, "ⅧⅫ", "😀🤖👍", "สวัสดีชาวโลก", "приветмир"],
}
ONE_VOICE = """
import json, sys
from baxterface_cli.speech.synthesis import engine
texts = json.loads(sys.argv[2])
print(json.dumps({t: engine().say(t, sys.argv[1], 80).duration / len(t) for t in texts}))
"""


def main() -> None:
    from baxterface_cli.language.durations import SECONDS_A_CHARACTER_AT_80, WORST_AT_80
    from baxterface_cli.speech.synthesis import VOICES

    worst = {kind: (0.0, "", "") for kind in KINDS}
    every = [text for texts in KINDS.values() for text in texts]
    for voice in sorted(VOICES):
        found = _said(voice, every)
        if found is None:  # one of them crashes espeak-ng: each alone, to skip only that one
            found = {}
            for text in every:
                alone = _said(voice, [text])
                if alone is None:
                    print(f"espeak-ng crashed: {voice} {text!r}", file=sys.stderr)
                found.update(alone or {})
        for kind, texts in KINDS.items():
            for text in texts:
                if text in found and found[text] > worst[kind][0]:
                    worst[kind] = (found[text], voice, text)
    bound = dict(SECONDS_A_CHARACTER_AT_80, other=WORST_AT_80)
    for kind, (per, voice, text) in worst.items():
        print(f"{kind:7s} slowest {per:.2f} s a character ({voice}, {text!r}); counted {bound[kind]:.2f}")


def _said(voice: str, texts: List[str]) -> Optional[Dict[str, float]]:
    """Seconds a character of each text takes in `voice`; None if espeak-ng crashed."""
    run = subprocess.run([sys.executable, "-c", ONE_VOICE, voice, json.dumps(texts)], capture_output=True)
    return json.loads(run.stdout) if run.returncode == 0 else None


if __name__ == "__main__":
    main()
