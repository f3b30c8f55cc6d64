"""Geometry of ISO 14649-12 turning: the raw bar, the turning features as radius profiles
along the spindle axis, the stock left after each workingstep, and its solid.

A part turned about the Z axis is a radius r(z). :class:`Profile` holds one as contiguous
linear segments over the raw bar's length; a jump between segments is a face (shoulder).
A feature is the radius profile the finished part may not exceed, ``FREE`` (no limit)
outside the feature; turning a feature leaves ``min(stock, feature)``.

Feature readings (docs/stepnc.md, "Turning"): the feature placement lies on the spindle
axis with its Z axis along it; ``OUTER_DIAMETER`` is the cylinder of its diameter from the
placement ``feature_length`` towards -Z (the chuck), tapering to a ``DIAMETER_TAPER``'s final
diameter or by an ``ANGLE_TAPER``'s angle there; ``REVOLVED_FLAT`` is the face at the
placement: the part ends there, down to ``radius`` (0 for a full face); ``GROOVE`` is a
``SQUARE_U_PROFILE`` of its width centred on the placement, down to ``radius``;
``GENERAL_REVOLUTION`` is the polyline of its ``outline`` in the feature's XZ plane
(x radial, offset by ``radius``).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

from kernel.diagnostics import Diagnostic
from stepnc.frames import Frame, coords, frame_of
from stepnc.geometry import _cq
from stepnc.model import Entity, Model, measure

#: radius standing for "no limit" outside a feature
FREE = 1.0e9
EPS = 1e-9

Seg = tuple[float, float, float, float]  # (z_a, z_b, r at z_a, r at z_b), z_a < z_b


@dataclass(frozen=True)
class Profile:
    """Radius as a function of z: contiguous segments in increasing z."""

    segs: tuple[Seg, ...]

    @property
    def z_lo(self) -> float:
        return self.segs[0][0]

    @property
    def z_hi(self) -> float:
        return self.segs[-1][1]

    def breaks(self) -> list[float]:
        return [s[0] for s in self.segs] + [self.z_hi]

    def piece(self, u: float, v: float) -> tuple[float, float]:
        """Radius at ``u`` and ``v`` of the segment covering ``[u, v]`` (which lies in one)."""
        mid = 0.5 * (u + v)
        for za, zb, ra, rb in self.segs:
            if za - EPS <= mid <= zb + EPS:
                if zb - za <= EPS:
                    return ra, rb
                k = (rb - ra) / (zb - za)
                return ra + k * (u - za), ra + k * (v - za)
        raise ValueError(f"z {mid:g} outside the profile")

    def minimum(self, other: Profile) -> Profile:
        """The pointwise minimum (both over the same z range)."""
        zs = sorted(set(self.breaks()) | set(other.breaks()))
        out: list[Seg] = []
        for u, v in zip(zs, zs[1:], strict=False):
            if v - u <= EPS:
                continue
            a_u, a_v = self.piece(u, v)
            b_u, b_v = other.piece(u, v)
            du, dv = a_u - b_u, a_v - b_v
            if du * dv < 0:
                t = du / (du - dv)
                zc = u + t * (v - u)
                rc = a_u + t * (a_v - a_u)
                out.append((u, zc, min(a_u, b_u), rc))
                out.append((zc, v, rc, min(a_v, b_v)))
            elif du + dv <= 0:
                out.append((u, v, a_u, a_v))
            else:
                out.append((u, v, b_u, b_v))
        return Profile(tuple(_merge(out)))

    def offset(self, d: float) -> Profile:
        """Every finite radius increased by ``d`` (an allowance)."""
        return Profile(
            tuple(
                (za, zb, ra + d if ra < FREE else ra, rb + d if rb < FREE else rb)
                for za, zb, ra, rb in self.segs
            )
        )

    def top(self) -> float:
        """The free end: the highest z with material."""
        for za, zb, ra, rb in reversed(self.segs):
            if rb > EPS:
                return zb
            if ra > EPS:
                return za + (zb - za) * ra / (ra - rb)
        return self.z_lo

    def max_r(self, z0: float, z1: float) -> float:
        """Largest radius over ``[z0, z1]``."""
        best = 0.0
        span = z1 - z0 > EPS
        for za, zb, ra, rb in self.segs:
            if zb < z0 - EPS or za > z1 + EPS:
                continue
            if span and (zb <= z0 + EPS or za >= z1 - EPS):
                continue  # touches the range at one end only
            lo, hi = max(za, z0), min(zb, z1)
            k = (rb - ra) / (zb - za) if zb > za else 0.0
            best = max(best, ra + k * (lo - za), ra + k * (hi - za))
        return best

    def volume(self) -> float:
        """The solid of revolution's volume (sum of frustums)."""
        return sum(
            math.pi * (zb - za) * (ra * ra + ra * rb + rb * rb) / 3.0
            for za, zb, ra, rb in self.segs
        )

    def outline(self) -> list[tuple[float, float]]:
        """(radius, z) points of the half section from the chuck end to the free end,
        closed along the axis; zero-radius ends are left out."""
        segs = [s for s in self.segs if s[2] > EPS or s[3] > EPS]
        if not segs:
            return []
        pts: list[tuple[float, float]] = [(0.0, segs[0][0])]
        for za, zb, ra, rb in segs:
            for p in ((ra, za), (rb, zb)):
                if abs(p[0] - pts[-1][0]) > EPS or abs(p[1] - pts[-1][1]) > EPS:
                    pts.append(p)
        pts.append((0.0, segs[-1][1]))
        return pts


