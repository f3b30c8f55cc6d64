"""The numba array types the compiled kernels' explicit signatures are written with (one
set for every kernels module kernel.aot builds ahead of time: gcode.ngc.lane, the Sandia
read-back lane, the chord comparison). Imported only by those modules, which load numba
anyway."""

from __future__ import annotations

from numba import types as nt

U8 = nt.Array(nt.uint8, 1, "C")
U8_RO = nt.Array(nt.uint8, 1, "C", readonly=True)
I8 = nt.Array(nt.int8, 1, "C")
I64 = nt.Array(nt.int64, 1, "C")
I64_2D = nt.Array(nt.int64, 2, "C")
F64 = nt.Array(nt.float64, 1, "C")
F64_2D = nt.Array(nt.float64, 2, "C")
