"""CrunchBot's tactile-SLAM session (thesis 6.5.6) as a protocol: training, then runs.

The real-time classifiers are trained once per seed (``train(seed, quick)``), then the
robot runs ``n_runs`` times for ``seconds`` of robot time in the ``slam`` arena
(``simulate_run(arena, seconds, seed, classifiers=...) -> RunRecord``), and once more in
the tiled arena (``texture_arena``) for the floor-texture trace of figure 6.11. Each run
is one chunk of the resumable, parallel generation
(:func:`vibrissa.experiments.generate.generate`: locks, atomic shards, local workers or a
Dask cluster). What a run keeps: its sensor log (one row per FSM step), the true poses,
the floor textures true and predicted, the true contact distances, the classifiers'
latencies and the wall time; the 2 kHz Hall signals only of run ``hall_run`` (for the
figure; all twenty would be gigabytes).

The robot is a parameter. By default it is the simulated physical robot
(:func:`vibrissa.robots.crunchbot.robot.run_crunchbot`, trained by
:func:`vibrissa.robots.crunchbot.training.train_classifiers`); tests and the viewer may
pass the exact-contact oracle (:func:`vibrissa.robots.crunchbot.synthetic.synthetic_record`,
synthetic Hall signals, no classifiers), and the reproduction then says so:
:attr:`CrunchbotProtocol.robot_kind` is ``"synthetic-oracle"`` in ``meta.robot`` and in its
report.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import xarray as xr

from vibrissa import __version__
from vibrissa._validate import positive
from vibrissa.experiments.contract import ChunkedTrials, SelfGenerating
from vibrissa.experiments.streams import TRIALS, stream
from vibrissa.robots.crunchbot import fsm
from vibrissa.robots.crunchbot.arena import Arena, get_arena
from vibrissa.robots.crunchbot.record import (
    CLASSIFIERS,
    N_OBSTACLE_WHISKERS,
    WHISKER_NAMES,
    RunRecord,
)
from vibrissa.slam.log import SensorLog, WhiskerLayout

__all__ = [
    "ROBOT_KINDS",
    "CrunchbotProtocol",
    "crunchbot_protocol",
    "default_robot",
    "hall_run",
    "robot_kind",
    "run_kinds",
    "sensor_logs",
]

#: What a protocol's robot is: the simulated physical robot, the exact-contact oracle
#: with synthetic signals, or a callable the caller passed.
ROBOT_KINDS = ("simulated-physics", "synthetic-oracle", "custom")
_PHYSICS = ("vibrissa.robots.crunchbot.robot", "run_crunchbot")
_SYNTHETIC = ("vibrissa.robots.crunchbot.synthetic", "synthetic_record")
#: The classifiers trained in this process, by (train function, seed, quick).
_TRAINED: dict[tuple[str, int, bool], Any] = {}


def default_robot() -> tuple[Callable[..., RunRecord], Callable[..., Any]]:
    """``(simulate_run, train)``: the simulated physical robot and its training."""
    from vibrissa.robots.crunchbot.robot import run_crunchbot
    from vibrissa.robots.crunchbot.training import train_classifiers

    return run_crunchbot, train_classifiers


def _qualname(f: Callable | None) -> str | None:
    return None if f is None else f"{f.__module__}:{f.__qualname__}"


@dataclass(frozen=True)
class CrunchbotProtocol(SelfGenerating, ChunkedTrials):
    """The tactile-SLAM session of 6.5.6.

    Parameters
    ----------
    n_runs
        Runs in ``arena`` (thesis: 20).
    seconds
        Robot time of each (thesis: 6 minutes).
    arena
        A preset name or an arena file (:func:`vibrissa.robots.crunchbot.get_arena`).
    texture_arena
        Where the extra floor-texture run drives (``None``: no such run).
    texture_seconds
        Its robot time.
    quick_training
        ``train(seed, quick=True)``: the classifiers' small training set.
    hall_run
        The run whose 2 kHz Hall signals are kept.
    seed
        Session seed: run ``i`` is seeded from stream ``(TRIALS, i)``.
    simulate_run, train
        The robot (see the module docstring; ``None``: :func:`default_robot`).
    """

    n_runs: int = 20
    seconds: float = 360.0
    arena: str = "slam"
    texture_arena: str | None = "tiles"
    texture_seconds: float = 120.0
    quick_training: bool = False
    hall_run: int = 0
    seed: int = 0
    simulate_run: Callable[..., RunRecord] | None = field(default=None, compare=False)
    train: Callable[..., Any] | None = field(default=None, compare=False)
    name: str = "crunchbot-slam"

    def __post_init__(self) -> None:
        for key in ("n_runs", "seed", "hall_run"):
            value = getattr(self, key)
            low = 1 if key == "n_runs" else 0
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise ValueError(f"{key} must be an integer >= {low}, got {value!r}")
        positive("seconds", self.seconds)
        positive("texture_seconds", self.texture_seconds)
        self.arenas()  # unknown arena files, bad arenas: one line now
        if self.simulate_run is None:
            run, train = default_robot()
            object.__setattr__(self, "simulate_run", run)
            if self.train is None:
                object.__setattr__(self, "train", train)

    # ------------------------------------------------------------------ identity
    @property
    def robot_kind(self) -> str:
        """One of :data:`ROBOT_KINDS`."""
        return robot_kind(self.simulate_run)

    def arenas(self) -> tuple[Arena, Arena | None]:
        """The SLAM arena and the floor-texture arena (``None``: none)."""
        tex = get_arena(self.texture_arena) if self.texture_arena else None
        return get_arena(self.arena), tex

    @property
    def n_trials(self) -> int:
        """Runs: the SLAM runs and the floor-texture run."""
        return self.n_runs + (1 if self.texture_arena else 0)

    #: One run per chunk.
    chunk_size = 1

    def to_dict(self) -> dict[str, Any]:
        """Every parameter as plain values (the robot by its function's name)."""
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        d["simulate_run"], d["train"] = _qualname(self.simulate_run), _qualname(self.train)
        d["robot"] = self.robot_kind
        return d

    def fingerprint(self) -> str:
        """Hash of every parameter (and the robot) that affects the runs."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()[:16]

    def signal_bytes(self) -> int:
        """Bytes of the finished dataset.

        About 200 bytes an FSM step, 2 per robot second, plus the kept Hall run (2 kHz, 12
        float32 and a pose).
        """
        steps = 3 * (self.n_runs * self.seconds + self.texture_seconds)
        return int(200 * steps + self.seconds * 2000 * (48 + 24 + 8))

    def seconds_per_trial(self) -> float:
        """Robot seconds of a run (the wall time depends on the robot)."""
        return float(self.seconds)

    # ------------------------------------------------------------------ simulation
    def run_seed(self, index: int) -> int:
        """The seed run ``index`` passes to the robot."""
        return int(stream(self.seed, TRIALS, index).generate_state(1)[0] % (2**31))

    def radial_fit_residuals_mm(self) -> dict[str, float] | None:
        """Per obstacle whisker, the residual std (mm) of the radial-distance line.

        The residual standard deviation of the radial distance line on its own training
        contacts: the quantity of the thesis' table in 6.5.6.2 ("standard error for the
        regression", figure 6.12). ``None`` for a robot without trained radial
        classifiers.
        """
        clf = self.classifiers() if self.train is not None else None
        radial = getattr(clf, "radial", None)
        if not radial or not all(hasattr(r, "residual_std_m_") for r in radial):
            return None
        return {WHISKER_NAMES[w]: 1e3 * float(r.residual_std_m_) for w, r in enumerate(radial)}

    def classifiers(self) -> Any:
        """The trained real-time classifiers (``None`` without training).

        Trained once per process, seed and ``quick_training``.
        """
        if self.train is None:
            return None
        key = (str(_qualname(self.train)), self.seed, self.quick_training)
        if key not in _TRAINED:
            _TRAINED[key] = self.train(self.seed, quick=self.quick_training)
        return _TRAINED[key]

    def simulate(self, index: int, progress: Callable[[float], None] | None = None) -> RunRecord:
        """Run ``index``: a SLAM run (``index < n_runs``) or the floor-texture run."""
        slam, tex = self.arenas()
        arena, seconds = (
            (slam, self.seconds) if index < self.n_runs else (tex, self.texture_seconds)
        )
        kwargs: dict[str, Any] = {}
        clf = self.classifiers()
        if clf is not None:
            kwargs["classifiers"] = clf
        if progress is not None:
            kwargs["progress"] = progress
        assert self.simulate_run is not None
        return self.simulate_run(arena, seconds, self.run_seed(index), **kwargs)

    def simulate_trials(self, indices: Sequence[int] | np.ndarray) -> dict[str, np.ndarray]:
        """Simulate runs ``indices``; their per-step arrays flattened along the first axis.

        One row per step, counts in ``n_steps``, so chunks concatenate.
        """
        parts = [
            _flatten(self.simulate(int(i)), int(i) == self.hall_run, self.textures())
            for i in indices
        ]
        out = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
        out["index"] = np.asarray(indices, dtype=np.int64)
        return out

    def textures(self) -> tuple[str, ...]:
        """Floor textures of the arenas (the texture axis of the stored likelihoods)."""
        names = {t for a in self.arenas() if a is not None for row in a.tiles for t in row}
        return tuple(sorted(names))

    #: Its chunks may run on a Dask cluster (``scheduler``).
    accepts_scheduler: ClassVar[bool] = True

    def generate_dataset(
        self,
        path: Path,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        scheduler: str | None = None,
        **kwargs: Any,
    ) -> xr.Dataset:
        """Train, then run every chunk into ``path``.

        Training happens in this process, so forked workers share it; the chunks run with
        :func:`~vibrissa.experiments.generate.generate`.
        """
        from vibrissa.experiments.generate import generate

        self.classifiers()
        ds = generate(
            self, path, workers=workers, scheduler=scheduler, chunk_size=1, progress=progress
        )
        assert ds is not None
        return ds

    def build_dataset(self, merged: dict[str, np.ndarray]) -> xr.Dataset:
        """Assemble the runs' flattened arrays into a Dataset, one trial per run.

        ``signal`` is the odometry ``(trial, channel, time)`` with ``time`` the FSM step
        (padded with zeros beyond a run's ``n_steps``); every other per-step array is a
        variable over ``(trial, time, ...)`` padded with NaN (states and textures: -1).
        """
        n_steps = merged["n_steps"].astype(int)
        t_max = int(n_steps.max())

        def per_step(key: str, fill: Any, extra: int = 0) -> np.ndarray:
            a = merged[key]
            out = np.full((len(n_steps), t_max + extra, *a.shape[1:]), fill, dtype=a.dtype)
            s0 = np.concatenate([[0], np.cumsum(n_steps + extra)])
            for r in range(len(n_steps)):
                out[r, : n_steps[r] + extra] = a[s0[r] : s0[r + 1]]
            return out

        def per_call(c: str) -> np.ndarray:
            counts = merged[f"n_latency_{c}"].astype(int)
            s0 = np.concatenate([[0], np.cumsum(counts)])
            out = np.full((len(counts), max(int(counts.max()), 1)), np.nan)
            for r in range(len(counts)):
                out[r, : counts[r]] = merged[f"latency_{c}"][s0[r] : s0[r + 1]]
            return out

        slam, tex = self.arenas()
        kinds = run_kinds(self.n_runs, self.n_trials)
        data: dict[str, Any] = {
            "signal": (
                ("trial", "channel", "time"),
                per_step("odometry", 0.0).transpose(0, 2, 1),
                {"units": "m, m, rad", "long_name": "odometry increment of each step"},
            ),
            "state": (
                ("trial", "time"),
                per_step("state", -1),
                {"long_name": "FSM state (index into attrs['states'], -1 none)"},
            ),
            "contact": (("trial", "time", "whisker"), per_step("contact", -1)),
            "radial_distance_m": (
                ("trial", "time", "whisker"),
                per_step("radial_distance_m", np.nan),
                {"units": "m"},
            ),
            "contact_true_m": (
                ("trial", "time", "whisker"),
                per_step("contact_true_m", np.nan),
                {"units": "m"},
            ),
            "surface_angle_rad": (
                ("trial", "time"),
                per_step("surface_angle_rad", np.nan),
                {"units": "rad"},
            ),
            "step_end_s": (
                ("trial", "time"),
                per_step("step_end_s", np.nan),
                {"units": "s", "long_name": "robot time at the step's end"},
            ),
            "floor_loglik": (
                ("trial", "time", "floor_whisker", "texture"),
                per_step("floor_loglik", np.nan),
            ),
            "floor_texture_true": (("trial", "time", "floor_whisker"), per_step("floor_true", -1)),
            "floor_texture_pred": (("trial", "time", "floor_whisker"), per_step("floor_pred", -1)),
            "true_pose": (
                ("trial", "pose_row", "pose"),
                per_step("true_pose", np.nan, 1),
                {"long_name": "true map-frame pose before each step and after the last"},
            ),
            "start_pose": (("trial", "pose"), merged["start_pose"]),
            "hall_v": (
                ("hall_time", "whisker_name", "axis"),
                merged["hall_v"],
                {"units": "V", "long_name": f"Hall outputs of run {self.hall_run}"},
            ),
            "hall_pose": (("hall_time", "pose"), merged["hall_pose"]),
            "hall_step_start": (("hall_step",), merged["hall_step_start"]),
            "ground_truth": (("gx", "gy"), slam.occupancy_grid()),
        }
        for c in CLASSIFIERS:
            data[f"latency_{c}_s"] = (("trial", f"call_{c}"), per_call(c), {"units": "s"})
        per_trial = {
            "run_seed": np.array([self.run_seed(i) for i in range(len(n_steps))]),
            "kind": np.array(kinds),
            "n_steps": n_steps,
            "wall_seconds": merged["wall_seconds"],
            "seconds": merged["seconds"],
            "sample_rate_hz": merged["sample_rate_hz"],
        }
        coords: dict[str, Any] = {
            "trial": np.arange(len(n_steps)),
            "channel": np.array(["forward_m", "left_m", "rotation_rad"]),
            "time": (
                "time",
                np.arange(t_max, dtype=float),
                {"units": "step", "long_name": "FSM step"},
            ),
            "pose": np.array(["x_m", "y_m", "heading_rad"]),
            "whisker": np.array(WHISKER_NAMES[:N_OBSTACLE_WHISKERS]),
            "whisker_name": np.array(WHISKER_NAMES),
            "axis": np.array(["x", "y"]),
            "floor_whisker": np.array(WHISKER_NAMES[N_OBSTACLE_WHISKERS:]),
            "texture": np.array(self.textures() or ("none",)),
            **{name: ("trial", vals) for name, vals in per_trial.items()},
        }
        lay = {
            k: np.asarray(merged[k][0]).tolist()
            for k in ("layout_base_m", "layout_angle_rad", "layout_length_m")
        }
        lay["body_radius_m"] = float(merged["layout_body_radius_m"][0])
        # runs in an arena without tiles report no floor whiskers: take one that does
        floor = [f for f in merged["floor_whisker_m"] if np.isfinite(f).all()]
        lay["floor_whisker_m"] = np.asarray(floor[0]).tolist() if floor else None
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "sample_rate_hz": 1.0 / fsm.FsmSettings().step_s,
                "protocol": self.name,
                "protocol_params": json.dumps(self.to_dict(), sort_keys=True, default=str),
                "robot": self.robot_kind,
                "states": json.dumps(fsm.STATES),
                "textures": json.dumps(self.textures()),
                "layout": json.dumps(lay),
                "arena": json.dumps(_arena_dict(slam)),
                "texture_arena": json.dumps(_arena_dict(tex) if tex else None),
                "hall_sample_rate_hz": float(merged["sample_rate_hz"][self.hall_run]),
                "radial_fit_residual_mm": json.dumps(self.radial_fit_residuals_mm()),
                "seed": int(self.seed),
                "vibrissa_version": __version__,
                "source": f"simulated: CrunchBot tactile SLAM runs (thesis 6.5), robot "
                f"{self.robot_kind}",
            },
        )


def run_kinds(n_runs: int, n_trials: int) -> list[str]:
    """``"slam"`` for the SLAM runs, ``"texture"`` for the floor-texture run."""
    return ["slam"] * n_runs + ["texture"] * (n_trials - n_runs)


def _arena_dict(a: Arena) -> dict[str, Any]:
    return {
        "name": a.name,
        "size_m": a.size_m,
        "tile_m": a.tile_m,
        "tiles": [list(r) for r in a.tiles],
        "obstacles": [dataclasses.asdict(o) for o in a.obstacles],
        "start": dataclasses.asdict(a.start),
    }


def _codes(names: np.ndarray, vocabulary: Sequence[str]) -> np.ndarray:
    lookup = {t: i for i, t in enumerate(vocabulary)}
    return np.vectorize(lambda s: lookup.get(str(s), -1), otypes=[np.int8])(names)


def _flatten(rec: RunRecord, keep_hall: bool, textures: tuple[str, ...]) -> dict[str, np.ndarray]:
    """One run as arrays with a step (or sample, or call) first axis."""
    log = rec.log
    t = log.n_steps
    ll = np.full((t, 2, max(len(textures), 1)), np.nan)
    if log.floor_loglik is not None and log.textures:
        for k, name in enumerate(log.textures):
            if name in textures:
                ll[:, :, textures.index(name)] = log.floor_loglik[:, :, k]
    lay = log.layout
    floor_m = log.floor_whisker_m if log.floor_whisker_m is not None else np.full((2, 2), np.nan)
    hall = rec.hall_v if keep_hall else np.empty((0, 6, 2), np.float32)
    out = {
        "n_steps": np.array([t]),
        "state": _codes(np.asarray(log.state), fsm.STATES),
        "odometry": np.asarray(log.odometry, float),
        "contact": np.asarray(log.contact, np.int8),
        "radial_distance_m": np.asarray(log.radial_distance_m, float),
        "surface_angle_rad": np.asarray(log.surface_angle_rad, float),
        "floor_loglik": ll,
        "true_pose": np.asarray(log.true_pose, float),
        "start_pose": np.asarray(log.start_pose, float)[None],
        "contact_true_m": np.asarray(rec.contact_true_m, float),
        "step_end_s": np.asarray(rec.step_start, float)[1:] / rec.sample_rate_hz,
        "floor_true": _codes(rec.floor_texture_true, textures),
        "floor_pred": _codes(rec.floor_texture_pred, textures),
        "wall_seconds": np.array([rec.wall_seconds]),
        "seconds": np.array([rec.seconds]),
        "sample_rate_hz": np.array([rec.sample_rate_hz]),
        "hall_v": np.asarray(hall, np.float32),
        "hall_pose": np.asarray(rec.pose if keep_hall else np.empty((0, 3)), float),
        "hall_step_start": np.asarray(rec.step_start if keep_hall else [], np.int64),
        "layout_base_m": np.asarray(lay.base_m, float)[None],
        "layout_angle_rad": np.asarray(lay.angle_rad, float)[None],
        "layout_length_m": np.asarray(lay.length_m, float)[None],
        "layout_body_radius_m": np.array([lay.body_radius_m]),
        "floor_whisker_m": np.asarray(floor_m, float)[None],
    }
    for c in CLASSIFIERS:
        lat = np.asarray(rec.latency_s.get(c, np.empty(0)), float).ravel()
        out[f"latency_{c}"] = lat
        out[f"n_latency_{c}"] = np.array([lat.size])
    return out


def sensor_logs(ds: xr.Dataset, kind: str = "slam") -> list[SensorLog]:
    """The :class:`SensorLog` of each run of ``kind`` (``"slam"`` or ``"texture"``)."""
    lay = json.loads(ds.attrs["layout"])
    layout = WhiskerLayout(
        np.array(lay["layout_base_m"]),
        np.array(lay["layout_angle_rad"]),
        np.array(lay["layout_length_m"]),
        lay["body_radius_m"],
    )
    states = np.array(json.loads(ds.attrs["states"]))
    textures = tuple(json.loads(ds.attrs["textures"]))
    logs = []
    for r in np.flatnonzero(ds["kind"].values == kind):
        t = int(ds["n_steps"].values[r])
        ll = ds["floor_loglik"].values[r, :t]
        has_floor = bool(textures) and np.isfinite(ll).all()
        logs.append(
            SensorLog(
                layout=layout,
                state=states[ds["state"].values[r, :t].astype(int)],
                odometry=ds["signal"].values[r, :, :t].T.copy(),
                contact=ds["contact"].values[r, :t].astype(bool),
                radial_distance_m=ds["radial_distance_m"].values[r, :t],
                surface_angle_rad=ds["surface_angle_rad"].values[r, :t],
                start_pose=ds["start_pose"].values[r],
                floor_loglik=ll if has_floor else None,
                floor_whisker_m=np.array(lay["floor_whisker_m"]) if has_floor else None,
                textures=textures if has_floor else (),
                true_pose=ds["true_pose"].values[r, : t + 1],
            )
        )
    return logs


def hall_run(ds: xr.Dataset) -> dict[str, np.ndarray]:
    """The kept run's 2 kHz arrays: ``time_s``, ``hall_v``, ``pose``, ``step_start``."""
    fs = float(ds.attrs["hall_sample_rate_hz"])
    n = ds.sizes["hall_time"]
    return {
        "time_s": np.arange(n) / fs,
        "hall_v": ds["hall_v"].values,
        "pose": ds["hall_pose"].values,
        "step_start": ds["hall_step_start"].values,
    }


def crunchbot_protocol(quick: bool = False, **overrides: Any) -> CrunchbotProtocol:
    """The thesis' session (20 runs of 6 minutes) or, ``quick``, 3 runs of 6 minutes."""
    base: dict[str, Any] = (
        {"n_runs": 3, "seconds": 360.0, "texture_seconds": 30.0, "quick_training": True}
        if quick
        else {}
    )
    return CrunchbotProtocol(**{**base, **overrides})


def robot_kind(run: Callable | None) -> str:
    """Which of :data:`ROBOT_KINDS` a ``simulate_run`` callable is."""
    q = _qualname(run)
    return (
        "simulated-physics"
        if q == ":".join(_PHYSICS)
        else "synthetic-oracle"
        if q == ":".join(_SYNTHETIC)
        else "custom"
    )
