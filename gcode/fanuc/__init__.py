"""Fanuc 0i/30i (and Haas) input: lexer, macro B, subprogram calls, transforms, executor.

The public readers are :mod:`gcode.fanuc.reader` and
:mod:`gcode.haas.reader`; docs/readers/fanuc.md describes the semantics.
"""
