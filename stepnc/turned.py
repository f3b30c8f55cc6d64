"""The turned part of an ISO 14649-12 program: the raw bar less every turning feature of
its workingsteps (the design shape, without allowances), as a radius profile and as a
cadquery solid of revolution."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable

from kernel.ir import canon
from stepnc.gouge import Gouge
from stepnc.lathe import EPS, Profile, feature_frame, feature_limit, raw_bar, turned_solid
from stepnc.model import Model, load
from stepnc.to_canon import setup_frames
from stepnc.toolpaths.turning import TURNING_OPS


def turned_profile(model: Model) -> Profile:
    """Raw bar minimum every turning feature's radius limit."""
    project = model.project()
    _, wp_frame = setup_frames(model, project, project.main_workplan)
    stock, _ = raw_bar(model, wp_frame)
    done: set[int] = set()
    for ws in model.all("MACHINING_WORKINGSTEP"):
        feature = ws.its_feature
        if ws.its_operation.type not in TURNING_OPS or feature.id in done:
            continue
        done.add(feature.id)
        stock = stock.minimum(feature_limit(feature, feature_frame(feature, wp_frame), stock))
    return stock


def is_turning(model: Model) -> bool:
    """Whether any workingstep of the program is a turning operation."""
    return any(ws.its_operation.type in TURNING_OPS for ws in model.all("MACHINING_WORKINGSTEP"))


def _inner_radius(profile: Profile, z: float) -> float | None:
    """The part's radius at ``z`` (the smaller side at a shoulder); None on or beyond an end
    face."""
    if z <= profile.z_lo + EPS or z >= profile.top() - 1e-6:
        return None
    best: float | None = None
    for za, zb, ra, rb in profile.segs:
        if za - EPS <= z <= zb + EPS:
            r = ra + (rb - ra) * (z - za) / (zb - za)
            best = r if best is None else min(best, r)
    return best


def turning_gouges(
    model: Model, commands: Iterable[canon.Command], step: float = 0.5, tol: float = 1e-4
) -> dict[int, list[Gouge]]:
    """Cutting moves whose tool point enters the turned part, per workingstep (every
    workingstep of the program has an entry)."""
    part = turned_profile(model)
    result: dict[int, list[Gouge]] = defaultdict(list)
    for ws in model.all("MACHINING_WORKINGSTEP"):
        result[ws.id] = []
    x0 = z0 = None
    for i, cmd in enumerate(commands):
        if not isinstance(cmd, (canon.StraightFeed, canon.StraightTraverse)):
            continue
        if isinstance(cmd, canon.StraightFeed) and x0 is not None and z0 is not None:
            n = max(1, int(max(abs(cmd.x - x0), abs(cmd.z - z0)) / step) + 1)
            for k in range(n + 1):
                x = x0 + (cmd.x - x0) * k / n
                z = z0 + (cmd.z - z0) * k / n
                r = _inner_radius(part, z)
                if r is not None and x < r - tol:
                    ws_id = cmd.source.workingstep if cmd.source is not None else None
                    result[ws_id if ws_id is not None else -1].append(Gouge(-1, i, (x, 0.0, z)))
                    break
        x0, z0 = cmd.x, cmd.z
    return dict(result)


def turned_part(path: str) -> object:
    """The cadquery solid of the turned part of the program at ``path``."""
    return turned_solid(turned_profile(load(path)))


__all__ = ["is_turning", "turned_part", "turned_profile", "turning_gouges"]
