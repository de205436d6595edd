"""One writer per atlas: a second sweep into an atlas that a running one is writing is refused.

HDF5's own file lock cannot do this job here (``atlas_format.WRITER_LOCKING``): it is held only
while the file is open, blocks readers, and Dask's nanny forks workers that inherit it. This lock
is an ``flock`` on ``ATLAS.h5.lock``, held from before the atlas is prepared until after its
last write. The kernel drops it when the sweep's process is gone, even after ``kill -9``; the
file left behind by such a kill is taken over by the next sweep. Forked workers close their
copy of its descriptor at once (an flock lives as long as any copy does), so that a worker
outliving a killed client for a moment does not hold the atlas.

The file names its holder: process, host and start (``PID HOST SINCE``), as a study on a
shared filesystem runs its sweeps from several machines and a process number alone says
nothing there (Linux's NFS client carries flock to the server, so the exclusion holds across
hosts). Whether the atlas is held is asked of the lock itself, never of the process number: a
file left by a kill may name a number that another process has taken since, or a process on
another machine that this one cannot see.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import socket
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from .journal import AtlasError

LOCK_SUFFIX = ".lock"
#: how long (s) a sweep keeps trying a lock that is held before it says the atlas is busy:
#: ``writer`` takes it for an instant to see whether anyone holds it
BUSY_PATIENCE = 1.0
_held: list[int] = []  # this process's lock descriptors
_held_by_atlas: dict[Path, int] = {}  # atlas (resolved) -> its lock's descriptor


def _drop_in_child() -> None:
    for fd in _held:
        with contextlib.suppress(OSError):
            os.close(fd)  # the child's copy only: the parent's lock stands
    _held.clear()


os.register_at_fork(after_in_child=_drop_in_child)


@dataclass(frozen=True)
class Holder:
    """The sweep holding an atlas's lock, as its lock file names it. ``pid`` None, ``host``
    and ``since`` "" when the file does not say (an older pydrill's wrote the pid alone)."""

    pid: int | None
    host: str
    since: str  #: when it took the lock, UTC, e.g. ``2026-11-30T22:41:05Z``

    @classmethod
    def parse(cls, text: str) -> Holder:
        words = text.split()
        pid = int(words[0]) if words and words[0].isdigit() else None
        return cls(pid, words[1] if len(words) > 1 else "", words[2] if len(words) > 2 else "")

    def __str__(self) -> str:
        what = "a process" if self.pid is None else f"process {self.pid}"
        here = socket.gethostname()
        if self.host:
            what += f" on host {self.host}" + (" (this machine)" if self.host == here else "")
            if self.host == here and self.pid is not None and not _alive(self.pid):
                # Only a process it started can hold the lock now: a child that kept the
                # descriptor (fork without exec).
                what += ", which has ended; a process it started still holds the lock"
        if self.since:
            what += f", since {self.since.replace('T', ' ').rstrip('Z')} UTC"
        return what


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except PermissionError:  # alive, another user's
        return True
    except OSError:  # no such process
        return False
    return True


class AtlasBusy(AtlasError):
    """Another process is writing this atlas."""

    @classmethod
    def of(cls, atlas: Path, holder: object) -> AtlasBusy:
        return cls(
            f"{atlas} is being written by another sweep ({holder}); wait for it to end, or "
            "stop it (what it computed is kept) and run again with resume=True"
        )


@contextlib.contextmanager
def writer_lock(atlas: Path) -> Iterator[None]:
    path = atlas.with_name(atlas.name + LOCK_SUFFIX)
    deadline = time.monotonic() + BUSY_PATIENCE
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
            holder = Holder.parse(os.read(fd, 256).decode(errors="replace"))
            os.close(fd)
            if time.monotonic() < deadline:  # perhaps only ``writer`` looking: try again
                time.sleep(0.05)
                continue
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
        since = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        os.write(fd, f"{os.getpid()} {socket.gethostname()} {since}\n".encode())
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


def writer(atlas: Path) -> Holder | None:
    """The sweep writing ``atlas`` now, as its lock file names it; None if none is. Asks the
    lock (taken shared for an instant, which a starting sweep rides over: ``BUSY_PATIENCE``),
    not the process number: a file left by ``kill -9`` names a process that is gone, or one
    that took its number since, and a process on another host is not seen from this one."""
    try:
        fd = os.open(atlas.with_name(atlas.name + LOCK_SUFFIX), os.O_RDONLY)
    except OSError:  # no file: nobody writes it
        return None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:  # held: by a sweep, which named itself in the file
            for _ in range(20):  # or is about to: it writes its name once it holds the lock
                holder = Holder.parse(os.pread(fd, 256, 0).decode(errors="replace"))
                if holder.pid is not None:
                    break
                time.sleep(0.01)
            return holder
        except OSError:  # a filesystem without flock: say nothing rather than guess
            return None
        fcntl.flock(fd, fcntl.LOCK_UN)
        return None
    finally:
        os.close(fd)


def writer_of(atlas: Path) -> int | None:
    """The process number of the sweep writing ``atlas`` now (``writer``); None if none is,
    -1 for a holder whose lock file does not name it."""
    holder = writer(atlas)
    if holder is None:
        return None
    return -1 if holder.pid is None else holder.pid
