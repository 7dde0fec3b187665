"""Identify the XY whisker's unknown parameters from the thesis' observables.

Two parameters the thesis does not give are set here, each from one physical
statement of the thesis (see ``docs/physics.md``, "Parameters and their sources"):

1. follicle stiffness ``k_f``: the first mode of the whisker with its tip held by
   the surface is the 30 Hz resonance of 5.3.1;
2. the MI loop's fixed delay: the median time from first contact to the start of
   the retraction over a 6 x 6 chapter-4 grid is the ~300 ms of 3.3.2 (the
   threshold crossing comes after first contact by a delay that depends on radius
   and speed, so the delay is iterated to a fixed point).

The script prints the values; they are written into ``vibrissa.whisker.geometry``
and ``vibrissa.robots.xy_stage`` by hand, with this script named as their source.
It also measures the mechanics quoted in ``docs/physics.md`` beside them (free,
clamped and pinned first modes, modal damping, the span of the Hall calibration,
the explicit time-step limit); ``--json OUT`` writes everything as a run file for
``scripts/render_docs.py``.
The Hall calibration of the chapter-4 protocol (60 mm at r = 80 mm) is not
identified here: ``vibrissa identify`` checks that it puts the closest usable
contact near the thesis' 80 mm. Run:

    .venv/bin/python scripts/identify_parameters.py [--json docs/runs/identify_parameters.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import scipy.optimize

from vibrissa.experiments.protocols import get_protocol
from vibrissa.robots.xy_stage import LatencyModel, PoleStimulus, run_trial
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSensor, calibrated_gain
from vibrissa.whisker.rod import RodModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
from render_docs import run_meta, write_run

RESONANCE_HZ = 30.0  # 5.3.1
LATENCY_S = 0.300  # 3.3.2


def follicle_stiffness() -> float:
    g = preset("xy-robot")

    def f(kf: float) -> float:
        m = RodModel(g.replace(follicle_stiffness_nm_per_rad=kf), 28)
        return float(m.pinned_frequencies_hz(g.length_mm)[0]) - RESONANCE_HZ

    return float(scipy.optimize.brentq(f, 0.005, 5.0, xtol=1e-5))


def _trial(p, model, gain, r, v, delay):
    stage = dataclasses.replace(p.stage, latency=LatencyModel(delay, p.stage.latency.duty_cycle_s))
    sensor = HallSensor(gain, sample_rate_hz=p.sensor.sample_rate_hz, noise_v=0.0)
    return run_trial(
        stage,
        model,
        sensor,
        PoleStimulus(r),
        v,
        1,
        p.window_s,
        np.random.default_rng(0),
        dt_s=p.dt_s,
    )


def mechanics() -> dict[str, Any]:
    """The XY whisker's modes and related figures quoted in ``docs/physics.md``.

    Returns
    -------
    dict
        Frequencies in Hz, stiffnesses in N m/rad, moduli in GPa, angles in degrees,
        times in microseconds (``_us``) or seconds.
    """
    g = preset("xy-robot")
    n = 28
    model = RodModel(g, n)
    zeta, _ = model.modal_damping(*model.damping, n_modes=3)
    rigid = RodModel(g, n, rigid_follicle=True)

    def clamped_first(e_gpa: float) -> float:
        m = RodModel(g.replace(youngs_modulus_gpa=e_gpa), n, rigid_follicle=True)
        return float(m.natural_frequencies_hz[0])

    fitted = g.replace(youngs_modulus_gpa=1.5, base_radius_mm=1.2, length_mm=230.0)  # table 4.1
    soft_kf = 0.02
    soft = RodModel(g.replace(follicle_stiffness_nm_per_rad=soft_kf), n)
    radii = np.arange(80.0, 181.0, 1.0)
    pole = np.array([model.pinned_frequencies_hz(r)[0] for r in radii])
    p4, p5 = get_protocol("radial-distance"), get_protocol("angle-texture")
    tan_323 = 0.5 * 0.9 * 5.0 / calibrated_gain(g, n, (150.0, 60.0))
    element_m = g.length_mm * 1e-3 / n
    wave_m_s = math.sqrt(g.youngs_modulus_gpa * 1e9 / g.density_kg_m3)
    explicit_dt_s = element_m / wave_m_s
    return {
        "follicle_stiffness_nm_per_rad": g.follicle_stiffness_nm_per_rad,
        "free_first_mode_hz": float(model.natural_frequencies_hz[0]),
        "damping_ratio_modes": [float(z) for z in zeta],
        "clamped_first_mode_hz": float(rigid.natural_frequencies_hz[0]),
        "clamped_modulus_for_resonance_gpa": float(
            scipy.optimize.brentq(lambda e: clamped_first(e) - RESONANCE_HZ, 0.5, 20.0, xtol=1e-4)
        ),
        "fitted_table_4_1_clamped_first_mode_hz": float(
            RodModel(fitted, n, rigid_follicle=True).natural_frequencies_hz[0]
        ),
        "tip_pinned_hz": {
            "current": float(model.pinned_frequencies_hz(g.length_mm)[0]),
            "soft_follicle": float(soft.pinned_frequencies_hz(g.length_mm)[0]),
            "soft_follicle_nm_per_rad": soft_kf,
            "rigid_follicle": float(rigid.pinned_frequencies_hz(g.length_mm)[0]),
        },
        "pole_pinned_hz": {
            "min": float(pole.min()),
            "max": float(pole.max()),
            "radius_of_max_mm": float(radii[np.argmax(pole)]),
            "at_80_mm": float(pole[0]),
            "at_180_mm": float(pole[-1]),
        },
        "hall_323_calibration_tilt_deg": math.degrees(math.atan(tan_323)),
        "explicit_axial_limit": {
            "element_mm": element_m * 1e3,
            "dt_us": explicit_dt_s * 1e6,
            "step_ratio_chapter4": p4.dt_s / explicit_dt_s,
            "step_ratio_chapter5": p5.dt_s / explicit_dt_s,
        },
    }


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--json",
        metavar="OUT",
        default=None,
        help="also write a run file (docs/runs/identify_parameters.json)",
    )
    args = ap.parse_args(argv)
    out: dict[str, Any] = {}
    kf = follicle_stiffness()
    out["identified_follicle_stiffness_nm_per_rad"] = kf
    print(f"follicle stiffness for a {RESONANCE_HZ:g} Hz tip-pinned mode: {kf:.4f} N m/rad")
    out["mechanics"] = mech = mechanics()
    for k, v in mech.items():
        print(f"{k}: {v}")
    p = get_protocol("radial-distance")
    g = preset("xy-robot").replace(follicle_stiffness_nm_per_rad=round(kf, 3))
    model = RodModel(g, p.n_elements)
    delay = p.stage.latency.latency_s
    radii = np.linspace(80.0, 180.0, 6)
    speeds = np.linspace(36.0, 216.0, 6)
    gain = calibrated_gain(g, p.n_elements, p.sensor.calibration_mm)
    for it in range(4):
        lat = [_trial(p, model, gain, r, v, delay).mi_latency_s for r in radii for v in speeds]
        print(
            f"iteration {it}: loop delay {delay * 1e3:.1f} ms -> median latency from first "
            f"contact {np.median(lat) * 1e3:.1f} ms"
        )
        delay += LATENCY_S - float(np.median(lat))
    print(f"loop delay: {delay * 1e3:.1f} ms")
    out["loop_delay_ms"] = delay * 1e3
    out["protocol_loop_delay_ms"] = p.stage.latency.latency_s * 1e3
    if args.json:
        cmd = ".venv/bin/python scripts/identify_parameters.py --json " + args.json
        write_run(args.json, {"meta": run_meta(cmd, None), **out})


if __name__ == "__main__":
    main()
