"""The line an interrupted command prints when it has nothing more precise to say.

Shared by the console entry point (:mod:`vibrissa.__main__`, before the command line is
imported) and the command group (:mod:`vibrissa.cli._usage`).
"""

from __future__ import annotations

__all__ = ["INTERRUPTED"]

#: What an interrupted command says when it has nothing more precise to say.
INTERRUPTED = "interrupted: the command stopped before it finished"
