"""How much texture information reaches the whisker base? Measured on a chapter-5 dataset.

For each texture: the median peak deflection, contact duration and the power of
``x`` above 35 Hz (the thesis' high-pass, 5.3.1) while the surface touches the
whisker (``contact_onset_s`` .. ``contact_end_s``) and in the 0.2 s after it leaves.
For each measure, the one-way ANOVA F statistic of texture within every
speed x angle cell (median over cells): how far apart the textures are compared
with the spread of repeated contacts. Run:

    .venv/bin/python scripts/texture_information.py vibrissa-out/angle-texture/data/*.nc \
        [--json docs/runs/texture_information.json]

``--json OUT`` (one dataset only) also writes the table as a run file for
``scripts/render_docs.py``: ``measures.<key>.median.<texture>`` and
``measures.<key>.median_f``.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

import numpy as np
import scipy.signal
import scipy.stats

from vibrissa.data import load_dataset

sys.path.insert(0, str(Path(__file__).resolve().parent))
from render_docs import run_meta, write_run

KEYS = {
    "peak deflection (V)": "peak_deflection_v",
    "contact duration (s)": "contact_duration_s",
    "power >35 Hz in contact (mV^2)": "power_above_35_hz_in_contact_mv2",
    "power >35 Hz after release (mV^2)": "power_above_35_hz_after_release_mv2",
}


def band_power(x: np.ndarray, fs: float, lo_hz: float = 35.0) -> np.ndarray:
    sos = scipy.signal.butter(4, lo_hz, "highpass", fs=fs, output="sos")
    return scipy.signal.sosfiltfilt(sos, x, axis=-1)


def measure(path: str) -> dict[str, Any]:
    """Print the table of one dataset; return it as ``{"n_trials", "measures"}``."""
    ds = load_dataset(path)
    fs = float(ds.attrs["sample_rate_hz"])
    t = ds["time"].values
    x = ds["signal"].sel(channel="x").values
    hp = band_power(x, fs)
    on, off = ds["contact_onset_s"].values, ds["contact_end_s"].values
    during = np.array(
        [
            np.mean(h[(t >= a) & (t <= b)] ** 2) if np.isfinite(a) else np.nan
            for h, a, b in zip(hp, on, off, strict=True)
        ]
    )
    after = np.array(
        [
            np.mean(h[(t > b) & (t <= b + 0.2)] ** 2) if np.isfinite(b) else np.nan
            for h, b in zip(hp, off, strict=True)
        ]
    )
    measures = {
        "peak deflection (V)": ds["peak_deflection_v"].values,
        "contact duration (s)": off - on,
        "power >35 Hz in contact (mV^2)": during * 1e6,
        "power >35 Hz after release (mV^2)": after * 1e6,
    }
    tex = ds["texture"].values
    names = list(dict.fromkeys(tex))
    print(f"{path}: {ds.sizes['trial']} trials")
    print("measure".ljust(36) + "".join(n.rjust(10) for n in names) + "   median F")
    table: dict[str, Any] = {}
    for label, m in measures.items():
        med = [np.nanmedian(m[tex == n]) for n in names]
        fs_cells = []
        for v in np.unique(ds["speed_mm_s"].values):
            for a in np.unique(ds["angle_deg"].values):
                cell = (ds["speed_mm_s"].values == v) & (ds["angle_deg"].values == a)
                groups = [m[cell & (tex == n)] for n in names]
                groups = [g[np.isfinite(g)] for g in groups]
                if all(g.size >= 2 for g in groups) and np.ptp(np.concatenate(groups)) > 0:
                    fs_cells.append(scipy.stats.f_oneway(*groups).statistic)
        print(
            label.ljust(36) + "".join(f"{q:10.4g}" for q in med) + f"{np.nanmedian(fs_cells):11.2f}"
        )
        table[KEYS[label]] = {
            "median": {str(n): float(q) for n, q in zip(names, med, strict=True)},
            "median_f": float(np.nanmedian(fs_cells)),
        }
    return {"n_trials": int(ds.sizes["trial"]), "measures": table}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("datasets", nargs="+", help="chapter-5 datasets (.nc)")
    ap.add_argument(
        "--json", metavar="OUT", default=None, help="also write a run file (one dataset only)"
    )
    args = ap.parse_args(argv)
    if args.json and len(args.datasets) != 1:
        ap.error("--json takes exactly one dataset")
    for p in args.datasets:
        values = measure(p)
    if args.json:
        cmd = ".venv/bin/python scripts/texture_information.py " + " ".join(
            shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:])
        )
        write_run(args.json, {"meta": run_meta(cmd, args.datasets[0]), **values})


if __name__ == "__main__":
    main()
