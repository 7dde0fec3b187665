"""vibrissa: whisker-based tactile sensing after Evans (2011).

The package simulates an artificial whisker (tapered elastic rod, rubber
follicle, Hall-effect sensor), the robots that move objects into it, the
thesis' experimental protocols, and the classifiers and evaluation of
chapters 4-6 of M. H. Evans, *Tactile Discrimination with Whiskers*
(University of Sheffield, 2011).
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("vibrissa")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
