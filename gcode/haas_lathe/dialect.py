"""Haas lathe (NGC control): the Fanuc lathe vocabulary (G code system A) with Haas's
program conventions: five-digit program numbers, ``G04 P`` in seconds with a decimal point,
sequence numbers up to 99999.
"""

from dataclasses import replace

from gcode.fanuc_lathe.dialect import DIALECT as FANUC_LATHE

DIALECT = replace(
    FANUC_LATHE,
    name="haas_lathe",
    title="Haas lathe (NGC control)",
    reference="Haas lathe operator's manual, G-code and M-code chapters",
    max_sequence_number=99999,
    # the Haas lathe has G154 P1-P99, but this project's lathe reader does not read it back
    # yet: a conversion that needs one reports the loss CONV-WORK-OFFSET instead
    header=("%", "O00001"),
    footer=("%",),
    dwell=("G04", "P", 1.0),
)
