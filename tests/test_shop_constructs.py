"""Constructs real Fanuc, Haas and Siemens shop programs use (issue 14), each against the
value the control's manual gives it (worked out by hand in the comments): Fanuc 30i extended
common variables and the system variables macros read, the macro short forms, ``:`` program
numbers, G91 G53; Haas tool-life variables and the one-block G76; the 840D instructions CAM
output writes in nearly every program, tool names, diameter programming, CYCLE832/CYCLE800,
system variables, bit operators and SETAL.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from gcode.fanuc import flow as fanuc_flow
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read, read_text
from gcode.siemens import flow as siemens_flow
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table


def _ir(text: str, dialect: str) -> list[canon.Command]:
    return list(read_text(text, dialect, "prog"))


def _ends(text: str, dialect: str) -> list[tuple[float, ...]]:
    """The end points (x, y, z) of the program's straight motions, rounded."""
    return [
        (round(c.x, 4), round(c.y, 4), round(c.z, 4))
        for c in _ir(text, dialect)
        if isinstance(c, canon.StraightFeed | canon.StraightTraverse | canon.StraightProbe)
    ]


def _error(text: str, dialect: str) -> Diagnostic:
    with pytest.raises(Diagnostic) as info:
        _ir(text, dialect)
    return info.value


# ----------------------------------------------------------------------------- Fanuc
def test_fanuc_30i_extended_common_variables_start_vacant_and_hold_values() -> None:
    # #100000 and #901200 are common: vacant (a word with a vacant value is ignored) until set
    text = "G21 G90\n#100000=5.\n#901200=2.\nG0 X#100000 Y#901200 Z#100001\nM30\n"
    assert _ends(text, "fanuc") == [(5.0, 2.0, 0.0)]


def test_fanuc_interface_signals_and_modal_words_read_as_the_state_says() -> None:
    text = (
        "G21 G90 G54\n"
        "#1100=1\n"  # an output signal: kept
        "T3 M6\nG43 H7 Z10.\n"
        "G0 X#1004 Y#1100\n"  # input signal: 0 (no signal); output read back: 1
        "G0 X#4014 Y#4111 Z#4120\n"  # G54 -> 54, H7 -> 7, tool 3
        "M30\n"
    )
    assert _ends(text, "fanuc")[-2:] == [(0.0, 1.0, 10.0), (54.0, 7.0, 3.0)]


def test_fanuc_skip_position_is_the_g31_end_point() -> None:
    # the stand-alone probe never trips: #5061-#5063 hold the commanded end point
    text = "G21 G90 F100.\nG31 X10. Y5. Z-2.\nG0 X[#5061+1] Y#5062 Z#5063\nM30\n"
    assert _ends(text, "fanuc")[-1] == (11.0, 5.0, -2.0)


