"""A pipeline fitted on recorded datasets: chapter-4 contacts for "where", chapter-5 for "what".

A Dataset of single contacts (one trial each, as the XY robot records them, or imported from a
lab's own recordings) calibrates the pipeline: each trial is played through the same
:class:`~vibrissa.framework.ContactDetector` the live pipeline uses, so the training windows
are cut exactly as live ones will be; the trial's labels become the classes. The where model
learns ``[radial_distance_mm, speed_mm_s]`` rows (a radial distance within ``tip_zone_mm`` of
the whisker's length counts as a tip contact), the what model ``[angle_deg, speed_mm_s,
texture_code]`` rows (speed is marginalised away by the pipeline). Trials in which the
detector finds no contact are left out and counted.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from vibrissa._validate import positive
from vibrissa.data.dataset import as_arrays
from vibrissa.framework.detect import DetectorSettings, contact_windows
from vibrissa.framework.models import (
    default_what_estimator,
    default_where_estimator,
    fit_what,
    fit_where,
)
from vibrissa.framework.pipeline import TactilePipeline

__all__ = ["TrialWindows", "check_datasets", "fit_pipeline_from_datasets", "trial_windows"]

#: Labels of the two kinds of dataset (the XY-robot protocols' label names).
WHERE_LABELS = ("radial_distance_mm", "speed_mm_s")
WHAT_LABELS = ("angle_deg", "speed_mm_s", "texture")


@dataclass(frozen=True)
class TrialWindows:
    """The detector's window of each trial that holds a contact, with the trial's labels."""

    windows: np.ndarray
    labels: np.ndarray
    trials: np.ndarray
    n_missed: int
    sample_rate_hz: float


def trial_windows(
    ds: xr.Dataset, labels: tuple[str, ...], detector: DetectorSettings | None = None
) -> TrialWindows:
    """Each trial of ``ds`` through the detector: its first contact's window and its labels.

    Parameters
    ----------
    ds : xarray.Dataset
        A dataset of the schema (``signal`` (trial, channel, time), ``sample_rate_hz``).
    labels : tuple of str
        Per-trial labels forming the label rows (``texture`` is encoded as its code).
    detector : DetectorSettings, optional
        The live pipeline's detector settings (default ``DetectorSettings()``).

    Returns
    -------
    TrialWindows
    """
    settings = detector if detector is not None else DetectorSettings()
    fs = positive("sample_rate_hz", float(ds.attrs["sample_rate_hz"]))
    X, y = as_arrays(ds, list(labels), encode_textures="texture" in labels)
    windows, rows, kept = [], [], []
    for i in range(X.shape[0]):
        found = contact_windows(X[i].T[:, None, :], fs, settings)
        if not found:
            continue
        windows.append(found[0].window)
        rows.append(np.asarray(y[i], dtype=float))
        kept.append(i)
    if not windows:
        raise ValueError("no trial of the dataset holds a contact the detector finds")
    return TrialWindows(
        np.stack(windows), np.stack(rows), np.asarray(kept), X.shape[0] - len(kept), fs
    )


def check_datasets(where: xr.Dataset | None, what: xr.Dataset | None) -> None:
    """Refuse, before any work, datasets the pipeline cannot be fitted on (one line each).

    At least one; the same channel count; each with a ``sample_rate_hz``, the labels its
    role needs and (where) the ``whisker`` attribute with its ``length_mm``.
    """
    if where is None and what is None:
        raise ValueError("give a where dataset, a what dataset or both")
    channels = {int(d.sizes["channel"]) for d in (where, what) if d is not None}
    if len(channels) != 1:
        raise ValueError(f"the datasets' channel counts differ: {sorted(channels)}")
    for role, d, labels in (("where", where, WHERE_LABELS), ("what", what, WHAT_LABELS)):
        if d is None:
            continue
        positive(f"{role} sample_rate_hz", float(d.attrs.get("sample_rate_hz", float("nan"))))
        missing = [k for k in labels if k not in d.coords and k not in d]
        if missing:
            raise ValueError(f"the {role} dataset has no {', '.join(missing)} labels")
    if where is not None:
        try:
            positive("whisker length_mm", float(json.loads(where.attrs["whisker"])["length_mm"]))
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(
                f"the where dataset's whisker attribute gives no length_mm ({exc})"
            ) from None


def fit_pipeline_from_datasets(
    where: xr.Dataset | None = None,
    what: xr.Dataset | None = None,
    *,
    detector: DetectorSettings | None = None,
    tip_zone_mm: float = 5.0,
    where_estimator: Any = None,
    what_estimator: Any = None,
    **pipeline_options: Any,
) -> tuple[TactilePipeline, dict[str, Any]]:
    """A single-whisker pipeline fitted on a chapter-4 (where) and/or chapter-5 (what) dataset.

    Parameters
    ----------
    where, what : xarray.Dataset, optional
        Datasets of single contacts labelled ``radial_distance_mm, speed_mm_s`` and
        ``angle_deg, speed_mm_s, texture``; at least one, with the same channels. Each model
        is fitted at its dataset's rate (chapter 4 recorded at 1 kHz, chapter 5 at 4 kHz);
        the pipeline streams at the higher one and resamples each contact's window to each
        model's rate (:func:`~vibrissa.framework.model_windows`).
    detector : DetectorSettings, optional
    tip_zone_mm : float
        A radial distance within this of the whisker's length (the dataset's ``whisker``
        attribute) is a tip contact (5 mm: thesis 4.2).
    where_estimator, what_estimator : estimator, optional
        Unfitted classifiers (default: the framework's defaults at the dataset's rate).
    **pipeline_options
        Passed to :class:`TactilePipeline` (e.g. ``decision_threshold``).

    Returns
    -------
    pipeline : TactilePipeline
    summary : dict
        Contacts used and missed per dataset, the rate, the tip radial distance.
    """
    settings = detector if detector is not None else DetectorSettings()
    check_datasets(where, what)
    fs = max(float(d.attrs["sample_rate_hz"]) for d in (where, what) if d is not None)
    channels = {int(d.sizes["channel"]) for d in (where, what) if d is not None}
    summary: dict[str, Any] = {"sample_rate_hz": fs, "n_channels": channels.pop()}
    where_model = what_model = None
    if where is not None:
        tw = trial_windows(where, WHERE_LABELS, settings)
        rate = tw.sample_rate_hz
        length = float(json.loads(where.attrs["whisker"])["length_mm"])
        tip_r = length - tip_zone_mm
        est = where_estimator if where_estimator is not None else default_where_estimator(rate)
        where_model = fit_where(
            est, tw.windows, tw.labels, rate, rate, tip_radial_distance_mm=tip_r, speed_column=1
        )
        summary["where"] = {"contacts": int(tw.windows.shape[0]), "missed": tw.n_missed}
        summary["tip_radial_distance_mm"] = tip_r
    if what is not None:
        tw = trial_windows(what, WHAT_LABELS, settings)
        rate = tw.sample_rate_hz
        est = what_estimator if what_estimator is not None else default_what_estimator(rate)
        what_model = fit_what(
            est, tw.windows, tw.labels, rate, rate, angle_column=0, texture_column=2
        )
        summary["what"] = {"contacts": int(tw.windows.shape[0]), "missed": tw.n_missed}
    pipe = TactilePipeline(
        fs,
        1,
        summary["n_channels"],
        detector=settings,
        where=where_model,
        what=what_model,
        **pipeline_options,
    )
    return pipe, summary
