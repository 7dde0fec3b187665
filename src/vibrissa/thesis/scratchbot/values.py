"""What the thesis says of SCRATCHbot (6.3, figure 6.5) and of figure 3.9 (3.4.2).

It gives no numbers for these experiments, only these relations and outcomes.
"""

from __future__ import annotations

#: The relations of 6.3 (figure 6.5) and the outcome of each panel of figure 3.9.
THESIS: dict[str, str] = {
    "peak_vs_distance": "varies predictably: falls with distance (fig 6.5 a)",
    "duration_vs_speed": "falls as speed rises (the reverse of the XY robot)",
    "figure_3_9_a": "one contact per whisk, no inter-whisk modulation",
    "figure_3_9_b": "biphasic whisk, two contacts",
    "classifiers": "too small to do an analysis similar to that conducted on the XY "
    "positioning robot data",
}
