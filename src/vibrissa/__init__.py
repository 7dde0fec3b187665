"""vibrissa: whisker-based tactile sensing after Evans (2011).

The package simulates an artificial whisker (tapered elastic rod, rubber
follicle, Hall-effect sensor), the robots that move objects into it, the
thesis' experimental protocols, and the classifiers and evaluation of
chapters 4-6 of M. H. Evans, *Tactile Discrimination with Whiskers*
(University of Sheffield, 2011).
"""

# No imports at all, ``__future__`` included (a real module, read from disk): a Ctrl-C
# while the package is imported, before the entry point runs, is Python's traceback.
__all__ = ["__version__"]


def __getattr__(name: str) -> str:
    """``__version__``, read from the installed metadata when first asked for.

    Importing the package stays free of work (``importlib.metadata`` takes tens of
    milliseconds), so the console entry point (:mod:`vibrissa.__main__`) installs its
    signal handling before anything slow runs: a Ctrl-C in that time was a traceback.
    """
    if name != "__version__":
        raise AttributeError(f"module 'vibrissa' has no attribute {name!r}")
    from importlib.metadata import PackageNotFoundError, version

    try:
        found = version("vibrissa")
    except PackageNotFoundError:  # pragma: no cover - running from a source tree
        found = "0.0.0+unknown"
    globals()["__version__"] = found
    return found
