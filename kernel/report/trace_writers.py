"""Explicit writers for trace tables (:mod:`kernel.report.trace`): CSV, NPZ and Parquet, streamed.

Each writer takes one chunk (a dict of equal-length column arrays in the order of
:func:`kernel.report.trace.columns`) at a time and never holds more than that chunk:

* CSV: a header line, then the rows; integers as integers, reals with ``%.9g``.
* NPZ: one ``.npy`` array per column in a ZIP (stored, not compressed), loadable with
  ``numpy.load``. The length is known only at the end, so the chunks go to one raw file per
  column beside the target first and are copied into the archive in blocks on close.
* Parquet: one row group per chunk through pyarrow (the ``parquet`` extra;
  ``IO-PARQUET`` when it is not installed).

Writers refuse to replace an existing file unless ``force`` is given (``IO-EXISTS``).
"""

from __future__ import annotations

import io
import os
import shutil
import struct
import tempfile
import zipfile
import zlib
from typing import Any, Protocol

import numpy as np

from kernel.diagnostics import Diagnostic, Location

FORMATS: tuple[str, ...] = ("csv", "npz", "parquet")
_BLOCK = 1 << 20


class Writer(Protocol):
    path: str

    def write(self, table: dict[str, np.ndarray]) -> None: ...

    def close(self) -> None: ...


def check_target(path: str, force: bool) -> None:
    """``IO-EXISTS`` when ``path`` exists and ``force`` is not set."""
    if os.path.exists(path) and not force:
        raise Diagnostic(
            "IO-EXISTS", "output file exists; use --force to replace it", Location(path)
        )


class CsvWriter:
    """Comma-separated values with a header row."""

    def __init__(self, path: str, names: list[str], force: bool = False) -> None:
        check_target(path, force)
        self.path = path
        self.names = names
        self._fh = open(path, "w", encoding="ascii", newline="\n")  # noqa: SIM115
        self._fh.write(",".join(names) + "\n")

    def write(self, table: dict[str, np.ndarray]) -> None:
        n = len(table[self.names[0]])
        if n == 0:
            return
        fmts = ["%d" if np.issubdtype(table[c].dtype, np.integer) else "%.9g" for c in self.names]
        row = ",".join(fmts) + "\n"
        # integer columns (segment, line) are exact in float64 and printed with %d
        flat = np.column_stack([np.asarray(table[c], dtype=float) for c in self.names])
        self._fh.write((row * n) % tuple(flat.ravel().tolist()))

    def close(self) -> None:
        self._fh.close()


class NpzWriter:
    """Columns as arrays of an ``.npy``-per-column ZIP (``numpy.load(path)[name]``).

    With ``rows`` known in advance the archive's layout is fixed before the first chunk:
    each chunk is written once, at its place in its column (ZIP64, stored), and the CRCs and
    the central directory are completed on close. Without it the chunks go to one raw file
    per column beside the target and are copied into the archive on close.
    """

    def __init__(
        self,
        path: str,
        names: list[str],
        force: bool = False,
        rows: int | None = None,
        dtypes: dict[str, np.dtype] | None = None,
    ) -> None:
        check_target(path, force)
        self.path = path
        self.names = names
        self._count = 0
        self._dtype: dict[str, np.dtype] = dict(dtypes or {})
        self._direct = rows is not None and all(n in self._dtype for n in names)
        if self._direct:
            self._layout = _ZipLayout(path, names, [self._dtype[n] for n in names], int(rows))
            return
        folder = os.path.dirname(os.path.abspath(path))
        self._tmp = tempfile.mkdtemp(prefix=".trace-", dir=folder)
        self._files: dict[str, Any] = {}

    def write(self, table: dict[str, np.ndarray]) -> None:
        n = len(table[self.names[0]])
        if self._direct:
            cols = [np.ascontiguousarray(table[c], dtype=self._dtype[c]) for c in self.names]
            self._layout.write(self._count, cols)
            self._count += n
            return
        for name in self.names:
            col = np.ascontiguousarray(table[name])
            if name not in self._files:
                raw = os.path.join(self._tmp, f"{len(self._files)}.raw")
                self._files[name] = open(raw, "wb")  # noqa: SIM115
                self._dtype.setdefault(name, col.dtype)
            self._files[name].write(col.astype(self._dtype[name], copy=False).tobytes())
        self._count += n

    def close(self) -> None:
        if self._direct:
            self._layout.close(self._count)
            return
        try:
            for fh in self._files.values():
                fh.close()
            with zipfile.ZipFile(self.path, "w", zipfile.ZIP_STORED, allowZip64=True) as zf:
                for i, name in enumerate(self.names):
                    dtype = self._dtype.get(name, np.dtype(float))
                    header = {
                        "descr": np.lib.format.dtype_to_descr(dtype),
                        "fortran_order": False,
                        "shape": (self._count,),
                    }
                    with zf.open(f"{name}.npy", "w", force_zip64=True) as out:
                        np.lib.format.write_array_header_2_0(out, header)
                        raw = os.path.join(self._tmp, f"{i}.raw")
                        if os.path.exists(raw):
                            with open(raw, "rb") as src:
                                shutil.copyfileobj(src, out, _BLOCK)
        finally:
            shutil.rmtree(self._tmp, ignore_errors=True)


