"""The Siemens SINUMERIK 840D sl reader's parts: lexer, blocks, expressions, frames, arcs,
motions, cycles, program flow and the modal executor (entry: gcode.siemens.reader).
"""
