"""Sound out of the local device: the mixer, and `play` speaking through real PortAudio.

There is no sound card here, so ALSA's own plugins make one: the default PCM
is a `file` plugin over `null`, writing raw samples into a named pipe. The file
plugin holds back one buffer, as a card's ring buffer would (PortAudio counts
it in the latency it reports), and lets each sample out as the next is
written: that moment is when the sample is heard. A thread of the test empties
the pipe at exactly the card's rate, so the pipe stays full and the card runs
in real time, as a card's converter makes it; the pipe's own size only gives
the recording room. PortAudio sees an ordinary ALSA device; the test hears
what it played, and when.
"""

from __future__ import annotations

import fcntl
import json
import os
import struct
import subprocess
import sys
import termios
import threading
import time
from pathlib import Path
from typing import List, Tuple

import numpy as np
import pexpect
import pytest

from baxterface_cli.speech.sound_device import (
    LOOKAHEAD,
    Mixer,
    SoundOut,
    SpeechCues,
    _open_device,
    open_sound,
    resample,
)
from conftest import ROOT
from playing import spawn_play

# The card: the speech's own rate, so the samples arrive as they were made, in 32-bit stereo.
RATE, CHANNELS = 22050, 2
FRAME = CHANNELS * 4
F_SETPIPE_SZ = 1031  # fcntl's, on Linux
ASOUNDRC = """pcm.!default {{
    type plug
    slave {{
        pcm {{ type file; slave.pcm "null"; file "{fifo}"; format "raw" }}
        format S32_LE
        channels {channels}
        rate {rate}
    }}
}}
"""


def have_sounddevice() -> None:
    try:
        import sounddevice  # noqa: F401
    except (ImportError, OSError) as e:
        if os.environ.get("CI"):
            pytest.fail(f"sounddevice does not load ({e}): make test installs it and libportaudio2")
        pytest.skip(f"sounddevice does not load: {e}")


class PipeCard:
    """A sound card made of a named pipe, emptied at its rate by a thread; it records what it plays."""

    def __init__(self, home: Path) -> None:
        home.mkdir(parents=True, exist_ok=True)
        fifo = home / "card.fifo"
        os.mkfifo(str(fifo))
        (home / ".asoundrc").write_text(ASOUNDRC.format(fifo=fifo, channels=CHANNELS, rate=RATE))
        self.home = home
        self.data = bytearray()
        self.written: List[Tuple[float, int]] = []  # (when, bytes in so far): out of the card, heard
        self.fd = os.open(str(fifo), os.O_RDONLY | os.O_NONBLOCK)
        fcntl.fcntl(self.fd, F_SETPIPE_SZ, 16384)  # 93 ms: room for a late writer, no more
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def env(self, **extra: str) -> dict:
        env = dict(os.environ, HOME=str(self.home), TERM="xterm-256color", **extra)
        env.pop("XDG_CONFIG_HOME", None)  # ALSA reads an asoundrc there too
        return env

    def _read(self, n: int) -> bytes:
        try:
            return os.read(self.fd, n)
        except BlockingIOError:
            return b""

    def _waiting(self) -> int:
        return struct.unpack("i", fcntl.ioctl(self.fd, termios.FIONREAD, b"\0\0\0\0"))[0]

    def _run(self) -> None:
        start, taken = None, 0  # the schedule: `taken` bytes are due by start + taken / byte rate
        byte_rate = RATE * FRAME
        while not self.done.wait(0.001):
            if start is None:
                if self._waiting():
                    start = time.monotonic()
                continue
            due = int((time.monotonic() - start) * byte_rate) - taken
            got = self._read(due) if due > 0 else b""
            self.data += got
            taken += len(got)
            if len(got) < due:  # nothing more yet: the schedule waits, as a card plays silence
                start += (due - len(got)) / byte_rate
            self.written.append((time.monotonic(), len(self.data) + self._waiting()))

    def drain(self, timeout: float = 5.0) -> None:
        """Wait for the card to play what the pipe still holds (the writer has gone)."""
        deadline = time.monotonic() + timeout
        while self._waiting() and time.monotonic() < deadline:
            time.sleep(0.01)
        time.sleep(0.01)

    def stop(self) -> None:
        self.done.set()
        self.thread.join()
        os.close(self.fd)

    def samples(self) -> np.ndarray:
        """What the card played, first channel, as int16 (the plug widened it to 32 bits)."""
        whole = len(self.data) // FRAME * FRAME
        frames = np.frombuffer(bytes(self.data[:whole]), "<i4").reshape(-1, CHANNELS)
        return (frames[:, 0] >> 16).astype(np.int16)

    def heard_at(self, index: int) -> float:
        """The monotonic time sample `index` came out of the card (between two looks at the pipe)."""
        times, counts = zip(*self.written)
        return float(np.interp((index + 1) * FRAME, counts, times))


