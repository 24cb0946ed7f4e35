"""How much hearing words may cost (issue 43, 7): every second of sound heard costs work for each
phrase listened for and each phone of its spellings, so a script listens for at most
LIMITS.max_phrases phrases, a listener for at most LIMITS.max_phones phones, and `--hear` is
refused up front, from the recording's header, past LIMITS.max_phone_seconds.

The real `baxterface`, pocketsphinx's dictionary, espeak-ng's voice, the node's real ears. These are
the word spotter's bounds: it listens here even where Moonshine is installed (whose work grows with
the seconds of speech alone).
"""

from __future__ import annotations

import re
import shutil
import subprocess
import time
import wave

import pytest

from baxterface_cli.core.face_constants import LIMITS
from conftest import baxterface
from listened_words import HEAVY, WORDS
from waiting import eventually


@pytest.fixture(autouse=True)
def the_spotter_listens(monkeypatch):
    monkeypatch.setenv("BAXTERFACE_LISTENER", "spotter")


def handlers(phrases) -> str:
    return "".join(f'on word "{p}" {{ happy }}\n' for p in phrases)


def quiet_wav(path, seconds: float, rate: int = 8000) -> None:
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1), w.setsampwidth(1), w.setframerate(rate)
        w.writeframes(b"\x80" * int(seconds * rate))  # 8-bit silence


def test_check_refuses_a_script_past_the_phrases_it_may_listen_for(tmp_path):
    most = LIMITS.max_phrases
    (tmp_path / "many.face").write_text('wait until word "hello"\n' + handlers(WORDS[: most + 1]))
    run = baxterface("check", str(tmp_path / "many.face"))
    assert run.code == 1
    # the first line says where: the handler of the phrase past the limit ("hello" is counted once)
    assert run.err.splitlines()[0] == (
        f"{tmp_path / 'many.face'}:{most + 2}:1: error: one phrase too many: "
        f"a script listens for {most} phrases at most"
    )
    (tmp_path / "enough.face").write_text(handlers(WORDS[:most]))
    assert baxterface("check", str(tmp_path / "enough.face")).code == 0


def test_hear_is_refused_up_front_past_the_phones_times_the_seconds(tmp_path):
    pytest.importorskip("pocketsphinx")
    pytest.importorskip("av")
    quiet_wav(tmp_path / "long.wav", 590)
    pairs = [f"{a} {b}" for a, b in zip(WORDS, WORDS[1:] + WORDS[:1])][: LIMITS.max_phrases]
    (tmp_path / "many.face").write_text(handlers(pairs))
    run = baxterface("explain", "many.face", "--hear", "long.wav", cwd=tmp_path)
    assert run.code == 2, run.err
    found = re.fullmatch(
        r"baxterface explain: --hear: 32 phrases of (\d+) phones, every spelling counted, over 590 s of "
        r"sound is too much to listen for \(([\d,]+) phone-seconds; the limit is ([\d,]+)\)\n",
        run.err,
    )
    assert found, run.err
    phones, work, limit = (int(g.replace(",", "")) for g in found.groups())
    assert work == phones * 590 > limit == LIMITS.max_phone_seconds
    # the same phrases over a shorter recording are heard
    quiet_wav(tmp_path / "short.wav", 5)
    assert baxterface("explain", "many.face", "--hear", "short.wav", cwd=tmp_path).code == 0


def test_a_phrase_of_too_many_phones_is_one_line_wherever_it_is_heard(tmp_path):
    pytest.importorskip("pocketsphinx")
    from baxterface_cli.speech.word_spotter import WordError, WordSpotter

    with pytest.raises(WordError, match=r"^too much to listen for: 1 phrase of 1323 phones, every spelling"):
        WordSpotter([HEAVY], lambda word, at: None)
    quiet_wav(tmp_path / "q.wav", 2)
    (tmp_path / "heavy.face").write_text(handlers([HEAVY]))
    run = baxterface("explain", "heavy.face", "--hear", "q.wav", cwd=tmp_path)
    assert run.code == 2 and run.err == (
        "baxterface explain: --hear: too much to listen for: 1 phrase of 1323 phones, every spelling "
        f"counted (the limit is {LIMITS.max_phones})\n"
    )


def test_the_nodes_ears_listen_for_the_phrases_within_the_phones_and_say_which_not(tmp_path):
    pytest.importorskip("pocketsphinx")
    if shutil.which("espeak-ng") is None:
        pytest.skip("espeak-ng is not installed")
    from baxterface_cli.engine.live_session import LiveSession
    from baxterface_cli.language.parser import parse
    from baxterface_cli.ros.node_ears import Ears

    said = tmp_path / "that.wav"
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(said), "look at that robot"], check=True)
    session = LiveSession(now=time.monotonic())
    heard, logged = [], []
    ears = Ears(
        session, lambda event, at: heard.append(event.arg), str(said), log=lambda *line: logged.append(line)
    )
    assert ears.start() is None
    try:
        # sent live, one command each, as the node takes them: together past the phones
        session.run(parse(handlers([HEAVY])), time.monotonic())
        session.run(parse(handlers(["robot"])), time.monotonic())
        assert eventually(lambda: heard, timeout=30) == ["robot"]
        past = f'not listening for "{HEAVY}": past {LIMITS.max_phones} phones, every spelling counted'
        assert ("warn", past) in logged
    finally:
        ears.close()
