"""Toolpath generators, one module per operation family (facing, pocket, slot, step,
open_pocket, drilling, explicit). Each exposes ``generate(ex, job)`` writing canonical
commands through an :class:`stepnc.executor.Executor`; geometry is built in feature
coordinates as :mod:`stepnc.toolpaths.code` pseudocode and placed with the feature's frame."""
