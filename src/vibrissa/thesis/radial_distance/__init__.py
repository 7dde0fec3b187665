"""Chapter 4: radial distance and speed from one whisker deflection (thesis 4.2-4.5).

The experiment ``vibrissa reproduce radial-distance``; its modules follow the
roles of :mod:`vibrissa.thesis`.
"""
