"""Suite-wide set-up: the compiled kernels (the fast lane's, the Part 21 scanner's, the
Sandia read-back lane's and the chord comparison's) are built before any test runs.

The first use of the kernels builds them once (``gcode.ngc.lane.fastlane.load_aot``, ~30 s) and says
so on stderr; building them here, in the controlling process, keeps that one-off notice and
its delay out of the tests' own timings and outputs (xdist workers then find them cached).
"""

from __future__ import annotations

import pytest


def pytest_configure(config: pytest.Config) -> None:
    if hasattr(config, "workerinput"):  # an xdist worker: the controller built them
        return
    from gcode.ngc.lane import fastlane
    from gcode.sandia import lane as sandia_lane
    from kernel.ir import chords
    from stepnc import p21_scan

    fastlane.kernel_mode()
    p21_scan.KERNELS.mode()
    sandia_lane.KERNELS.mode()
    chords.KERNELS.mode()
