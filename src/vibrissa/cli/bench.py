"""`vibrissa bench ...`: performance benchmarks.

``vibrissa bench physics`` times the standard pole-contact trial with
:func:`vibrissa.whisker.benchmark.physics_benchmark` and reports its real-time
factor: simulated seconds per wall-clock second on one core, the process pinned to one
CPU (:func:`one_core`) as ``benchmarks/bench_peers.py`` is.
``benchmarks/bench_physics.py`` runs the same over time steps and element counts.
"""

from __future__ import annotations

import contextlib
import os
import re
from collections.abc import Iterator
from typing import Annotated

import typer

from vibrissa.cli._common import echo_json, physics_errors, user_errors
from vibrissa.whisker.benchmark import STANDARD, physics_benchmark
from vibrissa.whisker.hall import steps_per_sample

bench_app = typer.Typer(help="Performance benchmarks.", no_args_is_help=True)

#: Smallest internal step ``bench physics`` accepts (ms): a step near 0 is unbounded work.
MIN_DT_MS = 0.001
#: Parameters of :func:`physics_benchmark` whose errors name them, with their options.
_OPTIONS = {"duration_s": "--duration-s", "repeats": "--repeats", "n_elements": "--n-elements"}


@contextlib.contextmanager
def one_core() -> Iterator[int | None]:
    """Run the block on one CPU (Linux) with BLAS on one thread; restore after.

    Pinned, the real-time factor varies 3.5 % between processes instead of 12 %
    (issue 14's measurement), as in ``benchmarks/bench_peers.py``. The rod's numba
    kernels are serial. Yields the CPU, or None where the platform cannot pin.
    """
    from threadpoolctl import threadpool_limits

    affinity = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    cpu = min(affinity) if affinity else None
    try:
        if cpu is not None:
            os.sched_setaffinity(0, {cpu})
        with threadpool_limits(limits=1):
            yield cpu
    finally:
        if affinity:
            os.sched_setaffinity(0, affinity)


@bench_app.command("physics")
@user_errors
@physics_errors
def physics_cmd(
    json_out: Annotated[bool, typer.Option("--json", help="Print JSON instead of text.")] = False,
    dt_ms: Annotated[
        float,
        typer.Option("--dt-ms", help="Internal time step (ms); must divide 0.25 ms evenly."),
    ] = STANDARD["dt_s"] * 1e3,
    n_elements: Annotated[
        int | None,
        typer.Option("--n-elements", help="Elements along the shaft (default: model default)."),
    ] = None,
    repeats: Annotated[
        int, typer.Option("--repeats", help="Timed trials; the fastest counts.")
    ] = 5,
    duration_s: Annotated[
        float,
        typer.Option("--duration-s", hidden=True, help="Simulated time (s); 1.5 is standard."),
    ] = STANDARD["duration_s"],
) -> None:
    """Real-time factor of the standard 1.5 s pole contact on one core.

    Scenario: xy-robot whisker, thin pole at r = 140 mm starting 1 mm from the
    shaft, advancing at 100 mm/s for 0.3 s, retracting at 720 mm/s by 36 mm;
    dt = 0.25 ms, Hall output at 4 kHz. The numba kernels are warmed up by a short
    run first (the very first compilation on a machine takes ~30 s); the best of
    --repeats timed runs counts. Reports the real-time factor (simulated seconds per
    wall-clock second), wall and CPU seconds, steps, and the peak memory of one
    trial (MB, tracemalloc).
    """
    dt_s = dt_ms * 1e-3
    if not dt_ms >= MIN_DT_MS:
        raise ValueError(
            f"--dt-ms must be at least {MIN_DT_MS:g} (1 us: 1.5 million steps a trial), "
            f"got {dt_ms:g}"
        )
    try:
        steps_per_sample(dt_s, STANDARD["sample_rate_hz"])
    except ValueError:
        raise ValueError(
            f"--dt-ms must divide the 0.25 ms output period (4 kHz) evenly, got {dt_ms:g}"
        ) from None
    try:
        with one_core() as cpu:
            out = physics_benchmark(dt_s, n_elements, duration_s, repeats)
        out["pinned_cpu"] = cpu
    except ValueError as exc:
        pattern = r"\b(" + "|".join(_OPTIONS) + r")\b"
        raise ValueError(re.sub(pattern, lambda m: _OPTIONS[m.group(1)], str(exc))) from None
    if json_out:
        echo_json(out)
        return
    from rich.console import Console

    con = Console(highlight=False, soft_wrap=True)
    con.print(f"[bold]physics benchmark[/bold]: {out['scenario']}")
    con.print(
        f"  {out['n_elements']} elements, dt = {out['dt_s'] * 1e3:g} ms, "
        f"{out['n_steps']} steps, {out['n_samples']} samples; "
        + (
            f"pinned to CPU {out['pinned_cpu']}, BLAS on one thread"
            if out["pinned_cpu"] is not None
            else "not pinned (this platform cannot), BLAS on one thread"
        )
    )
    con.print(
        f"  real-time factor [bold]{out['real_time_factor']:.1f}[/bold] "
        f"({out['duration_s']:g} s simulated in {out['wall_seconds']:.3f} s wall, "
        f"{out['cpu_seconds']:.3f} s CPU; best of {out['repeats']}); "
        f"{out['linear_free_flight_fraction']:.0%} of the steps in linear free flight"
    )
    con.print(
        f"  free flight {out['free_flight_real_time_factor']:.1f} x real time "
        f"({out['free_flight_scenario']}); whisking in air "
        f"{out['whisking_in_air_real_time_factor']:.1f} x ({out['whisking_in_air_scenario']}); "
        f"contact {out['contact_real_time_factor']:.1f} x ({out['contact_scenario']})"
    )
    if out["peak_memory_mb"] is not None:
        con.print(
            f"  peak memory of one trial {out['peak_memory_mb']:.2f} MB (tracemalloc); "
            f"process max RSS {out['process_max_rss_mb']:.0f} MB"
        )
    con.print(
        f"  peak follicle moment {out['peak_follicle_moment_nm'] * 1e3:.4f} mN m, "
        f"peak Hall x {out['peak_hall_x_v']:.3f} V"
    )


def register(app: typer.Typer) -> None:
    """Register the ``bench`` command group on the top-level ``app``."""
    app.add_typer(bench_app, name="bench")
