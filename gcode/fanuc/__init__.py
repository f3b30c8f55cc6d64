"""Fanuc 0i/30i (and Haas) input: lexer, macro B, subprogram calls, transforms, executor.

The public readers are :mod:`gcode.dialects.fanuc_reader` and
:mod:`gcode.dialects.haas_reader`; docs/readers/fanuc.md describes the semantics.
"""
