"""The evaluation of CrunchBot's tactile SLAM (thesis 6.5.6) on sensor logs and arrays.

Pure: it reads :class:`~vibrissa.slam.log.SensorLog` objects and numpy arrays (never the
robot), so a real robot's logs are scored the same way. For every run and mapping mode it
runs the particle filter (:func:`vibrissa.slam.run_slam`); the three modes read the same
sensor log, because the robot's behaviour (the FSM of 6.5.3) never reads the map. It
scores each run's best map by eq. 6.3 against the smoothed ground truth, the filter's pose
estimate against the true pose (which the thesis could not measure), and gathers the
radial-distance errors of the obstacle whiskers, the floor-texture accuracy and the
classifiers' latencies.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from vibrissa.evaluate.jobs import SharedArrays, resolve_workers, run_jobs
from vibrissa.slam import (
    MODES,
    SensorLog,
    SlamSettings,
    map_error,
    random_map_error,
    run_slam,
    smooth_ground_truth,
)
from vibrissa.slam.error import UNEXPLORED
from vibrissa.slam.filter import apply_motion
from vibrissa.slam.log import fsm_outcome_counts

__all__ = [
    "SlamEvaluation",
    "dead_reckoning",
    "evaluate_crunchbot",
    "floor_texture_accuracy",
    "json_ready",
    "latency_stats",
    "radial_distance_errors_mm",
    "slam_job",
    "trajectory_error_mm",
]


def dead_reckoning(log: SensorLog) -> np.ndarray:
    """``(n_steps + 1, 3)`` poses from the start pose and the odometry alone."""
    out = np.empty((log.n_steps + 1, 3))
    out[0] = log.start_pose
    for t in range(log.n_steps):
        out[t + 1] = apply_motion(out[t], np.asarray(log.odometry[t], float))
    return out


def trajectory_error_mm(estimate: np.ndarray, true_pose: np.ndarray | None) -> float:
    """Mean over steps of the distance between estimated and true positions (mm).

    Raises
    ------
    ValueError
        ``estimate`` and ``true_pose`` differ in shape (``None``, a log without its true
        pose, has none).
    """
    est, true = np.asarray(estimate, float), np.asarray(true_pose, float)
    if est.shape != true.shape:
        raise ValueError(f"estimate {est.shape} and true pose {true.shape} differ in shape")
    return float(1000 * np.mean(np.hypot(*(est[:, :2] - true[:, :2]).T)))


def slam_job(
    arrays: Mapping[str, np.ndarray], log: SensorLog, mode: str, particles: int, seed: int
) -> dict[str, Any]:
    """One run in one mode: map error, trajectory error, best map and pose estimate."""
    run = run_slam(log, SlamSettings(n_particles=particles, mode=mode), seed=seed)
    best = run.best_map()
    truth = np.asarray(arrays["ground_truth"])
    mask = np.asarray(arrays["arena_mask"]) if "arena_mask" in arrays else None
    return {
        "map_error": map_error(best, truth),
        "map_error_arena": map_error(best, truth, mask) if mask is not None else math.nan,
        "trajectory_error_mm": trajectory_error_mm(run.pose_estimate, log.true_pose),
        "best_map": best.astype(np.float32),
        "pose_estimate": run.pose_estimate,
        "n_resamples": run.n_resamples,
    }


def radial_distance_errors_mm(
    estimated_m: Sequence[np.ndarray], true_m: Sequence[np.ndarray], names: Sequence[str]
) -> dict[str, Any]:
    """Std of estimate - truth (mm) per obstacle whisker, and ``combined`` over all whiskers.

    Over every contact of every run; NaN where a whisker never touched.
    """
    est = np.concatenate([np.asarray(a, float) for a in estimated_m])
    tru = np.concatenate([np.asarray(a, float) for a in true_m])
    err = 1000 * (est - tru)
    ok = np.isfinite(err)
    out: dict[str, Any] = {}
    for w, name in enumerate(names):
        e = err[ok[:, w], w]
        out[name] = float(np.std(e)) if e.size > 1 else math.nan
    out["combined"] = float(np.std(err[ok])) if ok.sum() > 1 else math.nan
    out["n_contacts"] = {name: int(ok[:, w].sum()) for w, name in enumerate(names)}
    return out


def floor_texture_accuracy(true_codes: np.ndarray, pred_codes: np.ndarray) -> float:
    """Fraction of floor-whisker steps on a known tile whose prediction is right.

    NaN: none on a tile.
    """
    t, p = np.asarray(true_codes), np.asarray(pred_codes)
    on = t >= 0
    return float(np.mean(p[on] == t[on])) if on.any() else math.nan


def latency_stats(latency_s: Mapping[str, np.ndarray]) -> dict[str, dict[str, Any]]:
    """Median and 99th percentile (ms) of each classifier's per-call times."""
    out = {}
    for name, lat in latency_s.items():
        a = np.asarray(lat, float)
        a = a[np.isfinite(a)]
        out[name] = {
            "median": float(1000 * np.median(a)) if a.size else math.nan,
            "p99": float(1000 * np.percentile(a, 99)) if a.size else math.nan,
            "n_calls": int(a.size),
        }
    return out


