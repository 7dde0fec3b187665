"""The simulated robot against the thesis' own physical observations.

The thesis does not give every parameter of its whisker and XY robot (follicle
stiffness, loop delay, the Hall IC's programming for the XY whisker, friction),
but it reports what the hardware did: the whisker's resonance (5.3.1), the loop
latency (3.3.2), the closest usable contact (4.2), the zone near the tip where
contacts slip past (4.2), the speed limit (4.2), ringing (3.3, 5.4), contact
durations (4.3.4, 5.5). :func:`identify` simulates each of these on the current
parameters, with the protocols' own settings, and sets the result beside the
thesis' statement with a stated tolerance. Nothing here is an input to the
simulation: the observables are measured from the mechanics.

``docs/physics.md`` lists every parameter with its source, including those
identified from these observables.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Literal

import numpy as np
import scipy.signal

from vibrissa.experiments import runner
from vibrissa.experiments.protocols import Protocol, get_protocol
from vibrissa.experiments.streams import trial_stream
from vibrissa.robots.xy_stage import (
    PoleStimulus,
    SurfaceStimulus,
    TrialResult,
    XYStage,
    run_trial,
)
from vibrissa.signal import contact_duration
from vibrissa.whisker.rod import RodModel

__all__ = [
    "SPECS",
    "Observable",
    "ObservableSpec",
    "Tolerance",
    "identify",
    "deflection_duration_s",
    "ring_ratio",
    "spectral_peak_hz",
    "trial_spectral_peaks_hz",
]

Progress = Callable[[int], None]


@dataclass
class Observable:
    """One physical statement of the thesis, measured on the simulation.

    Attributes
    ----------
    key
        Short machine name (stable; used as the JSON key).
    description
        What is measured and how.
    thesis
        The thesis' statement, with its section.
    thesis_value
        The thesis' number (``None`` for a qualitative statement).
    value
        Ours, in ``unit``.
    unit
        Unit of ``thesis_value`` and ``value``.
    tolerance
        The agreement required, in words.
    within
        Whether ``value`` meets ``tolerance``.
    detail
        The measurements behind ``value``.
    """

    key: str
    description: str
    thesis: str
    thesis_value: float | None
    value: float
    unit: str
    tolerance: str
    within: bool
    detail: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-compatible dict."""
        return _plain(asdict(self))


