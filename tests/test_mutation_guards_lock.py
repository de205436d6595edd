"""The atlas writer's lock, against flock itself and the lock file's documented format.

Found by a mutation audit (atlas_lock): a lock held by a file that names no process was
taken for no lock at all, text that is no process number was a ValueError, and a sweep
gave up on a lock that ``writer`` held for an instant (BUSY_PATIENCE) at its first try.
"""

import fcntl
import os
import threading

from pydrill.atlas_lock import LOCK_SUFFIX, Holder, writer, writer_lock, writer_of


def _hold(lock):
    """An exclusive flock on ``lock`` through a descriptor of its own (as a sweep's)."""
    fd = os.open(lock, os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    return fd


def test_the_lock_file_is_read_as_pid_host_since_and_what_it_lacks_is_empty():
    since = "2026-11-30T22:41:05Z"
    assert Holder.parse(f"12 node7 {since}\n") == Holder(12, "node7", since)
    assert Holder.parse("12\n") == Holder(12, "", "")  # an older pydrill's: the pid alone
    assert Holder.parse("") == Holder(None, "", "")
    assert Holder.parse("pid? node7") == Holder(None, "node7", "")


def test_a_held_lock_whose_file_names_no_process_is_still_held(tmp_path):
    """writer_of: -1 (held, by whom unsaid), not None (free: snapshot would then read a
    file being written); None again once the flock is let go."""
    atlas = tmp_path / "a.h5"
    lock = tmp_path / ("a.h5" + LOCK_SUFFIX)
    lock.write_text("not a process\n")
    fd = _hold(lock)
    try:
        assert writer(atlas) == Holder(None, "a", "process")
        assert writer_of(atlas) == -1
    finally:
        os.close(fd)
    assert writer(atlas) is None and writer_of(atlas) is None


def test_a_sweep_waits_out_a_lock_held_for_less_than_its_patience(tmp_path):
    """Held 0.2 s (BUSY_PATIENCE is 1 s): the sweep's lock is taken once it is let go."""
    atlas = tmp_path / "a.h5"
    fd = _hold(tmp_path / ("a.h5" + LOCK_SUFFIX))
    threading.Timer(0.2, os.close, [fd]).start()
    with writer_lock(atlas):
        assert writer_of(atlas) == os.getpid()


def test_a_lock_file_removed_before_the_flock_lands_is_not_the_lock_taken(tmp_path, monkeypatch):
    """The holder before removes its file between our open and our flock: that flock is on
    a file nobody sees; the sweep starts over, and the lock it holds is the path's."""
    atlas, real = tmp_path / "a.h5", fcntl.flock
    removed = []

    def flock(fd, op):
        if not removed:  # the first flock: the file goes just before
            removed.append(os.fstat(fd).st_ino)
            os.unlink(tmp_path / ("a.h5" + LOCK_SUFFIX))
        return real(fd, op)

    monkeypatch.setattr(fcntl, "flock", flock)
    with writer_lock(atlas):
        monkeypatch.setattr(fcntl, "flock", real)
        assert removed and writer_of(atlas) == os.getpid()
