"""Tests of vibrissa.framework.pipeline: reports of a known stream, chunking, save and load."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vibrissa.framework import (
    EvidenceAccumulator,
    TactilePipeline,
    contact_windows,
    default_what_estimator,
    default_where_estimator,
    fit_what,
    fit_where,
)
from vibrissa.framework.evidence import floored_log_posterior

from .test_detect import FS, match, synthetic_stream

SURFACE = (30.0, 3.0)  # the test stream's surface: 30 degrees, P80


def surface_or_shaft(whisker, rng):
    """Half the contacts tip contacts on SURFACE, half shaft contacts of any angle/texture."""
    speed = float(rng.choice([50.0, 100.0]))
    if rng.random() < 0.5:
        return (60.0, speed, *SURFACE)
    return (30.0, speed, float(rng.choice([0.0, 30.0])), float(rng.choice([0.0, 3.0])))


@pytest.fixture(scope="module")
def models():
    x, events = synthetic_stream(30.0, 4, seed=11)
    contacts = contact_windows(x, FS)
    y = np.array([e[2] for e in match(contacts, events)])
    W = np.stack([c.window for c in contacts])
    # chapter 4 ran at 1 kHz: the where model reads the 2-kHz stream resampled
    where = fit_where(default_where_estimator(1000.0), W, y[:, :2], FS, 1000.0, 55.0)
    tip = y[:, 0] == 60.0
    what = fit_what(default_what_estimator(FS), W[tip], y[tip][:, [2, 1, 3]], FS, FS)
    return where, what


@pytest.fixture(scope="module")
def stream():
    return synthetic_stream(8.0, 3, seed=5, classes=surface_or_shaft)


def run(pipe, x, size):
    out = []
    for a in range(0, len(x), size):
        out += pipe.feed(x[a : a + size])
    return out + pipe.flush()


def dicts(reports):
    return [r.to_dict() for r in reports]


def test_reports_of_a_known_stream(models, stream):
    where, what = models
    x, events = stream
    pipe = TactilePipeline(FS, 3, 2, where=where, what=what, start_time_s=10.0)
    reports = run(pipe, x, 4096)
    contacts = contact_windows(x, FS)
    assert len(reports) == len(contacts) == len(events)
    truth = match(contacts, events)
    # whisker and onset: the detector's contacts, in stream time
    for r, c, e in zip(reports, contacts, truth, strict=True):
        assert r.whisker == c.whisker == e[0]
        assert r.onset_s == 10.0 + c.onset_index / FS
        assert 0 <= r.onset_s - (10.0 + e[1] / FS) < 0.03
    # tip or shaft from the where model's posterior (computed offline here)
    W = np.stack([c.window for c in contacts])
    p_tip = where.predict_proba(W, FS)[:, where.classes[:, 0] >= 55.0].sum(axis=1)
    np.testing.assert_allclose([r.p_tip for r in reports], p_tip, rtol=1e-9, atol=1e-300)
    assert [r.tip for r in reports] == list(p_tip >= 0.5)
    is_tip = np.array([e[2][0] == 60.0 for e in truth])
    assert np.mean(np.array([r.tip for r in reports]) == is_tip) >= 0.8
    for r in reports:
        assert (r.what is None) == (not r.tip) and (r.evidence is None) == (not r.tip)
        lo, hi = r.where.radial_interval_mm
        assert {lo, hi} <= {30.0, 60.0} and lo <= hi and 30.0 <= r.where.radial_distance_mm <= 60.0
        assert (lo == hi == 60.0) <= r.tip  # an interval of tip classes alone: a tip contact
    # texture of single tip contacts: mostly P80 on this surface
    tips = [r for r in reports if r.tip]
    single = [max(r.what.texture_posterior, key=r.what.texture_posterior.get) for r in tips]
    assert single.count("p80") >= 0.7 * len(single)
    # evidence: the accumulator's rule, surface by surface, replayed offline
    rows, index = what.surface_classes()
    acc = EvidenceAccumulator(rows, 0.99, 1e-3)
    surface, fresh, decisions = 0, False, []
    # one contact at a time, as the pipeline (MiniRocket's float32 features differ in the
    # last bits between a batch and a single contact)
    p_what = [what.predict_proba(W[i : i + 1], FS)[0] for i, r in enumerate(reports) if r.tip]
    for r, p in zip(tips, p_what, strict=True):
        if fresh:
            surface, fresh = surface + 1, False
            acc.reset()
        sp = np.zeros(len(rows))
        np.add.at(sp, index, p)
        acc.add(sp / sp.sum(), r.whisker)
        assert r.surface_id == surface and r.evidence.n_contacts == acc.n_contacts
        np.testing.assert_allclose(r.evidence.probability, acc.best()[1], rtol=1e-9)
        assert (r.decision is not None) == acc.decided
        if acc.decided:
            fresh = True
            decisions.append(r.decision)
            assert r.decision["n_contacts"] == acc.n_contacts
            assert r.decision["whiskers"] == sorted(acc.whiskers)
    assert len(decisions) >= 2
    assert all((d["angle_deg"], d["texture"]) == (30.0, "p80") for d in decisions)
    assert all(d["probability"] >= 0.99 for d in decisions)


@pytest.fixture(scope="module")
def reference(models, stream):
    """The first 3 s of the stream, fed in one chunk: ``(samples, report dicts)``."""
    where, what = models
    x = stream[0][: int(3.0 * FS)]
    ref = dicts(run(TactilePipeline(FS, 3, 2, where=where, what=what), x, len(x)))
    assert len(ref) >= 8 and any(r["decision"] for r in ref)
    return x, ref


@pytest.mark.parametrize("size", [1, 7, 4096])
def test_chunk_sizes_give_identical_reports(models, reference, size):
    where, what = models
    x, ref = reference
    assert dicts(run(TactilePipeline(FS, 3, 2, where=where, what=what), x, size)) == ref


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_any_partition_gives_identical_reports(models, reference, data):
    where, what = models
    x, ref = reference
    cuts = sorted(data.draw(st.lists(st.integers(0, len(x)), max_size=12)))
    pipe = TactilePipeline(FS, 3, 2, where=where, what=what)
    out = []
    for a, b in zip([0, *cuts], [*cuts, len(x)], strict=True):
        out += pipe.feed(x[a:b])
    assert dicts(out + pipe.flush()) == ref


def test_without_models_every_contact_is_tip(stream):
    x, events = stream
    pipe = TactilePipeline(FS, 3, 2)
    reports = run(pipe, x, 500)
    assert len(reports) == len(events)
    assert all(r.tip and r.p_tip == 1.0 and r.where is None and r.what is None for r in reports)
    assert all(r.evidence is None and r.decision is None for r in reports)
    json.dumps(dicts(reports))


def test_new_surface_and_no_reset(models, stream):
    where, what = models
    x, _ = stream
    pipe = TactilePipeline(FS, 3, 2, where=where, what=what, reset_after_decision=False)
    reports = [r for r in run(pipe, x, 4096) if r.tip]
    assert {r.surface_id for r in reports} == {0}
    assert [r.evidence.n_contacts for r in reports] == list(range(1, len(reports) + 1))
    first = next(i for i, r in enumerate(reports) if r.decision is not None)
    assert all(r.decision is not None for r in reports[first:])
    pipe.new_surface()
    (r, *_) = [r for r in run(pipe, x, 4096) if r.tip]
    assert r.surface_id == 1 and r.evidence.n_contacts == 1


def test_save_load_round_trip(models, stream, tmp_path):
    where, what = models
    x = stream[0][: int(4.0 * FS)]
    kwargs = dict(where=where, what=what, decision_threshold=0.95, tip_probability=0.4)
    pipe = TactilePipeline(FS, 3, 2, start_time_s=2.0, **kwargs)
    path = tmp_path / "pipe.vbp"
    pipe.save(path)
    loaded = TactilePipeline.load(path)
    assert (loaded.decision_threshold, loaded.tip_probability) == (0.95, 0.4)
    assert dicts(run(loaded, x, 333)) == dicts(run(pipe, x, 333))


def test_corrupt_truncated_and_foreign_files_refused_by_name(models, tmp_path):
    where, what = models
    path = tmp_path / "pipe.vbp"
    TactilePipeline(FS, 3, 2, where=where, what=what).save(path)
    data = path.read_bytes()
    bad = tmp_path / "truncated.vbp"
    bad.write_bytes(data[:-100])
    with pytest.raises(ValueError, match="truncated.vbp.*truncated"):
        TactilePipeline.load(bad)
    flipped = bytearray(data)
    flipped[-50] ^= 0xFF
    bad = tmp_path / "corrupt.vbp"
    bad.write_bytes(bytes(flipped))
    with pytest.raises(ValueError, match="corrupt.vbp.*corrupt"):
        TactilePipeline.load(bad)
    head, _, payload = data.partition(b"\n")
    header = json.loads(head)
    for key, value, word in (
        ("format_version", 99, "format version"),
        ("vibrissa_version", "0.0.1", "0.0.1"),
    ):
        other = tmp_path / f"other-{key}.vbp"
        other.write_bytes(json.dumps({**header, key: value}).encode() + b"\n" + payload)
        with pytest.raises(ValueError, match=f"other-{key}.vbp.*{word}"):
            TactilePipeline.load(other)
    foreign = tmp_path / "foreign.txt"
    foreign.write_text("hello\n")
    with pytest.raises(ValueError, match="foreign.txt is not a saved"):
        TactilePipeline.load(foreign)
    with pytest.raises(ValueError, match="missing.vbp"):
        TactilePipeline.load(tmp_path / "missing.vbp")


@pytest.mark.parametrize(
    ("samples", "match_"),
    [
        (np.zeros((10, 3)), "samples must have shape"),
        (np.zeros((10, 2, 2)), "samples must have shape"),
        (np.full((10, 3, 2), np.nan), "samples contain 60 NaN"),
    ],
)
def test_bad_input_refused_naming_it(samples, match_):
    with pytest.raises(ValueError, match=match_):
        TactilePipeline(FS, 3, 2).feed(samples)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"tip_probability": 1.5}, "tip_probability"),
        ({"decision_threshold": -1.0}, "decision_threshold"),
        ({"min_probability": float("nan")}, "min_probability"),
        ({"start_time_s": float("inf")}, "start_time_s"),
        ({"where": "model"}, "where"),
    ],
)
def test_bad_parameters_named(kwargs, name):
    with pytest.raises((ValueError, TypeError), match=name):
        TactilePipeline(FS, 3, 2, **kwargs)


def test_floored_log_posterior_normalised():
    lp = floored_log_posterior([[1.0, 0.0, 0.0]], 1e-3)
    np.testing.assert_allclose(np.exp(lp).sum(), 1.0)
    assert np.exp(lp[0, 1]) == pytest.approx(1e-3 / 1.002)
