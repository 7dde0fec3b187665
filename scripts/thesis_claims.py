"""Evaluate the ledger of thesis claims on the run files and write ``docs/runs/claims.json``.

Every claim of :data:`vibrissa.thesis.claims.CLAIMS` is evaluated against
``docs/runs/*.json``; a missing run file or key makes it "not measured", never an
error. ``docs/templates/thesis_claims.md`` prints the result (its table is the
pre-formatted ``table`` string of ``claims.json``), so after this script run
``scripts/render_docs.py``::

    .venv/bin/python scripts/thesis_claims.py            # write docs/runs/claims.json
    .venv/bin/python scripts/thesis_claims.py --check    # exit 1 if it is stale
    .venv/bin/python scripts/render_docs.py              # render docs/thesis_claims.md

``meta.date`` is the newest ``meta.date`` of the run files read (when the evidence was
made), so the file changes only when the evidence does.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import sys
from pathlib import Path
from typing import Any

from vibrissa.thesis.claims import evaluate_all, ledger, load_runs

ROOT = Path(__file__).resolve().parent.parent
RUNS = ROOT / "docs" / "runs"
COMMAND = ".venv/bin/python scripts/thesis_claims.py"


def claims_file(runs_dir: Path) -> dict[str, Any]:
    """The content of ``claims.json`` for the run files of ``runs_dir``.

    Parameters
    ----------
    runs_dir
        Folder of the run files.

    Returns
    -------
    dict
        ``meta`` (``command``, ``vibrissa_version``, ``date``, ``dataset`` = ``None``,
        ``sources``: the run files read) and :func:`vibrissa.thesis.claims.ledger`.
    """
    runs = load_runs(runs_dir)
    dates = [
        r["meta"]["date"]
        for r in runs.values()
        if isinstance(r, dict) and isinstance(r.get("meta"), dict) and r["meta"].get("date")
    ]
    meta = {
        "command": COMMAND,
        "vibrissa_version": importlib.metadata.version("vibrissa"),
        "date": max(dates) if dates else None,
        "dataset": None,
        "sources": [f"docs/runs/{name}.json" for name in sorted(runs)],
    }
    return {"meta": meta, **ledger(evaluate_all(runs_dir))}


def _text(data: dict[str, Any]) -> str:
    return json.dumps(data, indent=1, sort_keys=True) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write (or ``--check``) the ledger's run file; returns the exit status."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=Path, default=RUNS, help="folder of the run files")
    ap.add_argument(
        "--out", type=Path, default=None, help="the ledger's run file (default RUNS/claims.json)"
    )
    ap.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 if the file is stale"
    )
    args = ap.parse_args(argv)
    out = args.out or args.runs / "claims.json"
    text = _text(claims_file(args.runs))
    if args.check:
        if not out.is_file() or out.read_text(encoding="utf-8") != text:
            print(f"{out} differs from the evaluated claims; run: {COMMAND}")
            return 1
        return 0
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(f".{out.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(out)
    counts = json.loads(text)["counts"]
    print(
        f"wrote {out}: {counts['holds']} hold, {counts['does_not_hold']} do not hold, "
        f"{counts['not_measured']} not measured"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
