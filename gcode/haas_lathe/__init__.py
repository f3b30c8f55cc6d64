"""Haas lathe programs: the Fanuc lathe engine with Haas's differences."""
