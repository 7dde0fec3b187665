"""Time README's first command in a fresh clone, as a new user would run it.

Usage::

    python3 benchmarks/bench_readme_first_command.py [--repo .] [--keep DIR]
        [--out benchmarks/results/readme_first_command.json]

Clones ``--repo`` (its committed ``HEAD``, not the working tree) into a temporary
directory, reads the first command of README's quick start (the first line of its first
``bash`` block), runs it there with ``bash -c`` and times it. The reproduction's own stage
times (``meta.wall_seconds`` of its ``results.json``) split the wall time into set-up
(virtual environment and installation: the total minus the reproduction) and the
generate, evaluate and report stages. Issue 14's budget: 300 s for the whole command,
180 s for the chapter-4 generation, on this machine's two cores. The load average at the
start is recorded: other work on the machine slows the run down.

Needs only the standard library (it runs before any environment exists).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from datetime import UTC, datetime
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import machine

BUDGET_S = {"total": 300.0, "generate": 180.0}


def first_command(readme: str) -> str:
    """The first line of the first ``bash`` code block of ``readme``."""
    m = re.search(r"```bash\n(.+?)\n", readme)
    if m is None:
        raise ValueError("README has no ```bash block")
    return m.group(1).strip()


def _atomic_write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def main() -> int:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--repo", default=".", help="repository to clone (default: here)")
    ap.add_argument(
        "--keep",
        default=None,
        help="clone here and keep it (default: a temporary directory, removed afterwards)",
    )
    ap.add_argument("--out", default="benchmarks/results/readme_first_command.json")
    args = ap.parse_args()
    repo = Path(args.repo).resolve()
    commit = subprocess.run(
        ["git", "-C", str(repo), "rev-parse", "--short", "HEAD"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.strip()
    work = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="readme-"))
    if work.exists() and any(work.iterdir()):
        print(f"error: --keep {work}: directory is not empty", file=sys.stderr)
        return 2
    clone = work / "clone"
    subprocess.run(["git", "clone", "-q", str(repo), str(clone)], check=True)
    command = first_command((clone / "README.md").read_text())
    print(f"{commit}: {command}", flush=True)
    load = os.getloadavg()[0]
    started = datetime.now(UTC).isoformat(timespec="seconds")
    t0 = time.perf_counter()
    proc = subprocess.run(["bash", "-c", command], cwd=clone)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        print(f"error: the command exited with {proc.returncode}", file=sys.stderr)
        return 1
    results = sorted(clone.glob("vibrissa-out/*/results.json"))
    meta = json.loads(results[0].read_text())["meta"] if results else {}
    stages = meta.get("wall_seconds", {})
    out = {
        "what": "README's first command in a fresh clone of the committed HEAD, timed by "
        "benchmarks/bench_readme_first_command.py; stage times from the "
        "reproduction's results.json meta.wall_seconds",
        "command": command,
        "commit": commit,
        "machine": machine(),
        "started_at": started,
        "load_average_at_start": round(load, 2),
        "wall_seconds": round(wall, 2),
        "setup_seconds": round(wall - stages["total"], 1) if "total" in stages else None,
        "reproduction_wall_seconds": stages,
        "cores": meta.get("cores"),
        "dataset": {
            k: meta.get("dataset", {}).get(k) for k in ("fingerprint", "n_trials", "reused")
        },
        "budget_seconds": BUDGET_S,
        "within_budget": {
            "total": wall <= BUDGET_S["total"],
            "generate": stages.get("generate", float("inf")) <= BUDGET_S["generate"],
        },
    }
    _atomic_write(Path(args.out), json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
