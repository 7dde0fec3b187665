"""Generate a protocol's dataset: parallel, resumable, deterministic.

The trials are cut into chunks. Each finished chunk is written atomically to a
shard file in ``<out>.parts/`` next to the output, together with a manifest that
records the protocol's fingerprint. Interrupt a run and start it again: finished
shards are kept and only the missing chunks are simulated, so no trial is lost or
simulated twice. When all chunks are present they are assembled into the NetCDF
dataset (written atomically, with a checksum) and the shards are removed.

Every argument is checked before anything is created on disk. While a generation
runs it holds an exclusive lock on ``<out>.parts/.lock``: a second writer of the
same output fails at once (:class:`GenerationError`). Temporary files left by a
write that was killed are removed by the next run.

Chunks run on local worker processes (all cores by default) or, with
``scheduler=ADDRESS``, on an existing Dask cluster. Every trial is seeded from
``(seed, trial index)``, so the signals are the same bytes however the work is
distributed.
"""

from __future__ import annotations

import contextlib
import fcntl
import functools
import hashlib
import importlib.util
import json
import os
import re
import shutil
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa import __version__
from vibrissa._atomic import atomic_path, atomic_write_text, check_writable
from vibrissa._processes import imap_unordered
from vibrissa.data.dataset import coordinate_attrs
from vibrissa.experiments.contract import ChunkedTrials, SimulationProtocol
from vibrissa.experiments.protocols import Protocol
from vibrissa.experiments.runner import (
    TRIAL_DIAGNOSTICS,
    n_samples,
    simulate_trials,
    whisker_attrs,
)

__all__ = [
    "GenerationError",
    "build_dataset",
    "check_dask",
    "check_generation",
    "check_size",
    "dataset_bytes",
    "generate",
    "kept_trials",
    "SCHEDULER_ADDRESS",
    "WORKERS_PER_CORE",
    "max_workers",
    "parts_dir",
]

ProgressCallback = Callable[[int, int], None]

#: Local worker processes allowed per core (the simulation is CPU-bound).
WORKERS_PER_CORE = 4


class GenerationError(ValueError):
    """A generation cannot proceed as asked: the user's choice, so a ``ValueError``.

    For instance leftover shards of another protocol, or another writer of the same output.
    """


def parts_dir(out: str | os.PathLike[str]) -> Path:
    """Directory of the shards of a generation writing ``out``."""
    p = Path(out)
    return p.with_name(p.name + ".parts")


def dataset_bytes(protocol: SimulationProtocol) -> int:
    """Bytes of the finished dataset's signal (trials x 2 channels x samples, float64)."""
    if isinstance(protocol, ChunkedTrials):
        return int(protocol.signal_bytes())
    return int(protocol.n_trials) * 2 * int(n_samples(protocol)) * 8


def _memory_bytes() -> int | None:
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return None


def check_size(protocol: SimulationProtocol) -> None:
    """Refuse a protocol whose dataset cannot be assembled on this machine.

    The finished signal is assembled in memory (the shards, then one array): it must
    fit in half of this machine's physical memory.

    Raises
    ------
    ValueError
        Naming the trials, the size and the limit.
    """
    need = dataset_bytes(protocol)
    mem = _memory_bytes()
    if mem is not None and 2 * need > mem:
        raise ValueError(
            f"{protocol.n_trials} trials would make a {need / 1e9:.1f} GB dataset; it is "
            f"assembled in memory and this machine has {mem / 1e9:.1f} GB (limit: half of "
            "it). Use a coarser grid or fewer --runs"
        )


def _chunks(n: int, size: int) -> list[np.ndarray]:
    return [np.arange(s, min(n, s + size)) for s in range(0, n, size)]


def _shard_path(parts: Path, k: int) -> Path:
    return parts / f"chunk-{k:05d}.npz"


def kept_trials(out: str | os.PathLike[str]) -> int:
    """Trials in the finished shards of the generation of ``out``: what a rerun keeps.

    Counted on disk (a shard exists only once written whole), from the shard names and
    the chunking in the parts' manifest, so it is right even when an interruption lands
    between a shard's write and the progress report that follows it. 0 without a
    readable manifest.
    """
    parts = parts_dir(out)
    try:
        manifest = json.loads((parts / "manifest.json").read_text())
        chunks = _chunks(int(manifest["n_trials"]), int(manifest["chunk_size"]))
    except (OSError, ValueError, KeyError, TypeError):
        return 0
    n = 0
    for p in parts.glob("chunk-*.npz"):
        k = p.stem.removeprefix("chunk-")
        if k.isdigit() and int(k) < len(chunks):
            n += len(chunks[int(k)])
    return n


