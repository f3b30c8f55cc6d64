"""Per-axis simulation: acc/dec after interpolation, servo loops, feedforward, errors."""
