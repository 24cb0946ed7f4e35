"""Rewrite baxterface_cli/data/voices.txt from the espeak-ng on this machine.

    python assets/list_voices.py

Each voice name espeak-ng accepts (`espeak-ng -v NAME`), with the language it
speaks: names are its language codes, its voice files' names and their other
languages, kept if espeak-ng says something with them. A name that is one
voice's language or file is that voice's; one that is another language of
several voices is the one espeak-ng prefers (its lowest priority number).
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

OUT = Path(__file__).resolve().parent.parent / "baxterface_cli" / "data" / "voices.txt"


def main() -> None:
    listed = subprocess.run(["espeak-ng", "--voices"], capture_output=True, text=True, check=True)
    version = subprocess.run(["espeak-ng", "--version"], capture_output=True, text=True).stdout.split()
    by_language, by_file, other = {}, {}, {}
    for line in listed.stdout.splitlines()[1:]:
        _, code, _, name, path, *rest = line.split()
        name = name.replace("_", " ")
        by_language.setdefault(code.lower(), name)
        by_file.setdefault(path.rsplit("/", 1)[-1].lower(), name)
        for code2, priority in re.findall(r"\(([^ )]+) (\d+)\)", " ".join(rest)):
            if code2.lower() not in other or int(priority) < other[code2.lower()][0]:
                other[code2.lower()] = (int(priority), name)
    names = dict(by_file)  # a file's name, unless it is a language too
    names.update({code: name for code, (_, name) in other.items()})
    names.update(by_language)
    spoken = {}
    for code in sorted(names):
        said = subprocess.run(["espeak-ng", "-v", code, "-q", ""], capture_output=True)
        if said.returncode == 0:
            spoken[code] = names[code]
    header = [
        "# The voice names espeak-ng accepts (`espeak-ng -v NAME`), one a line, lower case, and after two",
        "# spaces the language each speaks: `check` validates a `say`'s voice against this list without",
        "# espeak-ng installed, and `baxterface voices` lists it.",
        f"# Made by assets/list_voices.py with espeak-ng {version[3] if len(version) > 3 else '?'} (the",
        '# variants, espeak-ng --voices=variant, "en+f3", are not voices of their own).',
    ]
    width = max(map(len, spoken))
    lines = [f"{code:<{width}}  {name}" for code, name in spoken.items()]
    OUT.write_text("\n".join(header + lines) + "\n", encoding="utf-8")
    print(f"wrote {len(lines)} voices to {OUT}")


if __name__ == "__main__":
    main()
