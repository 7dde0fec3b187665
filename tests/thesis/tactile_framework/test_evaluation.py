"""Scoring the framework's episodes: decisions over thresholds, policy comparison, maps."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from vibrissa.thesis.tactile_framework.evaluation import (
    compare_policies,
    deadline_decision,
    episode_decisions,
    evaluate_framework,
    paired_difference,
)

# two joint classes: (45 deg, texture 0) and (45 deg, texture 3)
CLASSES = np.array([[45.0, 0], [45.0, 3]])


def lp(p0: float) -> np.ndarray:
    return np.log([p0, 1.0 - p0])


def test_a_decision_comes_at_the_first_contact_past_the_threshold():
    used = np.array([True, False, True, True])
    log_p = np.stack([lp(0.2), lp(0.5), lp(0.2), lp(0.2)])
    truth = np.array([1, -1, 1, 1])
    onset = np.array([0.5, 1.0, 1.5, 2.0])
    d = episode_decisions(used, log_p, truth, onset, 0.9)
    # posterior of class 1 after 1 contact 0.8, after 2 (used) 0.94
    assert d["decided"] and d["class"] == 1 and d["correct"]
    assert d["contacts"] == 3  # every contact up to the deciding one counts
    assert d["seconds"] == 1.5
    # the same contacts never reach 0.999
    assert not episode_decisions(used, log_p, truth, onset, 0.999)["decided"]


def test_a_decision_on_corner_contacts_alone_is_wrong():
    used = np.array([True, True])
    d = episode_decisions(
        used, np.stack([lp(0.01), lp(0.01)]), np.array([-1, -1]), np.zeros(2), 0.9
    )
    assert d["decided"] and d["correct"] is False


def test_nothing_used_means_no_decision():
    d = episode_decisions(np.zeros(3, bool), np.zeros((3, 2)), -np.ones(3, int), np.zeros(3), 0.9)
    assert d == {
        "decided": False,
        "correct": None,
        "class": None,
        "contacts": None,
        "seconds": None,
    }


def test_the_deadline_decides_on_the_evidence_so_far():
    used = np.array([True, False, True])
    log_p = np.stack([lp(0.3), lp(0.5), lp(0.4)])  # class 1 ahead, never past 0.9
    truth = np.array([1, -1, 1])
    onset = np.array([0.5, 1.0, 1.5])
    assert not episode_decisions(used, log_p, truth, onset, 0.9)["decided"]
    d = deadline_decision(used, log_p, truth, onset, 0.9, end_s=8.0)
    assert d == {
        "at_threshold": False,
        "correct": True,
        "class": 1,
        "contacts": 3,  # every contact of the episode
        "seconds": 8.0,  # the end of its budget, not its last contact
    }
    # the same episode past its threshold decides there, as episode_decisions does
    d = deadline_decision(used, log_p, truth, onset, 0.6, end_s=8.0)
    assert d["at_threshold"] and d["contacts"] == 1 and d["seconds"] == 0.5


def test_the_deadline_with_no_evidence_names_nothing_and_is_wrong():
    d = deadline_decision(
        np.zeros(2, bool), np.zeros((2, 2)), np.array([0, 0]), np.zeros(2), 0.9, end_s=4.0
    )
    assert d["class"] is None and d["correct"] is False and d["contacts"] == 2


def test_paired_difference_brackets_the_mean():
    a = np.array([1, 1, 0, 1, 1, 0, 1, 1], dtype=float)
    b = np.array([0, 1, 0, 0, 1, 0, 1, 0], dtype=float)
    d = paired_difference(a, b)
    assert d["mean"] == pytest.approx(3 / 8)
    assert 0.0 <= d["lo"] < d["mean"] < d["hi"] <= 1.0
    assert paired_difference(a, a) == {"mean": 0.0, "lo": 0.0, "hi": 0.0}
    with pytest.raises(ValueError, match="one value per episode"):
        paired_difference(np.array([]), np.array([]))


def synthetic_dataset() -> xr.Dataset:
    """Three policies x two episodes; passive wastes contacts on corners called tip."""
    rows = []
    for p in range(3):
        for e in range(2):
            seq = {
                0: [
                    (2, False, 0.5),
                    (2, True, 0.5),
                    (1, True, 0.1),
                    (1, True, 0.1),
                    (1, True, 0.1),
                ],
                1: [(2, False, 0.5), (1, True, 0.1), (1, True, 0.1), (1, True, 0.1)],
                2: [(1, True, 0.1), (1, True, 0.1), (1, True, 0.1)],
            }[p]
            for k, (kind, tip, p0) in enumerate(seq):
                rows.append((p, e, k, kind, tip, p0))
    n = len(rows)
    col = lambda i: np.array([r[i] for r in rows])  # noqa: E731
    kind = col(3)
    g = np.zeros((8, 8))
    g[6:, :] = 1
    tex = np.full((8, 8), -1)
    tex[6, :] = 3
    world = {"boxes": [], "room": [0, 0, 200, 200], "wall_textures": ["p80"] * 4}
    ds = xr.Dataset(
        {
            "ep_policy": ("contact", col(0)),
            "ep_episode": ("contact", col(1)),
            "ep_whisk": ("contact", col(2)),
            "ep_onset_s": ("contact", col(2) * 1.0),
            "ep_truth_kind": ("contact", kind),
            "ep_truth_radial_mm": ("contact", np.where(kind == 2, 100.0, 185.0)),
            "ep_truth_angle_class_deg": ("contact", np.where(kind == 1, 45.0, np.nan)),
            "ep_truth_texture_code": ("contact", np.where(kind == 1, 3, -1)),
            "ep_est_radial_mm": ("contact", np.where(col(4), 185.0, 110.0)),
            "ep_tip": ("contact", col(4)),
            "ep_what_log_proba": (("contact", "what_class"), np.stack([lp(v) for v in col(5)])),
            "ep_point_x_mm": ("contact", np.full(n, 152.0)),
            "ep_point_y_mm": ("contact", np.full(n, 50.0)),
            "ep_pivot_x_mm": ("contact", np.full(n, 20.0)),
            "ep_pivot_y_mm": ("contact", np.full(n, 50.0)),
            # a whisker resting at -45 deg and protracting toward +45 deg meets a plane at 45
            # deg to its rest axis when the plane runs along y: the wall's direction, 90 deg
            "ep_rest_dir_deg": ("contact", np.full(n, -45.0)),
            "ep_prot_dir_deg": ("contact", np.full(n, 45.0)),
            "move_policy": ("move", np.array([0, 1, 2])),
            "move_episode": ("move", np.array([0, 0, 0])),
            "move_kind": ("move", np.array([0, 1, 1])),
            "move_done": ("move", np.array([True, True, True])),
            "gt_occupancy": (("gx", "gy"), g),
            "gt_texture_code": (("gx", "gy"), tex),
            "gt_face_direction_deg": (("gx", "gy"), np.where(tex >= 0, 90.0, np.nan)),
            "gt_arena": (("gx", "gy"), np.ones((8, 8), dtype=np.int8)),
            "signal": (("trial", "channel", "time"), np.zeros((3, 2, 4))),
        },
        coords={
            "kind": ("trial", np.array([1, 2, 1])),
            "radial_class_mm": ("trial", np.array([185.0, 110.0, 185.0])),
            "what_angle_deg": ("what_class", CLASSES[:, 0]),
            "what_texture_code": ("what_class", CLASSES[:, 1].astype(int)),
        },
        attrs={
            "gt_origin_mm": np.array([0.0, 0.0]),
            "gt_cell_mm": 25.0,
            "world": json.dumps(world),
            "protocol_params": json.dumps({"n_episodes": 2}),
        },
    )
    return ds


def test_the_synthetic_episodes_rank_oracle_active_passive():
    r = evaluate_framework(synthetic_dataset(), thresholds=(0.9, 0.99999))
    pol = r["policies"]
    assert pol["passive"]["tip_fraction"] == pytest.approx(3 / 5)
    assert pol["oracle"]["tip_fraction"] == 1.0
    assert pol["passive"]["tip_shaft_accuracy"] == pytest.approx(4 / 5)
    at = {n: r["curves"][n][0] for n in ("passive", "active", "oracle")}
    assert at["passive"]["accuracy"] == 1.0 and at["passive"]["contacts_to_decision"] == 4
    assert at["active"]["contacts_to_decision"] == 3
    assert at["oracle"]["contacts_to_decision"] == 2
    comp = r["comparison"]["per_threshold"][0]
    assert comp["contacts_active_beats_passive"] is True
    assert comp["accuracy_active_beats_passive"] is False  # equal accuracy is not "beats"
    # every synthetic episode decides at 0.9, so the deadline changes nothing there
    assert at["passive"]["accuracy_with_deadline"] == 1.0
    assert at["passive"]["contacts_with_deadline"] == 4
    assert comp["accuracy_gain_over_passive"] == {"mean": 0.0, "lo": 0.0, "hi": 0.0}
    assert comp["contacts_saved_over_passive"]["mean"] == 1.0
    # at 0.99999 nobody decides: each episode ends undecided after all its contacts
    at = {n: r["curves"][n][1] for n in ("passive", "active", "oracle")}
    assert at["passive"]["decided_fraction"] == 0.0 and at["passive"]["accuracy"] is None
    assert at["passive"]["accuracy_with_deadline"] == 1.0
    assert at["passive"]["contacts_with_deadline"] == 5
    assert at["oracle"]["contacts_with_deadline"] == 3
    maps = r["maps"]["active"]
    assert maps["texture_cells"] == 1 and maps["texture_accuracy"] == 1.0
    assert maps["direction_error_deg"] == pytest.approx(0.0, abs=1e-6)


def test_compare_policies_needs_both_to_win_everywhere():
    row = {"threshold": 0.9, "accuracy": 0.9, "contacts_to_decision": 3.0}
    worse = {"threshold": 0.9, "accuracy": 0.8, "contacts_to_decision": 4.0}
    c = compare_policies({"active": [row], "passive": [worse], "oracle": [row]})
    assert c["active_beats_passive_everywhere"] is True
    c = compare_policies({"active": [worse], "passive": [row], "oracle": [row]})
    assert c["active_beats_passive_everywhere"] is False


def test_the_comparison_is_with_the_deadline_and_reports_decided_only_beside_it():
    # passive decides in few episodes, the easy ones: right on those, wrong on the rest
    active = {
        "threshold": 0.9,
        "accuracy": 0.7,
        "contacts_to_decision": 3.0,
        "accuracy_with_deadline": 0.7,
        "contacts_with_deadline": 3.0,
    }
    passive = {
        "threshold": 0.9,
        "accuracy": 0.8,
        "contacts_to_decision": 4.0,
        "accuracy_with_deadline": 0.5,
        "contacts_with_deadline": 6.0,
    }
    c = compare_policies({"active": [active], "passive": [passive], "oracle": [active]})
    assert c["active_beats_passive_everywhere"] is True
    assert c["active_beats_passive_everywhere_decided_only"] is False
    row = c["per_threshold"][0]
    assert row["accuracy_active_beats_passive"] is True
    assert row["accuracy_active_beats_passive_decided_only"] is False
