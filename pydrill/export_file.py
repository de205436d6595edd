"""A file that HDF5 (through h5py's file-object driver) writes an export into, and whose
failures it never sees.

HDF5 told of a failed write (a full disk, a file size limit) leaves its metadata cache half
flushed, and h5py closing that file crashed Python (a segmentation fault, h5py 3.16 with
HDF5 2.0). So ``SinkFile`` remembers the first failure and tells HDF5 every write succeeded:
what it writes from then on is kept in memory, and read back from there, so that HDF5 finds
the file as it believes it wrote it and finishes it as if nothing had happened. The caller
then raises ``error``, and throws the file away.
"""

from __future__ import annotations

import io
import os
from typing import Any


class SinkFile(io.RawIOBase):
    """A raw, seekable, readable and writable file on the descriptor ``fd`` (opened for
    reading and writing), positioned by itself (``os.pread``/``os.pwrite``: no seek can
    fail). ``error``: the first OSError a write, a truncation or a flush met, or None. After
    it, writes go to memory: as much as HDF5 writes after it (at most the export's size)."""

    def __init__(self, fd: int) -> None:
        super().__init__()
        self.fd = fd
        self.error: OSError | None = None
        self.pos = 0
        self.size = 0  # the file's size as HDF5 sees it
        self.later: list[tuple[int, bytes]] = []  # what was written after the failure, in order

    def readable(self) -> bool:
        return True

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def tell(self) -> int:
        return self.pos

    def seek(self, offset: int, whence: int = os.SEEK_SET) -> int:
        base = {os.SEEK_SET: 0, os.SEEK_CUR: self.pos, os.SEEK_END: self.size}[whence]
        self.pos = max(0, base + offset)
        return self.pos

    def readinto(self, buffer: Any) -> int:
        view = memoryview(buffer).cast("B")
        n = max(0, min(len(view), self.size - self.pos))
        data = os.pread(self.fd, n, self.pos) if n else b""
        view[: len(data)] = data
        view[len(data) : n] = bytes(n - len(data))  # a hole, or past a failed write: zeros
        for at, chunk in self.later:  # what HDF5 wrote after the failure, over the file's
            lo, hi = max(at, self.pos), min(at + len(chunk), self.pos + n)
            if lo < hi:
                view[lo - self.pos : hi - self.pos] = chunk[lo - at : hi - at]
        self.pos += n
        return n

    def write(self, data: Any) -> int:
        chunk = bytes(data)
        if self.error is None:
            try:
                done = 0
                while done < len(chunk):
                    done += os.pwrite(self.fd, chunk[done:], self.pos + done)
            except OSError as exc:
                self.error = exc
        if self.error is not None:
            self.later.append((self.pos, chunk))
        self.pos += len(chunk)
        self.size = max(self.size, self.pos)
        return len(chunk)

    def truncate(self, size: int | None = None) -> int:
        size = self.pos if size is None else size
        if self.error is None:
            try:
                os.ftruncate(self.fd, size)
            except OSError as exc:
                self.error = exc
        self.size = size
        return size

    def flush(self) -> None:
        pass  # every write went straight to the descriptor (or memory)

    def close(self) -> None:
        # The descriptor is its owner's (``_write_whole``): not closed here.
        self.later = []
        super().close()
