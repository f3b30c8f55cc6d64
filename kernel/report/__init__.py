"""Measurements, traces and plots of a simulated program."""
