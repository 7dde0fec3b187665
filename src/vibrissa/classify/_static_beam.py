"""Radial distance from the static beam equation (thesis 4.3.1, eqs. 4.1-4.2)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from vibrissa import signal as vsig
from vibrissa.classify import _kernels
from vibrissa.classify._base import (
    EstimatorTags,
    TrialClassifier,
    nearest_values,
    target_column,
)
from vibrissa.data.schema import parse_whisker

__all__ = [
    "ANGLE_MODES",
    "DEFAULT_SPEED_MM_S",
    "StaticBeamClassifier",
    "base_moment_nm",
    "beam_radius_at_angle_mm",
    "oracle_protraction_angle_rad",
    "static_beam_radius_mm",
    "thesis_parameter_grid",
]

#: Grid points whose training error is within this of the smallest are ties, mm.
_TIE_MM = 1e-9

#: Median of the chapter-4 speed grid (36-216 mm/s), used when no speed is known.
DEFAULT_SPEED_MM_S = 126.0

#: Values of ``StaticBeamClassifier(angle=...)``: one assumed speed for every trial, or
#: the thesis author's oracle angle from each trial's true speed and radial distance.
ANGLE_MODES = ("fixed_speed", "oracle")

_REQUIRED_KEYS = (
    "length_mm",
    "base_radius_mm",
    "youngs_modulus_gpa",
    "follicle_stiffness_nm_per_rad",
    "hall_gain_v",
)


def thesis_parameter_grid() -> dict[str, np.ndarray]:
    """The brute-force grid of thesis 4.3.1.

    ``E`` 0.5-3 GPa in steps of 0.1, base radius 0.5-1.5 mm in steps of 0.1,
    length 170-240 mm in steps of 5, and the scaling factor ``S_f``
    0.0005-0.005 in steps of 0.0005. The thesis' ``S_f`` converts raw volts to a
    moment and its measured value was 0.0031; here the moment already comes from
    the calibrated sensor model, so the grid holds the relative factor
    ``S_f / 0.0031`` (0.16-1.61; 1 = the measured calibration).

    Returns
    -------
    dict of str to ndarray
        Keys ``youngs_modulus_gpa``, ``base_radius_mm``, ``length_mm``, ``moment_scale``.
    """
    return {
        "youngs_modulus_gpa": np.round(np.arange(5, 31) * 0.1, 10),
        "base_radius_mm": np.round(np.arange(5, 16) * 0.1, 10),
        "length_mm": np.arange(170.0, 241.0, 5.0),
        "moment_scale": np.arange(1, 11) * 0.0005 / 0.0031,
    }


def _whisker_dict(whisker: Any) -> dict[str, Any]:
    if whisker is None:
        raise ValueError(
            "whisker is required: a dict (or JSON string, the Dataset attr 'whisker') with "
            f"keys {list(_REQUIRED_KEYS)} and optionally 'hall_offset_v'"
        )
    if isinstance(whisker, str):
        whisker = parse_whisker(whisker)
    if not isinstance(whisker, Mapping):
        raise TypeError(f"whisker must be a dict or JSON string, got {type(whisker).__name__}")
    missing = [k for k in _REQUIRED_KEYS if k not in whisker]
    if missing:
        raise ValueError(f"whisker is missing key(s) {missing}")
    out = dict(whisker)
    for k in (*_REQUIRED_KEYS, "hall_offset_v"):
        if k in out:
            v = out[k]
            if isinstance(v, bool) or not isinstance(v, int | float | np.number):
                raise ValueError(f"whisker[{k!r}] must be a number, got {v!r}")
            if not math.isfinite(float(v)) or (k != "hall_offset_v" and float(v) <= 0):
                raise ValueError(f"whisker[{k!r}] must be finite and positive, got {v!r}")
    return out


def base_moment_nm(
    peak_deflection_v: np.ndarray, hall_gain_v: float, follicle_stiffness_nm_per_rad: float
) -> np.ndarray:
    """Base bending moment from the peak Hall-sensor deflection.

    The sensor reads ``V = hall_offset_v + hall_gain_v * tan(phi)`` with ``phi``
    the follicle (magnet) angle, and the follicle is a rotational spring, so
    ``M = follicle_stiffness * arctan(dV / hall_gain_v)``.

    Parameters
    ----------
    peak_deflection_v : ndarray
        ``|V - hall_offset_v|`` at peak deflection, V.
    hall_gain_v : float
        Volts per unit ``tan(phi)``.
    follicle_stiffness_nm_per_rad : float
        N m / rad.

    Returns
    -------
    ndarray
        Base moment, N m.
    """
    return follicle_stiffness_nm_per_rad * np.arctan(np.asarray(peak_deflection_v) / hall_gain_v)


def static_beam_radius_mm(
    moment_nm: np.ndarray,
    protraction_mm: float,
    youngs_modulus_gpa: float,
    base_radius_mm: float,
    length_mm: float,
) -> np.ndarray:
    """Radial distance from eq. 4.1 with the protraction angle ``theta = d / r``.

    Eq. 4.1, ``r = C theta L / (C theta + M L)`` with ``C = 3 E I_base / 4`` and
    ``I_base = pi r_base^4`` (eq. 4.2; i.e. ``C = 3 E I`` with the usual
    ``I = pi r_base^4 / 4``). The angle is that of the protraction distance ``d``
    seen from the base, ``theta = d / r`` (as in the thesis author's code), which
    makes eq. 4.1 a quadratic in ``r``, ``M L r^2 + C d r - C d L = 0``, whose
    positive root is ``r = 2 L / (1 + sqrt(1 + 4 q))`` with ``q = M L^2 / (C d)``.
    ``M = 0`` gives ``r = L`` (a tip contact).

    Parameters
    ----------
    moment_nm : ndarray
        Base moment at peak deflection, N m (>= 0).
    protraction_mm : float
        Distance the object travels into the whisker, mm.
    youngs_modulus_gpa, base_radius_mm, length_mm : float
        Beam parameters.

    Returns
    -------
    ndarray
        Radial distance, mm, in ``(0, length_mm]``.
    """
    c = 3.0 * youngs_modulus_gpa * 1e9 * math.pi * (base_radius_mm * 1e-3) ** 4 / 4.0
    L = length_mm * 1e-3
    q = np.asarray(moment_nm, dtype=float) * L * L / (c * protraction_mm * 1e-3)
    return 2.0 * length_mm / (1.0 + np.sqrt(1.0 + 4.0 * q))


def oracle_protraction_angle_rad(
    speed_mm_s: Any, radius_mm: Any, latency_s: float = 0.3
) -> np.ndarray:
    """The thesis author's protraction angle, from each trial's true speed and radial distance.

    The object travels ``d = speed x latency`` into the whisker during the
    controller's loop latency, and the angle is that distance seen from the base
    at the true contact point, ``theta = d / r``. This is an *oracle*: it needs the
    very radial distance the classifier is to estimate (and the speed, which the
    static beam cannot estimate, 4.3.6).

    Parameters
    ----------
    speed_mm_s : array-like
        True contact speed of each trial, mm/s (> 0).
    radius_mm : array-like
        True radial distance of each trial, mm (> 0); broadcast against ``speed_mm_s``.
    latency_s : float, default=0.3
        Protraction duration, s (> 0).

    Returns
    -------
    ndarray
        ``theta``, rad.
    """
    speed = np.asarray(speed_mm_s, dtype=float)
    radius = np.asarray(radius_mm, dtype=float)
    lat = float(latency_s)
    if not math.isfinite(lat) or lat <= 0:
        raise ValueError(f"latency_s must be positive, got {latency_s!r}")
    if not np.all(np.isfinite(speed)) or np.any(speed <= 0):
        raise ValueError("speed_mm_s must be finite and positive")
    if not np.all(np.isfinite(radius)) or np.any(radius <= 0):
        raise ValueError("radius_mm must be finite and positive")
    return speed * lat / radius


def beam_radius_at_angle_mm(
    moment_nm: Any,
    theta_rad: Any,
    youngs_modulus_gpa: float,
    base_radius_mm: float,
    length_mm: float,
) -> np.ndarray:
    """Radial distance from eq. 4.1 with a known protraction angle.

    ``r = C theta L / (C theta + M L)`` with ``C = 3 E I_base / 4`` and
    ``I_base = pi r_base^4`` (eq. 4.2), i.e. ``r = L / (1 + M L / (C theta))``.
    With ``theta = d / r`` at the root ``r`` of :func:`static_beam_radius_mm`, it
    returns that root.

    Parameters
    ----------
    moment_nm : array-like
        Base moment at peak deflection, N m (>= 0).
    theta_rad : array-like
        Protraction angle of each trial, rad (> 0); broadcast against ``moment_nm``.
    youngs_modulus_gpa, base_radius_mm, length_mm : float
        Beam parameters.

    Returns
    -------
    ndarray
        Radial distance, mm, in ``(0, length_mm]``.
    """
    c = 3.0 * youngs_modulus_gpa * 1e9 * math.pi * (base_radius_mm * 1e-3) ** 4 / 4.0
    m = np.asarray(moment_nm, dtype=float)
    theta = np.asarray(theta_rad, dtype=float)
    return length_mm / (1.0 + m * (length_mm * 1e-3) / (c * theta))


class StaticBeamClassifier(TrialClassifier):
    """Radial distance from the base moment with the static beam equation (thesis 4.3.1).

    For each trial the peak deflection ``|V - hall_offset_v|`` of the deflection
    channel (the operation of eq. 4.5) is turned into the base bending moment
    ``M`` through the sensor and follicle model (see :func:`base_moment_nm`), and
    eq. 4.1 with ``C`` from eq. 4.2 gives the radial distance (see
    :func:`static_beam_radius_mm`), which is snapped to the nearest radial-distance
    class seen in training (the thesis rounds to the nearest mm).

    **Protraction angle.** The thesis obtains ``theta`` from the robot's known
    motion: protraction lasts the controller's ~0.3 s loop latency, so the object
    travels ``d = speed x 0.3 s``, and ``theta = d / r``. The thesis author's code
    evaluates this with the *true* speed and radial distance of each test trial,
    which a classifier cannot know. Here the speed is unknown at test time, so
    ``d = speed_mm_s x latency_s`` uses one fixed speed: by default the median of
    the training speeds (the thesis' errors are smallest at the median speed and
    grow away from it, 4.4.1, which is what a fixed speed produces), and
    ``theta = d / r`` is solved jointly with eq. 4.1 for the unknown ``r``.

    **The author's oracle angle** (``angle="oracle"``). To reproduce the thesis
    author's numbers, ``angle="oracle"`` takes ``theta`` from each trial's *true*
    speed and radial distance (:func:`oracle_protraction_angle_rad`): ``fit`` reads
    them from ``y`` (speed in ``speed_column``; the parameter search of
    ``fit_parameters=True`` is then done under that angle), and the trials to
    classify need theirs too, so :meth:`predict`, :meth:`predict_proba`,
    :meth:`score` and :meth:`predict_radius_mm` refuse, and
    :meth:`predict_with_oracle_angle` takes them explicitly. It is not a
    classifier of unknown contacts: it shows what the angle is worth.

    **Speed.** The method cannot estimate speed (4.3.6). ``classes_`` holds the
    distinct radial distances; for a 2-D ``y`` its rows carry the radial distance
    in ``radius_column`` and NaN in every other column, so :meth:`predict` returns
    rows of the shape of ``y`` with NaN speed, and :meth:`score` ignores the NaN
    columns.

    Parameters
    ----------
    whisker : dict or str or None, default=None
        Measured whisker parameters (dict, or the JSON of the Dataset attr
        ``whisker``): ``length_mm``, ``base_radius_mm``, ``youngs_modulus_gpa``,
        ``follicle_stiffness_nm_per_rad``, ``hall_gain_v`` (V per unit tan angle),
        optional ``hall_offset_v`` (default 2.5). Required.
    fit_parameters : bool, default=False
        ``False``: use the measured parameters. ``True``: brute-force search of
        ``param_grid`` (default the thesis' grid, :func:`thesis_parameter_grid`) for
        the ``E``, base radius, length and moment scale with the smallest mean
        absolute radial-distance error on the training data (ties go to the
        combination closest to the measured values).
    param_grid : dict or None, default=None
        Grid for ``fit_parameters=True``; keys as in :func:`thesis_parameter_grid`
        (missing keys are held at the measured value, scale 1).
    channel : int, default=0
        Channel carrying the deflection (``x``).
    radius_column, speed_column : int, default=0, 1
        Columns of a 2-D ``y`` with the radial distance (mm) and speed (mm/s).
        A 1-D ``y`` is the radial distance.
    speed_mm_s : float or None, default=None
        Assumed contact speed, mm/s. ``None``: median of the training speeds, or
        :data:`DEFAULT_SPEED_MM_S` (126 mm/s) when ``y`` has no speed column.
    latency_s : float, default=0.3
        Protraction duration (controller loop latency), s.
    angle : {"fixed_speed", "oracle"}, default="fixed_speed"
        How ``theta`` is obtained (see above): from one assumed speed
        (``speed_mm_s``), or the author's oracle from each trial's true speed and
        radial distance (``speed_mm_s`` is then ignored).
    sample_rate_hz : float or None, default=None
        Sample rate of the trials, Hz. The method does not use it (the peak of a
        trial is the same at any rate); when given, data at another rate are
        refused, and ``fit`` records the rate it is given (``sample_rate_hz_``).

    Attributes
    ----------
    classes_ : ndarray of shape (n_radii,) or (n_radii, n_targets)
        Distinct radial distances (NaN in the non-radius columns).
    radii_mm_ : ndarray of shape (n_radii,)
        Sorted radial-distance classes, mm.
    protraction_mm_ : float
        ``d`` used for ``theta = d / r``, mm (NaN with ``angle="oracle"``, where
        each trial has its own).
    youngs_modulus_gpa_, base_radius_mm_, length_mm_, moment_scale_ : float
        Parameters in use (measured, or the grid optimum).
    hall_offset_v_, hall_gain_v_, follicle_stiffness_nm_per_rad_ : float
        Sensor and follicle calibration.
    training_error_mm_ : float
        Mean absolute error of the snapped training predictions, mm.
    residual_std_mm_ : float
        RMS error of the continuous training estimates (floored at half the
        class spacing); width of the Gaussian in :meth:`predict_proba`.
    n_channels_, n_timepoints_, n_features_in_ : int
    """

    def __init__(
        self,
        whisker: dict[str, Any] | str | None = None,
        fit_parameters: bool = False,
        param_grid: dict[str, Any] | None = None,
        channel: int = 0,
        radius_column: int = 0,
        speed_column: int = 1,
        speed_mm_s: float | None = None,
        latency_s: float = 0.3,
        angle: str = "fixed_speed",
        sample_rate_hz: float | None = None,
    ) -> None:
        self.whisker = whisker
        self.fit_parameters = fit_parameters
        self.param_grid = param_grid
        self.channel = channel
        self.radius_column = radius_column
        self.speed_column = speed_column
        self.speed_mm_s = speed_mm_s
        self.latency_s = latency_s
        self.angle = angle
        self.sample_rate_hz = sample_rate_hz

    def __vibrissa_tags__(self) -> EstimatorTags:
        """Radial distance only (column ``radius_column`` of ``y``; thesis 4.3.1)."""
        return EstimatorTags(estimated_targets=(int(self.radius_column),))

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        # Built for whisker time series: no accuracy promise on generic tabular data.
        tags.classifier_tags.poor_score = True
        return tags

    # -- labels: radial distance only ---------------------------------------------------
    def _encode_y(self, y: Any, n_trials: int) -> np.ndarray:
        super()._encode_y(y, n_trials)  # shape, length and finiteness checks
        y_arr = np.asarray(y)
        if y_arr.ndim == 2 and not 0 <= self.radius_column < y_arr.shape[1]:
            raise ValueError(
                f"radius_column={self.radius_column} is out of range for y with "
                f"{y_arr.shape[1]} column(s)"
            )
        radius = target_column(y_arr, self.radius_column, "y (radial distance)")
        radii, idx = np.unique(radius, return_inverse=True)
        if len(radii) < 2:
            raise ValueError(
                f"y has a single radial distance ({radii[0]!r}); StaticBeamClassifier needs at "
                "least 2 classes. Classifier can't train when only one class is present."
            )
        self.radii_mm_ = radii
        if y_arr.ndim == 1:
            self.classes_ = radii
        else:
            classes = np.full((len(radii), y_arr.shape[1]), np.nan)
            classes[:, self.radius_column] = radii
            self.classes_ = classes
        return idx

    def _moment(self, X: np.ndarray) -> np.ndarray:
        ch = self.channel
        if (
            isinstance(ch, bool)
            or not isinstance(ch, int | np.integer)
            or not (0 <= ch < X.shape[1])
        ):
            raise ValueError(f"channel must lie in [0, {X.shape[1] - 1}], got {ch!r}")
        peak = vsig.peak_magnitude(X[:, ch], rest_v=self.hall_offset_v_)
        return base_moment_nm(peak, self.hall_gain_v_, self.follicle_stiffness_nm_per_rad_)

    def _estimate(self, moment: np.ndarray, theta_rad: np.ndarray | None = None) -> np.ndarray:
        if theta_rad is not None:
            return beam_radius_at_angle_mm(
                self.moment_scale_ * moment,
                theta_rad,
                self.youngs_modulus_gpa_,
                self.base_radius_mm_,
                self.length_mm_,
            )
        if self.angle == "oracle":
            raise ValueError(
                "this StaticBeamClassifier has angle='oracle': it needs each trial's true speed "
                "and radial distance, call predict_with_oracle_angle(X, speed_mm_s, radius_mm)"
            )
        return static_beam_radius_mm(
            self.moment_scale_ * moment,
            self.protraction_mm_,
            self.youngs_modulus_gpa_,
            self.base_radius_mm_,
            self.length_mm_,
        )

    def _fit(self, X: np.ndarray, y: Any, y_idx: np.ndarray) -> None:
        w = _whisker_dict(self.whisker)
        lat = float(self.latency_s)
        if not math.isfinite(lat) or lat <= 0:
            raise ValueError(f"latency_s must be positive, got {self.latency_s!r}")
        y_arr = np.asarray(y)
        if self.angle not in ANGLE_MODES:
            raise ValueError(f"angle must be one of {list(ANGLE_MODES)}, got {self.angle!r}")
        theta = None
        if self.angle == "oracle":
            if not (
                y_arr.ndim == 2
                and 0 <= self.speed_column < y_arr.shape[1]
                and self.speed_column != self.radius_column
            ):
                raise ValueError(
                    "angle='oracle' needs y with a speed column (speed_column): the angle is "
                    "each trial's true speed x latency_s / its true radial distance"
                )
            speeds = target_column(y_arr, self.speed_column, "y (speed)")
            theta = oracle_protraction_angle_rad(speeds, self.radii_mm_[y_idx], lat)
            speed = math.nan
        elif self.speed_mm_s is not None:
            speed = float(self.speed_mm_s)
            if not math.isfinite(speed) or speed <= 0:
                raise ValueError(f"speed_mm_s must be positive, got {self.speed_mm_s!r}")
        elif (
            y_arr.ndim == 2
            and 0 <= self.speed_column < y_arr.shape[1]
            and (self.speed_column != self.radius_column)
        ):
            speed = float(np.median(target_column(y_arr, self.speed_column, "y (speed)")))
            if speed <= 0:
                raise ValueError(f"median training speed must be positive, got {speed}")
        else:
            speed = DEFAULT_SPEED_MM_S
        self.protraction_mm_ = speed * lat
        self.hall_offset_v_ = float(w.get("hall_offset_v", vsig.HALL_REST_V))
        self.hall_gain_v_ = float(w["hall_gain_v"])
        self.follicle_stiffness_nm_per_rad_ = float(w["follicle_stiffness_nm_per_rad"])
        measured = {
            "youngs_modulus_gpa": float(w["youngs_modulus_gpa"]),
            "base_radius_mm": float(w["base_radius_mm"]),
            "length_mm": float(w["length_mm"]),
            "moment_scale": 1.0,
        }
        moment = self._moment(X)
        r_true = self.radii_mm_[y_idx]
        best = (
            self._grid_search(moment, r_true, measured, theta) if self.fit_parameters else measured
        )
        self.youngs_modulus_gpa_ = best["youngs_modulus_gpa"]
        self.base_radius_mm_ = best["base_radius_mm"]
        self.length_mm_ = best["length_mm"]
        self.moment_scale_ = best["moment_scale"]
        est = self._estimate(moment, theta)
        snapped = self.radii_mm_[nearest_values(est, self.radii_mm_)]
        self.training_error_mm_ = float(np.mean(np.abs(snapped - r_true)))
        gap = float(np.min(np.diff(self.radii_mm_)))
        rms = float(np.sqrt(np.mean((est - r_true) ** 2)))
        self.residual_std_mm_ = max(rms, 0.5 * gap)

    def _grid_search(
        self,
        moment: np.ndarray,
        r_true: np.ndarray,
        measured: dict[str, float],
        theta_rad: np.ndarray | None = None,
    ) -> dict[str, float]:
        grid = thesis_parameter_grid() if self.param_grid is None else dict(self.param_grid)
        unknown = set(grid) - set(measured)
        if unknown:
            raise ValueError(f"param_grid has unknown key(s) {sorted(unknown)}")
        axes = {}
        for k in measured:
            vals = np.atleast_1d(np.asarray(grid.get(k, [measured[k]]), dtype=float))
            if vals.size == 0 or not np.all(np.isfinite(vals)) or np.any(vals <= 0):
                raise ValueError(f"param_grid[{k!r}] must hold positive finite values")
            axes[k] = vals
        E, rb, S = np.meshgrid(
            axes["youngs_modulus_gpa"], axes["base_radius_mm"], axes["moment_scale"], indexing="ij"
        )
        L_vals = axes["length_mm"]
        # Eq. 4.1 depends on E, r_base and the moment scale only through
        # kappa = scale / (C d): evaluate each distinct kappa once per length.
        c = 3.0 * E * 1e9 * math.pi * (rb * 1e-3) ** 4 / 4.0
        if theta_rad is None:
            kappa = (S / (c * self.protraction_mm_ * 1e-3)).ravel()
        else:
            # the oracle angle: eq. 4.1 depends on them through kappa = scale / C,
            # r = L / (1 + kappa L M / theta) for each trial's own theta
            kappa = (S / c).ravel()
        order = np.argsort(kappa)
        ks = kappa[order]
        new = np.r_[True, np.diff(ks) > 1e-12 * ks[1:]]
        inv = np.empty(kappa.size, dtype=np.intp)
        inv[order] = np.cumsum(new) - 1
        kappa_u = ks[new]
        if theta_rad is None:
            err_u = self._grid_errors(kappa_u, L_vals, moment, r_true)
        else:
            err_u = self._oracle_grid_errors(kappa_u, L_vals, moment / theta_rad, r_true)
        # full[e, b, s, l]: error of every grid combination.
        full = err_u[inv].reshape(*E.shape, len(L_vals))
        ties = np.argwhere(full <= full.min() + _TIE_MM)
        vals = np.column_stack(
            [
                axes["youngs_modulus_gpa"][ties[:, 0]],
                axes["base_radius_mm"][ties[:, 1]],
                axes["moment_scale"][ties[:, 2]],
                L_vals[ties[:, 3]],
            ]
        )
        ref = np.array(
            [
                measured["youngs_modulus_gpa"],
                measured["base_radius_mm"],
                measured["moment_scale"],
                measured["length_mm"],
            ]
        )
        pick = vals[np.argmin(np.sum(np.log(vals / ref) ** 2, axis=1))]
        return {
            "youngs_modulus_gpa": float(pick[0]),
            "base_radius_mm": float(pick[1]),
            "moment_scale": float(pick[2]),
            "length_mm": float(pick[3]),
        }

    def _snapped_errors(
        self, kappa: np.ndarray, length_mm: float, moment: np.ndarray, r_true: np.ndarray
    ) -> np.ndarray:
        """Mean absolute error of the snapped training radii for each ``kappa`` at one length."""
        mid = 0.5 * (self.radii_mm_[1:] + self.radii_mm_[:-1])
        Lm2 = (length_mm * 1e-3) ** 2
        out = np.empty(len(kappa))
        m = moment[None, :]
        block = max(1, 2_000_000 // max(1, moment.size))
        for s in range(0, len(kappa), block):
            q = (kappa[s : s + block, None] * Lm2) * m
            r = 2.0 * length_mm / (1.0 + np.sqrt(1.0 + 4.0 * q))
            snapped = self.radii_mm_[np.searchsorted(mid, r)]
            out[s : s + block] = np.mean(np.abs(snapped - r_true[None, :]), axis=1)
        return out

    def _grid_errors(
        self, kappa: np.ndarray, lengths_mm: np.ndarray, moment: np.ndarray, r_true: np.ndarray
    ) -> np.ndarray:
        """Errors ``(len(kappa), len(lengths_mm))`` of :meth:`_snapped_errors`, where they matter.

        The numba kernel :func:`~vibrissa.classify._kernels.beam_grid_errors` evaluates
        every grid point in a fraction of the time; it adds the same absolute errors
        in another order, so every point within a bound on that difference of the
        kernel's minimum (plus the tie tolerance of :meth:`_grid_search`) is
        evaluated again by :meth:`_snapped_errors` and the rest set to infinity:
        the minimum and its ties are exactly those of evaluating every point.
        """
        radii = self.radii_mm_
        n, n_cls = moment.size, radii.size
        if not (
            np.all(np.isfinite(moment))
            and np.all(moment >= 0)
            and np.all(np.isfinite(kappa))
            and np.all(kappa > 0)
        ):
            return np.column_stack(
                [self._snapped_errors(kappa, L, moment, r_true) for L in lengths_mm]
            )
        order = np.argsort(moment, kind="stable")
        prefix = np.zeros((n + 1, n_cls))
        np.cumsum(np.abs(radii[None, :] - r_true[order][:, None]), axis=0, out=prefix[1:])
        m_sorted = np.ascontiguousarray(moment[order])
        # bucket lookup of positions in the sorted moments, ~4 trials per bucket
        span = float(m_sorted[-1] - m_sorted[0])
        n_buckets = 4 * n if span > 0 else 1
        scale = n_buckets / span if span > 0 else 0.0
        lookup = (
            np.searchsorted(m_sorted, m_sorted[0] + np.arange(n_buckets + 1) / scale)
            if span > 0
            else np.array([0, n])
        )
        fast = np.empty((kappa.size, lengths_mm.size))
        _kernels.beam_grid_errors(
            np.ascontiguousarray(kappa, dtype=float),
            np.ascontiguousarray(lengths_mm, dtype=float),
            np.array([(L * 1e-3) ** 2 for L in lengths_mm]),
            m_sorted,
            0.5 * (radii[1:] + radii[:-1]),
            prefix,
            lookup.astype(np.int64),
            scale,
            fast,
        )
        # |fast - exact| <= (2 n_cls + 1) n eps max|error| (prefix sums against NumPy's
        # pairwise mean): twice that, generously rounded, plus the tie tolerance
        spread = float(radii[-1] - radii[0])
        slack = _TIE_MM + 8.0 * (n_cls + 2) * n * np.finfo(float).eps * max(spread, 1.0)
        near = fast <= fast.min() + slack
        err = np.full(fast.shape, np.inf)
        for j in np.flatnonzero(near.any(axis=0)):
            rows = np.flatnonzero(near[:, j])
            err[rows, j] = self._snapped_errors(kappa[rows], lengths_mm[j], moment, r_true)
        return err

    def _oracle_snapped_errors(
        self, kappa: np.ndarray, length_mm: float, u: np.ndarray, r_true: np.ndarray
    ) -> np.ndarray:
        """Mean absolute snapped error for each ``kappa`` at one length, oracle angle.

        ``u = M / theta`` per trial; the estimate is ``r = L / (1 + kappa L u)``
        (:func:`beam_radius_at_angle_mm` with ``kappa = scale / C``).
        """
        mid = 0.5 * (self.radii_mm_[1:] + self.radii_mm_[:-1])
        Lm = length_mm * 1e-3
        out = np.empty(len(kappa))
        block = max(1, 2_000_000 // max(1, u.size))
        for s in range(0, len(kappa), block):
            r = length_mm / (1.0 + (kappa[s : s + block, None] * Lm) * u[None, :])
            snapped = self.radii_mm_[np.searchsorted(mid, r)]
            out[s : s + block] = np.mean(np.abs(snapped - r_true[None, :]), axis=1)
        return out

    def _oracle_grid_errors(
        self, kappa: np.ndarray, lengths_mm: np.ndarray, u: np.ndarray, r_true: np.ndarray
    ) -> np.ndarray:
        """Errors ``(len(kappa), len(lengths_mm))`` of :meth:`_oracle_snapped_errors`.

        The estimate falls with ``u``, so the trials snapped to each class are a run
        of the trials sorted by ``u``, bounded where the estimate crosses the
        midpoints between classes: prefix sums of each class's absolute error give
        every grid point's error from ``n_classes`` binary searches. The points
        within a few boundary trials' worth of the smallest error (a trial whose
        ``u`` rounds across a bound moves by at most the widest class gap) are
        evaluated again directly, the rest set to infinity, so the minimum and its
        ties are those of :meth:`_oracle_snapped_errors`.
        """
        radii = self.radii_mm_
        n, n_cls = u.size, radii.size
        if not (np.all(np.isfinite(u)) and np.all(u >= 0) and np.all(kappa > 0)):
            return np.column_stack(
                [self._oracle_snapped_errors(kappa, L, u, r_true) for L in lengths_mm]
            )
        order = np.argsort(u, kind="stable")
        u_sorted = u[order]
        prefix = np.zeros((n + 1, n_cls))
        np.cumsum(np.abs(radii[None, :] - r_true[order][:, None]), axis=0, out=prefix[1:])
        mid = 0.5 * (radii[1:] + radii[:-1])
        cols = np.arange(n_cls)
        fast = np.empty((kappa.size, lengths_mm.size))
        for j, L in enumerate(lengths_mm):
            # class >= c  <=>  r > mid[c - 1]  <=>  u < (L / mid[c - 1] - 1) / (kappa L)
            with np.errstate(divide="ignore"):
                bound = (L / mid - 1.0)[None, :] / (kappa[:, None] * L * 1e-3)
            n_ge = np.searchsorted(u_sorted, bound.ravel(), side="left").reshape(bound.shape)
            hi = np.column_stack([np.full(kappa.size, n), n_ge])  # trials of class >= c
            lo = np.column_stack([n_ge, np.zeros(kappa.size, dtype=n_ge.dtype)])
            fast[:, j] = (prefix[hi, cols] - prefix[lo, cols]).sum(axis=1) / n
        gap = float(np.max(np.diff(radii)))
        spread = float(radii[-1] - radii[0])
        slack = _TIE_MM + 4.0 * gap / n + 8.0 * (n_cls + 2) * np.finfo(float).eps * spread
        near = fast <= fast.min() + slack
        err = np.full(fast.shape, np.inf)
        for j in np.flatnonzero(near.any(axis=0)):
            rows = np.flatnonzero(near[:, j])
            err[rows, j] = self._oracle_snapped_errors(kappa[rows], lengths_mm[j], u, r_true)
        return err

    def predict_with_oracle_angle(
        self,
        X: Any,
        speed_mm_s: Any,
        radius_mm: Any,
        sample_rate_hz: float | None = None,
    ) -> np.ndarray:
        """Classify with the thesis author's angle: each trial's TRUE speed and radial distance.

        An oracle (see the class docstring): ``theta = speed x latency_s / radius``
        of each trial (:func:`oracle_protraction_angle_rad`), eq. 4.1 with the
        fitted parameters (:func:`beam_radius_at_angle_mm`), snapped to the nearest
        radial-distance class. Works after either ``angle``; the parameters were
        searched under the angle of ``fit``.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        speed_mm_s : array-like of shape (n_trials,)
            True contact speed of each trial, mm/s.
        radius_mm : array-like of shape (n_trials,)
            True radial distance of each trial, mm (the quantity estimated: only
            its role in the angle is used).
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials,) or (n_trials, n_targets)
            Rows of ``classes_``, as :meth:`predict` returns.
        """
        Xc = self._fitted_input(X, sample_rate_hz)
        n = Xc.shape[0]
        speed = np.asarray(speed_mm_s, dtype=float)
        radius = np.asarray(radius_mm, dtype=float)
        for name, arr in (("speed_mm_s", speed), ("radius_mm", radius)):
            if arr.shape != (n,):
                raise ValueError(f"{name} must have shape ({n},) (one per trial), got {arr.shape}")
        theta = oracle_protraction_angle_rad(speed, radius, float(self.latency_s))
        est = self._estimate(self._moment(Xc), theta)
        return self.classes_[nearest_values(est, self.radii_mm_)]

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        est = self._estimate(self._moment(X))
        z = (est[:, None] - self.radii_mm_[None, :]) / self.residual_std_mm_
        return -0.5 * z * z

    def predict_radius_mm(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Continuous radial-distance estimates (eq. 4.1) before snapping to a class.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials,)
            Radial distance, mm.
        """
        return self._estimate(self._moment(self._fitted_input(X, sample_rate_hz)))
