"""Draw the pictures in the docs into docs/images/, with the library and its exporters.

    python docs/make_pictures.py

Run it again after the theme or the renderer changes what a face looks like.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import List, Tuple

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from baxterface_cli import Face, parse
from baxterface_cli.idle import Animation
from baxterface_cli.renderer import Renderer
from baxterface_cli.rendering import render
from baxterface_cli.tables import EMOTIONS
from baxterface_cli.theme import Theme
from baxterface_cli.timeline import compile_script

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


def frame_shown(path: Path, t: float) -> np.ndarray:
    """The RGB frame a player shows at `t` in an animation Pillow reads (GIF, WebP)."""
    with Image.open(path) as image:
        start = 0.0
        for index in range(image.n_frames):
            image.seek(index)
            start += image.info.get("duration", 0) / 1000
            if start > t:
                break
        return np.asarray(image.convert("RGB"))


def video_frame(path: Path, t: float) -> np.ndarray:
    """The RGB frame of an MP4 shown at `t`, decoded by PyAV."""
    import av

    with av.open(str(path)) as video:
        shown = None
        for frame in video.decode(video=0):
            if frame.time > t + 1e-6:
                break
            shown = frame.to_ndarray(format="rgb24")
        return shown


def crossfade() -> Image.Image:
    """One frame halfway through a skin crossfade, as each format stores it, close up."""
    script = parse("happy; angry", "<crossfade>")
    animation = Animation(compile_script(script, seed=0))
    renderer = Renderer(Theme.default().layers((1024, 600)))
    t = 20 / 30  # a frame of the 0.6..0.75 s blend from skin 2 to skin 4
    x, y = 420, 380  # a cheek, where the skins' gradients are; shown twice its size
    box = (x, y, x + THUMB[0] // 2, y + THUMB[1] // 2)
    with tempfile.TemporaryDirectory() as tmp:
        panels = [("drawn", renderer.render(animation.sample(t))[..., ::-1])]
        for ext, read, label in [
            (".gif", frame_shown, "GIF: one palette"),
            (".mp4", video_frame, "MP4: H.264"),
            (".webp", frame_shown, "WebP: lossless"),
        ]:
            out = Path(tmp) / f"fade{ext}"
            render(animation, renderer, str(out), fps=30)
            panels.append((label, read(out, t)))
    crops = []
    for label, rgb in panels:
        crop = Image.fromarray(np.ascontiguousarray(rgb)).crop(box)
        crops.append((label, crop.resize(THUMB, Image.NEAREST)))
    return sheet(crops, columns=4)


def main() -> None:
    OUT.mkdir(exist_ok=True)
    save_sheet(emotions(), OUT / "emotions.png")
    save_sheet(looking(), OUT / "looking.png")
    hello().save(OUT / "hello.png", optimize=True)
    crossfade().save(OUT / "crossfade.png", optimize=True)
    for name in ("emotions.png", "looking.png", "hello.png", "crossfade.png"):
        print(OUT / name)


if __name__ == "__main__":
    main()
