"""SinkFile (what HDF5 writes an export into) against io.BytesIO and the bytes on disk, where a
mutation audit found it untested: a seek before the start, a read past the end, a truncation
at the current position, and a write the kernel takes in pieces."""

import io
import os

import pytest

from pydrill import export_file
from pydrill.export_file import SinkFile


@pytest.fixture
def sink(tmp_path):
    fd = os.open(tmp_path / "sink", os.O_RDWR | os.O_CREAT)
    yield SinkFile(fd)
    os.close(fd)


def test_a_seek_before_the_start_is_the_start_and_a_read_past_the_end_is_empty(sink):
    """BytesIO refuses a negative position; SinkFile, whose seeks must never fail (HDF5
    would be told so), stays at 0. Past the end both read nothing (a pread at a negative
    length or offset would raise)."""
    ref = io.BytesIO()
    for f in (sink, ref):
        f.write(b"0123456789")
    assert sink.seek(-100, os.SEEK_END) == 0 and sink.read(3) == b"012"
    assert sink.seek(-50, os.SEEK_CUR) == 0 and sink.tell() == 0
    assert sink.seek(25) == ref.seek(25) == 25
    assert sink.read(5) == ref.read(5) == b""
    assert sink.tell() == ref.tell() == 25


def test_truncate_without_a_size_cuts_at_the_current_position_as_bytesio_does(sink):
    ref = io.BytesIO()
    for f in (sink, ref):
        f.write(b"0123456789")
        f.seek(4)
    assert sink.truncate() == ref.truncate() == 4
    assert sink.seek(0, os.SEEK_END) == ref.seek(0, os.SEEK_END) == 4
    assert os.fstat(sink.fd).st_size == 4


def test_a_write_taken_in_pieces_lands_in_order(sink, monkeypatch):
    """pwrite may write fewer bytes than asked (a signal, a pipe, some file systems): the
    rest goes after them, not over them."""
    real = os.pwrite
    monkeypatch.setattr(export_file.os, "pwrite", lambda fd, data, at: real(fd, data[:3], at))
    sink.seek(2)
    assert sink.write(b"abcdefgh") == 8 and sink.error is None
    assert os.pread(sink.fd, 100, 0) == b"\0\0abcdefgh"
