"""Whether an HDF5 file (a NetCDF-4 dataset, a MATLAB v7.3 ``.mat``) is self-contained.

HDF5 lets a file take its bytes from elsewhere: an *external link* names an object in
another file, a dataset with *external storage* keeps its raw data in other files
(named by path, resolved against the working directory), and a *virtual dataset* maps
its elements onto datasets of other files. A reader that follows them imports the bytes
of whatever those paths name when it runs, and a checksum of the input file covers none
of them: a provenance hole and a way to read any file the user can. vibrissa refuses
such inputs before reading any data (:func:`foreign_storage`).
"""

from __future__ import annotations

from typing import Any

__all__ = ["foreign_storage"]


def foreign_storage(f: Any) -> str | None:
    """The first object of an open HDF5 file whose data lies outside the file.

    Parameters
    ----------
    f
        An open ``h5py.File`` (or group).

    Returns
    -------
    str or None
        ``None`` when every link is internal and every dataset's bytes are in the
        file; else what was found and where, e.g. ``"an external link '/a' to
        other.h5:/x"``, ``"dataset '/signal' with external storage in raw.bin"`` or
        ``"virtual dataset '/v' mapped onto other.h5"``.
    """
    import h5py

    found: list[str] = []

    def on_link(name: str, link: Any) -> bool | None:
        if isinstance(link, h5py.ExternalLink):
            found.append(f"an external link {'/' + name!r} to {link.filename}:{link.path}")
            return True
        if isinstance(link, h5py.SoftLink):
            return None  # points inside this file; its target is visited on its own
        obj = f.get(name)
        if isinstance(obj, h5py.Dataset):
            if obj.external:
                files = sorted({str(entry[0]) for entry in obj.external})
                found.append(f"dataset {'/' + name!r} with external storage in {', '.join(files)}")
                return True
            if obj.is_virtual:
                sources = sorted({m.file_name for m in obj.virtual_sources()})
                found.append(f"virtual dataset {'/' + name!r} mapped onto {', '.join(sources)}")
                return True
        return None

    f.visititems_links(on_link)
    return found[0] if found else None
