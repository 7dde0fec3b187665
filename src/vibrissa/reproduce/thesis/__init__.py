"""One module per thesis experiment; each registers an :class:`~vibrissa.reproduce.Experiment`.

The registry imports every module of this package on first use, so a new
experiment is a new module here (plus its protocol in :mod:`vibrissa.experiments`).
"""