@pytest.fixture
def card(tmp_path):
    have_sounddevice()
    made = PipeCard(tmp_path / "home")
    yield made
    made.stop()


def correlation(recording: np.ndarray, sound: np.ndarray) -> np.ndarray:
    """How well `sound` matches `recording` from each of its samples on (cross-correlation)."""
    n = 1 << int(np.ceil(np.log2(len(recording) + len(sound))))
    spectrum = np.fft.rfft(recording.astype(float), n) * np.conj(np.fft.rfft(sound.astype(float), n))
    return np.fft.irfft(spectrum, n)[: len(recording)]


def find(recording: np.ndarray, sound: np.ndarray) -> int:
    """Where `sound` best matches in `recording`."""
    return int(np.argmax(correlation(recording, sound)))


def spoken(text: str) -> np.ndarray:
    """What espeak-ng says for `text` in the default voice, as `play` says it."""
    from baxterface_cli.core.voices import DEFAULT_RATE, DEFAULT_VOICE
    from baxterface_cli.speech.synthesis import engine

    return engine().say(text, DEFAULT_VOICE, DEFAULT_RATE).samples


def levels(samples: np.ndarray) -> List[Tuple[int, int]]:
    """Runs of equal samples as (value, length)."""
    edges = np.flatnonzero(np.diff(samples)) + 1
    starts = np.concatenate(([0], edges))
    ends = np.concatenate((edges, [len(samples)]))
    return [(int(samples[s]), int(e - s)) for s, e in zip(starts, ends)]


# -- through PortAudio, into the pipe card -----------------------------------
# These hear the card in real time, sample for sample: `make test` runs them alone, after the
# parallel suites, so that a starved sound callback is the product's fault, not the machine's.


@pytest.mark.realtime
def test_play_speaks_the_utterance_when_the_picture_starts_saying_it(card):
    text = "Hello there, I am Baxter."
    child = spawn_play("-e", f'wait 0.5s; say "{text}"', env=card.env())
    child.expect(r"0\.0/")  # the first frame: what came before it is out of the way
    child.expect("saying")
    seen = time.monotonic()  # the first frame with the speaking mouth, as it reaches the terminal
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0, child.before[-500:]
    assert "baxterface play:" not in child.before  # a device was found: nothing to say about it
    card.drain()
    recording = card.samples()

    utterance = spoken(text)
    at = find(recording, utterance)
    assert np.array_equal(recording[at : at + len(utterance)], utterance)  # sample for sample, all of it
    # Its first sample is heard as its frame is shown: within two frames (30 fps), and some time for
    # a busy machine to get round to drawing the frame and to this test's reading it.
    assert abs(card.heard_at(at) - seen) < 2 / 30 + 0.02


@pytest.mark.realtime
def test_play_loop_says_it_again_each_lap(card):
    utterance = spoken("Loop")
    lap = len(utterance) / RATE + 0.3
    child = spawn_play("--loop", "-e", 'say "Loop"; wait 0.3s', env=card.env())
    child.expect(r"/0\.7s")  # playing
    child.expect(pexpect.TIMEOUT, timeout=3 * lap)  # three laps and a bit, reading the screen all the while
    child.sendintr()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130
    card.drain()
    recording = card.samples()
    match = correlation(recording, utterance)
    starts = np.flatnonzero(match > 0.99 * float(np.sum(utterance.astype(float) ** 2)))
    assert len(starts) >= 3
    assert np.diff(starts) / RATE == pytest.approx([lap] * (len(starts) - 1), abs=0.005)  # every lap, in step


