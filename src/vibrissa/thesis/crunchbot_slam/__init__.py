"""Thesis 6.5: CrunchBot's tactile SLAM in three mapping modes.

The experiment ``vibrissa reproduce crunchbot-slam``; its modules follow the
roles of :mod:`vibrissa.thesis`.
"""
