"""The BIOTACT G1 texture and distance session of thesis 6.4 as a declarative protocol.

Nine classes (three textures x three horizontal distances: 5, 10, 15 mm) under three
whisking strategies (unmodulated, RCP7: ``sigma_z = 0.7``, RCP9: ``sigma_z = 0.9``;
``tau_z = T_w / 4`` throughout, as 3.4.2 says), twelve whisks per class at 2 Hz. The
head (:class:`vibrissa.robots.biotact.G1Head`) whisks both rows of three whiskers
(presets ``biotact-g1-80``, ``-112``, ``-158``) into a vertical textured surface
with :func:`vibrissa.robots.whisking.run_whisking`, one control period (0.5 ms, the
G1's 2 kHz loop, 3.4.1) at a time when RCP is on; each side's contact signal is the
largest filtered ``x`` of its three whiskers (eq. 3.2). The Hall sensors record
``x`` and ``y`` of the six whiskers at 2 kHz: 12 channels per whisk.

Each whisk is one trial. A class's twelve whisks come from one continuous run, as
on the robot: a lead-in whisk from rest at full retraction (dropped), then the
recorded whisks, each from full retraction to full retraction, the whisker's
ringing after it leaves the surface and the gating variable carried from one whisk
into the next (3.4.2: ``z`` "all but recovered by the time of the next contact").
One run per class is one chunk of the resumable, parallel generation
(:func:`vibrissa.experiments.generate.generate`). What differs between the whisks
of a class, from the class's own random stream:

* the whisk's amplitude on each side, normal with ``amplitude_jitter_deg`` (0.5 deg)
  standard deviation from whisk to whisk: the modules' position control is not
  perfectly repeatable (an assumption; the thesis gives no figure);
* the state the previous whisk left (ringing, ``z``), and with it where on the
  grains the tip lands;
* the sensors' noise.

Where each whisker's tip meets its row's sheet is drawn once per class (uniform
over the 8 x 2 mm tile).

With ``n_seeds`` > 1 the whole session is repeated with seeds ``seed .. seed + n_seeds
- 1`` (sheets, tip placements, amplitudes, noise all drawn anew); trials carry their
session's seed (``session_seed``), and a session's whisks are byte for byte those of a
one-session run with that seed.

Textures (the thesis: "a smooth plastic surface and two grades of commercial
abrasive sandpaper (3M silicon carbide 'Wetordry Tri-M-ite')", grades not given):
``plastic`` (below) and FEPA P600 and P180 (:data:`vibrissa.whisker.TEXTURES`),
both made as Wetordry Tri-M-ite sheets (3M's waterproof silicon-carbide paper runs
from about P150 to P2500), a factor of three apart in grain size, so one fine and
one coarse paper.
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
from vibrissa._validate import finite, in_range, non_negative, positive
from vibrissa.data.dataset import signal_coords
from vibrissa.experiments.contract import ChunkedTrials
from vibrissa.experiments.streams import SURFACES, TRIALS, stream
from vibrissa.robots.biotact import G1_CONTACT_SIGNAL_SCALE, G1Head
from vibrissa.robots.whisking import RCPControl, VaryingWhiskPattern, WhiskPattern, run_whisking
from vibrissa.thesis.biotact_g1.values import STRATEGIES
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSensor, HallSettings, steps_per_sample
from vibrissa.whisker.rod import RodModel, SimulationError
from vibrissa.whisker.surfaces import TEXTURES, Surface, TextureSpec, make_surface

__all__ = ["G1_TEXTURES", "STRATEGIES", "BiotactProtocol", "BiotactTrialSpec", "biotact_protocol"]


#: The surfaces a G1 session may use: smooth plastic and the sandpaper presets.
G1_TEXTURES: dict[str, TextureSpec] = {
    "plastic": TextureSpec(
        "plastic",
        0.0,
        0.1,
        0.35,
        "smooth plastic sheet (extruded acrylic or ABS), Ra ~ 0.1 um; friction 0.35, a "
        "typical tabulated polymer-on-polymer coefficient",
    ),
    **{k: v for k, v in TEXTURES.items() if k != "aluminium"},
}

#: Stream keys of the G1 sheets start here, clear of the chapter-5 and floor sheets'.
_SHEET_STREAM_BASE = 200
#: Sides of the head: the two rows.
SIDES = ("left", "right")


@dataclass(frozen=True)
class BiotactTrialSpec:
    """One whisk: its class, ``whisk`` (1-based) and the seed of its session."""

    index: int
    strategy: str
    texture: str
    distance_mm: float
    whisk: int
    session_seed: int = 0


def _sensor() -> HallSettings:
    # the G1 reads its whiskers at 2 kHz (3.4.1); calibration: the default point for
    # each whisker's length
    return HallSettings(sample_rate_hz=2000.0)


@dataclass(frozen=True)
class BiotactProtocol(ChunkedTrials):
    """The BIOTACT G1 session (thesis 6.4).

    Parameters
    ----------
    textures : tuple of str
        Surfaces (:data:`G1_TEXTURES`; thesis: smooth plastic and two 3M papers).
    distances_mm : tuple of float
        Horizontal distance of the surface from the head's front (thesis: 5, 10, 15).
    strategies : tuple of str
        Control strategies (:data:`STRATEGIES`).
    n_whisks : int
        Whisks per class and strategy (thesis: 12).
    whisk_frequency_hz : float
        ``f_w`` (thesis: 2 Hz).
    tau_z_periods : float
        RCP's decay time constant in whisk periods (thesis: 1/4).
    head : G1Head
        The head's geometry and whisk.
    amplitude_jitter_deg : float
        Standard deviation of a side's whisk amplitude from whisk to whisk.
    n_elements, dt_s
        Rod discretisation and internal step (must divide the sample period; a run
        the solver cannot finish is made again with half, then a quarter of it).
    motor_bandwidth_hz : float
        The modules' servo (:func:`vibrissa.robots.whisking.motor_follow`).
    sensor : HallSettings
        The Hall sensors' set-up (2 kHz); the control loop runs at its rate.
    seed : int
        Seed of the (first) session.
    n_seeds : int
        Sessions: the whole session is repeated with seeds ``seed .. seed + n_seeds - 1``
        (sheets, tip placements, whisk amplitudes and sensor noise all drawn anew); a
        session's whisks are those of a run with ``seed`` its seed and ``n_seeds = 1``.
    contact_signal_scale : float
        RCP's contact signal per unit of filtered deflection
        (:data:`vibrissa.robots.biotact.G1_CONTACT_SIGNAL_SCALE`, see there).
    """

    textures: tuple[str, ...] = ("plastic", "p600", "p180")
    distances_mm: tuple[float, ...] = (5.0, 10.0, 15.0)
    strategies: tuple[str, ...] = tuple(STRATEGIES)
    n_whisks: int = 12
    whisk_frequency_hz: float = 2.0
    tau_z_periods: float = 0.25
    head: G1Head = field(default_factory=G1Head)
    amplitude_jitter_deg: float = 0.5
    n_elements: int = 20
    dt_s: float = 2.5e-4
    motor_bandwidth_hz: float = 20.0
    sensor: HallSettings = field(default_factory=_sensor)
    seed: int = 0
    n_seeds: int = 1
    contact_signal_scale: float = G1_CONTACT_SIGNAL_SCALE
    name: str = "biotact-g1"

    def __post_init__(self) -> None:
        _names("textures", self.textures, G1_TEXTURES, "texture")
        _names("strategies", self.strategies, STRATEGIES, "strategy")
        if not self.distances_mm:
            raise ValueError("distances_mm: at least one distance is needed")
        ds = [self.head.check_distance(d, "distance_mm") for d in self.distances_mm]
        if len(set(ds)) != len(ds):
            raise ValueError(f"distances_mm: each distance once, got {list(self.distances_mm)}")
        if (
            isinstance(self.n_whisks, bool)
            or not isinstance(self.n_whisks, int)
            or self.n_whisks < 2
        ):
            raise ValueError(f"n_whisks must be an integer >= 2, got {self.n_whisks!r}")
        f = finite("whisk_frequency_hz", self.whisk_frequency_hz)
        if f <= 0:
            raise ValueError(f"whisk_frequency_hz must be > 0 Hz, got {self.whisk_frequency_hz!r}")
        in_range("whisk_frequency_hz", f, 0.0, 10.0, "Hz")  # the modules' limit (3.4.1)
        RCPControl(0.0, self.tau_z_periods)
        non_negative("amplitude_jitter_deg", self.amplitude_jitter_deg)
        positive("motor_bandwidth_hz", self.motor_bandwidth_hz)
        if not isinstance(self.head, G1Head):
            raise TypeError(f"head must be a G1Head, got {type(self.head).__name__}")
        if not isinstance(self.sensor, HallSettings):
            raise TypeError(f"sensor must be a HallSettings, got {type(self.sensor).__name__}")
        steps_per_sample(self.dt_s, self.sensor.sample_rate_hz)
        if abs(self.n_samples - self.sensor.sample_rate_hz / f) > 1e-6:
            raise ValueError(
                f"whisk_frequency_hz ({f:g}) must give a whole number of samples "
                f"per whisk at {self.sensor.sample_rate_hz:g} Hz"
            )
        for L in self.head.lengths_mm:
            self.sensor.calibration_point(preset(_whisker_name(L)))
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
        positive("contact_signal_scale", self.contact_signal_scale)

    # ------------------------------------------------------------------ trials
    label_names = ("texture", "distance_mm")

    def trials(self) -> list[BiotactTrialSpec]:
        """Every whisk in canonical order: session, strategy, texture, distance, whisk."""
        specs: list[BiotactTrialSpec] = []
        for q in range(self.n_seeds):
            for s in self.strategies:
                for t in self.textures:
                    for d in self.distances_mm:
                        for k in range(1, self.n_whisks + 1):
                            specs.append(
                                BiotactTrialSpec(len(specs), s, t, float(d), k, self.seed + q)
                            )
        return specs

    @property
    def classes_per_session(self) -> int:
        """Runs (strategy, texture, distance) of one session."""
        return len(self.strategies) * len(self.textures) * len(self.distances_mm)

    @property
    def n_trials(self) -> int:
        """Total number of whisks."""
        return self.n_seeds * self.classes_per_session * self.n_whisks

    @property
    def n_channels(self) -> int:
        """Recorded channels: x and y of every whisker of both rows."""
        return 2 * 2 * self.head.n_whiskers

    @property
    def n_samples(self) -> int:
        """Samples per whisk."""
        return int(round(self.sensor.sample_rate_hz / self.whisk_frequency_hz))

    def channel_names(self) -> list[str]:
        """``L1x, L1y, ..., R3y``: side, whisker (front to rear), direction."""
        return [
            f"{s[0].upper()}{i + 1}{c}"
            for s in SIDES
            for i in range(self.head.n_whiskers)
            for c in "xy"
        ]

    def signal_bytes(self) -> int:
        """Bytes of the finished dataset's arrays (float64)."""
        n_w = 2 * self.head.n_whiskers
        return self.n_trials * self.n_samples * 8 * (self.n_channels + n_w + 2 + 2)

    # ------------------------------------------------------------------ identity
    def to_dict(self) -> dict[str, Any]:
        """Every parameter as plain JSON-compatible values."""
        return dataclasses.asdict(self)

    def fingerprint(self) -> str:
        """Hash of every parameter that affects the generated signals."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()[:16]

    # ------------------------------------------------------------------ simulation
    @property
    def chunk_size(self) -> int:
        """Trials per chunk of a generation: one class's whisks (one continuous run)."""
        return self.n_whisks

    def simulate_trials(self, indices: Sequence[int] | np.ndarray) -> dict[str, np.ndarray]:
        """Simulate the whisks ``indices``.

        A class's whisks come from one continuous run (:meth:`simulate_class`), which
        draws from its own stream ``(TRIALS, class)`` of the seed, so the bytes do not
        depend on chunking; a chunk of one class's whisks runs it once.

        Returns
        -------
        dict
            ``index``; ``signal`` (n, 12, n_samples) in volts; per side ``angle_deg``
            (housing angle) and ``gating`` (``z``), (n, 2, n_samples); per whisker
            ``force_n`` (largest contact force of each sample period), (n, 6,
            n_samples); ``saturated`` (n,); ``dt_s`` (n,), the internal step used.
        """
        specs = self.trials()
        idx = np.asarray(indices, dtype=np.int64)
        if idx.size and (idx.min() < 0 or idx.max() >= len(specs)):
            raise ValueError(f"trial indices must lie in [0, {len(specs)})")
        n, m, nw = idx.size, self.n_samples, 2 * self.head.n_whiskers
        out: dict[str, np.ndarray] = {
            "index": idx,
            "signal": np.empty((n, self.n_channels, m)),
            "angle_deg": np.empty((n, 2, m)),
            "gating": np.empty((n, 2, m)),
            "force_n": np.empty((n, nw, m)),
            "saturated": np.empty(n, dtype=bool),
            "dt_s": np.empty(n),
        }
        for c in dict.fromkeys((idx // self.n_whisks).tolist()):
            run = self.simulate_class(int(c))
            for k in np.flatnonzero(idx // self.n_whisks == c):
                w = specs[int(idx[k])].whisk - 1
                for key in out:
                    if key != "index":
                        out[key][k] = run[key][w]
        return out

    def simulate_class(self, c: int, n_whisks: int | None = None) -> dict[str, np.ndarray]:
        """One continuous run of class ``c``; arrays with one row per recorded whisk.

        The class is a (strategy, texture, distance) in canonical order. The run is a
        lead-in whisk from rest at full retraction, dropped, then ``n_whisks`` (default:
        the protocol's) recorded whisks, each from full retraction to full retraction.
        """
        spec = self.trials()[c * self.n_whisks]
        n_rec = self.n_whisks if n_whisks is None else int(n_whisks)
        # the session's own seed and the class's index within its session: a session of
        # a multi-seed run is the single session of that seed
        seed = spec.session_seed
        rng = np.random.default_rng(stream(seed, TRIALS, c % self.classes_per_session))
        head, f = self.head, self.whisk_frequency_hz
        models = [_model(L, self.n_elements) for L in head.lengths_mm]
        halls = [_hall(self.sensor, L, self.n_elements) for L in head.lengths_mm]
        friction = G1_TEXTURES[spec.texture].friction
        setups = []
        for side in range(2):
            sheet = _sheet(spec.texture, seed, side)
            tile = np.array(sheet.heights_m.shape) * sheet.spacing_m * 1e3
            for i in range(head.n_whiskers):
                offset = rng.uniform(0.0, 1.0, 2) * tile
                setups.append(
                    head.whisker(
                        i,
                        models[i],
                        sheet,
                        spec.distance_mm,
                        side,
                        halls[i].gain_v,
                        friction,
                        (offset[0], offset[1]),
                    )
                )
        amps = head.amplitude_deg + self.amplitude_jitter_deg * rng.standard_normal((2, n_rec + 1))
        patterns: list[WhiskPattern] = [
            VaryingWhiskPattern(
                f, head.amplitude_deg, 0.0, amplitudes_deg=tuple(float(a) for a in side_amps)
            )
            for side_amps in amps
        ]
        sigma = STRATEGIES[spec.strategy]
        ctrl = (
            RCPControl(sigma, self.tau_z_periods, signal_scale=self.contact_signal_scale)
            if sigma > 0
            else None
        )
        fs = self.sensor.sample_rate_hz
        # a stiff moment (a tip catching on grains) can defeat the solver at dt_s: the
        # run is then made again with half the step, and once more with a quarter
        # (deterministic, so the bytes still do not depend on chunking)
        for halvings in range(3):
            dt = self.dt_s / 2**halvings
            try:
                res = run_whisking(
                    setups,
                    patterns,
                    ctrl,
                    (n_rec + 1) / f,
                    control_rate_hz=fs,
                    dt_s=dt,
                    motor_bandwidth_hz=self.motor_bandwidth_hz,
                )
                break
            except SimulationError:
                if halvings == 2:
                    raise
        m, step = self.n_samples, steps_per_sample(dt, fs)
        n_all = (n_rec + 1) * m
        sig = np.empty((self.n_channels, n_all))
        sat = np.zeros(n_rec, dtype=bool)
        for w in range(len(setups)):
            hall = halls[w % head.n_whiskers]
            tan_y = res.tan_y[w] if res.tan_y is not None else np.zeros_like(res.tan_x[w])
            volts = hall.read(np.column_stack([res.tan_x[w], tan_y]), 1.0 / dt, rng)[:n_all]
            sig[2 * w : 2 * w + 2] = volts.T
            rail = (volts[m:] <= hall.v_min + 1e-9) | (volts[m:] >= hall.v_max - 1e-9)
            sat |= rail.reshape(n_rec, m, 2).any(axis=(1, 2))
        force = res.contact_force_n[:, 1:].reshape(len(setups), -1, step).max(axis=2)
        first = [0, head.n_whiskers]

        def whisks(a: np.ndarray) -> np.ndarray:
            """(k, n_all) -> (n_rec, k, m), the lead-in whisk dropped."""
            return a[:, m:n_all].reshape(a.shape[0], n_rec, m).transpose(1, 0, 2)

        return {
            "signal": whisks(sig),
            "angle_deg": whisks(res.angle_deg[first, ::step][:, :n_all]),
            "gating": whisks(res.gating[:, :n_all]),
            "force_n": whisks(force[:, :n_all]),
            "saturated": sat,
            "dt_s": np.full(n_rec, dt),
        }

    def seconds_per_trial(self) -> float:
        """Wall-clock seconds of one whisk on one core of this machine.

        Measured on one modulated whisk after the lead-in (the kernels load from numba's
        cache).
        """
        import time

        specs = self.trials()
        t0 = time.perf_counter()
        self.simulate_class(specs[-1].index // self.n_whisks, n_whisks=1)
        return (time.perf_counter() - t0) / 2.0

    def build_dataset(self, results: dict[str, np.ndarray]) -> xr.Dataset:
        """Assemble simulated arrays (all whisks, canonical order) into a Dataset."""
        specs = self.trials()
        if results["signal"].shape[0] != len(specs):
            raise ValueError(f"expected {len(specs)} trials, got {results['signal'].shape[0]}")
        fs = self.sensor.sample_rate_hz
        per_trial: dict[str, np.ndarray] = {
            "strategy": np.array([s.strategy for s in specs]),
            "texture": np.array([s.texture for s in specs]),
            "distance_mm": np.array([s.distance_mm for s in specs]),
            "whisk": np.array([s.whisk for s in specs], dtype=np.int64),
            "saturated": np.asarray(results["saturated"], dtype=bool),
            "dt_s": np.asarray(results["dt_s"], dtype=float),
            "session_seed": np.array([s.session_seed for s in specs], dtype=np.int64),
        }
        coords = signal_coords(
            len(specs),
            self.channel_names(),
            self.n_samples,
            fs,
            "time from full retraction",
            per_trial,
        )
        coords["side"] = np.array(SIDES)
        coords["whisker_id"] = np.array(
            [f"{s[0].upper()}{i + 1}" for s in SIDES for i in range(self.head.n_whiskers)]
        )
        whiskers = {}
        for L in self.head.lengths_mm:
            g, s = preset(_whisker_name(L)), _hall(self.sensor, L, self.n_elements)
            whiskers[g.name] = {
                **g.to_dict(),
                "n_elements": self.n_elements,
                "hall_gain_v": s.gain_v,
                "hall_offset_v": s.offset_v,
            }
        data = {
            "signal": (("trial", "channel", "time"), results["signal"], {"units": "V"}),
            "angle_deg": (
                ("trial", "side", "time"),
                results["angle_deg"],
                {"units": "deg", "long_name": "housing angle from full retraction"},
            ),
            "gating": (
                ("trial", "side", "time"),
                results["gating"],
                {"units": "1", "long_name": "RCP gating variable z (eq. 3.3)"},
            ),
            "force_n": (
                ("trial", "whisker_id", "time"),
                results["force_n"],
                {"units": "N", "long_name": "largest contact force per sample"},
            ),
        }
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "sample_rate_hz": float(fs),
                "whisker": json.dumps(whiskers, sort_keys=True),
                "protocol": self.name,
                "protocol_params": json.dumps(self.to_dict(), sort_keys=True, default=str),
                "textures": json.dumps(
                    {t: dataclasses.asdict(G1_TEXTURES[t]) for t in self.textures}
                ),
                "seed": int(self.seed),
                "vibrissa_version": __version__,
                "source": "simulated: the BIOTACT G1 head whisking into textured surfaces "
                "(thesis 6.4)",
            },
        )


def _names(field_name: str, names: Any, known: dict[str, Any], item: str) -> None:
    if not isinstance(names, tuple) or not names:
        raise ValueError(f"{field_name}: a non-empty tuple of names is needed, got {names!r}")
    for v in names:
        if v not in known:
            raise ValueError(f"unknown {item} {v!r}; choose from {', '.join(known)}")
    if len(set(names)) != len(names):
        raise ValueError(f"{field_name}: each {item} once, got {list(names)}")


def _whisker_name(length_mm: float) -> str:
    return f"biotact-g1-{length_mm:g}"


@lru_cache(maxsize=8)
def _model(length_mm: float, n_elements: int) -> RodModel:
    return RodModel(preset(_whisker_name(length_mm)), n_elements)


@lru_cache(maxsize=8)
def _hall(settings: HallSettings, length_mm: float, n_elements: int) -> HallSensor:
    return settings.calibrate(preset(_whisker_name(length_mm)), n_elements)


@lru_cache(maxsize=16)
def _sheet(texture: str, seed: int, side: int) -> Surface:
    """The sheet of ``texture`` a side's row meets in a session (cached per process)."""
    key = _SHEET_STREAM_BASE + 2 * list(G1_TEXTURES).index(texture) + side
    return make_surface(
        G1_TEXTURES[texture], seed=np.random.default_rng(stream(seed, SURFACES, key))
    )


def biotact_protocol(quick: bool = False, **overrides: Any) -> BiotactProtocol:
    """The G1 session (``quick``: a small one); ``overrides`` replace fields.

    ``quick``: two textures (plastic, P180) at 5 and 15 mm, two whisks per class (24
    whisks: one to train, one to validate) instead of 3 x 3 classes x 12 whisks (324).
    ``overrides`` replace fields (``None`` ignored).
    """
    changes = {k: v for k, v in overrides.items() if v is not None}
    if quick:
        changes = {
            "textures": ("plastic", "p180"),
            "distances_mm": (5.0, 15.0),
            "n_whisks": 2,
            **changes,
        }
    return BiotactProtocol(**changes)
