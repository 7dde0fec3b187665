"""A pipeline fitted on single-contact datasets (chapter 4 for where, chapter 5 for what)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from vibrissa.data.dataset import make_dataset
from vibrissa.data.schema import decode_texture
from vibrissa.framework.calibrate import check_datasets, fit_pipeline_from_datasets, trial_windows

from .test_detect import ALL_CLASSES, REST_V, bump

FS = 2000.0
WHISKER = json.dumps({"length_mm": 65.0})


def trials(n_per_class: int, seed: int) -> tuple[np.ndarray, list[tuple]]:
    """One contact per trial at 0.2 s in a 1 s trial, rest and noise around it."""
    rng = np.random.default_rng(seed)
    sig, classes = [], []
    for cls in ALL_CLASSES:
        for _ in range(n_per_class):
            x = REST_V + 0.002 * rng.standard_normal((int(FS), 2))
            b = bump(cls, rng)
            x[400 : 400 + b.shape[0]] += b
            sig.append(x.T)
            classes.append(cls)
    return np.stack(sig), classes


def datasets(n_per_class: int = 3, seed: int = 0):
    sig, classes = trials(n_per_class, seed)
    where = make_dataset(
        sig,
        sample_rate_hz=FS,
        labels={
            "radial_distance_mm": [c[0] for c in classes],
            "speed_mm_s": [c[1] for c in classes],
        },
        attrs={"whisker": WHISKER},
    )
    what = make_dataset(
        sig,
        sample_rate_hz=FS,
        labels={
            "angle_deg": [c[2] for c in classes],
            "speed_mm_s": [c[1] for c in classes],
            "texture": list(decode_texture([int(c[3]) for c in classes])),
        },
    )
    return where, what, classes


def test_each_trial_gives_its_detected_window_and_labels():
    where, _, classes = datasets()
    tw = trial_windows(where, ("radial_distance_mm", "speed_mm_s"))
    assert tw.n_missed == 0 and tw.windows.shape[0] == len(classes)
    assert np.array_equal(tw.labels[:, 0], [c[0] for c in classes])


def test_a_fitted_pipeline_classifies_new_contacts():
    where, what, _ = datasets(seed=0)
    pipe, summary = fit_pipeline_from_datasets(where, what, tip_zone_mm=5.0)
    assert summary["where"]["contacts"] == summary["what"]["contacts"] == 48
    assert summary["tip_radial_distance_mm"] == 60.0  # 60 mm contacts count as the tip
    sig, classes = trials(1, seed=5)
    stream = np.concatenate([s.T for s in sig])[:, None, :]
    reports = pipe.feed(stream) + pipe.flush()
    assert len(reports) == len(classes)
    tips = [r.tip for r in reports]
    assert np.mean([t == (c[0] >= 60.0) for t, c in zip(tips, classes, strict=True)]) >= 0.8
    tex = [r.what.texture_posterior for r in reports if r.what is not None]
    assert tex and all(abs(sum(p.values()) - 1.0) < 1e-9 for p in tex)


def test_bad_datasets_are_refused_before_any_fit():
    where, what, _ = datasets(1)
    with pytest.raises(ValueError, match="at least|or both"):
        check_datasets(None, None)
    with pytest.raises(ValueError, match="no angle_deg"):
        check_datasets(None, where)
    no_length = where.copy()
    no_length.attrs["whisker"] = "{}"
    with pytest.raises(ValueError, match="length_mm"):
        check_datasets(no_length, None)
    one_channel = what.isel(channel=[0])
    with pytest.raises(ValueError, match="channel counts differ"):
        check_datasets(where, one_channel)
