"""The slow profile of the command-line fuzzer: the real commands, hostile values, no patches.

Usage::

    .venv/bin/python scripts/fuzz_cli_slow.py [--json FILE] [--jobs N] [--run-s S] [--limit N]
    .venv/bin/python scripts/fuzz_cli_slow.py --signals [--json FILE] [--jobs N]

``tests/cli/test_fuzz_contract.py`` runs in CI with every command's work patched out. This
script runs the real ``vibrissa`` console command in a subprocess, in a fresh directory,
for every option of every command (from :data:`vibrissa.cli._contract.CONTRACT`) with a
few hostile values of its kind (reproductions and generation with ``--quick``). A case is:

- *refused* when it exits 2 with exactly one ``error:`` line, no traceback, and nothing
  was created in its directory;
- *finished* when it exits 0 (a cheap command that did its work);
- *interrupted* when it was still working after ``--run-s`` seconds and, sent SIGINT,
  exited 130 with an ``interrupted:`` line and no traceback;
- a *failure* otherwise: a traceback, exit 1 or another status, more than one line on a
  refusal, files created on a refusal, or a *hang* (no exit within 60 s of SIGINT).

``--signals`` is the signal profile instead: every command with valid options (the
reproductions, generation and identification ``--quick``) is sent SIGINT or SIGTERM at
each of :data:`MOMENTS` seconds after it started; each run must finish (exit 0) or stop
with exit 130 / 143 and an ``interrupted:`` line, no traceback, within 60 s. A signal
that lands in the interpreter's own start (about 25 ms, before any of vibrissa runs) is
counted apart as *interpreter-start*: no program written in Python can report it.

It prints the counts and writes them, with every failure's command line, as JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
VIBRISSA = [sys.executable, "-m", "vibrissa"]

NUMBERS = ("nan", "1e300", "-1", "5e-324")
INTEGERS = ("0", "-1", "18446744073709551616")
TEXTS = ("", "\x07x", "x" * 5000)
#: Seconds after the start at which the signal profile interrupts a command: during the
#: import of the command line, its checks, the first work and well into it.
MOMENTS = (0.05, 0.3, 1.5, 4.0, 12.0)
#: A command that exits 0 this soon after the signal had finished its work: the signal
#: landed in the interpreter's teardown, which ignores it (s).
TEARDOWN_S = 2.0
#: The exit status of a command stopped by each signal.
EXPECTED_EXIT = {signal.SIGINT: 130, signal.SIGTERM: 143}


def assets(root: Path, labelled: bool = False) -> dict[str, Path]:
    """Valid inputs for required options and special files for hostile ones.

    ``labelled`` also generates a chapter-4 and a chapter-5 dataset (``--quick``) for
    ``fit-pipeline``'s ``--where`` and ``--what``, which the signal profile runs whole.
    """
    from vibrissa.examples import example_path
    from vibrissa.framework import TactilePipeline

    mat = root / "data.mat"
    shutil.copyfile(example_path("data_XY_small.mat"), mat)
    mapping = root / "mapping.json"
    shutil.copyfile(example_path("data_XY_small.mapping.json"), mapping)
    subprocess.run(
        [*VIBRISSA, "import", str(mat), "--mapping", str(mapping), "-o", str(root / "d.nc")],
        check=True,
        capture_output=True,
    )
    TactilePipeline(1000.0, 1, 2).save(root / "p.vtp")
    for name, protocol in (("where", "radial-distance"), ("what", "angle-texture")):
        if labelled:
            out = root / f"{name}.nc"
            subprocess.run([*VIBRISSA, "generate", protocol, "--quick", "-o", str(out)], check=True)
    (root / "dir").mkdir()
    os.mkfifo(root / "fifo")
    (root / "empty").write_text("")
    (root / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    names = ("mat", "mapping", "dir", "fifo", "empty")
    return {
        **{
            k: root / ("data.mat" if k == "mat" else f"{k}.json" if k == "mapping" else k)
            for k in names
        },
        "dataset": root / "d.nc",
        "where": root / ("where.nc" if labelled else "d.nc"),
        "what": root / ("what.nc" if labelled else "d.nc"),
        "pipeline": root / "p.vtp",
        "deep": root / "deep.json",
    }


def required(path: str, a: dict[str, Path]) -> dict[str, list[str]]:
    """The command's required options with valid values (and ``--quick`` where it has one)."""
    if path.startswith("reproduce "):
        return {"out": ["--out", "rep"], "quick": ["--quick"]}
    return {
        "generate": {"protocol": ["radial-distance"], "out": ["-o", "o.nc"], "quick": ["--quick"]},
        "import": {
            "source": [str(a["mat"])],
            "mapping": ["--mapping", str(a["mapping"])],
            "out": ["-o", "o.nc"],
        },
        "plot": {"dataset": [str(a["dataset"])], "out": ["-o", "figs"]},
        "identify": {"quick": ["--quick"]},
        "live": {"pipeline": ["--pipeline", str(a["pipeline"])], "input_": ["--input", "-"]},
        "fit-pipeline": {
            "out": ["--out", "p.vtp"],
            "where": ["--where", str(a.get("where", a["dataset"]))],
            "what": ["--what", str(a.get("what", a["dataset"]))],
        },
        "whisker static": {"force_n": ["--force-n", "0.001"], "at_mm": ["--at-mm", "100"]},
        "whisker push": {
            "at_mm": ["--at-mm", "150"],
            "displacement_mm": ["--displacement-mm", "1"],
        },
        "run crunchbot": {"out": ["--out", "watch"], "seconds": ["--seconds", "5"]},
    }.get(path, {})


