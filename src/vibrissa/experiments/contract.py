"""The contract of a simulation protocol and its two generation routes.

A protocol describes a simulated session: its trials, robot, stimulus and sensor. What
:func:`vibrissa.experiments.generate.generate`, the time estimate
(:mod:`vibrissa.experiments.estimate`) and the reproduction pipeline
(:func:`vibrissa.reproduce.pipeline.cached_dataset`) need of one is written here once,
as abstract base classes, and they dispatch on the class, never on which attributes an
object happens to have:

- :class:`SimulationProtocol`, every protocol: a name, a trial count and a fingerprint
  of every parameter (the dataset cache's key). A plain one is an XY-robot protocol
  (:class:`vibrissa.experiments.protocols.Protocol`), whose trials the XY-robot runner
  (:mod:`vibrissa.experiments.runner`) simulates;
- :class:`ChunkedTrials`, route 1: a protocol of another robot that simulates any chunk
  of its trials itself (on worker processes, resumably, by ``generate``) and builds the
  dataset from the joined chunks (the Roomba of 6.2, the G1 of 6.4, CrunchBot's runs);
- :class:`SelfGenerating`, route 2: a protocol that simulates its whole dataset in one
  call (SCRATCHbot's continuous runs, 6.3; CrunchBot, which trains its classifiers once
  and then generates its chunks).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import xarray as xr

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "ChunkedTrials",
    "SelfGenerating",
    "SimulationProtocol",
    "chunk_size_of",
]

#: Trials per chunk of work when the protocol does not set its own.
DEFAULT_CHUNK_SIZE = 32


class SimulationProtocol(ABC):
    """What every simulation protocol has.

    Attributes
    ----------
    name : str
        The protocol's name (the dataset file's prefix).
    """

    name: str

    @property
    @abstractmethod
    def n_trials(self) -> int:
        """Trials of the session."""

    @abstractmethod
    def fingerprint(self) -> str:
        """A digest of every parameter: a changed protocol never reuses a cached dataset."""


class ChunkedTrials(SimulationProtocol):
    """A protocol that simulates any chunk of its trials itself (generation route 1)."""

    @property
    def chunk_size(self) -> int:
        """Trials per chunk of work (a protocol sets its own, e.g. one class of trials)."""
        return DEFAULT_CHUNK_SIZE

    @abstractmethod
    def simulate_trials(self, indices: Sequence[int] | np.ndarray) -> dict[str, np.ndarray]:
        """Simulate the trials ``indices``.

        Returns arrays that ``np.concatenate`` joins in chunk order (among them ``index``, the
        trials' indices).
        """

    @abstractmethod
    def build_dataset(self, results: dict[str, np.ndarray]) -> xr.Dataset:
        """The session's dataset from the joined arrays of every chunk."""

    @abstractmethod
    def signal_bytes(self) -> int:
        """Bytes of the finished dataset's signal (the work statement's size)."""

    @abstractmethod
    def seconds_per_trial(self) -> float:
        """Seconds one trial takes on this machine, measured on a few of its own trials."""


class SelfGenerating(SimulationProtocol):
    """A protocol that simulates its whole dataset in one call (generation route 2)."""

    #: Whether :meth:`generate_dataset` can run on a Dask cluster (takes ``scheduler``).
    accepts_scheduler: ClassVar[bool] = False

    @abstractmethod
    def generate_dataset(
        self,
        path: Path,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        **kwargs: Any,
    ) -> xr.Dataset:
        """Simulate the session into the NetCDF file ``path`` and return its dataset.

        ``workers``: processes (``None``: every core); ``progress(done, total)``; with
        :attr:`accepts_scheduler`, ``scheduler`` (a Dask address) among ``kwargs``.
        """


def chunk_size_of(protocol: SimulationProtocol) -> int:
    """Trials per chunk of work of ``protocol``.

    Its own for :class:`ChunkedTrials`, else :data:`DEFAULT_CHUNK_SIZE`.
    """
    return int(protocol.chunk_size) if isinstance(protocol, ChunkedTrials) else DEFAULT_CHUNK_SIZE
