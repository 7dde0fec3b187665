"""Datasets of whisker recordings: the schema, NetCDF storage, importers."""

from vibrissa.data.dataset import (
    KNOWN_LABELS,
    as_arrays,
    concat_datasets,
    label_names,
    make_dataset,
    select,
    validate_dataset,
    whisker_params,
)
from vibrissa.data.netcdf import DatasetFileError, checksum, load_dataset, save_dataset

__all__ = [
    "KNOWN_LABELS",
    "DatasetFileError",
    "as_arrays",
    "checksum",
    "concat_datasets",
    "label_names",
    "load_dataset",
    "make_dataset",
    "save_dataset",
    "select",
    "validate_dataset",
    "whisker_params",
]
