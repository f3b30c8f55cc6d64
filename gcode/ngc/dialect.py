"""RS274/NGC as LinuxCNC 2.9 reads it (the reference dialect; read back by ``rs274``).

Everything the IR carries has a LinuxCNC form: G5.2/G5.3 NURBS (the current position is
the first control point, the knots are clamped uniform), G2/G3 ``P`` turns, G90.1
absolute centres, G64 ``P``/``Q``, G43.1 dynamic tool length, M19, M50/M51, G33.
"""

from gcode.write.spec import Dialect

DIALECT = Dialect(
    name="rs274ngc",
    title="RS274/NGC (LinuxCNC 2.9)",
    reference="LinuxCNC G-code reference; research/seed-canon-rs274.md §5",
    arc_formats=frozenset({"ijk", "ijk-abs", "r"}),
    centre_absolute_mode=("G90.1", "G91.1"),
    decimals_mm=5,
    decimals_inch=5,
    header=("%",),
    footer=("%",),
    turns_word="P",
    nurbs="g5.2",
    probe_in_place="G38.3",
    notes=("ELLIPSE_FEED: no G-code; approximated by lines",),
)
