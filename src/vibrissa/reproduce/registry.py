"""The registry of thesis experiments behind ``vibrissa reproduce NAME``.

An experiment is one :class:`Experiment` subclass in the ``experiment`` module of its
package in :mod:`vibrissa.thesis`, registered with :func:`register`. It owns
its protocol (grid, robot, sensor: :meth:`Experiment.protocol`), its classifiers
and evaluation (:meth:`Experiment.evaluate`), its files and figures
(:meth:`Experiment.write_outputs`), its report sections
(:meth:`Experiment.report_sections`) and its command-line summary
(:meth:`Experiment.summary`). :func:`vibrissa.reproduce.run_experiment` runs any of
them the same way: dataset cache, evaluation, results envelope, Markdown and HTML
report. Adding an experiment is adding a package to :mod:`vibrissa.thesis`.
"""

from __future__ import annotations

import importlib
import math
import pkgutil
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import xarray as xr

from vibrissa.experiments.contract import SimulationProtocol

__all__ = ["Evaluation", "Experiment", "Option", "experiments", "get_experiment", "register"]

_REGISTRY: dict[str, Experiment] = {}


@dataclass(frozen=True)
class Option:
    """An experiment's own option: an integer, a selection of names or a list of numbers.

    An integer (e.g. chapter 4's ``n_seeds``), with ``choices`` a comma-separated
    selection of names (e.g. 6.2's ``floors``), or with ``numbers`` a comma-separated list
    of finite numbers (e.g. 6.4's ``distances``; an empty string: none given, the
    protocol's own).

    Attributes
    ----------
    name : str
        Python name; the command-line flag is ``--`` + name with ``-`` for ``_``.
    default : int or str
        An integer, or (with ``choices``) a comma-separated list of names.
    help : str
    minimum : int
        Smallest allowed value; with ``choices``, fewest names.
    choices : tuple of str
        The names a selection may hold (empty: an integer option).
    item : str
        What one name is, for messages (``"floor texture"``).
    numbers : bool
        A comma-separated list of numbers (``minimum``: fewest, unless empty).
    """

    name: str
    default: int | str
    help: str
    minimum: int = 1
    choices: tuple[str, ...] = ()
    item: str = "name"
    numbers: bool = False

    @property
    def flag(self) -> str:
        """The command-line flag."""
        return "--" + self.name.replace("_", "-")

    def check(self, value: Any) -> int | tuple[str, ...] | tuple[float, ...]:
        """The value as int (or as a tuple of names or numbers), or ValueError naming the flag."""
        if self.choices:
            return self._check_names(value)
        if self.numbers:
            return self._check_numbers(value)
        if isinstance(value, bool) or not isinstance(value, int) or value < self.minimum:
            raise ValueError(f"{self.flag} must be an integer >= {self.minimum}, got {value!r}")
        return int(value)

    def _check_numbers(self, value: Any) -> tuple[float, ...]:
        if isinstance(value, str):
            parts = [v.strip() for v in value.split(",") if v.strip()]
        elif isinstance(value, tuple | list):
            parts = list(value)
        else:
            parts = [value]
        try:
            if any(isinstance(v, bool) for v in parts):
                raise ValueError
            nums = tuple(float(v) for v in parts)
        except (TypeError, ValueError):
            raise ValueError(
                f"{self.flag} must be comma-separated numbers, got {value!r}"
            ) from None
        if not all(math.isfinite(v) for v in nums):
            raise ValueError(f"{self.flag} must be finite numbers, got {value!r}")
        if nums and len(nums) < self.minimum:
            raise ValueError(f"{self.flag} needs at least {self.minimum} numbers, got {len(nums)}")
        return nums

    def _check_names(self, value: Any) -> tuple[str, ...]:
        if isinstance(value, str):
            names = tuple(v.strip() for v in value.split(",") if v.strip())
        elif isinstance(value, tuple | list) and all(isinstance(v, str) for v in value):
            names = tuple(value)
        else:
            raise ValueError(f"{self.flag} must be a comma-separated list of names, got {value!r}")
        unknown = [v for v in names if v not in self.choices]
        if unknown:
            raise ValueError(
                f"{self.flag}: unknown {self.item} {unknown[0]!r}; choose from "
                f"{', '.join(self.choices)}"
            )
        if len(set(names)) != len(names):
            raise ValueError(f"{self.flag}: each name once, got {','.join(names)}")
        if len(names) < self.minimum:
            raise ValueError(
                f"{self.flag} needs at least {self.minimum} of "
                f"{', '.join(self.choices)}, got {','.join(names) or 'none'}"
            )
        return names


