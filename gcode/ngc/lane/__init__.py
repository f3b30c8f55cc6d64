"""The fast lane: plain CAM lines read by compiled kernels."""
