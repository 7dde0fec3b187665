"""Chapter 5: surface angle, contact speed and texture, classified simultaneously (5.2-5.4).

The experiment ``vibrissa reproduce angle-texture``; its modules follow the
roles of :mod:`vibrissa.thesis`.
"""