def _merge(segs: list[Seg]) -> Iterator[Seg]:
    """Join consecutive collinear segments."""
    cur: Seg | None = None
    for s in segs:
        if cur is None:
            cur = s
            continue
        za, zb, ra, rb = cur
        _, zc, rb2, rc = s
        if abs(rb - rb2) <= 1e-9:
            k1 = (rb - ra) / (zb - za)
            k2 = (rc - rb2) / (zc - zb)
            if abs(k1 - k2) <= 1e-12 * max(1.0, abs(k1)):
                cur = (za, zc, ra, rc)
                continue
        yield cur
        cur = s
    if cur is not None:
        yield cur


def bar(z_lo: float, z_hi: float, r: float) -> Profile:
    return Profile(((z_lo, z_hi, r, r),))


def limit(z_lo: float, z_hi: float, pieces: list[tuple[float, float]]) -> Profile:
    """The profile FREE over ``[z_lo, z_hi]`` except along ``pieces``: (z, r) polyline points
    in increasing z (two points at one z make a face)."""
    segs: list[Seg] = []
    p0 = max(z_lo, pieces[0][0])
    if p0 > z_lo + EPS:
        segs.append((z_lo, p0, FREE, FREE))
    for (za, ra), (zb, rb) in zip(pieces, pieces[1:], strict=False):
        if zb - za <= EPS:
            continue
        lo, hi = max(za, z_lo), min(zb, z_hi)
        if hi - lo <= EPS:
            continue
        k = (rb - ra) / (zb - za)
        segs.append((lo, hi, ra + k * (lo - za), ra + k * (hi - za)))
    end = min(z_hi, pieces[-1][0])
    if z_hi > end + EPS:
        segs.append((end, z_hi, FREE, FREE))
    if not segs:
        segs.append((z_lo, z_hi, FREE, FREE))
    return Profile(tuple(segs))


# ----------------------------------------------------------------------------- the model
def _err(code: str, message: str, entity: Entity) -> Diagnostic:
    return Diagnostic(code, message, entity.where())


def raw_bar(model: Model, wp_frame: Frame) -> tuple[Profile, float]:
    """The raw bar (from the workpiece's RIGHT_CIRCULAR_CYLINDER) and its radius."""
    for wp in model.all("WORKPIECE"):
        for cand in (wp, wp.its_rawpiece):
            if not isinstance(cand, Entity):
                continue
            b = cand.its_bounding_geometry
            if isinstance(b, Entity) and b.type == "RIGHT_CIRCULAR_CYLINDER":
                fr = wp_frame.compose(frame_of(b.position))
                if not fr.vertical or abs(fr.origin[0]) > 1e-6 or abs(fr.origin[1]) > 1e-6:
                    raise _err(
                        "STEPNC-TURNING",
                        f"the raw bar #{b.id} must lie on the spindle (Z) axis",
                        b,
                    )
                r, h = float(b.radius), float(b.height)
                if r <= 0 or h <= 0:
                    raise _err("STEPNC-TURNING", f"the raw bar #{b.id} has no volume", b)
                z0 = fr.origin[2]
                return bar(z0, z0 + h, r), r
    raise Diagnostic(
        "STEPNC-TURNING",
        "turning needs the raw bar: a RIGHT_CIRCULAR_CYLINDER as the workpiece's "
        "its_bounding_geometry",
        model.project().where(),
    )


def _number(value: object, what: str, feature: Entity) -> float:
    v = measure(value)
    if v is None:
        raise _err(
            "STEPNC-TURNING", f"{feature.type} #{feature.id}: {what} is not a number", feature
        )
    return v


def feature_frame(feature: Entity, wp_frame: Frame) -> Frame:
    fr = wp_frame.compose(frame_of(feature.feature_placement))
    if not fr.vertical or abs(fr.origin[0]) > 1e-6 or abs(fr.origin[1]) > 1e-6:
        raise _err(
            "STEPNC-PLACEMENT",
            f"turning feature #{feature.id} must be placed on the spindle (Z) axis with its "
            "Z axis along it",
            feature,
        )
    return fr


