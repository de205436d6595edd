"""A worker forked while another thread writes to stderr: its own writes must not hang.

The hazard, reproduced exactly: a thread of the parent is inside a write to stderr (its
buffer's lock held) when another thread forks. The child's copy of that lock is held for ever.
"""

import subprocess
import sys
import textwrap

SCENARIO = textwrap.dedent(
    """
    import io, logging, os, sys, tempfile, threading, time
    from pydrill.fork_stdio import forking_workers

    guarded = sys.argv[1] == "guarded"
    gate, inside = threading.Event(), threading.Event()

    class Slow(io.RawIOBase):  # a stderr whose writes wait: its buffer's lock stays held
        def __init__(self, fd):
            self.fd = fd
        def writable(self):
            return True
        def fileno(self):
            return self.fd
        def write(self, b):
            if threading.current_thread() is not threading.main_thread():
                inside.set()
                gate.wait()
            return os.write(self.fd, b)

    log = tempfile.NamedTemporaryFile(delete=False)
    stream = io.TextIOWrapper(io.BufferedWriter(Slow(log.fileno())), line_buffering=True)
    sys.stderr = stream
    logger = logging.getLogger("worker")
    logger.addHandler(logging.StreamHandler(stream))
    if sys.argv[2] == "moved":  # the handler's stream is no longer sys.stderr (as Dask's,
        sys.stderr = open(os.devnull, "w")  # made at import, is under pytest's capture)
    writer = threading.Thread(target=lambda: stream.write("a progress bar\\n"), daemon=True)
    writer.start()
    # Until the writer is inside the write, holding the lock: a fixed 0.3 s promised nothing
    # on a loaded machine, where the child could fork with the lock free, and not hang.
    assert inside.wait(60), "the writer thread never reached its write"

    def child():
        logger.error("worker started")  # as a Dask worker logs "Start worker at ..."
        sys.stderr.flush()
        os._exit(0)

    with forking_workers() if guarded else open(os.devnull):
        pid = os.fork()
        if pid == 0:
            child()
    # A hung child stays hung: 5 s tell it. A guarded child exits at once, but one that is
    # slow to be scheduled on a loaded machine is not a hung one: up to 30 s for it.
    for _ in range(600 if guarded else 100):
        done, _ = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        time.sleep(0.05)
    else:
        os.kill(pid, 9)
        os.waitpid(pid, 0)
    gate.set()
    writer.join()
    stream.flush()
    print("hung" if not done else "exited", open(log.name).read().count("worker started"))
    """
)


def run(mode: str, *stderrs: str) -> list[str]:
    """The scenario's output in ``mode`` for each of ``stderrs``, each in a process of its own,
    run side by side (a hung child is waited for 5 s: the scenarios wait at the same time)."""
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", SCENARIO, mode, stderr],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for stderr in stderrs
    ]
    outs = []
    try:
        for proc in procs:
            out, err = proc.communicate(timeout=60)
            assert proc.returncode == 0, err
            outs.append(out.strip())
    finally:
        for proc in procs:
            if proc.poll() is None:
                proc.kill()
                proc.communicate()
    return outs


def test_a_child_forked_during_a_write_to_stderr_hangs_without_the_guard():
    """The scenario reproduces the hazard: unguarded, the child never gets its line out."""
    assert run("bare", "same", "moved") == ["hung 0", "hung 0"]


def test_a_child_forked_under_the_guard_writes_its_log_line_and_exits():
    # "moved": a logging handler on a stream that sys.stderr no longer is: its stream is
    # renewed too
    assert run("guarded", "same", "moved") == ["exited 1", "exited 1"]


WIRED = textwrap.dedent(
    """
    import sys
    from pydrill import fork_stdio
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    spec = parse_spec(sys.argv[1])
    how = {"serial": True} if sys.argv[3] == "serial" else {"workers": 1}
    run_sweep(spec, sys.argv[2], **how)
    print(fork_stdio._registered, fork_stdio._active)
    """
)


def test_a_local_cluster_forks_its_workers_under_the_guard_and_leaves_it(tmp_path):
    """The sweep's own cluster is started under the guard (registered), which ends with it
    (children forked later by the caller keep their streams); a serial sweep forks nothing."""
    from sweeping import TINY

    for how, expect in (("serial", "False 0"), ("local", "True 0")):
        argv = [sys.executable, "-c", WIRED, TINY, str(tmp_path / f"{how}.h5"), how]
        proc = subprocess.run(argv, capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert proc.stdout.strip() == expect
