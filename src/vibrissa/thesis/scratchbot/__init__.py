"""Thesis 6.3: radial distance and whisk speed on SCRATCHbot, a whisking robot.

The experiment ``vibrissa reproduce scratchbot``; its modules follow the
roles of :mod:`vibrissa.thesis`.
"""
