"""Draw the pictures in the docs into docs/images/, with the library and its exporters.

    python docs/make_pictures.py

Run it again after the theme or the renderer changes what a face looks like,
or the speech or its mouth shapes change. lipsync.png speaks, so it needs
espeak-ng (apt install espeak-ng). One picture alone:

    python -c "import make_pictures as m; m.save_sheet(m.mood_plane(), m.OUT / 'mood.png')"

from docs/.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import List, Tuple

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from baxterface_cli import Face, parse
from baxterface_cli.core.face_constants import EMOTIONS, REST, viseme_mouth
from baxterface_cli.core.presets import mood_weights
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.export.render_to_file import render
from baxterface_cli.extras import MissingTool
from baxterface_cli.speech.visemes import shape_at

OUT = Path(__file__).resolve().parent / "images"
THUMB = (320, 188)  # 1024x600 over 3.2: the face's own proportions
LABEL_H = 30
GAP = 12
INK = (34, 34, 40)
PAPER = (255, 255, 255)


def font(size: int = 18) -> ImageFont.ImageFont:
    try:
        return ImageFont.load_default(size=size)
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


def speech_mouths() -> Image.Image:
    """The default theme's speech mouths, close up: the mouth at the robot's own pixels."""
    box = (352, 410, 352 + THUMB[0], 410 + THUMB[1])  # the 320x188 round the mouth of a 1024x600 face
    cells = []
    for shape, sounds in [
        ("closed", "p b m"),
        ("slight", "most consonants"),
        ("fv", "f v"),
        ("lth", "l th"),
        ("wide", "e i"),
        ("round", "o u w"),
        ("open", "a as in father"),
    ]:
        face = Face()
        # Face.set_mouth takes the emotions' mouths only: speech shapes come with `say`.
        face.state = face.state.replace(mouth=viseme_mouth(shape))
        cells.append((f"speak-{shape}: {sounds}", face.image().crop(box)))
    cells.append(("smile: at rest", Face().image().crop(box)))
    return sheet(cells, columns=4)


SMALL = (224, 131)  # the robot's face at 7/32: for sheets of many faces
INTENSITIES = (0.33, 0.67, 1.0)
MOODS = (-1.0, -0.5, 0.0, 0.5, 1.0)  # valence across, arousal up


def small(image: Image.Image) -> Image.Image:
    return image.resize(SMALL, Image.LANCZOS)


def upright(text: str, text_font: ImageFont.ImageFont) -> Image.Image:
    """A label turned to read upwards, for a vertical axis."""
    probe = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    width = int(probe.textlength(text, font=text_font)) + 4
    label = Image.new("RGB", (width, 24), PAPER)
    ImageDraw.Draw(label).text((2, 2), text, fill=INK, font=text_font)
    return label.rotate(90, expand=True)


def labelled_grid(
    rows: List[Tuple[str, List[Tuple[str, Image.Image]]]],
    columns: List[str],
    row_title: str = "",
    column_title: str = "",
    label_w: int = 110,
) -> Image.Image:
    """Faces in rows and columns: a label left of each row, a heading over each column, and an
    optional caption under each face; `row_title` runs up the left, `column_title` along the top."""
    big, little = font(18), font(14)
    captioned = any(caption for _, cells in rows for caption, _ in cells)
    cell_w, cell_h = SMALL[0] + GAP // 2, SMALL[1] + (22 if captioned else GAP // 2)
    side = 28 if row_title else 0
    top = (28 if column_title else 0) + 26
    out = Image.new(
        "RGB", (side + label_w + len(columns) * cell_w + GAP, top + len(rows) * cell_h + GAP), PAPER
    )
    draw = ImageDraw.Draw(out)
    x0 = side + label_w
    if column_title:
        left = x0 + (len(columns) * cell_w - draw.textlength(column_title, font=big)) / 2
        draw.text((left, 4), column_title, fill=INK, font=big)
    for c, heading in enumerate(columns):
        left = x0 + c * cell_w + (SMALL[0] - draw.textlength(heading, font=big)) / 2
        draw.text((left, top - 24), heading, fill=INK, font=big)
    if row_title:
        title = upright(row_title, big)
        out.paste(title, (2, top + (len(rows) * cell_h - title.height) // 2))
    for r, (label, cells) in enumerate(rows):
        y = top + r * cell_h
        draw.text(
            (side + label_w - 8 - draw.textlength(label, font=big), y + SMALL[1] // 2 - 10),
            label,
            fill=INK,
            font=big,
        )
        for c, (caption, picture) in enumerate(cells):
            x = x0 + c * cell_w
            out.paste(picture, (x, y))
            if caption:
                left = x + (SMALL[0] - draw.textlength(caption, font=little)) / 2
                draw.text((left, y + SMALL[1] + 3), caption, fill=INK, font=little)
    return out


def side_by_side(*images: Image.Image) -> Image.Image:
    out = Image.new(
        "RGB", (sum(i.width for i in images) + GAP * (len(images) - 1), max(i.height for i in images)), PAPER
    )
    x = 0
    for image in images:
        out.paste(image, (x, 0))
        x += image.width + GAP
    return out


def intensities() -> Image.Image:
    """Every emotion at three intensities, variant 0: `face.set_emotion_intensity(name, x)`."""
    rows = []
    for name in EMOTIONS:
        cells = []
        for intensity in INTENSITIES:
            face = Face()
            face.set_emotion_intensity(name, intensity, variant=0)
            cells.append(("", small(face.image())))
        rows.append((name, cells))
    headings = [f"{x:g}" for x in INTENSITIES]
    half = (len(rows) + 1) // 2
    return side_by_side(
        *(labelled_grid(part, headings, column_title="intensity") for part in (rows[:half], rows[half:]))
    )


def blend_words(weights: Tuple[Tuple[str, float], ...]) -> str:
    """A blend as a script writes it: `happy 0.52 + wake_up 0.48`."""
    return " + ".join(f"{name.replace(' ', '_')} {weight:.2f}" for name, weight in weights) or "default"


def mood_plane() -> Image.Image:
    """`face.set_mood(valence, arousal)` over the plane, each face captioned with the blend it is."""
    rows = []
    for arousal in reversed(MOODS):
        cells = []
        for valence in MOODS:
            face = Face()
            face.set_mood(valence, arousal)
            cells.append((blend_words(mood_weights(valence, arousal)), small(face.image())))
        rows.append((f"{arousal:g}", cells))
    return labelled_grid(
        rows,
        [f"{v:g}" for v in MOODS],
        row_title="arousal: calm (-1) to excited (1)",
        column_title="valence: unpleasant (-1) to pleasant (1)",
        label_w=50,
    )


def morph(script: str = "sad in 1.5s", frames: int = 6) -> Image.Image:
    """The same change in the default theme (a morph: one mouth bending) and in a theme of
    pictures (its exported copy: a crossfade of two mouths)."""
    seed = next(s for s in range(50) if compile_script(parse(script), seed=s).sample(9.0).mouth == "sad")
    timeline = compile_script(parse(script), seed=seed)  # the variant with the frown
    times = [timeline.duration * k / (frames - 1) for k in range(frames)]
    with tempfile.TemporaryDirectory() as folder:
        Theme.default().export(Path(folder) / "pictures")
        themes = [("drawn", Theme.default()), ("pictures", Theme.load(Path(folder) / "pictures"))]
        rows = []
        for label, theme in themes:
            renderer = Renderer(theme.layers((1024, 600)))
            cells = []
            for t in times:
                rgb = np.ascontiguousarray(renderer.render(timeline.sample(t))[..., ::-1])
                cells.append(("", small(Image.fromarray(rgb))))
            rows.append((label, cells))
    return labelled_grid(
        rows, [f"{t:.1f} s" for t in times], column_title=f"{script}: from default", label_w=100
    )


def gesture_sheet(frames: int = 6) -> Image.Image:
    """Each of the face's gestures (`baxterface gestures`) at key frames across its length."""
    from baxterface_cli.language.parser import gestures

    renderer = Renderer(Theme.default().layers((1024, 600)))
    rows = []
    for name, gesture in gestures().items():
        timeline = compile_script(parse(name), seed=0)
        times = [gesture.seconds * (k + 0.5) / frames for k in range(frames)]
        cells = []
        for t in times:
            rgb = np.ascontiguousarray(renderer.render(timeline.sample(t))[..., ::-1])
            cells.append((f"{t:.1f} s", small(Image.fromarray(rgb))))
        rows.append((name, cells))
    columns = [f"{k + 1}/{frames}" for k in range(frames)]
    return labelled_grid(rows, columns, column_title="each gesture through its length", label_w=100)


