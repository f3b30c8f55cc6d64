"""Contour error measured exactly against path segments (kernel.axes.contour)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kernel.axes.contour import ContourMeter, ErrorTracker, distance_to_segments
from kernel.path.segments import ARC, LINE, SEGMENT_DTYPE


def arc_row(
    radius: float,
    sweep: float,
    axial: float = 0.0,
    radius_end: float | None = None,
    start_angle: float = 0.3,
) -> np.ndarray:
    seg = np.zeros(1, SEGMENT_DTYPE)
    e1 = np.array([math.cos(start_angle), math.sin(start_angle), 0.0])
    n = np.array([0.0, 0.0, 1.0])
    e2 = np.cross(n, e1)
    r1 = radius if radius_end is None else radius_end
    seg["kind"] = ARC
    seg["centre"] = (1.0, -2.0, 0.5)
    seg["normal"], seg["e1"], seg["e2"] = n, e1, e2
    seg["radius"], seg["radius_end"], seg["sweep"], seg["axial"] = radius, r1, sweep, axial
    c = np.array([1.0, -2.0, 0.5])
    seg["start"][0, :3] = c + radius * e1
    seg["end"][0, :3] = c + r1 * (math.cos(sweep) * e1 + math.sin(sweep) * e2) + axial * n
    return seg


def dense(seg: np.ndarray, n: int = 50_001) -> np.ndarray:
    """Brute-force reference: the arc sampled very finely."""
    lam = np.linspace(0, 1, n)[:, None]
    s = seg[0]
    psi = s["sweep"] * lam
    rho = s["radius"] + (s["radius_end"] - s["radius"]) * lam
    return (
        s["centre"]
        + rho * (np.cos(psi) * s["e1"] + np.sin(psi) * s["e2"])
        + s["axial"] * lam * s["normal"]
    )


def brute(points: np.ndarray, curve: np.ndarray) -> np.ndarray:
    return np.array([np.linalg.norm(curve - p, axis=1).min() for p in points])


@pytest.mark.parametrize(
    "seg",
    [
        arc_row(5.0, 2.0),
        arc_row(5.0, -4.0),
        arc_row(3.0, 5 * math.pi, axial=4.0),
        arc_row(3.0, 3.0, radius_end=4.0),
        arc_row(2.0, -2 * math.pi, axial=-1.0),
    ],
    ids=["ccw", "cw-long", "helix-2.5-turns", "spiral", "cw-helix"],
)
def test_arc_distance_matches_brute_force(seg):
    rng = np.random.default_rng(7)
    pts = seg[0]["centre"] + rng.uniform(-7, 7, size=(60, 3))
    got = distance_to_segments(pts, seg, np.zeros(60, dtype=np.int64))
    ref = brute(pts, dense(seg))
    # the reference is a polyline of 5e4 points: within its own spacing error
    assert got == pytest.approx(ref, abs=1e-3)
    assert np.all(got <= ref + 1e-9)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-10, 10), min_size=9, max_size=9))
def test_line_distance_is_the_clamped_projection(v):
    a, b, p = np.array(v[:3]), np.array(v[3:6]), np.array(v[6:])
    seg = np.zeros(1, SEGMENT_DTYPE)
    seg["kind"] = LINE
    seg["start"][0, :3], seg["end"][0, :3] = a, b
    got = distance_to_segments(p[None], seg, np.zeros(1, dtype=np.int64))[0]
    t = np.linspace(0, 1, 20001)[:, None]
    ref = np.linalg.norm(a + t * (b - a) - p, axis=1).min()
    assert got == pytest.approx(ref, abs=1e-3 * (1 + np.linalg.norm(b - a)))
    assert got <= ref + 1e-9


def square_path() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    corners = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [0, 0, 0]], float)
    segs = np.zeros(4, SEGMENT_DTYPE)
    segs["kind"] = LINE
    segs["start"][:, :3], segs["end"][:, :3] = corners[:-1], corners[1:]
    t = np.linspace(0, 4, 4001)[:-1]
    k = t.astype(int)
    frac = (t - k)[:, None]
    pts = corners[k] + frac * (corners[k + 1] - corners[k])
    return segs, pts, k


def test_contour_meter_in_chunks_equals_one_pass():
    segs, pts, k = square_path()
    lagged = np.roll(pts, 40, axis=0) + np.array([0.01, -0.02, 0.0])
    whole = ContourMeter(segs, lag=60).step(lagged, k)
    meter = ContourMeter(segs, lag=60)
    parts = np.concatenate(
        [meter.step(lagged[i : i + 333], k[i : i + 333]) for i in range(0, len(k), 333)]
    )
    assert parts == pytest.approx(whole, abs=1e-15)


def test_points_on_the_path_have_zero_contour_error_even_when_late():
    segs, pts, k = square_path()
    late = np.vstack([np.repeat(pts[:1], 50, axis=0), pts[:-50]])  # 50 samples behind
    err = ContourMeter(segs, lag=60).step(late, k)
    assert err.max() < 1e-12


def test_error_tracker_reports_the_largest_error_and_where():
    tr = ErrorTracker(("x", "y"))
    t = np.arange(5) * 0.1
    seg = np.array([0, 0, 1, 1, 2])
    line = seg + 10
    tr.update(
        t,
        seg,
        line,
        {"x": np.array([0, 0.1, -0.5, 0.2, 0]), "y": np.zeros(5)},
        np.array([0, 0.01, 0.02, 0.05, 0.0]),
    )
    d = tr.to_dict()
    assert d["following_error"]["x"] == {"value": -0.5, "time": 0.2, "segment": 1, "line": 11}
    assert d["contour_error"]["value"] == 0.05 and d["contour_error"]["line"] == 11
