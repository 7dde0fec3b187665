"""Where a standard contact's time goes, down to the kernels: the cost anatomy.

Usage::

    .venv/bin/python benchmarks/anatomy_physics.py [--out FILE] [--repeats N]

``profile_physics.py`` says which Python-visible calls take the time (the rod's
``run_dynamics`` dominates); this script opens that call up, for planning the next
speed-ups of the standard pole contact of ``vibrissa bench physics``:

* **Phases.** The trial's rows split by what the whisker does (approach, the push,
  the contact during the retraction, nonlinear free flight after the release, exact
  linear free flight), each with its solved steps, long steps by length and Newton
  iterations (read from the result's ``newton_iterations``: a solved row carries
  its step's iterations, a row inside a long step or in linear free flight 0).
* **Wall split.** One trial's wall time divided among ``run_dynamics`` (nonlinear
  rod), ``modal_advance`` (linear free flight) and everything else (Python: the
  hand-over tests, mode projections, set-up), by timing wrappers (best of
  ``--repeats``).
* **Kernels.** Per-call times of what one Newton iteration does, at a state in the
  middle of the push: the force assembly without and with the iteration matrix, the
  band factorisation (with the copy it needs here) and the back-substitution; and of
  the Python-side hand-over helpers. Each kernel is timed in a compiled loop.
* **Planar what-if.** The same factorisation and back-substitution for the band a
  planar (two unknowns per node) formulation would solve, ``2 n`` rows and half
  bandwidth 5 against ``3 n`` and 8 (random diagonally dominant matrices; a measure
  of the linear algebra only, not of a planar rod, which does not exist).

Single-threaded; timings are the best of ``--repeats``. Writes JSON (default
``benchmarks/results/anatomy.json``, atomically) and prints a summary.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import importlib
import inspect
import json
import sys
import time
import timeit
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numba import njit

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.whisker._kernels import _assemble, band_backsolve, band_factor

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "anatomy.json"
PLANAR_BW = 5  # half bandwidth with two unknowns per node and a three-node stencil


def _setup() -> dict[str, Any]:
    from vibrissa.whisker import RodModel, preset
    from vibrissa.whisker.benchmark import STANDARD, standard_trajectory
    from vibrissa.whisker.simulate import PoleContact

    model = RodModel(preset(STANDARD["preset"]))
    contact = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    return {
        "model": model,
        "contact": contact,
        "traj": standard_trajectory(model),
        "T": STANDARD["duration_s"],
        "dt": STANDARD["dt_s"],
        "retract_s": STANDARD["advance_s"],
    }


def phases(s: dict[str, Any]) -> dict[str, Any]:
    """Solved steps, long steps and Newton iterations in each phase of one trial."""
    from vibrissa.whisker.simulate import simulate

    res = simulate(s["model"], s["contact"], s["traj"], s["T"], s["dt"])
    it = res.newton_iterations.astype(int)
    touching = res.contact_force_n > 0.0
    rows = np.arange(it.size)
    first = int(np.argmax(touching))
    last = int(rows[touching][-1])
    retract = int(round(s["retract_s"] / s["dt"]))
    longest = inspect.signature(simulate).parameters["max_stride"].default
    solved = np.flatnonzero(it > 0)
    # rows each solved step advanced: a gap longer than the longest step is exact
    # linear free flight (at least MIN_LINEAR_STEPS rows) followed by a single step,
    # which is how the rod always resumes
    gaps = np.diff(np.concatenate([[0], solved]))
    lengths = np.where(gaps > longest, 1, gaps)
    step_len = np.zeros(it.size, dtype=int)
    step_len[solved] = lengths
    # rows inside a long step read 0 iterations too: mark them as covered by it
    covered = np.zeros(it.size, dtype=bool)
    for r, n in zip(solved, lengths, strict=True):
        covered[r - n + 1 : r + 1] = True
    linear = ~covered
    linear[0] = False
    spans = {
        "approach": (1, first),
        "push": (first, retract + 1),  # the step ending as the pole turns is the push's
        "retraction_contact": (retract + 1, last + 1),
        "after_release": (last + 1, it.size),
    }
    out: dict[str, Any] = {
        "rows": int(it.size - 1),
        "first_contact_row": first,
        "retraction_row": retract,
        "last_contact_row": last,
    }
    for name, (a, b) in spans.items():
        sel = slice(a, b)
        lens = step_len[sel][it[sel] > 0]
        out[name] = {
            "rows": int(b - a),
            "rows_in_contact": int(touching[sel].sum()),
            "rows_linear_free_flight": int(linear[sel].sum()),
            "solved_steps": int((it[sel] > 0).sum()),
            "newton_iterations": int(it[sel].sum()),
            "steps_by_length_dt": {
                str(k): int(v) for k, v in zip(*np.unique(lens, return_counts=True), strict=True)
            },
        }
    out["total"] = {
        "solved_steps": int(solved.size),
        "newton_iterations": int(it.sum()),
        "rows_linear_free_flight": int(linear.sum()),
    }
    return out


def wall_split(s: dict[str, Any], repeats: int) -> dict[str, float]:
    """One trial's wall time: run_dynamics, modal_advance and the rest (best of N)."""
    # the module, not the function vibrissa.whisker re-exports under its name
    sim = importlib.import_module("vibrissa.whisker.simulate")
    spent = {"run_dynamics": 0.0, "modal_advance": 0.0}
    originals = {name: getattr(sim, name) for name in spent}

    def timed(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            t0 = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                spent[name] += time.perf_counter() - t0

        return wrapper

    best: dict[str, float] | None = None
    try:
        for name, fn in originals.items():
            setattr(sim, name, timed(name, fn))
        sim.simulate(s["model"], s["contact"], s["traj"], s["T"], s["dt"])  # warm-up
        for _ in range(repeats):
            for k in spent:
                spent[k] = 0.0
            t0 = time.perf_counter()
            sim.simulate(s["model"], s["contact"], s["traj"], s["T"], s["dt"])
            total = time.perf_counter() - t0
            if best is None or total < best["total_ms"] * 1e-3:
                best = {
                    "total_ms": total * 1e3,
                    "run_dynamics_ms": spent["run_dynamics"] * 1e3,
                    "modal_advance_ms": spent["modal_advance"] * 1e3,
                    "rest_ms": (total - sum(spent.values())) * 1e3,
                }
    finally:
        for name, fn in originals.items():
            setattr(sim, name, fn)
    assert best is not None
    best["simulated_s"] = s["T"]
    best["real_time_factor"] = s["T"] / (best["total_ms"] * 1e-3)
    return best


@njit
def _loop_assemble(n_calls, x, v, rod, damping, spec, tr, anchors, F, S, jac, info):
    for _ in range(n_calls):
        _assemble(x, v, rod, damping, spec, tr, anchors, F, S, 1.0e3, 0.5, jac, info)


@njit
def _loop_factor(n_calls, S0, S, bw):
    for _ in range(n_calls):
        S[:, :] = S0
        if bw == 8:
            band_factor(S)
        else:
            _factor_planar(S)


@njit
def _factor_planar(A):
    """LU without pivoting of a band of half width 5, full-band rows unrolled as in
    the rod's band_factor (what-if only)."""
    n = A.shape[0]
    rowk = np.empty(PLANAR_BW + 1)
    for k in range(n):
        inv = 1.0 / A[k, PLANAR_BW]
        A[k, PLANAR_BW] = inv
        iend = min(n, k + PLANAR_BW + 1)
        m = iend - k
        for jj in range(1, m):
            rowk[jj] = A[k, PLANAR_BW + jj]
        if m == PLANAR_BW + 1:
            for di in range(1, PLANAR_BW + 1):
                i = k + di
                base = PLANAR_BW - di
                lik = A[i, base] * inv
                if lik != 0.0:
                    A[i, base] = lik
                    for jj in range(1, PLANAR_BW + 1):
                        A[i, base + jj] -= lik * rowk[jj]
            continue
        for i in range(k + 1, iend):
            base = PLANAR_BW + k - i
            lik = A[i, base] * inv
            if lik != 0.0:
                A[i, base] = lik
                for jj in range(1, m):
                    A[i, base + jj] -= lik * rowk[jj]


@njit
def _backsolve_planar(A, rhs):
    """Back-substitution for half width 5, rows summed as trees like the rod's (what-if)."""
    n = A.shape[0]
    for i in range(n):
        if i >= 5:
            rhs[i] -= (
                (A[i, 0] * rhs[i - 5] + A[i, 1] * rhs[i - 4])
                + (A[i, 2] * rhs[i - 3] + A[i, 3] * rhs[i - 2])
            ) + A[i, 4] * rhs[i - 1]
        else:
            acc = rhs[i]
            for k in range(i):
                acc -= A[i, 5 + k - i] * rhs[k]
            rhs[i] = acc
    for i in range(n - 1, -1, -1):
        if i + 5 < n:
            rhs[i] = (
                rhs[i]
                - (
                    (
                        (A[i, 6] * rhs[i + 1] + A[i, 7] * rhs[i + 2])
                        + (A[i, 8] * rhs[i + 3] + A[i, 9] * rhs[i + 4])
                    )
                    + A[i, 10] * rhs[i + 5]
                )
            ) * A[i, 5]
        else:
            acc = rhs[i]
            for j in range(i + 1, n):
                acc -= A[i, 5 + j - i] * rhs[j]
            rhs[i] = acc * A[i, 5]


@njit
def _loop_backsolve(n_calls, A, rhs, bw):
    for _ in range(n_calls):
        if bw == 8:
            band_backsolve(A, rhs)
        else:
            _backsolve_planar(A, rhs)


def _per_call_us(
    loop: Callable[..., Any], args: tuple[Any, ...], repeats: int, n_calls: int = 20000
) -> float:
    loop(10, *args)  # compile
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        loop(n_calls, *args)
        best = min(best, (time.perf_counter() - t0) / n_calls)
    return best * 1e6


def kernels(s: dict[str, Any], repeats: int) -> dict[str, Any]:
    """Per-call times (us) of one Newton iteration's parts, in the middle of the push."""
    from vibrissa.whisker._kernels import BW, Anchors, Damping, _fix_rows
    from vibrissa.whisker.modal import linear_modes
    from vibrissa.whisker.simulate import _contact_spec, simulate

    model, dt = s["model"], s["dt"]
    row = int(round(0.15 / dt))
    res = simulate(
        model, s["contact"], s["traj"], row * dt, dt, record_every=1, linear_free_flight=False
    )
    x = res.states_m[-1].copy()
    v = res.velocities_m_s[-1].copy()
    rod = model.rod_arrays()
    damping = Damping(*(float(c) for c in model.damping))
    times = np.arange(row + 2) * dt
    spec, traj = _contact_spec(model, s["contact"], s["traj"], times)
    tr = traj[row].copy()
    n = x.shape[0]
    anchors = Anchors(res.final_state.pole_anchor.copy(), np.zeros((n, 6)))
    F = np.zeros_like(x)
    S = np.zeros((3 * n, 2 * BW + 1))
    info = np.zeros(12)
    out: dict[str, Any] = {"state_row": row, "unknowns": 3 * n, "half_bandwidth": BW}
    args = (x, v, rod, damping, spec, tr, anchors, F, S)
    out["assemble_forces_us"] = _per_call_us(_loop_assemble, (*args, False, info), repeats)
    out["assemble_forces_and_matrix_us"] = _per_call_us(
        _loop_assemble, (*args, True, info), repeats
    )
    out["contact_force_n"] = float(info[0])
    # the iteration matrix of a 0.25 ms step: mass term on the diagonal, fixed rows
    for i in range(n):
        for c in range(3):
            S[3 * i + c, BW] += 1.0 / (0.25 * dt * dt) * rod.mass[i]
    _fix_rows(S, np.zeros(3 * n), rod.free)
    S0 = S.copy()
    out["band_factor_with_copy_us"] = _per_call_us(_loop_factor, (S0, S.copy(), 8), repeats)
    A = S0.copy()
    _loop_factor(1, S0, A, 8)
    rhs = np.random.default_rng(0).standard_normal(3 * n) * 1e-9
    out["band_backsolve_us"] = _per_call_us(_loop_backsolve, (A, rhs, 8), repeats)
    # Python-side hand-over helpers, per call
    lm = linear_modes(model)
    z, _ = lm.amplitudes(x, v)
    out["python_us"] = {
        "nonlinearity": min(timeit.repeat(lambda: lm.nonlinearity(x), number=500, repeat=repeats))
        / 500
        * 1e6,
        "amplitudes": min(timeit.repeat(lambda: lm.amplitudes(x, v), number=500, repeat=repeats))
        / 500
        * 1e6,
        "state": min(timeit.repeat(lambda: lm.state(z), number=500, repeat=repeats)) / 500 * 1e6,
        "contact_spec_full_trial": min(
            timeit.repeat(
                lambda: _contact_spec(
                    model, s["contact"], s["traj"], np.arange(int(round(s["T"] / dt)) + 1) * dt
                ),
                number=20,
                repeat=repeats,
            )
        )
        / 20
        * 1e6,
    }
    return out


def planar_what_if(n_nodes: int, repeats: int) -> dict[str, Any]:
    """Factorisation and back-substitution of the 3-D band against a planar one."""
    rng = np.random.default_rng(1)

    def band(rows: int, bw: int) -> np.ndarray:
        A = rng.uniform(-0.01, 0.01, (rows, 2 * bw + 1))
        A[:, bw] = 10.0
        return A

    out: dict[str, Any] = {}
    for label, rows, bw in (("spatial", 3 * n_nodes, 8), ("planar", 2 * n_nodes, PLANAR_BW)):
        A0 = band(rows, bw)
        F = A0.copy()
        _loop_factor(1, A0, F, bw)
        rhs = rng.standard_normal(rows)
        out[label] = {
            "unknowns": rows,
            "half_bandwidth": bw,
            "band_factor_with_copy_us": _per_call_us(_loop_factor, (A0, A0.copy(), bw), repeats),
            "band_backsolve_us": _per_call_us(_loop_backsolve, (F, rhs, bw), repeats),
        }
    return out


def run(repeats: int) -> dict[str, Any]:
    """All four parts."""
    from vibrissa.whisker.benchmark import SCENARIO, _single_thread_blas

    s = _setup()
    with _single_thread_blas():
        result = {
            "scenario": SCENARIO,
            "n_elements": s["model"].n_elements,
            "phases": phases(s),
            "wall_split_ms": wall_split(s, repeats),
            "kernels": kernels(s, repeats),
            "planar_what_if": planar_what_if(s["model"].n_nodes, repeats),
            "repeats": repeats,
            "vibrissa_version": __version__,
            "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        }
    return result


def summary(result: dict[str, Any]) -> str:
    """A few lines for the terminal."""
    ph = result["phases"]
    w = result["wall_split_ms"]
    k = result["kernels"]
    lines = [
        f"standard contact: {w['total_ms']:.2f} ms ({w['real_time_factor']:.1f} x real "
        f"time): run_dynamics {w['run_dynamics_ms']:.2f}, modal_advance "
        f"{w['modal_advance_ms']:.2f}, rest {w['rest_ms']:.2f} ms"
    ]
    for name in ("approach", "push", "retraction_contact", "after_release"):
        p = ph[name]
        lines.append(
            f"  {name:19s} rows {p['rows']:5d}  solved {p['solved_steps']:4d}  "
            f"iterations {p['newton_iterations']:5d}  linear rows "
            f"{p['rows_linear_free_flight']:5d}  "
            f"steps by length {p['steps_by_length_dt']}"
        )
    lines.append(
        f"kernels (us): forces {k['assemble_forces_us']:.2f}, forces+matrix "
        f"{k['assemble_forces_and_matrix_us']:.2f}, factor "
        f"{k['band_factor_with_copy_us']:.2f}, back-substitution "
        f"{k['band_backsolve_us']:.2f}"
    )
    pw = result["planar_what_if"]
    lines.append(
        "planar what-if (us): factor {:.2f} -> {:.2f}, back-substitution {:.2f} -> {:.2f}".format(
            pw["spatial"]["band_factor_with_copy_us"],
            pw["planar"]["band_factor_with_copy_us"],
            pw["spatial"]["band_backsolve_us"],
            pw["planar"]["band_backsolve_us"],
        )
    )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help=f"JSON file to write (default {DEFAULT_OUT})."
    )
    parser.add_argument(
        "--repeats",
        type=int,
        default=5,
        help="Timed repeats of each measurement; the best counts (default 5).",
    )
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    if args.out.is_dir():
        parser.error(f"--out {args.out} is a directory")
    result = run(args.repeats)
    atomic_write_text(args.out, json.dumps(result, indent=2) + "\n")
    print(summary(result), file=sys.stderr)
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
