"""Mapping modes of the tactile SLAM filter (thesis 6.5.5) as registered mapper classes.

A mapper is the part of a step that turns contacts into occupancy evidence; everything
else (motion, weights, negative evidence along free whiskers and under the body,
resampling) is the same in every mode and lives in
:class:`~vibrissa.slam.filter.ParticleFilter`. Each filter owns one mapper instance,
built from :data:`MAPPERS` by :attr:`SlamSettings.mode <vibrissa.slam.SlamSettings.mode>`,
and calls its hooks:

- :meth:`Mapper.on_sensing` in every step that senses (not ``BACK``, not the events
  ``HIT_1``, ``HIT_2``, ``ABORT``), after the weights and the negative evidence;
- :meth:`Mapper.on_evidence` in every step that is not ``BACK``, events included;
- :meth:`Mapper.on_episode_end` when a contact episode ends (``ABORT``, ``BACK``,
  ``TURN``) and once more when the log ends;
- :meth:`Mapper.on_resample` with the resampling indices.

The modes:

``blob``
    a blob at every contact (:class:`BlobMapper`);
``geometric``
    one edge per contact episode through the first two whiskers' contacts
    (:class:`GeometricMapper`);
``template``
    one edge per episode at the surface angle the log reports on ``HIT_2``
    (:class:`TemplateMapper`).

Both episode modes leave a blob at the episode's first contact when it ends without an
edge (6.5.5.2). A new mode is a :class:`Mapper` subclass with a unique :attr:`Mapper.name`
decorated with :func:`register_mapper`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from vibrissa.slam import grid

if TYPE_CHECKING:
    from vibrissa.slam.filter import ParticleFilter
    from vibrissa.slam.log import SensorLog

__all__ = [
    "MAPPERS",
    "MODES",
    "BlobMapper",
    "EpisodeMapper",
    "GeometricMapper",
    "Mapper",
    "TemplateMapper",
    "register_mapper",
]


class Mapper:
    """A mapping mode: the occupancy evidence the particles add from their contacts.

    Subclasses set :attr:`name` and override the hooks they need (each does nothing
    here). A mapper may keep per-particle state (arrays with a first axis of
    ``n_particles``); it must then reorder it in :meth:`on_resample`.

    Attributes
    ----------
    name
        The mode's name, its key in :data:`MAPPERS` and the value of
        :attr:`SlamSettings.mode <vibrissa.slam.SlamSettings.mode>` that selects it.
    """

    name: ClassVar[str] = ""

    def on_sensing(self, pf: ParticleFilter, hit_world: np.ndarray) -> None:
        """A sensing step, after its weights and negative evidence.

        Parameters
        ----------
        pf
            The filter; its poses are the step's, its grids include the step's negative
            evidence.
        hit_world
            ``(n_particles, n_hits, 2)`` map-frame contact points seen from every particle.
        """

    def on_evidence(
        self, pf: ParticleFilter, log: SensorLog, t: int, hit_idx: np.ndarray, hit_world: np.ndarray
    ) -> None:
        """Any step that is not ``BACK`` (events included), after :meth:`on_sensing`.

        Parameters
        ----------
        pf
            The filter.
        log, t
            The sensor log and the step's row.
        hit_idx
            ``(n_hits,)`` indices of the whiskers in contact.
        hit_world
            ``(n_particles, n_hits, 2)`` their contact points seen from every particle.
        """

    def on_episode_end(self, pf: ParticleFilter) -> None:
        """A contact episode ends (``ABORT``, ``BACK``, ``TURN``, or the log's end).

        Parameters
        ----------
        pf
            The filter.
        """

    def on_resample(self, idx: np.ndarray) -> None:
        """The particles were resampled: particle ``k`` is now old particle ``idx[k]``.

        Parameters
        ----------
        idx
            ``(n_particles,)`` resampling indices.
        """

    # -- evidence helpers ---------------------------------------------------------
    @staticmethod
    def blob(pf: ParticleFilter, centres: np.ndarray) -> None:
        """Add a contact blob (``contact_p``, ``blob_sigma_m``) for every particle.

        The blobs are at ``(n_particles, 2)`` map-frame ``centres``, one per particle.
        """
        s = pf.s
        grid.add_blob(
            pf.logodds,
            pf.visited,
            centres,
            s.contact_p,
            s.blob_sigma_m,
            s.cell_m,
            limit=s.logodds_limit,
        )

    @staticmethod
    def edge(pf: ParticleFilter, centres: np.ndarray, angles: np.ndarray) -> None:
        """Add an edge (eq. 6.2; ``edge_p``, ``sigma_r_m``, ``sigma_theta_rad``) per particle.

        The edges go through ``(n_particles, 2)`` ``centres`` at ``(n_particles,)`` map-frame
        ``angles``.
        """
        s = pf.s
        grid.add_edge(
            pf.logodds,
            pf.visited,
            centres,
            angles,
            s.edge_p,
            s.sigma_r_m,
            s.sigma_theta_rad,
            s.cell_m,
            limit=s.logodds_limit,
        )

    @classmethod
    def edge_between(cls, pf: ParticleFilter, a: np.ndarray, b: np.ndarray) -> None:
        """Add an edge through the midpoints of ``(n_particles, 2)`` points ``a`` and ``b``.

        The edge runs along the line from ``a`` to ``b``.
        """
        d = b - a
        cls.edge(pf, (a + b) / 2, np.arctan2(d[:, 1], d[:, 0]))


MAPPERS: dict[str, type[Mapper]] = {}
"""The registry of mapping modes: name -> :class:`Mapper` subclass."""


def register_mapper(cls: type[Mapper]) -> type[Mapper]:
    """Register a :class:`Mapper` subclass in :data:`MAPPERS` under its :attr:`~Mapper.name`.

    A class decorator.

    Raises
    ------
    ValueError
        The class has no name, or another class is registered under it.
    """
    if not cls.name:
        raise ValueError(f"mapper {cls.__qualname__} has no name")
    if MAPPERS.get(cls.name, cls) is not cls:
        raise ValueError(f"a mapper is already registered as {cls.name!r}")
    MAPPERS[cls.name] = cls
    return cls


@register_mapper
class BlobMapper(Mapper):
    """``blob``: a blob at every contact of every sensing step."""

    name = "blob"

    def on_sensing(self, pf: ParticleFilter, hit_world: np.ndarray) -> None:
        """Add a blob at each of the step's contacts, for every particle."""
        for k in range(hit_world.shape[1]):
            self.blob(pf, hit_world[:, k])


class EpisodeMapper(Mapper):
    """Base of the modes that lay one edge per contact episode (first contact to ``HIT_2``).

    Until the edge is laid it keeps the episode's first contact per particle
    (:attr:`pending`, with the whiskers then in contact); an episode ending without an
    edge leaves a blob there. Subclasses implement :meth:`episode_step`.

    Attributes
    ----------
    pending
        ``(n_particles, 2)`` the episode's first contact, or ``None``.
    pending_whiskers
        The whiskers in contact when :attr:`pending` was taken.
    episode_done
        The episode's edge is laid: nothing more until it ends.
    """

    def __init__(self) -> None:
        self.pending: np.ndarray | None = None
        self.pending_whiskers: frozenset[int] = frozenset()
        self.episode_done = False

    def on_evidence(
        self, pf: ParticleFilter, log: SensorLog, t: int, hit_idx: np.ndarray, hit_world: np.ndarray
    ) -> None:
        """Pass the step to :meth:`episode_step` unless the episode's edge is laid."""
        if not self.episode_done:
            self.episode_step(pf, log, t, hit_idx, hit_world)

    def episode_step(
        self, pf: ParticleFilter, log: SensorLog, t: int, hit_idx: np.ndarray, hit_world: np.ndarray
    ) -> None:
        """One evidence step of an episode whose edge is not laid yet.

        As :meth:`Mapper.on_evidence`.
        """
        raise NotImplementedError

    def new_contacts(self, hit_idx: np.ndarray) -> list[int]:
        """Positions in ``hit_idx`` of whiskers not in contact when :attr:`pending` was taken."""
        return [k for k, w in enumerate(hit_idx) if int(w) not in self.pending_whiskers]

    def remember_first(self, hit_idx: np.ndarray, hit_world: np.ndarray, new: list[int]) -> None:
        """Keep the first new contact as the episode's :attr:`pending` one, if none yet."""
        if self.pending is None and new:
            self.pending = hit_world[:, new[0]].copy()
            self.pending_whiskers = frozenset(int(w) for w in hit_idx)

    def on_episode_end(self, pf: ParticleFilter) -> None:
        """Leave a blob at the pending first contact, if any, and reset for the next episode."""
        if self.pending is not None:
            self.blob(pf, self.pending)
        self.pending, self.pending_whiskers, self.episode_done = None, frozenset(), False

    def on_resample(self, idx: np.ndarray) -> None:
        """Reorder the pending first contacts by the resampling indices."""
        if self.pending is not None:
            self.pending = self.pending[idx]


@register_mapper
class GeometricMapper(EpisodeMapper):
    """``geometric``: an edge through the first two whiskers' contacts of an episode.

    The two are new contacts in one step, or the pending first contact and the next new one.
    """

    name = "geometric"

    def episode_step(
        self, pf: ParticleFilter, log: SensorLog, t: int, hit_idx: np.ndarray, hit_world: np.ndarray
    ) -> None:
        """Lay the edge once two contacts are known; else remember the first new contact."""
        new = self.new_contacts(hit_idx)
        if self.pending is None and len(new) >= 2:
            self.edge_between(pf, hit_world[:, new[0]], hit_world[:, new[-1]])
            self.episode_done = True
        elif self.pending is not None and new:
            self.edge_between(pf, self.pending, hit_world[:, new[0]])
            self.pending, self.episode_done = None, True
        else:
            self.remember_first(hit_idx, hit_world, new)


@register_mapper
class TemplateMapper(EpisodeMapper):
    """``template``: an edge at the surface angle the log reports (on ``HIT_2``).

    The edge goes through the mean of the step's contacts and the pending first contact.
    """

    name = "template"

    def episode_step(
        self, pf: ParticleFilter, log: SensorLog, t: int, hit_idx: np.ndarray, hit_world: np.ndarray
    ) -> None:
        """Lay the edge at a reported surface angle; else remember the first new contact."""
        angle = float(log.surface_angle_rad[t])
        if math.isfinite(angle):
            pts = [hit_world[:, k] for k in range(hit_world.shape[1])]
            if self.pending is not None:
                pts.append(self.pending)
            if pts:
                self.edge(pf, np.mean(pts, axis=0), pf.poses[:, 2] + angle)
                self.pending, self.episode_done = None, True
            return
        self.remember_first(hit_idx, hit_world, self.new_contacts(hit_idx))


MODES: tuple[str, ...] = tuple(MAPPERS)
"""The built-in mapping modes' names, in registration order: ``blob``, ``geometric``,
``template``."""