def hostile(spec: Any, a: dict[str, Path]) -> tuple[str, ...]:
    """A few hostile values of an option's kind."""
    if spec.kind == "number":
        return NUMBERS
    if spec.kind in ("integer", "seed"):
        return INTEGERS
    if spec.kind == "file":
        return (str(a["fifo"]), str(a["dir"]), str(a["deep"]))
    if spec.kind == "refused":
        return (str(a["empty"]),)
    if spec.kind == "output":
        return (str(a["empty"]) if spec.directory else str(a["dir"]),)
    return (*TEXTS, str(a["fifo"]))


def flags() -> dict[tuple[str, str], str]:
    """(command, parameter) -> its flag, or "" for an argument."""
    import typer.main

    from vibrissa.cli import app

    out: dict[tuple[str, str], str] = {}

    def walk(cmd: Any, path: tuple[str, ...]) -> None:
        if getattr(cmd, "commands", None):
            for name, sub in cmd.commands.items():
                walk(sub, (*path, name))
            return
        for p in cmd.params:
            arg = p.param_type_name == "argument"
            out[(" ".join(path), p.name)] = "" if arg else max(p.opts, key=len)

    walk(typer.main.get_command(app), ())
    return out


def cases(a: dict[str, Path]) -> list[list[str]]:
    """Every command line of the profile."""
    from vibrissa.cli._contract import CONTRACT

    fl = flags()
    out = []
    for path, table in CONTRACT.items():
        reqs = required(path, a)
        for name, spec in table.items():
            if spec.kind == "flag":
                continue
            for value in hostile(spec, a):
                words = path.split()
                for opt, given in reqs.items():
                    if opt != name:
                        words += given
                flag = fl[(path, name)]
                if flag:
                    words += [flag, value]
                else:
                    words.insert(len(path.split()), value)
                out.append(words)
    return out


