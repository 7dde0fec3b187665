"""`vibrissa` commands of the whisker family (being built)."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    """Register this family's commands on the top-level app."""
