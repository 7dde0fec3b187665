"""Datasets of whisker recordings: the schema, NetCDF storage, importers."""

from vibrissa.data.dataset import (
    KNOWN_LABELS,
    as_arrays,
    attr_value,
    concat_datasets,
    coordinate_attrs,
    label_names,
    make_dataset,
    select,
    validate_dataset,
    whisker_params,
)
from vibrissa.data.importers import (
    ImportMapping,
    ImportMappingError,
    import_file,
    import_recording,
    load_mapping,
)
from vibrissa.data.netcdf import (
    SCHEMA_VERSION,
    DatasetFileError,
    DatasetIntegrityWarning,
    DatasetModifiedError,
    DatasetSchemaError,
    checksum,
    checksum_parts,
    load_dataset,
    save_dataset,
)
from vibrissa.data.schema import TEXTURE_CODES, decode_texture, encode_texture, parse_whisker

__all__ = [
    "KNOWN_LABELS",
    "SCHEMA_VERSION",
    "TEXTURE_CODES",
    "DatasetFileError",
    "DatasetIntegrityWarning",
    "DatasetModifiedError",
    "DatasetSchemaError",
    "ImportMapping",
    "ImportMappingError",
    "as_arrays",
    "attr_value",
    "checksum",
    "checksum_parts",
    "coordinate_attrs",
    "concat_datasets",
    "decode_texture",
    "encode_texture",
    "import_file",
    "import_recording",
    "label_names",
    "load_dataset",
    "load_mapping",
    "make_dataset",
    "parse_whisker",
    "save_dataset",
    "select",
    "validate_dataset",
    "whisker_params",
]
