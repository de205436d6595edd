"""Standard streams that a forked Dask worker can write to.

A local cluster's nanny forks its workers from this process, from a thread of Dask's own, at
start-up and whenever a worker has died. A fork copies the lock of every buffered stream as it
is at that instant: if another thread was inside ``sys.stderr.write`` (a progress bar, a log
line), the child's copy of that lock is held by a thread that does not exist in the child, and
the child's first write to stderr — a worker logs "Start worker at ..." — waits for ever (seen:
a replacement worker hung in ``logging.StreamHandler.flush``, and with it the sweep, whose
process then waited for that worker at exit). Python re-initialises the locks of ``logging``
after a fork, not those of the streams.

So, while :func:`forking_workers` is active, a forked child replaces ``sys.stdout`` and
``sys.stderr`` (and ``sys.__stdout__``/``sys.__stderr__``) with fresh streams on duplicates
of the same file descriptors, and so the stream of every logging handler on a descriptor.
Output goes where it went; only the copied locks are left behind.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
from collections.abc import Iterator

_active = 0  # forking_workers() blocks entered and not left
_registered = False


@contextlib.contextmanager
def forking_workers() -> Iterator[None]:
    """Children forked by this process inside the block get fresh standard streams."""
    global _active, _registered
    if not _registered:  # at-fork hooks cannot be removed: one, asking _active
        os.register_at_fork(after_in_child=_after_fork_in_child)
        _registered = True
    _active += 1
    try:
        yield
    finally:
        _active -= 1


def _after_fork_in_child() -> None:
    if _active:
        fresh_std_streams()


def fresh_std_streams() -> None:
    """Replace this process's standard output and error streams by new ones on duplicates of
    their file descriptors, and so the stream of every logging handler that writes to a file
    descriptor (a handler keeps the stream it was made with: Dask's, the sys.stderr of the
    moment it was imported, which need not be today's)."""
    swaps: dict[int, object] = {}

    def fresh(old):
        if id(old) not in swaps:
            swaps[id(old)] = _reopen(old)
        return swaps[id(old)]

    for attr in ("stdout", "stderr", "__stdout__", "__stderr__"):
        old = getattr(sys, attr, None)
        if old is not None and fresh(old) is not None:
            setattr(sys, attr, swaps[id(old)])
    loggers = [logging.getLogger()] + [
        x for x in logging.Logger.manager.loggerDict.values() if isinstance(x, logging.Logger)
    ]
    for logger in loggers:
        for handler in logger.handlers:
            stream = getattr(handler, "stream", None)
            if isinstance(handler, logging.StreamHandler) and stream is not None:
                new = fresh(stream)
                if new is not None:  # not setStream(): it flushes the old one, which hangs
                    handler.stream = new


def _reopen(stream):
    """A new line-buffered text stream on a duplicate of ``stream``'s descriptor; None for a
    stream without one (io.StringIO, a closed stream)."""
    try:
        fd = stream.fileno()
    except (AttributeError, OSError, ValueError):
        return None
    try:
        copy = os.dup(fd)
    except OSError:
        return None
    encoding = getattr(stream, "encoding", None) or "utf-8"
    errors = getattr(stream, "errors", None) or "backslashreplace"
    return open(copy, "w", buffering=1, encoding=encoding, errors=errors)
