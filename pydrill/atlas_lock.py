"""One writer per atlas: a second sweep into an atlas that a running one is writing is refused.

HDF5's own file lock cannot do this job here (``atlas_format.WRITER_LOCKING``): it is held only
while the file is open, blocks readers, and Dask's nanny forks workers that inherit it. This lock
is an ``flock`` on ``ATLAS.h5.lock``, held from before the atlas is prepared until after its
last write. The kernel drops it when the sweep's process is gone, even after ``kill -9``; the
file left behind by such a kill is taken over by the next sweep. Forked workers close their
copy of its descriptor at once (an flock lives as long as any copy does), so that a worker
outliving a killed client for a moment does not hold the atlas.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from .journal import AtlasError

LOCK_SUFFIX = ".lock"
_held: list[int] = []  # this process's lock descriptors


def _drop_in_child() -> None:
    for fd in _held:
        with contextlib.suppress(OSError):
            os.close(fd)  # the child's copy only: the parent's lock stands
    _held.clear()


os.register_at_fork(after_in_child=_drop_in_child)


class AtlasBusy(AtlasError):
    """Another process is writing this atlas."""

    @classmethod
    def of(cls, atlas: Path, holder: object) -> AtlasBusy:
        return cls(
            f"{atlas} is being written by another sweep (process {holder}); wait for it to "
            "end, or stop it (what it computed is kept) and run again with --resume"
        )


@contextlib.contextmanager
def writer_lock(atlas: Path) -> Iterator[None]:
    path = atlas.with_name(atlas.name + LOCK_SUFFIX)
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise AtlasBusy.of(atlas, holder) from None
        # The holder before us may have removed the file between our open and our flock:
        # then we hold a lock nobody else can see, and start over on the path's new file.
        try:
            same = os.stat(path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    _held.append(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
        _held.remove(fd)
        os.close(fd)


def writer_of(atlas: Path) -> int | None:
    """The process writing ``atlas`` now, as its lock file names it; None if none is. Reads
    only (no lock is taken, which could turn a sweep starting that instant away): for
    reports such as a dry run, not for exclusion. A file left by a killed sweep names a
    process that is gone."""
    try:
        pid = int(atlas.with_name(atlas.name + LOCK_SUFFIX).read_text().strip())
    except (OSError, ValueError):  # no file, or no number in it
        return None
    try:
        os.kill(pid, 0)
    except PermissionError:  # alive, another user's
        return pid
    except OSError:  # no such process
        return None
    return pid