def _listing(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def signal_cases(a: dict[str, Path]) -> list[tuple[list[str], float, int]]:
    """(command line, moment in s, signal) of the signal profile: valid lines only."""
    from vibrissa.cli._contract import CONTRACT

    fl = flags()
    out = []
    for path in CONTRACT:
        words = path.split()
        for name, given in required(path, a).items():
            if fl.get((path, name)) == "":  # an argument: right after the command's name
                at = len(path.split())
                words[at:at] = given
            else:
                words += given
        if path == "run crunchbot":  # long enough to be running at every moment
            words[words.index("--seconds") + 1] = "120"
        for moment in MOMENTS:
            for sig in EXPECTED_EXIT:
                out.append((words, moment, int(sig)))
    return out


def _in_interpreter_start(code: int | None, err: str) -> bool:
    """Whether a signal ended Python's own start, before any of vibrissa ran.

    The ``site`` module's import, or the default action of a signal with nothing
    printed (Python installs its SIGINT handler, vibrissa its SIGTERM one, after that).
    """
    in_site = "<frozen site>" in err or "init_import_site" in err
    # ``python -m`` finds the module with runpy before any of vibrissa is imported
    in_runpy = err.rstrip().endswith("KeyboardInterrupt") and "/vibrissa/" not in err
    return in_site or in_runpy or (code is not None and code < 0 and not err.strip())


def run_case(
    words: list[str], run_s: float, sig: int = signal.SIGINT, expect_signal: bool = False
) -> dict[str, Any]:
    """Run one command line, send ``sig`` if it runs past ``run_s``; classify what happened."""
    with tempfile.TemporaryDirectory(prefix="fuzz-slow-") as tmp:
        env = {**os.environ, "CI": "1", "COLUMNS": "100"}
        proc = subprocess.Popen(
            [*VIBRISSA, *words],
            cwd=tmp,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            errors="replace",
            env=env,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        interrupted = False
        sent = 0.0
        try:
            out, err = proc.communicate(timeout=run_s)
        except subprocess.TimeoutExpired:
            interrupted = True
            sent = time.perf_counter()
            proc.send_signal(sig)
            try:
                out, err = proc.communicate(timeout=60)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.communicate()
                return {"what": "hang", "argv": words}
        code = proc.returncode
        after_signal_s = time.perf_counter() - sent if interrupted else None
        text = out + err
        lines = err.strip().splitlines()
        if expect_signal and interrupted and _in_interpreter_start(code, err):
            return {"what": "interpreter-start", "argv": words, "code": code}
        if "Traceback" in text:
            return {"what": "traceback", "argv": words, "stderr": err[-2000:]}
        if interrupted:
            if code == 0 and after_signal_s is not None and after_signal_s < TEARDOWN_S:
                # the work was done: the signal landed in the teardown, which ignores it
                return {"what": "finished", "argv": words}
            ok = code == EXPECTED_EXIT[signal.Signals(sig)] and any(
                x.startswith("interrupted:") for x in lines
            )
            return {
                "what": "interrupted" if ok else "bad-interrupt",
                "argv": words,
                "code": code,
                "exit_after_signal_s": after_signal_s,
                "stderr": err[-2000:],
            }
        if code == 0:
            return {"what": "finished", "argv": words}
        if expect_signal:  # a valid command line that stopped on its own, not with 0
            return {"what": f"exit-{code}", "argv": words, "stderr": err[-2000:]}
        if code != 2:
            return {"what": f"exit-{code}", "argv": words, "stderr": err[-2000:]}
        if len(lines) != 1 or not lines[0].startswith("error: "):
            return {"what": "not-one-line", "argv": words, "stderr": err[-2000:]}
        if _listing(Path(tmp)):
            return {"what": "created-on-refusal", "argv": words, "files": _listing(Path(tmp))}
        return {"what": "refused", "argv": words}


def main(argv: list[str] | None = None) -> int:
    """Run the profile; print and write the counts."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write the counts and failures here")
    parser.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    parser.add_argument("--run-s", type=float, default=20.0, help="seconds before SIGINT")
    parser.add_argument("--limit", type=int, default=0, help="only the first N cases")
    parser.add_argument(
        "--signals",
        action="store_true",
        help=f"the signal profile: SIGINT and SIGTERM at {MOMENTS} s into valid commands",
    )
    args = parser.parse_args(argv)
    if args.jobs < 1 or not 0 < args.run_s <= 3600 or args.limit < 0:
        parser.error("--jobs >= 1, 0 < --run-s <= 3600 and --limit >= 0")
    root = Path(tempfile.mkdtemp(prefix="fuzz-assets-"))
    try:
        a = assets(root, labelled=args.signals)
        todo: list[tuple[list[str], float, int]] = (
            signal_cases(a) if args.signals else [(w, args.run_s, signal.SIGINT) for w in cases(a)]
        )[: args.limit or None]
        print(f"fuzz_cli_slow: {len(todo)} command lines, {args.jobs} at a time", file=sys.stderr)
        t0 = time.perf_counter()
        with ThreadPoolExecutor(args.jobs) as pool:
            results = list(
                pool.map(lambda c: run_case(c[0], c[1], c[2], expect_signal=args.signals), todo)
            )
    finally:
        shutil.rmtree(root, ignore_errors=True)
    for r, (_, moment, sig) in zip(results, todo, strict=True):
        r["signal"], r["after_s"] = signal.Signals(sig).name, moment
    counts: dict[str, int] = {}
    for r in results:
        counts[r["what"]] = counts.get(r["what"], 0) + 1
    good = {"refused", "finished", "interrupted", "interpreter-start"}
    failures = [r for r in results if r["what"] not in good]
    summary = {
        "cases": len(results),
        "counts": counts,
        "failures": failures,
        "wall_seconds": round(time.perf_counter() - t0, 1),
        "profile": "signals" if args.signals else "hostile values",
        "run_s_before_signal": list(MOMENTS) if args.signals else args.run_s,
    }
    print(json.dumps({k: v for k, v in summary.items() if k != "failures"}, indent=1))
    for f in failures:
        where = f" ({f['signal']} after {f['after_s']} s)" if args.signals else ""
        argv = " ".join(map(repr, f["argv"]))
        print(f"FAIL {f['what']}{where}: vibrissa {argv}", file=sys.stderr)
    if args.json is not None:
        from vibrissa._atomic import atomic_write_text

        atomic_write_text(args.json, json.dumps(summary, indent=1) + "\n")
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
