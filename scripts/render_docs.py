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


def sig4(value: Any) -> Any:
    """``value`` with every float rounded to 4 significant digits (dicts and lists too).

    Integers, strings, booleans and ``None`` are kept; a non-finite float becomes ``None``.
    """
    if isinstance(value, Mapping):
        return {str(k): sig4(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [sig4(v) for v in value]
    if isinstance(value, bool) or not isinstance(value, float):
        return value
    if value != value or value in (float("inf"), float("-inf")):
        return None
    return float(f"{value:.4g}")


def _int_matrix(matrix: Any) -> Any:
    return None if matrix is None else [[int(round(x)) for x in row] for row in matrix]


def _error_histogram(pred: list[Any] | None, true: list[Any]) -> dict[str, list[Any]] | None:
    """Counts of each signed error ``predicted - true`` (4 significant digits)."""
    if pred is None:
        return None
    counts: dict[float, int] = {}
    for p, t in zip(pred, true, strict=True):
        if p is None or t is None:
            continue
        e = sig4(float(p) - float(t))
        counts[e] = counts.get(e, 0) + 1
    keys = sorted(counts)
    return {"error": keys, "count": [counts[k] for k in keys]}


_SCORE_KEYS = ("mean", "std", "sem", "mean_abs", "rmse", "exact_hit", "n", "kappa")


def _scores(entry: Any) -> Any:
    if not isinstance(entry, Mapping):
        return None
    return sig4({k: entry[k] for k in (*_SCORE_KEYS, "mean_sd_over_seeds") if k in entry})


def _chapter4_tables(results: Mapping[str, Any]) -> dict[str, Any]:
    """Tables 4.1-4.7 and the figures' data (error histograms, errors by speed).

    ``tables.training_curves[name][fraction]`` holds tables 4.2-4.5 and figures 4.4-4.10
    (``"1"`` is the full training set); ``derived`` the comparisons the ledger of
    thesis claims reads (``scripts/thesis_claims.py``).
    """
    clfs = results.get("classifiers", {})
    fractions = results.get("training_fractions", {}) or {}
    curves: dict[str, Any] = {}
    for name, entry in clfs.items():
        rows = {"1": entry} | {
            f: fractions[f][name] for f in fractions if isinstance(fractions[f].get(name), Mapping)
        }
        curves[name] = {
            frac: {
                "radius_mm": _scores(r.get("radius_mm")),
                "speed_mm_s": _scores(r.get("speed_mm_s")),
                "joint": sig4(r.get("joint")),
                "n_train": r.get("n_train"),
                "fit_seconds": sig4(r.get("fit_seconds")),
                "classify_seconds": sig4(r.get("classify_seconds")),
            }
            for frac, r in rows.items()
        }
    preds = results.get("predictions", {}) or {}
    truth = {"radius_mm": preds.get("radius_mm_true"), "speed_mm_s": preds.get("speed_mm_s_true")}
    histograms = {
        name: {
            p: _error_histogram(pc.get(p), truth[p]) if truth[p] is not None else None
            for p in ("radius_mm", "speed_mm_s")
        }
        for name, pc in (preds.get("classifiers", {}) or {}).items()
    }
    tables: dict[str, Any] = {
        "table_4_1": {
            kind: sig4(clfs.get(f"static_beam_{kind}", {}).get("fitted_parameters"))
            for kind in ("measured", "fitted")
        },
        "table_4_6": {
            name: sig4({k: e.get(k) for k in ("classify_seconds", "fit_seconds", "n_test")})
            for name, e in clfs.items()
        },
        "table_4_7": {
            name: {p: _scores(e.get(p)) for p in ("radius_mm", "speed_mm_s")}
            | {"joint": sig4(e.get("joint"))}
            for name, e in clfs.items()
        },
        "training_curves": curves,
        "radius_error_by_speed": {
            name: sig4(e["radius_error_by_speed"])
            for name, e in clfs.items()
            if e.get("radius_error_by_speed")
        },
        "error_histograms": histograms,
    }
    if isinstance(results.get("other_split"), Mapping):
        other = results["other_split"]
        tables["other_split"] = {
            "description": other.get("description"),
            "classifiers": {
                name: {p: _scores(e.get(p)) for p in ("radius_mm", "speed_mm_s")}
                for name, e in (other.get("classifiers") or {}).items()
            },
        }
    if isinstance(results.get("oracle_angle"), Mapping):
        oracle = results["oracle_angle"]
        tables["oracle_angle"] = {
            "label": oracle.get("label"),
            "classifiers": {
                name: {
                    "radius_mm": _scores(e.get("radius_mm")),
                    "abs_error_mm": sig4(e.get("abs_error_mm")),
                }
                for name, e in (oracle.get("classifiers") or {}).items()
            },
        }
    derived: dict[str, Any] = {}
    for name in ("static_beam_measured", "static_beam_fitted"):
        rows = tables["radius_error_by_speed"].get(name)
        if not rows:
            continue
        speeds = sorted(r["speed_mm_s"] for r in rows)
        median = speeds[(len(speeds) - 1) // 2]
        by = {r["speed_mm_s"]: r for r in rows}
        derived[name] = {
            "median_speed_mm_s": median,
            "std_at_median_speed": by[median]["std"],
            "mean_at_median_speed": by[median]["mean"],
            "std_at_extreme_speed": max(by[speeds[0]]["std"], by[speeds[-1]]["std"]),
        }
    ratios = {}
    fitted = {f for c in curves.values() for f in c if f != "1"}  # None entries left out
    smallest = min(fitted, key=float) if fitted else None  # the thesis' 5 %
    for name in ("frequency", "template", "feature", "naive_bayes_velocity"):
        full = curves.get(name, {}).get("1", {}).get("radius_mm")
        low = curves.get(name, {}).get(str(smallest), {}).get("radius_mm")
        if full and low and full.get("std"):
            ratios[name] = sig4(low["std"] / full["std"])
    reduced: dict[str, Any] = {"smallest_fraction": smallest, "radius_std_ratio_smallest": ratios}
    if ratios:
        reduced["worst_radius_std_ratio_smallest"] = max(ratios.values())
    feat = {
        f: r["radius_mm"]["std"] for f, r in curves.get("feature", {}).items() if r["radius_mm"]
    }
    if feat:
        reduced["feature_best_radius_fraction"] = float(min(feat, key=lambda f: (feat[f], f)))
    derived["reduced_training"] = reduced
    return {"tables": tables, "derived": derived}


def extract_chapter4(results: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from a ``reproduce radial-distance`` results dict.

    Besides the keys the templates use (``classifiers``, times), every table and figure
    of chapter 4 the reproduction computes, floats to 4 significant digits: ``tables``
    (:func:`_chapter4_tables`: 4.1, 4.2-4.5 as ``training_curves``, 4.6, 4.7, the static
    beam's errors by speed, error histograms) and ``derived``.
    """
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
    return out | _chapter4_tables(results)


def _kappa(matrix: list[list[int]]) -> float | None:
    """Cohen's kappa of a confusion matrix (``None`` when undefined)."""
    n = sum(sum(row) for row in matrix)
    if n == 0:
        return None
    k = len(matrix)
    po = sum(matrix[i][i] for i in range(k)) / n
    pe = sum(sum(matrix[i]) * sum(row[i] for row in matrix) for i in range(k)) / n**2
    return None if pe >= 1 else sig4((po - pe) / (1 - pe))


def _texture_groups(conf: Mapping[str, Any], smooth_code: float) -> dict[str, Any] | None:
    """Kappa of smooth vs rough (the 4 x 4 texture matrix collapsed to 2 x 2) and among
    the sandpapers (the 3 x 3 block of sandpaper rows and columns)."""
    if not isinstance(conf, Mapping) or conf.get("matrix") is None:
        return None
    labels, m = list(conf["labels"]), conf["matrix"]
    if smooth_code not in labels or len(labels) < 3:
        return None
    s = labels.index(smooth_code)
    rough = [i for i in range(len(labels)) if i != s]
    two = [
        [m[s][s], sum(m[s][j] for j in rough)],
        [sum(m[i][s] for i in rough), sum(m[i][j] for i in rough for j in rough)],
    ]
    block = [[m[i][j] for j in rough] for i in rough]
    return {"smooth_vs_rough_kappa": _kappa(two), "among_sandpapers_kappa": _kappa(block)}


_FIGURE_5_15 = ("template_lowpass", "frequency", "feature", "naive_bayes_velocity")


def _chapter5_tables(results: Mapping[str, Any]) -> dict[str, Any]:
    """Tables 5.1-5.11, the confusion matrices (figures 5.3-5.14, 5.17) and figure 5.15.

    ``tables.classifiers[name]``: signed errors (mean, std, ...) per parameter, weighted
    kappas, the joint score, fit time; ``tables.confusion[name][parameter]``: labels and
    integer matrix (rows: true class); ``tables.figure_5_15[parameter]``: the four
    methods of figure 5.15 ranked by kappa, best first; ``derived.texture_groups``.
    """
    clfs = results.get("classifiers", {})
    tables: dict[str, Any] = {"classifiers": {}, "confusion": {}}
    groups: dict[str, Any] = {}
    codes = (results.get("meta", {}) or {}).get("texture_codes") or {"aluminium": 0}
    smooth = float(codes.get("aluminium", 0))
    for name, e in clfs.items():
        tables["classifiers"][name] = sig4(
            {
                "errors": {
                    unit: {k: v for k, v in (err or {}).items() if k in _SCORE_KEYS}
                    for unit, err in (e.get("errors") or {}).items()
                },
                "weighted_kappa": e.get("weighted_kappa"),
                "joint": e.get("joint"),
                **{
                    k: e.get(k)
                    for k in ("fit_seconds", "texture_alone_seconds", "n_train", "n_test")
                },
            }
        )
        conf = e.get("confusion") or {}
        tables["confusion"][name] = {
            p: None
            if c is None
            else {"labels": sig4(list(c["labels"])), "matrix": _int_matrix(c["matrix"])}
            for p, c in conf.items()
        }
        g = _texture_groups(conf.get("texture"), smooth)
        if g is not None:
            groups[name] = g
    fig: dict[str, Any] = {}
    for p in ("angle", "speed", "texture"):
        have = [n for n in _FIGURE_5_15 if (clfs.get(n) or {}).get("kappa", {}).get(p) is not None]
        fig[p] = sorted(have, key=lambda n: -clfs[n]["kappa"][p])
    tables["figure_5_15"] = fig
    return {"tables": tables, "derived": {"texture_groups": groups}}


def extract_chapter5(results: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from a ``reproduce angle-texture`` results dict.

    Besides the kappas, it derives the comparisons the doc states in words, against
    :data:`vibrissa.evaluate.THESIS_CHAPTER5`: the range of texture kappas of the
    thesis' methods, how many of them reach the thesis' kappa on angle and speed,
    and the largest kappa of the naive Bayes classifiers with the thesis' binning.
    ``tables`` keeps tables 5.1-5.11, the confusion matrices and figure 5.15
    (:func:`_chapter5_tables`), floats to 4 significant digits.
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
    more = _chapter5_tables(results)
    out["tables"] = more["tables"]
    out["derived"] = derived | more["derived"]
    return out


def extract_identify(report: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from ``vibrissa identify --json``: counts and met / unmet names.

    ``met`` and ``not_met`` are lists of observable keys in backticks (``["none"]`` if
    empty), so that a template can print them as a sentence. ``observables[key]`` keeps
    every observable whole: the thesis' statement and value, ours (``value``), the
    tolerance, the verdict (``within``) and the measurements behind it (``detail``),
    floats to 4 significant digits.
    """
    obs = report.get("observables", report)
    items = obs.items() if isinstance(obs, Mapping) else [(o.get("name"), o) for o in obs]
    met, unmet = [], []
    for name, o in items:
        (met if o.get("within") else unmet).append(f"`{name}`")
    kept = ("key", "description", "thesis", "thesis_value", "value", "unit", "tolerance")
    return {
        "met": met or ["none"],
        "not_met": unmet or ["none"],
        "n_within": len(met),
        "n_observables": len(met) + len(unmet),
        **{k: v for k, v in report.items() if k in ("n_trials", "quick")},
        "observables": {
            str(name): sig4({k: o.get(k) for k in kept if k in o})
            | {"within": bool(o.get("within")), "detail": sig4(o.get("detail") or {})}
            for name, o in items
        },
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
    for name in (
        "physics",
        "generation",
        "chapter5",
        "rod_convergence",
        "thesis",
        "consistent_mass_energy",
        "closed_loops_profile_stepper",
        "closed_loops_profile",
    ):
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
    out["rod_convergence"] = extract_rod_convergence(
        json.loads((root / "rod_convergence.json").read_text(encoding="utf-8"))
    )
    out["closed_loops"] = extract_closed_loops(root)
    energy = root / "consistent_mass_energy.json"
    if energy.is_file():
        out["consistent_mass_energy"] = extract_consistent_mass_energy(
            json.loads(energy.read_text(encoding="utf-8"))
        )
    thesis = root / "thesis.json"
    if thesis.is_file():
        out["thesis"] = extract_thesis(json.loads(thesis.read_text(encoding="utf-8")))
    for key, name in (
        ("kernel_profile", "kernel_profile"),
        ("kernel_profile_before", "kernel_profile_before_plane_culling"),
    ):
        kernels = root / f"{name}.json"
        if kernels.is_file():
            out[key] = extract_kernel_profile(json.loads(kernels.read_text(encoding="utf-8")))
    return out


#: Shared objects whose samples are memory management: ``malloc``/``free`` (libc) and
#: numba's reference counting (``NRT_incref``/``NRT_decref`` are compiled with the kernels).
_ALLOCATION = ("so:libc.so.6", "so:_nrt_python", "NRT_incref", "NRT_decref")


def extract_kernel_profile(d: Mapping[str, Any], top: int = 10) -> dict[str, Any]:
    """``benchmarks/profile_kernels.py``'s shares: a table of the busiest functions.

    One row per compiled function among the ``top`` busiest of any case (percent of the
    case's samples), then memory management (``malloc``/``free`` and numba's reference
    counting) and everything else, one column per case; with the CPU and the date.
    """
    cases = d["cases"]
    names: list[str] = []
    for c in cases.values():
        for k in c["share"]:
            if not k.startswith("so:") and k not in _ALLOCATION and k not in names:
                names.append(k)
    names.sort(key=lambda k: -max(c["share"].get(k, 0.0) for c in cases.values()))
    names = names[:top]
    head = " | ".join(f"{k} (%)" for k in cases)
    rows = [f"| function | {head} |", "|---" * (len(cases) + 1) + "|"]

    def pct(values: list[float | None]) -> str:
        return " | ".join("-" if v is None else f"{100 * v:.1f}" for v in values)

    for k in names:
        rows.append(f"| `{k}` | " + pct([c["share"].get(k) for c in cases.values()]) + " |")
    alloc = [
        sum(v for k, v in c["share"].items() if k.startswith(_ALLOCATION)) for c in cases.values()
    ]
    rest = [
        1.0 - sum(c["share"].get(k, 0.0) for k in names) - a
        for c, a in zip(cases.values(), alloc, strict=True)
    ]
    rows.append(
        "| memory management (`malloc`/`free`, numba's reference counting) | " + pct(alloc) + " |"
    )
    rows.append("| everything else | " + pct(rest) + " |")
    return {
        "table": "\n".join(rows),
        "cpu": d["machine"]["cpu"],
        "created_utc": d["meta"]["created_utc"],
        "samples": {k.replace("-", "_"): c["samples"] for k, c in cases.items()},
        "share_pct": {
            k.replace("-", "_"): {f: 100 * v for f, v in c["share"].items()}
            for k, c in cases.items()
        },
    }


def extract_consistent_mass_energy(run: Mapping[str, Any]) -> dict[str, Any]:
    """``benchmarks/consistent_mass_energy.py``'s rows by case and element count.

    ``{case: {"e<n>": {first_step_pct, max_pct, last_pct}}}`` with the cases' spaces
    made underscores (``lumped_energy``), plus the scheme's ``settings``.
    """
    out: dict[str, Any] = {"settings": dict(run["settings"])}
    for r in run["rows"]:
        case = out.setdefault(r["case"].replace(" ", "_"), {})
        case[f"e{r['n_elements']}"] = {k: r[k] for k in ("first_step_pct", "max_pct", "last_pct")}
    return out


def extract_closed_loops(root: Path) -> dict[str, Any]:
    """The whisking loops' profiles before the stepper, with it, and compiled (issue 32).

    ``closed_loops_profile_before_stepper.json``, ``closed_loops_profile_stepper.json``
    and ``closed_loops_profile.json`` of ``benchmarks/profile_closed_loops.py``: per loop,
    the profiled wall time, the seconds in the solver and in the per-call set-up, when
    it was profiled and on which CPU (where the file records it).
    """
    out: dict[str, Any] = {}
    for when, name in (
        ("before", "closed_loops_profile_before_stepper"),
        ("stepper", "closed_loops_profile_stepper"),
        ("after", "closed_loops_profile"),
    ):
        d = json.loads((root / f"{name}.json").read_text(encoding="utf-8"))
        for loop, v in d["loops"].items():
            cat = v["own_seconds_by_category"]
            out.setdefault(loop.replace("-", "_"), {})[when] = {
                "wall_seconds": v["wall_seconds"],
                "solver_seconds": cat.get("solver", 0.0),
                "step_setup_seconds": cat.get("step_setup", 0.0),
                "created_utc": d["meta"]["created_utc"],
                "cpu": d.get("machine", {}).get("cpu", "not recorded"),
            }
    return out


def extract_thesis(d: Mapping[str, Any]) -> dict[str, Any]:
    """``benchmarks/bench_thesis.py``'s run: each full reproduction's time and the total."""
    rows = [
        "| reproduction | trials | wall (s) | simulation (s) | evaluation (s) | load at start |",
        "|---|---|---|---|---|---|",
    ]
    for name, r in d["runs"].items():
        st = r.get("stages_seconds") or {}
        rows.append(
            f"| `{name}` | {r.get('n_trials')} | {r['wall_seconds']:.0f} | "
            f"{st.get('generate', float('nan')):.0f} | {st.get('evaluate', float('nan')):.0f} | "
            f"{r.get('load_average_at_start', float('nan')):.2f} |"
        )
    return {
        "table": "\n".join(rows),
        "total_seconds": d["total_seconds"],
        "total_minutes": d["total_seconds"] / 60.0,
        "budget_seconds": d["budget_seconds"],
        "budget_minutes": d["budget_seconds"] / 60.0,
        "within_budget": d["within_budget"],
        "complete": d["complete"],
        "workers": d["workers"],
        "cores": d["machine"]["cores"],
        "cpu": d["machine"]["cpu"],
        "created_utc": d["meta"]["created_utc"],
    }


def extract_rod_convergence(rc: Mapping[str, Any]) -> dict[str, Any]:
    """``benchmarks/rod_convergence.py``'s result: a table of the options and the default.

    One row per discretisation option at the fewest elements whose first mode is within
    the tolerance: its mode errors, static tip error, peak follicle moment error (where
    the dynamics ran) and the fewest elements within both tolerances.
    """
    rows = rc["rows"]

    def row(mass: str, stiffness: str, grading: str, n: int) -> Mapping[str, Any]:
        key = (mass, stiffness, grading, n)
        return next(
            r for r in rows if (r["mass"], r["stiffness"], r["grading"], r["n_elements"]) == key
        )

    lines = [
        "| mass | stiffness | elements | mode 1 | mode 2 | mode 3 | static tip | peak moment "
        "| elements within both |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for best in rc["fewest_elements_within_tolerance"]:
        n = best["fewest_elements"]
        label = f"| {best['mass']} | {best['stiffness']}" + (
            "" if best["grading"] == "uniform" else f", {best['grading']}-graded"
        )
        if n is None:
            lines.append(f"{label} | none tried | | | | | | |")
            continue
        r = row(best["mass"], best["stiffness"], best["grading"], n)
        m = r["mode_error_pct"]
        p = r.get("peak_moment_error_pct")
        lines.append(
            f"{label} | {n} | {m[0]:+.3f} % | {m[1]:+.3f} % | {m[2]:+.3f} % "
            f"| {r['tip_deflection_error_pct']:+.3f} % | "
            + ("not run" if p is None else f"{p:+.2f} %")
            + f" | {best['fewest_elements_both']} |"
        )
    default_mass = rc.get("default_mass", "lumped")
    default = row(default_mass, "node", "uniform", rc["default_n_elements"])
    load_points = rc.get("load_points")
    lp_table = ""
    if load_points:
        lp_table = "\n".join(
            [
                "| elements | " + " | ".join(f"{a:g} mm" for a in load_points["at_mm"]) + " |",
                "|---|" + "---|" * len(load_points["at_mm"]),
            ]
            + [
                f"| {r['n_elements']} | "
                + " | ".join(f"{e:+.2f} %" for e in r["deflection_error_pct"])
                + " |"
                for r in load_points["rows"]
            ]
        )
    return {
        "table": "\n".join(lines),
        "load_points_table": lp_table,
        "default_mass": default_mass,
        "default_n_elements": rc["default_n_elements"],
        "default_first_mode_error_pct": default["mode_error_pct"][0],
        "default_peak_moment_error_pct": default.get("peak_moment_error_pct"),
        "first_mode_tolerance_pct": rc["first_mode_tolerance_pct"],
        "moment_tolerance_pct": rc.get("moment_tolerance_pct"),
        "peak_reference_n_elements": rc["peak_reference"]["n_elements"],
        "peak_reference_dt_us": rc["peak_reference"]["dt_s"] * 1e6,
    }


def extract_peers(results: Mapping[str, Any]) -> dict[str, Any]:
    """What the docs quote from ``benchmarks/bench_peers.py``'s JSON (MuJoCo as a peer).

    Besides the headline numbers it turns the search into a markdown table, one row per
    number of links: its largest stable step, the first-mode error against the beam
    reference and the peak-moment error against the converged rod there, and the verdict
    (the accepted step where there is one); and our rod's search, one row per element
    count, as ``vibrissa_search_table``.
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
        "vibrissa_peak_moment_error_pct",
        "vibrissa_default_n_elements",
        "vibrissa_default_first_mode_error_pct",
        "vibrissa_default_peak_moment_error_pct",
    )
    out: dict[str, Any] = {k: results[k] for k in keys}
    out["reference_peak_follicle_moment_mnm"] = results["reference_peak_follicle_moment_nm"] * 1e3
    out["peak_reference_n_elements"] = results["peak_reference"]["n_elements"]
    out["peak_reference_dt_us"] = results["peak_reference"]["dt_s"] * 1e6
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
    tol_f = tol["first_mode_tolerance_pct"]
    ours = [
        "| elements | first mode vs reference | peak moment vs reference | verdict |",
        "|---|---|---|---|",
    ]
    for r in results["vibrissa_search"]:
        moment = (
            "not run"
            if r["peak_moment_error_pct"] is None
            else f"{r['peak_moment_error_pct']:+.2f} %"
        )
        verdict = (
            "accepted"
            if r["accepted"]
            else "first mode outside"
            if abs(r["first_mode_error_pct"]) > tol_f
            else "peak moment outside"
        )
        ours.append(
            f"| {r['n_elements']} | {r['first_mode_error_pct']:+.3f} % | {moment} | {verdict} |"
        )
    out["vibrissa_search_table"] = "\n".join(ours)
    lines = [
        "| links | step | first mode vs reference | peak moment vs reference | verdict |",
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
                    "accuracy_with_deadline",
                    "contacts_with_deadline",
                    "seconds_with_deadline",
                    "no_evidence_fraction",
                )
                if k in r
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
            "accuracy_decided_only": sum(
                1 for r in comp if r.get("accuracy_active_beats_passive_decided_only")
            ),
            "contacts_decided_only": sum(
                1 for r in comp if r.get("contacts_active_beats_passive_decided_only")
            ),
            "everywhere_decided_only": results["comparison"].get(
                "active_beats_passive_everywhere_decided_only"
            ),
        },
        "paired": {
            _threshold_key(r["threshold"]): {
                "accuracy_gain": r["accuracy_gain_over_passive"],
                "contacts_saved": r["contacts_saved_over_passive"],
            }
            for r in comp
            if "accuracy_gain_over_passive" in r
        },
        "gap_to_oracle": {
            _threshold_key(r["threshold"]): {
                "accuracy": r["accuracy_gap_to_oracle"],
                "contacts": r["contacts_gap_to_oracle"],
            }
            for r in comp
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
