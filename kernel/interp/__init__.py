"""Interpolation: sampling lines, arcs, helices and NURBS at the controller's period."""
