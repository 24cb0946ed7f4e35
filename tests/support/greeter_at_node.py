"""The greeter's `ask` answered at the ROS 1 face node by a visitor's recording, end to end.

The node plays scripts_examples/greeter.face with `_listen:=` a recording: silence, then the answer
in a natural voice (visitor_voices.py). Its ears start the recording when the greeter, woken by
`button ok`, first listens for a word, and log that moment's wall time; `person near` is raised
1.5 s after it, on the node's ~event topic, by a process of its own (this one stays out of ROS, so
a test module using it can share a session with test_ros.py). The greeter asks its question 4.1
to 5.0 s after `person near` (its greeting is one of three) and waits 6 s; the answer starts 1 s
after the latest end of the question (and the 0.3 s after it in which the face would hear its own
echo). What the node did is read from its session log: the ask's `answered` record, and what it
said after.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Dict, List, NamedTuple

from visitor_voices import placed

ROOT = Path(__file__).resolve().parent.parent.parent
GREETER = ROOT / "scripts_examples" / "greeter.face"
NEAR_AFTER = 1.5  # seconds from the recording's start (the greeter awake) to `person near`
ANSWER_AT = NEAR_AFTER + 5.0 + 0.3 + 1.0  # in the recording: after the latest question, and its echo
# What each answer routes to: the phrase the ask's log names (None: its `else`) and the first
# words the face says after it (None: nothing said).
ROUTES = {
    "yes": ("yes", "I would tell you a UDP joke"),
    "sure": ("sure", "I would tell you a UDP joke"),
    "go on": ("go on", "I would tell you a UDP joke"),
    "no": ("no", "Maybe later, then."),
    "what was that": (None, None),
}
RAISER = """
import sys, time
from baxterface_cli.ros.connect import open_link
link = open_link(1, "visitor", anonymous=True)
events = link.publisher("/baxter_face/event", "std_msgs/String", queue=10)
while events.listeners() == 0:
    time.sleep(0.02)
print("ready", flush=True)
for line in sys.stdin:  # "WALL EVENT": the event raised at that wall time
    wall, event = line.split(" ", 1)
    time.sleep(max(0.0, float(wall) - time.time()))
    events.publish(data=event.strip())
    print("raised", time.time(), flush=True)
"""


class Conversation(NamedTuple):
    answered: str  # the ask's `answered` line in the log
    said: List[str]  # what the face said after it
    near_at: float  # `person near` on the recording's clock (seconds after its start)

    def routed(self, text: str) -> bool:
        """Did the ask take `text`'s answer, and the face do what that answer says?"""
        phrase, says = ROUTES[text]
        if phrase is None:
            took = "answered none of its answers" in self.answered
        else:
            took = f'answered "{phrase}"' in self.answered
        first = self.said[0] if self.said else None
        return took and (first is None if says is None else first is not None and first.startswith(says))


class _Lines:
    """A process's output lines, read as they come."""

    def __init__(self, proc: subprocess.Popen) -> None:
        self.lines: List[str] = []
        self.came = threading.Condition()
        threading.Thread(target=self._read, args=(proc,), daemon=True).start()

    def _read(self, proc: subprocess.Popen) -> None:
        for line in proc.stdout:
            with self.came:
                self.lines.append(line)
                self.came.notify_all()

    def wait_for(self, start: str, timeout: float) -> str:
        deadline = time.monotonic() + timeout
        with self.came:
            while True:
                found = next((line for line in self.lines if start in line), None)
                if found is not None:
                    return found
                left = deadline - time.monotonic()
                assert left > 0, f"waited {timeout:g} s for {start!r}: " + "".join(self.lines[-20:])
                self.came.wait(left)


def _records(log: Path) -> List[Dict]:
    if not log.exists():
        return []
    lines = log.read_text(encoding="utf-8").splitlines()
    return [json.loads(line) for line in lines if line.endswith("}")]


def _record(log: Path, test, timeout: float) -> Dict:
    deadline = time.monotonic() + timeout
    while True:
        found = next((r for r in _records(log) if test(r)), None)
        if found is not None:
            return found
        assert time.monotonic() < deadline, f"waited {timeout:g} s in {log}"
        time.sleep(0.05)


def converse(
    env: Dict[str, str], folder: Path, voice: str, text: str, patience: float = 60.0
) -> Conversation:
    """One node, the greeter answered with `text` said by `voice`: what it did."""
    wav, log = folder / f"{voice}-{text.replace(' ', '-')}.wav", folder / f"{voice}-{text}.jsonl"
    log.unlink(missing_ok=True)
    placed(voice, text, ANSWER_AT, wav)
    pipe = dict(stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=str(ROOT), env=env)
    raiser = subprocess.Popen([sys.executable, "-c", RAISER], stdin=subprocess.PIPE, **pipe)
    node = subprocess.Popen(
        [sys.executable, "-m", "baxterface_cli", "node", str(GREETER), "_idle:=false", "_audio:=none",
         f"_listen:={wav}", f"_log:={log}"],
        **pipe,
    )  # fmt: skip
    raised, heard = _Lines(raiser), _Lines(node)
    try:
        raised.wait_for("ready", patience)
        _record(log, lambda r: r["type"] == "log" and r["text"].startswith("state asleep entered"), patience)
        raiser.stdin.write(f"{time.time()} button ok\n")
        raiser.stdin.flush()
        playing = heard.wait_for("as a microphone", patience)
        start = float(playing.split(" from ")[1].split()[0])
        raiser.stdin.write(f"{start + NEAR_AFTER} person near\n")
        raiser.stdin.flush()
        answered = _record(log, lambda r: r.get("kind") == "answered", patience)
        ended = _record(
            log, lambda r: r["type"] == "log" and r["text"] == "line 17 'on person near' ends", patience
        )
        records = _records(log)
        unix = records[0]["unix"]
        near = next(r for r in records if r["type"] == "event" and r["event"] == "person near")
        said = [r["text"] for r in records if r["type"] == "say" and answered["t"] <= r["t"] <= ended["t"]]
        return Conversation(answered["text"], said, unix + near["t"] - start)
    finally:
        for proc in (node, raiser):
            proc.send_signal(signal.SIGTERM)
        for proc in (node, raiser):
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
