"""Cutter radius compensation (G41/G42) for the RS274/NGC interpreter."""
