"""Haas mill programs: the Fanuc reader with Haas's differences."""