def test_fanuc_macro_short_forms_loop_as_the_long_ones() -> None:
    # WH for WHILE, EN for END, GO for GOTO: three passes, then a jump over one move
    text = "G21 G90\n#1=0\nWH[#1LT3]DO1\n#1=#1+1\nG0 X#1\nEN1\nGO10\nG0 Y9.\nN10 G0 Y1.\nM30\n"
    assert _ends(text, "fanuc") == [(1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (3.0, 0.0, 0.0)] + [
        (3.0, 1.0, 0.0)
    ]


def test_fanuc_colon_program_number_and_byte_order_mark() -> None:
    # ':' is the ISO program number address (read as O); a file may open with a BOM
    text = "\ufeff%\n:0097(PART)\nG21 G90 G0 X1.\nM30\n%\n"
    assert _ends(text, "fanuc") == [(1.0, 0.0, 0.0)]


def test_fanuc_g91_g53_moves_by_the_increment() -> None:
    # 30i: G53 in G91 is an increment in the machine system (here: the same increment)
    text = "G21 G90 G0 X10. Y10.\nG91 G53 G0 X5. Y-2.\nM30\n"
    assert _ends(text, "fanuc") == [(10.0, 10.0, 0.0), (15.0, 8.0, 0.0)]


def test_fanuc_macro_argument_e_is_taken_as_written() -> None:
    # G65 ... E41: #8 = 41 (a G code number passed on), not 0.041
    text = "G21 G90\nG65 P2 E41\nM30\nO2\nG0 X#8\nM99\n"
    assert _ends(text, "fanuc") == [(41.0, 0.0, 0.0)]


def test_fanuc_drilling_cycle_without_dwell_ignores_a_p_word() -> None:
    with_p = "G21 G90 G0 Z10.\nG81 G98 X1. Y1. Z-1. R1. P500 F10.\nG80\nM30\n"
    assert _ends(with_p, "haas") == _ends(with_p.replace(" P500", ""), "haas")


def test_haas_tool_life_variables_read_zero_and_3026_the_tool() -> None:
    text = "G21 G90\nT5 M6\nIF [#5405 GE 6000] THEN #3000=15 (TOOL LIFE EXPIRED)\nG0 X#3026\nM30\n"
    assert _ends(text, "haas") == [(5.0, 0.0, 0.0)]


def test_haas_one_block_g76_is_the_fanuc_two_block_form() -> None:
    # Haas K (height) D (first cut) A (angle) -> 0i-TF P010060 / P (height) Q (first cut)
    start = "G20 G99 G18\nT303\nG97 S1000 M03\nG00 X0.6 Z0.1\n"
    haas = start + "G76 X0.4069 Z-1.5 K0.043075 D0.01076875 A60 F0.07692308\nM30\n"
    fanuc = start + "G76 P010060 Q0 R0\nG76 X0.4069 Z-1.5 P0.043075 Q0.01076875 F0.07692308\nM30\n"
    ours = _ends(haas, "haas_lathe")
    assert len(ours) > 20 and ours == _ends(fanuc, "haas_lathe")
    err = _error(start + "G76 X0.4 Z-1. K0.04 D0.01 P2 F0.07\nM30\n", "haas_lathe")
    assert err.code == "HAAS-CYCLE-WORD" and "P2" in err.message


# ----------------------------------------------------------------------------- Siemens
MOVES = "G1 X10 Y5 Z-1 F500\nX20\nM30\n"


@pytest.mark.parametrize(
    "setting",
    ["SOFT", "BRISK", "FFWON", "COMPCAD", "STOPRE", "FNORM", "UPATH", "CFC", "DYNFINISH"]
    + ["G601", "G450", "TRAFOOF", "G60 G601 FNORM SOFT"],
)
def test_siemens_path_neutral_instructions_leave_the_path_as_it_is(setting: str) -> None:
    assert _ends(setting + "\n" + MOVES, "siemens840d") == _ends(MOVES, "siemens840d")


def test_siemens_tool_names_number_tools_in_the_order_first_met() -> None:
    text = 'T="END MILL 10" M6 D1\nT="DRILL" M6\nT="END MILL 10"\nM30\n'
    ir = _ir(text, "siemens840d")
    assert [c.slot for c in ir if isinstance(c, canon.SelectTool)] == [1, 2, 1]
    names = [c.text for c in ir if isinstance(c, canon.Comment)]
    assert names == ['T="END MILL 10" is tool 1', 'T="DRILL" is tool 2']


def test_siemens_diameter_programming() -> None:
    # DIAMON: X diameters absolute and incremental; DIAM90: incremental X is a radius
    text = "G18 G95 DIAMON\nG0 X50 Z2\nG91 X10\nG90 DIAM90\nG91 X10\nG90 X80\nDIAMOF\nX40\nM30\n"
    assert [p[0] for p in _ends(text, "siemens840d")] == [25.0, 30.0, 40.0, 40.0, 40.0]


def test_siemens_cycle832_sets_the_path_mode_and_cycle800_swivel_off_moves_nothing() -> None:
    text = "CYCLE832(0.05,_FINISH,1)\nCYCLE800()\nCYCLE832()\n" + MOVES
    modes = [
        (c.mode, c.tolerance)
        for c in _ir(text, "siemens840d")
        if isinstance(c, canon.SetMotionControlMode)
    ]
    assert modes == [
        (canon.MotionMode.CONTINUOUS, 0.05),
        (canon.MotionMode.EXACT_STOP, 0.0),
    ]
    unswivelled = 'CYCLE800(1,"TABLE",0,57,0,0,0,0,0,0,0,0,0,1,,1)\n' + MOVES
    assert _ends(unswivelled, "siemens840d") == _ends(MOVES, "siemens840d")
    err = _error('CYCLE800(1,"TABLE",0,57,0,0,0,30,0,0,0,0,0,1,,1)\n' + MOVES, "siemens840d")
    assert err.code == "SIEM-CYCLE-UNSUPPORTED" and "CYCLE800" in err.message


def test_siemens_system_variables_a_program_reads() -> None:
    # after TRANS Z100 the tool stays at machine Z10: work Z -90, machine Z 10
    text = (
        "T3 M6\nG1 X0 Y0 Z10 F1000\nTRANS Z100\n"
        "R1=$AA_IW[Z] R2=$AA_IM[Z] R3=$P_TOOLNO R4=$A_IN[1]\n"
        "G1 X=R3 Y=R2-R1 Z=R1+R4\nM30\n"
    )
    assert _ends(text, "siemens840d")[-1] == (3.0, 100.0, -90.0)
    err = _error("G0 X=$MN_USER_DATA_INT[0]\n", "siemens840d")
    assert err.code == "SIEM-UNSUPPORTED" and "$MN_USER_DATA_INT" in err.message


def test_siemens_bit_operators() -> None:
    text = "R1=6 B_AND 3\nR2=6 B_OR 3\nR3=B_NOT 0\nR4=5 B_XOR 1 == 4\nG0 X=R1 Y=R2 Z=R3 A=R4\n"
    ir = [c for c in _ir(text + "M30\n", "siemens840d") if isinstance(c, canon.StraightTraverse)]
    assert (ir[0].x, ir[0].y, ir[0].z, ir[0].a) == (2.0, 7.0, -1.0, 1.0)


def test_siemens_setal_stops_the_program_where_it_runs() -> None:
    text = "R1=0\nIF R1==0 GOTOF SKIP\nSETAL(65000)\nSKIP:\nG0 X1\nSETAL(61000)\nM30\n"
    err = _error(text, "siemens840d")
    assert (err.code, err.location.line) == ("SIEM-ALARM", 6) and "61000" in err.message


def test_siemens_supa_and_g53_positions_are_machine_positions() -> None:
    # G54 holds nothing here; TRANS Z100: machine Z0 is program Z-100; G53 X-5 is X-5;
    # an incremental SUPA move stays an increment
    text = "G0 X10 Y10 Z5\nTRANS Z100\nG0 SUPA Z0 D0\nG53 X-5\nG153 Y=IC(2)\nX1\nM30\n"
    assert _ends(text, "siemens840d")[1:] == [
        (10.0, 10.0, -100.0),
        (-5.0, 10.0, -100.0),
        (-5.0, 12.0, -100.0),
        (1.0, 12.0, -100.0),
    ]
    err = _error("ROT RPL=30\nG0 SUPA Z0\n", "siemens840d")
    assert (err.code, err.location.line) == ("SIEM-UNSUPPORTED", 2) and "SUPA" in err.message


def test_siemens_def_arrays() -> None:
    # FELD1[10,3]: element [1,0] is the 4th value (9); FELD[2,3,4] all 1 by REP; PT[3] 2.5
    text = (
        "DEF REAL FELD1[10,3]=SET(0,,,9,0,1,2,-10,-11,-12,-20)\n"
        "DEF INT FELD[2,3,4] = REP(1,24), CNT\n"
        "DEF REAL PT[3]=REP(2.5)\n"
        "FELD[1,2,3]=FELD1[1,0]*2+FELD[0,0,0]\n"
        "G0 X=FELD[1,2,3] Y=PT[2] Z=FELD1[3,1]\n"
        "M30\n"
    )
    assert _ends(text, "siemens840d") == [(19.0, 2.5, -20.0)]
    err = _error("DEF REAL PT[3]\nR1=PT[3]\n", "siemens840d")
    assert (err.code, err.location.line) == ("SIEM-ARRAY", 2)


def test_siemens_axis_dynamic_settings_leave_the_path() -> None:
    text = "ACC[X]=50 JERKLIM[Z]=20 VELOLIM[Y]=80\n" + MOVES
    assert _ends(text, "siemens840d") == _ends(MOVES, "siemens840d")
    err = _error("ACC[E]=50\n" + MOVES, "siemens840d")
    assert err.code == "SIEM-AXIS" and "ACC[E]" in err.message


def test_loops_waiting_for_a_machine_input_end_with_a_located_error() -> None:
    # the control waits for the signal; a reading without the machine holds it at 0
    fanuc = _error("G21\nWHILE[#1004EQ0]DO1\nG04 X0.2\nEND1\nM30\n", "fanuc")
    assert (fanuc.code, fanuc.location.line) == ("FANUC-WAIT-INPUT", 4)
    siemens = _error('WHILE($A_IN[9]==0)\nMSG("WAIT")\nG4 F0.2\nENDWHILE\nM30\n', "siemens840d")
    assert (siemens.code, siemens.location.line) == ("SIEM-WAIT-INPUT", 4)
    # a loop reading the signal a few times, then going on, is read
    ok = "G21\n#1=0\nWHILE[#1 LT 5]DO1\n#2=#1004\n#1=#1+1\nEND1\nG0 X#1\nM30\n"
    assert _ends(ok, "fanuc") == [(5.0, 0.0, 0.0)]  # a value from a variable: 5 mm


def test_haas_g71_contour_closed_by_a_retract_along_the_stock_roughs_without_it() -> None:
    # N20 G00 G40 Z0.1 returns along the stock diameter X1.5 to the start: no material
    # there, so the roughing passes are those of the contour ending at X1.5 Z-2.097
    head = (
        "G20 G99 G18\nT0101\nG97 S2000 M03\nG00 G54 X1.5 Z0.1\n"
        "G71 P10 Q20 U0.01 W0.005 D0.05 F0.010\n"
        "N10 G00 G42 X-0.062 Z0.1\nG01 Z0.0\nX0.42928932\nX0.5 Z-0.03535534\nZ-2.097\n"
    )
    closed = head + "X1.5\nN20 G00 G40 Z0.1\nM30\n"
    open_ended = head + "N20 X1.5\nM30\n"
    rough = _ends(closed, "haas_lathe")
    assert len(rough) > 10 and rough == _ends(open_ended, "haas_lathe")
    with pytest.raises(Diagnostic):  # the 0i-TF's type I contour must be monotonic
        _ir(
            closed.replace(
                "G71 P10 Q20 U0.01 W0.005 D0.05 F0.010",
                "G71 U0.05 R0.01\nG71 P10 Q20 U0.01 W0.005 F0.010",
            ),
            "fanuc_lathe",
        )


def test_siemens_radius_compensation_of_a_zero_radius_keeps_the_path() -> None:
    comp = "T1 M6 D1\nG0 X0 Y0\nG41 G1 X10 Y0 F100\nY10\nG40 X20\nM30\n"
    assert _ends(comp, "siemens840d") == _ends(comp.replace("G41 ", ""), "siemens840d")
    table = read_tool_table(["T1 P1 D0.5 Z0 ;"], "sim.tbl")
    with pytest.raises(Diagnostic) as info:
        list(read_text(comp, "siemens840d", "prog", InterpreterOptions(tool_table=table)))
    assert (info.value.code, info.value.location.line) == ("SIEM-COMP", 3)


def test_older_work_offset_numbers_and_haas_diameter_offsets() -> None:
    # Fanuc #2701 is G54's Z (#5223): the tool, still at machine Z0, is at program Z50;
    # Haas #2401 is tool 1's diameter geometry (radius 5)
    fanuc = "G21 G90\n#2701=-50.\nG0 X#5223 Y#2701\nM30\n"
    assert _ends(fanuc, "fanuc") == [(-50.0, -50.0, 50.0)]
    haas = "G21 G90\n#2401=10.\nG10 L12 P2 R3.\nG0 X#2401 Y#2402\nM30\n"
    assert _ends(haas, "haas") == [(10.0, 6.0, 0.0)]


def test_siemens_shopmill_workpiece_header_moves_nothing() -> None:
    text = 'WORKPIECE(,"",,"BOX",112,0,-50,-80,-60,-60,60,60)\n' + MOVES
    assert _ends(text, "siemens840d") == _ends(MOVES, "siemens840d")


def test_a_main_program_repeating_itself_for_ever_stops_soon(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # N1 ... GOTO1 with nothing changing: the control runs it for ever; the reader stops
    # after MAX_REPEATS passes through the same state, not at the (much larger) jump limit
    monkeypatch.setattr(fanuc_flow, "MAX_REPEATS", 5)
    monkeypatch.setattr(siemens_flow, "MAX_REPEATS", 5)
    err = _error("G21\nN1 G90 G0 X1.\nX2.\nGOTO1\nM30\n", "fanuc")
    assert (err.code, err.location.line) == ("FANUC-LOOP-LIMIT", 4) and "for ever" in err.message
    err = _error("LOOP\nG90 G0 X1\nX2\nENDLOOP\nM30\n", "siemens840d")
    assert (err.code, err.location.line) == ("SIEM-LOOP-LIMIT", 4) and "for ever" in err.message
    # a loop whose state changes (a counter) runs to its exit
    counted = "G21\n#1=0\nN1 #1=#1+1\nIF [#1 GT 9] GOTO 99\nG0 X#1\nGOTO 1\nN99 M30\n"
    assert len(_ends(counted, "fanuc")) == 9


def test_siemens_setms_of_spindle_1_and_g290_change_nothing() -> None:
    # SETMS / SETMS(1): spindle 1 is the master (the IR's only spindle); G290: Siemens mode
    plain = "G0 X1 Y2\nS1000 M3\nG1 X5 F100\nM30\n"
    marked = "G290\nSETMS(1)\nG0 X1 Y2\nSETMS\nS1000 M3\nG1 X5 F100\nM30\n"
    assert _ends(marked, "siemens840d") == _ends(plain, "siemens840d")
    err = _error("G0 X1\nSETMS(2)\nM30\n", "siemens840d")
    assert (err.code, err.location.line) == ("SIEM-UNSUPPORTED", 2) and "SETMS(2)" in err.message
    err = _error("G291\nG0 X1\n", "siemens840d")
    assert (err.code, err.location.line) == ("SIEM-G-CODE", 1) and "ISO dialect" in err.message


@pytest.mark.parametrize(
    ("text", "code", "column", "named"),
    [
        ("ID=1 WHENEVER $A_IN[1] DO OVR=0\n", "SIEM-UNSUPPORTED", 6, "WHENEVER"),
        ("N1 DO G0 X10 Y20\n", "SIEM-UNSUPPORTED", 4, "DO"),
        ("SETINT(3) PRIO=1 LIFTFAST\n", "SIEM-UNSUPPORTED", 1, "SETINT"),
        ("ISOCALL\n", "SIEM-UNSUPPORTED", 1, "ISOCALL"),
        ("N120 MCALL (10,20,30,50)\n", "SIEM-SYNTAX", 12, "name"),
        ("G[1] = 1\n", "SIEM-UNSUPPORTED", 1, "G[...]"),
        ("G0 X0 Y0\nG3 X70 Y10 R=R10\n", "SIEM-WORD", 12, "CR="),
        ("PROC CYCLE32(REAL VELO, INT DIR)\nG0 X1\nRET\n", "SIEM-PROC", 1, "CYCLE32"),
    ],
)
def test_siemens_constructs_the_reader_does_not_read_are_named(
    text: str, code: str, column: int, named: str
) -> None:
    err = _error(text, "siemens840d")
    assert (err.code, err.location.column) == (code, column)
    assert named in err.message


def test_siemens_machine_data_with_two_indexes_is_refused_by_name() -> None:
    err = _error("R3 = ABS($MA_ACT_POS_ABS[0, AX1])\n", "siemens840d")
    assert err.code == "SIEM-UNSUPPORTED" and "$MA_ACT_POS_ABS[0,AX1]" in err.message


def test_siemens_modal_subprogram_call_after_each_motion_block(tmp_path: Path) -> None:
    # job planning, "Modal subprogram call": MCALL L10 calls L10 after every block with
    # path motion until MCALL alone; arguments are evaluated at each call; the moves of
    # the called subprogram call nothing
    (tmp_path / "L10.SPF").write_text("G1 Z-1 F100\nG0 Z1\nM17\n")
    (tmp_path / "HOLE.SPF").write_text("PROC HOLE(REAL DD)\nG1 Z=-DD F50\nG0 Z2\nRET\n")
    main = tmp_path / "main.mpf"
    main.write_text(
        "G0 X0 Y0 Z1\nMCALL L10\nG0 X10 Y10\nX20\nMCALL\nX30\n"
        "R1=3\nMCALL HOLE(R1)\nX40\nR1=4\nY20\nMCALL\nM30\n"
    )
    ir = read(main, "siemens840d", InterpreterOptions(search_path=(str(tmp_path),)))
    ends = [
        (c.x, c.y, c.z) for c in ir if isinstance(c, canon.StraightFeed | canon.StraightTraverse)
    ]
    assert ends == [
        (0.0, 0.0, 1.0),
        (10.0, 10.0, 1.0),
        (10.0, 10.0, -1.0),
        (10.0, 10.0, 1.0),
        (20.0, 10.0, 1.0),
        (20.0, 10.0, -1.0),
        (20.0, 10.0, 1.0),
        (30.0, 10.0, 1.0),
        (40.0, 10.0, 1.0),
        (40.0, 10.0, -3.0),
        (40.0, 10.0, 2.0),
        (40.0, 20.0, 2.0),
        (40.0, 20.0, -4.0),
        (40.0, 20.0, 2.0),
    ]


def test_siemens_cycle_with_a_program_file_beside_is_called_as_that_subprogram(
    tmp_path: Path,
) -> None:
    # the 840D searches the program's own directory before its cycle directories: a
    # CYCLE81.SPF there is the cycle called (with the arguments), also under MCALL
    (tmp_path / "CYCLE81.SPF").write_text(
        "PROC CYCLE81(REAL RTP, REAL RFP, REAL SDIS, REAL DP, REAL DPR)\n"
        "G1 Z=DP F100\nG0 Z=RTP\nRET\n"
    )
    main = tmp_path / "main.mpf"
    main.write_text(
        "G0 X1 Y1 Z5\nCYCLE81(10, 0, 2, -3)\nMCALL CYCLE81(8, 0, 2, -4)\nG0 X2\nMCALL\nM30\n"
    )
    ir = read(main, "siemens840d", InterpreterOptions(search_path=(str(tmp_path),)))
    ends = [
        (c.x, c.y, c.z) for c in ir if isinstance(c, canon.StraightFeed | canon.StraightTraverse)
    ]
    assert ends == [
        (1.0, 1.0, 5.0),
        (1.0, 1.0, -3.0),
        (1.0, 1.0, 10.0),
        (2.0, 1.0, 10.0),
        (2.0, 1.0, -4.0),
        (2.0, 1.0, 8.0),
    ]
    # without the file the reader's own expansion: G0 to RFP + SDIS, G1 to DP, G0 to RTP
    main.write_text("G0 X1 Y1 Z5\nF100\nCYCLE81(10, 0, 2, -3)\nM30\n")
    (tmp_path / "CYCLE81.SPF").unlink()
    ir = read(main, "siemens840d", InterpreterOptions(search_path=(str(tmp_path),)))
    ends = [
        (c.x, c.y, c.z) for c in ir if isinstance(c, canon.StraightFeed | canon.StraightTraverse)
    ]
    assert ends == [(1.0, 1.0, 5.0), (1.0, 1.0, 2.0), (1.0, 1.0, -3.0), (1.0, 1.0, 10.0)]


def test_siemens_single_block_suppression_leaves_the_path() -> None:
    plain = "G0 X1 Y2\nG1 X5 F100\nM30\n"
    marked = "SBLOF\nG0 X1 Y2\nSBLON\nG1 X5 F100\nM30\n"
    assert _ends(marked, "siemens840d") == _ends(plain, "siemens840d")
