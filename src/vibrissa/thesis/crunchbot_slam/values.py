"""The thesis' CrunchBot numbers (Evans 2011, 6.5.4, 6.5.6)."""

from __future__ import annotations

from typing import Any

#: The thesis' numbers (6.5.4, 6.5.6): map error of eq. 6.3 per mode and of a random
#: map; radial-distance error (std, mm) per obstacle whisker and all together.
THESIS: dict[str, Any] = {
    "map_error": {"blob": 0.40, "geometric": 0.39, "template": 0.37, "random": 0.47},
    "radial_distance_error_mm": {"w1": 5.68, "w2": 2.78, "w3": 1.82, "w4": 4.37, "combined": 4.98},
}

#: The SLAM map's side (m): 50 x 50 cells of 50 mm, double the arena (6.5.3).
MAP_SIZE_M = 2.5
