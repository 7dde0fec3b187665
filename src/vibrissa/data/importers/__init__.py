"""Import real recordings (MATLAB ``.mat`` v5 and v7.3, CSV, NPZ) into the vibrissa Dataset.

A *mapping* (a dict, or a JSON/TOML file) says where the signals and labels are
in the source file; the same keys serve every format, and unknown keys or keys
that do not apply to the format are rejected. Every problem with the file or
the mapping raises :class:`ImportMappingError` (a :class:`ValueError`) naming
the key, variable, cell, column or line at fault. The source is only read.

>>> from vibrissa.data.importers import import_recording
>>> from vibrissa.examples import EXAMPLE_MAPPING, EXAMPLE_RECORDING, example_path
>>> ds = import_recording(example_path(EXAMPLE_RECORDING), example_path(EXAMPLE_MAPPING))
>>> dict(ds.sizes)
{'trial': 60, 'channel': 2, 'time': 750}

The user guide, with every mapping key, the thesis' ``data_XY.mat`` example and
the CSV layouts, is ``docs/importing.md``.

Modules
-------
mapping
    The mapping: :class:`ImportMapping`, :func:`load_mapping`, the
    command-line forms :func:`parse_range` and :func:`parse_axis_option`.
dispatch
    :func:`detect_format`, :func:`import_recording`, :func:`import_file`.
arrays
    Cell arrays and numeric arrays (MATLAB, NPZ) -> trials; NPZ files.
matlab_v5, matlab_hdf5
    MATLAB v4-v7 files (SciPy) and v7.3 files (HDF5, h5py).
csv_files
    CSV files, long and wide layouts.
"""

from vibrissa.data.importers.dispatch import detect_format, import_file, import_recording
from vibrissa.data.importers.mapping import (
    FORMATS,
    ImportMapping,
    ImportMappingError,
    load_mapping,
    parse_axis_option,
    parse_range,
)

__all__ = [
    "FORMATS",
    "ImportMapping",
    "ImportMappingError",
    "detect_format",
    "import_file",
    "import_recording",
    "load_mapping",
    "parse_axis_option",
    "parse_range",
]
