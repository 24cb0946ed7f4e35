"""After a command, a live face is looked at often until its picture changes, then at its ticks."""

from __future__ import annotations

from pytest import approx

from baxterface_cli.engine.change_polling import ChangePolling


def test_a_still_face_is_looked_at_on_its_ticks():
    assert ChangePolling(poll=0.002).next_look(tick=10.033, now=10.0) == 10.033


def test_after_a_command_it_is_looked_at_every_poll_until_the_change_shows():
    motion = ChangePolling(poll=0.002, eager_for=0.25)
    motion.heard(10.0)
    assert motion.next_look(tick=10.033, now=10.0) == approx(10.002)
    assert motion.next_look(tick=10.033, now=10.004) == approx(10.006)
    motion.shown()
    assert motion.next_look(tick=10.033, now=10.006) == 10.033


def test_a_command_that_changes_nothing_is_awaited_only_so_long():
    motion = ChangePolling(poll=0.002, eager_for=0.25)
    motion.heard(10.0)
    assert motion.next_look(tick=10.3, now=10.249) == approx(10.251)
    assert motion.next_look(tick=10.3, now=10.25) == 10.3


def test_a_tick_sooner_than_the_poll_comes_first():
    motion = ChangePolling(poll=0.002)
    motion.heard(10.0)
    assert motion.next_look(tick=10.001, now=10.0) == 10.001
