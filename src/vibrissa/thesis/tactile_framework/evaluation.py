"""The tactile framework's episodes scored: tip contacts, decisions over thresholds, the touch map.

Everything here reads the dataset of :mod:`vibrissa.thesis.tactile_framework.protocol` (or a
recording with the same per-contact table) and never the simulator:

* **per policy**: contacts, the fraction whose simulated contact was at the tip, how often the
  pipeline's tip/shaft call was right, the radial-distance error of shaft contacts, the
  repositioning moves;
* **speed-accuracy curves** (Lepora et al.'s active Bayesian perception): at each decision
  threshold, every episode's evidence is accumulated over the contacts its policy feeds to
  "what" (passive and active: those the pipeline called tip; the oracle: the true tip
  contacts), in time order, across whiskers, until the best texture reaches the threshold
  (:func:`vibrissa.classify.accumulate_evidence` on each contact's texture posterior, floored
  at ``MIN_PROBABILITY`` as the pipeline does). Texture, not the joint (angle, texture)
  class: the angle a contact measures is the surface's angle to the whisker, which changes
  as the base moves; the map carries the surface's direction instead. An episode's decision
  is right when it names the texture most of its true tip contacts so far touched; one that
  decided on corner contacts alone is wrong. Contacts and seconds to
  decision count every contact and every second of the episode up to the deciding contact.
  Two accuracies are kept. *At the threshold* scores only the episodes that reached it within
  their budget, so a policy that seldom decides is scored on the episodes easy enough to
  decide (the run's ``decided_fraction`` says how many).
  *With the deadline* scores every episode: one that has not reached the threshold when its
  budget of whisks runs out decides then, on the evidence it has (the accumulator's best
  texture; with no usable contact it names nothing and is wrong), after all its contacts and
  its whole duration. Active and passive are compared on the second, which asks the same
  question of both policies over the same episodes, with a paired bootstrap interval of the
  difference; the first is reported beside it;
* **the touch map** (:class:`vibrissa.framework.mapping.TouchMap`) of each policy from all its
  episodes: occupancy from every contact's estimated point, texture and surface direction from
  the tip contacts, scored by :func:`~vibrissa.framework.mapping.score_touch_map`.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.classify import accumulate_evidence
from vibrissa.framework.mapping import TouchMap, score_touch_map

__all__ = [
    "MIN_PROBABILITY",
    "THRESHOLDS",
    "build_touch_map",
    "compare_policies",
    "deadline_decision",
    "episode_decisions",
    "evaluate_framework",
    "paired_difference",
]

#: Decision thresholds of the speed-accuracy curves.
THRESHOLDS = (0.6, 0.8, 0.9, 0.95, 0.99, 0.999)
#: Floor of a contact's posterior before its log is added (the pipeline's default).
MIN_PROBABILITY = 1e-3
#: Policy codes in the dataset (``ep_policy``), as in the protocol.
POLICIES = ("passive", "active", "oracle")
TIP, SHAFT = 1, 2


def _col(ds: xr.Dataset, key: str) -> np.ndarray:
    return np.asarray(ds[f"ep_{key}"].values)


def _floored_log(lp: np.ndarray) -> np.ndarray:
    p = np.exp(lp - lp.max(axis=-1, keepdims=True))
    p /= p.sum(axis=-1, keepdims=True)
    p = np.maximum(p, MIN_PROBABILITY)
    return np.log(p / p.sum(axis=-1, keepdims=True))


def episode_decisions(
    used: np.ndarray,
    log_proba: np.ndarray,
    truth_class: np.ndarray,
    onset_s: np.ndarray,
    threshold: float,
) -> dict[str, Any]:
    """One episode's decision at ``threshold``.

    Parameters
    ----------
    used : ndarray of bool, shape (n_contacts,)
        Contacts the policy feeds to "what", in time order.
    log_proba : ndarray of shape (n_contacts, n_classes)
        Each contact's log posterior over the joint classes.
    truth_class : ndarray of int, shape (n_contacts,)
        Index of the joint class of each true tip contact, -1 for the others.
    onset_s : ndarray of shape (n_contacts,)
        Onset of each contact on the episode's clock.
    threshold : float

    Returns
    -------
    dict
        ``decided`` (bool), ``correct`` (bool or None), ``class``,
        ``contacts`` (every contact up to the deciding one) and ``seconds``.
    """
    idx = np.flatnonzero(used)
    if idx.size == 0:
        return {"decided": False, "correct": None, "class": None, "contacts": None, "seconds": None}
    lp = _floored_log(log_proba[idx])[None]
    decision, n_used, post = accumulate_evidence(lp, threshold)
    k = int(n_used[0]) - 1
    decided = bool(post[0].max() >= threshold)
    if not decided:
        return {"decided": False, "correct": None, "class": None, "contacts": None, "seconds": None}
    last = int(idx[k])
    seen = truth_class[: last + 1]
    seen = seen[seen >= 0]
    cls = int(decision[0])
    target = int(np.bincount(seen).argmax()) if seen.size else -1
    return {
        "decided": True,
        "correct": bool(cls == target),
        "target": target,
        "class": cls,
        "contacts": last + 1,
        "seconds": float(onset_s[last]),
    }


def deadline_decision(
    used: np.ndarray,
    log_proba: np.ndarray,
    truth_class: np.ndarray,
    onset_s: np.ndarray,
    threshold: float,
    end_s: float,
) -> dict[str, Any]:
    """One episode's decision at ``threshold``, or when its budget runs out.

    An episode that reaches ``threshold`` decides as in :func:`episode_decisions`. One that
    does not decides at the end of its budget (``end_s``, after all its contacts) on the
    texture evidence it has accumulated; with no contact fed to "what" it names nothing, which
    counts as wrong. Its decision is right when it names the texture most of the episode's
    true tip contacts touched.

    Parameters
    ----------
    used, log_proba, truth_class, onset_s, threshold
        As in :func:`episode_decisions`.
    end_s : float
        The episode's end on its clock (the deadline).

    Returns
    -------
    dict
        ``at_threshold`` (bool), ``correct`` (bool), ``class`` (int or None),
        ``contacts`` and ``seconds`` to the decision.
    """
    d = episode_decisions(used, log_proba, truth_class, onset_s, threshold)
    if d["decided"]:
        return {
            "at_threshold": True,
            "correct": d["correct"],
            "class": d["class"],
            "contacts": d["contacts"],
            "seconds": d["seconds"],
        }
    idx = np.flatnonzero(used)
    seen = truth_class[truth_class >= 0]
    cls: int | None = None
    if idx.size:
        cls = int(np.argmax(_floored_log(log_proba[idx]).sum(axis=0)))
    target = int(np.bincount(seen).argmax()) if seen.size else -1
    return {
        "at_threshold": False,
        "correct": cls is not None and cls == target,
        "class": cls,
        "contacts": int(len(used)),
        "seconds": float(end_s),
    }


def paired_difference(
    a: np.ndarray, b: np.ndarray, n_boot: int = 4000, seed: int = 0
) -> dict[str, float]:
    """Mean of ``a - b`` over paired episodes with a 95 % bootstrap interval.

    Parameters
    ----------
    a, b : ndarray of shape (n_episodes,)
        One value per episode for each policy, episodes in the same order.
    n_boot : int, default=4000
        Bootstrap resamples of the episodes.
    seed : int, default=0

    Returns
    -------
    dict
        ``mean``, ``lo``, ``hi`` (the 2.5 and 97.5 percentiles).
    """
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    if d.ndim != 1 or d.size == 0:
        raise ValueError(f"need one value per episode for each policy, got shape {d.shape}")
    rng = np.random.default_rng(seed)
    means = d[rng.integers(0, d.size, size=(n_boot, d.size))].mean(axis=1)
    lo, hi = np.percentile(means, [2.5, 97.5])
    return {"mean": float(d.mean()), "lo": float(lo), "hi": float(hi)}


def _policy_summary(ds: xr.Dataset, sel: np.ndarray, policy: int) -> dict[str, Any]:
    kind = _col(ds, "truth_kind")[sel]
    tip = _col(ds, "tip")[sel].astype(bool)
    matched = kind > 0
    shaft = kind == SHAFT
    err = np.abs(_col(ds, "est_radial_mm")[sel] - _col(ds, "truth_radial_mm")[sel])[shaft]
    mp = np.asarray(ds["move_policy"].values) == policy
    kinds = np.asarray(ds["move_kind"].values)[mp]
    done = np.asarray(ds["move_done"].values)[mp].astype(bool)
    n_ep = len(np.unique(_col(ds, "episode")[sel])) if sel.any() else 0
    return {
        "contacts": int(sel.sum()),
        "episodes_with_contacts": n_ep,
        "matched_contacts": int(matched.sum()),
        "tip_fraction": float(np.mean(kind[matched] == TIP)) if matched.any() else None,
        "tip_shaft_accuracy": (
            float(np.mean(tip[matched] == (kind[matched] == TIP))) if matched.any() else None
        ),
        "shaft_radial_error_mm": float(np.median(err)) if err.size else None,
        "used_for_what": int((kind == TIP).sum() if POLICIES[policy] == "oracle" else tip.sum()),
        "repositions": int(np.count_nonzero((kinds == 1) & done)),
        "bumps": int(np.count_nonzero(kinds == 2)),
        "blocked_moves": int(np.count_nonzero(~done)),
    }


def _texture_log_proba(lp: np.ndarray, textures: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per contact, the log posterior of each texture (the joint classes' marginal)."""
    uniq, inv = np.unique(textures, return_inverse=True)
    p = np.exp(lp - lp.max(axis=1, keepdims=True))
    p /= p.sum(axis=1, keepdims=True)
    marg = np.zeros((lp.shape[0], uniq.size))
    np.add.at(marg.T, inv, p.T)
    return np.log(np.maximum(marg, 1e-300)), uniq


