"""`vibrissa fit-pipeline`: datasets in, one pipeline file out that `vibrissa live` runs."""

from __future__ import annotations

import json

import numpy as np
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.data.dataset import make_dataset
from vibrissa.data.netcdf import save_dataset
from vibrissa.framework import TactilePipeline

runner = CliRunner()
FS = 1000.0


def datasets(n_per_class: int, seed: int = 0):
    """Single-contact trials: a bump at 0.2 s whose height is the class, rest around it."""
    rng = np.random.default_rng(seed)
    classes = [(r, a, t) for r in (30.0, 60.0) for a in (0.0, 30.0) for t in ("p80", "p600")]
    sig = []
    for r, a, t in classes * n_per_class:
        x = 2.5 + 0.002 * rng.standard_normal((2, int(FS)))
        n = 150 if t == "p80" else 100
        bumpy = np.sin(np.pi * np.arange(n) / n) * (1.2 - r / 100.0)
        x[0, 200 : 200 + n] += bumpy
        x[1, 200 : 200 + n] += bumpy * (0.2 + a / 60.0)
        sig.append(x)
    rows = classes * n_per_class
    where = make_dataset(
        np.stack(sig),
        sample_rate_hz=FS,
        labels={"radial_distance_mm": [c[0] for c in rows], "speed_mm_s": [50.0] * len(rows)},
        attrs={"whisker": json.dumps({"length_mm": 65.0})},
    )
    what = make_dataset(
        np.stack(sig),
        sample_rate_hz=FS,
        labels={
            "angle_deg": [c[1] for c in rows],
            "speed_mm_s": [50.0] * len(rows),
            "texture": [c[2] for c in rows],
        },
    )
    return where, what, rows


def test_fit_save_and_load(tmp_path):
    where, what, _ = datasets(2)
    save_dataset(where, tmp_path / "where.nc")
    save_dataset(what, tmp_path / "what.nc")
    out = tmp_path / "p" / "pipe.vtp"
    res = runner.invoke(
        app,
        [
            "fit-pipeline",
            "--where",
            str(tmp_path / "where.nc"),
            "--what",
            str(tmp_path / "what.nc"),
            "--out",
            str(out),
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    pipe = TactilePipeline.load(out)
    assert pipe.where is not None and pipe.what is not None and pipe.n_whiskers == 1


def test_bad_options_exit_2_in_one_line_and_create_nothing(tmp_path):
    where, _, _ = datasets(1)
    save_dataset(where, tmp_path / "where.nc")
    out = tmp_path / "new" / "pipe.vtp"
    for args, message in (
        ([], "at least one"),
        (["--where", str(tmp_path / "missing.nc")], "does not exist"),
        (["--where", str(tmp_path)], "not a regular file"),
        (["--what", str(tmp_path / "where.nc")], "no angle_deg"),
        (["--where", str(tmp_path / "where.nc"), "--decision-threshold", "2"], "threshold"),
    ):
        res = runner.invoke(app, ["fit-pipeline", "--out", str(out), *args])
        assert res.exit_code == 2, (args, res.output)
        lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
        assert len(lines) == 1 and message in lines[0], (args, res.stderr)
        assert not out.parent.exists()
