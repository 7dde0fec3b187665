"""Chapter 6.4: texture and distance on the BIOTACT G1 head, with and without RCP.

The G1 head whisks two rows of three whiskers at 2 Hz into a vertical surface (smooth
plastic, P600 or P180 silicon-carbide paper) 5, 10 or 15 mm ahead of it, unmodulated
or with rapid cessation of protraction (RCP7, RCP9), twelve whisks per class
(:mod:`vibrissa.thesis.biotact_g1.protocol`). Hit rate against 1-8 training whisks for
stationary naive Bayes and class-mean templates, on the 9-class problem and on
texture or distance alone (:mod:`vibrissa.thesis.biotact_g1.evaluation`), beside figures 6.6
and 6.7.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.reproduce.registry import Evaluation, Experiment, Option, register
from vibrissa.thesis.biotact_g1.values import CLASSIFIER_TITLES


def default_n_seeds(quick: bool) -> int:
    """Sessions of a run without ``--n-seeds``: 5, or 1 for ``--quick``."""
    return 1 if quick else 5


@register
class BiotactG1(Experiment):
    """Thesis 6.4 (see the module docstring)."""

    name = "biotact-g1"
    chapter = 6
    title = "Chapter 6.4 reproduction: texture and distance on the BIOTACT G1 with RCP"
    description = (
        "BIOTACT G1 head (2 x 3 whiskers) whisking into 3 textures at 3 distances, "
        "unmodulated, RCP7 and RCP9: naive Bayes and template hit rates against "
        "training whisks (figures 6.6, 6.7)"
    )
    options = (
        Option(
            "distances",
            "",
            "Horizontal distances of the surface from the head's front, "
            "mm, comma-separated (default 5,10,15; --quick 5,15).",
            minimum=2,
            numbers=True,
        ),
        Option("whisk_frequency", "", "Whisk frequency, Hz (default 2).", numbers=True),
        Option(
            "n_seeds",
            0,
            "Sessions, with seeds seed..seed+n-1; every figure is the mean over them "
            "with its spread (default 0: 5 for the full run, 1 for --quick).",
            minimum=0,
        ),
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """The G1 sessions of :func:`~vibrissa.thesis.biotact_g1.protocol.biotact_protocol`.

        5 sessions (``quick``: 1), seeds ``seed ..``.
        """
        from vibrissa.thesis.biotact_g1.protocol import biotact_protocol

        return biotact_protocol(quick=quick, seed=seed, n_seeds=default_n_seeds(quick))

    def protocol_for(
        self, quick: bool, seed: int, options: Mapping[str, Any]
    ) -> SimulationProtocol:
        """The G1 session with ``--distances`` and ``--whisk-frequency`` checked and applied."""
        from vibrissa.robots.biotact import G1Head
        from vibrissa.thesis.biotact_g1.protocol import biotact_protocol

        freq = tuple(options.get("whisk_frequency") or ())
        if len(freq) > 1:
            raise ValueError(f"--whisk-frequency takes one number, got {len(freq)}")
        if freq and freq[0] <= 0:
            raise ValueError(f"--whisk-frequency must be > 0 Hz, got {freq[0]:g}")
        dists = tuple(options.get("distances") or ())
        for d in dists:
            G1Head().check_distance(d, "--distances")
        try:
            return biotact_protocol(
                quick=quick,
                seed=seed,
                distances_mm=dists or None,
                whisk_frequency_hz=freq[0] if freq else None,
                n_seeds=int(options.get("n_seeds") or 0) or default_n_seeds(quick),
            )
        except ValueError as exc:
            raise ValueError(
                str(exc)
                .replace("whisk_frequency_hz", "--whisk-frequency")
                .replace("distances_mm", "--distances")
            ) from None

    def n_trials(self, quick: bool) -> int:
        """Whisks of the G1 session (full or quick)."""
        return int(self.protocol(quick, 0).n_trials)

    def evaluate(
        self,
        ds: xr.Dataset,
        *,
        seed: int,
        progress: Callable | None,
        options: Mapping[str, Any],
        workers: int | None = None,
    ) -> Evaluation:
        """Evaluate the G1 session ``ds``: hit rates, whisk statistics, the thesis' claims."""
        from vibrissa.thesis.biotact_g1.evaluation import evaluate_g1_sessions

        return Evaluation(evaluate_g1_sessions(ds, progress=progress))

    def write_outputs(
        self,
        results: Mapping[str, Any],
        out_dir: Path,
        *,
        dataset: xr.Dataset | None,
        figures: bool,
        workers: int | None = None,
        artifacts: Mapping[str, Any] | None = None,
    ) -> dict[str, Path]:
        """Draw the hit-rate figures (6.6, 6.7) and, with ``dataset``, whisk trajectories."""
        from vibrissa.evaluate.figures.common import save_figure
        from vibrissa.thesis.biotact_g1.figures import hit_rate_figure

        if not figures:
            return {}
        fig_dir = Path(out_dir) / "figures"
        hit = results["hit_rate"]
        out = {}
        sp = (results.get("spread") or {}).get("hit_rate") or {}
        for c, title in CLASSIFIER_TITLES.items():
            fig = hit_rate_figure(
                {s: v[c] for s, v in hit.items()},
                title,
                {s: (sp.get(s) or {}).get(c) for s in hit},
            )
            out[f"hit_rate_{c}"] = save_figure(fig, fig_dir / f"hit_rate_{c}.png")
        if dataset is not None:
            out.update(_trajectory_figures(dataset, fig_dir))
        return out

    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """The G1 report's Markdown body; ``baseline`` is not used."""
        from vibrissa.thesis.biotact_g1.report import markdown_g1

        return markdown_g1(results, figures)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """Hit rates, validation whisks, naive Bayes' robust range, whisk statistics, checks."""
        return {
            "hit_rate": results["hit_rate"],
            "n_validation": results["n_validation"],
            "naive_bayes_robust_range": results.get("naive_bayes_robust_range"),
            "whisks": results["whisks"],
            "checks": results["checks"],
        }


