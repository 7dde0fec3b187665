"""StreamGuard: each hostile case reported once, and contacts after it still reported."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.framework import ContactReport, TactilePipeline
from vibrissa.framework.stream import IssueLog, StreamGuard, StreamIssue

FS = 1000.0
ONSETS = (1.0, 2.5, 4.0, 5.2)


def make_stream(n_s: float = 6.0, fs: float = FS, seed: int = 0):
    """Two whiskers x two channels with four half-sine contacts, alternating whiskers."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(n_s * fs)) / fs
    x = 0.005 * rng.standard_normal((t.size, 2, 2))
    for i, onset in enumerate(ONSETS):
        m = (t >= onset) & (t < onset + 0.15)
        x[m, i % 2, 0] += 0.5 * np.sin(np.pi * (t[m] - onset) / 0.15)
    return t, x


def sampled_at(rate_hz: float, n_s: float = 6.0):
    """The same signal as :func:`make_stream` sampled at another rate (linear)."""
    t, x = make_stream(n_s)
    tt = np.arange(int(t[-1] * rate_hz) + 1) / rate_hz
    flat = x.reshape(t.size, -1)
    xx = np.stack([np.interp(tt, t, flat[:, k]) for k in range(flat.shape[1])], axis=1)
    return tt, xx.reshape(tt.size, 2, 2)


def offline(t, x):
    p = TactilePipeline(FS, 2, 2)
    return [r.to_dict() for r in p.feed(x) + p.flush()]


def guarded(t, x, chunk=97):
    g = StreamGuard(TactilePipeline(FS, 2, 2))
    out = []
    for i in range(0, len(t), chunk):
        out += g.push(t[i : i + chunk], x[i : i + chunk])
    out += g.flush()
    issues = [o for o in out if isinstance(o, StreamIssue)]
    contacts = [o.to_dict() for o in out if isinstance(o, ContactReport)]
    return issues, contacts, g


def test_a_clean_stream_gives_the_offline_reports_and_no_issue():
    t, x = make_stream()
    issues, contacts, g = guarded(t, x)
    assert issues == [] and g.issue_counts == {}
    assert contacts == offline(t, x) and len(contacts) == len(ONSETS)
    assert g.samples == t.size and g.contacts == len(ONSETS)


@settings(max_examples=15, deadline=None)
@given(st.lists(st.integers(1, 700), min_size=1, max_size=30))
def test_reports_do_not_depend_on_how_the_records_are_batched(cuts):
    t, x = make_stream(3.0)
    edges = np.unique(np.clip(np.cumsum(cuts), 0, t.size))
    g = StreamGuard(TactilePipeline(FS, 2, 2))
    out = []
    for a, b in zip(np.r_[0, edges], np.r_[edges, t.size], strict=True):
        out += g.push(t[a:b], x[a:b])
    out += g.flush()
    assert [r.to_dict() for r in out] == offline(t, x)


def _gap(t, x):
    keep = np.ones(t.size, bool)
    keep[2000:2300] = False
    return t[keep], x[keep]


def _backwards(t, x):
    t = t.copy()
    t[3000:3010] -= 0.5
    return t, x


def _repeated(t, x):
    t = t.copy()
    t[3001:3004] = t[3000]
    return t, x


def _nan_all(t, x):
    x = x.copy()
    x[2000:2005] = np.nan
    return t, x


def _dropout(t, x):
    x = x.copy()
    x[2000:2200, 1, :] = np.nan  # whisker 1 out, then back before its contact at 2.5 s
    return t, x


# (fault, kinds reported, stream time after which every offline contact must be found)
CASES = {
    "gap": (_gap, {"gap": 1}, 2.3),
    "backwards": (_backwards, {"time_backwards": 10, "gap": 1}, 3.01),
    "repeated": (_repeated, {"time_repeated": 3, "gap": 1}, 3.01),
    "nan_all": (_nan_all, {"nan_samples": 5, "gap": 1}, 2.01),
    "dropout": (_dropout, {"whisker_dropout": 1}, 2.2),
}


@pytest.mark.parametrize("name", list(CASES))
def test_each_fault_is_reported_once_and_later_contacts_survive(name):
    fault, kinds, after_s = CASES[name]
    t, x = make_stream()
    ref = [c for c in offline(t, x) if c["onset_s"] > after_s]
    issues, contacts, g = guarded(*fault(t, x))
    assert g.issue_counts == kinds
    assert sorted(i.kind for i in issues) == sorted(kinds)  # each kind once
    assert all(i.message and np.isfinite(i.at_s) for i in issues)
    assert ref and [c for c in contacts if c["onset_s"] > after_s] == ref


def test_a_whisker_that_drops_out_is_broken_and_its_held_values_report_nothing():
    t, x = make_stream()
    x = x.copy()
    x[1050:1100, 0, :] = np.nan  # whisker 0 drops out in the middle of its contact at 1.0 s
    x[5250:, 1, :] = np.nan  # and whisker 1 in its last contact, never to return
    issues, contacts, g = guarded(t, x)
    assert g.issue_counts == {"whisker_dropout": 2}
    got = [(c["whisker"], round(c["onset_s"], 3)) for c in contacts]
    # whisker 0 is back at 1.1 s still in contact: a contact from its return; whisker 1's
    # held value (mid-contact) is never reported, as it never returns
    assert got == [(0, 1.1), (1, 2.51), (0, 4.01)]


