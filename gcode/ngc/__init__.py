"""The RS274/NGC interpreter (LinuxCNC 2.9, NIST v3): G-code to canonical commands."""
