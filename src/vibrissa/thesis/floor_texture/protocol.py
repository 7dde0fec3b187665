"""The Roomba floor-texture session of thesis 6.2 as a declarative protocol.

Four floors x three movement conditions (clockwise, anticlockwise, 'spot') x 4
trials of 16 s recorded at 2 kHz (6.2.1: "Each 16-second trial was then repeated 4
times for each of the behavioural conditions"). With ``n_seeds`` > 1 the whole session
is repeated with the seeds ``seed`` .. ``seed + n_seeds - 1`` (coordinate ``seed`` of
each trial): session ``k`` is exactly the one-session protocol of seed ``seed + k``
(its own floor sheets, robot motion and sensor noise). :class:`FloorProtocol` plugs into
:func:`vibrissa.experiments.generate.generate` with its own
:meth:`~FloorProtocol.simulate_trials` and :meth:`~FloorProtocol.build_dataset`: the
same chunked, resumable, seeded generation as the XY-robot protocols.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import xarray as xr

from vibrissa import __version__
from vibrissa._validate import positive
from vibrissa.data.dataset import signal_coords
from vibrissa.experiments.contract import ChunkedTrials
from vibrissa.experiments.streams import SURFACES, TRIALS, stream
from vibrissa.robots.roomba import CONDITIONS, Roomba, base_motion, run_floor_trial, tip_path
from vibrissa.whisker.floors import FLOORS, floor_spec, make_floor
from vibrissa.whisker.geometry import PRESETS, preset
from vibrissa.whisker.hall import HallSensor, HallSettings, steps_per_sample
from vibrissa.whisker.rod import RodModel

__all__ = ["FLOOR_DIAGNOSTICS", "FloorProtocol", "FloorTrialSpec", "floor_protocol", "tip_paths"]

#: Per-trial quantities recorded besides the signal (see
#: :class:`vibrissa.robots.roomba.FloorTrial`).
FLOOR_DIAGNOSTICS = (
    "contact_fraction",
    "moving_fraction",
    "saturated",
    "rail_fraction",
    "catches",
    "catch_fraction",
    "contact_force_n",
)
_INTEGER_DIAGNOSTICS = {"saturated": bool, "catches": np.int64}

#: Stream keys of the floors' sheets start here, clear of the chapter-5 textures'.
_FLOOR_STREAM_BASE = 100


@dataclass(frozen=True)
class FloorTrialSpec:
    """One trial: ``floor``, ``condition``, its repetition ``trial`` (1-based), ``session``.

    ``session`` counts the sessions from 0 (seed ``seed + session``); ``within`` is the
    trial's index inside its session (its random stream's key).
    """

    index: int
    floor: str
    condition: str
    trial: int
    session: int = 0
    within: int = 0


def _sensor() -> HallSettings:
    # 2 kHz (6.2.1); the MLX90333 is re-programmable "to best suit the current
    # experiment" (3.2.3): full range for a 30 mm push at r = 150 mm, twice the floor's
    # static preload, so stick-slip on carpet stays mostly within range
    return HallSettings(sample_rate_hz=2000.0, calibration_mm=(150.0, 30.0))


@dataclass(frozen=True)
class FloorProtocol(ChunkedTrials):
    """The Roomba session (thesis 6.2).

    Parameters
    ----------
    floors : tuple of str
        Floor presets (:data:`vibrissa.whisker.floors.FLOORS`).
    conditions : tuple of str
        Movement conditions (:data:`vibrissa.robots.roomba.CONDITIONS`).
    trials_per_condition : int
        Repetitions of each (floor, condition) (thesis: 4).
    duration_s : float
        Seconds per trial (thesis: 16).
    whisker : str
        Whisker preset (thesis 6.1: a SCRATCHbot whisker).
    n_elements : int
        Rod discretisation.
    dt_s : float
        Internal time step (s); must divide the sample period.
    sensor : HallSettings
        The sensor's set-up (2 kHz).
    roomba : Roomba
        The base and the mounting.
    seed : int
        Seed of everything random in the (first) session.
    n_seeds : int
        Sessions: the session repeated with seeds ``seed`` .. ``seed + n_seeds - 1``.
    """

    floors: tuple[str, ...] = tuple(FLOORS)
    conditions: tuple[str, ...] = CONDITIONS
    trials_per_condition: int = 4
    duration_s: float = 16.0
    whisker: str = "scratchbot"
    n_elements: int = 28
    dt_s: float = 2.5e-4
    sensor: HallSettings = field(default_factory=_sensor)
    roomba: Roomba = field(default_factory=Roomba)
    seed: int = 0
    n_seeds: int = 1
    name: str = "floor-texture"

    def __post_init__(self) -> None:
        if not self.floors:
            raise ValueError("floors: at least one floor texture is needed")
        for f in self.floors:
            floor_spec(f)
        if len(set(self.floors)) != len(self.floors):
            raise ValueError(f"floors: each floor texture once, got {list(self.floors)}")
        if not self.conditions or any(c not in CONDITIONS for c in self.conditions):
            raise ValueError(
                f"conditions must be a non-empty subset of {CONDITIONS}, got {self.conditions!r}"
            )
        if len(set(self.conditions)) != len(self.conditions):
            raise ValueError(f"conditions: each condition once, got {list(self.conditions)}")
        if (
            isinstance(self.trials_per_condition, bool)
            or not isinstance(self.trials_per_condition, int)
            or self.trials_per_condition < 1
        ):
            raise ValueError(
                "trials_per_condition must be a positive integer, got "
                f"{self.trials_per_condition!r}"
            )
        positive("duration_s", self.duration_s)
        if self.whisker not in PRESETS:
            raise ValueError(f"unknown whisker preset {self.whisker!r}")
        if not isinstance(self.sensor, HallSettings):
            raise TypeError(f"sensor must be a HallSettings, got {type(self.sensor).__name__}")
        steps_per_sample(self.dt_s, self.sensor.sample_rate_hz)
        self.sensor.calibration_point(preset(self.whisker))
        if (
            isinstance(self.seed, bool)
            or not isinstance(self.seed, int | np.integer)
            or self.seed < 0
        ):
            raise ValueError(f"seed must be a non-negative integer, got {self.seed!r}")
        if (
            isinstance(self.n_seeds, bool)
            or not isinstance(self.n_seeds, int | np.integer)
            or self.n_seeds < 1
        ):
            raise ValueError(f"n_seeds must be a positive integer, got {self.n_seeds!r}")

    # ------------------------------------------------------------------ trials
    label_names = ("floor", "condition")
    #: Trials per chunk of a generation: a trial takes seconds, so small chunks keep
    #: every core busy (see :func:`vibrissa.experiments.generate.generate`).
    chunk_size = 4

    def trials(self) -> list[FloorTrialSpec]:
        """Every trial, in canonical order: session, condition, floor, repetition."""
        specs: list[FloorTrialSpec] = []
        for s in range(self.n_seeds):
            within = 0
            for c in self.conditions:
                for f in self.floors:
                    for k in range(1, self.trials_per_condition + 1):
                        specs.append(FloorTrialSpec(len(specs), f, c, k, s, within))
                        within += 1
        return specs

    @property
    def seeds(self) -> list[int]:
        """The sessions' seeds."""
        return [int(self.seed) + s for s in range(self.n_seeds)]

    @property
    def n_trials(self) -> int:
        """Total number of trials (all sessions)."""
        return self.n_seeds * len(self.conditions) * len(self.floors) * self.trials_per_condition

    @property
    def n_samples(self) -> int:
        """Samples per trial."""
        return int(round(self.duration_s * self.sensor.sample_rate_hz))

    def signal_bytes(self) -> int:
        """Bytes of the finished dataset's signal (float64)."""
        return self.n_trials * 2 * self.n_samples * 8

    # ------------------------------------------------------------------ identity
    def to_dict(self) -> dict[str, Any]:
        """Every parameter as plain JSON-compatible values."""
        return dataclasses.asdict(self)

    def fingerprint(self) -> str:
        """Hash of every parameter that affects the generated signals."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()[:16]

    # ------------------------------------------------------------------ simulation
    def simulate_trials(self, indices: Sequence[int] | np.ndarray) -> dict[str, np.ndarray]:
        """Simulate the trials ``indices``.

        Each draws from its own stream ``(TRIALS, within)`` of its session's seed, so the
        bytes do not depend on chunking, and session ``k`` is the one-session protocol of
        seed ``seed + k``.

        Returns
        -------
        dict
            ``index``, ``signal`` (n, 2, n_samples) in volts and one array per name
            in :data:`FLOOR_DIAGNOSTICS`.
        """
        specs = self.trials()
        idx = np.asarray(indices, dtype=np.int64)
        if idx.size and (idx.min() < 0 or idx.max() >= len(specs)):
            raise ValueError(f"trial indices must lie in [0, {len(specs)})")
        out: dict[str, np.ndarray] = {
            "index": idx,
            "signal": np.empty((idx.size, 2, self.n_samples)),
            **{
                name: np.empty(idx.size, dtype=_INTEGER_DIAGNOSTICS.get(name, float))
                for name in FLOOR_DIAGNOSTICS
            },
        }
        model = _model(self.whisker, self.n_elements)
        sensor = _hall(self.sensor, self.whisker, self.n_elements)
        for k, i in enumerate(idx):
            spec = specs[int(i)]
            seed = int(self.seed) + spec.session
            rng = np.random.default_rng(stream(seed, TRIALS, spec.within))
            res = run_floor_trial(
                self.roomba,
                model,
                sensor,
                _sheet(spec.floor, seed),
                floor_spec(spec.floor),
                spec.condition,
                self.duration_s,
                rng,
                dt_s=self.dt_s,
            )
            out["signal"][k] = res.signal_v
            for name in FLOOR_DIAGNOSTICS:
                out[name][k] = getattr(res, name)
        return out

    def seconds_per_trial(self) -> float:
        """Wall-clock seconds of one trial on one core of this machine.

        Estimated from a 1 s trial of the middle of the session (after one that loads the
        kernels), the robot moving from the start (a stationary whisker costs next to
        nothing).
        """
        import time

        from vibrissa.robots.roomba import SETTLE_S

        short = dataclasses.replace(
            self, duration_s=1.0, roomba=dataclasses.replace(self.roomba, start_delay_s=(0.0, 0.0))
        )
        mid = [self.n_trials // 2]
        short.simulate_trials(mid)
        t0 = time.perf_counter()
        short.simulate_trials(mid)
        spent = time.perf_counter() - t0
        return spent * (self.duration_s + SETTLE_S) / (1.0 + SETTLE_S)

    def build_dataset(self, results: dict[str, np.ndarray]) -> xr.Dataset:
        """Assemble simulated arrays (all trials, canonical order) into a Dataset."""
        specs = self.trials()
        if results["signal"].shape[0] != len(specs):
            raise ValueError(f"expected {len(specs)} trials, got {results['signal'].shape[0]}")
        fs = self.sensor.sample_rate_hz
        per_trial: dict[str, np.ndarray] = {
            "floor": np.array([s.floor for s in specs]),
            "condition": np.array([s.condition for s in specs]),
            "run": np.array([s.trial for s in specs], dtype=np.int64),
            "seed": np.array([self.seed + s.session for s in specs], dtype=np.int64),
            **{name: results[name] for name in FLOOR_DIAGNOSTICS},
        }
        coords = signal_coords(
            len(specs),
            ["x", "y"],
            self.n_samples,
            fs,
            "time from the start of the recording",
            per_trial,
        )
        g = preset(self.whisker)
        s = _hall(self.sensor, self.whisker, self.n_elements)
        whisker = {
            **g.to_dict(),
            "n_elements": self.n_elements,
            "hall_gain_v": s.gain_v,
            "hall_offset_v": s.offset_v,
            "hall_sensor": s.to_dict(),
        }
        return xr.Dataset(
            {"signal": (("trial", "channel", "time"), results["signal"], {"units": "V"})},
            coords=coords,
            attrs={
                "sample_rate_hz": float(fs),
                "whisker": json.dumps(whisker, sort_keys=True),
                "robot": json.dumps(self.roomba.to_dict(), sort_keys=True),
                "protocol": self.name,
                "protocol_params": json.dumps(self.to_dict(), sort_keys=True, default=str),
                "floors": json.dumps({f: dataclasses.asdict(floor_spec(f)) for f in self.floors}),
                "seed": int(self.seed),
                "vibrissa_version": __version__,
                "source": "simulated: a SCRATCHbot whisker on a Roomba over four floors "
                "(thesis 6.2)",
            },
        )


@lru_cache(maxsize=4)
def _model(whisker: str, n_elements: int) -> RodModel:
    return RodModel(preset(whisker), n_elements)


@lru_cache(maxsize=4)
def _hall(settings: HallSettings, whisker: str, n_elements: int) -> HallSensor:
    return settings.calibrate(preset(whisker), n_elements)


@lru_cache(maxsize=8)
def _sheet(floor: str, seed: int):
    """The one piece of ``floor`` of a session (cached per process)."""
    key = _FLOOR_STREAM_BASE + list(FLOORS).index(floor)
    return make_floor(floor, seed=np.random.default_rng(stream(seed, SURFACES, key)))


def floor_protocol(quick: bool = False, **overrides: Any) -> FloorProtocol:
    """The Roomba protocol (``quick``: a small one); ``overrides`` replace fields.

    ``quick``: 2 trials of 4 s per floor and condition (24 trials a session) instead of 4
    of 16 s (48). ``overrides`` replace fields (``None`` ignored), e.g. ``n_seeds``.
    """
    changes = {k: v for k, v in overrides.items() if v is not None}
    if quick:
        changes = {"trials_per_condition": 2, "duration_s": 4.0, **changes}
    return FloorProtocol(**changes)


def tip_paths(ds: xr.Dataset) -> dict[str, dict[str, np.ndarray]]:
    """The tip's path in the first trial of each condition of a session's dataset.

    Figure 6.1's paths, from the same random stream the simulation drew the base's motion
    from, with each point's packet kept or not (:func:`vibrissa.signal.active_packets`).
    """
    from vibrissa.signal import PACKET_SAMPLES, active_packets

    params = json.loads(ds.attrs["protocol_params"])
    fields: dict[str, Any] = {
        k: tuple(v) if isinstance(v, list) else v for k, v in params["roomba"].items()
    }
    roomba = Roomba(**fields)
    length = float(json.loads(ds.attrs["whisker"])["length_mm"])
    fs = float(ds.attrs["sample_rate_hz"])
    paths: dict[str, dict[str, np.ndarray]] = {}
    # the first session (its trials come first, so a trial's index is its stream key)
    first = int(params["seed"])
    for i, c in enumerate(ds["condition"].values.tolist()):
        if c in paths or ("seed" in ds.coords and int(ds["seed"].values[i]) != first):
            continue
        rng = np.random.default_rng(stream(first, TRIALS, i))
        t, fwd, yaw = base_motion(roomba, c, float(params["duration_s"]), rng)
        x, y = tip_path(roomba, length, t, fwd, yaw)
        keep = active_packets(ds["signal"].values[i])
        k = np.minimum((t * fs).astype(int) // PACKET_SAMPLES, keep.size - 1)
        paths[c] = {"x_mm": x, "y_mm": y, "kept": keep[k]}
    return paths
