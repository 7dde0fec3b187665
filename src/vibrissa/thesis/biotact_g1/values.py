"""The BIOTACT G1's thesis values.

Its control strategies (6.4.1) and what 6.4.4 says of each hit-rate curve.
"""

from __future__ import annotations

#: The control strategies of 6.4.1: name -> sigma_z.
STRATEGIES: dict[str, float] = {"unmodulated": 0.0, "rcp7": 0.7, "rcp9": 0.9}

#: What 6.4.4 says of each curve (figures 6.6 and 6.7 give no numbers in the text).
THESIS = {
    ("naive_bayes", "joint"): "rises, maximum after 4-5 whisks (unmodulated); RCP higher "
    "after 1-2 whisks, RCP7 best; RCP7 reaches 100 % after 7",
    ("naive_bayes", "texture"): "high after 3-4 whisks; RCP7 best, then RCP9, then "
    "unmodulated; maximum at 4 whisks",
    ("naive_bayes", "distance"): "high after 3-4 whisks; RCP7 best, then RCP9, then "
    "unmodulated; maximum at 4 whisks",
    ("template", "joint"): "maximum after 4-5 whisks (unmodulated); RCP higher after 1-2 "
    "whisks; RCP7 improves little; RCP9 falls, then improves after 6",
    ("template", "texture"): "unmodulated only reaches 75 %; RCP9 higher",
    ("template", "distance"): "like naive Bayes (unmodulated); RCP9 higher below 3 whisks, "
    "RCP lower than unmodulated with more",
}
CLASSIFIER_TITLES = {
    "naive_bayes": "stationary naive Bayes (figure 6.6)",
    "template": "class-mean templates (figure 6.7)",
}
