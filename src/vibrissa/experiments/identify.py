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
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
import scipy.signal

from vibrissa.experiments import runner
from vibrissa.experiments.protocols import Protocol, get_protocol
from vibrissa.experiments.streams import trial_stream
from vibrissa.robots.xy_stage import PoleStimulus, SurfaceStimulus, TrialResult, run_trial
from vibrissa.signal import contact_duration
from vibrissa.whisker.rod import RodModel

__all__ = [
    "Observable",
    "identify",
    "ring_ratio",
    "spectral_peak_hz",
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
            protocol.stage, model, sensor, PoleStimulus(r), v, 1, protocol.window_s, rng,
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
            protocol.stage, model, sensor, SurfaceStimulus(texture, angle), v, 1,
            protocol.window_s, rng, dt_s=protocol.dt_s,
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

    @property
    def n_trials(self) -> int:
        return (
            len(self.grid_radii) * len(self.grid_speeds)
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


# --------------------------------------------------------------------------- observables
def identify(quick: bool = False, progress: Progress | None = None) -> list[Observable]:
    """Measure every observable of the thesis on the simulated robot.

    Parameters
    ----------
    quick
        Coarser grids (about a tenth of the trials), for tests and a first look.
    progress
        Called with the number of trials just finished.

    Returns
    -------
    list of Observable
    """
    p4 = get_protocol("radial-distance")
    p5 = get_protocol("angle-texture")
    pl = plan(quick)
    fs4, fs5 = p4.sensor.sample_rate_hz, p5.sensor.sample_rate_hz
    model = runner.whisker_model(p4.whisker, p4.n_elements, 0.0)
    obs: list[Observable] = []

    # -- resonance ------------------------------------------------------------
    free = float(model.natural_frequencies_hz[0])
    tip_modes = model.pinned_frequencies_hz(model.geometry.length_mm)
    tip = float(tip_modes[0])
    rigid = float(RodModel(model.geometry, model.n_elements, rigid_follicle=True)
                  .natural_frequencies_hz[0])
    surf = _surface_trials(p5, pl.surface_points, 3, progress)
    sig5 = np.stack([res.signal_v[0] for *_, res in surf])
    fft_peak = spectral_peak_hz(sig5, fs5)
    obs.append(Observable(
        "resonance_hz",
        "first bending mode of the whisker with its tip held by the surface (linearised, "
        "follicle spring included); the chapter-5 stimulus holds the tip for most of each "
        "recording",
        "30 Hz, 'identified by inspection of the FFT' of the chapter-5 recordings, still "
        "present after the 35 Hz high-pass (5.3.1)",
        30.0, tip, "Hz", "within 10 %", abs(tip - 30.0) <= 3.0,
        {"free_first_mode_hz": free, "rigid_follicle_free_first_mode_hz": rigid,
         "tip_pinned_first_modes_hz": tip_modes.tolist(),
         "pinned_first_mode_by_radius_hz": {
             str(int(r)): float(model.pinned_frequencies_hz(r)[0])
             for r in (80.0, 100.0, 130.0, 160.0, 180.0)},
         "chapter5_fft_peak_hz": fft_peak, "n_chapter5_trials": len(surf)},
    ))

    # -- loop latency, durations, ringing on the chapter-4 grid ------------------
    grid = [(r, v) for v in pl.grid_speeds for r in pl.grid_radii]
    g4 = _pole_trials(p4, grid, 1, progress)
    lat = np.array([res.mi_latency_s for *_, res in g4]) * 1e3
    thr = np.array([res.threshold_time_s - res.contact_onset_s for *_, res in g4]) * 1e3
    med = float(np.nanmedian(lat))
    obs.append(Observable(
        "mi_latency_ms",
        "first contact to the start of the retraction, median over a radius x speed grid",
        "'Temporal latency for the loop is ~300 ms from initial contact' (3.3.2, 5.2)",
        300.0, med, "ms", "median within 300 +/- 30 ms", abs(med - 300.0) <= 30.0,
        {"percentiles_5_50_95_ms": np.nanpercentile(lat, [5, 50, 95]).tolist(),
         "contact_to_threshold_ms_5_50_95": np.nanpercentile(thr, [5, 50, 95]).tolist(),
         "n_trials": len(g4)},
    ))
    width = contact_duration(np.stack([res.signal_v[0] for *_, res in g4]), fs4, mode="peak")
    dur: dict[float, dict[float, float]] = {}
    usable: set[tuple[float, float]] = set()
    for (r, v, res), w in zip(g4, width, strict=True):
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
    obs.append(Observable(
        "duration_grows_with_speed",
        "deflection duration as the thesis measured it (feature f2: time above 0.05 V, "
        "4.3.4, the run above threshold holding the peak); fraction of neighbouring-speed "
        "pairs at the same radius, both usable (no slip-off, no saturation), where it is "
        "longer at the higher speed",
        "deflection duration grows with contact speed and discriminates speed (4.3.4)",
        None, frac, "fraction", "at least 0.9", frac >= 0.9,
        {"pairs": pairs, "wrong_way": int(wrong),
         "f2_ms_by_radius": {str(r): {str(v): 1e3 * d for v, d in sorted(b.items())}
                             for r, b in dur.items()},
         "contact_ms_by_radius": {
             str(r): {str(v): 1e3 * (res.contact_end_s - res.contact_onset_s)
                      for rr, v, res in g4 if rr == r} for r in pl.grid_radii}},
    ))
    rings = np.array([ring_ratio(res, fs4) for *_, res in g4])
    med_ring = float(np.nanmedian(rings))
    obs.append(Observable(
        "ringing_chapter4",
        "first overshoot past rest after the object leaves the whisker, fraction of the "
        "peak; median over the chapter-4 grid",
        "MI keeps 'whisker ringing after contact to a minimum' (3.3)",
        None, med_ring, "fraction of peak", "median at most 0.1", med_ring <= 0.1,
        {"percentiles_5_50_95": np.nanpercentile(rings, [5, 50, 95]).tolist()},
    ))
    rings5 = np.array([ring_ratio(res, fs5) for *_, res in surf])
    ringing5 = float(np.nanmean(rings5 > 0.1))
    obs.append(Observable(
        "ringing_chapter5",
        "fraction of chapter-5 trials whose first overshoot exceeds 10 % of the peak",
        "'oscillatory ringing after contact on some trials but not others' (5.4, fig. 5.2)",
        None, ringing5, "fraction of trials", "between 0.1 and 0.9",
        0.1 <= ringing5 <= 0.9,
        {"ratio_percentiles_5_50_95": np.nanpercentile(rings5, [5, 50, 95]).tolist()},
    ))
    d5 = np.array([res.contact_end_s - res.contact_onset_s for *_, res in surf]) * 1e3
    med5 = float(np.nanmedian(d5))
    obs.append(Observable(
        "contact_duration_chapter5_ms",
        "first contact of the chapter-5 stimulus, onset to end, median",
        "'Contact duration in this experiment is quite short (~300 ms)' (5.5)",
        300.0, med5, "ms", "median within 300 +/- 60 ms", abs(med5 - 300.0) <= 60.0,
        {"percentiles_5_50_95_ms": np.nanpercentile(d5, [5, 50, 95]).tolist()},
    ))

    # -- closest usable contact -------------------------------------------------
    near = [(r, v) for v in pl.near_speeds for r in pl.near_radii]
    n4 = _pole_trials(p4, near, 2, progress)
    sat: dict[float, list[float]] = {}
    for r, v, res in n4:
        if res.saturated:
            sat.setdefault(r, []).append(v)
    clean = [r for r in pl.near_radii if r not in sat]
    closest = float("nan")
    for r in sorted(pl.near_radii):
        if all(q in clean for q in pl.near_radii if q >= r):
            closest = r
            break
    obs.append(Observable(
        "closest_usable_contact_mm",
        f"smallest radius from which on no contact at {min(pl.near_speeds):g}-"
        f"{max(pl.near_speeds):g} mm/s saturates the sensor",
        "'the closest contact that could be made ... at any reasonable speed without "
        "saturating the Hall effect sensor was ~80 mm' (4.2)",
        80.0, closest, "mm", "80 +/- 10 mm", abs(closest - 80.0) <= 10.0,
        {"saturating_speeds_by_radius": {str(r): v for r, v in sorted(sat.items())},
         "calibration_mm": list(p4.sensor.calibration_point(model.geometry))},
    ))

    # -- tip zone ------------------------------------------------------------------
    tipg = [(r, v) for v in pl.tip_speeds for r in pl.tip_radii]
    t4 = _pole_trials(p4, tipg, 4, progress)
    L = model.geometry.length_mm
    zone: dict[float, float] = {}
    for v in pl.tip_speeds:
        slipped = [r for r, vv, res in t4 if vv == v and res.slipped_off]
        zone[v] = L - min(slipped) if slipped else 0.0
    worst = max(zone.values())
    obs.append(Observable(
        "tip_zone_mm",
        "distance from the tip within which the whisker slips past the object before the "
        "retraction; largest over speeds in the grid",
        "'Contacts at less than 5 mm from the tip did not deflect the base ... before "
        "slipping past' (4.2)",
        5.0, worst, "mm", "at most 10 mm at every speed up to 216 mm/s", worst <= 10.0,
        {"tip_zone_mm_by_speed": {str(v): z for v, z in zone.items()},
         "radii_tested_mm": list(pl.tip_radii)},
    ))

    # -- above 216 mm/s -----------------------------------------------------------------
    fastg = [(r, v) for v in pl.fast_speeds for r in pl.fast_radii]
    f4 = _pole_trials(p4, fastg, 5, progress)
    fails = np.array([res.slipped_off or res.saturated for *_, res in f4])
    frac_fail = float(fails.mean())
    obs.append(Observable(
        "above_216_mm_s",
        "fraction of contacts faster than 216 mm/s (over the chapter-4 radii) that slip past "
        "or saturate",
        "'Contact speeds above 216 mm/s either cause the whisker to slip past the object "
        "before a retraction, or saturates the sensors' (4.2)",
        None, frac_fail, "fraction", "at least 0.75", frac_fail >= 0.75,
        {"grid_fraction_slipped_or_saturated_up_to_216": float(np.mean(
            [res.slipped_off or res.saturated for *_, res in g4])),
         "trials": [{"radius_mm": r, "speed_mm_s": v, "slipped_off": res.slipped_off,
                     "saturated": res.saturated} for r, v, res in f4]},
    ))
    return obs
