"""Where the compiled solver spends its time, per numba function (Linux ``perf`` sampling).

Usage::

    .venv/bin/python benchmarks/profile_kernels.py [--case standard-contact|floor|all]
        [--seconds S] [--frequency HZ] [--out benchmarks/results/kernel_profile.json]

``cProfile`` sees a numba kernel as one entry (``run_dynamics``); this script splits it.
For each case it starts a worker process with an empty numba cache of its own (so the
kernels are compiled there and numba still holds their LLVM modules, whose functions'
addresses it reads), lets the worker compile and warm up, then samples the worker's
instruction pointer with ``perf record -p PID`` while it repeats the case for
``--seconds``, and attributes every sample to the compiled function whose code holds it
(the nearest function start below it in ``run_dynamics``' library; numba inlines the
small helpers marked ``inline="always"`` into their callers, so those never appear).
Samples outside the compiled code are reported by shared object (``libc`` is mostly
``malloc``/``free``; ``_nrt_python``/``NRT_*`` numba's reference counting).

The cases:

- ``standard-contact``: the standard pole contact of ``vibrissa bench physics``
  (xy-robot whisker, the default element count), repeated;
- ``floor``: three floor-texture trials (rough carpet clockwise, tarmac spot, smooth
  carpet spot; 3 recorded seconds each) of the full protocol, repeated.

Needs ``perf`` (Debian: ``apt-get install linux-perf``) and permission to sample another
process (``/proc/sys/kernel/perf_event_paranoid`` <= 1, or root). Shares are fractions
of the samples; the sampling rate does not change them beyond noise. Writes JSON
atomically (default ``benchmarks/results/kernel_profile.json``) and prints the shares.
"""

from __future__ import annotations

import argparse
import bisect
import datetime as _dt
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import vibrissa
from vibrissa import __version__
from vibrissa._atomic import atomic_write_text

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "kernel_profile.json"
CASES = ("standard-contact", "floor")
#: A mangled numba name: ``..._kernels<len><name>B<n>...``; group 1 is the Python name.
_MANGLED = re.compile(r"_kernels\d+([A-Za-z_][A-Za-z0-9_]*?)B\d")

#: The worker: compile, write its symbol table, wait for the sampler, repeat the case.
WORKER = r"""
import json, sys, time
case, seconds, ready, table = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
if case == "standard-contact":
    from vibrissa.whisker.benchmark import STANDARD, standard_trajectory
    from vibrissa.whisker.geometry import preset
    from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS, RodModel
    from vibrissa.whisker.simulate import PoleContact, simulate
    model = RodModel(preset(STANDARD["preset"]), DEFAULT_N_ELEMENTS)
    contact = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    traj = standard_trajectory(model)
    def once():
        simulate(model, contact, traj, STANDARD["duration_s"], STANDARD["dt_s"])
else:
    import dataclasses
    from vibrissa.reproduce import get_experiment
    protocol = get_experiment("floor-texture").protocol_for(False, 0, {})
    protocol = dataclasses.replace(protocol, duration_s=3.0)
    first = {}
    for i, spec in enumerate(protocol.trials()):
        first.setdefault((spec.floor, spec.condition), i)
    picks = [first[("rough-carpet", "clockwise")], first[("tarmac", "spot")],
             first[("smooth-carpet", "spot")]]
    def once():
        protocol.simulate_trials(picks)
once()
from vibrissa.whisker import _kernels
rows = []
for cres in _kernels.run_dynamics.overloads.values():
    lib = cres.library
    for fn in lib._final_module.functions:
        if fn.is_declaration:
            continue
        try:
            address = lib.get_pointer_to_function(fn.name)
        except Exception:
            continue
        if address:
            rows.append([address, fn.name])
with open(table, "w") as fh:
    json.dump(rows, fh)
open(ready, "w").close()
time.sleep(1.0)  # the sampler attaches
t0 = time.perf_counter()
n = 0
while time.perf_counter() - t0 < seconds:
    once()
    n += 1
print(json.dumps({"repeats": n, "wall_seconds": time.perf_counter() - t0}))
"""


def _python_name(mangled: str) -> str:
    m = _MANGLED.search(mangled)
    return m.group(1) if m else mangled[:60]


def attribute(samples: list[tuple[int, str]], table: list[tuple[int, str]]) -> dict[str, int]:
    """Count samples per compiled function (by start address) or per shared object.

    Parameters
    ----------
    samples : list of (int, str)
        Instruction pointer and the shared object ``perf`` named for it.
    table : list of (int, str)
        Start address and (mangled) name of every function of the compiled library.

    Returns
    -------
    dict
        Samples per function name (Python name for numba functions) or per shared
        object (``"so:<name>"``), most first.
    """
    starts = sorted(table)
    addresses = [a for a, _ in starts]
    counts: dict[str, int] = {}
    for ip, dso in samples:
        k = bisect.bisect_right(addresses, ip) - 1
        # the library's functions lie within a few MB of each other; beyond that an
        # address belongs to other compiled code (a cfunc wrapper, NRT)
        jit = "JIT" in dso or "perf-" in dso or "unknown" in dso
        if jit and k >= 0 and ip - addresses[k] < 0x40000:
            key = _python_name(starts[k][1])
        else:
            key = "so:" + Path(dso).name
        counts[key] = counts.get(key, 0) + 1
    return dict(sorted(counts.items(), key=lambda kv: -kv[1]))


