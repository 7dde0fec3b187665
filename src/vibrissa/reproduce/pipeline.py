"""Run any registered experiment: dataset cache -> evaluation -> results -> reports.

:func:`run_experiment` is what ``vibrissa reproduce NAME`` calls. Every run writes
into its output directory:

- ``data/<protocol>-<fingerprint>.nc``: the simulated dataset (reused when the
  protocol is unchanged; a corrupt file is regenerated);
- ``results.json``: the results envelope — ``meta`` (vibrissa version, command
  line, seed, quick or full, start time, wall seconds per stage, cores),
  ``parameters``, ``classifiers`` and the experiment's own sections;
- ``report.md`` and ``report.html`` (one self-contained file, figures inlined),
  ``figures/`` and the experiment's extra files.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import errno
import functools
import hashlib
import os
import shlex
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa import __version__
from vibrissa.data import DatasetFileError, load_dataset
from vibrissa.experiments.contract import SelfGenerating, SimulationProtocol, chunk_size_of
from vibrissa.experiments.generate import (
    SCHEDULER_ADDRESS,
    WORKERS_PER_CORE,
    check_dask,
    generate,
    max_workers,
)
from vibrissa.reproduce.provenance import code_fingerprint, git_commit
from vibrissa.reproduce.registry import Evaluation, Experiment, get_experiment

__all__ = [
    "Progress",
    "cached_dataset",
    "check_job_arguments",
    "dataset_path",
    "run_experiment",
    "write_reports",
]

#: ``progress(stage, done, total)``; stage is ``"generate"`` or ``"evaluate"``.
Progress = Callable[[str, int, int], None]


def check_job_arguments(
    out_dir: str | os.PathLike[str],
    seed: object,
    workers: object = None,
    *,
    scheduler: object = None,
    **counts: object,
) -> Path:
    """Check a reproduction's arguments before any work is done; return ``out_dir``.

    Raises
    ------
    ValueError
        Naming the argument: ``seed`` not a non-negative integer, ``workers`` or any
        of ``counts`` (e.g. ``n_seeds``) not a positive integer, ``scheduler`` not a
        Dask address (``tcp://host:port``), ``out_dir`` an existing file.
    """
    if scheduler is not None and (
        not isinstance(scheduler, str) or not SCHEDULER_ADDRESS.fullmatch(scheduler)
    ):
        raise ValueError(
            f"scheduler must be a Dask address like tcp://host:8786, got {scheduler!r}"
        )

    def integer(v: object) -> bool:
        return isinstance(v, int | np.integer) and not isinstance(v, bool)

    if not integer(seed) or int(seed) < 0:  # type: ignore[call-overload]
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    for name, v in {"workers": workers, **counts}.items():
        if v is None and name == "workers":
            continue
        if not integer(v) or int(v) < 1:  # type: ignore[call-overload]
            raise ValueError(f"{name} must be a positive integer, got {v!r}")
    if workers is not None and int(workers) > max_workers():  # type: ignore[call-overload]
        raise ValueError(
            f"workers must be at most {max_workers()} ({WORKERS_PER_CORE} per "
            f"core of this machine), got {workers!r}"
        )
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"output directory {str(out)!r} is an existing file")
    for name in RUN_FILES:
        if (out / name).is_dir():
            raise ValueError(
                f"output directory {str(out)!r} holds a directory {name!r} where the run "
                "writes a file; move it away"
            )
    if (out / "figures").exists() and not (out / "figures").is_dir():
        raise ValueError(
            f"output directory {str(out)!r} holds a file 'figures' where the run writes its "
            "figures; move it away"
        )
    return out


#: The files every run writes into its output directory.
RUN_FILES = ("results.json", "report.md", "report.html")


def check_scheduler(protocol: SimulationProtocol, scheduler: str | None) -> None:
    """Refuse ``scheduler`` where it cannot be used.

    That is for a protocol that simulates its dataset on local processes only (its own
    ``generate_dataset`` takes no ``scheduler``), or when Dask is not installed
    (:func:`~vibrissa.experiments.generate.check_dask`).
    """
    if scheduler is None:
        return
    if isinstance(protocol, SelfGenerating) and not protocol.accepts_scheduler:
        raise ValueError(
            f"scheduler: the {protocol.name} session simulates on local "
            "processes only; leave out the scheduler"
        )
    check_dask()


def dataset_path(protocol: SimulationProtocol, out_dir: str | os.PathLike[str]) -> Path:
    """Where a run writing ``out_dir`` keeps the dataset of ``protocol``.

    ``<out_dir>/data/<protocol>-<fingerprint>-<code>.nc``: the fingerprint changes with
    any parameter of the protocol and the code part with the code that simulates it, so
    neither a changed protocol nor changed physics ever reuses stale data.
    """
    return Path(out_dir) / "data" / _file_name(protocol)


def _file_name(protocol: SimulationProtocol) -> str:
    code = _code_digest(type(protocol).__module__)[:8]
    return f"{protocol.name}-{protocol.fingerprint()}-{code}.nc"


@functools.cache
def _code_digest(module: str) -> str:
    """The fingerprint of the code that simulates a protocol's trials.

    Its module's closure (:func:`~vibrissa.reproduce.provenance.code_fingerprint`): a
    cached dataset is reused only by the code that made it. A module outside vibrissa (a
    user's own protocol) counts by its name alone.
    """
    try:
        return str(code_fingerprint(module)["digest"])
    except ValueError:
        return hashlib.sha256(module.encode()).hexdigest()[:16]


def cached_dataset(
    protocol: SimulationProtocol,
    data_dir: Path,
    progress: Progress | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
):
    """Load the dataset of ``protocol`` from ``data_dir``, generating it if absent.

    The file name carries the protocol's fingerprint, so a changed protocol never
    reuses stale data; a cached file that is corrupt, changed since it was written or
    carries no vibrissa checksum (``vibrissa_checksum``) is simulated again. With ``scheduler`` (a
    Dask address) the trials are simulated on that cluster instead of local processes.

    Returns
    -------
    (xarray.Dataset, pathlib.Path, bool)
        The dataset, its file and whether it was reused.
    """
    path = Path(data_dir) / _file_name(protocol)
    if path.exists():
        try:
            return load_dataset(path, written_by_vibrissa=True), path, True
        except DatasetFileError:
            # unreadable, changed since written, or not written by vibrissa at all (its
            # checksum attributes stripped or never there): never trusted, simulated again
            path.unlink()
    cb = (lambda d, t: progress("generate", d, t)) if progress else None
    if isinstance(protocol, SelfGenerating):  # simulates its whole dataset itself
        extra = {"scheduler": scheduler} if scheduler is not None else {}
        return protocol.generate_dataset(path, workers=workers, progress=cb, **extra), path, False
    # the protocols left (an XY-robot Protocol or a ChunkedTrials) are generate's
    ds = generate(
        protocol,
        path,
        workers=workers,
        scheduler=scheduler,
        progress=cb,
        chunk_size=chunk_size_of(protocol),
    )
    return ds, path, False


def _options(exp: Experiment, options: Mapping[str, Any]) -> dict[str, Any]:
    known = {o.name: o for o in exp.options}
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise ValueError(
            f"experiment {exp.name!r} has no option(s) {unknown}; "
            f"its options: {sorted(known) or 'none'}"
        )
    return {k: o.check(options.get(k, o.default)) for k, o in known.items()}


def run_experiment(
    name: str,
    out_dir: str | os.PathLike[str],
    *,
    quick: bool = False,
    seed: int = 0,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Progress | None = None,
    figures: bool = True,
    baseline: Mapping[str, Any] | None = None,
    command: str | None = None,
    **options: Any,
) -> dict[str, Any]:
    """Run the registered experiment ``name`` end to end; return its results.

    Parameters
    ----------
    name : str
        A registered experiment (``vibrissa reproduce --list``).
    out_dir : path-like
        Report, results, figures and the cached dataset (``data/``).
    quick : bool, default=False
        The experiment's small grid instead of the thesis' full one.
    seed : int, default=0
        Seed of the simulated session and of the evaluation's random choices.
    workers : int, optional
        Processes for dataset generation and for the evaluation (default: all cores;
        the results do not depend on it).
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:port``) to simulate the dataset on
        (the evaluation stays local); the results do not depend on it.
    progress : callable, optional
        ``progress(stage, done, total)``.
    figures : bool, default=True
        Draw the figures.
    baseline : dict, optional
        An earlier run's results (:func:`vibrissa.evaluate.baseline.load_baseline`),
        shown as "before" in the report.
    command : str, optional
        The command line recorded in ``meta`` (default: this process's ``sys.argv``).
    **options
        The experiment's own options (e.g. ``n_seeds`` for chapter 4).

    Returns
    -------
    dict
        The results envelope, as written to ``results.json``.

    Raises
    ------
    ValueError
        For an unknown experiment or option or a bad argument, before any work.
    """
    exp = get_experiment(name)
    opts = _options(exp, options)
    out = check_job_arguments(out_dir, seed, workers, scheduler=scheduler)
    protocol = exp.protocol_for(bool(quick), int(seed), opts)
    check_scheduler(protocol, scheduler)
    started = dt.datetime.now(dt.UTC)
    t0 = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    ds, path, reused = cached_dataset(protocol, out / "data", progress, workers, scheduler)
    t1 = time.perf_counter()
    cb = (lambda d, t, _desc: progress("evaluate", d, t)) if progress else None
    evaluation = exp.evaluate(ds, seed=int(seed), progress=cb, options=opts, workers=workers)
    if not isinstance(evaluation, Evaluation):
        raise TypeError(
            f"{exp.name}: evaluate() must return an Evaluation, got {type(evaluation).__name__}"
        )
    results = evaluation.results
    t2 = time.perf_counter()
    evaluation_meta = dict(results.get("meta", {}))
    meta = {
        "experiment": exp.name,
        "chapter": exp.chapter,
        "title": exp.title,
        "vibrissa_version": __version__,
        "command": command
        if command is not None
        else shlex.join([Path(sys.argv[0]).name, *sys.argv[1:]]),
        "seed": int(seed),
        "quick": bool(quick),
        "options": opts,
        "commit": git_commit(),
        "code": {"package": _package(exp), **code_fingerprint(_package(exp))},
        "started_at": started.isoformat(timespec="seconds"),
        "date": started.date().isoformat(),
        "wall_seconds": {"generate": round(t1 - t0, 3), "evaluate": round(t2 - t1, 3)},
        "scheduler": scheduler,
        "cores": {
            "available": os.cpu_count(),
            "generate_workers": workers if workers is not None else os.cpu_count(),
            "evaluate_workers": workers if workers is not None else os.cpu_count(),
        },
        "dataset": {
            "path": str(path),
            "reused": reused,
            "fingerprint": protocol.fingerprint(),
            "n_trials": int(ds.sizes["trial"]),
            **_variability_meta(protocol),
        },
        **evaluation_meta,
    }
    # meta, then what was measured (parameters) and with what (classifiers), then the rest
    first = [k for k in ("parameters", "classifiers") if k in results]
    envelope: dict[str, Any] = {
        "meta": meta,
        **{k: results[k] for k in first},
        **{k: v for k, v in results.items() if k != "meta" and k not in first},
    }
    from vibrissa.evaluate.report_common import write_json

    # results, reports and figures are written into a staging directory beside them and
    # moved into place only when all are whole: a full disk or a failing figure leaves
    # the run's earlier outputs as they were, never results without their report (the
    # simulated dataset stays cached in data/, so a rerun only evaluates again)
    with _staging(out) as stage:
        write_reports(
            exp,
            envelope,
            stage,
            dataset=ds if figures else None,
            figures=figures,
            baseline=baseline,
            workers=workers,
            artifacts=evaluation.artifacts,
        )
        meta["wall_seconds"]["report"] = round(time.perf_counter() - t2, 3)
        meta["wall_seconds"]["total"] = round(time.perf_counter() - t0, 3)
        write_json(envelope, stage / "results.json")
    return envelope


#: The staging directory of a run's outputs, inside its output directory.
STAGING_PREFIX = ".staging-"


@contextlib.contextmanager
def _staging(out: Path) -> Iterator[Path]:
    """A directory to write a run's outputs into; they replace ``out``'s when it closes.

    On an exception (a full disk, a failing figure, an interruption) the staging
    directory is removed and ``out`` keeps what it had. Otherwise each entry moves onto
    its namesake in ``out`` (a figures directory replaced whole), ``results.json`` last:
    a rename within one filesystem, so a reader sees the old outputs or the new ones.
    Stale staging directories of killed runs are removed first.
    """
    for old in out.glob(STAGING_PREFIX + "*"):
        shutil.rmtree(old, ignore_errors=True)
    stage = Path(tempfile.mkdtemp(prefix=STAGING_PREFIX, dir=out))
    try:
        yield stage
        entries = sorted(stage.iterdir(), key=lambda p: (p.name == "results.json", p.name))
        for entry in entries:  # never a file onto a directory or the reverse: check first
            dest = out / entry.name
            if dest.exists() and dest.is_dir() != entry.is_dir():
                raise IsADirectoryError(
                    errno.EISDIR, "in the way of the run's output of the same name", str(dest)
                )
        for entry in entries:
            dest = out / entry.name
            if entry.is_dir() and dest.is_dir() and not dest.is_symlink():
                shutil.rmtree(dest)  # the previous run's figures, replaced whole
            os.replace(entry, dest)
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def _package(exp: Experiment) -> str:
    """The package of ``exp`` (its ``experiment`` module's parent)."""
    return type(exp).__module__.rsplit(".", 1)[0]


def _variability_meta(protocol: Any) -> dict[str, Any]:
    """The trial-to-trial variability sources a protocol simulates (empty if it has none)."""
    variability = getattr(protocol, "variability", None)
    if variability is None or not hasattr(variability, "enabled"):
        return {}
    return {"variability_sources": list(variability.enabled())}


def write_reports(
    exp: Experiment,
    results: Mapping[str, Any],
    out: Path,
    *,
    dataset: Any,
    figures: bool,
    baseline: Mapping[str, Any] | None,
    workers: int | None = None,
    artifacts: Mapping[str, Any] | None = None,
) -> dict[str, Path]:
    """Figures, extra files, ``report.md`` and ``report.html`` of one run.

    ``workers`` processes may draw the figures (``None``: every core); ``artifacts``: the
    run's :attr:`~vibrissa.reproduce.registry.Evaluation.artifacts`.
    """
    from vibrissa._atomic import atomic_write_text
    from vibrissa.evaluate.html import write_html_report
    from vibrissa.evaluate.report_common import report_header

    figs = exp.write_outputs(
        results, out, dataset=dataset, figures=figures, workers=workers, artifacts=artifacts or {}
    )
    rel = {k: p.relative_to(out) for k, p in figs.items()}
    from vibrissa.thesis.claims import report_section

    text = report_header(results["meta"]) + exp.report_sections(results, rel, baseline)
    text = text.rstrip() + "\n\n" + report_section(exp.name)
    md = atomic_write_text(out / "report.md", text.rstrip() + "\n")
    html = write_html_report(md, out / "report.html")
    return {"report": md, "report_html": html, **{f"figure:{k}": p for k, p in figs.items()}}