LIPSYNC_TEXT = "Hello there, I am Baxter. Bob met Pam."
MOUTH_BOX = (366, 432, 658, 590)  # every mouth of the default theme at 1024x600, with a margin
WAVE = (70, 110, 170)
RESTING = (234, 236, 242)
CLOSED = (205, 55, 55)
FAINT = (160, 160, 170)


def lipsync(
    fps: int = 30, width: int = 1200, statement: str = "", filename: str = "<lipsync>"
) -> Image.Image:
    """One sentence over time: its sound, its words, and the mouth of every frame at `fps`.

    The sound and the word times are the utterance's own (espeak-ng's, or those found in a
    recording for `say file`), the mouths the real renderer's frames, cropped. A line is a
    stretch of the sentence, broken in the pauses, all at one scale: a frame is as wide as its mouth.
    """
    statement = statement or f'say "{LIPSYNC_TEXT}"'
    timeline = compile_script(parse(statement, filename))
    (said,) = timeline.speech
    sound = said.utterance
    renderer = Renderer(Theme.default().layers((1024, 600)))
    count = int(sound.duration * fps) + 1
    keys = said.mouth
    breaks = [round((key.at + after.at) / 2 * fps) for key, after in zip(keys, keys[1:]) if key.shape == REST]
    lines = list(zip([0] + breaks, breaks + [count]))
    margin = 24
    frame_w = (width - 2 * margin) // max(b - a for a, b in lines)
    frame_h = round(frame_w * (MOUTH_BOX[3] - MOUTH_BOX[1]) / (MOUTH_BOX[2] - MOUTH_BOX[0]))
    mouths, shapes = [], []
    for k in range(count):
        rgb = np.ascontiguousarray(renderer.render(timeline.sample(k / fps))[..., ::-1])
        mouths.append(Image.fromarray(rgb).crop(MOUTH_BOX).resize((frame_w, frame_h), Image.LANCZOS))
        shapes.append(shape_at(keys, k / fps)[0])
    samples = sound.samples.astype(np.float64)
    samples /= np.abs(samples).max()

    title_h, words_h, wave_h, axis_h, gap, legend_h = 36, 24, 64, 22, 16, 30
    line_h = words_h + wave_h + 4 + frame_h + axis_h + gap
    out = Image.new("RGB", (width, title_h + len(lines) * line_h + legend_h), PAPER)
    draw, big, small = ImageDraw.Draw(out), font(), font(14)
    how = sound.recording.method if sound.recording else f"voice {sound.voice}, {sound.rate} words a minute"
    title = f"{statement}: {how}, the mouth at {fps} fps"
    draw.text((margin, 8), title, fill=INK, font=big)
    for n, (first, end) in enumerate(lines):
        top = title_h + n * line_h
        wave_top, mid = top + words_h, top + words_h + wave_h / 2
        mouths_top = wave_top + wave_h + 4

        def x_at(t: float, first: int = first) -> float:
            return margin + (t * fps - first) * frame_w

        for k in range(first, end):
            x = x_at(k / fps)
            if shapes[k] == REST:  # a frame whose mouth rests: shaded behind the sound
                draw.rectangle([x, wave_top, x + frame_w - 1, wave_top + wave_h], fill=RESTING)
        # The waveform: each pixel column from the lowest sample under it to the highest.
        left, right = int(x_at(first / fps)), int(x_at(end / fps))
        for x in range(left, right):
            a, b = (round((first + (x + d - left) / frame_w) / fps * sound.sample_rate) for d in (0, 1))
            piece = samples[a:b]
            if piece.size:
                draw.line(
                    [(x, mid - piece.max() * wave_h / 2), (x, mid - piece.min() * wave_h / 2)], fill=WAVE
                )
        draw.line([(left, mid), (right, mid)], fill=WAVE)
        for k in range(first, end):
            x = int(x_at(k / fps))
            out.paste(mouths[k], (x, mouths_top))
            if shapes[k] == "closed":
                draw.rectangle(
                    [x, mouths_top, x + frame_w - 1, mouths_top + frame_h - 1], outline=CLOSED, width=2
                )
        for word in sound.words:
            if first <= word.at * fps < end:
                x = x_at(word.at)
                draw.line([(x, top + 4), (x, mouths_top - 1)], fill=INK)
                draw.text((x + 4, top + 2), word.text, fill=INK, font=big)
        axis = mouths_top + frame_h + 2
        for k in range(first, end + 1):
            x = x_at(k / fps)
            if k % (fps // 10) == 0:
                draw.line([(x, axis), (x, axis + 4)], fill=FAINT)
            if k % (fps // 5) == 0:
                draw.text((x - 10, axis + 5), f"{k / fps:.1f} s", fill=INK, font=small)

    # The legend: a swatch, then what it means.
    x, y = margin, title_h + len(lines) * line_h
    for swatch, meaning in [
        ({"fill": RESTING}, "the mouth at rest (the emotion's own): before, after and in pauses"),
        ({"outline": CLOSED, "width": 2}, "lips closed: p, b, m"),
    ]:
        draw.rectangle([x, y + 2, x + 28, y + 18], **swatch)
        draw.text((x + 36, y + 2), meaning, fill=INK, font=small)
        x += 36 + draw.textlength(meaning, font=small) + 40
    return out


def recorded_lipsync() -> Image.Image:
    """The lip-sync picture of scripts_examples/greeting.ogg, said with its words (`say file`)."""
    examples = Path(__file__).resolve().parent.parent / "scripts_examples"
    statement = (
        'say file "greeting.ogg" text "Good morning! I am Baxter. These words were recorded before the show."'
    )
    return lipsync(statement=statement, filename=str(examples / "recorded.face"), width=1400)


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


def sonar_walk(seconds: float = 12.0, width: int = 1000, height: int = 360) -> Image.Image:
    """A person walking back and forth past the sonar, and where each follower puts the eyes."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "support"))
    from baxterface_cli.robot.following import HumanFollower
    from traces import back_and_forth, faulty_trace, run

    readings = faulty_trace(back_and_forth(1.0), seconds, seed=1, second_object=True)
    lines = [
        ("person", [(t, truth) for t, _, truth in run(HumanFollower(), readings)], (150, 150, 150), 7),
        ("original", [(t, s) for t, s, _ in run(HumanFollower.original(), readings)], (214, 96, 77), 3),
        ("baxterface", [(t, s) for t, s, _ in run(HumanFollower(), readings)], (46, 110, 190), 3),
    ]
    image = Image.new("RGB", (width, height), PAPER)
    draw = ImageDraw.Draw(image)
    left, top, right, bottom = 70, 20, width - 20, height - 50

    def at(t: float, x: float) -> Tuple[float, float]:
        return left + (right - left) * t / seconds, top + (bottom - top) * (80 - x) / 160

    for x in (-80, -40, 0, 40, 80):
        draw.line([at(0, x), at(seconds, x)], fill=(225, 225, 225))
        draw.text((left - 10, at(0, x)[1]), f"{x:+d}" if x else "0", fill=INK, font=font(14), anchor="rm")
    for t in range(int(seconds) + 1):
        draw.text((at(t, -80)[0], bottom + 8), f"{t} s", fill=INK, font=font(14), anchor="mt")
    for _, points, colour, thickness in lines:
        shown = [at(t, x) for t, x in points if x is not None]
        draw.line(shown, fill=colour, width=thickness, joint="curve")
    x = left
    for name, _, colour, _ in lines:
        draw.line([(x, height - 14), (x + 30, height - 14)], fill=colour, width=5)
        draw.text((x + 38, height - 14), name, fill=INK, font=font(15), anchor="lm")
        x += 60 + draw.textlength(name, font=font(15))
    draw.text((right, height - 14), "eye x (pixels) over time", fill=INK, font=font(15), anchor="rm")
    return image


def face_following(times=(1.5, 3.2, 5.0, 6.6), scene="combined") -> Image.Image:
    """Camera frames of a synthetic scene (tests/support/face_streams.py or far_streams.py), where
    the follower looks in each (the cross), and the face `play --follow-from` draws for it."""
    import math
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "support"))
    import face_streams
    import far_streams
    from baxterface_cli.robot.following import DEGREES_PER_RADIAN, PIXELS_PER_ELEVATION
    from baxterface_cli.robot.person_finder import BAXTER_HEAD_CAMERA_HFOV
    from baxterface_cli.robot.rehearsal import Rehearsal

    stream = getattr(face_streams, scene, None) or getattr(far_streams, scene)
    stream = stream()

    class Frames:  # a --follow-from source made of the stream's frames
        has = frozenset({"image"})

        def rewind(self):
            return ((frame.t, "image", frame.image) for frame in stream.frames())

    images = {round(frame.t * 30): frame.image for frame in stream.frames()}
    timeline = compile_script(parse(f"follow face; wait {stream.seconds}s"))
    rehearsal = Rehearsal(Frames())
    renderer = Renderer(Theme.default().layers((1024, 600)))
    shown = (round(THUMB[1] * 640 / 400), THUMB[1])  # the camera's shape, as tall as a face
    focal = 320 / math.tan(math.radians(BAXTER_HEAD_CAMERA_HFOV) / 2)
    pairs = []
    for k in range(int(max(times) * 30) + 1):
        t = k / 30
        state = rehearsal.look(timeline.sample(t), t, timeline.status(t))
        if any(abs(t - wanted) < 1e-6 for wanted in times):
            camera = Image.fromarray(np.ascontiguousarray(images[k][..., ::-1])).resize(shown, Image.BOX)
            target = rehearsal.robot.gaze.face
            if target is not None:  # where the follower looks, back in the picture
                u = 320 - focal * math.tan(target[0] / DEGREES_PER_RADIAN)
                v = 200 + focal * math.tan(target[1] / PIXELS_PER_ELEVATION)
                x, y = u * shown[0] / 640, v * shown[1] / 400
                draw = ImageDraw.Draw(camera)
                for dx, dy in ((1, 0), (0, 1)):
                    draw.line(
                        [(x - 9 * dx, y - 9 * dy), (x + 9 * dx, y + 9 * dy)], fill=(255, 40, 40), width=3
                    )
            face = Image.fromarray(np.ascontiguousarray(renderer.render(state)[..., ::-1]))
            framed = Image.new("RGB", THUMB, PAPER)
            framed.paste(camera, ((THUMB[0] - shown[0]) // 2, 0))
            pairs += [(f"camera, {t:.1f} s", framed), ("the face", face.resize(THUMB, Image.LANCZOS))]
    return sheet(pairs, columns=2)


def _test_helpers() -> None:
    """The tests' browser and server helpers importable (they take `needs` from tests/conftest.py)."""
    import sys

    tests = Path(__file__).resolve().parent.parent / "tests"
    for folder in (tests, tests / "support"):
        if str(folder) not in sys.path:
            sys.path.insert(0, str(folder))


def screen_page(path: Path) -> None:
    """`baxterface screen` in headless chromium, in a landscape tablet's 1280x800 window, mid-sentence."""
    _test_helpers()
    from browser import chromium, wait_for
    from studio_server import running_screen

    said = 'happy; look 20 -10 in 0.3s; say "Hello! I am on a tablet now."'
    folder = Path(tempfile.mkdtemp())
    with running_screen(folder, "--no-idle") as screen, chromium(1280, 800) as driver:
        driver.execute_cdp_cmd(
            "Emulation.setDeviceMetricsOverride",
            {"width": 1280, "height": 800, "deviceScaleFactor": 1, "mobile": False},
        )
        driver.get(screen.url)
        wait_for(driver, "window.screenFace && window.screenFace.frames >= 1")
        driver.find_element("css selector", "#tap").click()  # sound let in: the prompt goes
        wait_for(driver, "document.getElementById('tap').hidden")
        screen.json("POST", "/api/command", said)
        # In the middle of "tablet", heard on the page as the mouth shapes it.
        wait_for(driver, "window.screenFace.sounds().some(s => s.t > 1.05)")
        driver.save_screenshot(str(path))
    folder.rmdir()


def studio_page(path: Path) -> None:
    """The studio's page in headless chromium: a typo underlined, a few presses in the session."""
    import shutil

    _test_helpers()
    from browser import chromium, wait_for
    from studio_server import running_studio

    with tempfile.TemporaryDirectory() as folder:
        script = Path(folder) / "show.face"
        shutil.copy(Path(__file__).resolve().parent.parent / "scripts_examples" / "show.face", script)
        with running_studio(script, "--no-idle") as studio, chromium(1500, 950) as driver:
            driver.get(studio.url)
            wait_for(driver, "window.studio && window.__frames >= 1")
            driver.find_element("css selector", "#robot").click()  # used, as a person would: sound may play
            driver.execute_script(
                "const v = window.studio.editor.view, line = v.state.doc.line(20);"
                "v.dispatch({changes: {from: line.from, to: line.to, insert: 'hapy'}});"
            )
            wait_for(driver, "document.querySelector('.cm-lintRange-error')")
            for command in ("wake up", "happy", "look left in 0.4s", 'say "Hello! I am Baxter."'):
                driver.execute_script("return window.studio.press(arguments[0]);", command)
                wait_for(driver, f"document.getElementById('session').textContent.includes({command!r})")
            wait_for(driver, "document.getElementById('robot').textContent.includes('Hello')")
            driver.save_screenshot(str(path))


def main() -> None:
    OUT.mkdir(exist_ok=True)
    save_sheet(emotions(), OUT / "emotions.png")
    save_sheet(looking(), OUT / "looking.png")
    hello().save(OUT / "hello.png", optimize=True)
    save_sheet(speech_mouths(), OUT / "speech-mouths.png")
    save_sheet(intensities(), OUT / "intensities.png")
    save_sheet(mood_plane(), OUT / "mood.png")
    save_sheet(morph(), OUT / "morph.png")
    save_sheet(gesture_sheet(), OUT / "gestures.png")
    crossfade().save(OUT / "crossfade.png", optimize=True)
    sonar_walk().save(OUT / "sonar-walk.png", optimize=True)
    save_sheet(face_following(), OUT / "face-following.png")
    save_sheet(face_following((1.0, 2.0, 3.0, 4.5), "walking_away"), OUT / "far-faces.png")
    studio_page(OUT / "studio.png")
    screen_page(OUT / "screen.png")
    try:
        lipsync().save(OUT / "lipsync.png", optimize=True)
        recorded_lipsync().save(OUT / "lipsync-recorded.png", optimize=True)
    except MissingTool as e:  # the pictures that speak
        raise SystemExit(f"make_pictures.py: the speech pictures not drawn: {e}") from None
    for name in (
        "emotions.png",
        "looking.png",
        "hello.png",
        "speech-mouths.png",
        "intensities.png",
        "mood.png",
        "morph.png",
        "gestures.png",
        "crossfade.png",
        "sonar-walk.png",
        "face-following.png",
        "far-faces.png",
        "lipsync.png",
        "lipsync-recorded.png",
        "studio.png",
        "screen.png",
    ):
        print(OUT / name)


if __name__ == "__main__":
    main()
