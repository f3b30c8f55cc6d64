"""ISO 14649-12 turning: golden IR of the turning programs (tests/stepnc/turning), their
cutting moves and finished volumes derived by hand (tests/stepnc/turning/README.md), the
cadquery solid of each turned part against the closed form, and the located refusals."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc.model import load
from stepnc.to_canon import canon_from_file
from stepnc.turned import turned_part, turned_profile

HERE = Path(__file__).resolve().parent / "stepnc" / "turning"
sys.path.insert(0, str(HERE))
from turning_programs import PROGRAMS, REFUSED  # noqa: E402

PI = math.pi

#: every cutting (feed) move's end point (X = radius, Z), in order, worked out by hand from
#: the rules in docs/stepnc.md "Turning" (README.md gives the arithmetic)
FEEDS: dict[str, list[tuple[float, float]]] = {
    "face_rough_finish": [(0, 1.1), (0, 0.2), (0, 0)],
    "od_rough": [(23.5, -30), (22, -30), (20.5, -30), (20.5, 0), (20.5, -30), (25, -30)],
    "od_rough_finish": [(23.5, -30), (22, -30), (20.5, -30), (20.5, 0), (20.5, -30), (25, -30)]
    + [(20, 0), (20, -30), (25, -30)],
    "book_face_cylinder_cone": [(0, 0)]
    + [(27, -40), (24, -18), (21, -12), (18, -6)]
    + [(15, 0), (25, -20), (25, -40), (30, -40)]
    + [(27.5, -70), (25, -70)]
    + [(25, -40), (25, -70), (30, -70)],
    "book_tapered_outer_diameter": [(0, 0)]
    + [(27, -20), (24, -18), (21, -12), (18, -6), (15, 0), (25, -20), (30, -20)]
    + [(27.5, -70), (25, -70), (25, -20), (25, -70), (30, -70)],
    "stepped_shaft": [(22.5, -50), (20, -50), (20, 0), (20, -50), (25, -50)]
    + [(17.5, -20), (15, -20), (15, 0), (15, -20), (20, -20)],
    "taper_rough_finish": [(22.625, -28.5), (20.25, -19), (17.875, -9.5)]
    + [(15.5, 0), (25.5, -40)]
    + [(15, 0), (25, -40)],
    "chamfer_shoulder_finish": [(21.25, -35), (17.5, -20), (13.75, -20)]
    + [(10, 0), (12, -2), (12, -20), (18, -20), (18, -35), (25, -35)] * 2,
    "groove_cut_in": [(20, -20)],
    "groove_multistep_rough_finish": [
        p for c in (-27.5, -30, -32.5) for p in ((23, c), (21, c), (19, c), (18.2, c))
    ]
    + [(18, c) for c in (-27.5, -30, -32.5)],
    "css_feed_per_minute_mist": [(18, -25), (16, -25), (16, 0), (16, -25), (20, -25)],
    "shaft_two_tools": [(0, 1), (0, 0)]
    + [(22.7667, -40), (20.5333, -40), (18.3, -40), (18.3, 0), (18.3, -40), (25, -40)]
    + [(18, 0), (18, -40), (25, -40)]
    + [(15, -25)],
}

#: the turned part (raw bar less the features, ISO 14649-12 shapes) as (z, r) outline points
#: from the chuck end (two points at one z are a shoulder), and its volume in closed form
#: (sums of cylinders and cone frustums)
FINISHED: dict[str, tuple[list[tuple[float, float]], float]] = {
    "face_rough_finish": ([(-80, 25), (0, 25)], PI * 25**2 * 80),
    # roughed only: the part is still the feature's (the allowance is stock, not design)
    "od_rough": ([(-80, 25), (-30, 25), (-30, 20), (0, 20)], PI * (400 * 30 + 625 * 50)),
    "od_rough_finish": ([(-80, 25), (-30, 25), (-30, 20), (0, 20)], PI * (400 * 30 + 625 * 50)),
    "book_face_cylinder_cone": (
        [(-100, 30), (-70, 30), (-70, 25), (-20, 25), (0, 15)],
        PI * (900 * 30 + 625 * 50 + 20 * (15**2 + 15 * 25 + 25**2) / 3),
    ),
    "book_tapered_outer_diameter": (
        [(-100, 30), (-70, 30), (-70, 25), (-20, 25), (0, 15)],
        PI * (900 * 30 + 625 * 50 + 20 * (15**2 + 15 * 25 + 25**2) / 3),
    ),
    "stepped_shaft": (
        [(-80, 25), (-50, 25), (-50, 20), (-20, 20), (-20, 15), (0, 15)],
        PI * (625 * 30 + 400 * 30 + 225 * 20),
    ),
    "taper_rough_finish": (
        [(-60, 25), (-40, 25), (0, 15)],
        PI * (625 * 20 + 40 * (15**2 + 15 * 25 + 25**2) / 3),
    ),
    "chamfer_shoulder_finish": (
        [(-60, 25), (-35, 25), (-35, 18), (-20, 18), (-20, 12), (-2, 12), (0, 10)],
        PI * (625 * 25 + 324 * 15 + 144 * 18 + 2 * (10**2 + 10 * 12 + 12**2) / 3),
    ),
    "groove_cut_in": (
        [(-60, 25), (-21.5, 25), (-21.5, 20), (-18.5, 20), (-18.5, 25), (0, 25)],
        PI * (625 * 60 - (625 - 400) * 3),
    ),
    "groove_multistep_rough_finish": (
        [(-60, 25), (-34, 25), (-34, 18), (-26, 18), (-26, 25), (0, 25)],
        PI * (625 * 60 - (625 - 324) * 8),
    ),
    "css_feed_per_minute_mist": (
        [(-50, 20), (-25, 20), (-25, 16), (0, 16)],
        PI * (400 * 25 + 256 * 25),
    ),
    "shaft_two_tools": (
        [(-70, 25), (-40, 25), (-40, 18), (-26, 18), (-26, 15), (-24, 15), (-24, 18), (0, 18)],
        PI * (625 * 30 + 324 * 40 - (324 - 225) * 2),
    ),
}


def _commands(name: str) -> list[canon.Command]:
    return list(canon_from_file(str(HERE / f"{name}.stp"), None, "default"))


@pytest.fixture(scope="module")
def runs() -> dict[str, list[canon.Command]]:
    return {name: _commands(name) for name in PROGRAMS}


def test_there_are_at_least_ten_turning_programs():
    assert len(PROGRAMS) >= 10
    assert set(FEEDS) == set(PROGRAMS) == set(FINISHED)


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_turning_program_matches_its_golden_ir(name, runs):
    golden = (HERE / f"{name}.can").read_text().splitlines()
    assert list(canon.write_text(runs[name])) == golden


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_cutting_moves_are_the_hand_derived_ones(name, runs):
    feeds = [(c.x, c.z) for c in runs[name] if isinstance(c, canon.StraightFeed)]
    assert len(feeds) == len(FEEDS[name])
    for (x, z), (ex, ez) in zip(feeds, FEEDS[name], strict=True):
        assert x == pytest.approx(ex, abs=5e-5) and z == pytest.approx(ez, abs=5e-5)
    assert all(c.y == 0.0 for c in runs[name] if hasattr(c, "y"))
    assert any(c == canon.SelectPlane(canon.Plane.XZ) for c in runs[name])


def _radius(outline: list[tuple[float, float]], z: float) -> float:
    """The finished radius at z (at a shoulder, the smaller side: the face itself is not
    inside the part); 0 beyond the part."""
    if z >= outline[-1][0] - 1e-9 or z <= outline[0][0] + 1e-9:
        return 0.0  # on an end face or beyond the part
    best: float | None = None
    for (za, ra), (zb, rb) in zip(outline, outline[1:], strict=False):
        if zb - za <= 0 or not (za - 1e-9 <= z <= zb + 1e-9):
            continue
        r = ra + (rb - ra) * (z - za) / (zb - za)
        best = r if best is None else min(best, r)
    return 0.0 if best is None else best


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_no_cutting_move_enters_the_finished_part(name, runs):
    outline = FINISHED[name][0]
    x0 = z0 = None
    for c in runs[name]:
        if isinstance(c, (canon.StraightFeed, canon.StraightTraverse)):
            if isinstance(c, canon.StraightFeed) and x0 is not None:
                for k in range(101):
                    t = k / 100
                    x = x0 + (c.x - x0) * t
                    z = z0 + (c.z - z0) * t
                    assert x >= _radius(outline, z) - 1e-6, (name, c, x, z)
            x0, z0 = c.x, c.z


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_turned_profile_is_the_closed_form_part(name):
    profile = turned_profile(load(str(HERE / f"{name}.stp")))
    assert profile.volume() == pytest.approx(FINISHED[name][1], rel=1e-9)
    outline = FINISHED[name][0]
    for z in [outline[0][0] + k * (outline[-1][0] - outline[0][0]) / 97 for k in range(98)]:
        assert profile.max_r(z, z) == pytest.approx(_radius(outline, z), abs=1e-9) or any(
            abs(z - zo) < 1e-6 for zo, _ in outline
        )


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_turned_solid_volume_matches_the_closed_form(name):
    pytest.importorskip("cadquery")
    solid = turned_part(str(HERE / f"{name}.stp"))
    assert solid.val().Volume() == pytest.approx(FINISHED[name][1], rel=1e-6)


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_unsupported_turning_is_a_located_error(name):
    _, code, word = REFUSED[name]
    with pytest.raises(Diagnostic) as err:
        list(canon_from_file(str(HERE / f"refused_{name}.stp"), None, "default"))
    assert err.value.code == code
    assert word in err.value.message
    assert err.value.location.line is not None


def test_gouge_check_passes_the_programs_and_catches_a_move_into_the_part(runs):
    from dataclasses import replace

    from stepnc.turned import turning_gouges

    model = load(str(HERE / "od_rough_finish.stp"))
    cmds = runs["od_rough_finish"]
    assert not any(turning_gouges(model, cmds).values())
    # the finishing pass 0.5 mm deeper than the diameter
    i = max(k for k, c in enumerate(cmds) if isinstance(c, canon.StraightFeed) and c.x == 20.0)
    bad = [*cmds[:i], replace(cmds[i], x=19.5), *cmds[i + 1 :]]
    found = [g for gs in turning_gouges(model, bad).values() for g in gs]
    assert found and found[0].command in (i, i + 1)


def test_turning_programs_have_no_check_error_on_the_default_machine():
    import json

    from click.testing import CliRunner

    from cli.main import cli

    files = [str(HERE / f"{name}.stp") for name in sorted(PROGRAMS)]
    result = CliRunner().invoke(cli, ["check", "--format", "json", *files])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    errors = [f for e in doc["files"] for f in e["findings"] if f["severity"] == "error"]
    assert errors == []