@pytest.mark.realtime
def test_ctrl_c_silences_the_words_being_said(card):
    text = "I will keep on talking for a good few seconds, so that there is time to stop me."
    utterance = spoken(text)
    length = len(utterance) / RATE  # over four seconds: cut off and finished differ by seconds
    child = spawn_play("-e", f'say "{text}"', env=card.env())
    deadline = time.monotonic() + 20
    while not np.any(card.samples()) and time.monotonic() < deadline:  # the first words are heard
        child.expect([pexpect.TIMEOUT, pexpect.EOF], timeout=0.02)  # reading the screen all the while
    child.sendintr()
    stopped = time.monotonic()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130
    card.drain()
    recording = card.samples()
    heard = np.flatnonzero(recording)
    at = find(recording, utterance)
    assert np.array_equal(
        recording[at : heard[-1] + 1], utterance[: heard[-1] + 1 - at]
    )  # its beginning, as said
    assert (heard[-1] - at) / RATE < length / 2  # cut off, not said to the end
    # What the device already held still comes out (about 0.16 s here): a moment, not the seconds left.
    assert card.heard_at(heard[-1]) - stopped < 1.0


MIX_DRIVER = """
import json, sys, time
import numpy as np
from baxterface_cli.speech.sound_device import open_sound

sound = open_sound(lambda m: print(m, file=sys.stderr))
time.sleep(0.2)
sound.play(np.full(13230, 6000, np.int16), 22050, skip=-0.1)  # 0.6 s, from 0.1 s on
sound.play(np.full(13230, 9000, np.int16), 22050, skip=-0.3)  # 0.6 s from 0.2 s later: over the first
time.sleep(1.0)
sound.play(np.arange(1000, 9820, dtype=np.int16), 44100, skip=0.1)  # at twice the rate, 0.1 s cut
time.sleep(0.5)
sound.close()
print(json.dumps({"available": sound.available, "rate": sound.rate}))
"""


