"""Files written whole or not at all: unseen while written, in place at once, gone on failure."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from baxterface_cli.core import partial_files
from baxterface_cli.core.partial_files import PartialFile, remove_stale, write_atomic


@pytest.mark.parametrize("named", [False, True])
def test_a_partial_file_is_put_in_place_whole_over_the_old_file(tmp_path, named):
    target = tmp_path / "face.gif"
    target.write_bytes(b"old")
    partial = PartialFile(target, named=named)
    partial.file.write(b"new ")
    partial.file.write(b"file")
    assert target.read_bytes() == b"old"  # the old file stays whole until the new one is
    partial.commit()
    assert target.read_bytes() == b"new file"
    assert [p.name for p in tmp_path.iterdir()] == ["face.gif"]


@pytest.mark.skipif(not hasattr(os, "O_TMPFILE"), reason="unnamed files are Linux's")
def test_an_unnamed_partial_file_has_no_name_in_the_folder_while_written(tmp_path):
    partial = PartialFile(tmp_path / "face.mp4")
    partial.file.write(b"x" * 10_000)
    partial.file.flush()
    assert partial.path is None and list(tmp_path.iterdir()) == []
    partial.discard()
    assert list(tmp_path.iterdir()) == []


def test_a_named_partial_is_hidden_beside_its_target_and_discarded_with_what_it_held(tmp_path):
    partial = PartialFile(tmp_path / "face.mp4", named=True)
    assert partial.path.parent == tmp_path and partial.path.name.startswith(".face.mp4.")
    assert partial.path.name.endswith(".baxterface-partial")
    partial.file.write(b"half")
    partial.discard()
    assert list(tmp_path.iterdir()) == []


def test_a_partial_is_never_written_through_a_planted_link(tmp_path, monkeypatch):
    victim = tmp_path / "victim"
    victim.write_bytes(b"mine")
    names = iter(["planted", "free"])
    monkeypatch.setattr(partial_files, "_partial_name", lambda target: tmp_path / next(names))
    (tmp_path / "planted").symlink_to(victim)
    path, file = partial_files.create_file(tmp_path / "face.gif")  # the planted name is passed over
    with file:
        file.write(b"new")
    assert path.name == "free" and victim.read_bytes() == b"mine"


def test_write_atomic_leaves_the_old_file_when_writing_fails(tmp_path):
    target = tmp_path / "show.face"
    target.write_text("happy\n")

    with pytest.raises(TypeError):  # anything going wrong halfway: here, what is written is no bytes
        write_atomic(target, "sad\n")  # type: ignore[arg-type]
    assert target.read_text() == "happy\n"
    assert [p.name for p in tmp_path.iterdir()] == ["show.face"]


def test_only_partials_whose_writer_is_gone_are_removed(tmp_path):
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True)
    dead_pid = int(gone.stdout)
    stale = tmp_path / f".face.gif.{dead_pid}.abcd1234.baxterface-partial"
    alive = tmp_path / f".face.gif.{os.getpid()}.abcd1234.baxterface-partial"
    other = tmp_path / ".face.gif.notes"
    for path in (stale, alive, other):
        path.write_bytes(b"x")
    remove_stale(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([alive.name, other.name])
