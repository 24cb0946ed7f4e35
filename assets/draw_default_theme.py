"""Draw the default theme from its vector shapes and write it to assets/default/.

    python assets/draw_default_theme.py [FOLDER] [--size 1024x600]

The committed assets/default/ is this script's output at 1024x600 (`make theme`
rewrites it). The shapes themselves are in baxterface_cli/artwork.py.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from baxterface_cli.drawing import artwork
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.drawing.theme_manifest import Placed, parse_size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", nargs="?", default=str(Path(__file__).resolve().parent / "default"))
    parser.add_argument("--size", default="1024x600", type=parse_size)
    args = parser.parse_args()
    images = {key: Placed(image, (0, 0)) for key, image in artwork.draw_theme(args.size).items()}
    theme = Theme("default", args.size, artwork.LID_TRAVEL, images)
    for path in theme.export(args.folder, force=True, smallest=True):
        print(path)


if __name__ == "__main__":
    main()
