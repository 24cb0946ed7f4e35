"""The greeter's `ask` heard end to end at the ROS 1 face node, COUNT conversations (issue 46).

    .venv-ros/bin/python bench/bench_conversation.py [COUNT] [--spotter]

Each conversation is a fresh `baxterface node scripts_examples/greeter.face` on a roscore of the
bench's own (loopback), hearing `_listen:=` a visitor's recording: `button ok` wakes it, `person
near` makes it greet and ask "Shall I tell you a joke?", and the recording answers in a natural
voice (piper's joe, hibari's heart, in turn) with each of the ask's answers in turn: "yes", "sure",
"go on" (the joke), "no" ("Maybe later, then.") and "what was that" (its `else`: puzzled, nothing
said). An answer is routed right when the session log's `answered` record names it and the face
says what it says next (tests/support/greeter_at_node.py). COUNT is 20 (each voice and answer
twice). With --spotter, the same conversations with the word spotter listening
(BAXTERFACE_LISTENER=spotter), the listener before Moonshine, as the baseline: it hears the
phrases alone, so the `else` cannot be told from silence. Prints JSON.
"""

from __future__ import annotations

import json
import os
import signal
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "tests" / "support")]
from ros_master import start_roscore  # noqa: E402

from greeter_at_node import ROUTES, converse  # noqa: E402
from visitor_voices import VOICES  # noqa: E402


def conversations(env, count, listener):
    runs = [(voice, text) for text in ROUTES for voice in VOICES]
    folder = Path(tempfile.mkdtemp(prefix=f"bench-conversation-{listener}-"))
    heard = dict(env, BAXTERFACE_LISTENER=listener)
    right, wrong, near = 0, [], []
    for i in range(count):
        voice, text = runs[i % len(runs)]
        try:
            got = converse(heard, folder, voice, text)
        except AssertionError as e:  # a wait in vain: the node did not answer at all
            wrong.append({"voice": voice, "said": text, "answered": f"nothing logged: {str(e)[:120]}"})
            continue
        near.append(got.near_at)
        if got.routed(text):
            right += 1
        else:
            wrong.append({"voice": voice, "said": text, "answered": got.answered, "face_said": got.said})
    return {
        "routed_right": f"{right}/{count}",
        "wrong": wrong,
        "person_near_after_recording_start_s": [round(min(near), 2), round(max(near), 2)] if near else None,
    }


def main() -> None:
    count = int(next((a for a in sys.argv[1:] if a.isdigit()), "20"))
    core, env = start_roscore()
    out = {"count": count, "load_before": os.getloadavg()}
    try:
        out["moonshine"] = conversations(env, count, "moonshine")
        if "--spotter" in sys.argv:
            out["spotter"] = conversations(env, count, "spotter")
    finally:
        core.send_signal(signal.SIGINT)
        core.wait(timeout=30)
    out["load_after"] = os.getloadavg()
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
