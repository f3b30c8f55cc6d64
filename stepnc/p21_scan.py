"""The Part 21 reader's compiled scan of large DATA sections, and the lazy instance table
it fills.

The compiled scanner (:mod:`stepnc.p21_kernels`, loaded by :mod:`kernel.aot`) takes runs of
well-formed simple instances straight from the file's bytes into arrays: id, entity name,
the span of the parameter list, line and column. No value is decoded while reading: an
instance is decoded by the reader's fast path (:func:`stepnc.p21_fast.fast_params`, on the
same text, so to the same values) when the model first asks for it, and kept. Instances the
scanner does not take (and every defect) are read by the Python reader, which stores them
in the same table.
"""

from __future__ import annotations

import gc
import sys
from collections.abc import ItemsView, Iterator, MutableMapping, ValuesView

import numpy as np

from kernel.aot import Kernels
from stepnc.p21_fast import fast_params
from stepnc.p21_values import Instance

KERNELS = Kernels("stepnc.p21_kernels", "_p21_aot", "fast Part 21 kernels", "CNC_P21_JIT")
#: the scanner's reasons to return (:mod:`stepnc.p21_kernels`)
_STOP, _FULL, _ID_BIG, _NAMES_FULL = 0, 1, 2, 3
#: ids up to this many times the text's length (plus a margin) get a slot in the id table;
#: the Python reader takes an instance with a larger id
_ID_SPAN = 4
_HASH_SLOTS = 1 << 16
#: the longest text scanned (offsets, ids and rows are 32-bit)
MAX_CHARS = (1 << 31) - 1
#: rows decoded in the first and the largest chunks when all are iterated
_CHUNK = 4096
_MAX_CHUNK = 1 << 14


