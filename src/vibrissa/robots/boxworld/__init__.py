"""The thesis' tactile "box world" (2.5) and a whisking head that moves through it.

:mod:`~vibrissa.robots.boxworld.scene` (the world and its ground truth),
:mod:`~vibrissa.robots.boxworld.head` (the head, its pose and its whiskers' frames),
:mod:`~vibrissa.robots.boxworld.whisk` (first contacts and the whisks' physics).
"""

from vibrissa.robots.boxworld.head import HeadPose, WhiskingHead, whisker_frame
from vibrissa.robots.boxworld.scene import BOX_WORLDS, Box, BoxWorld, Face, box_world
from vibrissa.robots.boxworld.whisk import (
    CONTACT_KINDS,
    ContactGeometry,
    WhiskRecord,
    can_move,
    first_contact,
    whisk,
)

__all__ = [
    "BOX_WORLDS",
    "CONTACT_KINDS",
    "Box",
    "BoxWorld",
    "ContactGeometry",
    "Face",
    "HeadPose",
    "WhiskRecord",
    "WhiskingHead",
    "box_world",
    "can_move",
    "first_contact",
    "whisk",
    "whisker_frame",
]
