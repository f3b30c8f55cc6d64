"""Mach3 (ArtSoft) programs: RS274/NGC with Mach3's own codes."""
