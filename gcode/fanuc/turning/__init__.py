"""Fanuc lathe cycles (G70-G76, G90/G92/G94) expanded into moves."""
