"""Trial-to-trial variability of the XY robot from physical sources (issue 30, item 2).

The simulated XY robot repeats a contact far more cleanly than the real one: only
the Hall sensor's white noise, the 12-bit ADC and the controller's timer jitter
vary between repeats. This module draws, for each trial, the slow physical
perturbations a real session adds, each from a cited value (:data:`SOURCES`) and
each switchable (:class:`TrialVariability`):

``hall_drift``
    The Hall IC's offset and sensitivity drift with the room's temperature. The
    thesis' whisker is read by a Melexis MLX90333 Triaxis IC (thesis 3.2.3,
    :mod:`vibrissa.whisker.hall`). Its joystick outputs are computed from *ratios*
    of field components (the DSP's angle decoupling, 3.2.3), so the magnet's
    reversible temperature coefficient of remanence (NdFeB about -0.12 %/K)
    cancels to first order; what remains is the IC's thermal offset drift of the
    analog output stage and its sensitivity-mismatch drift. A non-ratiometric
    (linear) Hall sensor would see the magnet's coefficient in full
    (``hall_ratiometric=False``).
``creep``
    Viscoelastic creep of the whisker under each contact and its recovery between
    contacts: a residual rest-angle offset in the direction of the previous
    deflections. The shaft's creep compliance is a log-uniform retardation
    spectrum (one Kelvin element per decade of time, ``creep_per_decade`` of
    the elastic compliance each), so a single contact's residual relaxes within
    seconds while unilateral repeats accumulate over hours (why the thesis
    alternated directions, 4.2, 5.2).
``placement``
    The object's start position along the motion axis ``x`` and along the whisker
    ``z``, within the robot's repeatability (+/-0.01 mm, thesis 3.3, read as a
    3-sigma band per axis).
``modulus``
    The shaft's Young's modulus changing with the room's temperature (the same
    temperature draw as ``hall_drift``).

The room's temperature during a trial, relative to the temperature at which the
sensor was calibrated, is drawn per trial from ``N(0, room_temperature_sd_k)``:
the thesis interleaved its contact combinations randomly over a session of hours
(4.2, 5.2), so a condition's repeats meet independent room temperatures.

:class:`VariabilityState` carries the creep memory from trial to trial and draws
one :class:`TrialPerturbation` per trial. The module only draws the numbers; where
each enters the simulation (sensor volts, contact point, start position, modulus)
is up to the caller (``experiments`` / :func:`~vibrissa.robots.xy_stage.run_trial`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from vibrissa._validate import finite, in_range, non_negative, positive

__all__ = [
    "SOURCES",
    "TrialPerturbation",
    "TrialVariability",
    "VariabilityState",
]

#: Names of the variability sources, in the order :meth:`TrialVariability.enabled` lists them.
SOURCE_NAMES: tuple[str, ...] = ("hall_drift", "creep", "placement", "modulus")

#: Where each default of :class:`TrialVariability` comes from.
SOURCES: dict[str, dict[str, str]] = {
    "hall_drift": {
        "sensor": "Melexis MLX90333 Triaxis 3D-joystick position sensor (thesis 3.2.3).",
        "hall_offset_tc_v_per_k": (
            "MLX90333 datasheet (Melexis 3901090333), accuracy specification: thermal "
            "offset drift of the DAC and output stage +/-0.3 % of VDD over the operating "
            "range (-40..150 C, i.e. up to 125 K from the 25 C trim point): "
            "0.003 * 5 V / 125 K = 1.2e-4 V/K, taken as the worst-case slope with the "
            "same sign on both axes (a device's sign is unknown). Value as recalled from "
            "the datasheet; not re-read from the document in this session."
        ),
        "hall_gain_tc_per_k": (
            "MLX90333 datasheet: thermal drift of the sensitivity mismatch between the "
            "in-plane (IMC) and vertical Hall channels +/-0.5 % over the operating "
            "range: 0.005 / 125 K = 4e-5 per K. In joystick mode tan(alpha) is the ratio "
            "of an in-plane to the vertical component, so this mismatch is the output's "
            "gain drift. Value as recalled; not re-read in this session."
        ),
        "magnet_tc_per_k": (
            "Reversible temperature coefficient of remanence of sintered NdFeB, "
            "about -0.12 %/K (magnet manufacturers' data, e.g. grades N35-N52: "
            "-0.11 to -0.12 %/K). Cancels in the Triaxis ratiometric angle output; "
            "enters the gain only with hall_ratiometric=False."
        ),
        "room_temperature_sd_k": (
            "Assumed 1.0 K: an air-conditioned laboratory within ANSI/ASHRAE Standard 55 "
            "(2004, 5.2.5: operative-temperature drifts at most 1.1 K in 15 min, 2.2 K in "
            "1 h, 3.3 K in 4 h), over a session of hours (chapter 4: 2 x 2626 contacts "
            "of 4 s per run, 3.3.1, 4.2). The thesis gives no room temperature."
        ),
    },
    "creep": {
        "material": (
            "The XY-robot whisker is FDM-built ABS (thesis 4.5: 'manufacturing precision "
            "of ABS plastic', 'built up of layers of ABS'; 3.2.3). Nanocure RC25 (3.2.2) "
            "is the G1 and CrunchBot whiskers' acrylate; a cured acrylate below its Tg "
            "creeps in the same class (a few % of compliance per decade)."
        ),
        "creep_per_decade": (
            "Class value for ABS at 23 C at low stress: creep-modulus curves of "
            "ISO 899-1 tests in ABS producers' data fall from about 2.1 GPa at 1 h to "
            "about 1.7 GPa at 1000 h, i.e. creep compliance growing 5-8 % per decade of "
            "time; 0.06 per decade is used (a class value, not a measurement of the "
            "thesis' whisker). Linear viscoelasticity (Boltzmann superposition; "
            "Findley, Lai & Onaran 1976, 'Creep and relaxation of nonlinear viscoelastic "
            "materials', ch. 5) at the whisker's strains (< 0.5 %)."
        ),
        "creep_times_s": (
            "One Kelvin element per decade from 0.1 s to 1e5 s (about a day, longer than "
            "any session): a log-uniform retardation spectrum, the Prony-series form of a "
            "compliance growing by a constant amount per decade."
        ),
        "creep_contact_s": (
            "Effective full-load time of one MI contact: 2/pi (a half-sine's mean) of the "
            "thesis' ~300 ms contact duration (5.5): 0.19 s."
        ),
    },
    "placement": {
        "repeatability_mm": (
            "Yamaha PXYX repeatability +/-0.01 mm (thesis 3.3), read as a +/-3 sigma "
            "band per axis (sigma = 0.0033 mm), the convention of ISO 9283 pose "
            "repeatability (mean + 3 standard deviations). No defensible value was found "
            "for the stimulus mount's play (the thesis describes the chapter-5 stimulus "
            "as an aluminium strip on a pole, 5.2, and not the chapter-4 object), so "
            "only the repeatability is modelled."
        ),
    },
    "modulus": {
        "modulus_tc_per_k": (
            "Class value for ABS below its glass transition (~105 C): the storage modulus "
            "of DMA curves falls by about 0.3-0.5 %/K between 20 and 60 C; -0.4 %/K is "
            "used. Same room temperature as hall_drift."
        ),
    },
}


def _bool(name: str, value: Any) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"{name} must be a bool, got {value!r}")
    return bool(value)


@dataclass(frozen=True)
class TrialVariability:
    """Which physical sources of trial-to-trial variability are on, and their parameters.

    Defaults are the cited values of :data:`SOURCES`, every source on; :meth:`off`
    switches all of them off.

    Parameters
    ----------
    hall_drift : bool
        Hall sensor offset and gain drift with the room's temperature.
    creep : bool
        Whisker creep under contacts and recovery between them.
    placement : bool
        Object start-position scatter within the robot's repeatability.
    modulus : bool
        Shaft Young's modulus changing with the room's temperature.
    room_temperature_sd_k : float
        Standard deviation (K) of the room's temperature during a trial about the
        calibration temperature (``hall_drift`` and ``modulus``).
    hall_offset_tc_v_per_k : float
        Output offset drift of each Hall channel (V/K).
    hall_gain_tc_per_k : float
        Relative drift of the Hall output's gain (1/K).
    magnet_tc_per_k : float
        Reversible temperature coefficient of the magnet's remanence (1/K).
    hall_ratiometric : bool
        True (the MLX90333): the output is a ratio of field components and the
        magnet's coefficient cancels; False: it scales the gain.
    creep_per_decade : float
        Creep compliance added per decade of time, as a fraction of the elastic
        compliance (each Kelvin element's amplitude), in [0, 1).
    creep_times_s : tuple of float
        Retardation times (s) of the Kelvin elements, positive, distinct.
    creep_contact_s : float
        Effective time (s) a contact holds the whisker at its peak deflection.
    repeatability_mm : float
        The robot's repeatability (mm), a +/-3 sigma band per axis.
    modulus_tc_per_k : float
        Relative change of the shaft's Young's modulus per kelvin (1/K).
    """

    hall_drift: bool = True
    creep: bool = True
    placement: bool = True
    modulus: bool = True
    room_temperature_sd_k: float = 1.0
    hall_offset_tc_v_per_k: float = 0.003 * 5.0 / 125.0
    hall_gain_tc_per_k: float = 0.005 / 125.0
    magnet_tc_per_k: float = -0.0012
    hall_ratiometric: bool = True
    creep_per_decade: float = 0.06
    creep_times_s: tuple[float, ...] = (0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5)
    creep_contact_s: float = 2.0 / math.pi * 0.3
    repeatability_mm: float = 0.01
    modulus_tc_per_k: float = -0.004

    def __post_init__(self) -> None:
        for name in (*SOURCE_NAMES, "hall_ratiometric"):
            _bool(name, getattr(self, name))
        non_negative("room_temperature_sd_k", self.room_temperature_sd_k)
        finite("hall_offset_tc_v_per_k", self.hall_offset_tc_v_per_k)
        in_range("hall_gain_tc_per_k", self.hall_gain_tc_per_k, -0.01, 0.01, "1/K")
        in_range("magnet_tc_per_k", self.magnet_tc_per_k, -0.01, 0.01, "1/K")
        in_range("creep_per_decade", self.creep_per_decade, 0.0, 1.0 - 1e-12)
        times = tuple(float(positive("creep_times_s", t)) for t in self.creep_times_s)
        if not times:
            raise ValueError("creep_times_s must hold at least one retardation time")
        if len(set(times)) != len(times):
            raise ValueError(f"creep_times_s must be distinct, got {self.creep_times_s!r}")
        object.__setattr__(self, "creep_times_s", times)
        positive("creep_contact_s", self.creep_contact_s)
        non_negative("repeatability_mm", self.repeatability_mm)
        in_range("modulus_tc_per_k", self.modulus_tc_per_k, -0.05, 0.05, "1/K")

    @classmethod
    def off(cls) -> TrialVariability:
        """Every source switched off (the default parameters kept)."""
        return cls(**dict.fromkeys(SOURCE_NAMES, False))

    def enabled(self) -> tuple[str, ...]:
        """Names of the sources switched on, in :data:`SOURCE_NAMES` order."""
        return tuple(n for n in SOURCE_NAMES if getattr(self, n))

    @property
    def position_sd_mm(self) -> float:
        """Standard deviation (mm) of the start position per axis: repeatability / 3."""
        return self.repeatability_mm / 3.0

    @property
    def gain_tc_per_k(self) -> float:
        """Relative gain drift of the sensor's output per kelvin (1/K)."""
        magnet = 0.0 if self.hall_ratiometric else self.magnet_tc_per_k
        return self.hall_gain_tc_per_k + magnet

    def to_dict(self) -> dict[str, Any]:
        """Parameters as a plain, JSON-ready dict, with ``enabled``."""
        d = dataclasses.asdict(self)
        d["creep_times_s"] = list(self.creep_times_s)
        d["enabled"] = list(self.enabled())
        return d


def _vec2(name: str, value: Any) -> np.ndarray:
    arr = np.array(value, dtype=float).reshape(-1)
    if arr.shape != (2,):
        raise ValueError(f"{name} must have shape (2,), got {np.shape(value)}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class TrialPerturbation:
    """What one trial gets from the physical variability sources.

    Frames: ``x`` and ``y`` are the Hall sensor's (and the lab's) axes, with the
    object moving along ``x``; a trial simulated mirrored (``direction = -1`` in
    :func:`~vibrissa.robots.xy_stage.run_trial`) must mirror the ``x`` components.

    Parameters
    ----------
    sensor_offset_v : numpy.ndarray
        Shape (2,): added to the sensor's x and y outputs (V), on top of its 2.5 V.
    sensor_gain : float
        Factor on the sensor's gain (V per unit tan); 1 is nominal.
    rest_angle_rad : numpy.ndarray
        Shape (2,): the whisker's residual rest-direction offset (rad) from creep,
        about x (tilt toward +x) and y, in units of the deflection angle the
        previous contacts imposed (see :class:`VariabilityState`).
    position_offset_mm : numpy.ndarray
        Shape (2,): the object's start-position error (mm) along the motion axis
        ``x`` and along the whisker ``z`` (the radial distance of a pole contact).
    modulus_factor : float
        Factor on the shaft's Young's modulus; 1 is nominal.
    temperature_k : float
        The room's temperature for this trial relative to calibration (K), the draw
        behind ``sensor_offset_v``, ``sensor_gain`` and ``modulus_factor``.
    """

    sensor_offset_v: np.ndarray
    sensor_gain: float
    rest_angle_rad: np.ndarray
    position_offset_mm: np.ndarray
    modulus_factor: float
    temperature_k: float = 0.0

    __hash__: ClassVar[None] = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        object.__setattr__(self, "sensor_offset_v", _vec2("sensor_offset_v", self.sensor_offset_v))
        object.__setattr__(self, "rest_angle_rad", _vec2("rest_angle_rad", self.rest_angle_rad))
        object.__setattr__(
            self, "position_offset_mm", _vec2("position_offset_mm", self.position_offset_mm)
        )
        object.__setattr__(self, "sensor_gain", positive("sensor_gain", self.sensor_gain))
        object.__setattr__(self, "modulus_factor", positive("modulus_factor", self.modulus_factor))
        object.__setattr__(self, "temperature_k", finite("temperature_k", self.temperature_k))

    @classmethod
    def none(cls) -> TrialPerturbation:
        """No perturbation: zero offsets, unit factors."""
        return cls(np.zeros(2), 1.0, np.zeros(2), np.zeros(2), 1.0, 0.0)

    def __eq__(self, other: object) -> bool:
        """Field-by-field exact equality (arrays compared element-wise)."""
        if not isinstance(other, TrialPerturbation):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, f.name), getattr(other, f.name))
            for f in dataclasses.fields(self)
        )

    def to_dict(self) -> dict[str, Any]:
        """The fields as plain floats and lists."""
        return {
            f.name: (v.tolist() if isinstance(v := getattr(self, f.name), np.ndarray) else v)
            for f in dataclasses.fields(self)
        }