class _ZipLayout:
    """A stored ZIP64 archive of ``.npy`` entries whose sizes are known up front
    (PKWARE APPNOTE 4.3: local headers with ZIP64 extra, central directory, ZIP64 end)."""

    def __init__(self, path: str, names: list[str], dtypes: list[np.dtype], rows: int) -> None:
        self.rows = rows
        self.names = [f"{n}.npy".encode() for n in names]
        self.items = [d.itemsize for d in dtypes]
        self.fh = open(path, "wb")  # noqa: SIM115
        self.offsets: list[int] = []  # local header offsets
        self.data: list[int] = []  # where each column's array data starts
        self.sizes: list[int] = []
        self.crc: list[int] = []
        pos = 0
        for name, dtype, item in zip(self.names, dtypes, self.items, strict=True):
            buf = io.BytesIO()
            np.lib.format.write_array_header_1_0(
                buf,
                {
                    "descr": np.lib.format.dtype_to_descr(dtype),
                    "fortran_order": False,
                    "shape": (rows,),
                },
            )
            head = buf.getvalue()
            size = len(head) + rows * item
            self.offsets.append(pos)
            self.fh.seek(pos)
            self.fh.write(self._local(name, size, 0))
            self.fh.write(head)
            self.crc.append(zlib.crc32(head))
            self.data.append(self.fh.tell())
            self.sizes.append(size)
            pos = self.fh.tell() + rows * item

    @staticmethod
    def _local(name: bytes, size: int, crc: int) -> bytes:
        extra = struct.pack("<HHQQ", 1, 16, size, size)
        return (
            struct.pack(
                "<IHHHHHIIIHH",
                0x04034B50,
                45,
                0,
                0,
                0,
                0x21,
                crc,
                0xFFFFFFFF,
                0xFFFFFFFF,
                len(name),
                len(extra),
            )
            + name
            + extra
        )

    def write(self, start: int, cols: list[np.ndarray]) -> None:
        if start + cols[0].size > self.rows:
            raise Diagnostic("TRACE-ROWS", f"more than the {self.rows} rows announced")
        for i, col in enumerate(cols):
            self.fh.seek(self.data[i] + start * self.items[i])
            raw = col.tobytes()
            self.crc[i] = zlib.crc32(raw, self.crc[i])
            self.fh.write(raw)

    def close(self, written: int) -> None:
        try:
            if written != self.rows:
                raise Diagnostic("TRACE-ROWS", f"{written} rows written, {self.rows} announced")
            for name, off, size, crc in zip(
                self.names, self.offsets, self.sizes, self.crc, strict=True
            ):
                self.fh.seek(off)
                self.fh.write(self._local(name, size, crc))
            self.fh.seek(0, os.SEEK_END)
            cd_start = self.fh.tell()
            for name, off, size, crc in zip(
                self.names, self.offsets, self.sizes, self.crc, strict=True
            ):
                extra = struct.pack("<HHQQQ", 1, 24, size, size, off)
                self.fh.write(
                    struct.pack(
                        "<IHHHHHHIIIHHHHHII",
                        0x02014B50,
                        45,
                        45,
                        0,
                        0,
                        0,
                        0x21,
                        crc,
                        0xFFFFFFFF,
                        0xFFFFFFFF,
                        len(name),
                        len(extra),
                        0,
                        0,
                        0,
                        0,
                        0xFFFFFFFF,
                    )
                    + name
                    + extra
                )
            cd_end = self.fh.tell()
            n = len(self.names)
            self.fh.write(
                struct.pack(
                    "<IQHHIIQQQQ", 0x06064B50, 44, 45, 45, 0, 0, n, n, cd_end - cd_start, cd_start
                )
            )
            self.fh.write(struct.pack("<IIQI", 0x07064B50, 0, cd_end, 1))
            self.fh.write(
                struct.pack(
                    "<IHHHHIIH",
                    0x06054B50,
                    0,
                    0,
                    min(n, 0xFFFF),
                    min(n, 0xFFFF),
                    min(cd_end - cd_start, 0xFFFFFFFF),
                    0xFFFFFFFF,
                    0,
                )
            )
        finally:
            self.fh.close()


class ParquetWriter:
    """Apache Parquet through pyarrow, one row group per chunk."""

    def __init__(self, path: str, names: list[str], force: bool = False) -> None:
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise Diagnostic(
                "IO-PARQUET",
                "Parquet output needs pyarrow, which is not installed; use --format csv or npz",
                Location(path),
            ) from None
        check_target(path, force)
        self.path = path
        self.names = names
        self._pa, self._pq = pa, pq
        self._writer: Any = None

    def write(self, table: dict[str, np.ndarray]) -> None:
        t = self._pa.table({n: table[n] for n in self.names})
        if self._writer is None:
            self._writer = self._pq.ParquetWriter(self.path, t.schema)
        self._writer.write_table(t)

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()


def open_writer(
    fmt: str,
    path: str,
    names: list[str],
    force: bool = False,
    rows: int | None = None,
    dtypes: dict[str, np.dtype] | None = None,
) -> Writer:
    """A writer for ``fmt`` (one of :data:`FORMATS`); ``rows`` and ``dtypes``, when known,
    let NPZ write every value once."""
    if fmt == "npz":
        return NpzWriter(path, names, force, rows, dtypes)
    cls = {"csv": CsvWriter, "parquet": ParquetWriter}.get(fmt)
    if cls is None:
        raise Diagnostic("TRACE-FORMAT", f"unknown trace format {fmt!r}; use {', '.join(FORMATS)}")
    return cls(path, names, force)
