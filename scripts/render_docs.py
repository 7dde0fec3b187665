"""Render the measured docs from their templates and the committed run files.

A template ``docs/templates/<name>.md`` is rendered into ``docs/<name>.md``. Every
measured number in it is a placeholder resolved from a run file
``docs/runs/<source>.json``::

    {{ methods.frequency_window.ring_mv.radius_80_130 | .0f }}
    {{ chapter5.classifiers.minirocket.kappa.texture | .2f }}
    {{ identify.met }}

The first part of the dotted key names the run file (``docs/runs/methods.json``),
the rest walks its nested objects. After ``|`` comes a Python format specification
(``.2f``, ``.0f``, ``,d``, ``+.1f``); without one, strings and integers print as they
are, floats with ``repr`` and lists of strings joined by ", ". Nothing else is
supported (no expressions, no conditionals): anything a sentence depends on is
computed by the script that writes the run file. Fenced code blocks are copied
verbatim (no placeholders there). ``{# ... #}`` (on one line) is a template comment,
dropped from the render (a line holding only a comment is dropped whole); templates
use it to declare the literal decimals they carry that are settings of the code, not
measurements (``tests/docs/test_docs_rendered.py`` reads them).

Every run file records how it was made, in ``meta``: ``command``,
``vibrissa_version``, ``date`` and ``dataset`` (the data file with its
fingerprint, or ``null`` when the run simulates its own trials). A rendered doc
starts with an HTML comment naming its template, its run files and this command.

Usage::

    .venv/bin/python scripts/render_docs.py            # rewrite docs/<name>.md
    .venv/bin/python scripts/render_docs.py --check    # exit 1 if any doc differs

A reproduction's ``results.json`` is too large to commit; ``extract`` keeps what the
docs quote (plus the wall time and peak RSS of the run when given GNU ``time -v``
output)::

    /usr/bin/time -v .venv/bin/vibrissa reproduce angle-texture --out /tmp/ch5 2> /tmp/ch5.time
    .venv/bin/python scripts/render_docs.py extract chapter5 /tmp/ch5/results.json \
        --command ".venv/bin/vibrissa reproduce angle-texture --out /tmp/ch5" \
        --time-v /tmp/ch5.time --out docs/runs/chapter5.json

(``chapter4`` for ``reproduce radial-distance``, ``identify`` for the output of
``vibrissa identify --json``, ``benchmarks`` for the folder ``benchmarks/results``,
``peers`` for ``benchmarks/results/peers.json`` of ``benchmarks/bench_peers.py``).
Rendering needs the standard library only; ``extract`` imports vibrissa.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
TEMPLATES = ROOT / "docs" / "templates"
RUNS = ROOT / "docs" / "runs"
DOCS = ROOT / "docs"
META_KEYS = ("command", "vibrissa_version", "date", "dataset")

KEY = r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z0-9_]+)+"
PLACEHOLDER = re.compile(r"\{\{\s*(?P<key>" + KEY + r")\s*(?:\|\s*(?P<spec>[^{}|]*?)\s*)?\}\}")
OPEN_OR_CLOSE = re.compile(r"\{\{|\}\}|\{#|#\}")
COMMENT = re.compile(r"\{#.*?#\}")


class RenderError(ValueError):
    """A template cannot be rendered: malformed placeholder, missing key or run file."""


def _load_run(source: str, runs_dir: Path, cache: dict[str, Any], where: str) -> Any:
    if source not in cache:
        path = runs_dir / f"{source}.json"
        if not path.is_file():
            raise RenderError(f"{where}: no run file {_rel(path)} for source {source!r}")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise RenderError(f"{where}: run file {_rel(path)} is not JSON ({exc})") from None
        meta = data.get("meta") if isinstance(data, Mapping) else None
        missing = [k for k in META_KEYS if not isinstance(meta, Mapping) or k not in meta]
        if missing:
            raise RenderError(f"{where}: run file {_rel(path)} lacks meta keys {missing}")
        cache[source] = data
    return cache[source]


def _rel(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def _lookup(data: Any, parts: list[str], key: str, where: str) -> Any:
    value = data
    for depth, part in enumerate(parts):
        if isinstance(value, Mapping) and part in value:
            value = value[part]
        elif isinstance(value, list) and part.isdigit() and int(part) < len(value):
            value = value[int(part)]
        else:
            have = ".".join([key.split(".")[0], *parts[:depth]])
            raise RenderError(f"{where}: missing key {key!r} ({have!r} has no {part!r})")
    return value


def _format(value: Any, spec: str | None, key: str, where: str) -> str:
    if isinstance(value, Mapping) or value is None:
        raise RenderError(f"{where}: key {key!r} is {type(value).__name__}, not a value")
    if isinstance(value, list):
        if spec:
            return ", ".join(_format(v, spec, key, where) for v in value)
        return ", ".join(str(v) for v in value)
    if not spec:
        return str(value)
    try:
        return format(value, spec)
    except (ValueError, TypeError) as exc:
        raise RenderError(f"{where}: bad format {spec!r} for key {key!r} ({exc})") from None


def render_text(text: str, template_name: str, runs_dir: Path = RUNS) -> tuple[str, list[str]]:
    """Substitute every placeholder of a template.

    Parameters
    ----------
    text : str
        The template's text.
    template_name : str
        Its path, for error messages.
    runs_dir : Path
        Folder of the run files.

    Returns
    -------
    rendered : str
        The text with every placeholder replaced.
    sources : list of str
        The run files used, in order of first use.

    Raises
    ------
    RenderError
        On a malformed placeholder (unbalanced ``{{``/``}}``, bad key), a missing
        run file, meta or key, or a format that does not apply to the value.
    """
    cache: dict[str, Any] = {}
    out = []
    in_code = False
    for lineno, line in enumerate(text.splitlines(keepends=True), 1):
        where = f"{template_name}:{lineno}"
        if line.lstrip().startswith("```"):
            in_code = not in_code
        if in_code or line.lstrip().startswith("```"):
            out.append(line)  # fenced code is copied verbatim
            continue
        if COMMENT.search(line):
            line = COMMENT.sub("", line)
            if not line.strip():
                continue

        def sub(m: re.Match[str], where: str = where) -> str:
            key = m.group("key")
            source, *parts = key.split(".")
            data = _load_run(source, runs_dir, cache, where)
            return _format(_lookup(data, parts, key, where), m.group("spec"), key, where)

        rendered = PLACEHOLDER.sub(sub, line)
        leftover = OPEN_OR_CLOSE.search(PLACEHOLDER.sub("", line))
        if leftover:
            bad = line.strip()
            raise RenderError(f"{where}: malformed placeholder in {bad!r}")
        out.append(rendered)
    return "".join(out), list(cache)


def header(template: Path, sources: list[str]) -> str:
    """The comment that opens a rendered doc."""
    runs = ", ".join(f"docs/runs/{s}.json" for s in sources) or "none"
    return (
        f"<!-- Generated from {_rel(template)} with the run files {runs} (their `meta` says "
        "how each was made). Do not edit this file: edit the template and run "
        "`.venv/bin/python scripts/render_docs.py`. -->\n"
    )


def render(template: Path, runs_dir: Path = RUNS) -> str:
    """The rendered doc of one template, header included."""
    body, sources = render_text(template.read_text(encoding="utf-8"), _rel(template), runs_dir)
    return header(template, sources) + body


def targets(templates_dir: Path = TEMPLATES, docs_dir: Path = DOCS) -> list[tuple[Path, Path]]:
    """(template, rendered doc) pairs, sorted by name."""
    return [(t, docs_dir / t.name) for t in sorted(templates_dir.glob("*.md"))]


def run_meta(command: str, dataset: str | os.PathLike[str] | None) -> dict[str, Any]:
    """The ``meta`` of a run file written by a measuring script.

    Parameters
    ----------
    command : str
        The command that made the run (as typed, from the worktree root).
    dataset : path or None
        The data file measured (its name carries the protocol's fingerprint), or
        ``None`` when the run simulates its own trials.

    Returns
    -------
    dict
        ``command``, ``vibrissa_version``, ``date`` (UTC, ISO 8601) and ``dataset``
        (the file's name).
    """
    import datetime
    import importlib.metadata

    return {
        "command": command,
        "vibrissa_version": importlib.metadata.version("vibrissa"),
        "date": datetime.datetime.now(datetime.UTC).replace(microsecond=0).isoformat(),
        "dataset": None if dataset is None else Path(dataset).name,
    }


def write_run(path: str | os.PathLike[str], data: Mapping[str, Any]) -> None:
    """Write a run file (sorted keys, indent 1, trailing newline) atomically."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    _write_atomic(p, json.dumps(data, indent=1, sort_keys=True) + "\n")


def parse_time_v(text: str) -> dict[str, float]:
    """Wall time (s) and peak RSS (MB) from GNU ``time -v`` output."""
    out: dict[str, float] = {}
    m = re.search(r"Elapsed \(wall clock\) time.*?: (?:(\d+):)?(\d+):(\d+(?:\.\d+)?)", text)
    if m:
        h, mi, sec = m.groups()
        out["wall_seconds"] = int(h or 0) * 3600 + int(mi) * 60 + float(sec)
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    if m:
        out["peak_rss_mb"] = int(m.group(1)) / 1024
    return out


def _stats(entry: Any) -> Any:
    if not isinstance(entry, Mapping):
        return None
    return {k: entry[k] for k in ("mean", "std") if k in entry}


def _run_figures(meta: Mapping[str, Any]) -> dict[str, Any]:
    """Trials and stage seconds from a results ``meta``: the envelope of issue 12
    (``dataset.n_trials``, ``wall_seconds``) or the older flat keys."""
    walls = meta.get("wall_seconds") if isinstance(meta.get("wall_seconds"), Mapping) else {}
    data = meta.get("dataset") if isinstance(meta.get("dataset"), Mapping) else {}
    generate = walls.get("generate", meta.get("generate_seconds"))
    if data.get("reused"):
        generate = None  # a reused dataset was not simulated by this run
    return {
        "n_trials": data.get("n_trials", meta.get("n_trials")),
        "generate_seconds": generate,
        "evaluate_seconds": walls.get("evaluate", meta.get("evaluate_seconds")),
    }


def extract_chapter4(results: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from a ``reproduce radial-distance`` results dict."""
    meta = results.get("meta", {})
    out: dict[str, Any] = {
        **_run_figures(meta),
        "classifiers": {
            name: {p: _stats(entry.get(p)) for p in ("radius_mm", "speed_mm_s")}
            | {"classify_seconds": entry.get("classify_seconds")}
            for name, entry in results.get("classifiers", {}).items()
        },
    }
    if out["n_trials"] and out["generate_seconds"]:
        out["trials_per_second"] = out["n_trials"] / out["generate_seconds"]
    return out


def extract_chapter5(results: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from a ``reproduce angle-texture`` results dict.

    Besides the kappas, it derives the comparisons the doc states in words, against
    :data:`vibrissa.evaluate.THESIS_CHAPTER5`: the range of texture kappas of the
    thesis' methods, how many of them reach the thesis' kappa on angle and speed,
    and the largest kappa of the naive Bayes classifiers with the thesis' binning.
    """
    from vibrissa.thesis.angle_texture.values import THESIS_CHAPTER5

    meta = results.get("meta", {})
    clfs = results.get("classifiers", {})
    out: dict[str, Any] = {
        **_run_figures(meta),
        "n_test": meta.get("split", {}).get("n_test"),
        "n_train": meta.get("split", {}).get("n_train"),
        "notch_hz": meta.get("notch_hz"),
        "classifiers": {
            name: {"kappa": dict(e["kappa"]), "classify_seconds": e.get("classify_seconds")}
            for name, e in clfs.items()
        },
        "sequential": dict(results.get("sequential", {})),
    }
    detail = results.get("sequential_detail", {})
    out["sequential_detail"] = {
        k: detail.get(k) for k in ("base", "threshold", "mean_contacts_used")
    }
    if isinstance(detail.get("mean_contacts_used"), Mapping):
        out["sequential_detail"]["mean_contacts_used"] = dict(detail["mean_contacts_used"])
    thesis = [n for n in THESIS_CHAPTER5 if n in clfs]
    texture = [clfs[n]["kappa"]["texture"] for n in thesis]
    derived: dict[str, Any] = {
        "thesis_methods": len(thesis),
        "thesis_methods_texture_kappa_min": min(texture),
        "thesis_methods_texture_kappa_max": max(texture),
    }
    for p in ("angle", "speed"):
        pairs = [
            (clfs[n]["kappa"][p], THESIS_CHAPTER5[n]["kappa"][p])
            for n in thesis
            if THESIS_CHAPTER5[n]["kappa"][p] is not None
        ]
        derived[f"{p}_compared"] = len(pairs)
        derived[f"{p}_at_least_thesis"] = sum(ours >= th for ours, th in pairs)
    nb = [
        n
        for n in ("naive_bayes_raw", "naive_bayes_velocity", "naive_bayes_acceleration")
        if n in clfs
    ]
    derived["naive_bayes_thesis_binning_kappa_max"] = max(
        clfs[n]["kappa"][p] for n in nb for p in ("angle", "speed", "texture")
    )
    out["derived"] = derived
    return out


def extract_identify(report: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from ``vibrissa identify --json``: counts and met / unmet names.

    ``met`` and ``not_met`` are lists of observable keys in backticks (``["none"]`` if
    empty), so that a template can print them as a sentence.
    """
    obs = report.get("observables", report)
    items = obs.items() if isinstance(obs, Mapping) else [(o.get("name"), o) for o in obs]
    met, unmet = [], []
    for name, o in items:
        (met if o.get("within") else unmet).append(f"`{name}`")
    return {
        "met": met or ["none"],
        "not_met": unmet or ["none"],
        "n_within": len(met),
        "n_observables": len(met) + len(unmet),
        **{k: v for k, v in report.items() if k in ("n_trials", "quick")},
    }


def extract_benchmarks(folder: str | os.PathLike[str]) -> dict[str, Any]:
    """Timings and memory the docs quote, from the committed ``benchmarks/results/``.

    Timings are taken from the benchmarks (run on an otherwise idle machine), not
    from the reproductions above (run while other jobs shared the two cores).
    ``sources`` names each file with the commit that last changed it.
    """
    import subprocess

    root = Path(folder)
    out: dict[str, Any] = {"sources": {}}
    for name in ("physics", "generation", "chapter5"):
        f = root / f"{name}.json"
        log = subprocess.run(
            ["git", "log", "-1", "--format=%H %aI", "--", str(f)],
            capture_output=True,
            text=True,
            check=False,
            cwd=ROOT,
        ).stdout.split()
        out["sources"][name] = {
            "file": _rel(f),
            "commit": log[0] if log else None,
            "date": log[1] if len(log) > 1 else None,
        }
    phys = json.loads((root / "physics.json").read_text(encoding="utf-8"))
    runs = {f"e{r['n_elements']}_dt{round(r['dt_s'] * 1e6)}us": r for r in phys["runs"]}
    out["physics"] = {
        "runs": {
            k: {
                "real_time_factor": r["real_time_factor"],
                "peak_follicle_moment_nm": r["peak_follicle_moment_nm"],
            }
            for k, r in runs.items()
        },
        "memory": dict(phys["memory"]),
    }
    if "standard_trial" in phys:  # issue 14: the speed-ups on and off, in one run
        keys = (
            "real_time_factor",
            "free_flight_real_time_factor",
            "whisking_in_air_real_time_factor",
            "contact_real_time_factor",
            "linear_free_flight_fraction",
        )
        out["physics"]["standard"] = {k: phys["standard_trial"][k] for k in keys}
        out["physics"]["standard_without_speedups"] = {
            k: phys["standard_trial_without_speedups"][k] for k in keys
        }
        out["physics"]["speedup"] = phys["speedup"]
        out["physics"]["linear_free_flight_percent"] = (
            100 * phys["standard_trial"]["linear_free_flight_fraction"]
        )
    ref = runs["e24_dt250us"]["peak_follicle_moment_nm"]
    out["physics"]["moment_change_percent"] = {
        "dt_halved": 100 * abs(runs["e24_dt125us"]["peak_follicle_moment_nm"] / ref - 1),
        "elements_doubled": 100 * abs(runs["e48_dt250us"]["peak_follicle_moment_nm"] / ref - 1),
    }
    gen = json.loads((root / "generation.json").read_text(encoding="utf-8"))
    out["generation"] = {
        k: gen[k]
        for k in ("n_trials", "workers", "wall_seconds", "trials_per_second", "peak_rss_parent_mb")
    }
    out["generation"]["ms_per_trial_per_worker"] = (
        1e3 * gen["wall_seconds"] * gen["workers"] / gen["n_trials"]
    )
    ch5 = json.loads((root / "chapter5.json").read_text(encoding="utf-8"))
    out["chapter5"] = {
        k: ch5[k]
        for k in (
            "n_trials",
            "n_test",
            "workers",
            "reproduction_wall_seconds",
            "generate_seconds",
            "evaluate_seconds",
            "peak_rss_parent_mb",
            "budgets",
        )
    }
    out["chapter5"]["classify_seconds"] = {
        n: c["classify_seconds"] for n, c in ch5["classifiers"].items()
    }
    return out


def extract_peers(results: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from ``benchmarks/bench_peers.py``'s JSON (MuJoCo as a peer).

    Besides the headline numbers it turns the search into a markdown table, one row per
    number of links: its largest stable step, the first-mode error against the beam
    reference and the peak-moment error against ours there, and the verdict (the
    accepted step where there is one).
    """
    keys = (
        "vibrissa_rtf",
        "mujoco_rtf",
        "ratio",
        "mujoco_links",
        "mujoco_dt_s",
        "mujoco_first_mode_error_pct",
        "reference_first_mode_hz",
        "mujoco_first_mode_hz",
        "vibrissa_first_mode_hz",
        "vibrissa_first_mode_error_pct",
        "vibrissa_peak_follicle_moment_nm",
        "mujoco_peak_follicle_moment_nm",
        "mujoco_peak_moment_error_pct",
        "damping_ratio",
        "mujoco_first_mode_damping_ratio",
        "mujoco_version",
        "vibrissa_n_elements",
        "vibrissa_dt_s",
        "repeats",
        "duration_s",
        "created_utc",
        "mujoco_planar_rtf",
        "ratio_planar",
        "mujoco_planar_peak_moment_error_pct",
    )
    out: dict[str, Any] = {k: results[k] for k in keys}
    out["mujoco_dt_us"] = results["mujoco_dt_s"] * 1e6
    out["mujoco_max_penetration_um"] = results["mujoco_max_penetration_m"] * 1e6
    out["vibrissa_dt_us"] = results["vibrissa_dt_s"] * 1e6
    for who in ("vibrissa", "mujoco"):
        out[f"{who}_peak_follicle_moment_mnm"] = results[f"{who}_peak_follicle_moment_nm"] * 1e3
        out[f"{who}_wall_ms"] = [round(1e3 * w, 1) for w in results[f"{who}_wall_seconds_all"]]
    out["mujoco_planar_wall_ms"] = [
        round(1e3 * w, 1) for w in results["mujoco_planar_wall_seconds_all"]
    ]
    out["machine"] = {k: results["machine"][k] for k in ("cpu", "cpu_count", "pinned_cpu")}
    out["machine"]["load_average_before"] = results["machine"]["load_average_before"][0]
    tol = results["criteria"]
    lines = [
        "| links | step | first mode vs reference | peak moment vs ours | verdict |",
        "|---|---|---|---|---|",
    ]
    for n in sorted({row["links"] for row in results["search"]}):
        stable = [r for r in results["search"] if r["links"] == n and r["stable"]]
        if not stable:
            lines.append(f"| {n} | none stable | | | unstable |")
            continue
        r = next((r for r in stable if r["accepted"]), stable[0])  # else the largest step
        moment = f"{r['peak_moment_error_pct']:+.2f} %"
        verdict = (
            "accepted"
            if r["accepted"]
            else "first mode outside"
            if abs(r["first_mode_error_pct"]) > tol["first_mode_tolerance_pct"]
            else "peak moment outside"
        )
        lines.append(
            f"| {n} | {r['dt_s'] * 1e6:g} us | {r['first_mode_error_pct']:+.3f} % "
            f"| {moment} | {verdict} |"
        )
    out["search_table"] = "\n".join(lines)
    return out


def _threshold_key(t: float) -> str:
    """A threshold as a key without a dot: 0.6 -> ``t0_6``, 0.999 -> ``t0_999``."""
    return "t" + f"{t:g}".replace(".", "_")


def extract_framework(results: Mapping[str, Any]) -> dict[str, Any]:
    """What ``docs/framework.md`` quotes from a ``reproduce tactile-framework`` results dict.

    The per-threshold rows are keyed by threshold (``curves.t0_99.active.accuracy``), and
    the counts of thresholds at which active beats passive are derived here.
    """
    meta = results.get("meta", {})
    curves = results["curves"]
    by_t: dict[str, Any] = {}
    for name, rows in curves.items():
        for r in rows:
            by_t.setdefault(_threshold_key(r["threshold"]), {})[name] = {
                k: r[k]
                for k in (
                    "accuracy",
                    "contacts_to_decision",
                    "seconds_to_decision",
                    "decided_fraction",
                )
            }
    comp = results["comparison"]["per_threshold"]
    proto = meta.get("protocol") or {}
    return {
        **_run_figures(meta),
        "protocol": {
            k: proto.get(k)
            for k in (
                "world",
                "calibration_world",
                "n_calibration",
                "n_episodes",
                "n_whisks",
                "step_mm",
                "margin_mm",
                "tip_zone_mm",
            )
        },
        "head": proto.get("head"),
        "calibration": results["calibration"],
        "policies": results["policies"],
        "curves": by_t,
        "thresholds": len(comp),
        "active_beats_passive": {
            "accuracy": sum(1 for r in comp if r["accuracy_active_beats_passive"]),
            "contacts": sum(1 for r in comp if r["contacts_active_beats_passive"]),
            "everywhere": results["comparison"]["active_beats_passive_everywhere"],
        },
        "maps": results["maps"],
        "transfer": results.get("transfer"),
    }


EXTRACTORS = {
    "framework": extract_framework,
    "chapter4": extract_chapter4,
    "chapter5": extract_chapter5,
    "identify": extract_identify,
    "benchmarks": extract_benchmarks,
    "peers": extract_peers,
}


def _write_atomic(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def extract_main(argv: list[str]) -> int:
    """``render_docs.py extract KIND RESULTS --command CMD --out OUT [--time-v FILE]``."""
    ap = argparse.ArgumentParser(
        prog="render_docs.py extract", description="Store a compact run file from a run's JSON."
    )
    ap.add_argument("kind", choices=sorted(EXTRACTORS))
    ap.add_argument(
        "results",
        help="the run's JSON (results.json, identify --json output; "
        "for benchmarks: the folder benchmarks/results)",
    )
    ap.add_argument("--command", required=True, help="the command that made RESULTS")
    ap.add_argument("--out", required=True, help="the run file (docs/runs/<source>.json)")
    ap.add_argument("--time-v", default=None, help="GNU time -v output of the command")
    ap.add_argument(
        "--wall-seconds",
        type=float,
        default=None,
        help="the command's wall time, s, when no --time-v output was kept",
    )
    ap.add_argument(
        "--dataset", default=None, help="the data file (default: results' meta.dataset, if any)"
    )
    args = ap.parse_args(argv)
    if args.kind == "benchmarks":
        results: dict[str, Any] = {}
        values = extract_benchmarks(args.results)
    else:
        results = json.loads(Path(args.results).read_text(encoding="utf-8"))
        values = EXTRACTORS[args.kind](results)
    if args.time_v:
        values["run"] = parse_time_v(Path(args.time_v).read_text(encoding="utf-8"))
    if args.wall_seconds is not None:
        values.setdefault("run", {})["wall_seconds"] = args.wall_seconds
    dataset = args.dataset or results.get("meta", {}).get("dataset")
    if isinstance(dataset, Mapping):  # the results envelope of issue 12
        dataset = dataset.get("path")
    meta = run_meta(args.command, dataset)
    dates = [v["date"] for v in values.get("sources", {}).values() if v.get("date")]
    if dates:  # measured when the sources were committed, not when extracted
        meta["date"] = max(dates)
    elif "created_utc" in values:  # measured when the results were made
        meta["date"] = values["created_utc"]
    write_run(args.out, {"meta": meta, **values})
    print(f"wrote {args.out}")
    return 0


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["extract"]:
        return extract_main(argv[1:])
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--check",
        action="store_true",
        help="write nothing; exit 1 listing the docs that differ from their render",
    )
    args = ap.parse_args(argv)
    try:
        rendered = [(doc, render(t, RUNS)) for t, doc in targets(TEMPLATES, DOCS)]
    except RenderError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.check:
        stale = [
            doc
            for doc, text in rendered
            if not doc.is_file() or doc.read_text(encoding="utf-8") != text
        ]
        for doc in stale:
            print(f"{_rel(doc)} differs from its render (hand edit, or template/run not rendered)")
        if stale:
            print("run: .venv/bin/python scripts/render_docs.py")
            return 1
        return 0
    for doc, text in rendered:
        if not doc.is_file() or doc.read_text(encoding="utf-8") != text:
            _write_atomic(doc, text)
            print(f"wrote {_rel(doc)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
