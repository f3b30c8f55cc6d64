"""Allocation of bulk arrays: samples and large per-segment tables (kernel.interp.interpolate,
kernel.path.build).

Bulk arrays are tens of MB (a 200,000-segment program sampled at 1 ms: 2 million samples)
and new on every run, so how their memory is first touched shows in the run time
(issue 3's speed clause, bench/bench_plan.py).
"""

from __future__ import annotations

import mmap

import numpy as np

#: arrays at least this large (bytes) get their own 4 KiB-page mapping in :func:`bulk_array`
MAPPED_BYTES = 1 << 22


def bulk_array(
    shape: int | tuple[int, ...], dtype: type | np.dtype = np.float64, sparse: bool = False
) -> np.ndarray:
    """A new array of zeros for bulk data (samples, per-segment tables), faulted in up front
    unless ``sparse`` (then only the pages written ever take memory).

    Sample arrays are large (a 200,000-segment program: 2 million samples, tens of MB per
    array) and new on every run. numpy asks for transparent huge pages for arrays of 4 MiB
    and more; on a virtual machine that hands free memory back to its host (virtio-balloon
    free page reporting, as on the project's 2-core machine) the first touch of each fresh
    2 MiB page then costs milliseconds: measured, 150 MB in 0.2-0.3 s of system time in a
    fresh process, against 0.05 s in 4 KiB pages faulted in by ``MAP_POPULATE``. So a large
    array is an anonymous mapping (zero-filled by the kernel) in 4 KiB pages. Small arrays,
    and platforms without anonymous ``mmap``, use ``numpy.zeros``. Raises MemoryError when
    the memory cannot be had.
    """
    dt = np.dtype(dtype)
    nbytes = int(np.prod(shape, dtype=np.int64)) * dt.itemsize
    if nbytes < MAPPED_BYTES or not hasattr(mmap, "MAP_ANONYMOUS"):
        return np.zeros(shape, dt)
    flags = mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS
    if not sparse:
        flags |= getattr(mmap, "MAP_POPULATE", 0)
    try:
        buf = mmap.mmap(-1, nbytes, flags=flags)
    except OSError as e:  # as numpy's allocator does when the memory is not there
        raise MemoryError(f"cannot allocate {nbytes} bytes for a {shape} {dt} array") from e
    return np.frombuffer(buf, dtype=dt).reshape(shape)
