"""`vibrissa` commands of the data family: ``vibrissa import``."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.markup import escape

from vibrissa._atomic import check_writable
from vibrissa.cli._common import echo_json, regular_file, user_errors

_IMPORT_HELP = "\n\n".join(
    [
        "Import a recording (.mat v5/v7.3, .csv, .npz) into a vibrissa dataset (NetCDF).",
        "A mapping (--mapping FILE.json or .toml, and/or the options below, which override "
        "it) says where signals and labels are. For the thesis' data_XY.mat (a 4 x 26 x 101 "
        "cell array 'data' of 750 x 2 samples at 1 kHz):",
        "vibrissa import data_XY.mat --out xy.nc --signal data --axis set=1:4 "
        "--axis speed_mm_s=36:7.2:216 --axis radial_distance_mm=80:180 "
        "--channels x,y --sample-rate-hz 1000",
        'or the same as xy.json (--mapping xy.json): {"format": "mat", "signal": "data", '
        '"cell_axes": [{"name": "set", "values": [1, 2, 3, 4]}, {"name": "speed_mm_s", '
        '"start": 36, "stop": 216, "num": 26}, {"name": "radial_distance_mm", "start": 80, '
        '"stop": 180, "num": 101}], "channels": ["x", "y"], "time_axis": 0, '
        '"sample_rate_hz": 1000, "units": "V"}',
        "Mapping keys (unknown keys and wrong types are errors):\n"
        "format: mat | csv | npz (default: from the extension; --format overrides);\n"
        "signal: the variable (struct fields with dots);\n"
        "cell_axes: one per cell dimension (or leading array dimension), MATLAB order, each "
        "with values, start/stop/num, start/step/stop or from (a variable);\n"
        "time_axis: 0 = samples x channels (default), 1 = channels x samples;\n"
        "trial_axes: first (default) | last, for numeric arrays (samples x channels x trials);\n"
        "channels; sample_rate_hz (number or variable); t0_s; units; attrs;\n"
        "labels: label -> variable or CSV column; constants: label -> value;\n"
        "ragged: error | crop (to the shortest); empty: error | skip;\n"
        "CSV only: layout (long = one row per sample with trial, time, channel and label "
        "columns; wide = one row per trial with columns CHANNEL_0, CHANNEL_1, ...), "
        "trial_column, time_column.",
        "Trials are in C order over cell_axes (last axis fastest). Full reference: "
        "python -m pydoc vibrissa.data.importers. The source is only read; the output is "
        "written atomically (an existing OUT is left as it was when the import fails). "
        "Bad input: one line on stderr, exit status 2.",
        "A small SIMULATED recording in the data_XY layout (4 x 3 x 5 cells) ships with "
        "vibrissa, with its mapping: vibrissa.examples.example_path('data_XY_small.mat') "
        "and example_path('data_XY_small.mapping.json').",
    ]
)


_FORMATS = ("auto", "mat", "csv", "npz")
#: Mapping keys and the options that set them.
_MAPPING_OPTIONS = {
    "signal": "--signal",
    "cell_axes": "--axis",
    "channels": "--channels",
    "sample_rate_hz": "--sample-rate-hz",
    "time_axis": "--time-axis",
    "labels": "--label",
    "constants": "--const",
    "ragged": "--crop",
    "empty": "--skip-empty",
    "trial_axes": "--trials-last",
    "t0_s": "--t0-s",
}


def _name_options(message: str, given: dict[str, str], mapping: Path | None) -> str:
    """A mapping error naming the option that set the key (else the mapping file).

    ``given`` maps the keys the options set (all of them without a mapping file) to
    their options.
    """

    def name(match: re.Match[str]) -> str:
        key = match.group(1) or match.group(2)
        if key in given:
            return given[key]
        return f"{mapping}: {key!r}" if mapping is not None else match.group(0)

    return re.sub(r"the mapping's (\w+)|mapping '(\w+)'", name, message)


def _pairs(items: list[str] | None, option: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ValueError(f"{option} {item!r}: expected NAME=VALUE")
        out[name.strip()] = value.strip()
    return out


def _constant(value: str) -> Any:
    try:
        v = float(value)
    except ValueError:
        return value
    return int(v) if v.is_integer() and "." not in value and "e" not in value.lower() else v


def _summary(ds: Any, out: Path) -> dict[str, Any]:
    from vibrissa.data import label_names

    labels: dict[str, Any] = {}
    for name in label_names(ds):
        vals = np.asarray(ds[name].values)
        uniq = np.unique(vals)
        entry: dict[str, Any] = {"n_values": int(uniq.size)}
        if uniq.size <= 6:
            entry["values"] = uniq.tolist()
        elif vals.dtype.kind in "iuf":
            entry["min"], entry["max"] = float(uniq[0]), float(uniq[-1])
        labels[name] = entry
    fs = float(ds.attrs["sample_rate_hz"])
    return {
        "out": str(out),
        "n_trials": int(ds.sizes["trial"]),
        "channels": [str(c) for c in ds["channel"].values],
        "n_timepoints": int(ds.sizes["time"]),
        "sample_rate_hz": fs,
        "duration_s": float(ds.sizes["time"] / fs),
        "labels": labels,
        "source_file": ds.attrs.get("source_file"),
        "source_format": ds.attrs.get("source_format"),
        "cropped_from_samples": ds.attrs.get("cropped_from_samples"),
    }


def _describe(label: dict[str, Any]) -> str:
    if "values" in label:
        return ", ".join(str(v) for v in label["values"])
    if "min" in label:
        return f"{label['n_values']} values, {label['min']:g} .. {label['max']:g}"
    return f"{label['n_values']} values"


def register(app: typer.Typer) -> None:
    """Register this family's commands on the top-level app."""

    @app.command("import", help=escape(_IMPORT_HELP))
    @user_errors
    def import_cmd(
        source: Path = typer.Argument(..., help="Recording to import (.mat, .csv, .npz)."),
        out: Path = typer.Option(..., "--out", "-o", help="Output dataset (NetCDF, .nc)."),
        mapping: Path | None = typer.Option(
            None, "--mapping", "-m", help="Mapping file (JSON, or TOML if it ends in .toml)."
        ),
        fmt: str = typer.Option("auto", "--format", help="auto (from extension), mat, csv, npz."),
        signal: str | None = typer.Option(None, "--signal", help="Variable holding signals."),
        axis: list[str] | None = typer.Option(
            None,
            "--axis",
            help="A cell/trial axis, repeated in order: NAME=1,2,3 | NAME=start:stop | "
            "NAME=start:step:stop (MATLAB) | NAME=@VARIABLE | trial. Replaces cell_axes.",
        ),
        channels: str | None = typer.Option(None, "--channels", help="Channel names, e.g. x,y."),
        sample_rate_hz: float | None = typer.Option(
            None, "--sample-rate-hz", help="Sampling rate (Hz)."
        ),
        time_axis: int | None = typer.Option(
            None, "--time-axis", help="Time axis of one recording: 0 (samples x channels) or 1."
        ),
        label: list[str] | None = typer.Option(
            None, "--label", help="LABEL=VARIABLE (or CSV column), repeatable."
        ),
        const: list[str] | None = typer.Option(
            None, "--const", help="LABEL=VALUE for every trial (e.g. texture=P80), repeatable."
        ),
        crop: bool = typer.Option(
            False, "--crop", help="Crop recordings of unequal length to the shortest."
        ),
        skip_empty: bool = typer.Option(False, "--skip-empty", help="Leave out empty cells."),
        trials_last: bool = typer.Option(
            False,
            "--trials-last",
            help="Numeric arrays: trial axes come last (e.g. samples x channels x trials).",
        ),
        t0_s: float | None = typer.Option(
            None, "--t0-s", help="Time of the first sample relative to alignment (s)."
        ),
        as_json: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
    ) -> None:
        from vibrissa.data.importers import import_file, load_mapping, parse_axis_option

        if fmt not in _FORMATS:
            raise ValueError(f"--format must be one of {', '.join(_FORMATS)}, got {fmt!r}")
        try:
            check_writable(out)
        except ValueError as exc:
            raise ValueError(f"--out: {exc}") from None
        regular_file("SOURCE", source)
        if mapping is not None:
            regular_file("--mapping", mapping)
        raw = dict(load_mapping(mapping).raw) if mapping is not None else {}
        if signal is not None:
            raw["signal"] = signal
        if axis:
            raw["cell_axes"] = [parse_axis_option(a) for a in axis]
        if channels is not None:
            raw["channels"] = [c.strip() for c in channels.split(",")]
        if sample_rate_hz is not None:
            raw["sample_rate_hz"] = sample_rate_hz
        if time_axis is not None:
            raw["time_axis"] = time_axis
        if label:
            raw["labels"] = {**dict(raw.get("labels") or {}), **_pairs(label, "--label")}
        if const:
            consts = {k: _constant(v) for k, v in _pairs(const, "--const").items()}
            raw["constants"] = {**dict(raw.get("constants") or {}), **consts}
        if crop:
            raw["ragged"] = "crop"
        if skip_empty:
            raw["empty"] = "skip"
        if trials_last:
            raw["trial_axes"] = "last"
        if t0_s is not None:
            raw["t0_s"] = t0_s
        options = {
            "signal": signal,
            "cell_axes": axis,
            "channels": channels,
            "sample_rate_hz": sample_rate_hz,
            "time_axis": time_axis,
            "labels": label,
            "constants": const,
            "ragged": crop or None,
            "empty": skip_empty or None,
            "trial_axes": trials_last or None,
            "t0_s": t0_s,
        }
        given = {
            key: _MAPPING_OPTIONS[key]
            for key, v in options.items()
            if v is not None or mapping is None
        }
        try:
            ds = import_file(source, load_mapping(raw), out, format=fmt)
        except ValueError as exc:
            raise ValueError(_name_options(str(exc), given, mapping)) from exc
        summary = _summary(ds, out)
        if as_json:
            echo_json(summary)
            return
        typer.echo(
            f"{out}: {summary['n_trials']} trials x {len(summary['channels'])} channels "
            f"({', '.join(summary['channels'])}) x {summary['n_timepoints']} samples at "
            f"{summary['sample_rate_hz']:g} Hz ({summary['duration_s']:g} s)"
        )
        for name, entry in summary["labels"].items():
            typer.echo(f"  {name}: {_describe(entry)}")
        if summary["cropped_from_samples"] is not None:
            typer.echo(f"  cropped from up to {summary['cropped_from_samples']} samples")
