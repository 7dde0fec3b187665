"""The ledger of thesis claims: predicates, statuses, anchors, and the committed run files."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vibrissa.thesis import claims as cl

ROOT = Path(__file__).resolve().parents[2]
RUNS = ROOT / "docs" / "runs"


def _claim(**kw):
    base = {
        "id": "a-claim",
        "section": "4.5",
        "experiments": ("radial-distance",),
        "quote": "a beats b",
        "thesis_value": "1 vs 2",
        "keys": {"a": "r.x.a", "b": "r.x.b"},
        "predicate": cl.Compare("a", "<", "b"),
        "ours": "{a:.1f} vs {b:.1f}",
        "diagnosis": "a is {a:.1f}",
    }
    return cl.Claim(**(base | kw))


def test_anchors_are_unique_and_stable():
    anchors = [cl.anchor(c.id) for c in cl.CLAIMS]
    assert len(set(anchors)) == len(anchors) == len(cl.CLAIMS)
    assert cl.anchor("velocity-beats-raw-radius") == "claim-velocity-beats-raw-radius"
    with pytest.raises(ValueError, match="claim_id"):
        cl.anchor("no-such-claim")


def test_every_key_exists_in_the_committed_runs_or_the_claim_is_not_measured():
    runs = cl.load_runs(RUNS)
    for verdict in cl.evaluate_all(RUNS):
        present = [cl.lookup(runs, k) is not None for k in verdict.claim.keys.values()]
        if verdict.status == "not measured":
            assert verdict.missing and not all(present), verdict.claim.id
        else:
            assert all(present) and verdict.status in ("holds", "does not hold")
            assert verdict.ours != "-"
            assert bool(verdict.diagnosis) == (verdict.status == "does not hold")


def test_claims_cover_the_chapters_and_every_experiment():
    sections = {c.section.split(".")[0] for c in cl.CLAIMS}
    assert sections == {"3", "4", "5", "6"}
    for name in cl.EXPERIMENTS:
        assert cl.claims_for(name), name
        assert all(name in c.experiments for c in cl.claims_for(name))
    with pytest.raises(ValueError, match="experiment_name"):
        cl.claims_for("chapter-9")


def test_missing_run_file_or_key_is_not_measured(tmp_path):
    claim = _claim()
    assert cl.evaluate(claim, {}).status == "not measured"
    assert cl.evaluate(claim, {"r": {"x": {"a": 1.0}}}).missing == ["r.x.b"]
    assert cl.evaluate(claim, {"r": {"x": {"a": 1.0, "b": None}}}).status == "not measured"
    (tmp_path / "r.json").write_text("{not json")
    assert cl.evaluate_all(tmp_path, [claim])[0].status == "not measured"


def test_status_follows_the_values():
    claim = _claim()
    holds = cl.evaluate(claim, {"r": {"x": {"a": 1.0, "b": 2.0}}})
    fails = cl.evaluate(claim, {"r": {"x": {"a": 3.0, "b": 2.0}}})
    assert (holds.status, holds.ours, holds.diagnosis) == ("holds", "1.0 vs 2.0", "")
    assert (fails.status, fails.diagnosis) == ("does not hold", "a is 3.0")
    text = cl.evaluate(claim, {"r": {"x": {"a": "3", "b": 2.0}}})
    assert (text.status, text.missing) == ("not measured", ["r.x.a", "r.x.b"])
    same = cl.evaluate(
        _claim(predicate=cl.Compare("a", "==", "b")), {"r": {"x": {"a": "s", "b": "s"}}}
    )
    assert (same.status, same.ours) == ("holds", "a = s, b = s")


def test_predicates():
    v = {"a": -3.0, "b": 2.0, "c": 2.5, "t": True}
    assert cl.Compare("a", "<", "b").holds(v)
    assert not cl.Compare("a", "<", "b", absolute=True).holds(v)
    assert cl.Compare("c", "<=", 2.5).holds(v) and cl.Compare("t", "==", True).holds(v)
    assert cl.Between("c", 2.0, 2.5).holds(v) and not cl.Between("a", 0, 1).holds(v)
    assert cl.Ranking((("a",), ("b", "c"))).holds(v)
    assert not cl.Ranking((("b",), ("c",)), descending=True).holds(v)
    assert cl.All((cl.Compare("a", "<", "b"), cl.Between("c", 2, 3))).holds(v)
    assert cl.Compare("a", "<", "b", absolute=True).text() == "|a| < |b|"
    assert cl.Ranking((("a", "b"), ("c",))).text() == "ranking (lowest first): a = b, c"


@given(st.lists(st.floats(-1e6, 1e6), min_size=2, max_size=6, unique=True))
def test_ranking_holds_exactly_for_the_sorted_order(xs):
    names = [f"v{i}" for i in range(len(xs))]
    values = dict(zip(names, xs, strict=True))
    ordered = tuple((n,) for n in sorted(names, key=values.__getitem__))
    assert cl.Ranking(ordered).holds(values)
    assert cl.Ranking(tuple(reversed(ordered)), descending=True).holds(values)
    assert not cl.Ranking(tuple(reversed(ordered))).holds(values)


def test_bad_claims_are_refused():
    with pytest.raises(ValueError, match="id"):
        _claim(id="Bad Id")
    with pytest.raises(ValueError, match="experiments"):
        _claim(experiments=("chapter-9",))
    with pytest.raises(ValueError, match="unnamed values"):
        _claim(predicate=cl.Compare("a", "<", "z"))
    with pytest.raises(ValueError, match="key"):
        cl.lookup({}, "nodot")


def test_ledger_counts_and_rows():
    claim = _claim()
    verdicts = [
        cl.evaluate(claim, {"r": {"x": {"a": 3.0, "b": 2.0}}}),
        cl.evaluate(_claim(id="b-claim"), {}),
    ]
    out = cl.ledger(verdicts)
    assert out["counts"] == {"holds": 0, "does_not_hold": 1, "not_measured": 1, "total": 2}
    rows = out["table"].splitlines()
    assert len(rows) == 4 and rows[2].startswith('| <a id="claim-a-claim"></a>')
    assert "**does not hold** | a is 3.0 |" in rows[2]
    assert "no value for `r.x.a`, `r.x.b`" in rows[3]
    json.dumps(out)  # JSON-ready


def _seeded(a: list[float], b: list[float]) -> dict:
    mean = {"a": sum(a) / len(a), "b": sum(b) / len(b)}
    spread = {k: {"values": v} for k, v in (("a", a), ("b", b))}
    return {"r": {"x": mean, "spread": {"x": spread}}}


def test_a_claim_over_seeds_holds_only_where_the_spread_allows():
    claim = _claim()
    clear = cl.evaluate(claim, _seeded([1.0, 1.1, 0.9, 1.0, 1.05], [2.0, 2.1, 1.9, 2.0, 2.05]))
    assert clear.status == "holds" and clear.support == 1.0 and clear.n_seeds == 5
    assert "mean of 5 seeds" in clear.ours
    # a < b on the mean, but one seed in five has a far above b: not within the spread
    mixed = cl.evaluate(claim, _seeded([1.0, 1.0, 1.0, 1.0, 9.0], [2.7, 2.7, 2.7, 2.7, 2.7]))
    assert mixed.values["a"] < mixed.values["b"]
    assert mixed.status == "does not hold" and mixed.support < cl.SUPPORT
    assert "not within the spread over 5 seeds" in mixed.diagnosis
    # the same figures without a spread: judged on the means alone
    flat = {"r": {"x": {"a": 2.6, "b": 2.6001}}}
    assert cl.evaluate(claim, flat).support is None


def test_seed_pairs_are_kept_when_resampling():
    # a < b in every seed although a's and b's ranges overlap: the pairing decides
    a = [1.0, 2.0, 3.0, 4.0, 5.0]
    b = [x + 0.1 for x in a]
    assert cl.evaluate(_claim(), _seeded(a, b)).status == "holds"
