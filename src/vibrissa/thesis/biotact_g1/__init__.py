"""Thesis 6.4: texture and distance on the BIOTACT G1 head, with and without RCP.

The experiment ``vibrissa reproduce biotact-g1``; its modules follow the
roles of :mod:`vibrissa.thesis`.
"""