#: A shard's own arrays: the protocol fingerprint it was simulated for and its checksum.
_SHARD_FINGERPRINT = "__vibrissa_fingerprint__"
_SHARD_CHECKSUM = "__vibrissa_checksum__"


def _shard_checksum(arrays: dict[str, np.ndarray]) -> str:
    """SHA-256 over a shard's arrays: each one's name, dtype, shape and bytes, by name."""
    h = hashlib.sha256()
    for key in sorted(arrays):
        a = np.ascontiguousarray(arrays[key])
        h.update(f"{key}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _write_shard(parts: Path, k: int, result: dict[str, np.ndarray], fingerprint: str) -> None:
    """Write a shard with the fingerprint of its protocol and the checksum of its arrays."""
    meta = {
        _SHARD_FINGERPRINT: np.array(fingerprint),
        _SHARD_CHECKSUM: np.array(_shard_checksum(result)),
    }
    with atomic_path(_shard_path(parts, k), suffix=".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **result, **meta)


def _read_shard(path: Path, expected: np.ndarray, fingerprint: str) -> dict[str, np.ndarray] | None:
    """Load a shard; None (redo it) if it cannot be trusted.

    That is: unreadable (truncated), not the expected chunk, simulated for another
    protocol (its fingerprint differs: another seed, another grid) or changed since it
    was written (its checksum differs), or written without either (an older vibrissa).
    """
    try:
        with np.load(path) as z:
            data = {k: z[k] for k in z.files}
    except Exception:  # any unreadable shard (truncated zip, ...) is redone
        return None
    own = data.pop(_SHARD_FINGERPRINT, None)
    checksum = data.pop(_SHARD_CHECKSUM, None)
    if own is None or checksum is None or str(own) != fingerprint:
        return None
    if "index" not in data or not np.array_equal(data["index"], expected):
        return None
    if str(checksum) != _shard_checksum(data):
        return None
    return data


def _prepare_parts(protocol: SimulationProtocol, out: Path, chunk_size: int, restart: bool) -> Path:
    parts = parts_dir(out)
    manifest = {
        "fingerprint": protocol.fingerprint(),
        "n_trials": protocol.n_trials,
        "chunk_size": chunk_size,
        "protocol": protocol.to_dict(),
    }
    mpath = parts / "manifest.json"
    parts.mkdir(parents=True, exist_ok=True)
    if restart:  # discard everything but the lock file we hold
        for f in parts.iterdir():
            if f.name != ".lock":
                shutil.rmtree(f) if f.is_dir() else f.unlink()
    if mpath.exists():
        try:
            old = json.loads(mpath.read_text())
        except (OSError, ValueError):
            old = None
        if old is None or any(old.get(k) != manifest[k] for k in ("fingerprint", "chunk_size")):
            raise GenerationError(
                f"{parts} holds a partial generation of a different protocol or chunking; "
                "add --restart (restart=True) to discard it, or rerun the original command "
                "to resume it"
            )
    elif any(parts.glob("chunk-*.npz")):
        raise GenerationError(
            f"{parts} holds shards without a manifest; add --restart (restart=True) to discard them"
        )
    else:
        atomic_write_text(mpath, json.dumps(manifest, indent=2, default=str))
    return parts


@contextlib.contextmanager
def _exclusive(out: Path) -> Iterator[None]:
    """Hold an exclusive lock on the generation of ``out`` (``<out>.parts/.lock``)."""
    parts = parts_dir(out)
    parts.mkdir(parents=True, exist_ok=True)
    with open(parts / ".lock", "a+") as fh:
        try:
            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise GenerationError(
                f"another vibrissa generate is writing {out} (lock {parts / '.lock'} is held); "
                "wait for it to finish or stop it"
            ) from None
        try:
            yield
        finally:
            fcntl.flock(fh.fileno(), fcntl.LOCK_UN)


def _remove_stale_temporaries(out: Path) -> list[Path]:
    """Temporary files of a killed write of ``out`` or of its shards (we hold the lock)."""
    stale = list(out.parent.glob(f".{out.name}.*.tmp"))
    stale += list(parts_dir(out).glob(".chunk-*.tmp"))
    for f in stale:
        with contextlib.suppress(FileNotFoundError):
            f.unlink()
    return stale


def _run_chunk(protocol: SimulationProtocol, indices: np.ndarray) -> dict[str, np.ndarray]:
    # a protocol of another robot (ChunkedTrials, e.g. the Roomba's FloorProtocol) simulates
    # its own trials; the XY-robot protocols use the runner's
    if isinstance(protocol, ChunkedTrials):
        return protocol.simulate_trials(indices)
    return simulate_trials(protocol, indices)


class _Assembly:
    """The shards' arrays joined as ``np.concatenate`` joins them in chunk order.

    An array with a row per trial of its chunk (the signal, the labels) is copied into
    place as its shard comes in and the shard's copy let go, so the process holds the
    trials once (a full grid's signal is hundreds of MB), not once in shards and again
    joined. Any other array (a protocol of another robot may keep, say, a run's
    states of its own length) is kept per shard and joined at the end. Either way the
    result is ``np.concatenate``'s, to the byte (dtypes promoted as it would).
    """

    def __init__(self, chunks: list[np.ndarray]) -> None:
        self.starts = np.concatenate([[0], np.cumsum([len(c) for c in chunks])]).astype(int)
        self.keys: list[str] | None = None
        self.rows: dict[str, np.ndarray] = {}
        self.parts: dict[str, dict[int, np.ndarray]] = {}
        self.filled: set[int] = set()

    def add(self, k: int, shard: dict[str, np.ndarray]) -> None:
        """Take chunk ``k``'s arrays."""
        if self.keys is None:
            self.keys = list(shard)
        elif set(shard) != set(self.keys):
            raise GenerationError(
                f"shard {k} has the arrays {sorted(shard)}, the others {sorted(self.keys)}"
            )
        a, b = int(self.starts[k]), int(self.starts[k + 1])
        for key, part in shard.items():
            out = self.rows.get(key)
            fits = (
                part.ndim > 0
                and part.shape[0] == b - a
                and (out is None or part.shape[1:] == out.shape[1:])
            )
            if key in self.parts or not fits:
                self._keep_per_shard(key)
                self.parts[key][k] = part
                continue
            if out is None:
                # zeros, not empty: the pages are only mapped as the rows are written
                out = self.rows[key] = np.zeros((int(self.starts[-1]), *part.shape[1:]), part.dtype)
            dtype = np.result_type(out.dtype, part.dtype)
            if dtype != out.dtype:
                out = self.rows[key] = out.astype(dtype)
            out[a:b] = part
        self.filled.add(k)

    def _keep_per_shard(self, key: str) -> None:
        if key in self.parts:
            return
        out = self.rows.pop(key, None)
        self.parts[key] = (
            {}
            if out is None
            else {j: out[self.starts[j] : self.starts[j + 1]].copy() for j in self.filled}
        )

    def arrays(self) -> dict[str, np.ndarray]:
        """Every array joined (once every chunk is in)."""
        return {
            key: self.rows[key]
            if key in self.rows
            else np.concatenate([self.parts[key][j] for j in sorted(self.parts[key])])
            for key in self.keys or []
        }


def _local_results(
    protocol: SimulationProtocol, todo: list[tuple[int, np.ndarray]], workers: int
) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
    if workers <= 1:
        for k, idx in todo:
            yield k, _run_chunk(protocol, idx)
        return
    # leaving this (finished, failed or interrupted) kills the workers at once: chunks
    # still running are not waited for (their shards were never written)
    run = functools.partial(_run_chunk, protocol)
    for j, res in imap_unordered(run, [idx for _, idx in todo], workers):
        yield todo[j][0], res


def _dask_results(
    protocol: SimulationProtocol, todo: list[tuple[int, np.ndarray]], scheduler: str
) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
    from dask.distributed import Client, as_completed

    with Client(scheduler) as client:
        futs = client.map(_run_chunk, [protocol] * len(todo), [idx for _, idx in todo], pure=False)
        keys = {f.key: k for f, (k, _) in zip(futs, todo, strict=True)}
        for fut in as_completed(futs):
            yield keys[fut.key], fut.result()


def build_dataset(protocol: Protocol, results: dict[str, np.ndarray]) -> xr.Dataset:
    """Assemble simulated arrays (all trials, canonical order) into the Dataset schema."""
    specs = protocol.trials()
    n = len(specs)
    if results["signal"].shape[0] != n:
        raise ValueError(f"expected {n} trials, got {results['signal'].shape[0]}")
    fs = protocol.sensor.sample_rate_hz
    nb = int(round(protocol.window_s[0] * fs))
    time_s = (np.arange(n_samples(protocol)) - nb) / fs
    coords: dict[str, Any] = {
        "trial": np.arange(n),
        "channel": np.array(["x", "y"]),
        "time": ("time", time_s, {"units": "s", "long_name": "time from peak deflection"}),
    }
    per_trial: dict[str, np.ndarray] = {
        name: np.array([s.labels[name] for s in specs]) for name in protocol.label_names
    }
    for name in ("run", "direction", "set", "order"):
        per_trial[name] = np.array([getattr(s, name) for s in specs], dtype=np.int64)
    per_trial.update({name: results[name] for name in TRIAL_DIAGNOSTICS})
    for name, vals in per_trial.items():
        coords[name] = ("trial", vals, coordinate_attrs(name, vals))
    ds = xr.Dataset(
        {"signal": (("trial", "channel", "time"), results["signal"], {"units": "V"})},
        coords=coords,
        attrs={
            "sample_rate_hz": float(fs),
            "whisker": json.dumps(whisker_attrs(protocol), sort_keys=True),
            "robot": json.dumps(protocol.stage.to_dict(), sort_keys=True),
            "protocol": protocol.name,
            "protocol_params": json.dumps(protocol.to_dict(), sort_keys=True, default=str),
            "seed": int(protocol.seed),
            "vibrissa_version": __version__,
            "source": "simulated: vibrissa XY positioning robot (thesis 3.3)",
        },
    )
    return ds


def check_generation(
    protocol: SimulationProtocol,
    out: str | os.PathLike[str],
    workers: int | None = None,
    scheduler: str | None = None,
    chunk_size: int = 32,
) -> Path:
    """Check every argument of :func:`generate` before any work; return ``out`` as a Path.

    Raises
    ------
    ValueError
        Naming the argument: ``chunk_size`` or ``workers`` not a positive integer,
        a dataset too large for this machine (:func:`check_size`), an output that
        cannot be written (:func:`vibrissa._atomic.check_writable`: a directory, a
        file where a directory is needed, a place where nothing can be created), a
        ``scheduler`` without Dask installed (:func:`check_dask`).
    """
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1:
        raise ValueError(f"chunk_size must be a positive integer, got {chunk_size!r}")
    if scheduler is None:
        w = workers if workers is not None else (os.cpu_count() or 1)
        if isinstance(w, bool) or not isinstance(w, int) or w < 1:
            raise ValueError(f"workers must be a positive integer, got {workers!r}")
        if w > max_workers():
            raise ValueError(
                f"workers must be at most {max_workers()} ({WORKERS_PER_CORE} per core of "
                f"this machine; more processes only share the same cores), got {w}"
            )
    elif not isinstance(scheduler, str) or not SCHEDULER_ADDRESS.fullmatch(scheduler):
        raise ValueError(
            f"scheduler must be a Dask address like tcp://host:8786, got {scheduler!r}"
        )
    else:
        check_dask()
    check_size(protocol)
    return check_writable(out)


#: A Dask scheduler's address: ``tcp://host:port`` (the protocol may be left out).
SCHEDULER_ADDRESS = re.compile(r"([a-z]+://)?[^\s:/]+:\d+")


def check_dask() -> None:
    """Refuse a ``scheduler`` when Dask's distributed scheduler is not installed.

    Dask is the optional extra ``distributed``; this finds its modules without running
    them (only the small ``dask`` package itself is imported).

    Raises
    ------
    ValueError
        ``scheduler: needs the 'distributed' extra (pip install 'vibrissa[distributed]')``.
    """
    for name in ("dask", "distributed", "dask.distributed"):
        try:
            found = importlib.util.find_spec(name) is not None
        except (ImportError, ValueError):  # a parent missing, or a module without a spec
            found = False
        if not found:
            raise ValueError(
                "scheduler: needs the 'distributed' extra (pip install 'vibrissa[distributed]')"
            )


def max_workers() -> int:
    """Most local worker processes a generation accepts on this machine."""
    return WORKERS_PER_CORE * (os.cpu_count() or 1)


def generate(
    protocol: SimulationProtocol,
    out: str | os.PathLike[str],
    workers: int | None = None,
    scheduler: str | None = None,
    chunk_size: int = 32,
    restart: bool = False,
    progress: ProgressCallback | None = None,
    max_chunks: int | None = None,
) -> xr.Dataset | None:
    """Simulate every trial of ``protocol`` and write the dataset to ``out`` (NetCDF).

    Parameters
    ----------
    protocol
        The experiment.
    out
        Output file. Never left half-written; an existing file is only replaced
        when the new one is complete.
    workers
        Local worker processes (default: all cores). Ignored with ``scheduler``.
    scheduler
        Address of a Dask scheduler (``tcp://host:port``) to run the chunks on.
    chunk_size
        Trials per chunk (the unit of work and of resumption).
    restart
        Discard shards left by an interrupted run instead of resuming.
    progress
        Called as ``progress(done_trials, total_trials)``.
    max_chunks
        Stop after simulating this many new chunks without assembling the output
        (for tests of interruption); returns None then.

    Returns
    -------
    xarray.Dataset or None
        The dataset written, or None if stopped by ``max_chunks``.
    """
    out = check_generation(protocol, out, workers, scheduler, chunk_size)
    created = not parts_dir(out).exists()
    try:
        with _exclusive(out):
            _remove_stale_temporaries(out)
            return _generate_locked(
                protocol, out, workers, scheduler, chunk_size, restart, progress, max_chunks
            )
    except Exception:
        # a refused or failed run that kept no trial leaves nothing behind
        if created and not any(parts_dir(out).glob("chunk-*.npz")):
            shutil.rmtree(parts_dir(out), ignore_errors=True)
        raise


def _generate_locked(
    protocol: SimulationProtocol,
    out: Path,
    workers: int | None,
    scheduler: str | None,
    chunk_size: int,
    restart: bool,
    progress: ProgressCallback | None,
    max_chunks: int | None,
) -> xr.Dataset | None:
    from vibrissa.data import save_dataset

    parts = _prepare_parts(protocol, out, chunk_size, restart)
    fingerprint = protocol.fingerprint()
    chunks = _chunks(protocol.n_trials, chunk_size)
    done = _Assembly(chunks)
    redone = 0
    for k, idx in enumerate(chunks):
        p = _shard_path(parts, k)
        if p.exists():
            data = _read_shard(p, idx, fingerprint)
            if data is not None:
                done.add(k, data)
            else:
                redone += 1
    if redone:
        warnings.warn(
            f"{redone} kept shard(s) in {parts} could not be trusted (unreadable, changed "
            "since written, or simulated for another protocol) and are simulated again",
            stacklevel=3,
        )
    todo = [(k, idx) for k, idx in enumerate(chunks) if k not in done.filled]
    if max_chunks is not None:
        todo = todo[:max_chunks]
    n_done = sum(len(chunks[k]) for k in done.filled)
    if progress:
        progress(n_done, protocol.n_trials)
    if todo:
        if scheduler:
            it = _dask_results(protocol, todo, scheduler)
        else:
            w = workers if workers is not None else (os.cpu_count() or 1)
            it = _local_results(protocol, todo, min(w, len(todo)))
        for k, res in it:
            _write_shard(parts, k, res, fingerprint)
            done.add(k, res)
            n_done += len(chunks[k])
            if progress:
                progress(n_done, protocol.n_trials)
    if len(done.filled) < len(chunks):
        return None
    merged = done.arrays()
    if not np.array_equal(merged["index"], np.arange(protocol.n_trials)):
        raise GenerationError("shards do not cover every trial exactly once")
    ds = (
        protocol.build_dataset(merged)
        if isinstance(protocol, ChunkedTrials)
        else build_dataset(protocol, merged)
    )
    save_dataset(ds, out)
    shutil.rmtree(parts, ignore_errors=True)
    return ds
