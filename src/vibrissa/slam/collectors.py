"""Collectors: what to record of a particle filter as it runs.

They have the shape of ``particles``' ``collectors.py`` (Chopin & Papaspiliopoulos 2020).

A :class:`Collector` is handed to :class:`~vibrissa.slam.filter.ParticleFilter` (or
:func:`~vibrissa.slam.filter.run_slam`) in ``collect=[...]``. Iterating the filter calls
every collector's :meth:`Collector.collect` once on the state before the first step and
once after each step, the last call after the log's last step and the closing of an open
contact episode: ``n_steps + 1`` calls for a log of ``n_steps`` steps, in the order the
collectors were given. :meth:`Collector.result` gives what was recorded;
:func:`~vibrissa.slam.filter.run_slam` puts it in ``SlamRun.collected[collector.name]``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from vibrissa.slam import grid

if TYPE_CHECKING:
    from vibrissa.slam.filter import ParticleFilter

__all__ = ["Collector", "FrameStack", "Frames", "PoseEstimates", "Progress", "map_bytes"]


class Collector:
    """Records something of the filter at the start and after every step.

    Subclasses implement :meth:`collect` and :meth:`result`; they read the filter's public
    state (``poses``, ``log_weights``, ``logodds``, ``visited``, ``t``, ``log``,
    :meth:`~vibrissa.slam.filter.ParticleFilter.pose_estimate`) and must not change it.

    Attributes
    ----------
    name
        The key of the result in ``SlamRun.collected``; a class default that an instance
        may override (``Frames(name="frames_b")``).
    """

    name: str = ""

    def __init__(self, name: str | None = None) -> None:
        if name is not None:
            self.name = name

    def collect(self, pf: ParticleFilter) -> None:
        """Record the filter's state before its first step (``pf.t == 0``) and after each step.

        After a step, ``pf.t`` steps are done.

        Parameters
        ----------
        pf
            The filter.
        """
        raise NotImplementedError

    def result(self) -> Any:
        """What was recorded."""
        raise NotImplementedError


@dataclass(frozen=True)
class FrameStack:
    """The frames :class:`Frames` recorded (``n_frames = n_steps + 1``).

    Attributes
    ----------
    particles
        ``(n_frames, n_particles, 3)`` float32 map-frame poses.
    maps
        ``(n_frames, n_cells, n_cells)`` uint8 occupancy (0-255, ``[ix, iy]``) of the most
        probable particle, 128 where it has seen nothing.
    estimate
        ``(n_frames, 3)`` the weighted mean pose.
    """

    particles: np.ndarray
    maps: np.ndarray
    estimate: np.ndarray


def map_bytes(pf: ParticleFilter) -> np.ndarray:
    """The most probable particle's occupancy as ``(n_cells, n_cells)`` uint8 (0-255).

    It is 128 where the particle has seen nothing.
    """
    k = int(np.argmax(pf.log_weights))
    occ = np.where(pf.visited[k], grid.occupancy(pf.logodds[k]), 0.5)
    return np.round(occ * 255).astype(np.uint8)


class Frames(Collector):
    """Every frame of the run for a viewer; :meth:`result` is a :class:`FrameStack`.

    A frame is the particles, the best particle's map and the pose estimate.
    """

    name = "frames"

    def __init__(self, name: str | None = None) -> None:
        super().__init__(name)
        self._particles: list[np.ndarray] = []
        self._maps: list[np.ndarray] = []
        self._estimate: list[np.ndarray] = []

    def collect(self, pf: ParticleFilter) -> None:
        """Record the particles (float32), the best particle's map and the pose estimate."""
        self._particles.append(pf.poses.astype(np.float32))
        self._maps.append(map_bytes(pf))
        self._estimate.append(pf.pose_estimate())

    def result(self) -> FrameStack:
        """The recorded frames, stacked."""
        return FrameStack(np.stack(self._particles), np.stack(self._maps), np.stack(self._estimate))


class PoseEstimates(Collector):
    """The weighted mean pose of every frame; :meth:`result` is ``(n_frames, 3)``."""

    name = "pose_estimate"

    def __init__(self, name: str | None = None) -> None:
        super().__init__(name)
        self._estimate: list[np.ndarray] = []

    def collect(self, pf: ParticleFilter) -> None:
        """Record the weighted mean pose."""
        self._estimate.append(pf.pose_estimate())

    def result(self) -> np.ndarray:
        """The weighted mean poses, ``(n_frames, 3)``."""
        return np.stack(self._estimate)


class Progress(Collector):
    """Calls ``callback(frames_done, n_frames)`` at every frame (``n_frames = n_steps + 1``).

    :meth:`result` is the number of frames seen.

    Parameters
    ----------
    callback
        E.g. a progress bar's update.
    name
        As :class:`Collector`'s.
    """

    name = "progress"

    def __init__(self, callback: Callable[[int, int], None], name: str | None = None) -> None:
        super().__init__(name)
        self.callback = callback
        self.count = 0

    def collect(self, pf: ParticleFilter) -> None:
        """Count the frame and pass the frames done and ``n_frames`` to the callback."""
        self.count += 1
        self.callback(self.count, pf.log.n_steps + 1 if pf.log is not None else self.count)

    def result(self) -> int:
        """The number of frames seen."""
        return self.count
