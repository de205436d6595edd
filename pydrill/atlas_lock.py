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
_held_by_atlas: dict[Path, int] = {}  # atlas (resolved) -> its lock's descriptor


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
            "end, or stop it (what it computed is kept) and run again with --resume (resume=True)"
        )


@contextlib.contextmanager
def writer_lock(atlas: Path) -> Iterator[None]:
    path = atlas.with_name(atlas.name + LOCK_SUFFIX)
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:  # say what it is for: the user named the atlas, not this
            raise AtlasError(
                f"{atlas}: cannot create its lock file {path.name} beside it ({exc.strerror})"
            ) from None
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
    _held_by_atlas[atlas.resolve()] = fd
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
        _held.remove(fd)
        _held_by_atlas.pop(atlas.resolve(), None)
        os.close(fd)


# Reading an atlas while its sweep rewrites it: HDF5 has no safe way without SWMR (which
# takes neither variable-length strings nor a rewrite of compressed chunks), and a reader
# that meets a half-written chunk fails ("filter returned failure", "addr overflow") or,
# worse, reads it. So the writer holds a POSIX record lock (fcntl) on the lock file, shared
# by nobody, while it writes the atlas; a reader takes the same lock shared, copies the file
# into memory and reads the copy: the state of the last complete write. Record locks are
# independent of the flock above, and forked workers do not inherit them.


@contextlib.contextmanager
def writing(atlas: Path) -> Iterator[None]:
    """Around every write of ``atlas`` by its sweep: readers wait until the write is whole.
    Nothing to do for an atlas this process does not hold (tests, a one-off rebuild)."""
    fd = _held_by_atlas.get(atlas.resolve())
    if fd is None:
        yield
        return
    fcntl.lockf(fd, fcntl.LOCK_EX)
    try:
        yield
    finally:
        fcntl.lockf(fd, fcntl.LOCK_UN)


def snapshot(atlas: Path) -> bytes | None:
    """The bytes of ``atlas`` as its last complete write left them, while a sweep is writing
    it; None when none is (then read the file itself)."""
    if writer_of(atlas) is None:
        return None
    try:
        fd = os.open(atlas.with_name(atlas.name + LOCK_SUFFIX), os.O_RDONLY)
    except OSError:  # the sweep ended, and removed its lock, since
        return None
    try:
        fcntl.lockf(fd, fcntl.LOCK_SH)  # waits while the writer writes
        return atlas.read_bytes()
    finally:
        os.close(fd)  # drops the lock


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
