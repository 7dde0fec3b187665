"""Identify the contact signal's scale in eq. 3.2 from figure 3.9's outcomes (issue 31).

The thesis gives eqs. 3.2-3.3 and figure 3.9's two outcomes, but neither the contact
signal's units (the scale on which ``sigma_z`` acts) nor figure 3.9's whisk frequency.
This script whisks the simulated SCRATCHbot whisker into the pole of the SCRATCHbot
protocol's closed-loop comparison (the rod model, the Hall sensor's ``x``, eqs.
3.2-3.3 one control period at a time: :func:`vibrissa.robots.whisking.run_whisking`)
over a grid of scales (``RCPControl.signal_scale``: the contact signal per unit of the
filtered deflection as a fraction of the Hall half range) and whisk frequencies, at
both of figure 3.9's settings, and counts the contacts of every whisk
(:func:`vibrissa.robots.whisking.whisk_contacts`)::

    .venv/bin/python scripts/identify_rcp.py --json docs/runs/identify_rcp.json

A setting is admissible when sigma_z 0.7, tau_z T_w/4 gives exactly one contact in
every whisk (3.4.2: protraction suppressed during the contact, "the depth of contact is
controlled") and sigma_z 2, tau_z T_w/10 a biphasic whisk (two or more contacts) in
every whisk. The rule: the frequency is the thesis' own for both robots, 2 Hz (6.4.1;
the slowest of 6.3), if any scale is admissible there, else the frequency with the
widest admissible range; the scale is the geometric centre of the widest run of
consecutive admissible grid scales at that frequency, rounded to the grid point
nearest it (the outcome most robust to the scale in both directions). The script also
reports, for the chosen scale, the largest gating variable in air (whisking without
the pole: RCP should not suppress free whisking much) at each frequency.

The G1 (6.4) runs the same eqs. 3.2-3.3 on three longer whiskers per side. The script
checks each of :data:`G1_SCALES` against what the thesis says of the G1: under RCP7 and
RCP9 (tau_z T_w/4) each row touches the surface in every whisk (6.4 classifies those
contacts) and no whisk is biphasic (3.4.2: "this biphasic whisking was not
encountered"). The G1 takes the SCRATCHbot scale if the check holds there, else the
grid scale nearest it at which it holds (``g1_chosen``). ``--derive-only`` recomputes
both choices from an existing record. It takes about 10 min on two idle cores.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.reproduce.provenance import git_commit
from vibrissa.robots.whisking import CONTACT_DIP_FRACTION

#: Candidate scales: a log grid from half to 32 times the half-range fraction; 2.25 is
#: the deflection in volts from rest (half range 0.45 x 5 V).
SCALES = (
    0.5,
    0.75,
    1.0,
    1.5,
    2.0,
    2.25,
    2.5,
    2.75,
    3.0,
    3.25,
    3.5,
    4.0,
    5.0,
    6.0,
    8.0,
    12.0,
    16.0,
    32.0,
)
#: SCRATCHbot's whisk frequencies in 6.3 (2-6 Hz) and the rat's dominant 8 Hz (2.2.2).
FREQUENCIES_HZ = (2.0, 4.0, 6.0, 8.0)
#: Figure 3.9's panels: (sigma_z, tau_z in whisk periods).
SETTING_A = (0.7, 0.25)
SETTING_B = (2.0, 0.1)
#: Whisks simulated per run (from rest); every one is counted.
N_WHISKS = 4
#: A withdrawal of the housing of this fraction of the whisk amplitude separates contacts.
DIP_FRACTION = CONTACT_DIP_FRACTION


def run_setting(
    scale: float,
    frequency_hz: float,
    sigma_z: float,
    tau_z_periods: float,
    n_whisks: int = N_WHISKS,
    pole: bool = True,
) -> dict[str, Any]:
    """One closed-loop run on the SCRATCHbot protocol's pole; contacts per whisk.

    Parameters
    ----------
    scale
        ``RCPControl.signal_scale``.
    frequency_hz
        Whisk frequency.
    sigma_z, tau_z_periods
        Eq. 3.3's gain and time constant (whisk periods).
    n_whisks
        Whisks from rest.
    pole
        Whisk into the pole (False: in air).

    Returns
    -------
    dict
        ``contacts_per_whisk`` (list), ``max_z``, ``peak_deflection`` (fraction of the
        half range), ``force_runs`` (runs of contact force over the run).
    """
    from vibrissa.robots.whisking import (
        RCPControl,
        WhiskerSetup,
        WhiskPattern,
        pole_whisker,
        run_whisking,
        whisk_contacts,
    )
    from vibrissa.thesis.scratchbot.protocol import ScratchbotProtocol
    from vibrissa.whisker.geometry import preset
    from vibrissa.whisker.rod import RodModel

    p = ScratchbotProtocol()
    g = preset(p.whisker)
    model = RodModel(g, p.n_elements)
    sensor = p.sensor.calibrate(g, p.n_elements)
    setup = (
        pole_whisker(
            model,
            p.rcp_radial_distance_mm,
            p.contact_angle_deg,
            p.pole_radius_mm,
            hall_gain_v=sensor.gain_v,
        )
        if pole
        else WhiskerSetup(model, hall_gain_v=sensor.gain_v)
    )
    pattern = WhiskPattern(frequency_hz, p.amplitude_deg, p.retracted_deg)
    res = run_whisking(
        [setup],
        pattern,
        RCPControl(sigma_z, tau_z_periods, signal_scale=scale),
        n_whisks / frequency_hz,
        control_rate_hz=p.sensor.sample_rate_hz,
        dt_s=p.dt_s,
        motor_bandwidth_hz=p.motor_bandwidth_hz,
    )
    on = res.contact_force_n[0] > 0
    counts = whisk_contacts(
        res.time_s, res.angle_deg[0], on, frequency_hz, DIP_FRACTION * p.amplitude_deg
    )[:n_whisks]
    return {
        "contacts_per_whisk": [int(c) for c in counts],
        "max_z": float(res.gating[0].max()),
        "peak_deflection": float(np.abs(res.deflection[0]).max()),
        "force_runs": int(np.count_nonzero(np.diff(on.astype(np.int8)) == 1) + on[0]),
    }


def _point(args: tuple[float, float]) -> dict[str, Any]:
    scale, f = args
    a = run_setting(scale, f, *SETTING_A)
    b = run_setting(scale, f, *SETTING_B)
    one = all(c == 1 for c in a["contacts_per_whisk"])
    biphasic = all(c >= 2 for c in b["contacts_per_whisk"])
    return {
        "scale": scale,
        "frequency_hz": f,
        "a": a,
        "b": b,
        "a_one_contact_per_whisk": one,
        "b_biphasic_every_whisk": biphasic,
        "admissible": one and biphasic,
    }


def choose(rows: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The chosen (frequency, scale) by the module's rule, or None if nothing is admissible."""

    def widest(f: float) -> list[float]:
        best: list[float] = []
        run: list[float] = []
        for r in sorted((r for r in rows if r["frequency_hz"] == f), key=lambda r: r["scale"]):
            run = [*run, r["scale"]] if r["admissible"] else []
            if len(run) > len(best) or (
                len(run) == len(best) and run and run[-1] / run[0] > best[-1] / best[0]
            ):
                best = run
        return best

    runs = {f: widest(f) for f in FREQUENCIES_HZ}
    if runs.get(2.0):
        f = 2.0
    else:
        cands = [f for f, r in runs.items() if r]
        if not cands:
            return None
        f = max(cands, key=lambda f: (runs[f][-1] / runs[f][0], len(runs[f]), -f))
    run = runs[f]
    centre = math.sqrt(run[0] * run[-1])
    scale = min(run, key=lambda s: abs(math.log(s / centre)))
    return {
        "frequency_hz": f,
        "scale": scale,
        "admissible_run": run,
        "admissible_runs_per_frequency": {str(k): v for k, v in runs.items()},
        "geometric_centre": centre,
    }


