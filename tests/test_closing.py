"""Resources that hold a thread until closed are closed by the end of a `with` block, however it ends."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_intake import SessionIntake
from baxterface_cli.robot.camera_watch import CameraWatch
from waiting import eventually


def test_an_intake_prepares_commands_inside_its_block_and_its_worker_ends_with_it():
    session = LiveSession(idle=False, seed=1, now=0.0)
    with SessionIntake(session, lambda: 0.0) as intake:
        assert intake.submit("look 40 0 in 1s") is None
        eventually(lambda: intake.idle() and session.main is not None)
        assert intake._thread.is_alive()
    eventually(lambda: not intake._thread.is_alive())


def test_a_block_that_fails_still_closes_the_intake():
    session = LiveSession(idle=False, seed=1, now=0.0)
    with pytest.raises(ZeroDivisionError), SessionIntake(session, lambda: 0.0) as intake:
        1 / 0  # noqa: B018
    eventually(lambda: not intake._thread.is_alive())


def test_a_camera_watch_stops_watching_at_its_blocks_end_and_its_worker_ends():
    pytest.importorskip("cv2")
    seen = []
    with CameraWatch(seen.append, warn=seen.append) as watch:
        assert watch.start() is None and watch.watching
        watch.give(np.zeros((400, 640, 3), np.uint8), 0.0)
    assert not watch.watching
    eventually(lambda: not watch._worker.is_alive())
