"""Draw the pictures in the docs into docs/images/, with the public library only.

    python docs/make_pictures.py

Run it again after the theme or the renderer changes what a face looks like.
"""

from __future__ import annotations

from pathlib import Path
from typing import List, Tuple

from PIL import Image, ImageDraw, ImageFont

from baxterface_cli import Face
from baxterface_cli.tables import EMOTIONS

OUT = Path(__file__).resolve().parent / "images"
THUMB = (320, 188)  # 1024x600 over 3.2: the face's own proportions
LABEL_H = 30
GAP = 12
INK = (34, 34, 40)
PAPER = (255, 255, 255)


def font() -> ImageFont.ImageFont:
    try:
        return ImageFont.load_default(size=18)
    except TypeError:  # Pillow before 10.1 has only its small bitmap font
        return ImageFont.load_default()


def thumbnail(face: Face) -> Image.Image:
    # Drawn at the robot's size and shrunk, so the pictures show the face the
    # robot shows rather than the theme redrawn small.
    return face.image().resize(THUMB, Image.LANCZOS)


def sheet(faces: List[Tuple[str, Image.Image]], columns: int) -> Image.Image:
    """Thumbnails in a grid on white, each with its label centred underneath."""
    rows = -(-len(faces) // columns)
    cell_w, cell_h = THUMB[0] + GAP, THUMB[1] + LABEL_H
    out = Image.new("RGB", (columns * cell_w + GAP, rows * cell_h + GAP), PAPER)
    draw, text_font = ImageDraw.Draw(out), font()
    for i, (label, picture) in enumerate(faces):
        x, y = GAP + (i % columns) * cell_w, GAP + (i // columns) * cell_h
        out.paste(picture, (x, y))
        # Centred by hand: old Pillow's bitmap font ignores text anchors.
        left = x + (THUMB[0] - draw.textlength(label, font=text_font)) / 2
        draw.text((left, y + THUMB[1] + 5), label, fill=INK, font=text_font)
    return out


def save_sheet(image: Image.Image, path: Path) -> None:
    # 256 colours make the sheets a half to two thirds their RGB size. Ten skins share
    # one palette, so undithered gradients show rings; k-means refining of the
    # palette keeps the dither's speckle off the flat cheeks.
    palette = image.quantize(256, method=Image.Quantize.MEDIANCUT, kmeans=3)
    out = image.quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG)
    # The paper's nearest palette colour is a near-white that shows as a grey
    # box on a white page: make that entry white again.
    colours = out.getpalette()
    paper = out.getpixel((0, 0)) * 3
    colours[paper : paper + 3] = PAPER
    out.putpalette(colours)
    out.save(path, optimize=True)


def emotions() -> Image.Image:
    faces = []
    for name in EMOTIONS:
        face = Face()
        face.set_emotion(name, variant=0)
        faces.append((name, thumbnail(face)))
    return sheet(faces, columns=5)


def looking() -> Image.Image:
    faces = []
    for label, (x, y), openness in [
        ("look_at(0, 0)", (0, 0), 1.0),
        ("look_at(60, -60)", (60, -60), 1.0),
        ("look_at(-70, 30)", (-70, 30), 1.0),
        ("set_eyelids(0.45)", (0, 0), 0.45),
    ]:
        face = Face()
        face.look_at(x, y)
        face.set_eyelids(openness)
        faces.append((label, thumbnail(face)))
    return sheet(faces, columns=4)


def hello() -> Image.Image:
    face = Face()
    face.set_emotion("happy", variant=0)
    face.look_at(40, -20)
    return face.image()


def main() -> None:
    OUT.mkdir(exist_ok=True)
    save_sheet(emotions(), OUT / "emotions.png")
    save_sheet(looking(), OUT / "looking.png")
    hello().save(OUT / "hello.png", optimize=True)
    for name in ("emotions.png", "looking.png", "hello.png"):
        print(OUT / name)


if __name__ == "__main__":
    main()
