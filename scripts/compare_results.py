"""Compare two trees of ``results.json`` files key for key (e.g. before and after a refactor).

Walks ``BEFORE`` and ``AFTER`` for every ``results.json`` (matched by their path relative
to each root) and compares the two JSON documents recursively. Values that measure the
run rather than the results (wall-clock times, time stamps, the command line, paths,
real-time factors, classifier latencies, every ``*_seconds``) are left out by key name;
``--ignore`` adds more names. Numbers must be equal exactly unless ``--rtol`` is given.

Usage::

    python scripts/compare_results.py BEFORE_DIR AFTER_DIR [--ignore KEY ...] [--rtol 0]

Prints one line per difference and a summary; exit status 0 when every file has its
counterpart and no value differs, 1 otherwise, 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

#: Keys whose values describe the run (time, place, machine), not its results.
VOLATILE = frozenset(
    {
        "wall_seconds",
        "started_at",
        "command",
        "path",
        "fit_seconds",
        "classify_seconds",
        "real_time_factor",
        "classifier_latency_ms",
        "cores",
        "wall_s",
        "elapsed_s",
        "seconds_per_trial",
        "vibrissa_version",
    }
)


def volatile(key: str, where: str, ignore: frozenset[str]) -> bool:
    """Whether the value at ``where.key`` measures the run: a name in ``ignore``, any
    ``*_seconds`` timing, or a classifier's ``seconds``."""
    return (
        key in ignore
        or key.endswith("_seconds")
        or (key == "seconds" and ".classifiers." in where + ".")
    )


def differences(a: Any, b: Any, where: str, ignore: frozenset[str], rtol: float) -> Iterator[str]:
    """Every difference between ``a`` and ``b`` as ``where: a != b`` lines."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            if volatile(str(k), where, ignore):
                continue
            if k not in a:
                yield f"{where}.{k}: only after"
            elif k not in b:
                yield f"{where}.{k}: only before"
            else:
                yield from differences(a[k], b[k], f"{where}.{k}", ignore, rtol)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            yield f"{where}: {len(a)} items before, {len(b)} after"
            return
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            yield from differences(x, y, f"{where}[{i}]", ignore, rtol)
    elif (
        isinstance(a, int | float)
        and isinstance(b, int | float)
        and not isinstance(a, bool)
        and not isinstance(b, bool)
    ):
        if a == b or (math.isnan(a) and math.isnan(b)):
            return
        if rtol > 0 and math.isclose(a, b, rel_tol=rtol):
            return
        yield f"{where}: {a!r} != {b!r}"
    elif a != b:
        yield f"{where}: {a!r} != {b!r}"


def compare_trees(
    before: Path, after: Path, ignore: frozenset[str] = VOLATILE, rtol: float = 0.0
) -> tuple[int, list[str]]:
    """(files compared, difference lines) of the two trees."""
    lines: list[str] = []
    files_b = {p.relative_to(before) for p in before.rglob("results.json")}
    files_a = {p.relative_to(after) for p in after.rglob("results.json")}
    for rel in sorted(files_b - files_a):
        lines.append(f"{rel}: missing after")
    for rel in sorted(files_a - files_b):
        lines.append(f"{rel}: missing before")
    common = sorted(files_b & files_a)
    for rel in common:
        a = json.loads((before / rel).read_text())
        b = json.loads((after / rel).read_text())
        lines += [f"{rel}: {d}" for d in differences(a, b, "", ignore, rtol)]
    return len(common), lines


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--ignore", nargs="*", default=[], help="more keys to leave out")
    ap.add_argument("--rtol", type=float, default=0.0, help="relative tolerance of numbers")
    args = ap.parse_args(argv)
    for d in (args.before, args.after):
        if not d.is_dir():
            ap.error(f"not a directory: {d}")
    if not (args.rtol >= 0 and math.isfinite(args.rtol)):
        ap.error(f"--rtol must be a finite number >= 0, got {args.rtol}")
    n, lines = compare_trees(args.before, args.after, VOLATILE | set(args.ignore), args.rtol)
    for line in lines:
        print(line)
    print(
        f"{n} results.json compared, {len(lines)} differences "
        f"(left out: {', '.join(sorted(VOLATILE | set(args.ignore)))}, *_seconds, "
        "classifiers' seconds)"
    )
    return 0 if n and not lines else 1


if __name__ == "__main__":
    sys.exit(main())
