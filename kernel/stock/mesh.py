"""The final stock as a closed triangle mesh: the height field's top surface through the
cell centres (the outer ones moved out to the box's faces), four side walls down to the
stock bottom, and the bottom as a fan from its centre over the boundary (no T-junction,
so the mesh is watertight)."""

from __future__ import annotations

import numpy as np

from kernel.diagnostics import Diagnostic, Location
from kernel.stock.heightfield import HeightField


def _boundary(nx: int, ny: int) -> np.ndarray:
    """Flat indices (j * nx + i) of the grid's boundary, counter-clockwise seen from +Z."""
    idx = np.arange(nx * ny).reshape(ny, nx)
    if nx == 1 or ny == 1:
        return idx.ravel()
    return np.concatenate([idx[0, :-1], idx[:-1, -1], idx[-1, :0:-1], idx[:0:-1, 0]])


def stock_mesh(hf: HeightField) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3) float64, faces (m, 3) int64) of the stock, faces counter-clockwise
    seen from outside. Needs at least 2 x 2 cells."""
    nx, ny = hf.nx, hf.ny
    xv, yv = hf.xs.copy(), hf.ys.copy()
    xv[0], xv[-1], yv[0], yv[-1] = hf.box.x0, hf.box.x1, hf.box.y0, hf.box.y1
    gx, gy = np.meshgrid(xv, yv)
    top = np.column_stack([gx.ravel(), gy.ravel(), hf.h.ravel()])
    ring = _boundary(nx, ny)
    bottom = top[ring].copy()
    bottom[:, 2] = hf.box.z0
    b = hf.box
    centre = np.array([[0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1), b.z0]])
    verts = np.vstack([top, bottom, centre])
    idx = np.arange(nx * ny).reshape(ny, nx)
    v00, v10 = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    v01, v11 = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    faces_top = np.concatenate([np.column_stack([v00, v10, v11]), np.column_stack([v00, v11, v01])])
    nb = len(ring)
    a_t, b_t = ring, np.roll(ring, -1)
    a_b = nx * ny + np.arange(nb)
    b_b = np.roll(a_b, -1)
    walls = np.concatenate([np.column_stack([a_b, b_b, b_t]), np.column_stack([a_b, b_t, a_t])])
    c = np.full(nb, len(verts) - 1)
    floor = np.column_stack([c, b_b, a_b])
    return verts, np.concatenate([faces_top, walls, floor]).astype(np.int64)


def stl_bytes(verts: np.ndarray, faces: np.ndarray, name: bytes = b"cnc sim stock") -> bytes:
    """A binary STL of the mesh (normals from the right-hand rule)."""
    tri = verts[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    norm = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.divide(n, norm, out=np.zeros_like(n), where=norm > 0)
    rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    rec["n"], rec["v"] = n, tri
    header = name[:80].ljust(80, b" ")
    return header + np.uint32(len(faces)).tobytes() + rec.tobytes()


def mesh_volume(verts: np.ndarray, faces: np.ndarray) -> float:
    """Enclosed volume by the divergence theorem (a check that the mesh is closed)."""
    tri = verts[faces]
    return float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0)


def read_stl(data: bytes, where: str | None = None) -> np.ndarray:
    """Triangles (n, 3, 3) of a binary or ASCII STL (``SIM-DESIGN`` when it is neither).
    Binary when the size is 84 + 50 x the count in its header, ASCII otherwise."""
    if len(data) >= 84:
        count = int.from_bytes(data[80:84], "little")
        if len(data) == 84 + 50 * count:
            rec = np.frombuffer(
                data, dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")], offset=84
            )
            return rec["v"].astype(np.float64)
    text = data.decode("ascii", errors="replace")
    if not text.lstrip().lower().startswith("solid"):
        raise Diagnostic("SIM-DESIGN", "not an STL file (binary or ASCII)", Location(where))
    values = []
    for line in text.splitlines():
        parts = line.split()
        if parts[:1] == ["vertex"]:
            try:
                values.append([float(v) for v in parts[1:4]])
            except ValueError:
                values = []
                break
            if len(parts) != 4:
                values = []
                break
    if not values or len(values) % 3:
        raise Diagnostic("SIM-DESIGN", "an ASCII STL without whole triangles", Location(where))
    return np.asarray(values, dtype=np.float64).reshape(-1, 3, 3)


#: candidate (triangle, cell) pairs handled at once by :func:`top_surface`
PAIRS_PER_CHUNK = 2_000_000


def top_surface(tri: np.ndarray, hf: HeightField) -> np.ndarray:
    """The highest triangle Z over each cell centre of ``hf``'s grid, -inf where no
    triangle covers it (a design's top surface rasterised like the stock).

    Each triangle's XY bounding box gives its candidate cells; the pairs are expanded all
    at once (in chunks), tested with barycentric coordinates and the Z at the centre kept
    by maximum. Triangles seen edge-on from above (walls) are skipped: their neighbours
    give the Z."""
    out = np.full(hf.nx * hf.ny, -np.inf)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    e1, e2 = b - a, c - a
    den = e1[:, 0] * e2[:, 1] - e2[:, 0] * e1[:, 1]
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    box = hf.box
    i0 = np.maximum(np.ceil((lo[:, 0] - box.x0) / hf.dx - 0.5), 0).astype(np.int64)
    i1 = np.minimum(np.floor((hi[:, 0] - box.x0) / hf.dx - 0.5), hf.nx - 1).astype(np.int64)
    j0 = np.maximum(np.ceil((lo[:, 1] - box.y0) / hf.dy - 0.5), 0).astype(np.int64)
    j1 = np.minimum(np.floor((hi[:, 1] - box.y0) / hf.dy - 0.5), hf.ny - 1).astype(np.int64)
    ni, nj = i1 - i0 + 1, j1 - j0 + 1
    keep = np.flatnonzero((ni > 0) & (nj > 0) & (np.abs(den) > 1e-12))
    counts = (ni * nj)[keep]
    ends = np.cumsum(counts)
    start = 0
    while start < len(keep):
        base = ends[start - 1] if start else 0
        stop = max(start + 1, int(np.searchsorted(ends, base + PAIRS_PER_CHUNK, "right")))
        idx = keep[start:stop]
        cnt = counts[start:stop]
        t = np.repeat(idx, cnt)
        local = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        ii = i0[t] + local % ni[t]
        jj = j0[t] + local // ni[t]
        px = hf.xs[ii] - a[t, 0]
        py = hf.ys[jj] - a[t, 1]
        l1 = (px * e2[t, 1] - e2[t, 0] * py) / den[t]
        l2 = (e1[t, 0] * py - px * e1[t, 1]) / den[t]
        eps = 1e-9
        inside = (l1 >= -eps) & (l2 >= -eps) & (l1 + l2 <= 1 + eps)
        z = a[t, 2] + l1 * e1[t, 2] + l2 * e2[t, 2]
        np.maximum.at(out, (jj * hf.nx + ii)[inside], z[inside])
        start = stop
    return out.reshape(hf.ny, hf.nx)