def _episode_end_s(ds: xr.Dataset, policy: int, episode: int, onset: np.ndarray) -> float:
    """The episode's last clock reading: its last move's or its last contact's onset."""
    end = float(onset.max()) if onset.size else 0.0
    if "move_clock_s" in ds:
        sel = (np.asarray(ds["move_policy"].values) == policy) & (
            np.asarray(ds["move_episode"].values) == episode
        )
        if sel.any():
            end = max(end, float(np.asarray(ds["move_clock_s"].values)[sel].max()))
    return end


def _mean(values: list[Any]) -> float | None:
    return float(np.mean(values)) if values else None


def _curves(
    ds: xr.Dataset, thresholds: tuple[float, ...]
) -> tuple[dict[str, list[dict[str, Any]]], dict[str, dict[str, np.ndarray]]]:
    """Texture decisions of every episode at every threshold, per policy.

    The evidence accumulated is each contact's texture posterior (the joint (angle, texture)
    posterior's marginal): texture is the surface's own property, whereas the angle a contact
    reports is the surface's angle to the whisker, which changes whenever the base moves or
    turns; the touch map turns each contact's angle into the surface's direction in the world
    instead (:func:`build_touch_map`).

    Returns
    -------
    curves : dict
        Per policy, one row per threshold: at the threshold (``accuracy``,
        ``contacts_to_decision``, ``seconds_to_decision`` over the episodes that reached it,
        ``decided_fraction``) and with the deadline (``accuracy_with_deadline``,
        ``contacts_with_deadline``, ``seconds_with_deadline`` over every episode,
        ``no_evidence_fraction``).
    paired : dict
        Per policy, ``correct`` and ``contacts`` of shape (n_thresholds, n_episodes) with the
        deadline, episodes in the same order for every policy.
    """
    pol = _col(ds, "policy")
    ep = _col(ds, "episode")
    onset = _col(ds, "onset_s")
    kind = _col(ds, "truth_kind")
    tip = _col(ds, "tip").astype(bool)
    lp_joint = np.asarray(ds["ep_what_log_proba"].values, dtype=float)
    lp, codes = _texture_log_proba(lp_joint, np.asarray(ds["what_texture_code"].values))
    true_tex = _col(ds, "truth_texture_code")
    truth = np.where(kind == TIP, np.searchsorted(codes, true_tex), -1)
    truth[(kind == TIP) & ~np.isin(true_tex, codes)] = codes.size  # a texture never calibrated
    episodes = sorted(set(ep.tolist()))
    out: dict[str, list[dict[str, Any]]] = {}
    paired: dict[str, dict[str, np.ndarray]] = {}
    for p, name in enumerate(POLICIES):
        rows = []
        correct = np.zeros((len(thresholds), len(episodes)), dtype=bool)
        contacts = np.zeros((len(thresholds), len(episodes)))
        inputs = []  # per episode: what its policy feeds to "what", in time order
        for e in episodes:
            sel = np.flatnonzero((pol == p) & (ep == e))
            sel = sel[np.argsort(onset[sel], kind="stable")]
            used = (kind[sel] == TIP) if name == "oracle" else tip[sel]
            end = _episode_end_s(ds, p, e, onset[sel])
            inputs.append((used, lp[sel], truth[sel], onset[sel], end))
        for t, thr in enumerate(thresholds):
            dl = [deadline_decision(u, q, tr, on, thr, end) for u, q, tr, on, end in inputs]
            correct[t] = [d["correct"] for d in dl]
            contacts[t] = [d["contacts"] for d in dl]
            dec = [d for d in dl if d["at_threshold"]]  # decided at the threshold
            rows.append(
                {
                    "threshold": thr,
                    "episodes": len(dl),
                    "decided_fraction": len(dec) / len(dl) if dl else None,
                    "accuracy": _mean([d["correct"] for d in dec]),
                    "contacts_to_decision": _mean([d["contacts"] for d in dec]),
                    "seconds_to_decision": _mean([d["seconds"] for d in dec]),
                    "accuracy_with_deadline": _mean([d["correct"] for d in dl]),
                    "contacts_with_deadline": _mean([d["contacts"] for d in dl]),
                    "seconds_with_deadline": _mean([d["seconds"] for d in dl]),
                    "no_evidence_fraction": (
                        sum(d["class"] is None for d in dl) / len(dl) if dl else None
                    ),
                }
            )
        out[name] = rows
        paired[name] = {"correct": correct, "contacts": contacts}
    return out, paired


