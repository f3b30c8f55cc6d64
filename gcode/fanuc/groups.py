"""The G code groups of a Fanuc control, as the 0i/30i operator's manuals list them.

One table for the mill (M series) and one for the lathe (T series, G code system A), keys
``round(G * 10)``, values the manual's group number; group 00 codes are one-shot (G10 and
G11 excepted: they set a data-input mode). Haas codes sit in the group of the Fanuc code
they stand for (Haas numbers its groups differently; the membership is the same).

The manual's rules these tables carry (0i-MF/30i-B "G code list", notes):

* codes of different groups may share a block; of several codes of one group in a block
  the last one written is the one that counts;
* a group 01 code given in canned-cycle mode cancels the cycle as G80 would; a canned
  cycle code (group 09) leaves group 01 as it was, so after G80 an axis word moves in the
  group 01 mode set before the cycle.

docs/readers/fanuc.md "Modal groups" prints the tables.
"""

from __future__ import annotations

ONE_SHOT = 0
MOTION = 1
#: group of the mill's drilling canned cycles (G73, G74, G76, G80-G89)
CYCLE = 9
#: group of the lathe's drilling canned cycles (G80-G89; the lathe reader runs none)
LATHE_CYCLE = 10


def _table(groups: dict[int, tuple[int, ...]]) -> dict[int, int]:
    return {code: group for group, codes in groups.items() for code in codes}


#: Fanuc 0i-MF / 30i-MB (M series) groups of the codes the mill reader accepts
MILL: dict[int, int] = _table(
    {
        0: (40, 51, 90, 100, 280, 300, 310, 520, 530, 650, 920),
        1: (0, 10, 20, 30, 62, 330),
        2: (170, 180, 190),
        3: (900, 910),
        5: (930, 940, 950),
        6: (200, 210),
        7: (400, 410, 420),
        8: (430, 440, 490),
        9: (730, 740, 760, 800, 810, 820, 830, 840, 850, 860, 870, 880, 890),
        10: (980, 990),
        11: (500, 510),
        12: (660, 670),
        13: (960, 970),
        14: (540, 541, 550, 560, 570, 580, 590),
        15: (610, 630, 640),
        16: (680, 690),
        17: (150, 160),
        22: (501, 511),
    }
)
#: Haas mill codes: G187 smoothness, G47 engraving, G103 look-ahead (one-shot on Haas's
#: list), G154 P additional work offsets (the work-offset group, as G54.1)
HAAS_MILL: dict[int, int] = {1870: 0, 470: 0, 1030: 0, 1540: 14}

#: Fanuc 0i-TF / 30i-TB (T series, G code system A) groups of the codes the lathe reader
#: accepts; G90/G92/G94 are the single cycles (group 01), G70-G76 the multiple repetitive
#: cycles (one-shot)
LATHE: dict[int, int] = _table(
    {
        0: (40, 90, 100, 280, 300, 500, 520, 530, 650, 700, 710, 720, 730, 740, 750, 760),
        1: (0, 10, 20, 30, 320, 900, 920, 940),
        2: (960, 970),
        5: (980, 990),
        6: (200, 210),
        7: (400, 410, 420),
        10: (800,),
        12: (660, 670),
        14: (540, 550, 560, 570, 580, 590),
        15: (610, 640),
        16: (170, 180, 190),
    }
)


def last_of_each_group(codes: list[int], table: dict[int, int]) -> list[int]:
    """``codes`` in block order with every modal code dropped that a later code of its
    group overrides (one-shot group 00 codes are all kept)."""
    out: list[int] = []
    for i, code in enumerate(codes):
        group = table[code]
        later = codes[i + 1 :]
        if group != ONE_SHOT and any(table[c] == group for c in later):
            continue
        if group == ONE_SHOT and code in later:
            continue
        out.append(code)
    return out


def name(code: int) -> str:
    """``G04``, ``G54.1`` for a code ``round(G * 10)``."""
    return f"G{code // 10:02d}" + (f".{code % 10}" if code % 10 else "")
