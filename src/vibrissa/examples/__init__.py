r"""Example files shipped with vibrissa.

``data_XY_small.mat``
    A *simulated* recording in exactly the layout of the thesis author's
    ``data_XY.mat`` (MATLAB v5 file holding a cell array ``data`` of sets x
    speeds x radial distances, each cell a samples x channels double array
    at 1 kHz), reduced to 4 sets x 3 speeds (36, 126, 216 mm/s) x 5 radial
    distances (80, 105, 130, 155, 180 mm), each cell 750 x 2 (x, y in volts).
    It was made by ``scripts/make_example_recording.py`` with vibrissa's own
    simulator (radial-distance protocol, seed 1); it is *not* a real recording.
``data_XY_small.mapping.json``
    The import mapping for it (see :mod:`vibrissa.data.importers`)::

        vibrissa import "$(python -c 'from vibrissa.examples import example_path; \
            print(example_path("data_XY_small.mat"))')" \
            --mapping .../data_XY_small.mapping.json --out xy_small.nc

Examples
--------
>>> from vibrissa.data import import_recording
>>> from vibrissa.examples import EXAMPLE_MAPPING, EXAMPLE_RECORDING, example_path
>>> ds = import_recording(example_path(EXAMPLE_RECORDING), example_path(EXAMPLE_MAPPING))
>>> dict(ds.sizes)
{'trial': 60, 'channel': 2, 'time': 750}
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

__all__ = ["EXAMPLE_MAPPING", "EXAMPLE_RECORDING", "example_names", "example_path"]

#: The simulated recording in the data_XY layout.
EXAMPLE_RECORDING = "data_XY_small.mat"
#: Its import mapping (JSON).
EXAMPLE_MAPPING = "data_XY_small.mapping.json"

_SUFFIXES = (".mat", ".json")


def example_names() -> list[str]:
    """Names of the example files shipped with the package, sorted."""
    return sorted(
        p.name for p in files(__name__).iterdir() if p.is_file() and p.name.endswith(_SUFFIXES)
    )


def example_path(name: str) -> Path:
    """Path of the shipped example file ``name``.

    Parameters
    ----------
    name
        A file name such as ``"data_XY_small.mat"`` (see :func:`example_names`).

    Returns
    -------
    pathlib.Path
        The file inside the installed package (read it, do not modify it). The
        package must be installed as a directory, not inside a zip archive.

    Raises
    ------
    FileNotFoundError
        If there is no example of that name (the message lists those there are).
    """
    if not isinstance(name, str) or not name or "/" in name or "\\" in name:
        raise FileNotFoundError(f"no example named {name!r}; examples: {example_names()}")
    res = files(__name__) / name
    if not res.is_file():
        raise FileNotFoundError(f"no example named {name!r}; examples: {example_names()}")
    return Path(str(res))