@pytest.mark.realtime
def test_sounds_played_together_are_mixed_and_skip_cuts_or_delays(card):
    proc = subprocess.run(
        [sys.executable, "-c", MIX_DRIVER],
        cwd=str(ROOT),
        env=card.env(),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""  # nor anything from ALSA
    assert json.loads(proc.stdout) == {"available": True, "rate": RATE}
    card.drain()
    recording = card.samples()
    runs = levels(recording)
    # silence; the first alone for 0.2 s; both, summed, for 0.4 s; the second alone; silence
    assert [v for v, _ in runs[:5]] == [0, 6000, 15000, 9000, 0]
    (_, alone), (_, both), (_, after) = runs[1:4]
    assert alone + both == 13230 and both + after == 13230  # neither cut the other
    assert abs(alone - 4410) <= 44  # the second started 0.2 s after the first, to 2 ms
    # The third was resampled from 44100 to the device's 22050, its first 0.1 s (4410 samples) cut.
    start = sum(n for _, n in runs[:5])
    assert list(recording[start : start + 3]) == [5410, 5412, 5414]
    assert np.all(np.diff(recording[start : start + 2205].astype(int)) == 2)
    assert not recording[start + 2205 :].any()


def test_without_a_device_play_says_so_once_and_plays_on(tmp_path):
    have_sounddevice()
    cards = Path("/proc/asound/cards")
    if cards.exists() and "no soundcards" not in cards.read_text():
        pytest.skip("this machine has a sound card: ALSA would find it")
    home = tmp_path / "home"
    home.mkdir()
    (home / ".asoundrc").write_text('pcm.!default { type hw; card "NoSuchCard" }\n')
    env = dict(os.environ, HOME=str(home), TERM="xterm-256color")
    env.pop("XDG_CONFIG_HOME", None)
    child = spawn_play("-e", 'say "Hi"; blink', env=env)
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0
    said = [line for line in child.before.splitlines() if "baxterface play:" in line]
    assert len(said) == 1, said
    assert said[0].endswith(
        "baxterface play: no sound device (PortAudio finds no output device): playing silently"
    )
    assert "played" in child.before and "ALSA" not in child.before  # ALSA's own complaints stay hidden


@pytest.fixture
def no_sounddevice(tmp_path):
    """An environment where `import sounddevice` fails, and leaves a mark that it was tried."""
    stub = tmp_path / "stub"
    stub.mkdir()
    mark = tmp_path / "imported"
    (stub / "sounddevice.py").write_text(
        f"open({str(mark)!r}, 'w').close()\nraise ImportError('no module named sounddevice')\n"
    )
    path = os.pathsep.join([str(stub), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return dict(os.environ, PYTHONPATH=path, TERM="xterm-256color"), mark


def test_without_sounddevice_play_says_what_to_install_once(no_sounddevice):
    env, mark = no_sounddevice
    child = spawn_play("-e", 'say "Hi"; say "there"', env=env)
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0 and mark.exists()
    said = [line.strip() for line in child.before.splitlines() if "baxterface play:" in line]
    assert said == [
        "baxterface play: sound needs the sounddevice module: pip install 'baxterface[speech]'; "
        "playing silently"
    ]
    assert "played" in child.before and child.before.count("\u2580") > 100  # the face played on


def test_a_script_that_says_nothing_never_looks_for_a_device(no_sounddevice):
    env, mark = no_sounddevice
    child = spawn_play("-e", "happy; blink", env=env)
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0
    assert not mark.exists()
    assert "baxterface play:" not in child.before and "sound" not in child.before


# -- the mixer and the device, without a device -------------------------------


def blocks(mixer: Mixer, seconds: float, sizes=(7, 64, 1, 200, 33), channels: int = 1) -> np.ndarray:
    """Run `mixer` as an output callback would, in blocks of uneven sizes, from time 0."""
    out, t, i = [], 0.0, 0
    while t < seconds:
        block = np.zeros((sizes[i % len(sizes)], channels), np.int16)
        mixer.fill(block, t)
        out.append(block)
        t += len(block) / mixer.rate
        i += 1
    return np.concatenate(out)


def test_the_mixer_places_each_sound_to_the_sample_and_sums_overlaps():
    mixer = Mixer(1000)
    rng = np.random.default_rng(0)
    a = rng.integers(-3000, 3000, 500).astype(np.int16)
    b = rng.integers(-3000, 3000, 300).astype(np.int16)
    mixer.add(a, 0.100)
    mixer.add(b, 0.350)
    out = blocks(mixer, 1.0, channels=2)[:1000]
    assert np.array_equal(out[:, 0], out[:, 1])  # every channel the same
    expected = np.zeros(1000, np.int32)
    expected[100:600] += a
    expected[350:650] += b
    assert np.array_equal(out[:, 0], expected)
    assert not mixer.busy()  # both finished, and let go


def test_the_mixer_clips_rather_than_wraps_and_stop_silences_at_once():
    mixer = Mixer(1000)
    mixer.add(np.full(100, 30000, np.int16), 0.0)
    mixer.add(np.full(100, 30000, np.int16), 0.0)
    mixer.add(np.full(100, -1000, np.int16), 0.0)
    block = np.zeros(10, np.int16)
    mixer.fill(block, 0.0)
    assert list(block) == [32767] * 10
    mixer.clear()
    mixer.fill(block, 0.01)
    assert not block.any() and not mixer.busy()


def test_a_late_sound_starts_at_once_rather_than_losing_its_start():
    mixer = Mixer(1000)
    mixer.add(np.arange(1, 51, dtype=np.int16), 0.0)
    block = np.zeros(20, np.int16)
    mixer.fill(block, 0.5)  # the block after the one it was meant for
    assert list(block) == list(range(1, 21))


def test_resampling_keeps_the_length_in_time_and_the_shape():
    ramp = np.arange(0, 22050, dtype=np.int16)
    up = resample(ramp, 22050, 48000)
    assert len(up) == 48000 and up[0] == 0 and abs(int(up[-1]) - 22049) <= 1
    assert np.all(np.diff(up.astype(int)) >= 0)
    assert resample(ramp, 22050, 22050) is ramp


class FakeStream:
    latency = 0.05

    def __init__(self, samplerate, channels, dtype, callback) -> None:
        self.samplerate, self.channels, self.callback = samplerate, channels, callback
        self.started = self.closed = False

    def start(self):
        self.started = True
        self.callback(np.zeros((0, self.channels), np.int16), 0, Timing(0.0), None)

    def stop(self, ignore_errors=True):
        self.started = False

    def close(self, ignore_errors=True):
        self.closed = True


class FakeSd:
    """sounddevice's surface, for a device that takes only 48000 samples a second, in stereo."""

    class PortAudioError(Exception):
        pass

    def __init__(self) -> None:
        self.streams: List[FakeStream] = []

    def query_devices(self, kind):
        return {"default_samplerate": 48000.0}

    def OutputStream(self, samplerate, channels, dtype, callback):
        if samplerate != 48000 or channels != 2:
            raise self.PortAudioError(
                "Invalid sample rate" if samplerate != 48000 else "Invalid channel count"
            )
        self.streams.append(FakeStream(samplerate, channels, dtype, callback))
        return self.streams[-1]


class Timing:
    def __init__(self, ahead: float) -> None:
        self.currentTime, self.outputBufferDacTime = 100.0, 100.0 + ahead


def test_a_device_that_refuses_the_speech_rate_gets_the_sound_resampled_to_its_own():
    sd = FakeSd()
    sound = _open_device(sd, clock=lambda: 10.0)
    assert sound.available and sound.rate == 48000 and sound.latency == 0.05
    (stream,) = sd.streams
    assert stream.started
    sound.play(np.full(22050, 1000, np.int16), 22050)  # a second of sound
    out = np.zeros((72000, 2), np.int16)
    # The device is empty and says nothing of its timing: its first block is heard at once, so the
    # sound, to be heard after the latency (0.05 s) like any other, starts 2400 samples in.
    stream.callback(out, 72000, Timing(0.0), None)
    assert not out[:2400].any() and (out[2400:50400] == 1000).all() and not out[50400:].any()
    sound.close()
    assert stream.closed and not sound.mixer.busy()


def test_the_block_the_device_says_is_further_ahead_takes_the_sound_later():
    sd = FakeSd()
    sound = _open_device(sd, clock=lambda: 10.0)
    sound.play(np.full(4800, 7, np.int16), 48000, skip=-0.1)  # to leave 0.1 s from now (plus latency)
    out = np.zeros((9600, 2), np.int16)
    # This block goes out 0.06 s from now, 0.01 s later than the latency the device gave at opening:
    # the sound starts 0.09 s into it, not 0.1 s.
    sd.streams[0].callback(out, 9600, Timing(0.06), None)
    assert np.flatnonzero(out[:, 0])[0] == 4320


def test_open_sound_without_a_default_output_warns_once_and_is_silent(monkeypatch):
    sd = FakeSd()

    def no_device(kind):
        raise sd.PortAudioError("Error querying device -1")

    sd.query_devices = no_device
    monkeypatch.setitem(sys.modules, "sounddevice", sd)
    said: List[str] = []
    sound = open_sound(said.append)
    assert said == ["no sound device (PortAudio finds no output device): playing silently"]
    assert isinstance(sound, SoundOut) and not sound.available and sound.latency == 0.0
    sound.play(np.zeros(10, np.int16), 22050)  # and does nothing, quietly
    sound.stop()
    sound.close()


# -- the script's clock ------------------------------------------------------


class Heard(SoundOut):
    available = True

    def __init__(self, latency: float) -> None:
        self.latency = latency
        self.played: List[Tuple[int, float]] = []

    def play(self, samples, rate, skip=0.0):
        self.played.append((len(samples), round(skip, 6)))


class Said:
    def __init__(self, at: float, seconds: float) -> None:
        self.at = at
        self.utterance = type(
            "U", (), {"samples": np.zeros(int(seconds * 100), np.int16), "sample_rate": 100}
        )()
        self.utterance.duration = seconds


def test_utterances_start_ahead_of_their_time_by_the_latency_and_the_lookahead():
    sound = Heard(latency=0.1)
    cues = SpeechCues(sound, [Said(1.0, 0.5), Said(2.0, 0.5)], origin=50.0)
    cues.tick(50.0)
    assert sound.played == []
    cues.tick(51.0 - 0.1 - LOOKAHEAD)  # heard at 51.0 exactly if started now with this delay
    assert sound.played == [(50, -LOOKAHEAD)]
    cues.tick(52.3)  # late: the first 0.4 s (0.3 late, plus the latency) is cut
    assert sound.played[-1] == (50, 0.4)


def test_an_utterance_already_over_is_not_started_and_loops_start_again():
    sound = Heard(latency=0.0)
    cues = SpeechCues(sound, [Said(0.0, 0.5)], origin=0.0, loop_every=2.0)
    cues.tick(0.0)
    cues.tick(1.9)  # the next lap's, ahead
    cues.tick(10.7)  # after a long stall: laps 2 to 4 are gone, lap 5's is half over
    assert sound.played[:2] == [(50, 0.0), (50, -0.1)]
    assert sound.played[2:] == []  # 10.7 is 0.7 into lap 5 (from 10.0): past its 0.5 s utterance
    cues.tick(11.9)
    assert sound.played[2:] == [(50, -0.1)]  # lap 6, at 12.0
