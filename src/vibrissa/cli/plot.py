"""`vibrissa plot`: dataset figures (typical traces, feature contours) as PNG files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from vibrissa._atomic import check_writable
from vibrissa.cli._common import echo_json, regular_file, user_errors

KINDS = ("traces", "contours", "all")


def _load(path: Path) -> Any:
    """Load a dataset with :func:`vibrissa.data.load_dataset` (checksum verified).

    Falls back to :func:`xarray.load_dataset` while :mod:`vibrissa.data` has no
    loader (interim; to be removed once ``vibrissa.data`` ships it).
    """
    regular_file("DATASET", path)
    try:
        from vibrissa.data import load_dataset
    except ImportError:
        import xarray as xr

        try:
            return xr.load_dataset(path)
        except (ValueError, OSError) as exc:
            raise ValueError(f"cannot read {path} as a NetCDF dataset: {exc}") from exc
    return load_dataset(path)


def _check_channel(ds: Any, value: str) -> int | str:
    """``--channel`` as an index or a name of one of the dataset's channels."""
    channel: int | str = int(value) if value.strip().lstrip("-").isdigit() else value
    names = [str(c) for c in ds["channel"].values] if "channel" in ds.coords else []
    if (channel not in names) if isinstance(channel, str) else not 0 <= channel < len(names):
        raise ValueError(
            f"--channel must be an index in [0, {len(names) - 1}] or a name "
            f"({', '.join(names)}) of the dataset's channels, got {value!r}"
        )
    return channel


def check_contour_grid(ds: Any) -> None:
    """Refuse, in one line, labels a contour map cannot be drawn over.

    A NaN radial distance or speed, or fewer than two different values of either, gave a
    blank map.
    """
    import numpy as np

    for name in ("radial_distance_mm", "speed_mm_s"):
        if name not in ds.coords and name not in ds.data_vars:
            continue
        values = np.asarray(ds[name].values, dtype=float)
        if not np.isfinite(values).all():
            raise ValueError(f"dataset: {name} holds NaN or infinite labels; contours need numbers")
        if np.unique(values).size < 2:
            raise ValueError(
                f"dataset: contours need at least two different {name} values, got "
                f"{np.unique(values).size}"
            )


def plot_dataset(
    ds: Any, out: Path, kind: str = "all", channel: int | str = 0, dpi: int = 110
) -> list[Path]:
    """Write the dataset figures of ``kind`` into ``out`` and return their paths.

    Parameters
    ----------
    ds : xarray.Dataset
        Dataset of the package schema.
    out : pathlib.Path
        Output directory (created if needed).
    kind : {"traces", "contours", "all"}
        ``traces``: typical deflections (figure 3.7 for radial distance x speed
        data, ``traces.png``; figure 5.2 for angle x texture data,
        ``traces_angle_texture.png``). ``contours``: peak deflection and
        duration over speed x radial distance (figure 4.1, ``contours.png``).
        ``all``: whatever applies to the dataset.
    channel : int or str, default=0
        Channel index or name.
    dpi : int, default=110

    Returns
    -------
    list of pathlib.Path
    """
    from vibrissa.evaluate import figures as vfig

    if kind not in KINDS:
        raise ValueError(f"--kind must be one of {', '.join(KINDS)}, got {kind!r}")
    names = set(ds.coords) | set(ds.data_vars)
    radial = {"radial_distance_mm", "speed_mm_s"} <= names
    angular = {"angle_deg", "texture", "speed_mm_s"} <= names
    written: list[Path] = []
    if kind in ("traces", "all"):
        if not (radial or angular):
            raise ValueError(
                "dataset has neither radial_distance_mm/speed_mm_s nor angle_deg/texture/"
                "speed_mm_s coordinates to choose typical traces by"
            )
        if radial:
            fig = vfig.typical_traces_figure(ds, channel=channel)
            written.append(vfig.save_figure(fig, out / "traces.png", dpi))
        if angular:
            axs = vfig.angle_texture_traces(ds, channel=channel)
            written.append(
                vfig.save_figure(axs.flat[0].figure, out / "traces_angle_texture.png", dpi)
            )
    if kind == "contours" or (kind == "all" and radial):
        if not radial:
            raise ValueError(
                "contours need the coordinates radial_distance_mm and speed_mm_s (chapter-4 grid)"
            )
        check_contour_grid(ds)
        axes = vfig.feature_contours(ds, channel=channel)
        written.append(vfig.save_figure(axes[0].figure, out / "contours.png", dpi))
    return written


def register(app: typer.Typer) -> None:
    """Register this family's commands on the top-level ``app``."""

    @app.command("plot")
    @user_errors
    def plot(
        dataset: Path = typer.Argument(..., help="Dataset file (.nc)."),
        out: Path = typer.Option(..., "--out", "-o", help="Directory for the PNG files."),
        kind: str = typer.Option(
            "all", "--kind", help="traces (figures 3.7/5.2), contours (figure 4.1) or all."
        ),
        channel: str = typer.Option("0", "--channel", help="Channel index or name (e.g. x)."),
        dpi: int = typer.Option(110, "--dpi", min=20, max=600, help="Resolution of the PNGs."),
    ) -> None:
        """Draw dataset figures: typical deflection traces and feature contour maps.

        Prints the written paths as JSON.
        """
        if kind not in KINDS:
            raise ValueError(f"--kind must be one of {', '.join(KINDS)}, got {kind!r}")
        try:
            check_writable(out, directory=True)
        except ValueError as exc:
            raise ValueError(f"--out: {exc}") from None
        ds = _load(dataset)
        if kind in ("contours", "all") and {"radial_distance_mm", "speed_mm_s"} <= (
            set(ds.coords) | set(ds.data_vars)
        ):
            check_contour_grid(ds)
        paths = plot_dataset(ds, out, kind=kind, channel=_check_channel(ds, channel), dpi=dpi)
        echo_json({"written": [str(p) for p in paths]})