def build_touch_map(ds: xr.Dataset, policy: int) -> TouchMap:
    """The touch map of one policy from every contact of its episodes."""
    origin = tuple(float(v) for v in ds.attrs["gt_origin_mm"])
    cell = float(ds.attrs["gt_cell_mm"])
    shape = ds["gt_occupancy"].shape
    textures = np.asarray(ds["what_texture_code"].values, dtype=int)
    angles = np.asarray(ds["what_angle_deg"].values, dtype=float)
    n_tex = int(max(4, textures.max() + 1))
    tm = TouchMap((origin[0], origin[1]), cell, (int(shape[0]), int(shape[1])), n_textures=n_tex)
    sel = np.flatnonzero(_col(ds, "policy") == policy)
    kind = _col(ds, "truth_kind")
    tip = _col(ds, "tip").astype(bool)
    lp = np.asarray(ds["ep_what_log_proba"].values, dtype=float)
    use = (kind == TIP) if POLICIES[policy] == "oracle" else tip
    px, py = _col(ds, "point_x_mm"), _col(ds, "point_y_mm")
    vx, vy = _col(ds, "pivot_x_mm"), _col(ds, "pivot_y_mm")
    rest = np.radians(_col(ds, "rest_dir_deg"))
    prot = np.radians(_col(ds, "prot_dir_deg"))
    for i in sel:
        tex = None
        direction = None
        if use[i]:
            p = np.exp(lp[i] - lp[i].max())
            p /= p.sum()
            tex = np.bincount(textures, weights=p, minlength=n_tex)
            a = math.radians(float(angles[int(np.argmax(p))]))
            # the plane's in-plane direction in the whisker frame: -sin a x + cos a z
            ux = -math.sin(a) * math.cos(prot[i]) + math.cos(a) * math.cos(rest[i])
            uy = -math.sin(a) * math.sin(prot[i]) + math.cos(a) * math.sin(rest[i])
            direction = math.degrees(math.atan2(uy, ux)) % 180.0
        tm.add_contact((vx[i], vy[i]), (px[i], py[i]), tex, direction)
    return tm