def _parse_perf_script(text: str) -> list[tuple[int, str]]:
    out = []
    for line in text.splitlines():
        parts = line.split(None, 1)
        if len(parts) != 2:
            continue
        try:
            ip = int(parts[0], 16)
        except ValueError:
            continue
        out.append((ip, parts[1].strip().strip("()")))
    return out


def profile_case(case: str, seconds: float, frequency: int) -> dict[str, Any]:
    """Run one case in a worker under ``perf``; the shares of its samples."""
    with tempfile.TemporaryDirectory(prefix="vibrissa-perf-") as tmp:
        ready = os.path.join(tmp, "ready")
        table_file = os.path.join(tmp, "table.json")
        data = os.path.join(tmp, "perf.data")
        env = {**os.environ, "NUMBA_CACHE_DIR": os.path.join(tmp, "numba")}
        worker = subprocess.Popen(
            [sys.executable, "-c", WORKER, case, str(seconds), ready, table_file],
            env=env,
            stdout=subprocess.PIPE,
            text=True,
        )
        t0 = time.perf_counter()
        while not os.path.exists(ready):
            if worker.poll() is not None:
                raise RuntimeError(
                    f"the {case} worker exited ({worker.returncode}) before warming up"
                )
            time.sleep(0.2)
        compile_s = time.perf_counter() - t0
        rec = subprocess.run(
            ["perf", "record", "-q", "-F", str(frequency), "-p", str(worker.pid), "-o", data],
            capture_output=True,
            text=True,
        )
        out, _ = worker.communicate()
        if worker.returncode != 0 or rec.returncode != 0:
            raise RuntimeError(f"the {case} run failed: {rec.stderr.strip()[-300:]}")
        script = subprocess.run(
            ["perf", "script", "-i", data, "-F", "ip,dso"], capture_output=True, text=True
        )
        with open(table_file) as fh:
            table = [(int(a), str(n)) for a, n in json.load(fh)]
    samples = _parse_perf_script(script.stdout)
    counts = attribute(samples, table)
    total = sum(counts.values())
    run = json.loads(out.strip().splitlines()[-1])
    return {
        "samples": total,
        "repeats": run["repeats"],
        "wall_seconds": round(run["wall_seconds"], 2),
        "compile_and_warm_up_seconds": round(compile_s, 1),
        "share": {k: round(v / total, 4) for k, v in counts.items() if v / total >= 0.002},
    }


def main(argv: list[str] | None = None) -> int:
    """Parse the options, profile each case, write the JSON."""
    ap = argparse.ArgumentParser(
        description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--case", choices=[*CASES, "all"], default="all", help="what to profile")
    ap.add_argument("--seconds", type=float, default=20.0, help="sampled wall seconds per case")
    ap.add_argument("--frequency", type=int, default=2000, help="samples per second")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON file")
    args = ap.parse_args(argv)
    if not 1.0 <= args.seconds <= 600.0:
        ap.error(f"--seconds: expected a number in [1, 600], got {args.seconds}")
    if not 100 <= args.frequency <= 20000:
        ap.error(f"--frequency: expected an integer in [100, 20000], got {args.frequency}")
    if args.out.exists() and not args.out.is_file():
        ap.error(f"--out: {args.out} is not a file")
    if shutil.which("perf") is None:
        ap.error("perf is not installed (Debian: apt-get install linux-perf)")
    cases = CASES if args.case == "all" else (args.case,)
    print(
        f"profile_kernels: {len(cases)} case(s) x {args.seconds:g} s sampled "
        f"(plus a compile each) -> {args.out}",
        file=sys.stderr,
    )
    load = os.getloadavg()[0]
    results = {}
    for case in cases:
        results[case] = profile_case(case, args.seconds, args.frequency)
        shares = ", ".join(
            f"{k} {100 * v:.1f}%" for k, v in list(results[case]["share"].items())[:8]
        )
        print(f"  {case}: {shares}", file=sys.stderr)
    package = Path(vibrissa.__file__).resolve().parent
    head = subprocess.run(
        ["git", "-C", str(package), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    )
    doc = {
        "what": "Shares of perf samples per compiled function (numba) or shared object",
        "profiled_package": str(package),
        "commit": head.stdout.strip() if head.returncode == 0 else "not a git checkout",
        "frequency_hz": args.frequency,
        "load_average_at_start": round(load, 2),
        "machine": machine(),
        "cases": results,
        "meta": {
            "command": " ".join(["python benchmarks/profile_kernels.py", *sys.argv[1:]]),
            "vibrissa_version": __version__,
            "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        },
    }
    atomic_write_text(args.out, json.dumps(doc, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