def _trajectory_figures(ds: xr.Dataset, fig_dir: Path) -> dict[str, Path]:
    """Whisk trajectories with contacts.

    One whisk per strategy (middle class), and the unmodulated whisks at every distance
    (middle texture).
    """
    from vibrissa.evaluate.figures.common import save_figure
    from vibrissa.evaluate.figures.whisking import whisk_trajectories_figure

    strat = np.asarray(ds["strategy"].values).astype(str)
    tex = np.asarray(ds["texture"].values).astype(str)
    dist = np.asarray(ds["distance_mm"].values, dtype=float)
    whisk = np.asarray(ds["whisk"].values)
    textures = list(dict.fromkeys(tex.tolist()))
    dists = sorted(set(dist.tolist()))
    t_mid, d_mid = textures[len(textures) // 2], dists[len(dists) // 2]
    chans = [str(c) for c in ds["channel"].values]
    wid = [str(w) for w in ds["whisker_id"].values]
    xi, fi = chans.index("L3x"), wid.index("L3")
    out: dict[str, Path] = {}

    def draw(cases: list[tuple[str, float]], name: str) -> None:
        """First whisk of each (strategy, distance) at the middle texture."""
        picks, titles = [], []
        for s, d in cases:
            m = np.flatnonzero((strat == s) & (tex == t_mid) & (dist == d) & (whisk == 1))
            if m.size:
                picks.append(int(m[0]))
                titles.append(f"{s}: {t_mid}, {d:g} mm")
        if not picks:
            return
        fig = whisk_trajectories_figure(
            ds["time"].values,
            ds["angle_deg"].values[picks, 0],
            ds["signal"].values[picks, xi],
            ds["force_n"].values[picks, fi],
            titles,
            gating=ds["gating"].values[picks, 0],
            signal_label="Hall x, L3 (V)",
        )
        out[name] = save_figure(fig, fig_dir / f"{name}.png")

    draw([(s, d_mid) for s in dict.fromkeys(strat.tolist())], "trajectories")
    draw([(strat[0], d) for d in dists], "distances")
    return out
