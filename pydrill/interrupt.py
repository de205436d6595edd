"""How a sweep stops on Ctrl-C (or another signal it is told to stop on): between batches.

A sweep's client absorbs each finished batch in two steps, the journal and the in-memory table.
A KeyboardInterrupt between them would leave the atlas, flushed on the way out, one batch short
of the journal (nothing lost: ``--resume`` replays the journal, but the atlas would not show
what the sweep says it saved). So while a batch is absorbed, the signal is held and acted on
right after.

The handlers are installed before Dask's nanny forks the workers, which inherit them. Ctrl-C
in a terminal goes to the whole process group, workers included: in a worker the handler
ignores SIGINT (the client shuts the workers down, and no worker prints a traceback of its
own), and gives any other signal its default action (a nanny's SIGTERM still ends a worker).
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field


@dataclass
class Stop:
    """What ``stop_between_batches`` yields: ``hold`` and the signal that came (0: none)."""

    hold: Callable[[], contextlib.AbstractContextManager[None]]
    signum: int = 0
    _holding: bool = field(default=False, repr=False)
    _pending: bool = field(default=False, repr=False)


@contextlib.contextmanager
def stop_between_batches(signals: tuple[int, ...] = (signal.SIGINT,)) -> Iterator[Stop]:
    """While active, each of ``signals`` raises KeyboardInterrupt in the main thread, but not
    inside ``with stop.hold(): ...``, whose block runs whole first. Signals the process ignores
    (a shell's background job ignores SIGINT) stay ignored."""

    @contextlib.contextmanager
    def hold() -> Iterator[None]:
        stop._holding = True
        try:
            yield
        finally:
            stop._holding = False
        if stop._pending:
            stop._pending = False
            raise KeyboardInterrupt

    stop = Stop(hold)
    if threading.current_thread() is not threading.main_thread():
        yield stop  # only the main thread may set handlers (and gets KeyboardInterrupt)
        return
    client = os.getpid()

    def handler(signum, frame):
        if os.getpid() != client:  # in a forked worker
            if signum != signal.SIGINT:
                signal.signal(signum, signal.SIG_DFL)
                os.kill(os.getpid(), signum)
            return
        stop.signum = signum
        if stop._holding:
            stop._pending = True
            return
        raise KeyboardInterrupt

    previous = {}
    for sig in signals:
        if signal.getsignal(sig) is not signal.SIG_IGN:
            previous[sig] = signal.signal(sig, handler)
    try:
        yield stop
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)
