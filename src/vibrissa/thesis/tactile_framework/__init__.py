"""Thesis 2.5: the tactile framework as a closed loop on a whisking robot in a box world.

The experiment ``vibrissa reproduce tactile-framework``; its modules follow the roles of
:mod:`vibrissa.thesis`.
"""