def _plain(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_plain(v) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


# --------------------------------------------------------------------------- specifications
ToleranceKind = Literal["abs", "rel", "max", "min", "between"]


@dataclass(frozen=True)
class Tolerance:
    """The agreement an observable must reach, as data.

    Attributes
    ----------
    kind
        ``"abs"``: ``|value - target| <= width``; ``"rel"``: ``|value - target| <=
        |target| * width / 100`` (``width`` in percent); ``"max"``: ``value <= high``;
        ``"min"``: ``value >= low``; ``"between"``: ``low <= value <= high``. Every bound
        is inclusive; ``nan`` holds none of them. Bounds a kind does not use stay ``nan``.
    target
        Centre of an ``"abs"`` or ``"rel"`` tolerance.
    width
        Half-width of an ``"abs"`` tolerance (in ``unit``) or of a ``"rel"`` one (in %).
    low
        Lower bound of a ``"min"`` or ``"between"`` tolerance.
    high
        Upper bound of a ``"max"`` or ``"between"`` tolerance.
    unit
        Unit written after the numbers (``""``: none, as for fractions).
    statistic
        The statistic compared, written first (``"median"``; ``""``: the value itself).
    scope
        Words appended to the text (e.g. ``"at every speed up to 216 mm/s"``).
    """

    kind: ToleranceKind
    target: float = math.nan
    width: float = math.nan
    low: float = math.nan
    high: float = math.nan
    unit: str = ""
    statistic: str = ""
    scope: str = ""

    def __post_init__(self) -> None:
        needs = {
            "abs": ("target", "width"),
            "rel": ("target", "width"),
            "max": ("high",),
            "min": ("low",),
            "between": ("low", "high"),
        }
        if self.kind not in needs:
            raise ValueError(f"unknown tolerance kind {self.kind!r}")
        missing = [f for f in needs[self.kind] if not math.isfinite(getattr(self, f))]
        if missing:
            raise ValueError(f"a {self.kind!r} tolerance needs {', '.join(missing)}")

    def holds(self, value: float) -> bool:
        """Whether ``value`` meets the tolerance.

        Parameters
        ----------
        value
            The measured value (``nan`` never holds).

        Returns
        -------
        bool
        """
        if self.kind == "abs":
            return bool(abs(value - self.target) <= self.width)
        if self.kind == "rel":
            return bool(abs(value - self.target) <= abs(self.target) * self.width / 100)
        if self.kind == "max":
            return bool(value <= self.high)
        if self.kind == "min":
            return bool(value >= self.low)
        return bool(self.low <= value <= self.high)

    def text(self) -> str:
        """The tolerance in words, as printed and stored (e.g. ``"median at most 0.1"``).

        ``"abs"`` reads ``"<target> +/- <width> <unit>"``, preceded by ``"<statistic>
        within "`` when a statistic is named; ``"rel"`` reads ``"within <width> %"``.

        Returns
        -------
        str
        """
        unit = f" {self.unit}" if self.unit else ""
        if self.kind == "abs":
            words = f"{self.target:g} +/- {self.width:g}{unit}"
            if self.statistic:
                words = f"within {words}"
        elif self.kind == "rel":
            words = f"within {self.width:g} %"
        elif self.kind == "max":
            words = f"at most {self.high:g}{unit}"
        elif self.kind == "min":
            words = f"at least {self.low:g}{unit}"
        else:
            words = f"between {self.low:g}{unit} and {self.high:g}{unit}"
        return " ".join(w for w in (self.statistic, words, self.scope) if w)


@dataclass(frozen=True)
class ObservableSpec:
    """Everything about one observable that is not measured: what, the thesis, the tolerance.

    Attributes
    ----------
    name
        Short machine name (:attr:`Observable.key`).
    description
        What is measured and how; a :meth:`str.format` template whose fields
        (``near_speed_min``, ``near_speed_max``) come from the plan.
    quote
        The thesis' words.
    section
        Where the thesis says it (e.g. ``"4.2"``).
    thesis_value
        The thesis' number (``None`` for a qualitative statement).
    unit
        Unit of ``thesis_value`` and of the measured value.
    tolerance
        The agreement required.
    """

    name: str
    description: str
    quote: str
    section: str
    thesis_value: float | None
    unit: str
    tolerance: Tolerance

    @property
    def thesis(self) -> str:
        """The thesis' statement with its section, ``"<quote> (<section>)"``."""
        return f"{self.quote} ({self.section})"

    def observable(
        self, value: float, detail: dict[str, Any], fields: Mapping[str, Any]
    ) -> Observable:
        """The :class:`Observable` of a measured ``value``.

        Parameters
        ----------
        value
            The measured value, in ``unit``.
        detail
            The measurements behind ``value``.
        fields
            Values of the fields of the ``description`` template.

        Returns
        -------
        Observable
        """
        return Observable(
            self.name,
            self.description.format(**fields),
            self.thesis,
            self.thesis_value,
            value,
            self.unit,
            self.tolerance.text(),
            self.tolerance.holds(value),
            detail,
        )


SPECS: tuple[ObservableSpec, ...] = (
    ObservableSpec(
        "resonance_hz",
        "largest peak of each chapter-5 recording's amplitude spectrum between 10 and 200 Hz "
        "(mean removed, Hann window), median over trials: what inspection of the recordings' "
        "FFT finds; the linearised modes (free, tip held by the surface) are in the detail",
        "30 Hz, 'identified by inspection of the FFT' of the chapter-5 recordings, still "
        "present after the 35 Hz high-pass",
        "5.3.1",
        30.0,
        "Hz",
        Tolerance("between", low=25.0, high=35.0, unit="Hz", statistic="median"),
    ),
    ObservableSpec(
        "mi_latency_ms",
        "first contact to the start of the retraction, median over a radius x speed grid",
        "'Temporal latency for the loop is ~300 ms from initial contact'",
        "3.3.2, 5.2",
        300.0,
        "ms",
        Tolerance("abs", target=300.0, width=30.0, unit="ms", statistic="median"),
    ),
    ObservableSpec(
        "duration_grows_with_speed",
        "deflection duration as the thesis measured it (feature f2: time above 0.05 V, "
        "4.3.4, the run above threshold holding the peak); fraction of neighbouring-speed "
        "pairs at the same radius, both usable (no slip-off, no saturation), where it is "
        "longer at the higher speed",
        "deflection duration grows with contact speed and discriminates speed",
        "4.3.4",
        None,
        "fraction",
        Tolerance("min", low=0.9),
    ),
    ObservableSpec(
        "ringing_chapter4",
        "first overshoot past rest after the object leaves the whisker, fraction of the "
        "peak; median over the chapter-4 grid (the same with the MI retraction switched off, "
        "the whisker slipping past the pole, is in the detail)",
        "MI keeps 'whisker ringing after contact to a minimum'",
        "3.3",
        None,
        "fraction of peak",
        Tolerance("max", high=0.1, statistic="median"),
    ),
    ObservableSpec(
        "ringing_chapter5",
        "fraction of chapter-5 trials whose first overshoot exceeds 10 % of the peak",
        "'oscillatory ringing after contact on some trials but not others'",
        "5.4, fig. 5.2",
        None,
        "fraction of trials",
        Tolerance("between", low=0.1, high=0.9),
    ),
    ObservableSpec(
        "contact_duration_chapter5_ms",
        "deflection duration of the chapter-5 recordings read with the thesis' threshold "
        "(0.05 V, f2 of 4.3.4): the longest stretch above it, dips under 5 ms bridged "
        "(noise, texture), median; the physical contact (first touch to the end of the MI "
        "contact) is in the detail",
        "'Contact duration in this experiment is quite short (~300 ms)'",
        "5.5",
        300.0,
        "ms",
        Tolerance("abs", target=300.0, width=60.0, unit="ms", statistic="median"),
    ),
    ObservableSpec(
        "closest_usable_contact_mm",
        "smallest radius from which on no contact at {near_speed_min:g}-{near_speed_max:g} "
        "mm/s saturates the sensor",
        "'the closest contact that could be made ... at any reasonable speed without "
        "saturating the Hall effect sensor was ~80 mm'",
        "4.2",
        80.0,
        "mm",
        Tolerance("abs", target=80.0, width=10.0, unit="mm"),
    ),
    ObservableSpec(
        "tip_zone_mm",
        "distance from the tip within which the whisker slips past the object before the "
        "retraction; largest over speeds in the grid",
        "'Contacts at less than 5 mm from the tip did not deflect the base ... before "
        "slipping past'",
        "4.2",
        5.0,
        "mm",
        Tolerance("max", high=10.0, unit="mm", scope="at every speed up to 216 mm/s"),
    ),
    ObservableSpec(
        "above_216_mm_s",
        "fraction of contacts faster than 216 mm/s (over the chapter-4 radii) that slip past "
        "or saturate",
        "'Contact speeds above 216 mm/s either cause the whisker to slip past the object "
        "before a retraction, or saturates the sensors'",
        "4.2",
        None,
        "fraction",
        Tolerance("min", low=0.75),
    ),
)
"""The nine observables, in the order :func:`identify` returns them."""


# --------------------------------------------------------------------------- mechanics
def spectral_peak_hz(
    signals: np.ndarray, fs: float, band_hz: tuple[float, float] = (8.0, 150.0)
) -> float:
    """Frequency of the most prominent peak of the mean amplitude spectrum in a band.

    What "inspection of the FFT" finds: each trial's ``x`` minus its mean is
    Hann-windowed and transformed; the amplitude spectra are averaged over trials;
    among the local maxima inside ``band_hz`` the one standing highest above its
    surroundings (``scipy.signal.find_peaks`` prominence, on a log scale) is taken.
    """
    x = np.asarray(signals, dtype=float)
    x = x - x.mean(axis=-1, keepdims=True)
    spec = np.abs(np.fft.rfft(x * np.hanning(x.shape[-1]), axis=-1)).mean(axis=0)
    f = np.fft.rfftfreq(x.shape[-1], 1.0 / fs)
    keep = (f >= band_hz[0]) & (f <= band_hz[1])
    logs = np.log(spec[keep] + 1e-300)
    peaks, props = scipy.signal.find_peaks(logs, prominence=0.0)
    if peaks.size == 0:
        return float("nan")
    return float(f[keep][peaks[int(np.argmax(props["prominences"]))]])


def trial_spectral_peaks_hz(
    signals: np.ndarray, fs: float, band_hz: tuple[float, float] = (10.0, 200.0)
) -> np.ndarray:
    """Frequency of the largest amplitude in each trial's spectrum inside a band.

    Each trial's ``x`` minus its mean is Hann-windowed and transformed; the
    frequency of the largest amplitude with ``band_hz[0] <= f <= band_hz[1]`` is
    returned (the band's lower edge when the contact's own slow shape dominates).

    Parameters
    ----------
    signals
        Recordings, shape (n_trials, n_samples), V.
    fs
        Sample rate (Hz).
    band_hz
        Inclusive band (Hz).

    Returns
    -------
    numpy.ndarray
        Shape (n_trials,), Hz.
    """
    x = np.atleast_2d(np.asarray(signals, dtype=float))
    x = x - x.mean(axis=-1, keepdims=True)
    spec = np.abs(np.fft.rfft(x * np.hanning(x.shape[-1]), axis=-1))
    f = np.fft.rfftfreq(x.shape[-1], 1.0 / fs)
    keep = np.flatnonzero((f >= band_hz[0]) & (f <= band_hz[1]))
    if keep.size == 0:
        raise ValueError(f"band_hz {band_hz} holds no frequency of a {x.shape[-1]}-sample FFT")
    return f[keep][np.argmax(spec[:, keep], axis=1)]


def deflection_duration_s(
    x: np.ndarray, fs: float, threshold_v: float = 0.05, bridge_s: float = 0.005
) -> float:
    """The longest stretch a recording's deflection stays above a threshold (s).

    What one reads off a trace as "the contact": ``|x - 2.5 V| >= threshold_v``,
    with dips shorter than ``bridge_s`` (noise, a texture's wiggle) bridged; single
    ringing half-cycles after the release are separate, shorter stretches.

    Parameters
    ----------
    x
        One channel of one recording (V).
    fs
        Sample rate (Hz).
    threshold_v
        Deflection threshold (V); the thesis' 0.05 V (4.3.4).
    bridge_s
        Longest dip below the threshold that does not end a stretch (s).

    Returns
    -------
    float
        Seconds; 0 if the deflection never reaches the threshold.
    """
    above = np.abs(np.asarray(x, dtype=float) - 2.5) >= threshold_v
    idx = np.flatnonzero(above)
    if idx.size == 0:
        return 0.0
    breaks = np.flatnonzero(np.diff(idx) > max(1, int(round(bridge_s * fs))))
    starts = np.concatenate([[0], breaks + 1])
    ends = np.concatenate([breaks, [idx.size - 1]])
    return float((idx[ends] - idx[starts] + 1).max() / fs)


def ring_ratio(res: TrialResult, fs: float, span_s: float = 0.2) -> float:
    """Largest overshoot past rest after the contact ends, as a fraction of the peak.

    After the object leaves the whisker, a ringing whisker swings through its rest
    position; the deepest excursion to the other side (``x`` below 2.5 V) within
    ``span_s`` is the first ring. 0 means the whisker settled without overshoot.
    """
    x = res.signal_v[0] - 2.5
    if not math.isfinite(res.contact_end_s) or res.peak_deflection_v <= 0:
        return float("nan")
    k0 = res.peak_index + int(round(res.contact_end_s * fs))
    k1 = min(x.size, k0 + int(round(span_s * fs)))
    if k0 >= k1:
        return float("nan")
    return float(max(0.0, -x[max(k0, 0) : k1].min()) / res.peak_deflection_v)


# --------------------------------------------------------------------------- trials
def _pole_trials(
    protocol: Protocol,
    points: Iterable[tuple[float, float]],
    group: int,
    progress: Progress | None,
) -> list[tuple[float, float, TrialResult]]:
    model = runner.whisker_model(protocol.whisker, protocol.n_elements, 0.0)
    sensor = runner.hall_sensor(protocol)
    out = []
    for k, (r, v) in enumerate(points):
        rng = np.random.default_rng(trial_stream(protocol.seed, group, k))
        res = run_trial(
            protocol.stage,
            model,
            sensor,
            PoleStimulus(r),
            v,
            1,
            protocol.window_s,
            rng,
            dt_s=protocol.dt_s,
        )
        out.append((r, v, res))
        if progress:
            progress(1)
    return out


def _surface_trials(
    protocol: Protocol,
    points: Iterable[tuple[str, float, float]],
    group: int,
    progress: Progress | None,
) -> list[tuple[str, float, float, TrialResult]]:
    model = runner.whisker_model(protocol.whisker, protocol.n_elements, 0.0)
    sensor = runner.hall_sensor(protocol)
    out = []
    for k, (texture, angle, v) in enumerate(points):
        rng = np.random.default_rng(trial_stream(protocol.seed, group, k))
        res = run_trial(
            protocol.stage,
            model,
            sensor,
            SurfaceStimulus(texture, angle),
            v,
            1,
            protocol.window_s,
            rng,
            dt_s=protocol.dt_s,
            surface=runner.session_surface(texture, protocol.seed),
        )
        out.append((texture, angle, v, res))
        if progress:
            progress(1)
    return out


@dataclass(frozen=True)
class _Plan:
    """The trials each observable needs (grids in mm and mm/s)."""

    grid_radii: tuple[float, ...]
    grid_speeds: tuple[float, ...]
    near_radii: tuple[float, ...]
    near_speeds: tuple[float, ...]
    tip_radii: tuple[float, ...]
    tip_speeds: tuple[float, ...]
    fast_radii: tuple[float, ...]
    fast_speeds: tuple[float, ...]
    surface_points: tuple[tuple[str, float, float], ...]
    passive_radii: tuple[float, ...] = (100.0, 140.0, 180.0)
    passive_speeds: tuple[float, ...] = (72.0, 144.0)

    @property
    def n_trials(self) -> int:
        return (
            len(self.passive_radii) * len(self.passive_speeds)
            + len(self.grid_radii) * len(self.grid_speeds)
            + len(self.near_radii) * len(self.near_speeds)
            + len(self.tip_radii) * len(self.tip_speeds)
            + len(self.fast_radii) * len(self.fast_speeds)
            + len(self.surface_points)
        )


def plan(quick: bool = False) -> _Plan:
    """The trials :func:`identify` simulates (``quick``: a coarser version)."""
    if quick:
        return _Plan(
            grid_radii=(80.0, 130.0, 180.0),
            grid_speeds=(36.0, 126.0, 216.0),
            near_radii=(70.0, 75.0, 80.0, 85.0),
            near_speeds=(36.0, 126.0, 216.0),
            tip_radii=(175.0, 180.0, 183.0),
            tip_speeds=(36.0, 216.0),
            fast_radii=(100.0, 140.0, 180.0),
            fast_speeds=(300.0,),
            surface_points=tuple(
                (t, a, v) for t in ("aluminium", "p80") for a in (20.0, 60.0) for v in (36.0,)
            ),
            passive_radii=(140.0,),
        )
    speeds6 = tuple(float(v) for v in np.linspace(36.0, 216.0, 6))
    return _Plan(
        grid_radii=(80.0, 100.0, 120.0, 140.0, 160.0, 180.0),
        grid_speeds=speeds6,
        near_radii=(60.0, 65.0, 70.0, 75.0, 80.0, 85.0, 90.0, 95.0, 100.0),
        near_speeds=speeds6,
        tip_radii=(170.0, 172.0, 174.0, 176.0, 178.0, 180.0, 182.0, 184.0),
        tip_speeds=(36.0, 126.0, 216.0),
        fast_radii=(80.0, 100.0, 120.0, 140.0, 160.0, 180.0),
        fast_speeds=(250.0, 300.0),
        surface_points=tuple(
            (t, a, v)
            for t in ("aluminium", "p600", "p180", "p80")
            for a in (20.0, 50.0, 80.0)
            for v in (16.0, 56.0, 96.0)
        ),
    )


# --------------------------------------------------------------------------- measurements
Measured = dict[str, tuple[float, dict[str, Any]]]
"""Observable name -> (value, the measurements behind it)."""

# Random-stream group of each set of trials (part of the stream index: keep them fixed).
_GROUP_GRID, _GROUP_NEAR, _GROUP_SURFACE, _GROUP_TIP, _GROUP_FAST = 1, 2, 3, 4, 5
_GROUP_PASSIVE = 6

PoleTrials = list[tuple[float, float, TrialResult]]
SurfaceTrials = list[tuple[str, float, float, TrialResult]]


def _speed_major(radii: Iterable[float], speeds: Iterable[float]) -> list[tuple[float, float]]:
    """``(radius, speed)`` points, all radii at the first speed first."""
    radii = tuple(radii)
    return [(r, v) for v in speeds for r in radii]


def _measure_resonance(model: RodModel, surface: SurfaceTrials, fs: float) -> Measured:
    """``resonance_hz``: tip-pinned first mode; free modes and the chapter-5 FFT beside it.

    Parameters
    ----------
    model
        The chapter-4 whisker.
    surface
        The chapter-5 trials.
    fs
        Their sample rate (Hz).

    Returns
    -------
    Measured
    """
    free = float(model.natural_frequencies_hz[0])
    tip_modes = model.pinned_frequencies_hz(model.geometry.length_mm)
    tip = float(tip_modes[0])
    rigid = float(
        RodModel(model.geometry, model.n_elements, rigid_follicle=True).natural_frequencies_hz[0]
    )
    sig5 = np.stack([res.signal_v[0] for *_, res in surface])
    peaks = trial_spectral_peaks_hz(sig5, fs)
    # bands of the per-trial peaks: [0, 14), [14, 20), [20, 25), [25, 35], above 35 Hz
    band = np.searchsorted([14.0, 20.0, 25.0], peaks, side="right") + (peaks > 35.0)
    names = ("below_14_hz", "14_to_20_hz", "20_to_25_hz", "25_to_35_hz", "above_35_hz")
    bins = {name: int(np.count_nonzero(band == i)) for i, name in enumerate(names)}
    return {
        "resonance_hz": (
            float(np.median(peaks)),
            {
                "trial_peak_hz_percentiles_5_50_95": np.percentile(peaks, [5, 50, 95]).tolist(),
                "trial_peaks_by_band": bins,
                "mean_spectrum_most_prominent_peak_hz": spectral_peak_hz(sig5, fs),
                "tip_pinned_first_mode_hz": tip,
                "tip_pinned_first_modes_hz": tip_modes.tolist(),
                "free_first_mode_hz": free,
                "rigid_follicle_free_first_mode_hz": rigid,
                "pinned_first_mode_by_radius_hz": {
                    str(int(r)): float(model.pinned_frequencies_hz(r)[0])
                    for r in (80.0, 100.0, 130.0, 160.0, 180.0)
                },
                "n_chapter5_trials": len(surface),
            },
        )
    }


def _measure_chapter4_grid(
    grid: PoleTrials, radii: tuple[float, ...], fs: float, passive: PoleTrials
) -> Measured:
    """``mi_latency_ms``, ``duration_grows_with_speed``, ``ringing_chapter4`` on the grid.

    Parameters
    ----------
    grid
        The chapter-4 radius x speed grid of pole trials.
    passive
        Pole trials with the MI retraction switched off (the object pushes on until the
        whisker slips past it), for the ringing comparison.
    radii
        The grid's radii (mm).
    fs
        The sample rate (Hz).

    Returns
    -------
    Measured
    """
    lat = np.array([res.mi_latency_s for *_, res in grid]) * 1e3
    thr = np.array([res.threshold_time_s - res.contact_onset_s for *_, res in grid]) * 1e3
    med = float(np.nanmedian(lat))
    width = contact_duration(np.stack([res.signal_v[0] for *_, res in grid]), fs, mode="peak")
    dur: dict[float, dict[float, float]] = {}
    usable: set[tuple[float, float]] = set()
    for (r, v, res), w in zip(grid, width, strict=True):
        dur.setdefault(r, {})[v] = float(w)
        if not (res.slipped_off or res.saturated):
            usable.add((r, v))
    pairs = wrong = 0
    for r, by_v in dur.items():
        vs = sorted(by_v)
        for a, b in zip(vs[:-1], vs[1:], strict=True):
            if (r, a) not in usable or (r, b) not in usable:
                continue
            pairs += 1
            wrong += by_v[b] < by_v[a]
    frac = 1.0 - wrong / max(pairs, 1)
    rings = np.array([ring_ratio(res, fs) for *_, res in grid])
    rings_passive = np.array([ring_ratio(res, fs) for *_, res in passive])
    return {
        "mi_latency_ms": (
            med,
            {
                "percentiles_5_50_95_ms": np.nanpercentile(lat, [5, 50, 95]).tolist(),
                "contact_to_threshold_ms_5_50_95": np.nanpercentile(thr, [5, 50, 95]).tolist(),
                "n_trials": len(grid),
            },
        ),
        "duration_grows_with_speed": (
            frac,
            {
                "pairs": pairs,
                "wrong_way": int(wrong),
                "f2_ms_by_radius": {
                    str(r): {str(v): 1e3 * d for v, d in sorted(b.items())} for r, b in dur.items()
                },
                "contact_ms_by_radius": {
                    str(r): {
                        str(v): 1e3 * (res.contact_end_s - res.contact_onset_s)
                        for rr, v, res in grid
                        if rr == r
                    }
                    for r in radii
                },
            },
        ),
        "ringing_chapter4": (
            float(np.nanmedian(rings)),
            {
                "percentiles_5_50_95": np.nanpercentile(rings, [5, 50, 95]).tolist(),
                "fraction_above_0_1": float(np.nanmean(rings > 0.1)),
                "passive_push_median": float(np.nanmedian(rings_passive)),
                "passive_push_percentiles_5_50_95": np.nanpercentile(
                    rings_passive, [5, 50, 95]
                ).tolist(),
                "n_passive_trials": len(passive),
            },
        ),
    }


def _measure_chapter5(surface: SurfaceTrials, fs: float) -> Measured:
    """``ringing_chapter5`` and ``contact_duration_chapter5_ms`` on the chapter-5 trials.

    Parameters
    ----------
    surface
        The chapter-5 trials.
    fs
        Their sample rate (Hz).

    Returns
    -------
    Measured
    """
    rings5 = np.array([ring_ratio(res, fs) for *_, res in surface])
    d5 = np.array([res.contact_end_s - res.contact_onset_s for *_, res in surface]) * 1e3
    f2 = 1e3 * np.array([deflection_duration_s(res.signal_v[0], fs) for *_, res in surface])
    return {
        "ringing_chapter5": (
            float(np.nanmean(rings5 > 0.1)),
            {
                "ratio_percentiles_5_50_95": np.nanpercentile(rings5, [5, 50, 95]).tolist(),
            },
        ),
        "contact_duration_chapter5_ms": (
            float(np.median(f2)),
            {
                "percentiles_5_50_95_ms": np.percentile(f2, [5, 50, 95]).tolist(),
                "physical_contact_median_ms": float(np.nanmedian(d5)),
                "physical_contact_percentiles_5_50_95_ms": np.nanpercentile(
                    d5, [5, 50, 95]
                ).tolist(),
            },
        ),
    }


def _measure_closest_contact(
    near: PoleTrials, radii: tuple[float, ...], calibration_mm: list[float]
) -> Measured:
    """``closest_usable_contact_mm``: the smallest radius from which on nothing saturates.

    Parameters
    ----------
    near
        Pole trials near the base.
    radii
        Their radii (mm).
    calibration_mm
        The sensor's calibration point (reported beside the value).

    Returns
    -------
    Measured
    """
    sat: dict[float, list[float]] = {}
    for r, v, res in near:
        if res.saturated:
            sat.setdefault(r, []).append(v)
    clean = [r for r in radii if r not in sat]
    closest = float("nan")
    for r in sorted(radii):
        if all(q in clean for q in radii if q >= r):
            closest = r
            break
    return {
        "closest_usable_contact_mm": (
            closest,
            {
                "saturating_speeds_by_radius": {str(r): v for r, v in sorted(sat.items())},
                "calibration_mm": calibration_mm,
            },
        )
    }


def _measure_tip_zone(
    tip: PoleTrials, radii: tuple[float, ...], speeds: tuple[float, ...], length_mm: float
) -> Measured:
    """``tip_zone_mm``: how far from the tip contacts slip past, largest over speeds.

    Parameters
    ----------
    tip
        Pole trials near the tip.
    radii, speeds
        Their radii (mm) and speeds (mm/s).
    length_mm
        The whisker's length.

    Returns
    -------
    Measured
    """
    zone: dict[float, float] = {}
    for v in speeds:
        slipped = [r for r, vv, res in tip if vv == v and res.slipped_off]
        zone[v] = length_mm - min(slipped) if slipped else 0.0
    return {
        "tip_zone_mm": (
            max(zone.values()),
            {
                "tip_zone_mm_by_speed": {str(v): z for v, z in zone.items()},
                "radii_tested_mm": list(radii),
            },
        )
    }


def _measure_above_216(fast: PoleTrials, grid: PoleTrials) -> Measured:
    """``above_216_mm_s``: the fraction of fast contacts that slip past or saturate.

    Parameters
    ----------
    fast
        Pole trials faster than 216 mm/s.
    grid
        The chapter-4 grid (up to 216 mm/s), for comparison.

    Returns
    -------
    Measured
    """
    fails = np.array([res.slipped_off or res.saturated for *_, res in fast])
    return {
        "above_216_mm_s": (
            float(fails.mean()),
            {
                "grid_fraction_slipped_or_saturated_up_to_216": float(
                    np.mean([res.slipped_off or res.saturated for *_, res in grid])
                ),
                "trials": [
                    {
                        "radius_mm": r,
                        "speed_mm_s": v,
                        "slipped_off": res.slipped_off,
                        "saturated": res.saturated,
                    }
                    for r, v, res in fast
                ],
            },
        )
    }


# --------------------------------------------------------------------------- observables
def identify(
    quick: bool = False, progress: Progress | None = None, stage: XYStage | None = None
) -> list[Observable]:
    """Measure every observable of the thesis on the simulated robot.

    The trial groups are simulated in a fixed order (chapter-5 surfaces, chapter-4
    grid, near the base, near the tip, above 216 mm/s), each on its own random streams;
    the values are set beside :data:`SPECS`.

    Parameters
    ----------
    quick
        Coarser grids (about a tenth of the trials), for tests and a first look.
    progress
        Called with the number of trials just finished.
    stage
        The robot to measure (default: the protocols' own), e.g. to identify its
        motion parameters (``scripts/identify_stage.py``).

    Returns
    -------
    list of Observable
        One per :data:`SPECS` entry, in its order.
    """
    p4 = get_protocol("radial-distance")
    p5 = get_protocol("angle-texture")
    if stage is not None:
        p4, p5 = replace(p4, stage=stage), replace(p5, stage=stage)
    # the same robot pushing on without the MI retraction (its threshold never crossed)
    # until the whisker slips past the pole (300 mm of travel: the robot's x range is
    # 350 mm, thesis 3.3)
    p4_passive = replace(p4, stage=replace(p4.stage, threshold_v=1e9, max_travel_mm=300.0))
    pl = plan(quick)
    fs4, fs5 = p4.sensor.sample_rate_hz, p5.sensor.sample_rate_hz
    model = runner.whisker_model(p4.whisker, p4.n_elements, 0.0)

    surface = _surface_trials(p5, pl.surface_points, _GROUP_SURFACE, progress)
    measured = _measure_resonance(model, surface, fs5)
    grid = _pole_trials(p4, _speed_major(pl.grid_radii, pl.grid_speeds), _GROUP_GRID, progress)
    passive = _pole_trials(
        p4_passive, _speed_major(pl.passive_radii, pl.passive_speeds), _GROUP_PASSIVE, progress
    )
    measured |= _measure_chapter4_grid(grid, pl.grid_radii, fs4, passive)
    measured |= _measure_chapter5(surface, fs5)
    near = _pole_trials(p4, _speed_major(pl.near_radii, pl.near_speeds), _GROUP_NEAR, progress)
    measured |= _measure_closest_contact(
        near, pl.near_radii, list(p4.sensor.calibration_point(model.geometry))
    )
    tip = _pole_trials(p4, _speed_major(pl.tip_radii, pl.tip_speeds), _GROUP_TIP, progress)
    measured |= _measure_tip_zone(tip, pl.tip_radii, pl.tip_speeds, model.geometry.length_mm)
    fast = _pole_trials(p4, _speed_major(pl.fast_radii, pl.fast_speeds), _GROUP_FAST, progress)
    measured |= _measure_above_216(fast, grid)

    if set(measured) != {s.name for s in SPECS}:
        raise RuntimeError(f"measured {sorted(measured)}, specified {[s.name for s in SPECS]}")
    fields = {"near_speed_min": min(pl.near_speeds), "near_speed_max": max(pl.near_speeds)}
    return [spec.observable(*measured[spec.name], fields) for spec in SPECS]
