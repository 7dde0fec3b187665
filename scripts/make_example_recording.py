"""Make the shipped example ``src/vibrissa/examples/data_XY_small.mat`` and its mapping.

The example is a *simulated* recording laid out exactly like the thesis
author's ``data_XY.mat`` (README of github.com/mathewzilla/old_matlab): a MATLAB
v5 file holding a cell array ``data`` of sets x speeds x radial distances, each
cell a samples x channels (x, y) double array at 1 kHz. The full file is
4 x 26 x 101 cells of 750 x 2; this one is 4 sets x 3 speeds (36, 126,
216 mm/s) x 5 radial distances (80, 105, 130, 155, 180 mm).

The signals come from vibrissa's own simulator (radial-distance protocol,
seed 1, a window of 375 ms before and 374 ms after peak deflection, so
750 samples); the recorded sets 1-4 are (run 1, +x), (run 1, -x), (run 2, +x),
(run 2, -x) as in :meth:`vibrissa.experiments.protocols.Protocol.trials`.
The file is compressed (zlib, MATLAB v7 compression in a v5-format file) and
must stay under 200 kB. The script checks the result by importing it with the
mapping and comparing every cell.

Usage::

    .venv/bin/python scripts/make_example_recording.py [--out-dir DIR]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import scipy.io

from vibrissa.experiments.protocols import get_protocol
from vibrissa.experiments.runner import n_samples, simulate_trials

SETS = (1, 2, 3, 4)
SPEEDS_MM_S = (36.0, 126.0, 216.0)
RADII_MM = (80.0, 105.0, 130.0, 155.0, 180.0)
WINDOW_S = (0.375, 0.374)
SEED = 1
MAX_BYTES = 200_000

#: The import mapping written beside the recording.
MAPPING = {
    "format": "mat",
    "signal": "data",
    "cell_axes": [
        {"name": "set", "values": list(SETS)},
        {"name": "speed_mm_s", "start": 36, "stop": 216, "num": len(SPEEDS_MM_S)},
        {"name": "radial_distance_mm", "start": 80, "stop": 180, "num": len(RADII_MM)},
    ],
    "channels": ["x", "y"],
    "time_axis": 0,
    "sample_rate_hz": 1000,
    "t0_s": -WINDOW_S[0],
    "units": "V",
    "attrs": {
        "description": (
            "SIMULATED example in the layout of data_XY.mat (Evans 2011): "
            "vibrissa radial-distance protocol, seed 1; not a real recording"
        )
    },
}


def make_cells() -> np.ndarray:
    """Simulate the trials and arrange them as MATLAB's ``data{set, speed, radius}``.

    Returns
    -------
    numpy.ndarray
        Object array of shape (4, 3, 5); each element a (750, 2) float64 array
        (samples x channels x, y) in volts.
    """
    p = get_protocol(
        "radial-distance",
        radial_distances_mm=RADII_MM,
        speeds_mm_s=SPEEDS_MM_S,
        window_s=WINDOW_S,
        seed=SEED,
    )
    ns = n_samples(p)
    if ns != 750:
        raise RuntimeError(f"the protocol gives {ns} samples per trial, not 750")
    specs = p.trials()
    sig = simulate_trials(p, range(p.n_trials))["signal"]  # (n, 2, 750)
    cells = np.empty((len(SETS), len(SPEEDS_MM_S), len(RADII_MM)), dtype=object)
    for spec in specs:
        i = SETS.index(spec.set)
        j = SPEEDS_MM_S.index(spec.labels["speed_mm_s"])
        k = RADII_MM.index(spec.labels["radial_distance_mm"])
        if cells[i, j, k] is not None:
            raise RuntimeError(f"two trials for cell {{{i + 1},{j + 1},{k + 1}}}")
        cells[i, j, k] = np.ascontiguousarray(sig[spec.index].T)  # samples x channels
    if any(c is None for c in cells.flat):
        raise RuntimeError("some cells of the grid got no trial")
    return cells


def mapping_json(mapping: dict[str, object]) -> str:
    """``mapping`` as JSON, one line per key and per cell axis."""
    lines = []
    for key, value in mapping.items():
        if key == "cell_axes":
            axes = ",\n".join(f"    {json.dumps(a)}" for a in value)  # type: ignore[union-attr]
            lines.append(f'  "cell_axes": [\n{axes}\n  ]')
        else:
            lines.append(f"  {json.dumps(key)}: {json.dumps(value)}")
    text = "{\n" + ",\n".join(lines) + "\n}\n"
    if json.loads(text) != mapping:
        raise RuntimeError("mapping JSON does not round-trip")
    return text


def main(argv: list[str] | None = None) -> int:
    """Write the example recording and mapping, then check them by importing."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = Path(__file__).resolve().parents[1]
    parser.add_argument(
        "--out-dir",
        type=Path,
        default=root / "src" / "vibrissa" / "examples",
        help="directory to write data_XY_small.mat and data_XY_small.mapping.json",
    )
    args = parser.parse_args(argv)
    out_dir: Path = args.out_dir
    out_dir.mkdir(parents=True, exist_ok=True)
    cells = make_cells()
    mat = out_dir / "data_XY_small.mat"
    mapping_path = out_dir / "data_XY_small.mapping.json"
    scipy.io.savemat(mat, {"data": cells}, do_compression=True, format="5")
    mapping_path.write_text(mapping_json(MAPPING), encoding="utf-8")
    size = mat.stat().st_size
    if size >= MAX_BYTES:
        raise SystemExit(f"{mat} is {size} bytes, more than {MAX_BYTES}")

    from vibrissa.data import import_recording

    ds = import_recording(mat, mapping_path)
    for t, (i, j, k) in enumerate(np.ndindex(cells.shape)):
        assert ds["set"].values[t] == SETS[i]
        assert ds["speed_mm_s"].values[t] == SPEEDS_MM_S[j]
        assert ds["radial_distance_mm"].values[t] == RADII_MM[k]
        np.testing.assert_array_equal(ds["signal"].values[t], cells[i, j, k].T)
    print(f"{mat}: {size} bytes, {ds.sizes['trial']} trials checked; {mapping_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
