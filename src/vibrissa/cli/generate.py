"""`vibrissa generate PROTOCOL --out FILE`: simulate a thesis experiment's dataset."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path
from typing import Any

import typer

from vibrissa.cli._common import (
    count_option,
    echo_json,
    free_space,
    generation_disk_bytes,
    option_renamer,
    seed_option,
    user_errors,
)
from vibrissa.cli._interrupt import interruptible

_GRID_HELP = "start:stop:step (inclusive), start:stop:#count, or a comma list"


#: The protocol's parameters (in the library's messages) and the options that set them.
_RENAME = option_renamer(
    {
        "sample_rate_hz": "--sample-rate-hz",
        "noise_v": "--noise-v",
        "drift_fraction": "--drift",
        "workers": "--workers",
        "chunk_size": "--chunk-size",
        "scheduler": "--scheduler",
    }
)
#: Words of a message that does not name an option, and the option it is about.
_ABOUT = (
    ("unknown protocol", "PROTOCOL"),
    ("radial_distance_mm", "--radial-distances"),
    ("speed_mm_s", "--speeds"),
    ("angle_deg", "--angles"),
    ("texture", "--textures"),
    ("whisker", "--whisker"),
    ("sample period", "--sample-rate-hz"),
)


def _name_options(message: str) -> str:
    """A library message about the protocol, naming the option it is about."""
    message = _RENAME(message)
    if "--" in message:
        return message
    about = next((opt for word, opt in _ABOUT if word in message), None)
    return f"{about}: {message}" if about else message


def work_statement(
    protocol: Any, workers: int | None = None, scheduler: str | None = None, chunk_size: int = 32
) -> str:
    """The work of generating ``protocol`` here: ``"about 3 min on 2 cores, about 14 MB"``.

    The time is measured on a few of the protocol's own trials
    (:mod:`vibrissa.experiments.estimate`, well under a second); on a Dask cluster,
    whose cores are not known here, it is the time of one local core. The size is
    the dataset's signal.
    """
    from vibrissa.experiments.estimate import (
        format_duration,
        generation_seconds,
        seconds_per_trial,
    )
    from vibrissa.experiments.generate import dataset_bytes

    per_trial = seconds_per_trial(protocol)
    if scheduler:
        time_text = (
            f"{format_duration(protocol.n_trials * per_trial)} of one core's time "
            "on the Dask cluster"
        )
    else:
        cores = workers if workers is not None else (os.cpu_count() or 1)
        seconds = generation_seconds(protocol.n_trials, per_trial, cores, chunk_size)
        time_text = f"{format_duration(seconds)} on {cores} core{'s' * (cores > 1)}"
    mb = dataset_bytes(protocol) / 1e6
    size = f"{mb:.1f}" if mb < 10 else f"{mb:.0f}"
    return f"about {time_text}, about {size} MB"


class _ProgressBar:
    """A progress bar on standard error, shown only on a terminal.

    It is shown only once the work has started (the first report), so that a refused run
    prints no bar.
    """

    def __init__(self, description: str, enabled: bool = True) -> None:
        self.description = description
        self.enabled = enabled and sys.stderr.isatty() and os.environ.get("CI") is None
        self._progress: Any = None
        self._task: Any = None

    def __enter__(self) -> _ProgressBar:
        return self

    def update(self, done: int, total: int) -> None:
        """Show ``done`` of ``total`` trials (starting the bar on the first call)."""
        if not self.enabled:
            return
        if self._progress is None:
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

            self._progress = Progress(
                TextColumn("[bold]{task.description}"),
                BarColumn(),
                TextColumn("{task.completed}/{task.total} trials"),
                TimeRemainingColumn(),
                console=Console(stderr=True),
            )
            self._progress.start()
            self._task = self._progress.add_task(self.description, total=total)
        self._progress.update(self._task, completed=done, total=total)

    def __exit__(self, *exc: object) -> None:
        if self._progress is not None:
            self._progress.stop()


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
        from vibrissa.experiments.generate import (
            check_generation,
            generate,
            kept_trials,
            parts_dir,
        )
        from vibrissa.experiments.protocols import get_protocol, parse_grid

        seed_option("--seed", seed)
        count_option("--workers", workers)
        count_option("--runs", runs)
        count_option("--chunk-size", chunk_size)
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
        try:
            overrides = dict(
                radial_distances_mm=None
                if radial_distances is None
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
        except ValueError as exc:
            raise ValueError(_name_options(str(exc))) from exc
        try:
            check_generation(proto, out, workers, scheduler, chunk_size)
        except ValueError as exc:  # the messages name the output path or the parameter
            raise ValueError(_RENAME(str(exc))) from exc
        free_space("-o", out, generation_disk_bytes(proto, out), "the dataset and its shards")
        kept: list[int | None] = [None]  # trials kept in the shards, once known

        def interrupted() -> str:
            parts = parts_dir(out)
            if kept[0] is None:
                if not parts.exists():
                    return "before any trial was simulated; nothing was written"
                return (
                    f"before the generation started; {parts}/ is kept as it was; rerun "
                    "the same command to resume"
                )
            return (
                f"{kept_trials(out)} of {proto.n_trials} trials kept in {parts}/; rerun "
                "the same command to resume"
            )

        with interruptible(interrupted):
            # every option is checked: state the work, then start it
            typer.echo(
                f"{proto.name}: {proto.n_trials} trials, "
                f"{work_statement(proto, workers, scheduler, chunk_size)} -> {out}",
                err=True,
            )
            t0 = time.perf_counter()
            with _ProgressBar(f"generate {proto.name}", enabled=not json_out) as bar:

                def report(done: int, total: int) -> None:
                    kept[0] = done
                    bar.update(done, total)

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
