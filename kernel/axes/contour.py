"""Following and contour errors (book §5.1 eq. 5.1, §4.2.3, §5.5), measured and predicted.

* Following error: commanded minus actual position, per axis.
* Contour error: the distance of the actual tool point (X, Y, Z) from the programmed path,
  computed exactly against the path's segments (:mod:`kernel.path.build` rows: lines, arcs,
  helices, spirals), not against samples. The actual point at time ``t`` lags the command,
  so it is compared with every segment commanded during ``[t - lag, t]`` and one segment
  either side (``lag`` covers the servo and filter delays; a path that comes back near
  itself later is not mistaken for the local path).
* :class:`ErrorTracker` keeps the maxima and where they happen (time, segment, source
  line) over a stream of chunks.
* :func:`circle_error` and :func:`corner_error`: what the acc/dec-after-interpolation
  filters predict (book Table 4.5 and its exact forms; corners derived here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from kernel.path.segments import ARC

_NEWTON = 12


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to segments ``a``-``b`` (rows)."""
    d = b - a
    dd = np.einsum("ij,ij->i", d, d)
    t = np.einsum("ij,ij->i", p - a, d) / np.where(dd > 0, dd, 1.0)
    t = np.clip(np.where(dd > 0, t, 0.0), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def _arc_point(s: dict[str, np.ndarray], lam: np.ndarray) -> tuple[np.ndarray, ...]:
    """Position and first two derivatives w.r.t. ``lam`` of arc rows (kernel.path.geometry form:
    ``centre + rho(lam) (cos psi e1 + sin psi e2) + axial lam normal``, ``psi = sweep lam``)."""
    sw, r0 = s["sweep"][:, None], s["radius"][:, None]
    dr, ax = (s["radius_end"] - s["radius"])[:, None], s["axial"][:, None]
    psi = sw * lam[:, None]
    c, si = np.cos(psi), np.sin(psi)
    w = c * s["e1"] + si * s["e2"]
    wp = -si * s["e1"] + c * s["e2"]
    rho = r0 + dr * lam[:, None]
    pos = s["centre"] + rho * w + ax * lam[:, None] * s["normal"]
    d1 = dr * w + rho * sw * wp + ax * s["normal"]
    d2 = 2 * dr * sw * wp - rho * sw**2 * w
    return pos, d1, d2


def _point_arc(p: np.ndarray, s: dict[str, np.ndarray]) -> np.ndarray:
    """Distance from points to arc rows: closed form for circles, Newton for helices and
    spirals (started on the turn the point's angle and height select), ends included."""
    q = p - s["centre"]
    n = s["normal"]
    h = np.einsum("ij,ij->i", q, n)
    x = np.einsum("ij,ij->i", q, s["e1"])
    y = np.einsum("ij,ij->i", q, s["e2"])
    sw = s["sweep"]
    sgn = np.where(sw < 0, -1.0, 1.0)
    phi = np.mod(sgn * np.arctan2(y, x), 2 * np.pi)  # angle travelled from the start
    turns = np.abs(sw) / (2 * np.pi)
    ax = s["axial"]
    # the turn: by height for helices, else the first one the angle falls in
    k_h = np.where(np.abs(ax) > 0, np.floor(h / np.where(ax != 0, ax, 1.0) * turns), 0.0)
    top = np.maximum(np.ceil(turns) - 1, 0)
    span = np.where(sw != 0, np.abs(sw), 1.0)
    lam = np.clip((phi + 2 * np.pi * np.clip(k_h, 0, top)) / span, 0.0, 1.0)
    pos, _, _ = _arc_point(s, lam)
    best = np.linalg.norm(p - pos, axis=1)
    spiral = (np.abs(ax) > 0) | (s["radius_end"] != s["radius"])
    if spiral.any():
        # Newton on |P - H(lam)|² from the angle-matched point of the turns around the
        # height's turn, each step limited to an eighth of a turn and kept only if it helps
        cap = (np.pi / 4) / span
        for off in (-2.0, -1.0, 0.0, 1.0, 2.0):
            turn = np.clip(np.clip(k_h, 0, top) + off, 0, top)
            lam_k = np.clip((phi + 2 * np.pi * turn) / span, 0.0, 1.0)
            pos, d1, d2 = _arc_point(s, lam_k)
            dist = np.linalg.norm(p - pos, axis=1)
            for _ in range(_NEWTON):
                r = pos - p
                g = np.einsum("ij,ij->i", r, d1)
                gg = np.einsum("ij,ij->i", d1, d1) + np.einsum("ij,ij->i", r, d2)
                step = np.where(gg > 0, g / np.where(gg > 0, gg, 1.0), g * cap)
                trial = np.clip(lam_k - np.clip(step, -cap, cap), 0.0, 1.0)
                pos_t, d1_t, d2_t = _arc_point(s, trial)
                dist_t = np.linalg.norm(p - pos_t, axis=1)
                ok = dist_t < dist
                lam_k = np.where(ok, trial, lam_k)
                dist = np.where(ok, dist_t, dist)
                pos = np.where(ok[:, None], pos_t, pos)
                d1 = np.where(ok[:, None], d1_t, d1)
                d2 = np.where(ok[:, None], d2_t, d2)
            better = spiral & (dist < best)
            best = np.where(better, dist, best)
            lam = np.where(better, lam_k, lam)
    circle = ~spiral
    inside = circle & (lam > 0) & (lam < 1)
    rho = np.hypot(x, y)
    exact = np.sqrt((rho - s["radius"]) ** 2 + h**2)
    best = np.where(inside, exact, best)
    ends = np.minimum(
        np.linalg.norm(p - s["start3"], axis=1), np.linalg.norm(p - s["end3"], axis=1)
    )
    return np.minimum(best, ends)


_FIELDS = ("sweep", "radius", "radius_end", "axial", "e1", "e2", "normal", "centre")


class Geometry:
    """The path rows in compact column form for fast gathers (XYZ only)."""

    def __init__(self, segments: np.ndarray) -> None:
        self.a = np.ascontiguousarray(segments["start"][:, :3], dtype=float)
        b = np.ascontiguousarray(segments["end"][:, :3], dtype=float)
        self.b = b
        self.d = b - self.a
        dd = np.einsum("ij,ij->i", self.d, self.d)
        # a segment shorter than 1e-12 mm is a point (and 1/dd would overflow)
        real = dd > 1e-24
        self.inv_dd = np.where(real, 1.0 / np.where(real, dd, 1.0), 0.0)
        self.arc = segments["kind"] == ARC
        self.has_arcs = bool(self.arc.any())
        self.fields = {f: np.ascontiguousarray(segments[f]) for f in _FIELDS}

    def __len__(self) -> int:
        return int(self.a.shape[0])

    def distance(self, points: np.ndarray, index: np.ndarray) -> np.ndarray:
        """Distance of each XYZ point to row ``index[i]`` (lines, arcs; a hold is the
        point where the tool waits)."""
        w = points - self.a[index]
        d = self.d[index]
        t = np.clip(np.einsum("ij,ij->i", w, d) * self.inv_dd[index], 0.0, 1.0)
        w -= t[:, None] * d
        out = np.sqrt(np.einsum("ij,ij->i", w, w))
        if self.has_arcs:
            arc = self.arc[index]
            if arc.any():
                rows = index[arc]
                s = {f: v[rows] for f, v in self.fields.items()}
                s["start3"], s["end3"] = self.a[rows], self.b[rows]
                out[arc] = _point_arc(points[arc], s)
        return out


def distance_to_segments(points: np.ndarray, segments: np.ndarray, index: np.ndarray) -> np.ndarray:
    """Distance of each XYZ point to the path row ``index[i]`` (see :class:`Geometry`)."""
    return Geometry(segments).distance(np.asarray(points, dtype=float), np.asarray(index))


@dataclass
class ContourMeter:
    """Contour error over a stream of chunks (state: the recent commanded segments).

    ``lag`` (samples) is how far back the actual point may be along the commanded path.
    """

    segments: np.ndarray
    lag: int
    _recent: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    _last: int = 0
    _geometry: Geometry | None = None

    def step(self, actual_xyz: np.ndarray, segment: np.ndarray) -> np.ndarray:
        """Contour error (mm) of a chunk; ``segment`` is the commanded row per sample
        (-1 while no motion: the last row before counts)."""
        seg = np.asarray(segment, dtype=np.int64).copy()
        n = seg.size
        if not len(self.segments) or n == 0:
            return np.zeros(n)
        valid = seg >= 0
        fill = np.where(valid, np.arange(n), -1)
        np.maximum.accumulate(fill, out=fill)
        seg = np.where(fill >= 0, seg[np.maximum(fill, 0)], self._last)
        self._last = int(seg[-1])
        hist = np.concatenate([self._recent, seg])
        off = self._recent.size
        # segments are run in order: the range commanded over the lag window
        lo_src = np.arange(n) + off - self.lag
        lo = hist[np.clip(lo_src, 0, None)]
        lo = np.where(lo_src < 0, np.minimum(lo, hist[0]), lo)
        hi = seg
        self._recent = hist[-self.lag :] if self.lag else np.zeros(0, dtype=np.int64)
        last = len(self.segments) - 1
        lo = np.clip(np.minimum(lo, hi) - 1, 0, last)
        hi = np.clip(np.maximum(lo, hi) + 1, 0, last)
        if self._geometry is None:
            self._geometry = Geometry(self.segments)
        geo = self._geometry
        pts = np.asarray(actual_xyz, dtype=float)
        best = geo.distance(pts, lo)
        span = int((hi - lo).max())
        for o in range(1, span + 1):
            idx = lo + o
            sel = np.flatnonzero(idx <= hi)
            if sel.size == 0:
                break
            if sel.size == n:
                np.minimum(best, geo.distance(pts, idx), out=best)
            else:
                best[sel] = np.minimum(best[sel], geo.distance(pts[sel], idx[sel]))
        return best


@dataclass
class Peak:
    """The largest absolute value seen, and where."""

    value: float = 0.0
    time: float = 0.0
    segment: int = -1
    line: int = 0

    def update(
        self, values: np.ndarray, t: np.ndarray, segment: np.ndarray, line: np.ndarray
    ) -> None:
        if values.size == 0:
            return
        i = int(np.nanargmax(np.abs(values))) if np.isfinite(values).any() else -1
        if i >= 0 and abs(values[i]) > abs(self.value):
            self.value = float(values[i])
            self.time, self.segment, self.line = float(t[i]), int(segment[i]), int(line[i])

    def to_dict(self) -> dict[str, float | int]:
        return {"value": self.value, "time": self.time, "segment": self.segment, "line": self.line}


@dataclass
class ErrorTracker:
    """Maxima of the following error per axis and of the contour error over a run."""

    axes: tuple[str, ...]
    following: dict[str, Peak] = field(default_factory=dict)
    contour: Peak = field(default_factory=Peak)

    def __post_init__(self) -> None:
        self.following = {a: Peak() for a in self.axes}

    def update(
        self,
        t: np.ndarray,
        segment: np.ndarray,
        line: np.ndarray,
        following: dict[str, np.ndarray],
        contour: np.ndarray | None,
    ) -> None:
        for a, e in following.items():
            self.following[a].update(e, t, segment, line)
        if contour is not None:
            self.contour.update(contour, t, segment, line)

    def to_dict(self) -> dict[str, object]:
        return {
            "following_error": {a: p.to_dict() for a, p in self.following.items()},
            "contour_error": self.contour.to_dict(),
        }


# --------------------------------------------------------------------------- predictions
_APPROX = {"linear": 24.0, "s_shape": 48.0, "exponential": 2.0}


def circle_error(kind: str, feed: float, radius: float, tau: float, exact: bool = True) -> float:
    """Radius lost on a circle by an acc/dec-after-interpolation filter (book §4.2.3).

    ``w = F/R``. Exact forms: linear ``R(1 - 2 sin(w tau/2)/(w tau))`` (eq. 4.37),
    S-shape ``R(1 - 8(1 - cos(w tau/2))/(w tau)^2)`` (eq. 4.42-4.44, ``tau`` the total
    width), exponential ``R(1 - 1/sqrt(1 + (w tau)^2))`` (eq. 4.47-4.49). Approximations
    (Table 4.5): ``F² tau²/(24 R)``, ``F² tau²/(48 R)``, ``F² tau²/(2 R)``.
    """
    w = feed / radius
    x = w * tau
    if not exact:
        return feed**2 * tau**2 / (_APPROX[kind] * radius)
    if x == 0:
        return 0.0
    if kind == "linear":
        return radius * (1.0 - 2.0 * math.sin(x / 2) / x)
    if kind == "s_shape":
        return radius * (1.0 - 8.0 * (1.0 - math.cos(x / 2)) / x**2)
    if kind == "exponential":
        return radius * (1.0 - 1.0 / math.sqrt(1.0 + x * x))
    raise ValueError(kind)


def corner_error(kind: str, feed: float, tau: float, angle: float) -> float:
    """Contour error at a corner run at constant feed through an ADCAI filter [derived].

    The book gives none (research/seed-book-motion.md §1.4). For a filter with a symmetric
    impulse response the filtered point is the weighted mean of the path over the window;
    in the middle of the transition it is ``c + F k tau (d2 - d1)`` with ``k = 1/8`` for the
    linear (box) filter and ``1/12`` for the S-shape (triangle of total width ``tau``), and
    its distance from either leg, ``F k tau sin(angle)``, is the largest contour error.
    ``angle`` is the direction change in radians, valid up to 90° (legs longer than
    ``F tau/2``). The exponential filter is not symmetric and has no such closed form.
    """
    k = {"linear": 1.0 / 8.0, "s_shape": 1.0 / 12.0}[kind]
    if not 0 <= angle <= math.pi / 2 + 1e-12:
        raise ValueError("corner_error holds for direction changes up to 90 degrees")
    return feed * k * tau * math.sin(angle)


def predict_arcs(segments: np.ndarray, kind: str, tau: float) -> Peak:
    """The largest circle error an ADCAI filter predicts over a path's arcs at their
    programmed feed (:func:`circle_error`, exact form; an upper bound where the planner
    runs an arc slower than programmed). ``Peak.time`` is left 0."""
    out = Peak()
    if kind not in _APPROX or not len(segments):
        return out
    arc = np.flatnonzero((segments["kind"] == ARC) & np.isfinite(segments["feed"]))
    for i in arc:
        r = float(segments["radius"][i])
        if r <= 0:
            continue
        e = circle_error(kind, float(segments["feed"][i]), r, tau)
        if e > out.value:
            out.value, out.segment, out.line = e, int(i), int(segments["line"][i])
    return out
