"""multibots._io: the one atomic writer every output file goes through."""

from __future__ import annotations

import os
import stat

import pytest

from multibots import MultibotsError, OutputError, _io


def test_writes_whole_files_with_the_usual_mode(tmp_path):
    target = tmp_path / "sub" / "out.txt"
    assert _io.atomic_write_text(target, "one") == target
    assert target.read_text() == "one"
    _io.atomic_write_bytes(target, b"two")
    assert target.read_bytes() == b"two"
    mask = os.umask(0o022)
    os.umask(mask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~mask
    assert sorted(p.name for p in target.parent.iterdir()) == ["out.txt"]


def test_the_umask_is_read_once_at_import(tmp_path, monkeypatch):
    # Reading the umask means setting it; a writer that did so on every call would race with
    # threads that create files meanwhile. This one never calls os.umask after import.
    def no(*args):
        raise AssertionError("os.umask called while writing")

    monkeypatch.setattr(os, "umask", no)
    _io.atomic_write_text(tmp_path / "x.txt", "x")
    assert (tmp_path / "x.txt").read_text() == "x"


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "keep.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with _io.atomic_open(target) as f:
            f.write(b"half")
            raise RuntimeError("disk full")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


@pytest.mark.parametrize("kind", ["directory", "dev-null", "fifo", "symlink-to-dev-null"])
def test_refuses_to_replace_what_is_not_a_regular_file(tmp_path, kind):
    if kind == "directory":
        target = tmp_path / "folder"
        target.mkdir()
    elif kind == "dev-null":
        target = "/dev/null"
    elif kind == "fifo":
        target = tmp_path / "pipe"
        os.mkfifo(target)
    else:
        target = tmp_path / "link"
        target.symlink_to("/dev/null")
    with pytest.raises(OutputError) as e:
        _io.atomic_write_text(target, "x")
    msg = str(e.value)
    assert isinstance(e.value, MultibotsError) and "\n" not in msg
    assert str(target) in msg and "refusing to replace" in msg
    assert os.path.exists("/dev/null") and stat.S_ISCHR(os.stat("/dev/null").st_mode)
    if kind == "directory":
        assert os.path.isdir(target)
    if kind == "fifo":
        assert stat.S_ISFIFO(os.stat(target).st_mode)


def test_a_folder_that_cannot_be_written_is_one_line(tmp_path):
    (tmp_path / "file").write_text("")
    for target in (tmp_path / "file" / "x.txt", tmp_path / "file" / "sub" / "x.txt"):
        with pytest.raises(OutputError, match="cannot write") as e:
            _io.atomic_write_text(target, "x")
        assert "\n" not in str(e.value) and "Not a directory" in str(e.value)
