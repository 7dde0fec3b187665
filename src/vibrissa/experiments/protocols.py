"""The thesis' XY-robot experiments as declarative protocols.

A :class:`Protocol` is a parameter grid plus the robot, stimulus, whisker and
recording settings (the Hall sensor's set-up is nested as ``Protocol.sensor``, a
:class:`~vibrissa.whisker.hall.HallSettings`). :meth:`Protocol.trials` expands it
into the session's trial list: every grid point x runs x directions, with the four
(run, direction) combinations numbered as the recorded *sets* 1-4 and each run's
contacts "randomly interleaved to limit any effects of changing whisker properties" (4.2).

* ``radial-distance`` (chapter 4, 4.2): 101 radial distances 80-180 mm in 1 mm
  steps x 26 speeds 36-216 mm/s (~7.2 mm/s steps), 2 runs x 2 directions, 1 kHz,
  +/-325 ms about the peak: 10,504 trials.
* ``angle-texture`` (chapter 5, 5.2): 8 surface angles 10-80 deg x 11 speeds
  6-106 mm/s x 4 textures (aluminium, P600, P180, P80), 2 runs x 2 directions, 4 kHz,
  +/-750 ms about the peak: 1,408 trials (352 combinations x 4 sets).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vibrissa._validate import in_range, positive
from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.experiments.streams import ORDER, stream
from vibrissa.robots.xy_stage import XYStage
from vibrissa.robots.xy_variability import TrialVariability
from vibrissa.whisker.geometry import PRESETS, preset
from vibrissa.whisker.hall import HallSettings, steps_per_sample
from vibrissa.whisker.surfaces import TEXTURES

__all__ = [
    "PROTOCOL_NAMES",
    "Protocol",
    "TrialSpec",
    "get_protocol",
    "MAX_GRID_VALUES",
    "parse_grid",
]


#: Most values one axis of a grid may have. The thesis' finest axis has 101 values
#: (radial distances 80-180 mm in 1 mm steps, 4.2); 100 times that is far beyond any
#: grid a robot session could record, and refusing more stops a typo (a step of
#: 1e-7) from asking for billions of trials.
MAX_GRID_VALUES = 10_000


def parse_grid(text: str, name: str = "grid") -> tuple[float, ...]:
    """Parse a grid specification into a tuple of floats.

    The specification is ``"start:stop:step"`` (inclusive), ``"start:stop:num"`` with
    ``#num`` or a comma list ``"a,b,c"``.

    Raises ValueError (naming ``name``) for anything else: an empty or malformed
    specification, non-finite values, repeated values, or more than
    :data:`MAX_GRID_VALUES` values.

    Examples
    --------
    >>> parse_grid("80:180:20")
    (80.0, 100.0, 120.0, 140.0, 160.0, 180.0)
    >>> parse_grid("36:216:#6")
    (36.0, 72.0, 108.0, 144.0, 180.0, 216.0)
    >>> parse_grid("10,20,45")
    (10.0, 20.0, 45.0)
    """
    t = str(text).strip()
    if not t:
        raise ValueError(f"{name}: empty grid specification")
    usage = f"{name}: cannot parse {text!r}; use start:stop:step, start:stop:#count or a,b,c"
    too_many = f"{name}: {text!r} asks for more than {MAX_GRID_VALUES} values (the limit per axis)"
    try:
        if ":" in t:
            parts = t.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop = float(parts[0]), float(parts[1])
            if not (np.isfinite(start) and np.isfinite(stop)):
                raise ValueError(f"{name}: {text!r} has a non-finite end")
            if parts[2].startswith("#"):
                num = int(parts[2][1:])
                if num < 1:
                    raise ValueError
                if num > MAX_GRID_VALUES:
                    raise ValueError(too_many)
                vals = np.linspace(start, stop, num)
            else:
                step = float(parts[2])
                if not np.isfinite(step) or step <= 0 or stop < start:
                    raise ValueError
                with np.errstate(over="ignore"):
                    span = (stop - start) / step
                if not np.isfinite(span) or span + 1 > MAX_GRID_VALUES:
                    raise ValueError(too_many)
                n = int(np.floor(span + 1e-9)) + 1
                vals = start + step * np.arange(n)
        else:
            items = [v for v in t.split(",") if v.strip()]
            if len(items) > MAX_GRID_VALUES:
                raise ValueError(too_many)
            vals = np.array([float(v) for v in items])
    except ValueError as exc:
        raise ValueError(str(exc) if str(exc).startswith(f"{name}:") else usage) from None
    except OverflowError:
        raise ValueError(too_many) from None
    if vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ValueError(f"{name}: {text!r} gives no finite values")
    with np.errstate(over="ignore", invalid="ignore"):
        rounded = tuple(float(round(v, 9)) if abs(v) < 1e15 else float(v) for v in vals)
    if len(set(rounded)) != len(rounded):
        dup = sorted({v for v in rounded if rounded.count(v) > 1})
        raise ValueError(f"{name}: {text!r} repeats the value(s) {dup[:5]}; each value once")
    return rounded


@dataclass(frozen=True)
class TrialSpec:
    """One trial of a session.

    Attributes
    ----------
    index
        Position in the protocol's canonical trial list (the dataset's trial order).
    labels
        Contact parameters, e.g. ``{"radial_distance_mm": 120.0, "speed_mm_s": 72.0}``.
    run, direction, set
        Repetition (1, 2), movement direction (+1/-1) and recorded set (1-4).
    order
        Position in the recording session (random interleaving).
    """

    index: int
    labels: dict[str, Any]
    run: int
    direction: int
    set: int
    order: int


@dataclass(frozen=True)
class Protocol(SimulationProtocol):
    """A declarative XY-robot experiment.

    Parameters
    ----------
    name
        ``"radial-distance"`` or ``"angle-texture"``.
    speeds_mm_s
        Approach speeds.
    radial_distances_mm
        Pole contact radii (radial-distance protocol).
    angles_deg, textures
        Surface angles and textures (angle-texture protocol).
    runs
        Repetitions of the whole grid.
    directions
        Movement directions recorded (+1, -1).
    window_s
        Seconds kept before and after the peak.
    whisker
        Whisker preset name.
    n_elements
        Rod discretisation.
    dt_s
        Internal time step (s); must divide the sensor's sample period
        (:func:`~vibrissa.whisker.hall.steps_per_sample`).
    sensor
        The Hall sensor's set-up: recording rate (``sensor.sample_rate_hz``),
        bandwidth, noise, ADC, supply, calibrated range and the (radius,
        deflection) of its calibration push (``sensor.calibration_mm``); calibrated
        on the nominal whisker before the session. Change some of it with
        :meth:`with_sensor`.
    drift_fraction
        Relative change of the whisker's Young's modulus and follicle stiffness from
        the first to the last trial of a session (0 = no drift). Default -0.05: the
        whisker softens by 5 % over a session; thesis 4.5 attributes its fitted,
        lower Young's modulus to "a softening over time through extended use", and
        4.2 interleaves the contacts randomly "to limit any affects of changing
        whisker properties".
    stage
        The robot and its MI controller.
    variability
        Physical trial-to-trial variability (:mod:`vibrissa.robots.xy_variability`):
        Hall offset and gain drift with room temperature, object placement within the
        stage's repeatability, Young's modulus with room temperature; each trial draws
        its own. Whisker creep is off here: it carries over from one contact to the
        next, which a generator simulating trials in parallel and resuming in any order
        cannot follow (its size between alternating contacts, below 1 mV, is under
        the sensor's 2 mV noise: ``robots.xy_variability``).
    seed
        Seed of everything random in the session.
    """

    name: str
    speeds_mm_s: tuple[float, ...]
    radial_distances_mm: tuple[float, ...] = ()
    angles_deg: tuple[float, ...] = ()
    textures: tuple[str, ...] = ()
    runs: int = 2
    directions: tuple[int, ...] = (1, -1)
    window_s: tuple[float, float] = (0.325, 0.325)
    whisker: str = "xy-robot"
    n_elements: int = 28
    dt_s: float = 2.5e-4
    sensor: HallSettings = field(default_factory=HallSettings)
    drift_fraction: float = -0.05
    stage: XYStage = field(default_factory=XYStage)
    variability: TrialVariability = field(default_factory=lambda: TrialVariability(creep=False))
    seed: int = 0

    def __post_init__(self) -> None:
        if self.name not in PROTOCOL_NAMES:
            raise ValueError(f"unknown protocol {self.name!r}; choose one of {PROTOCOL_NAMES}")
        if self.whisker not in PRESETS:
            raise ValueError(f"unknown whisker preset {self.whisker!r}")
        g = preset(self.whisker)
        if not self.speeds_mm_s:
            raise ValueError("speeds_mm_s: at least one speed is needed")
        for v in self.speeds_mm_s:
            self.stage.check_speed(v)
        if self.name == "radial-distance":
            if not self.radial_distances_mm:
                raise ValueError("radial_distances_mm: at least one radial distance is needed")
            for r in self.radial_distances_mm:
                in_range("radial_distance_mm", r, 1e-6, g.length_mm, "mm (the whisker's length)")
        else:
            if not self.angles_deg or not self.textures:
                raise ValueError("angles_deg and textures must not be empty")
            for a in self.angles_deg:
                in_range("angle_deg", a, 0.0, 90.0, "deg")
                if a in (0.0, 90.0):
                    raise ValueError(
                        "angle_deg: 0 and 90 deg are point contacts on the shaft, not "
                        "tip-surface contacts (thesis 5.2)"
                    )
            for t in self.textures:
                if t not in TEXTURES:
                    raise ValueError(f"unknown texture {t!r}; choose from {', '.join(TEXTURES)}")
        if (
            isinstance(self.seed, bool)
            or not isinstance(self.seed, int | np.integer)
            or self.seed < 0
        ):
            raise ValueError(f"seed must be a non-negative integer, got {self.seed!r}")
        if not isinstance(self.runs, int) or self.runs < 1:
            raise ValueError(f"runs must be a positive integer, got {self.runs!r}")
        if not self.directions or any(d not in (1, -1) for d in self.directions):
            raise ValueError(
                f"directions must be a non-empty subset of (1, -1), got {self.directions}"
            )
        positive("window before peak", self.window_s[0])
        positive("window after peak", self.window_s[1])
        if not isinstance(self.sensor, HallSettings):
            raise TypeError(f"sensor must be a HallSettings, got {type(self.sensor).__name__}")
        steps_per_sample(self.dt_s, self.sensor.sample_rate_hz)
        self.sensor.calibration_point(g)
        in_range("drift_fraction", self.drift_fraction, -0.5, 0.5)

    # ------------------------------------------------------------------ grid
    @property
    def label_names(self) -> tuple[str, ...]:
        """Names of the contact parameters varied by the grid."""
        if self.name == "radial-distance":
            return ("radial_distance_mm", "speed_mm_s")
        return ("angle_deg", "speed_mm_s", "texture")

    def grid(self) -> list[dict[str, Any]]:
        """The grid points in canonical order."""
        if self.name == "radial-distance":
            return [
                {"radial_distance_mm": r, "speed_mm_s": v}
                for v in self.speeds_mm_s
                for r in self.radial_distances_mm
            ]
        return [
            {"angle_deg": a, "speed_mm_s": v, "texture": t}
            for t in self.textures
            for v in self.speeds_mm_s
            for a in self.angles_deg
        ]

    @property
    def n_trials(self) -> int:
        """Total number of trials."""
        return len(self.grid()) * self.runs * len(self.directions)

    def trials(self) -> list[TrialSpec]:
        """Expand the grid into the session's trials (canonical order: set, then grid).

        Within each run the contacts of both directions are randomly interleaved
        (seeded), which fixes each trial's ``order`` in the session.
        """
        grid = self.grid()
        rng = np.random.default_rng(stream(self.seed, ORDER))
        nd = len(self.directions)
        per_run = len(grid) * nd
        specs: list[TrialSpec] = []
        idx = 0
        for run in range(1, self.runs + 1):
            perm = rng.permutation(per_run)
            for di, d in enumerate(self.directions):
                set_no = (run - 1) * nd + di + 1
                for gi, labels in enumerate(grid):
                    pos = int(perm[di * len(grid) + gi])
                    specs.append(
                        TrialSpec(idx, dict(labels), run, d, set_no, (run - 1) * per_run + pos)
                    )
                    idx += 1
        return specs

    # ------------------------------------------------------------------ identity
    def to_dict(self) -> dict[str, Any]:
        """Every parameter as plain JSON-compatible values."""
        d = dataclasses.asdict(self)
        d["stage"] = self.stage.to_dict()
        d["variability"] = self.variability.to_dict()
        return d

    def fingerprint(self) -> str:
        """Hash of every parameter that affects the generated signals."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()[:16]

    def with_overrides(self, **changes: Any) -> Protocol:
        """Copy with some fields replaced (validated again)."""
        return dataclasses.replace(self, **changes)

    def with_sensor(self, **changes: Any) -> Protocol:
        """Copy with some fields of :attr:`sensor` replaced (validated again).

        E.g. ``protocol.with_sensor(sample_rate_hz=2000.0, noise_v=0.0)``.
        """
        return dataclasses.replace(self, sensor=dataclasses.replace(self.sensor, **changes))


PROTOCOL_NAMES = ("radial-distance", "angle-texture")


#: Chapter-4 recording kept per trial, s before and after the peak. The thesis' own
#: +/-325 ms window about the peak (4.2) is cut from it by the classifiers that use it;
#: the author's analysis code instead cut 750 samples starting 100 samples before x
#: first exceeds 0.1 V, after filtering the velocity with a causal 101-tap FIR (see
#: docs/methods.md). The onset precedes the peak by at most the loop latency plus
#: braking (< 0.4 s), so 0.6 s before the peak holds that window and the filter's
#: 100-sample warm-up; 0.7 s after the peak holds the window's end.
RADIAL_DISTANCE_WINDOW_S = (0.6, 0.7)


def _radial_distance(quick: bool) -> Protocol:
    if quick:
        return Protocol(
            name="radial-distance",
            radial_distances_mm=parse_grid("80:180:25"),
            speeds_mm_s=parse_grid("36:216:#4"),
            sensor=HallSettings(calibration_mm=(80.0, 60.0)),
            window_s=RADIAL_DISTANCE_WINDOW_S,
        )
    return Protocol(
        name="radial-distance",
        window_s=RADIAL_DISTANCE_WINDOW_S,
        radial_distances_mm=parse_grid("80:180:1"),
        speeds_mm_s=parse_grid("36:216:#26"),
        # The Hall IC is re-programmable "to best suit the current experiment" (3.2.3);
        # with SCRATCHbot's calibration (60 mm at r = 150 mm) most of this grid would
        # saturate the sensor, so the session is calibrated at its closest contact.
        sensor=HallSettings(calibration_mm=(80.0, 60.0)),
    )


def _angle_texture(quick: bool) -> Protocol:
    common = dict(
        name="angle-texture",
        sensor=HallSettings(sample_rate_hz=4000.0),
        window_s=(0.75, 0.75),
        dt_s=1.25e-4,
        textures=("aluminium", "p600", "p180", "p80"),
    )
    if quick:
        return Protocol(angles_deg=(20.0, 50.0, 80.0), speeds_mm_s=(16.0, 56.0, 96.0), **common)
    return Protocol(angles_deg=parse_grid("10:80:10"), speeds_mm_s=parse_grid("6:106:10"), **common)


def get_protocol(name: str, quick: bool = False, **overrides: Any) -> Protocol:
    """The named protocol (``--quick``: a small grid for a run of under a minute).

    ``overrides`` replace fields (e.g. ``radial_distances_mm=parse_grid("80:180:20")``,
    ``seed=3``, ``sensor=HallSettings(...)``); ``None`` values are ignored. To change
    a few sensor settings, use :meth:`Protocol.with_sensor` on the result.
    """
    makers = {"radial-distance": _radial_distance, "angle-texture": _angle_texture}
    if name not in makers:
        raise ValueError(f"unknown protocol {name!r}; choose one of {', '.join(makers)}")
    base = makers[name](quick)
    changes = {k: v for k, v in overrides.items() if v is not None}
    return base.with_overrides(**changes) if changes else base
