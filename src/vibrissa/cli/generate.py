"""`vibrissa generate PROTOCOL --out FILE`: simulate a thesis experiment's dataset."""

from __future__ import annotations

import os
import time
from pathlib import Path

import typer

from vibrissa.cli._common import echo_json, user_errors

_GRID_HELP = "start:stop:step (inclusive), start:stop:#count, or a comma list"


def register(app: typer.Typer) -> None:
    """Register ``vibrissa generate`` on the top-level ``app``."""

    @app.command("generate")
    @user_errors
    def generate_cmd(
        protocol: str = typer.Argument(
            ..., help="Protocol: radial-distance (chapter 4) or angle-texture (chapter 5)."
        ),
        out: Path = typer.Option(..., "--out", "-o", help="Output NetCDF file."),
        quick: bool = typer.Option(
            False, "--quick", help="A small grid that runs in under a minute."
        ),
        radial_distances: str = typer.Option(
            None, "--radial-distances", help=f"Radial distances in mm ({_GRID_HELP})."
        ),
        speeds: str = typer.Option(
            None, "--speeds", help=f"Contact speeds in mm/s ({_GRID_HELP})."
        ),
        angles: str = typer.Option(None, "--angles", help=f"Surface angles in deg ({_GRID_HELP})."),
        textures: str = typer.Option(
            None, "--textures", help="Comma list of textures (aluminium, p600, p180, p80)."
        ),
        runs: int = typer.Option(None, "--runs", help="Repetitions of the grid (thesis: 2)."),
        sample_rate_hz: float = typer.Option(None, "--sample-rate-hz", help="Recording rate (Hz)."),
        whisker: str = typer.Option(None, "--whisker", help="Whisker preset (default xy-robot)."),
        noise_v: float = typer.Option(None, "--noise-v", help="Sensor noise, V rms."),
        drift: float = typer.Option(
            None,
            "--drift",
            help="Relative drift of whisker stiffness over the session, e.g. -0.05.",
        ),
        seed: int = typer.Option(0, "--seed", help="Seed: same seed, same bytes."),
        workers: int = typer.Option(
            None, "--workers", help="Local processes (default: all cores)."
        ),
        scheduler: str = typer.Option(
            None, "--scheduler", help="Run on an existing Dask cluster at this address."
        ),
        chunk_size: int = typer.Option(32, "--chunk-size", help="Trials per unit of work."),
        restart: bool = typer.Option(
            False, "--restart", help="Discard an interrupted run's shards."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print a JSON summary."),
    ) -> None:
        """Simulate a protocol on the virtual XY robot and save it as a NetCDF dataset.

        Runs in parallel and resumes after an interruption (rerun the same command).
        """
        from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

        from vibrissa.experiments.generate import check_size, dataset_bytes, generate
        from vibrissa.experiments.protocols import get_protocol, parse_grid

        not_for = {
            "radial-distance": {"--angles": angles, "--textures": textures},
            "angle-texture": {"--radial-distances": radial_distances},
        }
        unused = [flag for flag, v in not_for.get(protocol, {}).items() if v is not None]
        if unused:
            raise ValueError(f"{', '.join(unused)} does not apply to the {protocol} protocol")
        texture_list = None
        if textures is not None:
            texture_list = tuple(t.strip().lower() for t in textures.split(",") if t.strip())
            if not texture_list:
                raise ValueError("--textures: empty list; name at least one texture")
        overrides = dict(
            radial_distances_mm=None if radial_distances is None
            else parse_grid(radial_distances, "--radial-distances"),
            speeds_mm_s=None if speeds is None else parse_grid(speeds, "--speeds"),
            angles_deg=None if angles is None else parse_grid(angles, "--angles"),
            textures=texture_list,
            runs=runs,
            whisker=whisker,
            drift_fraction=drift,
            seed=seed,
        )
        sensor = {"sample_rate_hz": sample_rate_hz, "noise_v": noise_v}
        proto = get_protocol(protocol, quick=quick, **overrides)
        if any(v is not None for v in sensor.values()):
            proto = proto.with_sensor(**{k: v for k, v in sensor.items() if v is not None})
        check_size(proto)
        typer.echo(f"{proto.name}: {proto.n_trials} trials, about "
                   f"{dataset_bytes(proto) / 1e6:.0f} MB -> {out}", err=True)
        t0 = time.perf_counter()
        show = not json_out and os.environ.get("CI") is None
        with Progress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total} trials"),
            TimeRemainingColumn(),
            disable=not show,
            transient=False,
        ) as bar:
            task = bar.add_task(f"generate {proto.name}", total=proto.n_trials)

            def report(done: int, total: int) -> None:
                bar.update(task, completed=done, total=total)

            ds = generate(
                proto,
                out,
                workers=workers,
                scheduler=scheduler,
                chunk_size=chunk_size,
                restart=restart,
                progress=report,
            )
        elapsed = time.perf_counter() - t0
        assert ds is not None
        summary = {
            "protocol": proto.name,
            "out": str(out),
            "n_trials": int(ds.sizes["trial"]),
            "n_samples": int(ds.sizes["time"]),
            "sample_rate_hz": proto.sensor.sample_rate_hz,
            "seed": proto.seed,
            "saturated_fraction": float(ds["saturated"].mean()),
            "wall_seconds": round(elapsed, 3),
        }
        if json_out:
            echo_json(summary)
        else:
            typer.echo(
                f"wrote {summary['n_trials']} trials x {summary['n_samples']} samples to {out} "
                f"in {elapsed:.1f} s ({100 * summary['saturated_fraction']:.1f} % saturated)"
            )