@dataclass
class Evaluation:
    """What :meth:`Experiment.evaluate` returns.

    Attributes
    ----------
    results : dict
        The results envelope's sections: ``meta`` (merged into the run's meta),
        ``parameters``, ``classifiers`` and the experiment's own; JSON-ready, written to
        ``results.json`` as they are.
    artifacts : dict
        In-memory data for the figures (arrays, simulated runs), handed to
        :meth:`Experiment.write_outputs` and never serialised.
    """

    results: dict[str, Any]
    artifacts: dict[str, Any] = field(default_factory=dict)


class Experiment(ABC):
    """One experiment of the thesis: protocol, classifiers, evaluation, report.

    Subclasses set the class attributes and implement the abstract methods; they
    are stateless (one instance is registered).
    """

    #: Registry name and command (``vibrissa reproduce NAME``).
    name: ClassVar[str]
    #: Thesis chapter.
    chapter: ClassVar[int]
    #: Report title.
    title: ClassVar[str]
    #: One line for ``vibrissa reproduce --list``.
    description: ClassVar[str]
    #: Own options beyond the common ones (quick, seed, workers, figures, baseline).
    options: ClassVar[tuple[Option, ...]] = ()

    # ------------------------------------------------------------------ protocol
    @abstractmethod
    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """The protocol that simulates the session's data.

        See :mod:`vibrissa.experiments.contract` for what one is.
        """

    def protocol_for(
        self, quick: bool, seed: int, options: Mapping[str, Any]
    ) -> SimulationProtocol:
        """The protocol of a run with the experiment's own (checked) ``options``.

        The default ignores them (they are evaluation options).
        """
        return self.protocol(quick, seed)

    def n_trials(self, quick: bool) -> int:
        """Trials of the simulated session."""
        return int(self.protocol(quick, 0).n_trials)

    # ------------------------------------------------------------------ evaluation
    @abstractmethod
    def evaluate(
        self,
        ds: xr.Dataset,
        *,
        seed: int,
        progress: Callable | None,
        options: Mapping[str, Any],
        workers: int | None = None,
    ) -> Evaluation:
        """Run the classifiers and the evaluation.

        Gives the results (``meta``, ``parameters``, ``classifiers`` and the experiment's
        own sections) and the figures' in-memory artifacts. ``workers``: processes the
        evaluation may use (``None``: every core); its results do not depend on it.
        """

    # ------------------------------------------------------------------ outputs
    def write_outputs(
        self,
        results: Mapping[str, Any],
        out_dir: Path,
        *,
        dataset: xr.Dataset | None,
        figures: bool,
        workers: int | None = None,
        artifacts: Mapping[str, Any] | None = None,
    ) -> dict[str, Path]:
        """Write extra files (CSV) and figures; return figure key -> path.

        ``workers``: processes that may draw the figures (``None``: every core);
        ``artifacts``: the :attr:`Evaluation.artifacts` of the run (empty for a run drawn
        again from its ``results.json``).
        """
        return {}

    @abstractmethod
    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """The report's Markdown body (everything after the common header)."""

    @abstractmethod
    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """The experiment's part of ``vibrissa reproduce NAME --json``."""

    def console_table(self, summary: Mapping[str, Any]) -> Any:
        """A rich renderable of the summary for the terminal (``None``: nothing)."""
        return None

    def listing(self) -> dict[str, Any]:
        """The entry of ``vibrissa reproduce --list --json``."""
        return {
            "name": self.name,
            "chapter": self.chapter,
            "title": self.title,
            "description": self.description,
            "trials": {"quick": self.n_trials(True), "full": self.n_trials(False)},
            "options": {o.flag: {"default": o.default, "help": o.help} for o in self.options},
        }


def register(cls: type[Experiment]) -> type[Experiment]:
    """Class decorator: register one instance of an :class:`Experiment` subclass."""
    inst = cls()
    if inst.name in _REGISTRY and type(_REGISTRY[inst.name]) is not cls:
        raise ValueError(f"experiment {inst.name!r} is registered twice")
    _REGISTRY[inst.name] = inst
    return cls


def _discover() -> None:
    import vibrissa.thesis as pkg

    for mod in pkgutil.iter_modules(pkg.__path__):
        if mod.ispkg:
            importlib.import_module(f"{pkg.__name__}.{mod.name}.experiment")


def experiments() -> dict[str, Experiment]:
    """Every registered experiment, by name, in thesis order (chapter, then name)."""
    _discover()
    return dict(sorted(_REGISTRY.items(), key=lambda kv: (kv[1].chapter, kv[0])))


def get_experiment(name: str) -> Experiment:
    """The registered experiment ``name``.

    Raises
    ------
    ValueError
        Naming the known experiments.
    """
    exps = experiments()
    if name not in exps:
        raise ValueError(f"unknown experiment {name!r}; choose one of {', '.join(exps)}")
    return exps[name]
