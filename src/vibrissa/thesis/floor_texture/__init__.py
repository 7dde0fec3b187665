"""Thesis 6.2: floor-texture discrimination with a whisker on a Roomba.

The experiment ``vibrissa reproduce floor-texture``; its modules follow the
roles of :mod:`vibrissa.thesis`.
"""
