"""Run the hostile-input corpus through the installed ``vibrissa`` command and count.

Every case of ``tests/cli/hostile_corpus.py`` (the same corpus the test suite runs)
is run through the console script in a fresh empty directory. A case is *refused
cleanly* when it exits with status 2, prints exactly one line on standard error,
``error: ...``, naming the option or path at fault, prints no traceback and creates
no file. The summary counts inputs tried, refused cleanly, tracebacks, other exit
statuses, other messages (more lines, or not naming the culprit) and cases that
left files behind; each failing case is listed.

Usage::

    python scripts/hostile_inputs.py [--vibrissa PATH] [--jobs N]

Exit status 0 if every case was refused cleanly, 1 otherwise.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "cli"))

from hostile_corpus import CASES, Case, Outcome, run_console  # noqa: E402


def _default_executable() -> str:
    beside = Path(sys.executable).with_name("vibrissa")
    found = str(beside) if beside.exists() else shutil.which("vibrissa")
    if found is None:
        raise SystemExit("vibrissa console script not found; pass --vibrissa PATH")
    return found


def _run(case: Case, executable: str) -> Outcome:
    with tempfile.TemporaryDirectory(prefix="vibrissa-hostile-") as d:
        return run_console(case, Path(d), executable)


def summarise(outcomes: list[Outcome]) -> dict[str, int]:
    """Counts of the outcomes (see the module docstring)."""
    return {
        "inputs tried": len(outcomes),
        "refused cleanly (exit 2, one line naming the option or path)": sum(
            o.refused_cleanly for o in outcomes
        ),
        "tracebacks": sum(o.traceback for o in outcomes),
        "other exit statuses": sum(o.exit_code != 2 for o in outcomes),
        "other messages (not one line naming the culprit)": sum(
            o.exit_code == 2 and not o.one_line for o in outcomes
        ),
        "left files behind": sum(bool(o.new_files) for o in outcomes),
    }


def main(argv: list[str] | None = None) -> int:
    """Run the corpus and print the summary; 0 if every case was refused cleanly."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--vibrissa", default=None, help="The console script to run.")
    parser.add_argument(
        "--jobs",
        type=int,
        default=os.cpu_count() or 1,
        help="Cases run at the same time (default: all cores).",
    )
    args = parser.parse_args(argv)
    executable = args.vibrissa or _default_executable()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        outcomes = list(pool.map(lambda c: _run(c, executable), CASES))
    for o in outcomes:
        if not o.refused_cleanly:
            print(f"NOT REFUSED CLEANLY: {o.problem()}")
    width = max(len(k) for k in summarise(outcomes))
    print(f"hostile inputs against {executable}:")
    for key, n in summarise(outcomes).items():
        print(f"  {key:<{width}}  {n}")
    return 0 if all(o.refused_cleanly for o in outcomes) else 1


if __name__ == "__main__":
    raise SystemExit(main())
