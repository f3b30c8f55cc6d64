"""The final stock as a closed triangle mesh: the height field's top surface through the
cell centres (the outer ones moved out to the box's faces), four side walls down to the
stock bottom, and the bottom as a fan from its centre over the boundary (no T-junction,
so the mesh is watertight)."""

from __future__ import annotations

import numpy as np

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