class Instances(MutableMapping[int, Instance]):
    """The DATA instances by id, in file order: rows the scanner took (decoded on first
    access) and instances the Python reader made (or a caller set), as a ``dict`` would
    hold them."""

    def __init__(self, text: str, buf: np.ndarray, capacity: int) -> None:
        self._text = text
        self._buf = buf
        cap = max(capacity, 16)
        self._ids = np.zeros(cap, dtype=np.int32)
        self._names = np.zeros(cap, dtype=np.int32)
        self._body_s = np.zeros(cap, dtype=np.int32)
        self._body_e = np.zeros(cap, dtype=np.int32)
        self._lines = np.zeros(cap, dtype=np.int32)
        self._cols = np.zeros(cap, dtype=np.int32)
        #: id -> row + 1 of the scanner's rows, -1 for an id in ``_over``, 0 for none
        self._seen = np.zeros(min(cap, 1 << 20), dtype=np.int32)
        self._id_bound = min(_ID_SPAN * len(text) + (1 << 20), MAX_CHARS)
        self._ht_start = np.zeros(_HASH_SLOTS, dtype=np.int64)
        self._ht_len = np.zeros(_HASH_SLOTS, dtype=np.int64)
        self._ht_id = np.full(_HASH_SLOTS, -1, dtype=np.int32)
        self._entity: list[str] = []
        self._rows = 0
        self._dead = 0
        #: instances not in the scanner's rows, and the row each comes before (file order)
        self._over: dict[int, Instance] = {}
        self._before: dict[int, int] = {}
        self._cache: list[Instance | None] | None = None
        self._pending = 0
        self._finished = False

    # -- reading
    def scan(self, pos: int, line_no: int, last_nl: int) -> tuple[int, int, int]:
        """Take instances from ``pos`` on (``line_no``: the line there, ``last_nl``: the last
        newline before it); returns the position, line and last newline after them."""
        kernels = KERNELS.module()
        while True:
            pos, rows, line_no, last_nl, n_names, status, big = kernels.scan(
                self._buf,
                pos,
                self._rows,
                self._ids,
                self._names,
                self._body_s,
                self._body_e,
                self._lines,
                self._cols,
                self._seen,
                self._ht_start,
                self._ht_len,
                self._ht_id,
                len(self._entity),
                line_no,
                last_nl,
            )
            self._rows = rows
            self._add_names(n_names)
            if status == _FULL:
                self._grow_rows()
            elif status != _ID_BIG or not self._grow_ids(big):
                return pos, line_no, last_nl

    def _add_names(self, n_names: int) -> None:
        known = len(self._entity)
        if n_names == known:
            return
        slots = np.flatnonzero(self._ht_id >= known)
        order = slots[np.argsort(self._ht_id[slots])]
        text = self._text
        for s in order.tolist():
            start = int(self._ht_start[s])
            raw = text[start : start + int(self._ht_len[s])]
            self._entity.append(sys.intern(raw.upper()))

    def _grow_rows(self) -> None:
        cap = len(self._ids) * 2
        for attr in ("_ids", "_names", "_body_s", "_body_e", "_lines", "_cols"):
            old = getattr(self, attr)
            new = np.zeros(cap, dtype=old.dtype)
            new[: len(old)] = old
            setattr(self, attr, new)

    def _grow_ids(self, ident: int) -> bool:
        """Widen the id table to hold ``ident``; False when it is beyond the bound (the
        Python reader then takes its instance)."""
        if ident >= self._id_bound:
            return False
        size = max(ident + 1, 2 * len(self._seen))
        seen = np.zeros(size, dtype=np.int32)
        seen[: len(self._seen)] = self._seen
        for k in self._over:
            if len(self._seen) <= k < size:
                seen[k] = -1
        self._seen = seen
        return True

    def finish(self) -> None:
        """Drop the scanner's working tables after reading."""
        self._finished = True
        self._buf = np.zeros(0, dtype=np.uint8)
        self._ht_start = self._ht_len = np.zeros(0, dtype=np.int64)
        self._ht_id = np.zeros(0, dtype=np.int32)

    # -- the mapping
    def _row(self, key: object) -> int:
        """The scanner's row for ``key``; -1 when the id is not a row."""
        if not isinstance(key, int):
            return -1
        k = int(key)
        if 0 <= k < len(self._seen):
            return int(self._seen.item(k)) - 1
        return -1

    def _new_cache(self) -> list[Instance | None]:
        self._cache = [None] * self._rows
        self._pending = self._rows
        return self._cache

    def _decoded(self, count: int) -> None:
        """``count`` more rows are decoded; once all are, the text and the spans are no
        longer needed (the decoded instances take their place in memory)."""
        self._pending -= count
        if self._pending == 0:
            self._text = ""
            empty = np.zeros(0, dtype=np.int32)
            self._body_s = self._body_e = self._names = self._lines = self._cols = empty

    def _decode(self, row: int) -> Instance:
        """Row ``row`` as an :class:`Instance`, kept once reading is over (while reading,
        the Python reader only asks for the line of a duplicate's first definition)."""
        cache = self._cache
        if cache is None:
            if not self._finished:
                return self._make(row)
            cache = self._new_cache()
        inst = cache[row]
        if inst is None:
            inst = cache[row] = self._make(row)
            self._decoded(1)
        return inst

    def _make(self, row: int) -> Instance:
        params = fast_params(self._text[self._body_s[row] : self._body_e[row]])
        assert params is not None, "the scanner takes only what fast_params reads"
        return Instance(
            int(self._ids[row]),
            self._entity[self._names[row]],
            params,
            int(self._lines[row]),
            int(self._cols[row]),
        )

    def __getitem__(self, key: int) -> Instance:
        row = self._row(key)
        if row >= 0:
            return self._decode(row)
        return self._over[key]

    def __contains__(self, key: object) -> bool:
        seen = self._seen
        if type(key) is int and 0 <= key < len(seen):  # -1: in _over
            return bool(seen.item(key))
        return self._row(key) >= 0 or key in self._over

    def __setitem__(self, key: int, value: Instance) -> None:
        row = self._row(key)
        k = int(key)
        if row >= 0:  # replaces a row: in its place
            self._seen[k] = -1
            self._dead += 1
            self._before[k] = row
        elif k not in self._over:
            self._before[k] = self._rows
            if 0 <= k < len(self._seen):
                self._seen[k] = -1
        self._over[k] = value

    def __delitem__(self, key: int) -> None:
        row = self._row(key)
        if row >= 0:
            self._seen[int(key)] = 0
            self._dead += 1
            return
        del self._over[key]
        del self._before[key]
        k = int(key)
        if 0 <= k < len(self._seen):
            self._seen[k] = 0

    def __len__(self) -> int:
        return self._rows - self._dead + len(self._over)

    def _live_rows(self, start: int, stop: int) -> Iterator[int]:
        if not self._dead:
            return iter(range(start, stop))
        seen = self._seen
        ids = self._ids[start:stop].tolist()
        return (r for r, k in zip(range(start, stop), ids, strict=True) if seen[k] == r + 1)

    def _order(self) -> Iterator[tuple[int, int]]:
        """(row, -1) for a scanner row and (-1, id) for another instance, in file order."""
        before = self._before
        r = 0
        for k in sorted(self._over, key=before.__getitem__):
            b = before[k]
            if b > r:
                yield from ((x, -1) for x in self._live_rows(r, b))
                r = b
            yield -1, k
        yield from ((x, -1) for x in self._live_rows(r, self._rows))

    def __iter__(self) -> Iterator[int]:
        if not self._over and not self._dead:
            return iter(self._ids[: self._rows].tolist())
        ids = self._ids
        return (int(ids[r]) if r >= 0 else k for r, k in self._order())

    def iter_values(self) -> Iterator[Instance]:
        """The instances in file order, decoded as they come (no look-up by id)."""
        if not self._over and not self._dead:
            start, size = 0, _CHUNK
            while start < self._rows:  # chunks that grow: few windows for the collector
                stop = min(start + size, self._rows)
                cache = self._decode_rows(start, stop)
                for r in range(start, stop):
                    inst = cache[r]
                    assert inst is not None
                    yield inst
                start, size = stop, min(2 * size, _MAX_CHUNK)
            return
        decode = self._decode
        over = self._over
        for r, k in self._order():
            yield decode(r) if r >= 0 else over[k]

    def _decode_rows(self, start: int, stop: int) -> list[Instance | None]:
        """Decode (and keep) rows ``start`` to ``stop``; the cache. One tight loop over plain
        lists, with the cyclic collector off (it would only rescan the new tuples)."""
        cache = self._cache
        if cache is None:
            cache = self._new_cache()
        todo = cache[start:stop].count(None)
        if not todo:
            return cache
        enabled = gc.isenabled()
        gc.disable()
        try:
            text = self._text
            entity = self._entity
            for r, ident, name, bs, be, line, col in zip(
                range(start, stop),
                self._ids[start:stop].tolist(),
                self._names[start:stop].tolist(),
                self._body_s[start:stop].tolist(),
                self._body_e[start:stop].tolist(),
                self._lines[start:stop].tolist(),
                self._cols[start:stop].tolist(),
                strict=True,
            ):
                if cache[r] is None:
                    params = fast_params(text[bs:be])
                    assert params is not None, "the scanner takes only what fast_params reads"
                    cache[r] = Instance(ident, entity[name], params, line, col)
        finally:
            if enabled:
                gc.enable()
        self._decoded(todo)
        return cache

    def values(self) -> ValuesView[Instance]:
        return _Values(self)

    def items(self) -> ItemsView[int, Instance]:
        return _Items(self)


class _Values(ValuesView[Instance]):
    """``Instances.values()``: iterates without a look-up per id."""

    _mapping: Instances

    def __iter__(self) -> Iterator[Instance]:
        return self._mapping.iter_values()


class _Items(ItemsView[int, Instance]):
    """``Instances.items()``: iterates without a look-up per id."""

    _mapping: Instances

    def __iter__(self) -> Iterator[tuple[int, Instance]]:
        return zip(self._mapping, self._mapping.iter_values(), strict=True)
