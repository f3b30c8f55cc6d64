"""NIST RS274/NGC v3 programs: the interpreter's subset of the language."""