@pytest.mark.parametrize(
    ("rate_hz", "kinds"), [(800.0, {"wrong_rate": 1}), (500.0, {"wrong_rate": 1})]
)
def test_a_wrong_rate_is_reported_and_resampled_onto_true_times(rate_hz, kinds):
    t, x = make_stream()
    ref = offline(t, x)
    issues, contacts, g = guarded(*sampled_at(rate_hz))
    assert g.issue_counts == kinds  # no gap for every slow record once measured
    assert "resampled" in issues[0].message and f"{rate_hz:g} Hz" in issues[0].message
    assert len(contacts) == len(ref)
    for c, r in zip(contacts, ref, strict=True):
        assert c["whisker"] == r["whisker"]
        assert abs(c["onset_s"] - r["onset_s"]) <= 2.5 / rate_hz


def test_a_changing_rate_is_reported_once_and_contacts_after_it_survive():
    t, x = make_stream()
    ref = offline(t, x)
    t7, x7 = sampled_at(700.0)
    cut = 2.0
    tt = np.r_[t[t < cut], t7[t7 >= cut]]
    xx = np.concatenate([x[t < cut], x7[t7 >= cut]])
    issues, contacts, g = guarded(tt, xx)
    assert g.issue_counts == {"rate_change": 1, "wrong_rate": 1}
    change = next(i for i in issues if i.kind == "rate_change")
    assert cut <= change.at_s < cut + 0.05 and "700 Hz" in change.message
    assert [(c["whisker"], round(c["onset_s"], 2)) for c in contacts] == [
        (r["whisker"], round(r["onset_s"], 2)) for r in ref
    ]


def test_contact_times_are_on_the_streams_clock_across_a_gap():
    t, x = make_stream()
    t = t + 1.7e9  # epoch seconds
    keep = np.ones(t.size, bool)
    keep[1500:1800] = False
    issues, contacts, _ = guarded(t[keep], x[keep])
    ref = offline(t, x)
    assert [i.kind for i in issues] == ["gap"]
    for c, r in zip(contacts, ref, strict=True):
        assert abs(c["onset_s"] - (r["onset_s"] + 1.7e9)) < 1e-6


class _Recorder:
    """A pipeline stand-in that records what it is given."""

    sample_rate_hz, n_whiskers, n_channels = FS, 2, 1

    def __init__(self):
        self.calls = []
        self.fed = []

    def feed(self, samples):
        self.calls.append(("feed", len(samples)))
        self.fed.append(np.array(samples))
        return []

    def flush(self):
        self.calls.append(("flush",))
        return []

    def break_stream(self, whiskers=None):
        self.calls.append(("break", whiskers))


def test_breaks_fall_where_a_whisker_leaves_and_returns_and_values_are_held():
    t = np.arange(20) / FS
    x = np.arange(40, dtype=float).reshape(20, 2, 1)
    x[8:12, 1, 0] = np.nan
    rec = _Recorder()
    g = StreamGuard(rec)
    g.push(t, x)
    g.flush()
    breaks = [c for c in rec.calls if c[0] == "break"]
    assert breaks == [("break", [1]), ("break", [1])]
    fed = np.concatenate(rec.fed)
    assert fed.shape == (20, 2, 1)
    assert np.all(fed[8:12, 1, 0] == x[7, 1, 0]) and np.array_equal(fed[:8], x[:8])
    # the breaks come after 8 samples (leaving) and 12 (returning)
    sizes = [c[1] for c in rec.calls if c[0] == "feed"]
    assert np.cumsum(sizes)[:2].tolist() == [8, 12]


def test_a_shared_log_reports_a_kind_once_and_counts_the_rest():
    log = IssueLog()
    log.report("bad_line", 1.0, "first", 2)
    log.report("bad_line", 2.0, "second")
    assert [i.message for i in log.drain()] == ["first"] and log.drain() == []
    assert log.counts == {"bad_line": 3}
    assert log.first["bad_line"].to_dict() == {
        "type": "stream_issue",
        "kind": "bad_line",
        "at_s": 1.0,
        "message": "first",
    }
    with pytest.raises(ValueError, match="kind"):
        log.report("nonsense", 0.0, "x")


def test_bad_batches_and_settings_are_refused_naming_them():
    g = StreamGuard(TactilePipeline(FS, 2, 2))
    with pytest.raises(ValueError, match="values"):
        g.push([0.0], np.zeros((1, 3, 2)))
    with pytest.raises(ValueError, match="t_s"):
        g.push(np.zeros((1, 1)), np.zeros((1, 2, 2)))
    with pytest.raises(ValueError, match="gap_periods"):
        StreamGuard(TactilePipeline(FS, 2, 2), gap_periods=1.0)
    with pytest.raises(TypeError, match="pipeline"):
        StreamGuard(object())
