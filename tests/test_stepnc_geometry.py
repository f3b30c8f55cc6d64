"""Finished-part solids (stepnc.geometry, cadquery) and the analytic volumes behind them."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from stepnc import geometry
from stepnc.model import load
from stepnc.prisms import raw_block
from stepnc.volumes import feature_volumes
from tests.data_paths import CORPUS_STEPNC

HERE = Path(__file__).resolve().parent
EX1 = str(CORPUS_STEPNC / "ex1.stp")
EX1_RAW = (0.0, 0.0, -45.0, 100.0, 120.0, 5.0)  # book §11.1: block 100 x 120 x 50


@pytest.fixture(scope="module")
def ex1_part():
    return geometry.finished_part(load(EX1), EX1_RAW)


def test_ex1_finished_volume_is_block_minus_face_pocket_and_hole(ex1_part):
    block = 100 * 120 * 50
    face = 100 * 120 * 5  # planar face: 5 mm off the top
    pocket = (80 * 50 - (4 - math.pi) * 10**2) * 30  # 80 x 50, corner radius 10, depth 30
    hole = math.pi * 11**2 * 45  # D22 through the remaining 45 mm
    expected = block - face - pocket - hole
    assert geometry.volume(ex1_part) == pytest.approx(expected, rel=1e-6)


def test_analytic_volumes_agree_with_the_solid(ex1_part):
    model = load(EX1)
    raw = raw_block(model, EX1_RAW)
    removed = sum(v.volume() for v in feature_volumes(model) if v.z_bottom > -100)
    hole = math.pi * 11**2 * 45
    assert raw.volume() - removed - hole == pytest.approx(geometry.volume(ex1_part), rel=1e-9)


def test_step_and_stl_export(tmp_path, ex1_part):
    for name in ("part.step", "part.stl"):
        path = tmp_path / name
        geometry.export(ex1_part, str(path))
        assert path.stat().st_size > 1000
    assert (tmp_path / "part.step").read_text().startswith("ISO-10303-21;")


def test_block_from_the_program_is_used_when_present():
    model = load(str(HERE / "stepnc" / "two_tools_face_and_pocket.stp"))
    part = geometry.finished_part(model)
    # pocket (depth 8) and hole (depth 12) start at Z=0, the face removes the top 2 mm
    expected = (
        100 * 80 * 40
        - 100 * 80 * 2
        - (40 * 30 - (4 - math.pi) * 36) * (8 - 2)
        - math.pi * 16 * (12 - 2)
    )
    assert geometry.volume(part) == pytest.approx(expected, rel=1e-6)


def test_polyline_pocket_boundary_gives_a_prism(tmp_path):
    """ISO Example 1 bounds its pocket by a GENERAL_CLOSED_PROFILE polyline (research §7.2);
    corners of a polyline profile are sharp."""
    text = Path(EX1).read_text(encoding="latin-1")
    text = text.replace(
        "#28= RECTANGULAR_CLOSED_PROFILE($, #122, #121);",
        "#28= GENERAL_CLOSED_PROFILE($,#59);\n"
        "#59= POLYLINE('CONTOUR OF POCKET1',(#131,#132,#133,#134,#131));\n"
        "#131= CARTESIAN_POINT('P1',(-40.0,-25.0,0.0));\n"
        "#132= CARTESIAN_POINT('P2',(40.0,-25.0,0.0));\n"
        "#133= CARTESIAN_POINT('P3',(40.0,25.0,0.0));\n"
        "#134= CARTESIAN_POINT('P4',(-40.0,25.0,0.0));",
    )
    path = tmp_path / "poly.stp"
    path.write_text(text)
    model = load(str(path))
    expected = 100 * 120 * 50 - 100 * 120 * 5 - 80 * 50 * 30 - math.pi * 11**2 * 45
    assert geometry.volume(geometry.finished_part(model, EX1_RAW)) == pytest.approx(
        expected, rel=1e-6
    )
    pocket = next(v for v in feature_volumes(model) if v.kind == "poly")
    assert pocket.volume() == pytest.approx(80 * 50 * 30)
    import numpy as np

    probe = np.array([[70.0, 70.0, -10.0], [70.0 + 24.9, 70.0 + 39.9, -1.0], [96.0, 70.0, -1.0]])
    assert pocket.contains(probe).tolist() == [True, True, False]
