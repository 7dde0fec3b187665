"""The Hall-effect sensor under the follicle's magnet (thesis 3.2.1, 3.2.3).

The MLX90333 was programmed to output two voltages linear in the tangents of the
magnet's two tilt angles (``x = tan(alpha)``, ``y = tan(beta)``), 2.5 V (50 % of
V_DD = 5 V) at rest, and scaled so that +/-60 mm applied at r = 150 mm spans
5-95 % of V_DD. Outside that range the output clamps: close contacts saturate
the sensor, as the thesis found (4.2).

:class:`HallSettings` is a sensor's set-up (rate, bandwidth, noise, ADC, supply,
calibrated range and calibration point); :meth:`HallSettings.calibrate` makes the
:class:`HallSensor` for a whisker. :func:`steps_per_sample` relates a
simulation's time step to the sample rate.

Signal chain modelled here, in order: the magnet's tangents at the simulation's
internal rate -> the sensor's own low-pass response (``bandwidth_hz``, a causal
2nd-order Butterworth, as the IC's output filter) -> additive white noise
(``noise_v`` rms) -> sampling at ``sample_rate_hz`` (the data-acquisition card, no
further anti-alias filter, as on the LabJack UE9) -> ADC quantisation
(``adc_bits`` over 0-5 V) -> clamping to the calibrated 5-95 % range.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
import scipy.signal

from vibrissa._validate import finite, in_range, non_negative, positive
from vibrissa.whisker.geometry import WhiskerGeometry

__all__ = [
    "CALIBRATION_DEFLECTION_MM",
    "CALIBRATION_RADIUS_MM",
    "HallSensor",
    "HallSettings",
    "calibrated_gain",
    "calibration_point_mm",
    "steps_per_sample",
]

CALIBRATION_RADIUS_MM = 150.0
CALIBRATION_DEFLECTION_MM = 60.0


def steps_per_sample(dt_s: float, sample_rate_hz: float) -> int:
    """Internal time steps per output sample, ``1 / (dt_s * sample_rate_hz)``.

    The one place that relates a simulation's time step to a recording's sample
    rate: the sensor keeps every ``steps_per_sample``-th internal step.

    Parameters
    ----------
    dt_s : float
        Internal time step of the simulation (s).
    sample_rate_hz : float
        Output sample rate (Hz).

    Returns
    -------
    int
        Steps per sample, at least 1.

    Raises
    ------
    ValueError
        If either is not positive, or ``dt_s`` does not divide the sample period
        ``1 / sample_rate_hz`` evenly (to a relative 1e-6): the internal rate
        ``1 / dt_s`` must be an integer multiple of the sample rate.
    """
    positive("dt_s", dt_s)
    positive("sample_rate_hz", sample_rate_hz)
    ratio = 1.0 / (dt_s * sample_rate_hz)
    step = int(round(ratio))
    if step < 1 or abs(ratio - step) > 1e-6 * ratio:
        raise ValueError(
            f"dt_s ({dt_s:g} s) must divide the sample period 1/{sample_rate_hz:g} s evenly "
            f"(the internal rate {1.0 / dt_s:g} Hz an integer multiple of the sample rate)"
        )
    return step


def _check_sensor_fields(s: HallSensor | HallSettings) -> None:
    """Validate the fields :class:`HallSensor` and :class:`HallSettings` share."""
    positive("sample_rate_hz", s.sample_rate_hz)
    if s.bandwidth_hz is not None:
        positive("bandwidth_hz", s.bandwidth_hz)
    non_negative("noise_v", s.noise_v)
    if not isinstance(s.adc_bits, int | np.integer) or not 0 <= s.adc_bits <= 24:
        raise ValueError(f"adc_bits must be an integer in [0, 24], got {s.adc_bits!r}")
    positive("supply_v", s.supply_v)
    finite("offset_v", s.offset_v)
    in_range("range_fraction", s.range_fraction, 0.0, 1.0)


@dataclass(frozen=True)
class HallSettings:
    """How a Hall sensor is set up for a session, before it is calibrated on a whisker.

    Everything of :class:`HallSensor` except the gain, plus where the gain is
    calibrated; :meth:`calibrate` turns it into the sensor for a given whisker.
    The defaults are the thesis' MLX90333 on a 5 V supply, 2.5 V at rest,
    calibrated to 5-95 % of V_DD, read by a 12-bit ADC at 1 kHz.

    Parameters
    ----------
    sample_rate_hz : float
        Output sample rate (Hz; the thesis used 1, 2 and 4 kHz).
    bandwidth_hz : float or None
        -3 dB bandwidth of the sensor's output filter (Hz); ``None`` means no filter.
    noise_v : float
        RMS white noise added before sampling (V).
    adc_bits : int
        ADC resolution over 0..supply_v; 0 disables quantisation.
    offset_v : float
        Output at rest (V).
    supply_v : float
        Supply voltage V_DD (V).
    range_fraction : float
        Fraction of V_DD spanned by the calibrated deflection, centred on the
        offset (0.9: 5-95 %).
    calibration_mm : tuple of float, optional
        (radius, deflection) in mm of the calibration push; ``None``:
        :func:`calibration_point_mm` of the whisker (the thesis' 60 mm at
        r = 150 mm, scaled for whiskers shorter than 185 mm). The MLX90333 is
        re-programmable "to best suit the current experiment" (3.2.3).
    """

    sample_rate_hz: float = 1000.0
    bandwidth_hz: float | None = 2000.0
    noise_v: float = 0.002
    adc_bits: int = 12
    offset_v: float = 2.5
    supply_v: float = 5.0
    range_fraction: float = 0.9
    calibration_mm: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        _check_sensor_fields(self)
        if self.calibration_mm is not None:
            if len(self.calibration_mm) != 2:
                raise ValueError(
                    "calibration_mm must be (radius, deflection) in mm, got "
                    f"{self.calibration_mm!r}"
                )
            object.__setattr__(self, "calibration_mm", tuple(float(v) for v in self.calibration_mm))
            positive("calibration radius", self.calibration_mm[0])
            positive("calibration deflection", self.calibration_mm[1])

    def calibration_point(self, geometry: WhiskerGeometry) -> tuple[float, float]:
        """Radius and deflection (mm) of the calibration push on ``geometry``.

        Raises
        ------
        ValueError
            If the radius lies beyond the whisker's length.
        """
        if self.calibration_mm is None:
            return calibration_point_mm(geometry)
        r, d = self.calibration_mm
        return in_range("calibration radius", r, 1e-6, geometry.length_mm, "mm"), d

    def calibrate(self, geometry: WhiskerGeometry, n_elements: int | None = None) -> HallSensor:
        """The sensor with these settings, its gain calibrated on ``geometry``.

        Parameters
        ----------
        geometry : WhiskerGeometry
            The whisker calibrated (the nominal one: calibration precedes a session).
        n_elements : int, optional
            Discretisation of the model used (default: the model's default).

        Returns
        -------
        HallSensor
        """
        gain = calibrated_gain(geometry, n_elements, self.calibration_point(geometry), self)
        return HallSensor(
            gain,
            sample_rate_hz=self.sample_rate_hz,
            bandwidth_hz=self.bandwidth_hz,
            noise_v=self.noise_v,
            adc_bits=self.adc_bits,
            offset_v=self.offset_v,
            supply_v=self.supply_v,
            range_fraction=self.range_fraction,
        )


@dataclass(frozen=True)
class HallSensor:
    """Two-axis Hall sensor with calibration, bandwidth, noise and ADC.

    Usually made by :meth:`HallSettings.calibrate`; the defaults are those of
    :class:`HallSettings`.

    Parameters
    ----------
    gain_v : float
        Volts per unit tangent of the magnet angle (from :func:`calibrated_gain`).
    sample_rate_hz : float
        Output sample rate (Hz; the thesis used 1, 2 and 4 kHz).
    bandwidth_hz : float or None
        -3 dB bandwidth of the sensor's output filter (Hz); ``None`` means no filter.
    noise_v : float
        RMS white noise added before sampling (V).
    adc_bits : int
        ADC resolution over 0..supply_v; 0 disables quantisation.
    offset_v : float
        Output at rest (V).
    supply_v : float
        Supply voltage V_DD (V).
    range_fraction : float
        Fraction of V_DD spanned by the calibrated deflection, centred on the offset.
    """

    gain_v: float
    sample_rate_hz: float = HallSettings.sample_rate_hz
    bandwidth_hz: float | None = HallSettings.bandwidth_hz
    noise_v: float = HallSettings.noise_v
    adc_bits: int = HallSettings.adc_bits
    offset_v: float = HallSettings.offset_v
    supply_v: float = HallSettings.supply_v
    range_fraction: float = HallSettings.range_fraction

    def __post_init__(self) -> None:
        positive("gain_v", self.gain_v)
        _check_sensor_fields(self)

    @property
    def v_min(self) -> float:
        """Lowest output (V): the calibrated range's lower end."""
        return self.offset_v - 0.5 * self.range_fraction * self.supply_v

    @property
    def v_max(self) -> float:
        """Highest output (V): the calibrated range's upper end."""
        return self.offset_v + 0.5 * self.range_fraction * self.supply_v

    def with_rate(self, sample_rate_hz: float) -> HallSensor:
        """Copy with another sample rate."""
        return replace(self, sample_rate_hz=sample_rate_hz)

    def ideal_volts(self, tan_xy: np.ndarray) -> np.ndarray:
        """Noise-free, unfiltered, clamped output for tangents ``tan_xy`` (..., 2)."""
        v = self.offset_v + self.gain_v * np.asarray(tan_xy, dtype=float)
        return np.clip(v, self.v_min, self.v_max)

    def read(
        self, tan_xy: np.ndarray, internal_rate_hz: float, rng: np.random.Generator | None = None
    ) -> np.ndarray:
        """Turn magnet tangents at the simulation rate into sampled sensor volts.

        Parameters
        ----------
        tan_xy
            Tangents of the magnet's tilt angles, shape ``(n_steps, 2)``, sampled at
            ``internal_rate_hz``.
        internal_rate_hz
            Rate of ``tan_xy``; must be an integer multiple of ``sample_rate_hz``.
        rng
            Generator for the noise (``None``: no noise).

        Returns
        -------
        numpy.ndarray
            Volts, shape ``(n_samples, 2)`` with ``n_samples = ceil(n_steps / step)``,
            ``step`` = :func:`steps_per_sample`.
        """
        t = np.asarray(tan_xy, dtype=float)
        if t.ndim != 2 or t.shape[1] != 2:
            raise ValueError(f"tan_xy must have shape (n_steps, 2), got {t.shape}")
        if not np.all(np.isfinite(t)):
            raise ValueError("tan_xy contains NaN or infinite values")
        step = steps_per_sample(
            1.0 / positive("internal_rate_hz", internal_rate_hz), self.sample_rate_hz
        )
        v = self.offset_v + self.gain_v * t
        if self.bandwidth_hz is not None and self.bandwidth_hz < 0.45 * internal_rate_hz:
            sos = scipy.signal.butter(2, self.bandwidth_hz, fs=internal_rate_hz, output="sos")
            zi = scipy.signal.sosfilt_zi(sos)[:, :, None] * v[0][None, None, :]
            v, _ = scipy.signal.sosfilt(sos, v, axis=0, zi=zi)
        v = v[::step]
        if rng is not None and self.noise_v > 0:
            v = v + rng.normal(0.0, self.noise_v, v.shape)
        if self.adc_bits:
            lsb = self.supply_v / (2**self.adc_bits)
            v = np.round(v / lsb) * lsb
        return np.clip(v, self.v_min, self.v_max)

    def to_dict(self) -> dict:
        """Parameters as a plain dict."""
        return {
            "gain_v": self.gain_v,
            "sample_rate_hz": self.sample_rate_hz,
            "bandwidth_hz": self.bandwidth_hz,
            "noise_v": self.noise_v,
            "adc_bits": self.adc_bits,
            "offset_v": self.offset_v,
            "supply_v": self.supply_v,
            "range_fraction": self.range_fraction,
        }


def calibration_point_mm(geometry: WhiskerGeometry) -> tuple[float, float]:
    """Radius and deflection (mm) of the calibration push for ``geometry``.

    The thesis' calibration is 60 mm at r = 150 mm (3.2.3). Whiskers shorter than
    185 mm are calibrated at the same fraction of their length (150/185) with the
    deflection scaled in proportion (60/150 of the radius).
    """
    r = min(CALIBRATION_RADIUS_MM, geometry.length_mm * CALIBRATION_RADIUS_MM / 185.0)
    return r, CALIBRATION_DEFLECTION_MM * r / CALIBRATION_RADIUS_MM


@lru_cache(maxsize=64)
def _gain_cached(
    geometry_json: str, n_elements: int, r: float, d: float, supply_v: float, range_fraction: float
) -> float:
    from vibrissa.whisker.rod import RodModel, SimulationError

    g = WhiskerGeometry.from_dict(json.loads(geometry_json))
    # small-deflection estimate of the tilt first: a shaft far more compliant than the
    # follicle bends without tilting it, and the push would not converge or read 0
    _check_tilt(_linear_tilt(g, r, d), r, d)
    model = RodModel(g, n_elements)
    try:
        res = model.push(r, d, friction=0.0)
    except SimulationError as exc:
        raise SimulationError(
            f"the Hall sensor's calibration push ({d:g} mm at r = {r:g} mm) failed: {exc}"
        ) from None
    tan = math.hypot(res.tan_x, res.tan_y)
    _check_tilt(tan, r, d)
    return 0.5 * range_fraction * supply_v / tan


#: Smallest follicle tilt (tan) a calibration push may give: below it the gain would
#: exceed 1e9 V per unit tan, and the follicle's tilt is lost in rounding.
MIN_CALIBRATION_TAN = 1e-9


def _linear_tilt(g: WhiskerGeometry, r_mm: float, d_mm: float) -> float:
    """Follicle tilt (tan) of a small-deflection push of ``d_mm`` at ``r_mm``.

    A force F at r tilts the follicle by F r / k_f and deflects the point by
    F (C + r^2 / k_f), with the shaft's compliance C = int_0^r (r - s)^2 / EI(s) ds.
    """
    r = r_mm * 1e-3
    s = np.linspace(0.0, r, 201)
    ei = g.youngs_modulus_gpa * 1e9 * np.pi * g.radius_m(s) ** 4 / 4
    c = float(np.trapezoid((r - s) ** 2 / ei, s))
    kf = g.follicle_stiffness_nm_per_rad
    return d_mm * 1e-3 * r / (kf * c + r * r)


def _check_tilt(tan: float, r: float, d: float) -> None:
    if not tan >= MIN_CALIBRATION_TAN:
        raise ValueError(
            f"the Hall sensor's calibration push ({d:g} mm at r = {r:g} mm) does not tilt "
            f"the follicle (tan = {tan:.3g}): the shaft is too compliant for the follicle's "
            "stiffness to be read; use a stiffer or thicker whisker (youngs_modulus_gpa, "
            "base_radius_mm)"
        )


def calibrated_gain(
    geometry: WhiskerGeometry,
    n_elements: int | None = None,
    calibration_mm: tuple[float, float] | None = None,
    sensor: HallSensor | HallSettings | None = None,
) -> float:
    """Hall gain (V per unit tan) that maps the calibration deflection to the sensor's range.

    Computed from the simulated whisker itself: a frictionless pole pushes the
    whisker by the calibration deflection at the calibration radius and the
    follicle's tilt is read. The gain puts that tilt at the edge of the sensor's
    calibrated range, ``range_fraction`` of ``supply_v`` centred on the offset
    (5-95 % of 5 V for the default sensor).

    Parameters
    ----------
    geometry : WhiskerGeometry
        The whisker calibrated.
    n_elements : int, optional
        Discretisation of the model used (default: the model's default).
    calibration_mm : tuple of float, optional
        (radius, deflection) in mm; default :func:`calibration_point_mm` (the
        thesis' 60 mm at r = 150 mm). The MLX90333 is re-programmable "to best suit
        the current experiment" (3.2.3), so protocols may calibrate elsewhere.
    sensor : HallSensor or HallSettings, optional
        The sensor whose ``supply_v`` and ``range_fraction`` the calibration spans
        (default: :class:`HallSettings` ()). Its ``calibration_mm`` is not read:
        pass the point as ``calibration_mm`` (or use :meth:`HallSettings.calibrate`).

    Returns
    -------
    float
        Gain (V per unit tangent of the magnet angle).
    """
    from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS

    if calibration_mm is None:
        r, d = calibration_point_mm(geometry)
    else:
        r = in_range("calibration radius", calibration_mm[0], 1e-6, geometry.length_mm, "mm")
        d = positive("calibration deflection", calibration_mm[1])
    s = HallSettings() if sensor is None else sensor
    return _gain_cached(
        geometry.to_json(),
        int(n_elements or DEFAULT_N_ELEMENTS),
        r,
        d,
        float(s.supply_v),
        float(s.range_fraction),
    )
