"""The thesis' floor-texture numbers (Evans 2011, 6.2): tables 6.1-6.3 and 6.2.2."""

from __future__ import annotations

from typing import Any

#: The thesis' tables 6.1-6.3 as confusion matrices with rows = true floor (the
#: printed tables have the true floor in columns), floors in the order rough carpet,
#: vinyl, smooth carpet, tarmac; and its mean-correct figures (6.2.2).
THESIS: dict[str, Any] = {
    "confusion": {
        "anticlockwise": [[78, 1, 0, 1], [6, 54, 1, 19], [12, 4, 43, 21], [10, 12, 4, 54]],
        "clockwise": [[64, 0, 11, 5], [6, 63, 1, 10], [26, 0, 27, 27], [11, 9, 8, 52]],
        "spot": [[60, 0, 13, 7], [7, 48, 3, 22], [48, 1, 9, 22], [7, 2, 9, 62]],
    },
    "mean_correct": {"anticlockwise": 0.72, "clockwise": 0.64, "spot": 0.56},
    "cross_condition": 0.52,
    "floors": ["rough-carpet", "vinyl", "smooth-carpet", "tarmac"],
}
