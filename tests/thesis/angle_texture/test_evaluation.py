"""Chapter-5 evaluation: kappa by hand, the split, the JSON contract and the report."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from vibrissa.classify import (
    MiniRocketClassifier,
    StationaryNaiveBayes,
    decode_texture,
)
from vibrissa.evaluate import metrics
from vibrissa.evaluate.metrics import kappa_from_confusion
from vibrissa.thesis.angle_texture.evaluation import (
    run_chapter5,
    score_chapter5,
    split_chapter5,
)
from vibrissa.thesis.angle_texture.figures import confusion_figure, kappa_figure
from vibrissa.thesis.angle_texture.report import (
    THESIS_CHAPTER5,
    discussion,
    markdown_chapter5,
    write_outputs,
)

FS = 4000.0


def make_ch5(seed: int, n_t: int = 600) -> tuple[np.ndarray, np.ndarray]:
    """One complete grid of peak-aligned pulses (2 angles x 2 speeds x 3 textures)."""
    rng = np.random.default_rng(seed)
    t = (np.arange(n_t) - n_t // 2) / FS
    X, y = [], []
    for a in (20.0, 60.0):
        for v in (20.0, 80.0):
            for tex in (0, 1, 2):
                amp = 0.005 * v
                pulse = np.exp(-0.5 * (t / (0.01 + 0.0005 * a)) ** 2)
                vib = 0.02 * amp * np.sin(2 * np.pi * (150 + 150 * tex) * t) * pulse
                X.append(np.stack([2.5 + amp * pulse + vib, 2.5 + 0.1 * vib]))
                y.append((a, v, tex))
    X = np.asarray(X) + 2e-4 * rng.standard_normal((len(X), 2, n_t))
    return X, np.asarray(y, dtype=float)


@pytest.fixture(scope="module")
def dataset() -> xr.Dataset:
    parts = [make_ch5(seed=s) for s in range(4)]
    X = np.concatenate([p[0] for p in parts])
    y = np.concatenate([p[1] for p in parts])
    n1 = len(parts[0][1])
    sets = np.repeat([1, 2, 3, 4], n1)
    return xr.Dataset(
        {"signal": (("trial", "channel", "time"), X)},
        coords={
            "trial": np.arange(len(y)),
            "channel": ["x", "y"],
            "time": (np.arange(X.shape[2]) - X.shape[2] // 2) / FS,
            "angle_deg": ("trial", y[:, 0]),
            "speed_mm_s": ("trial", y[:, 1]),
            "texture": ("trial", decode_texture(y[:, 2])),
            "set": ("trial", sets),
            "run": ("trial", (sets + 1) // 2),
            "direction": ("trial", np.where(sets % 2 == 1, 1, -1)),
        },
        attrs={"sample_rate_hz": FS, "whisker": '{"natural_frequencies_hz": [13.0]}'},
    )


def test_kappa_of_known_confusion_matrix():
    m = np.array([[20, 5], [10, 15]])
    # by hand: P_O = 35/50 = 0.7; P_E = (25*30 + 25*20) / 50^2 = 0.5; kappa = 0.2/0.5 = 0.4
    assert kappa_from_confusion(m) == pytest.approx(0.4)
    t = np.repeat([0, 0, 1, 1], [20, 5, 10, 15])
    p = np.repeat([0, 1, 0, 1], [20, 5, 10, 15])
    assert metrics.kappa(t, p) == pytest.approx(0.4)
    m3 = np.array([[5, 1, 0], [1, 3, 2], [0, 1, 7]])
    t3 = np.repeat(np.repeat([0, 1, 2], 3), m3.ravel())
    p3 = np.repeat(np.tile([0, 1, 2], 3), m3.ravel())
    for w in (None, "linear", "quadratic"):
        assert kappa_from_confusion(m3, w) == pytest.approx(metrics.kappa(t3, p3, weights=w))


def test_score_chapter5_confusions():
    t = np.array([[20, 10, 0], [20, 10, 1], [60, 80, 2], [60, 80, 3]], dtype=float)
    p = t.copy()
    p[1, 2] = 0
    sc = score_chapter5(t, p)
    assert sc["angle"]["kappa"] == 1.0
    assert sc["texture"]["confusion"]["labels"] == [0.0, 1.0, 2.0, 3.0]
    assert np.asarray(sc["texture"]["confusion"]["matrix"]).sum() == 4
    assert sc["texture"]["mean"] == pytest.approx(-0.25)


def test_split_by_run(dataset):
    s = split_chapter5(dataset, seed=0)
    runs = dataset["run"].values
    assert len(set(runs[s.train_index])) == 1 and len(set(runs[s.test_index])) == 1
    assert set(runs[s.train_index]) != set(runs[s.test_index])
    assert len(s.train_set) == len(s.test_set) == 2
    bad = dataset.isel(trial=np.flatnonzero(dataset["set"].values != 4)[:-1])
    with pytest.raises(ValueError, match="complete grid"):
        split_chapter5(bad)


def test_run_chapter5_json_contract(dataset, tmp_path):
    clfs = {
        "naive_bayes_velocity": StationaryNaiveBayes(signal="velocity", sample_rate_hz=FS),
        "minirocket": MiniRocketClassifier(pool=4, n_dilations=3),
    }
    res = run_chapter5(dataset, clfs, seed=0)
    for name in clfs:
        e = res["classifiers"][name]
        assert set(e["kappa"]) >= {"angle", "speed", "texture", "texture_alone"}
        assert isinstance(e["classify_seconds"], float)
        assert set(e["errors"]) == {"angle_deg", "speed_mm_s", "texture"}
        assert set(e["confusion"]) >= {"angle", "speed", "texture"}
    assert list(res["sequential"]) == ["1", "2", "3", "5", "10"]
    text = json.dumps(res, allow_nan=False)
    back = json.loads(text)
    assert back["sequential"].keys() == res["sequential"].keys()
    assert res["meta"]["evaluation"] == "evans2011_chapter5"
    assert set(res["parameters"]) == {"angle", "speed", "texture"}
    md = markdown_chapter5(res)
    assert "naive_bayes_velocity" in md and "0.39" in md  # thesis value beside ours
    assert "## Discussion" in md and discussion(res) in md
    axs = confusion_figure(res["classifiers"]["minirocket"], "minirocket")
    assert len(axs) == 4 and all(a.get_xlabel().startswith("predicted") for a in axs)
    tex_ax = [a for a in axs if a.get_title().startswith("texture (")][0]
    assert [t.get_text() for t in tex_ax.get_xticklabels()] == ["aluminium", "p600", "p180"]
    kax = kappa_figure(res)
    assert len(kax) == 3 and all("kappa" in a.get_ylabel() for a in kax)
    # thesis bars drawn beside ours where the thesis reports the method
    labels = {t.get_label() for t in kax[0].containers}
    assert labels == {"this run", "thesis (fig. 5.15, 5.4)"}
    figs = write_outputs(res, tmp_path / "n", figures=True)
    assert (tmp_path / "n" / "figures" / "sequential.png").stat().st_size > 0
    assert set(figs) >= {"kappa", "sequential", "confusion/minirocket"}


def test_discussion_is_computed_from_the_results(dataset):
    res = run_chapter5(
        dataset,
        {"nb": StationaryNaiveBayes(sample_rate_hz=FS)},
        seed=0,
        texture_alone=False,
        sequential_base=None,
    )
    text = discussion(res)
    k = res["classifiers"]["nb"]["kappa"]["speed"]
    assert f"best kappa {k:.2f} (`nb`)" in text


def test_run_chapter5_errors(dataset):
    with pytest.raises(ValueError, match="classifiers"):
        run_chapter5(dataset, {})
    with pytest.raises(ValueError, match="coordinate"):
        run_chapter5(dataset.drop_vars("texture"), {"nb": StationaryNaiveBayes()})


def test_thesis_constant_covers_figure_5_15():
    for name, k in (
        ("template_lowpass", 0.30),
        ("frequency", 0.44),
        ("feature", 0.11),
        ("naive_bayes_velocity", 0.39),
    ):
        assert THESIS_CHAPTER5[name]["kappa"]["angle"] == k


def test_classifiers_built_for_another_rate_are_refused(dataset):
    # StationaryNaiveBayes() is built for 1 kHz (its velocity is in V/s at that rate)
    with pytest.raises(
        ValueError,
        match="classifier 'nb' does not fit the dataset: "
        "StationaryNaiveBayes is built for sample_rate_hz=1000 "
        "Hz, but the data are sampled at 4000 Hz",
    ):
        run_chapter5(dataset, {"nb": StationaryNaiveBayes()}, texture_alone=False)
