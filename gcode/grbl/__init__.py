"""Grbl 1.1 programs: an RS274/NGC subset."""
