"""SCRATCHbot whisking into a pole (thesis 6.3) as a declarative protocol.

"The robot was kept stationary while it whisked into a vertical pole at three
different radial distances (70, 100 and 130 mm), and 3 whisk speeds (2, 4 and
6 Hz)" (6.3). Modelled with :func:`vibrissa.robots.whisking.run_whisking`: one
SCRATCHbot whisker (preset ``scratchbot``, 3.2.3) whose follicle housing is turned
by the whisking pattern generator, unmodulated by default (6.3 does not say the
feedback of 3.2.4 was on; ``sigma_z`` > 0 turns it on); the pole (0.5 mm radius,
parallel to ``y``) stands where the straight whisker, turned by
``contact_angle_deg``, touches it at the radial distance.

Each condition is one continuous run of ``n_whisks + 1`` whisks; the first whisk
(the start from rest) is dropped. The recording is the Hall sensor's output at
1 kHz (SCRATCHbot's calibration, 60 mm at r = 150 mm) minus the same whisk in air
(the robot's prediction of its own whisking, the self-motion cancellation of
3.2.4, here a noise-free in-air run of the same pattern): at 6 Hz the
whisker's first mode (7.6 Hz) makes the in-air deflection larger than a light
contact. Each whisk is one trial: the whisk's own samples (from full retraction
to full retraction), the rest of a 0.5 s window held at the sensor's rest output.

With ``n_seeds`` > 1 the grid is recorded in that many sessions, with seeds ``seed ..
seed + n_seeds - 1``. The whisker, the pole and the pattern generator are
deterministic here, so a session differs from another only in the sensor's noise: each
condition is simulated once and read with each session's noise stream.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa import __version__
from vibrissa._processes import imap_unordered
from vibrissa._validate import in_range, non_negative, positive
from vibrissa.experiments.contract import SelfGenerating
from vibrissa.experiments.streams import stream
from vibrissa.robots.whisking import (
    CONTACT_DIP_FRACTION,
    CONTACT_SIGNAL_SCALE,
    RCPControl,
    WhiskerSetup,
    WhiskPattern,
    check_pole_placement,
    pole_whisker,
    run_whisking,
    whisk_contacts,
)
from vibrissa.whisker.geometry import PRESETS, preset
from vibrissa.whisker.hall import HallSettings
from vibrissa.whisker.rod import RodModel

__all__ = ["ScratchbotProtocol", "scratchbot_protocol"]

#: Window of one trial (s): the longest whisk period of the thesis' grid (2 Hz).
WINDOW_S = 0.5


@dataclass(frozen=True)
class ScratchbotProtocol(SelfGenerating):
    """The SCRATCHbot pole experiment (6.3).

    Parameters
    ----------
    radial_distances_mm
        Pole radial distances (thesis: 70, 100, 130 mm).
    whisk_frequencies_hz
        Whisk frequencies (thesis: 2, 4, 6 Hz), each > 0.
    n_whisks
        Whisks kept per condition (one more is simulated and dropped).
    amplitude_deg, retracted_deg
        The whisk: housing angle from ``retracted_deg`` to ``retracted_deg +
        amplitude_deg`` (SCRATCHbot's amplitude is not given; 12 deg keeps the in-air
        deflection at 6 Hz, near the whisker's 7.6 Hz first mode, inside the sensor's range).
    contact_angle_deg
        Housing angle at which the straight whisker first touches the pole (6 deg:
        half-way through the protraction).
    pole_radius_mm
        The pole's radius.
    sigma_z, tau_z_periods
        RCP feedback (eqs. 3.2-3.3; ``sigma_z = 0``: unmodulated).
    whisker, n_elements, dt_s
        Whisker preset and its discretisation.
    motor_bandwidth_hz
        The housing servo (see :mod:`vibrissa.robots.whisking`).
    sensor
        The Hall sensor set-up (1 kHz, SCRATCHbot's calibration).
    seed
        Seed of the sensor noise.
    n_seeds
        Sessions (seeds ``seed .. seed + n_seeds - 1``; see the module's note).
    contact_signal_scale
        RCP's contact signal per unit of filtered deflection (``RCPControl.signal_scale``;
        default the identified :data:`vibrissa.robots.whisking.CONTACT_SIGNAL_SCALE`).
    rcp_settings, rcp_radial_distance_mm, rcp_whisk_frequency_hz, rcp_whisks
        The closed-loop comparison beside the grid: ``rcp_whisks`` whisks into the pole
        at one distance and frequency under each (``sigma_z``, ``tau_z`` in whisk
        periods) of ``rcp_settings`` (default: unmodulated, figure 3.9's (a) and (b)),
        the contact signal being the raw Hall ``x`` (eq. 3.2, no self-motion
        cancellation).
    """

    radial_distances_mm: tuple[float, ...] = (70.0, 100.0, 130.0)
    whisk_frequencies_hz: tuple[float, ...] = (2.0, 4.0, 6.0)
    n_whisks: int = 12
    amplitude_deg: float = 12.0
    retracted_deg: float = 0.0
    contact_angle_deg: float = 6.0
    pole_radius_mm: float = 0.5
    sigma_z: float = 0.0
    tau_z_periods: float = 0.25
    whisker: str = "scratchbot"
    n_elements: int = 28
    dt_s: float = 2.5e-4
    motor_bandwidth_hz: float = 20.0
    sensor: HallSettings = dataclasses.field(default_factory=HallSettings)
    seed: int = 0
    n_seeds: int = 1
    contact_signal_scale: float = CONTACT_SIGNAL_SCALE
    rcp_settings: tuple[tuple[float, float], ...] = ((0.0, 0.25), (0.7, 0.25), (2.0, 0.1))
    rcp_radial_distance_mm: float = 100.0
    rcp_whisk_frequency_hz: float = 2.0
    rcp_whisks: int = 4
    name: str = "scratchbot"

    def __post_init__(self) -> None:
        if self.whisker not in PRESETS:
            raise ValueError(f"unknown whisker preset {self.whisker!r}")
        g = preset(self.whisker)
        if not self.whisk_frequencies_hz or not self.radial_distances_mm:
            raise ValueError("at least one whisk frequency and one radial distance are needed")
        for f in self.whisk_frequencies_hz:
            if not (isinstance(f, int | float) and math.isfinite(f) and f > 0):
                raise ValueError(f"whisk frequency must be > 0 Hz, got {f!r}")
            in_range("whisk frequency", f, 0.0, 20.0, "Hz")
        if (
            isinstance(self.n_whisks, bool)
            or not isinstance(self.n_whisks, int)
            or self.n_whisks < 2
        ):
            raise ValueError(f"n_whisks must be an integer >= 2, got {self.n_whisks!r}")
        non_negative("sigma_z", self.sigma_z)
        positive("tau_z_periods", self.tau_z_periods)
        positive("pole_radius_mm", self.pole_radius_mm)
        positive("motor_bandwidth_hz", self.motor_bandwidth_hz)
        pattern = WhiskPattern(
            min(self.whisk_frequencies_hz), self.amplitude_deg, self.retracted_deg
        )
        for r in self.radial_distances_mm:
            check_pole_placement(
                r, self.contact_angle_deg, pattern, self.pole_radius_mm, g.length_mm
            )
        if not self.rcp_settings:
            raise ValueError("rcp_settings: at least one (sigma_z, tau_z_periods) is needed")
        for sz, tz in self.rcp_settings:
            RCPControl(sz, tz)
        rcp_pattern = WhiskPattern(
            self.rcp_whisk_frequency_hz, self.amplitude_deg, self.retracted_deg
        )
        check_pole_placement(
            self.rcp_radial_distance_mm,
            self.contact_angle_deg,
            rcp_pattern,
            self.pole_radius_mm,
            g.length_mm,
        )
        if (
            isinstance(self.rcp_whisks, bool)
            or not isinstance(self.rcp_whisks, int)
            or self.rcp_whisks < 1
        ):
            raise ValueError(f"rcp_whisks must be a positive integer, got {self.rcp_whisks!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {self.seed!r}")
        if isinstance(self.n_seeds, bool) or not isinstance(self.n_seeds, int) or self.n_seeds < 1:
            raise ValueError(f"n_seeds must be a positive integer, got {self.n_seeds!r}")
        positive("contact_signal_scale", self.contact_signal_scale)
        if not isinstance(self.sensor, HallSettings):
            raise TypeError(f"sensor must be a HallSettings, got {type(self.sensor).__name__}")

    # ------------------------------------------------------------------ grid
    @property
    def label_names(self) -> tuple[str, ...]:
        """Labels of a trial."""
        return ("radial_distance_mm", "whisk_frequency_hz")

    def conditions(self) -> list[dict[str, float]]:
        """Grid points in canonical order (frequency, then distance)."""
        return [
            {"radial_distance_mm": float(r), "whisk_frequency_hz": float(f)}
            for f in self.whisk_frequencies_hz
            for r in self.radial_distances_mm
        ]

    @property
    def n_trials(self) -> int:
        """Whisks kept over all conditions and sessions."""
        return self.n_seeds * len(self.conditions()) * self.n_whisks

    def to_dict(self) -> dict[str, Any]:
        """Every parameter as plain values."""
        return dataclasses.asdict(self)

    def fingerprint(self) -> str:
        """Hash of every parameter that affects the signals."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()[:16]

    # ------------------------------------------------------------------ simulation
    def simulate_condition(self, index: int) -> dict[str, np.ndarray]:
        """Simulate condition ``index``: per whisk trial windows and the whole run.

        ``signal`` holds every session's windows, (n_seeds, n_whisks, 2, window); the
        whole run's arrays are the first session's.
        """
        cond = self.conditions()[index]
        r, f = cond["radial_distance_mm"], cond["whisk_frequency_hz"]
        g = preset(self.whisker)
        model = RodModel(g, self.n_elements)
        sensor = self.sensor.calibrate(g, self.n_elements)
        pattern = WhiskPattern(f, self.amplitude_deg, self.retracted_deg)
        ctrl = RCPControl(self.sigma_z, self.tau_z_periods, signal_scale=self.contact_signal_scale)
        duration = (self.n_whisks + 1) / f
        common = dict(
            control_rate_hz=self.sensor.sample_rate_hz,
            dt_s=self.dt_s,
            motor_bandwidth_hz=self.motor_bandwidth_hz,
        )
        touch = run_whisking(
            [
                pole_whisker(
                    model, r, self.contact_angle_deg, self.pole_radius_mm, hall_gain_v=sensor.gain_v
                )
            ],
            pattern,
            ctrl,
            duration,
            **common,
        )
        air = run_whisking(
            [WhiskerSetup(model, hall_gain_v=sensor.gain_v)], pattern, None, duration, **common
        )
        rate = 1.0 / self.dt_s
        tan = np.column_stack([touch.tan_x[0], np.zeros_like(touch.tan_x[0])])
        ref = sensor.read(np.column_stack([air.tan_x[0], np.zeros_like(air.tan_x[0])]), rate)
        fs = self.sensor.sample_rate_hz
        nwin = int(round(WINDOW_S * fs))
        per = int(round(fs / f))
        sig = np.full((self.n_seeds, self.n_whisks, 2, nwin), sensor.offset_v)
        sats = np.zeros(self.n_seeds)
        volts = ref
        for q in reversed(range(self.n_seeds)):  # the first session's volts kept last
            rng = np.random.default_rng(stream(self.seed + q, 1000 + index))
            volts = sensor.read(tan, rate, rng)
            resid = volts - ref + sensor.offset_v
            for k in range(self.n_whisks):
                a = (k + 1) * per
                seg = resid[a : a + per]
                sig[q, k, :, : seg.shape[0]] = seg.T
            sats[q] = np.mean(
                (volts[:, 0] <= sensor.v_min + 1e-9) | (volts[:, 0] >= sensor.v_max - 1e-9)
            )
        step = int(round(rate / fs))
        return {
            "signal": sig,
            "raw_v": volts[:, 0],
            "air_v": ref[:, 0],
            "angle_deg": touch.angle_deg[0, ::step][: volts.shape[0]],
            "force_n": touch.contact_force_n[0, ::step][: volts.shape[0]],
            "saturated": sats,
        }

    def simulate_rcp(self, index: int) -> dict[str, np.ndarray]:
        """The closed loop under ``rcp_settings[index]``, at the control samples.

        Housing angle (deg), normalised ``x`` deflection, gating ``z`` and the largest
        contact force of each control period (N); ``contacts``: the contacts of each whisk
        as figure 3.9 counts them (:func:`vibrissa.robots.whisking.whisk_contacts`).
        """
        sz, tz = self.rcp_settings[index]
        g = preset(self.whisker)
        model = RodModel(g, self.n_elements)
        sensor = self.sensor.calibrate(g, self.n_elements)
        f = self.rcp_whisk_frequency_hz
        res = run_whisking(
            [
                pole_whisker(
                    model,
                    self.rcp_radial_distance_mm,
                    self.contact_angle_deg,
                    self.pole_radius_mm,
                    hall_gain_v=sensor.gain_v,
                )
            ],
            WhiskPattern(f, self.amplitude_deg, self.retracted_deg),
            RCPControl(sz, tz, signal_scale=self.contact_signal_scale),
            self.rcp_whisks / f,
            control_rate_hz=self.sensor.sample_rate_hz,
            dt_s=self.dt_s,
            motor_bandwidth_hz=self.motor_bandwidth_hz,
        )
        spp = int(round(1.0 / (self.sensor.sample_rate_hz * self.dt_s)))
        force = res.contact_force_n[0, 1:].reshape(-1, spp).max(axis=1)
        contacts = whisk_contacts(
            res.time_s,
            res.angle_deg[0],
            res.contact_force_n[0] > 0,
            f,
            CONTACT_DIP_FRACTION * self.amplitude_deg,
        )[: self.rcp_whisks]
        return {
            "contacts": contacts.astype(float),
            "angle_deg": res.angle_deg[0, ::spp],
            "deflection": res.deflection[0],
            "gating": res.gating[0],
            "force_n": np.concatenate([[0.0], force]),
        }

    def _job(self, job: tuple[str, int]) -> dict[str, np.ndarray]:
        kind, i = job
        return self.simulate_condition(i) if kind == "condition" else self.simulate_rcp(i)

    def generate_dataset(
        self,
        path: Path,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        **kwargs: Any,
    ) -> xr.Dataset:
        """Simulate every condition and the closed-loop comparison.

        Save the dataset to ``path`` (NetCDF). Local processes only (no ``scheduler``).
        """
        from vibrissa.data import save_dataset

        jobs = [("condition", i) for i in range(len(self.conditions()))] + [
            ("rcp", i) for i in range(len(self.rcp_settings))
        ]
        w = min(workers if workers is not None else (os.cpu_count() or 1), len(jobs))
        done: list[dict[str, np.ndarray]] = []

        def tick() -> None:
            if progress:
                n_cond = min(len(done), len(self.conditions()))
                progress(n_cond * self.n_whisks * self.n_seeds, self.n_trials)

        if w <= 1:
            for job in jobs:
                done.append(self._job(job))
                tick()
        else:
            # in job order, as they finish: a job waits for the ones before it
            arrived: dict[int, dict[str, np.ndarray]] = {}
            for i, res in imap_unordered(self._job, jobs, w):
                arrived[i] = res
                while len(done) in arrived:
                    done.append(arrived.pop(len(done)))
                tick()
        n = len(self.conditions())
        ds = self.build_dataset(done[:n], done[n:])
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        save_dataset(ds, path)
        return ds

    def build_dataset(
        self, results: list[dict[str, np.ndarray]], rcp: list[dict[str, np.ndarray]] | None = None
    ) -> xr.Dataset:
        """Assemble the conditions' results into the dataset schema.

        Per trial: ``signal`` (V, in-air whisk subtracted, rest 2.5 V), labels,
        ``whisk`` (1-based within its condition), ``set`` (1: odd whisks, 2: even) and
        ``session_seed``; trials in order session, condition, whisk.
        The whole runs (raw and in-air volts, housing angle, contact force) are kept
        per condition, padded with NaN to the longest, for the figures; ``rcp``
        (:meth:`simulate_rcp` per setting) as ``rcp_*`` variables.
        """
        from vibrissa.data.dataset import coordinate_attrs

        fs = self.sensor.sample_rate_hz
        conds = self.conditions()
        n_q = results[0]["signal"].shape[0]
        sig = np.concatenate([r["signal"][q] for q in range(n_q) for r in results])
        labels = {
            k: np.tile(np.repeat([c[k] for c in conds], self.n_whisks), n_q)
            for k in self.label_names
        }
        whisk = np.tile(np.arange(1, self.n_whisks + 1), len(conds) * n_q)
        session = np.repeat(self.seed + np.arange(n_q), len(conds) * self.n_whisks)
        coords: dict[str, Any] = {
            "trial": np.arange(sig.shape[0]),
            "channel": np.array(["x", "y"]),
            "time": (
                "time",
                np.arange(sig.shape[2]) / fs,
                {"units": "s", "long_name": "time from the whisk's start"},
            ),
        }
        per_trial = {
            **labels,
            "whisk": whisk,
            "set": np.where(whisk % 2 == 1, 1, 2),
            "session_seed": session,
        }
        for name, vals in per_trial.items():
            coords[name] = ("trial", np.asarray(vals), coordinate_attrs(name, vals))
        n_run = max(r["raw_v"].size for r in results)

        def padded(key: str) -> np.ndarray:
            out = np.full((len(results), n_run), np.nan)
            for i, r in enumerate(results):
                out[i, : r[key].size] = r[key][:n_run]
            return out

        data: dict[str, tuple[Any, ...]] = {
            "signal": (("trial", "channel", "time"), sig, {"units": "V"})
        }
        for key, units in (("raw_v", "V"), ("air_v", "V"), ("angle_deg", "deg"), ("force_n", "N")):
            data[f"run_{key}"] = (("condition", "run_time"), padded(key), {"units": units})
        data["run_saturated"] = (
            ("condition",),
            np.array([float(np.mean(r["saturated"])) for r in results]),
        )
        coords["condition"] = np.arange(len(conds))
        coords["run_time"] = ("run_time", np.arange(n_run) / fs, {"units": "s"})
        if rcp:
            for key, units in (
                ("angle_deg", "deg"),
                ("deflection", "1"),
                ("gating", "1"),
                ("force_n", "N"),
            ):
                data[f"rcp_{key}"] = (
                    ("rcp_setting", "rcp_time"),
                    np.vstack([r[key] for r in rcp]),
                    {"units": units},
                )
            data["rcp_contacts"] = (
                ("rcp_setting", "rcp_whisk"),
                np.vstack([r["contacts"] for r in rcp]),
                {"long_name": "contacts per whisk (figure 3.9's count)"},
            )
            coords["rcp_setting"] = np.arange(len(rcp))
            coords["rcp_sigma_z"] = ("rcp_setting", [float(a) for a, _ in self.rcp_settings])
            coords["rcp_tau_z_periods"] = ("rcp_setting", [float(b) for _, b in self.rcp_settings])
            coords["rcp_time"] = ("rcp_time", np.arange(rcp[0]["gating"].size) / fs, {"units": "s"})
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "sample_rate_hz": float(fs),
                "whisker": json.dumps(
                    dataclasses.asdict(preset(self.whisker)), sort_keys=True, default=str
                ),
                "protocol": self.name,
                "protocol_params": json.dumps(self.to_dict(), sort_keys=True, default=str),
                "seed": int(self.seed),
                "vibrissa_version": __version__,
                "source": "simulated: SCRATCHbot whisking into a pole (thesis 6.3)",
            },
        )


def scratchbot_protocol(quick: bool = False, seed: int = 0, **overrides: Any) -> ScratchbotProtocol:
    """The thesis' grid with 12 whisks per condition (``quick``: 4)."""
    changes = {k: v for k, v in overrides.items() if v is not None}
    return ScratchbotProtocol(n_whisks=4 if quick else 12, seed=seed, **changes)
