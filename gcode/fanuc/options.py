"""What distinguishes one Fanuc-family control from another, as data (reader side)."""

from __future__ import annotations

from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Flavour:
    """Reader options of one control (Fanuc 0i/30i or Haas) and the user's choices."""

    name: str = "fanuc"
    lathe: bool = False  # lathe mode (book Table A.1): X diameter, U/W, G98/G99 feed
    polar_book_convention: bool = False  # book Table A.2: G15 polar on, G16 off
    block_delete: bool = True  # "/" blocks are skipped (block skip switch on)
    #: M98 P with more than four digits holds the repeat count (0i: P30100 = 3 x O0100)
    repeat_in_p: bool = True
    #: G04 P with a decimal point is seconds (Haas); else P is always milliseconds
    dwell_p_point_seconds: bool = False
    local_call: bool = False  # M97 P (N label) L (Haas)
    smoothness: bool = False  # G187 (Haas)
    pallet_m50: bool = False  # M50 = pallet change (Haas)
    #: Haas's own G codes: G187 smoothness, G47 engraving, G103 look-ahead, G154 P offsets
    haas_g_codes: bool = False
    m19_p_angle: bool = False  # M19 P<angle> orients the spindle to an angle (Haas)
    #: additional work offsets G54.1 P1-P<n> / G154 P1-P<n> (0i/30i: 48; Haas: 99)
    extended_offsets: int = 48
    #: Haas lathe: one-block G71/G72 (D depth of cut) and G73 (I K relief, D passes), and
    #: the machine-function M codes of gcode/fanuc/haas_lathe_m.py
    haas_lathe: bool = False
    #: IF [c] followed by the rest of the block, no THEN or GOTO (Haas)
    if_without_then: bool = False
    max_loops: int = 2_000_000  # backward jumps before FANUC-LOOP-LIMIT


FANUC = Flavour()
HAAS = Flavour(
    name="haas",
    repeat_in_p=False,
    dwell_p_point_seconds=True,
    local_call=True,
    smoothness=True,
    pallet_m50=True,
    haas_g_codes=True,
    m19_p_angle=True,
    extended_offsets=99,
    if_without_then=True,
)
#: Haas lathe (NGC control): Haas's program and call conventions, Fanuc lathe mode, and the
#: Haas lathe cycle forms and M codes
HAAS_LATHE = replace(HAAS, name="haas_lathe", lathe=True, haas_lathe=True)