class VariabilityState:
    """A session's variability: the creep memory carried from trial to trial.

    The creep compliance is a Prony series, ``J(t) / J_0 = 1 + sum_k a (1 -
    exp(-t / tau_k))`` with ``a = creep_per_decade`` and ``tau_k =
    creep_times_s``. Each element's strain ``x_k`` (in units of the contact's
    peak angle) obeys ``tau_k dx_k/dt = a s(t) - x_k`` with the load ``s`` = the
    signed peak angle during a contact (for ``creep_contact_s``) and 0 between
    contacts. So after a contact ``x_k`` has moved toward ``a s`` by the factor
    ``1 - exp(-creep_contact_s / tau_k)``, and over an interval it decays exactly
    as ``exp(-interval_s / tau_k)``. The residual rest angle is ``sum_k x_k``;
    alternating directions cancel it, unilateral repeats build it up.

    Parameters
    ----------
    variability : TrialVariability
        The sources and their parameters (default: all on, cited values).
    """

    def __init__(self, variability: TrialVariability | None = None) -> None:
        self.variability = TrialVariability() if variability is None else variability
        if not isinstance(self.variability, TrialVariability):
            raise TypeError(
                f"variability must be a TrialVariability, got {type(self.variability).__name__}"
            )
        self._tau_s = np.asarray(self.variability.creep_times_s, dtype=float)
        self._memory = np.zeros_like(self._tau_s)

    @property
    def creep_memory(self) -> np.ndarray:
        """Each Kelvin element's strain (rad of rest angle along x), a copy."""
        return self._memory.copy()

    def residual_rest_angle_rad(self) -> float:
        """The rest-angle offset along x (rad) the creep memory gives now."""
        return float(self._memory.sum())

    def load(self, peak_tan: float, direction: int) -> None:
        """Apply one contact's load: ``peak_tan`` toward ``direction`` for ``creep_contact_s``.

        Parameters
        ----------
        peak_tan : float
            Peak tangent of the contact's deflection angle (>= 0).
        direction : int
            +1 or -1, the direction of the deflection along x; 0 for no contact.
        """
        p = non_negative("previous_peak_tan", peak_tan)
        if direction not in (-1, 0, 1) or isinstance(direction, bool):
            raise ValueError(f"previous_direction must be -1, 0 or +1, got {direction!r}")
        if direction == 0 or not self.variability.creep:
            return
        target = self.variability.creep_per_decade * math.atan(p) * direction
        frac = -np.expm1(-self.variability.creep_contact_s / self._tau_s)
        self._memory += (target - self._memory) * frac

    def relax(self, interval_s: float) -> None:
        """Let the creep memory recover for ``interval_s`` seconds without load."""
        dt = non_negative("interval_s", interval_s)
        self._memory *= np.exp(-dt / self._tau_s)

    def draw(
        self,
        rng: np.random.Generator,
        *,
        previous_peak_tan: float,
        previous_direction: int,
        interval_s: float,
    ) -> TrialPerturbation:
        """The perturbation of the next trial.

        Applies the previous contact's load to the creep memory, lets it recover over
        ``interval_s`` and draws the trial's room temperature and position error.
        Always consumes three standard normals from ``rng`` (temperature, x, z),
        whichever sources are on, so switching one source leaves the others' draws
        unchanged.

        Parameters
        ----------
        rng : numpy.random.Generator
            The trial's random stream.
        previous_peak_tan : float
            Peak tangent of the previous contact's deflection angle, |V_x - 2.5 V| /
            gain at the peak (>= 0; ignored when ``previous_direction`` is 0).
        previous_direction : int
            +1 or -1, the previous contact's deflection direction along x (the robot's
            motion direction); 0 for the session's first trial.
        interval_s : float
            Time (s) from the end of the previous contact to this trial's contact
            (about the 4 s trial length, thesis 3.3.1).

        Returns
        -------
        TrialPerturbation
        """
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        self.load(previous_peak_tan, previous_direction)
        self.relax(interval_s)
        z = rng.standard_normal(3)
        v = self.variability
        temp = v.room_temperature_sd_k * float(z[0]) if (v.hall_drift or v.modulus) else 0.0
        if v.hall_drift:
            offset = np.full(2, v.hall_offset_tc_v_per_k * temp)
            gain = 1.0 + v.gain_tc_per_k * temp
        else:
            offset, gain = np.zeros(2), 1.0
        rest = np.array([self.residual_rest_angle_rad(), 0.0]) if v.creep else np.zeros(2)
        pos = v.position_sd_mm * z[1:] if v.placement else np.zeros(2)
        modulus = 1.0 + v.modulus_tc_per_k * temp if v.modulus else 1.0
        return TrialPerturbation(
            sensor_offset_v=offset,
            sensor_gain=gain,
            rest_angle_rad=rest,
            position_offset_mm=pos,
            modulus_factor=modulus,
            temperature_k=temp,
        )