#: G1 check (6.4, 3.4.2): scales tried, on one texture at the nearest and farthest distance.
G1_SCALES = (0.5, 1.0, 1.5, 2.0, 2.25, 2.75, 3.0)
G1_TEXTURE = "p180"
G1_DISTANCES_MM = (5.0, 15.0)
G1_WHISKS = 3


def g1_run(args: tuple[float, str, float]) -> dict[str, Any]:
    """One G1 class (RCP7 or RCP9) at ``scale``: contacts per whisk of every whisker.

    A side touches in a whisk when any of its whiskers does; a whisk is biphasic when a
    whisker has two or more contacts in it (:func:`vibrissa.robots.whisking.whisk_contacts`).
    """
    from vibrissa.robots.whisking import whisk_contacts
    from vibrissa.thesis.biotact_g1.protocol import biotact_protocol

    scale, strategy, distance = args
    p = biotact_protocol(
        textures=(G1_TEXTURE,),
        distances_mm=(distance,),
        strategies=(strategy,),
        n_whisks=G1_WHISKS,
        contact_signal_scale=scale,
    )
    r = p.simulate_class(0)
    fs, n = p.sensor.sample_rate_hz, p.head.n_whiskers
    counts = []
    for w in range(2 * n):
        ang = r["angle_deg"][:, w // n, :].reshape(-1)
        on = r["force_n"][:, w, :].reshape(-1) > 0
        t = np.arange(ang.size) / fs
        counts.append(
            whisk_contacts(
                t, ang, on, p.whisk_frequency_hz, DIP_FRACTION * p.head.amplitude_deg
            ).tolist()[:G1_WHISKS]
        )
    c = np.array(counts)
    touched = all(
        bool(c[side * n : (side + 1) * n, k].any()) for side in (0, 1) for k in range(G1_WHISKS)
    )
    return {
        "scale": scale,
        "strategy": strategy,
        "distance_mm": distance,
        "contacts_per_whisker_per_whisk": counts,
        "max_z": float(r["gating"].max()),
        "max_protraction_deg": float(r["angle_deg"].max()),
        "every_side_touches_every_whisk": touched,
        "biphasic": bool((c >= 2).any()),
    }


def choose_g1(out: dict[str, Any]) -> dict[str, Any] | None:
    """The G1's scale: SCRATCHbot's if the G1 check holds there, else the nearest that holds.

    Nearest on a log scale among :data:`G1_SCALES`; None if none holds.
    """
    chosen = out.get("chosen")
    ok = out["g1_check"]["consistent_per_scale"]
    if chosen is None:
        return None
    same = bool(ok.get(str(float(chosen["scale"]))))
    cands = [float(k) for k, v in ok.items() if v]
    if same:
        scale = float(chosen["scale"])
    elif cands:
        scale = min(cands, key=lambda k: (abs(math.log(k / chosen["scale"])), -k))
    else:
        return None
    return {
        "scale": scale,
        "same_as_scratchbot": same,
        "consistent_scales": sorted(cands),
        "rule": "the SCRATCHbot scale if the G1 check holds at it, else the grid scale "
        "nearest it (log) at which the G1 check holds",
    }


def main(argv: list[str] | None = None) -> int:
    """Run the grid and write the JSON record."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", type=Path, required=True, help="output file")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument(
        "--derive-only",
        action="store_true",
        help="recompute the choices of an existing --json file (no simulation)",
    )
    args = ap.parse_args(argv)
    if args.derive_only:
        try:
            out = json.loads(args.json.read_text())
            missing = [k for k in ("grid", "g1_check") if k not in out]
            if missing:
                raise KeyError(", ".join(missing))
        except (OSError, ValueError, KeyError) as e:
            ap.error(f"--json: {args.json} is not a record of this script ({e})")
        out["chosen"] = choose(out["grid"])
        out["g1_chosen"] = choose_g1(out)
        _write(args.json, out)
        print(f"chosen: {out['chosen']}; G1: {out['g1_chosen']}", file=sys.stderr)
        return 0
    if args.workers < 1:
        ap.error("--workers must be >= 1")
    if not args.json.parent.is_dir():
        ap.error(f"--json: folder {args.json.parent} does not exist")
    grid = [(s, f) for f in FREQUENCIES_HZ for s in SCALES]
    print(f"identify_rcp: {len(grid)} settings x 2 closed-loop runs", file=sys.stderr)
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(_point, grid))
    chosen = choose(rows)
    g1_jobs = [(sc, st, d) for sc in G1_SCALES for st in ("rcp7", "rcp9") for d in G1_DISTANCES_MM]
    print(f"identify_rcp: G1 check, {len(g1_jobs)} runs", file=sys.stderr)
    with ProcessPoolExecutor(args.workers) as pool:
        g1_rows = list(pool.map(g1_run, g1_jobs))
    g1_ok = {
        str(sc): all(
            r["every_side_touches_every_whisk"] and not r["biphasic"]
            for r in g1_rows
            if r["scale"] == sc
        )
        for sc in G1_SCALES
    }
    in_air = {}
    if chosen is not None:
        with ProcessPoolExecutor(args.workers) as pool:
            jobs = [(chosen["scale"], f, *SETTING_A, N_WHISKS, False) for f in FREQUENCIES_HZ]
            for f, r in zip(FREQUENCIES_HZ, pool.map(_in_air, jobs), strict=True):
                in_air[str(f)] = r
    from vibrissa import __version__
    from vibrissa.thesis.scratchbot.protocol import ScratchbotProtocol

    p = ScratchbotProtocol()
    out = {
        "meta": {
            "command": ".venv/bin/python scripts/identify_rcp.py --json "
            "docs/runs/identify_rcp.json",
            "commit": git_commit(),
            "vibrissa_version": __version__,
            "date": datetime.now(UTC).isoformat(timespec="seconds"),
            "whisker": p.whisker,
            "pole": {
                "radial_distance_mm": p.rcp_radial_distance_mm,
                "contact_angle_deg": p.contact_angle_deg,
                "pole_radius_mm": p.pole_radius_mm,
            },
            "whisk": {"amplitude_deg": p.amplitude_deg, "retracted_deg": p.retracted_deg},
            "control_rate_hz": p.sensor.sample_rate_hz,
            "whisks_per_run": N_WHISKS,
            "dip_deg": DIP_FRACTION * p.amplitude_deg,
            "counting": "vibrissa.robots.whisking.whisk_contacts: two runs of contact "
            "force are distinct contacts only if the housing withdrew by dip_deg and "
            "protraction resumed between them",
        },
        "swept": {
            "scales": list(SCALES),
            "frequencies_hz": list(FREQUENCIES_HZ),
            "setting_a": {"sigma_z": SETTING_A[0], "tau_z_periods": SETTING_A[1]},
            "setting_b": {"sigma_z": SETTING_B[0], "tau_z_periods": SETTING_B[1]},
        },
        "grid": rows,
        "rule": "admissible: (a) exactly one contact in every whisk and (b) two or more "
        "in every whisk; frequency 2 Hz (the thesis' G1 frequency, the slowest of 6.3) "
        "if any scale is admissible there, else the frequency with the widest admissible "
        "range; scale: the grid point nearest the geometric centre of the widest run of "
        "consecutive admissible scales",
        "chosen": chosen,
        "in_air_at_chosen_scale_setting_a": in_air,
        "g1_check": {
            "what": "6.4: the G1 whiskers touch the surface in every whisk under RCP7 and "
            "RCP9 (the thesis classifies their contacts) and 3.4.2: with sigma_z <= 0.9 and "
            "tau_z T_w/4 'this biphasic whisking was not encountered'; one texture, the "
            "nearest and farthest distance, whisks after a lead-in",
            "texture": G1_TEXTURE,
            "distances_mm": list(G1_DISTANCES_MM),
            "whisks": G1_WHISKS,
            "runs": g1_rows,
            "consistent_per_scale": g1_ok,
        },
    }
    out["g1_chosen"] = choose_g1(out)
    _write(args.json, out)
    for r in rows:
        print(
            f"f={r['frequency_hz']:g} Hz scale={r['scale']:g}: (a) {r['a']['contacts_per_whisk']}"
            f" z<={r['a']['max_z']:.2f}  (b) {r['b']['contacts_per_whisk']} "
            f"z<={r['b']['max_z']:.2f}  {'ADMISSIBLE' if r['admissible'] else ''}",
            file=sys.stderr,
        )
    for r in g1_rows:
        print(
            f"G1 scale={r['scale']:g} {r['strategy']} {r['distance_mm']:g} mm: "
            f"{r['contacts_per_whisker_per_whisk']} z<={r['max_z']:.2f} "
            f"touch={r['every_side_touches_every_whisk']} biphasic={r['biphasic']}",
            file=sys.stderr,
        )
    print(f"chosen: {chosen}; G1 consistent per scale: {g1_ok}", file=sys.stderr)
    return 0


def _write(path: Path, out: dict[str, Any]) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as fh:
        json.dump(out, fh, indent=1, sort_keys=True)
        fh.write("\n")
    os.replace(tmp, path)


def _in_air(args: tuple[Any, ...]) -> dict[str, Any]:
    r = run_setting(*args)
    return {"max_z": r["max_z"], "peak_deflection": r["peak_deflection"]}


if __name__ == "__main__":
    sys.exit(main())