def _marginal_argmax(proba: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Per row, the value whose marginal posterior (summed over the joint classes) is largest."""
    uniq, inv = np.unique(values, return_inverse=True)
    marg = np.zeros((proba.shape[0], uniq.size))
    np.add.at(marg.T, inv, proba.T)
    return uniq[np.argmax(marg, axis=1)]


def _transfer_scores(
    truth_kind: np.ndarray,
    truth_angle: np.ndarray,
    truth_texture: np.ndarray,
    tip_call: np.ndarray,
    angle_pred: np.ndarray,
    texture_pred: np.ndarray,
) -> dict[str, Any]:
    tips = truth_kind == TIP
    err = np.abs(angle_pred[tips] - truth_angle[tips])
    return {
        "contacts": int(truth_kind.size),
        "tip_contacts": int(tips.sum()),
        "tip_shaft_accuracy": float(np.mean(tip_call == tips)),
        "texture_accuracy": float(np.mean(texture_pred[tips] == truth_texture[tips]))
        if tips.any()
        else None,
        "angle_error_deg": float(np.median(err)) if err.size else None,
    }


def transfer(ds: xr.Dataset) -> dict[str, Any] | None:
    """Calibration-session models against XY-robot models on the episodes' contacts.

    Every episode contact that a simulated contact explains (all policies pooled): tip/shaft
    called right, texture right on the true tip contacts, median surface-angle error (the
    predicted angle class against the true one). The calibration row reads the pipeline's
    own calls from the dataset; the XY row fits the same estimator (MiniRocket) on the XY
    robot's chapter-4 contacts (where, at 1 kHz) and chapter-5 contacts (what, at 4 kHz),
    windowed by the same detector, and calls the same contacts. ``None`` when the dataset
    holds no XY sessions.
    """
    from vibrissa.classify import MiniRocketClassifier
    from vibrissa.framework import fit_what, fit_where

    if "xy_where_window" not in ds or "xy_what_window" not in ds:
        return None
    sel = _col(ds, "truth_kind") > 0
    kind = _col(ds, "truth_kind")[sel]
    t_angle = _col(ds, "truth_angle_class_deg")[sel]
    t_tex = _col(ds, "truth_texture_code")[sel]
    W = np.asarray(ds["ep_window"].values, dtype=float)[sel]
    fs = float(ds.attrs["sample_rate_hz"])
    params = json.loads(ds.attrs.get("protocol_params", "{}"))
    length = float(json.loads(ds.attrs["whisker"])["length_mm"])
    tip_r = length - float(params.get("tip_zone_mm", 5.0))
    angles = np.asarray(ds["what_angle_deg"].values, dtype=float)
    textures = np.asarray(ds["what_texture_code"].values, dtype=float)
    lp = np.asarray(ds["ep_what_log_proba"].values, dtype=float)[sel]
    p = np.exp(lp - lp.max(axis=1, keepdims=True))
    p /= p.sum(axis=1, keepdims=True)
    calibration = _transfer_scores(
        kind,
        t_angle,
        t_tex,
        _col(ds, "tip")[sel].astype(bool),
        _marginal_argmax(p, angles),
        _marginal_argmax(p, textures),
    )
    rate_w = float(ds.attrs["xy_where_rate_hz"])
    where = fit_where(
        MiniRocketClassifier(sample_rate_hz=rate_w),
        np.asarray(ds["xy_where_window"].values, dtype=float),
        np.asarray(ds["xy_where_labels"].values, dtype=float),
        rate_w,
        rate_w,
        tip_radial_distance_mm=tip_r,
        speed_column=1,
    )
    pw = where.predict_proba(W, fs)
    tip_xy = pw[:, where.classes[:, 0] >= tip_r].sum(axis=1) >= 0.5
    rate_h = float(ds.attrs["xy_what_rate_hz"])
    what = fit_what(
        MiniRocketClassifier(sample_rate_hz=rate_h),
        np.asarray(ds["xy_what_window"].values, dtype=float),
        np.asarray(ds["xy_what_labels"].values, dtype=float),
        rate_h,
        rate_h,
        angle_column=0,
        texture_column=2,
    )
    ph = what.predict_proba(W, fs)
    xy = _transfer_scores(
        kind,
        t_angle,
        t_tex,
        tip_xy,
        _marginal_argmax(ph, what.classes[:, 0]),
        _marginal_argmax(ph, what.classes[:, 2]),
    )
    xy["training_contacts"] = {
        "where": int(ds.sizes["xy_where"]),
        "what": int(ds.sizes["xy_what"]),
    }
    xy["datasets"] = [ds.attrs.get("xy_where_dataset"), ds.attrs.get("xy_what_dataset")]
    xy["tip_radial_classes_mm"] = sorted({float(r) for r in where.classes[:, 0] if r >= tip_r})
    calibration["training_contacts"] = int(ds.sizes["trial"])
    return {"calibration": calibration, "xy_robot": xy}


def evaluate_framework(
    ds: xr.Dataset, thresholds: tuple[float, ...] = THRESHOLDS
) -> dict[str, Any]:
    """Every figure of the tactile-framework report, JSON-ready."""
    pol = _col(ds, "policy")
    kind_c = np.asarray(ds["kind"].values)
    calibration = {
        "contacts": int(ds.sizes["trial"]),
        "tip_contacts": int(np.count_nonzero(kind_c == TIP)),
        "shaft_contacts": int(np.count_nonzero(kind_c == SHAFT)),
        "what_classes": int(ds.sizes["what_class"]),
        "radial_classes_mm": sorted({float(v) for v in ds["radial_class_mm"].values}),
    }
    policies = {name: _policy_summary(ds, pol == p, p) for p, name in enumerate(POLICIES)}
    curves, paired = _curves(ds, thresholds)
    maps = {}
    for p, name in enumerate(POLICIES):
        tm = build_touch_map(ds, p)
        maps[name] = score_touch_map(
            tm,
            ds["gt_occupancy"].values,
            ds["gt_texture_code"].values,
            ds["gt_face_direction_deg"].values,
            ds["gt_arena"].values.astype(bool),
        )
    from vibrissa.data.schema import decode_texture

    textures = sorted({int(t) for t in ds["what_texture_code"].values})
    return {
        "meta": {"protocol": json.loads(ds.attrs.get("protocol_params", "{}"))},
        "parameters": {
            "radial_distance_mm": {
                "coordinate": "radial_class_mm",
                "unit": "mm",
                "values": calibration["radial_classes_mm"],
            },
            "angle_deg": {
                "coordinate": "what_angle_deg",
                "unit": "deg",
                "values": sorted({float(a) for a in ds["what_angle_deg"].values}),
            },
            "texture": {
                "coordinate": "what_texture_code",
                "unit": "name",
                "values": [str(t) for t in decode_texture(textures)],
            },
        },
        "classifiers": {
            "where": "MiniRocket on the 4 kHz contact window: radial-distance class; p_tip the "
            "posterior mass of the tip class",
            "what": "MiniRocket on the 4 kHz contact window: joint (angle class, texture); "
            "texture evidence summed over contacts and whiskers",
        },
        "calibration": calibration,
        "policies": policies,
        "curves": curves,
        "maps": maps,
        "comparison": compare_policies(curves, paired),
        "transfer": transfer(ds),
    }


def compare_policies(
    curves: dict[str, list[dict[str, Any]]],
    paired: dict[str, dict[str, np.ndarray]] | None = None,
) -> dict[str, Any]:
    """Whether active beats passive at every threshold, and the gap to the oracle.

    Active beats passive at a threshold when its accuracy with the deadline is higher and its
    contacts to decision with the deadline fewer (every episode scored: see the module's
    docstring); the same comparison over only the episodes that reached the threshold is
    reported beside it (``*_decided_only``). Rows without the deadline columns (older results)
    are compared at the threshold.

    Parameters
    ----------
    curves : dict
        Per policy, the rows of :func:`_curves`.
    paired : dict, optional
        Per policy, per-episode ``correct`` and ``contacts`` with the deadline (shape
        (n_thresholds, n_episodes)): adds the paired bootstrap interval of active minus
        passive at each threshold.
    """

    def better(x: float | None, y: float | None, higher: bool) -> bool | None:
        if x is None or y is None:
            return None
        return x > y if higher else x < y

    def gap(x: float | None, y: float | None) -> float | None:
        return None if x is None or y is None else x - y

    rows = []
    for t, (a, p, o) in enumerate(
        zip(curves["active"], curves["passive"], curves["oracle"], strict=True)
    ):
        acc = "accuracy_with_deadline" if "accuracy_with_deadline" in a else "accuracy"
        con = "contacts_with_deadline" if "contacts_with_deadline" in a else "contacts_to_decision"
        row: dict[str, Any] = {
            "threshold": a["threshold"],
            "accuracy_active_beats_passive": better(a[acc], p[acc], True),
            "contacts_active_beats_passive": better(a[con], p[con], False),
            "accuracy_active_beats_passive_decided_only": better(
                a["accuracy"], p["accuracy"], True
            ),
            "contacts_active_beats_passive_decided_only": better(
                a["contacts_to_decision"], p["contacts_to_decision"], False
            ),
            "accuracy_gap_to_oracle": gap(o[acc], a[acc]),
            "contacts_gap_to_oracle": gap(a[con], o[con]),
            "accuracy_gap_to_oracle_decided_only": gap(o["accuracy"], a["accuracy"]),
            "contacts_gap_to_oracle_decided_only": gap(
                a["contacts_to_decision"], o["contacts_to_decision"]
            ),
        }
        if paired is not None:
            act, pas = paired["active"], paired["passive"]
            row["accuracy_gain_over_passive"] = paired_difference(
                act["correct"][t], pas["correct"][t]
            )
            row["contacts_saved_over_passive"] = paired_difference(
                pas["contacts"][t], act["contacts"][t]
            )
        rows.append(row)

    def everywhere(key: str) -> bool:
        return bool(rows) and all(r[f"accuracy_{key}"] and r[f"contacts_{key}"] for r in rows)

    return {
        "per_threshold": rows,
        "rule": "with the deadline: every episode decides, at the threshold or when its "
        "budget runs out",
        "active_beats_passive_everywhere": everywhere("active_beats_passive"),
        "active_beats_passive_everywhere_decided_only": everywhere(
            "active_beats_passive_decided_only"
        ),
    }