def feature_limit(feature: Entity, fr: Frame, stock: Profile) -> Profile:
    """The radius profile ``feature`` allows (FREE outside it)."""
    z0 = fr.origin[2]
    lo, hi = stock.z_lo, stock.z_hi
    t = feature.type
    if t == "OUTER_DIAMETER":
        r = _number(feature.diameter_at_placement, "diameter_at_placement", feature) / 2
        length = _number(feature.feature_length, "feature_length", feature)
        if r <= 0 or length <= 0:
            raise _err(
                "STEPNC-TURNING",
                f"OUTER_DIAMETER #{feature.id} needs a positive diameter and length",
                feature,
            )
        r_end = r
        taper = feature.reduced_size
        if isinstance(taper, Entity) and taper.type == "DIAMETER_TAPER":
            r_end = _number(taper.final_diameter, "final_diameter", feature) / 2
        elif isinstance(taper, Entity) and taper.type == "ANGLE_TAPER":
            # positive: the diameter grows away from the placement (towards the chuck)
            r_end = r + length * math.tan(math.radians(float(taper.angle)))
        elif taper is not None:
            raise _err(
                "STEPNC-UNSUPPORTED",
                f"OUTER_DIAMETER #{feature.id}: reduced_size {taper!r} is not a taper",
                feature,
            )
        if r_end < 0:
            raise _err(
                "STEPNC-TURNING",
                f"OUTER_DIAMETER #{feature.id}: the taper ends below the axis",
                feature,
            )
        return limit(lo, hi, [(z0 - length, r_end), (z0, r)])
    if t == "REVOLVED_FLAT":
        r = _number(feature.radius, "radius", feature)
        return limit(lo, hi, [(z0, r), (hi, r)])
    if t == "GROOVE":
        sweep = feature.sweep
        if not isinstance(sweep, Entity) or sweep.type != "SQUARE_U_PROFILE":
            raise _err(
                "STEPNC-UNSUPPORTED",
                f"GROOVE #{feature.id}: only a SQUARE_U_PROFILE sweep is read",
                feature,
            )
        for name in ("first_radius", "second_radius"):
            rad = measure(getattr(sweep, name))
            if rad:
                raise _err(
                    "STEPNC-UNSUPPORTED",
                    f"GROOVE #{feature.id}: a {name} (rounded groove corner) is not read",
                    feature,
                )
        width = _number(sweep.width, "width", feature)
        r = _number(feature.radius, "radius", feature)
        return limit(lo, hi, [(z0 - width / 2, r), (z0 + width / 2, r)])
    if t == "GENERAL_REVOLUTION":
        return limit(lo, hi, _outline(feature, fr))
    raise _err("STEPNC-UNSUPPORTED", f"{t} is not a turning feature this reader knows", feature)


def _outline(feature: Entity, fr: Frame) -> list[tuple[float, float]]:
    prof = feature.outline
    curve = (
        prof.its_profile if isinstance(prof, Entity) and prof.type == "GENERAL_PROFILE" else None
    )
    if not isinstance(curve, Entity) or curve.type != "POLYLINE":
        raise _err(
            "STEPNC-UNSUPPORTED",
            f"GENERAL_REVOLUTION #{feature.id}: the outline must be a GENERAL_PROFILE polyline",
            feature,
        )
    pf = frame_of(prof.placement)
    r0 = _number(feature.radius, "radius", feature)
    pts = []
    for p in curve.points:
        x, _, z = pf.point(coords(p))
        pts.append((fr.origin[2] + z, r0 + x))
    if pts[0][0] > pts[-1][0]:
        pts.reverse()
    for (za, ra), (zb, rb) in zip(pts, pts[1:], strict=False):
        if zb < za - EPS or ra < -EPS or rb < -EPS:
            raise _err(
                "STEPNC-TURNING",
                f"GENERAL_REVOLUTION #{feature.id}: the outline must run along the axis one "
                f"way with radii >= 0 (it turns back at Z={za:g})",
                feature,
            )
    return pts


def turned_solid(profile: Profile) -> object:
    """The cadquery solid of ``profile`` revolved about Z."""
    cq = _cq()
    pts = profile.outline()
    wp = cq.Workplane("XZ").polyline(pts).close()
    return wp.revolve(360.0, (0.0, 0.0, 0.0), (0.0, 1.0, 0.0))


__all__ = [
    "FREE",
    "Profile",
    "bar",
    "feature_frame",
    "feature_limit",
    "limit",
    "raw_bar",
    "turned_solid",
]