def json_ready(value: Any) -> Any:
    """``value`` with every NaN or infinite float (nested in dicts and lists) as ``None``."""
    if isinstance(value, Mapping):
        return {k: json_ready(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_ready(v) for v in value]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    return value


def _mean_std(values: Sequence[float]) -> dict[str, float]:
    a = np.asarray(values, float)
    return {"mean": float(a.mean()), "std": float(a.std(ddof=1)) if a.size > 1 else 0.0}


@dataclass(frozen=True)
class SlamEvaluation:
    """What :func:`evaluate_crunchbot` measured.

    The JSON-ready numbers and the arrays of the figures (never serialised).

    Attributes
    ----------
    map_error : dict
        Eq. 6.3 per mode (mean, std over runs) and of the ``random``, ``random_smoothed``
        and ``empty`` baselines.
    map_error_arena : dict
        The same over the arena's cells only (``None`` without an arena mask).
    trajectory_error_mm : dict
        Per mode and of ``dead_reckoning`` (mean, std over runs).
    per_run : list of dict
        Each run's errors and resamplings per mode.
    mean_maps : dict of str to numpy.ndarray
        Per mode, the best particle's map averaged over runs.
    estimates : dict of str to numpy.ndarray
        Per mode, the first run's pose estimate ``(n_steps + 1, 3)``.
    dead_reckoning : numpy.ndarray
        The first run's odometry-only poses.
    truth : numpy.ndarray
        The smoothed ground-truth map.
    """

    map_error: dict[str, Any]
    map_error_arena: dict[str, Any] | None
    trajectory_error_mm: dict[str, Any]
    per_run: list[dict[str, Any]]
    mean_maps: dict[str, np.ndarray]
    estimates: dict[str, np.ndarray]
    dead_reckoning: np.ndarray
    truth: np.ndarray


def evaluate_crunchbot(
    logs: Sequence[SensorLog],
    ground_truth: np.ndarray,
    *,
    particles: int = 100,
    seed: int = 0,
    modes: Sequence[str] = MODES,
    workers: int | None = None,
    progress: Callable[[int, int, str], None] | None = None,
    arena_mask: np.ndarray | None = None,
) -> SlamEvaluation:
    """SLAM in every mode over every run's log, spread over ``workers`` processes.

    Parameters
    ----------
    logs
        One sensor log per run, each with its ``true_pose``.
    ground_truth
        The arena's occupancy grid (1 occupied, 0 free), unsmoothed.
    particles
        Particles of each filter (> 0).
    seed
        Seeds the filters (run ``r`` uses the same filter seed in every mode) and the
        random-map baseline.
    arena_mask
        The map's cells that hold the arena (:func:`vibrissa.slam.error.arena_mask`): the
        errors are given over those cells too (``map_error_arena``).

    Returns
    -------
    dict
        ``map_error`` (per mode mean/std, ``random``: the cell-wise Bernoulli(0.5) map,
        ``random_smoothed``, ``empty``: a map that explored nothing, all 0.3),
        ``trajectory_error_mm`` (per mode and ``dead_reckoning``),
        ``per_run`` (JSON-ready), and the figures' arrays (see :class:`SlamEvaluation`).
    """
    if isinstance(particles, bool) or not isinstance(particles, int) or particles <= 0:
        raise ValueError(f"particles must be a positive integer, got {particles!r}")
    if not logs or any(lg.true_pose is None for lg in logs):
        raise ValueError("every run needs a sensor log with its true_pose")
    truth = smooth_ground_truth(np.asarray(ground_truth, float))
    seeds = [int(np.random.SeedSequence([seed, r]).generate_state(1)[0]) for r in range(len(logs))]
    jobs = [
        {"log": lg, "mode": m, "particles": particles, "seed": seeds[r]}
        for r, lg in enumerate(logs)
        for m in modes
    ]
    done = [0]

    def tick(i: int) -> None:
        done[0] += 1
        if progress:
            progress(done[0], len(jobs), f"run {i // len(modes)} {jobs[i]['mode']}")

    with SharedArrays(resolve_workers(workers)) as arrays:
        arrays.add("ground_truth", truth)
        if arena_mask is not None:
            arrays.add("arena_mask", np.asarray(arena_mask, bool))
        res = run_jobs(slam_job, jobs, arrays, on_done=tick)
    by = {m: [res[r * len(modes) + k] for r in range(len(logs))] for k, m in enumerate(modes)}
    rng = np.random.default_rng(np.random.SeedSequence([seed, 10**6]))
    dr = [trajectory_error_mm(dead_reckoning(lg), lg.true_pose) for lg in logs]
    arena_err = None
    if arena_mask is not None:
        mask = np.asarray(arena_mask, bool)
        arena_rng = np.random.default_rng(np.random.SeedSequence([seed, 10**6 + 1]))
        arena_err = {
            **{m: _mean_std([r["map_error_arena"] for r in by[m]]) for m in modes},
            "random": random_map_error(truth, arena_rng, mask=mask),
            "random_smoothed": random_map_error(truth, arena_rng, smooth=True, mask=mask),
            "empty": map_error(np.full(truth.shape, UNEXPLORED), truth, mask),
        }
    return SlamEvaluation(
        map_error={
            **{m: _mean_std([r["map_error"] for r in by[m]]) for m in modes},
            "random": random_map_error(truth, rng),
            "random_smoothed": random_map_error(truth, rng, smooth=True),
            "empty": map_error(np.full(truth.shape, UNEXPLORED), truth),
        },
        map_error_arena=arena_err,
        trajectory_error_mm={
            **{m: _mean_std([r["trajectory_error_mm"] for r in by[m]]) for m in modes},
            "dead_reckoning": _mean_std(dr),
        },
        per_run=[
            {
                "run": r,
                "n_steps": lg.n_steps,
                **{
                    m: {
                        "map_error": by[m][r]["map_error"],
                        "map_error_arena": by[m][r]["map_error_arena"],
                        "trajectory_error_mm": by[m][r]["trajectory_error_mm"],
                        "n_resamples": by[m][r]["n_resamples"],
                    }
                    for m in modes
                },
                "dead_reckoning_error_mm": dr[r],
                "fsm": {
                    **fsm_outcome_counts(lg.state),
                    "hit_2_with_surface_angle": int(
                        np.isfinite(np.asarray(lg.surface_angle_rad)[lg.state == "HIT_2"]).sum()
                    ),
                },
            }
            for r, lg in enumerate(logs)
        ],
        mean_maps={m: np.mean([r["best_map"] for r in by[m]], axis=0) for m in modes},
        estimates={m: by[m][0]["pose_estimate"] for m in modes},
        dead_reckoning=dead_reckoning(logs[0]),
        truth=truth,
    )


def sum_outcomes(per_run: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The runs' FSM outcome counts (``fsm.outcome_counts``), summed.

    Nested counts (``abort_after``, ``fwd2_ends``) are summed key by key; ``runs`` says
    how many runs.
    """

    def add(a: Any, b: Any) -> Any:
        if isinstance(a, Mapping):
            other = b if isinstance(b, Mapping) else {}
            return {k: add(a[k], other.get(k, 0)) for k in a}
        return a + b

    total: dict[str, Any] = {}
    for r in per_run:
        total = add(r, total)
    return {**total, "runs": len(per_run)}


def _order_holds(err: Mapping[str, float]) -> bool:
    return bool(err["template"] < err["geometric"] < err["blob"])


def ordering_over_runs(
    per_run: Mapping[str, Mapping[str, Sequence[float]]],
    grid: Mapping[str, Any],
    arena: Mapping[str, Any],
) -> dict[str, Any]:
    """Whether the thesis' ordering and the baselines hold on the means and run by run.

    Parameters
    ----------
    per_run
        ``{"grid" | "arena": {mode: [error per run]}}``.
    grid, arena
        The map errors over the grid and over the arena: per mode ``{"mean", "std"}`` and
        the ``empty`` and ``random`` baselines (``arena`` may be empty: not measured).

    Returns
    -------
    dict
        ``runs_template_lt_geometric_lt_blob``: the fraction of runs whose own errors are
        in the thesis' order (over the grid); ``arena``: the order over the arena's cells
        (on the means, and that fraction); ``beats_empty`` and ``beats_random``: per
        region and mode, whether the mean is below the baseline and the fraction of runs
        that are.
    """
    modes = ("blob", "geometric", "template")

    def fraction(region: str) -> float | None:
        rows = per_run.get(region, {})
        if not rows or any(not rows.get(m) for m in modes):
            return None
        n = len(rows["blob"])
        return sum(_order_holds({m: rows[m][i] for m in modes}) for i in range(n)) / n

    def below(region: str, err: Mapping[str, Any], base: str) -> dict[str, Any]:
        if not err or base not in err:
            return {}
        out = {}
        for m in modes:
            vals = [x for x in per_run[region][m] if x is not None and math.isfinite(x)]
            out[m] = {
                "mean_below": bool(err[m]["mean"] < err[base]),
                "runs_below": sum(x < err[base] for x in vals) / len(vals) if vals else None,
            }
        return out

    out: dict[str, Any] = {"runs_template_lt_geometric_lt_blob": fraction("grid")}
    if arena:
        means = {m: arena[m]["mean"] for m in modes}
        out["arena"] = {
            "template_lt_geometric_lt_blob": _order_holds(means),
            "order": sorted(means, key=means.__getitem__),
            "runs_template_lt_geometric_lt_blob": fraction("arena"),
        }
    for base in ("empty", "random"):
        out[f"beats_{base}"] = {
            "grid": below("grid", grid, base),
            "arena": below("arena", arena, base),
        }
    return out
