"""The tactile framework of thesis 2.5 as a closed loop in a box world: calibrate, then explore.

Thesis 2.5 (figure 2.17): the whiskers whisk; at each contact a "tip or shaft" decision is
made from the radial distance (chapter 4); after a shaft contact -- in the box world always a
corner, "the tip would flick past the object" (2.5.1) -- the whiskers are repositioned so
that the next contact is at the tip; a tip contact is classified for surface angle and
texture (chapter 5); the results feed a map (6.5). Section 7.2 names putting these on one
whisking mobile robot as the first future work. Here:

* **the world** (:mod:`vibrissa.robots.boxworld`): square-cornered, straight-sided boxes
  ("the floor of a house or office where all the furniture either have straight sides, or
  square legs", 2.5) in a walled room, every face one of the four chapter-5 textures;
* **the robot**: a whisking head of ``n_whiskers`` straight whiskers on one side of a mobile
  base (:class:`~vibrissa.robots.boxworld.WhiskingHead`); each step it whisks once where it
  stands, then the base moves with the whiskers retracted (the CrunchBot "mini-whisk",
  6.5.3). While it moves the Hall sensors read their rest output (with their noise);
* **perception** is :class:`vibrissa.framework.TactilePipeline`, fed the head's Hall stream
  sample by sample as a robot would feed it; its reports drive the policy;
* **calibration session**: before the episodes the robot patrols, passively and with
  detection only, ``n_calibration`` whisks in the calibration rig (``calibration_world``: two
  boxes and four walls carrying each texture about equally); every detected contact that a
  simulated contact explains is labelled from the simulator's ground truth (radial distance
  class, or "tip"; surface angle class and texture for tip contacts) and the pipeline's where
  and what models are fitted on them;
* **the XY robot's sessions** (the transfer comparison): chapter 4's and chapter 5's quick
  grids on the XY robot with the same whisker, windowed by the same detector;
* **episodes**: a patrol past a face of the exploration world (``world``) starting at a random
  point beside it, ``n_whisks`` whisk-and-step cycles, under three policies with the same
  starts and seeds -- ``passive`` (whisk and step, never reposition), ``active`` (after a
  contact the pipeline calls shaft, move back along that whisker's direction at contact by
  the estimated distance to the tip plus ``margin_mm``: the "microsaccade" of 2.5.1) and
  ``oracle`` (the same move by the true distance, after true shaft contacts, and only true tip
  contacts feed "what": every contact that is used is a tip contact, the upper bound).

An episode never stops at a decision: every per-contact posterior is kept, so the evaluation
replays the evidence accumulation at any decision threshold (the speed-accuracy curves of
Lepora et al.'s active Bayesian perception). The dataset holds the calibration contacts'
windows as ``signal`` (one trial per contact), a per-contact table of the episodes (``ep_*``
variables on a ``contact`` dimension) with each contact's window, the moves (``move_*``), the
XY sessions' windows and labels (``xy_*``) and the exploration world's ground truth on the
map's grid (``gt_*``).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa import __version__
from vibrissa._processes import imap_unordered
from vibrissa._validate import positive
from vibrissa.classify import MiniRocketClassifier
from vibrissa.data.schema import TEXTURE_CODES
from vibrissa.experiments.contract import SelfGenerating
from vibrissa.experiments.streams import stream
from vibrissa.framework import (
    DetectorSettings,
    TactilePipeline,
    contact_windows,
    default_what_estimator,
    fit_what,
    fit_where,
    model_windows,
)
from vibrissa.robots.boxworld import (
    HeadPose,
    WhiskingHead,
    box_world,
    can_move,
    first_contact,
    whisk,
    whisker_frame,
)
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import SimulationError

__all__ = [
    "ANGLE_BIN_DEG",
    "POLICIES",
    "FrameworkProtocol",
    "KIND_CODES",
    "angle_class",
    "framework_protocol",
    "radial_class",
]

#: The three policies, in the order of every table.
POLICIES = ("passive", "active", "oracle")
#: Ground-truth kind of a detected contact: 0 none (no simulated contact matches it).
KIND_CODES = {"none": 0, "tip": 1, "shaft": 2}
#: Width of a surface-angle class (deg): classes are centred on 15, 45, 75 deg.
ANGLE_BIN_DEG = 30.0
#: The touch map's cell (mm; the thesis' SLAM grid used 50 mm, 6.5.6) and its overspill
#: beyond the room on every side (mm; the thesis' grid doubled the arena's size).
MAP_CELL_MM = 25.0
MAP_OVERSPILL_MM = 250.0
#: An episode starts at least this far from every solid, so a reposition has room (mm).
START_CLEARANCE_MM = 150.0
#: After a bump (a whisker resting against a solid at the start of a whisk) the base backs
#: away sideways by this much (mm) and turns away by this much (deg), as CrunchBot turns
#: away after a collision (6.5.3).
BUMP_SIDESTEP_MM = 30.0
BUMP_TURN_DEG = 15.0
#: The where model: MiniRocket (beyond the thesis; the chapter-5 line-up's best, whose
#: logistic head gives calibrated posteriors) on the 4 kHz stream. Measured on the
#: calibration patrols (124 contacts, 4-fold stratified cross-validation, tip/shaft right):
#: MiniRocket 0.91, chapter 4's template (4.3.3, 1 kHz) 0.83, frequency 0.79, naive Bayes
#: raw 0.77 (on velocity 0.42: too few contacts per class for its histograms). The template
#: wins on argmax but its posterior (a softmax of L1 distances) is not calibrated: on a quick
#: run's episodes it gave p_tip 0.4-0.5 to most tip contacts, so the marginal tip/shaft call
#: (p_tip >= 0.5) was right for 14 % of the active policy's contacts; MiniRocket fitted on
#: the same calibration called 74 % of those contacts right.
WHERE_RATE_HZ = 4000.0
#: Width of a radial-distance class of shaft contacts (mm).
RADIAL_BIN_MM = 20.0
#: Extra time (s) a detected contact may start before or end after its simulated contact.
MATCH_SLACK_S = 0.05
#: The detector for every stream of this experiment: the chapter-4 author's 0.1 V onset
#: threshold; a 0.4 s window, which covers a contact ended by the head's 0.3 s reflex.
DETECTOR = DetectorSettings(threshold=0.1, pre_s=0.02, window_s=0.4, hold_s=0.02)


def angle_class(angle_deg: float | np.ndarray) -> np.ndarray:
    """Surface-angle class (deg, the bin's centre) of angles (deg)."""
    a = np.asarray(angle_deg, dtype=float)
    return ANGLE_BIN_DEG * np.floor(a / ANGLE_BIN_DEG) + ANGLE_BIN_DEG / 2


def radial_class(kind: str, radial_mm: float, length_mm: float, tip_zone_mm: float) -> float:
    """Radial-distance class (mm) of a contact: the whisker's length for a tip contact.

    A corner's class is the centre of its ``RADIAL_BIN_MM`` bin, kept below the tip zone
    (a corner within the tip zone gets the last bin below it).
    """
    if kind == "tip":
        return float(length_mm)
    c = RADIAL_BIN_MM * math.floor(radial_mm / RADIAL_BIN_MM) + RADIAL_BIN_MM / 2
    return float(min(c, length_mm - tip_zone_mm - RADIAL_BIN_MM / 2))


@dataclass(frozen=True)
class FrameworkProtocol(SelfGenerating):
    """The calibration session and the episodes (see the module docstring).

    Parameters
    ----------
    world, calibration_world
        Box-world presets explored and calibrated on.
    head
        The whisking head.
    n_calibration
        Calibration whisks (passive patrols of ``n_whisks`` whisks in ``calibration_world``).
    n_episodes, n_whisks
        Episodes per policy, whisk-and-step cycles per episode. Active and passive are
        compared episode by episode (paired); at 20 episodes the 95 % interval of the
        accuracy difference was about +-0.2 wide (the 20-episode run of
        docs/runs/framework.json at 7cc5204, re-scored with
        :func:`~.evaluation.paired_difference`), too wide to rank the policies, so the
        full run has 40.
    step_mm, margin_mm
        The patrol's step along the heading per whisk; the extra distance of a reposition
        beyond the estimated distance to the tip.
    base_speed_mm_s
        Speed of the base while it moves (the episode clock: a move takes distance / speed).
    odometry_noise
        Relative standard deviation of the odometry per move (CrunchBot's odometry is
        "accurate to about 10 % of any movement", 6.5.4).
    transfer
        Also simulate the XY robot's quick chapter-4/5 sessions for the transfer comparison
        (:meth:`xy_sessions`; off in the quick run, which checks the loop end to end).
    tip_zone_mm
        A contact is called a tip contact when its radial distance is estimated within
        this of the length (5 mm: "Contacts at less than 5 mm from the tip did not
        deflect the base ... before slipping past", thesis 4.2).
    seed
        Seed of every random stream.
    """

    world: str = "furniture"
    calibration_world: str = "calibration"
    head: WhiskingHead = dataclasses.field(default_factory=WhiskingHead)
    n_calibration: int = 1200
    n_episodes: int = 40
    n_whisks: int = 20
    step_mm: float = 10.0
    margin_mm: float = 5.0
    base_speed_mm_s: float = 100.0
    odometry_noise: float = 0.1
    tip_zone_mm: float = 5.0
    transfer: bool = True
    seed: int = 0
    name: str = "tactile-framework"

    def __post_init__(self) -> None:
        for key in ("n_calibration", "n_episodes", "n_whisks"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ValueError(f"{key} must be a positive integer, got {v!r}")
        for key in ("step_mm", "base_speed_mm_s", "tip_zone_mm"):
            positive(key, getattr(self, key))
        if not 0.0 <= float(self.margin_mm) < 100.0:
            raise ValueError(f"margin_mm must lie in [0, 100) mm, got {self.margin_mm!r}")
        if not 0.0 <= float(self.odometry_noise) < 1.0:
            raise ValueError(f"odometry_noise must lie in [0, 1), got {self.odometry_noise!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {self.seed!r}")
        box_world(self.world)
        box_world(self.calibration_world)

    # ------------------------------------------------------------------ bookkeeping
    @property
    def n_trials(self) -> int:
        """Whisks of the session: calibration plus every policy's episodes."""
        return self.n_calibration + len(POLICIES) * self.n_episodes * self.n_whisks

    @property
    def length_mm(self) -> float:
        """The head's whisker length (mm)."""
        return float(preset(self.head.whisker).length_mm)

    @property
    def tip_radial_distance_mm(self) -> float:
        """Radial distance from which a contact counts as at the tip (mm)."""
        return self.length_mm - self.tip_zone_mm

    def to_dict(self) -> dict[str, Any]:
        """Every parameter as plain values."""
        return dataclasses.asdict(self)

    def fingerprint(self) -> str:
        """Hash of every parameter and of the code that makes the dataset.

        The code: this module, the box world and the framework's sources (a closed loop's
        dataset depends on the pipeline that drove it), so a cached dataset is never reused
        by other code.
        """
        blob = json.dumps(
            {**self.to_dict(), "v": __version__, "code": _code_digest()},
            sort_keys=True,
            default=str,
        )
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    # ------------------------------------------------------------------ calibration
    @property
    def n_calibration_episodes(self) -> int:
        """Episodes of the calibration session (``n_calibration`` whisks in all)."""
        return -(-self.n_calibration // self.n_whisks)

    def calibration_episode(self, index: int) -> dict[str, Any]:
        """Calibration episode ``index``: a passive patrol in ``calibration_world``.

        Detection only (no models yet); every detected contact that a simulated contact
        explains becomes a labelled training contact.
        """
        return _Episode(self, "passive", index, None, calibration=True).run()

    def calibrate(
        self, workers: int | None = 1, progress: Callable[[int, int], None] | None = None
    ) -> dict[str, np.ndarray]:
        """The calibration session: passive patrols in the calibration world, labelled.

        The robot explores as it will in the episodes (the same head, patrol and bumps), so
        the classifiers see the contacts the episodes make; each contact's labels come from
        the simulator's ground truth.
        """
        n = self.n_calibration_episodes

        def tick(done: int) -> None:
            if progress:
                progress(done * self.n_whisks, self.n_trials)

        done = _in_order(self.calibration_episode, n, workers, tick)
        rows = [r for d in done for r in d["rows"] if r["truth_kind"] > 0]
        if not rows:
            raise RuntimeError("the calibration session detected no contact")
        kinds = {v: k for k, v in KIND_CODES.items()}
        out: dict[str, np.ndarray] = {
            "kind": np.array([r["truth_kind"] for r in rows]),
            "radial_distance_mm": np.array([r["truth_radial_mm"] for r in rows]),
            "radial_class_mm": np.array(
                [
                    radial_class(
                        kinds[r["truth_kind"]],
                        r["truth_radial_mm"],
                        self.length_mm,
                        self.tip_zone_mm,
                    )
                    for r in rows
                ]
            ),
            "angle_class_deg": np.array([r["truth_angle_class_deg"] for r in rows]),
            "texture_code": np.array([r["truth_texture_code"] for r in rows]),
            "whisk": np.array([r["episode"] * self.n_whisks + r["whisk"] for r in rows]),
            "window": np.stack([r["window"] for r in rows]).astype(float),
        }
        out["failed_whisks"] = np.array(sum(d["failed_whisks"] for d in done))
        return out

    def labels(self, truth: Any) -> dict[str, Any]:
        """The class labels of a simulated contact (``None``: no contact, kind 0)."""
        if truth is None:
            return {
                "kind": 0,
                "radial_distance_mm": math.nan,
                "radial_class_mm": math.nan,
                "angle_deg": math.nan,
                "angle_class_deg": math.nan,
                "texture_code": -1,
            }
        tip = truth.kind == "tip"
        return {
            "kind": KIND_CODES[truth.kind],
            "radial_distance_mm": float(truth.radial_distance_mm),
            "radial_class_mm": radial_class(
                truth.kind, float(truth.radial_distance_mm), self.length_mm, self.tip_zone_mm
            ),
            "angle_deg": float(truth.surface_angle_deg) if tip else math.nan,
            "angle_class_deg": float(angle_class(truth.surface_angle_deg)) if tip else math.nan,
            "texture_code": TEXTURE_CODES[truth.texture] if tip else -1,
        }

    def fit_pipeline(self, calib: dict[str, np.ndarray]) -> TactilePipeline:
        """The pipeline with where and what fitted on the calibration contacts."""
        fs = self.head.sample_rate_hz
        X = calib["window"]
        where = fit_where(
            MiniRocketClassifier(sample_rate_hz=WHERE_RATE_HZ),
            X,
            calib["radial_class_mm"][:, None],
            fs,
            WHERE_RATE_HZ,
            tip_radial_distance_mm=self.tip_radial_distance_mm,
            speed_column=None,
        )
        tip = calib["kind"] == KIND_CODES["tip"]
        if (
            len(
                {
                    (a, t)
                    for a, t in zip(
                        calib["angle_class_deg"][tip], calib["texture_code"][tip], strict=True
                    )
                }
            )
            < 2
        ):
            raise RuntimeError("the calibration session has fewer than two surface classes")
        what = fit_what(
            default_what_estimator(fs),
            X[tip],
            np.column_stack([calib["angle_class_deg"][tip], calib["texture_code"][tip]]),
            fs,
            fs,
            angle_column=0,
            texture_column=1,
        )
        return self.new_pipeline(where, what)

    def new_pipeline(self, where: Any, what: Any) -> TactilePipeline:
        """A fresh pipeline for one episode (decisions are replayed offline at any threshold)."""
        return TactilePipeline(
            self.head.sample_rate_hz,
            self.head.n_whiskers,
            2,
            detector=DETECTOR,
            where=where,
            what=what,
            decision_threshold=0.99,
            reset_after_decision=False,
        )

    # ------------------------------------------------------------------ episodes
    def episode_start(self, index: int, calibration: bool = False) -> HeadPose:
        """The start pose of episode ``index`` (the same for every policy).

        ``calibration``: of the calibration session's episode ``index`` instead, in
        ``calibration_world``.

        A pose from which a whisker would meet a face of a box (:func:`_pose_beside`), backed
        off 1-4 patrol steps along the heading, clear of every solid by the body's radius and
        with no whisker resting against anything.
        """
        world = box_world(self.calibration_world if calibration else self.world)
        rng = np.random.default_rng(stream(self.seed, 5 if calibration else 2, index))
        faces = [f for f in world.faces if f.box >= 0]
        for _ in range(500):
            face = faces[int(rng.integers(len(faces)))]
            pose = _pose_beside(face, self.head, self.length_mm, rng, near_corner=index % 2 == 1)
            pose = pose.moved(-self.p_step() * rng.uniform(1.0, 4.0))
            if world.clearance_mm((pose.x_mm, pose.y_mm)) <= START_CLEARANCE_MM:
                continue
            geo = [first_contact(world, pose, self.head, i) for i in range(self.head.n_whiskers)]
            if any(g is not None and g.kind in ("pressed", "grazing") for g in geo):
                continue
            ahead = [pose.moved(self.p_step() * j) for j in range(5)]
            if any(
                g is not None and g.kind in ("tip", "shaft")
                for q in ahead
                for g in (
                    first_contact(world, q, self.head, i) for i in range(self.head.n_whiskers)
                )
            ):
                return pose
        raise RuntimeError(f"no clear start pose for episode {index}")

    def p_step(self) -> float:
        """The patrol's step (mm)."""
        return float(self.step_mm)

    def run_episode(self, policy: str, index: int, pipeline: TactilePipeline) -> dict[str, Any]:
        """One episode under ``policy``: every contact with its report and its truth."""
        return _Episode(self, policy, index, pipeline).run()

    def ground_truth(self) -> dict[str, Any]:
        """The exploration world on the map's grid: the room plus ``MAP_OVERSPILL_MM`` around it.

        ``arena`` marks the cells whose centre lies inside the room (eq. 6.3 "over the arena").
        """
        world = box_world(self.world)
        if world.room is None:
            raise ValueError(f"world {self.world!r} has no room: the map needs one")
        x0, y0, x1, y1 = world.room
        m = MAP_OVERSPILL_MM
        gt = world.ground_truth(MAP_CELL_MM, (x0 - m, y0 - m, x1 + m, y1 + m))
        nx, ny = gt["shape"]
        xc = gt["origin_mm"][0] + (np.arange(nx) + 0.5) * MAP_CELL_MM
        yc = gt["origin_mm"][1] + (np.arange(ny) + 0.5) * MAP_CELL_MM
        X, Y = np.meshgrid(xc, yc, indexing="ij")
        gt["arena"] = ((X > x0) & (X < x1) & (Y > y0) & (Y < y1)).astype(np.int8)
        return gt

    # ------------------------------------------------------------------ generation
    def generate_dataset(
        self,
        path: Path,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        **kwargs: Any,
    ) -> xr.Dataset:
        """Calibrate, fit the pipeline, run every episode; save the dataset to ``path``."""
        from vibrissa.data import save_dataset

        calib = self.calibrate(workers, progress)
        pipeline = self.fit_pipeline(calib)
        xy = self.xy_sessions(Path(path).parent, workers) if self.transfer else None
        jobs = [(p, i) for p in POLICIES for i in range(self.n_episodes)]

        def job(k: int) -> dict[str, Any]:
            p, i = jobs[k]
            return self.run_episode(p, i, pipeline)

        def tick(done: int) -> None:
            if progress:
                progress(self.n_calibration + done * self.n_whisks, self.n_trials)

        results = _in_order(job, len(jobs), workers, tick)
        ds = self.build_dataset(calib, results, pipeline, xy)
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        save_dataset(ds, path)
        return ds

    def xy_sessions(self, data_dir: Path, workers: int | None) -> dict[str, Any]:
        """The XY robot's quick chapter-4 and chapter-5 sessions, cut by this detector.

        The transfer comparison's training data: the same whisker on the XY robot, its
        contacts windowed exactly as the pipeline windows this head's (``DETECTOR``). The
        datasets are kept in ``data_dir`` under the names a reproduction of those
        chapters uses there (``<protocol>-<fingerprint>.nc``), so either run reuses the
        other's.
        """
        from vibrissa.data import load_dataset
        from vibrissa.experiments.generate import generate
        from vibrissa.experiments.protocols import get_protocol
        from vibrissa.framework.calibrate import WHAT_LABELS, WHERE_LABELS, trial_windows

        out: dict[str, Any] = {}
        for role, name, labels in (
            ("where", "radial-distance", WHERE_LABELS),
            ("what", "angle-texture", WHAT_LABELS),
        ):
            proto = get_protocol(name, quick=True, seed=self.seed)
            f = Path(data_dir) / f"{proto.name}-{proto.fingerprint()}.nc"
            try:
                ds = load_dataset(f)
            except (OSError, ValueError):
                made = generate(proto, f, workers=workers)
                ds = made if made is not None else load_dataset(f)
            tw = trial_windows(ds, labels, DETECTOR)
            out[role] = {
                "window": tw.windows.astype(np.float32),
                "labels": tw.labels,
                "sample_rate_hz": tw.sample_rate_hz,
                "dataset": f.name,
                "missed": tw.n_missed,
            }
        return out

    def build_dataset(
        self,
        calib: dict[str, np.ndarray],
        episodes: list[dict[str, Any]],
        pipeline: TactilePipeline,
        xy: dict[str, Any] | None = None,
    ) -> xr.Dataset:
        """The calibration contacts as trials and the episodes' contacts as a table."""
        from vibrissa.data.dataset import coordinate_attrs

        fs = self.head.sample_rate_hz
        X = calib["window"]
        coords: dict[str, Any] = {
            "trial": np.arange(X.shape[0]),
            "channel": np.array(["x", "y"]),
            "time": ("time", np.arange(X.shape[2]) / fs, {"units": "s"}),
        }
        for key in (
            "kind",
            "radial_distance_mm",
            "radial_class_mm",
            "angle_class_deg",
            "texture_code",
            "whisk",
        ):
            coords[key] = ("trial", calib[key], coordinate_attrs(key, calib[key]))
        data: dict[str, Any] = {"signal": (("trial", "channel", "time"), X, {"units": "V"})}
        table = _join_episodes(episodes, X.shape[2])
        if pipeline.what is None:
            raise ValueError("the pipeline has no what model: the dataset needs its classes")
        what_classes = np.asarray(pipeline.what.estimator.classes_, dtype=np.float64)
        for key, arr in table.items():
            dims = ("contact",) + tuple(f"{key}_{j}" for j in range(arr.ndim - 1))
            if key == "window":
                dims = ("contact", "channel", "time")
            elif key == "what_log_proba":
                dims = ("contact", "what_class")
            data[f"ep_{key}"] = (dims, arr)
        moves = _join_moves(episodes)
        for key, arr in moves.items():
            data[f"move_{key}"] = (("move",), arr)
        coords["what_class"] = np.arange(what_classes.shape[0])
        coords["what_angle_deg"] = ("what_class", what_classes[:, 0])
        coords["what_texture_code"] = ("what_class", what_classes[:, 1].astype(int))
        attrs_xy: dict[str, Any] = {}
        for role, d in (xy or {}).items():
            data[f"xy_{role}_window"] = ((f"xy_{role}", "channel", f"xy_{role}_time"), d["window"])
            data[f"xy_{role}_labels"] = ((f"xy_{role}", f"xy_{role}_label"), d["labels"])
            attrs_xy[f"xy_{role}_rate_hz"] = float(d["sample_rate_hz"])
            attrs_xy[f"xy_{role}_dataset"] = d["dataset"]
            attrs_xy[f"xy_{role}_missed"] = int(d["missed"])
        world = box_world(self.world)
        gt = self.ground_truth()
        for key in ("occupancy", "texture_code", "face_direction_deg", "arena"):
            data[f"gt_{key}"] = (("gx", "gy"), np.asarray(gt[key]))
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "sample_rate_hz": float(fs),
                "whisker": json.dumps(
                    dataclasses.asdict(preset(self.head.whisker)), sort_keys=True, default=str
                ),
                "protocol": self.name,
                "protocol_params": json.dumps(self.to_dict(), sort_keys=True, default=str),
                "world": json.dumps(world.to_dict(), sort_keys=True),
                "gt_origin_mm": np.asarray(gt["origin_mm"], dtype=float),
                "gt_cell_mm": float(gt["cell_mm"]),
                "seed": int(self.seed),
                "vibrissa_version": __version__,
                "source": "simulated: a whisking head in a tactile box world (thesis 2.5)",
                **attrs_xy,
            },
        )


def _pose_beside(
    face: Any,
    head: WhiskingHead,
    length_mm: float,
    rng: np.random.Generator,
    near_corner: bool = False,
) -> HeadPose:
    """A pose from which one whisker's protraction meets ``face`` (or a corner beyond it).

    The head's whiskers rest pointing sideways and protract forward, so a surface is met
    when it lies ahead on their side. Drawn: a whisker ``i``, the sweep at which its straight
    shaft would reach the face's line (5-35 deg into the whisk), the angle between the whisker
    and the face's normal there (20-70 deg, so the surface angle to the whisker is 20-70
    deg) and the point of the line (from 0.5 face lengths before its start to 0.5 after its
    end: beyond the ends a corner is met on the shaft; ``near_corner``: within a quarter
    of its length of one end). The pose puts whisker ``i``'s tip on
    that point at that sweep; whether the tip, a corner or nothing is met first, and whether
    another whisker rests against the box, is the simulator's answer, not assumed.
    """
    a = np.asarray(face.start_mm, dtype=float)
    b = np.asarray(face.end_mm, dtype=float)
    n = np.asarray(face.normal, dtype=float)
    i = int(rng.integers(head.n_whiskers))
    sweep = rng.uniform(5.0, min(35.0, head.amplitude_deg - 2.0))
    alpha = rng.uniform(20.0, 70.0)
    theta = head.retracted_deg[i] - sweep  # from the heading toward the whiskers' side
    beta = theta - alpha  # bearing of the face's inward normal (-n) from the heading
    heading = math.degrees(math.atan2(-n[1], -n[0])) - head.side * beta
    if near_corner:  # within a quarter of the face's length of one of its ends
        u = rng.uniform(-0.25, 0.25)
        c = (a if u < 0 else b) + u * (b - a)
    else:
        c = a + rng.uniform(-0.5, 1.5) * (b - a)
    w = math.radians(heading + head.side * theta)
    pivot = c - length_mm * np.array([math.cos(w), math.sin(w)])
    p0, _, _ = whisker_frame(HeadPose(0.0, 0.0, heading), head, i)
    return HeadPose(float(pivot[0] - p0[0]), float(pivot[1] - p0[1]), float(heading))


def _match(whisker: int, onset_s: float, end_s: float, rec: Any) -> Any | None:
    """The simulated contact of ``whisker`` in ``rec`` that a detected contact belongs to."""
    c = rec.contacts[whisker]
    t0 = float(np.ravel(rec.truth_onsets_s[whisker])[0])
    t1 = float(np.ravel(rec.truth_ends_s[whisker])[0])
    if c is None or not math.isfinite(t0):
        return None
    if onset_s < t0 - MATCH_SLACK_S or onset_s > t1 + MATCH_SLACK_S:
        return None
    return c


class _Episode:
    """The closed loop of one episode: whisk, wait for the reports, decide, move."""

    #: Seconds the robot waits after a whisk for the pipeline's reports before it moves.
    SETTLE_S = 0.1

    def __init__(
        self,
        protocol: FrameworkProtocol,
        policy: str,
        index: int,
        pipeline: TactilePipeline | None,
        calibration: bool = False,
    ) -> None:
        if policy not in POLICIES:
            raise ValueError(f"policy must be one of {POLICIES}, got {policy!r}")
        self.p = protocol
        self.policy = policy
        self.index = index
        self.world = box_world(protocol.calibration_world if calibration else protocol.world)
        self.head = protocol.head
        if pipeline is None:  # the calibration session: detection only
            self.pipe = protocol.new_pipeline(None, None)
        else:
            self.pipe = protocol.new_pipeline(pipeline.where, pipeline.what)
        # the same physics and odometry noise for every policy: streams by episode only
        key = (6, 7) if calibration else (3, 4)
        self.rng = np.random.default_rng(stream(protocol.seed, key[0], index))
        self.odo_rng = np.random.default_rng(stream(protocol.seed, key[1], index))
        self.pose = protocol.episode_start(index, calibration)
        self.odom = self.pose
        self.fed: list[np.ndarray] = []
        self.samples = 0
        self.rows: list[dict[str, Any]] = []
        self.moves: list[dict[str, Any]] = []
        self.bumps = 0
        self.failed = 0
        #: (record, first sample, whisk index, odometry pose) of the last whisk
        self.last: tuple[Any, int, int, HeadPose] | None = None

    @property
    def clock_s(self) -> float:
        """Seconds since the episode began (whisks, waits and moves)."""
        return self.samples / self.head.sample_rate_hz

    def run(self) -> dict[str, Any]:
        """Run every whisk-and-move cycle; the contacts, moves and bumps."""
        for k in range(self.p.n_whisks):
            self._cycle(k)
        self._feed(_rest_samples(self.head, int(0.3 * self.head.sample_rate_hz), self.rng))
        self._take(self.pipe.flush())
        self._attach_windows()
        return {
            "policy": self.policy,
            "episode": self.index,
            "rows": self.rows,
            "moves": self.moves,
            "bumps": self.bumps,
            "failed_whisks": self.failed,
        }

    def _cycle(self, k: int) -> None:
        n_w = self.head.n_whiskers
        geo = [first_contact(self.world, self.pose, self.head, i) for i in range(n_w)]
        if any(c is not None and c.kind in ("pressed", "grazing") for c in geo):
            self._bump()
            return
        try:
            rec = whisk(self.world, self.pose, self.head, self.rng)
        except SimulationError:
            # the rod solver did not converge on this contact: the robot backs off
            self.failed += 1
            self._bump()
            return
        self.last = (rec, self.samples, k, self.odom)
        self._feed(rec.hall_v)
        settle = int(round(self.SETTLE_S * self.head.sample_rate_hz))
        self._feed(_rest_samples(self.head, settle, self.rng))
        move = self._shaft_to_reposition(k) if self.policy != "passive" else None
        if move is not None:
            if not self._translate(*move, "reposition"):
                # blocked (a wall or box behind): back off along the heading instead
                h = math.radians(self.pose.heading_deg)
                d = math.hypot(*move)
                self._translate(-d * math.cos(h), -d * math.sin(h), "reposition")
        else:
            h = math.radians(self.pose.heading_deg)
            self._translate(self.p.step_mm * math.cos(h), self.p.step_mm * math.sin(h), "step")

    def _feed(self, samples: np.ndarray) -> None:
        self.fed.append(np.asarray(samples, dtype=float))
        reports = self.pipe.feed(samples)
        self.samples += samples.shape[0]
        self._take(reports)

    def _take(self, reports: list[Any]) -> None:
        fs = self.head.sample_rate_hz
        for rep in reports:
            if self.last is None:  # nothing whisked yet: noise
                continue
            rec, start, k, odom = self.last
            onset_local = rep.onset_s - start / fs
            end_local = rep.end_s - start / fs
            truth = _match(rep.whisker, onset_local, end_local, rec) if onset_local >= 0 else None
            self.rows.append(self._row(rep, truth, k, onset_local, odom))

    def _row(
        self, rep: Any, truth: Any, k: int, onset_local: float, odom: HeadPose
    ) -> dict[str, Any]:
        L = self.p.length_mm
        labels = self.p.labels(truth)
        where = rep.where
        sweep = _sweep_deg_at(self.head, onset_local)
        pivot, z_dir, x_dir = whisker_frame(odom, self.head, rep.whisker)
        a = math.radians(sweep)
        direction = math.cos(a) * np.asarray(z_dir) + math.sin(a) * np.asarray(x_dir)
        r_est = float(where.radial_distance_mm) if where is not None else L
        point = np.asarray(pivot) + direction * (L if rep.tip else r_est)
        return {
            "policy": POLICIES.index(self.policy),
            "episode": self.index,
            "whisk": k,
            "whisker": rep.whisker,
            "onset_s": rep.onset_s,
            "truth_kind": labels["kind"],
            "truth_radial_mm": labels["radial_distance_mm"],
            "truth_angle_class_deg": labels["angle_class_deg"],
            "truth_texture_code": labels["texture_code"],
            "truth_face": int(truth.face) if truth is not None and truth.kind == "tip" else -1,
            "truth_x_mm": float(truth.point_mm[0]) if truth is not None else math.nan,
            "truth_y_mm": float(truth.point_mm[1]) if truth is not None else math.nan,
            "est_radial_mm": r_est,
            "est_radial_lo_mm": where.radial_interval_mm[0] if where is not None else math.nan,
            "est_radial_hi_mm": where.radial_interval_mm[1] if where is not None else math.nan,
            "p_tip": float(rep.p_tip),
            "tip": bool(rep.tip),
            "pivot_x_mm": float(pivot[0]),
            "pivot_y_mm": float(pivot[1]),
            "point_x_mm": float(point[0]),
            "point_y_mm": float(point[1]),
            "dir_x": float(direction[0]),
            "dir_y": float(direction[1]),
            "rest_dir_deg": math.degrees(math.atan2(z_dir[1], z_dir[0])),
            "prot_dir_deg": math.degrees(math.atan2(x_dir[1], x_dir[0])),
            "sweep_deg": sweep,
            "odom_x_mm": odom.x_mm,
            "odom_y_mm": odom.y_mm,
            "odom_heading_deg": odom.heading_deg,
        }

    def _attach_windows(self) -> None:
        """Each contact's window, cut offline from the whole stream the pipeline was fed.

        The detector's output does not depend on how the stream was chunked, so the offline
        pass finds the same contacts in the same order as the live one (checked here).
        """
        stream_v = np.concatenate(self.fed) if self.fed else np.zeros((0, self.head.n_whiskers, 2))
        fs = self.head.sample_rate_hz
        found = [d for d in contact_windows(stream_v, fs, DETECTOR) if d.onset_index >= 0]
        by_key = {(d.whisker, round(d.onset_index / fs, 9)): d for d in found}
        for row in self.rows:
            d = by_key.get((row["whisker"], round(row["onset_s"], 9)))
            if d is None:
                raise RuntimeError(
                    f"episode {self.index} ({self.policy}): a live contact at "
                    f"{row['onset_s']:.4f} s is missing from the offline pass"
                )
            row["window"] = np.asarray(d.window, dtype=np.float32)
        if self.rows and self.pipe.what is not None:
            what = self.pipe.what
            X = model_windows(
                np.stack([r["window"] for r in self.rows]).astype(float),
                fs,
                what.sample_rate_hz,
                what.channels,
            )
            log_p = np.log(np.maximum(what.estimator.predict_proba(X), 1e-300))
            for row, lp in zip(self.rows, log_p, strict=True):
                row["what_log_proba"] = lp

    def _shaft_to_reposition(self, k: int) -> tuple[float, float] | None:
        """The move (dx, dy) after this whisk's shaft contact, or None."""
        mine = [r for r in self.rows if r["whisk"] == k]
        if self.policy == "oracle":
            shafts = [r for r in mine if r["truth_kind"] == KIND_CODES["shaft"]]
            dist = [self.p.length_mm - r["truth_radial_mm"] for r in shafts]
        else:
            shafts = [r for r in mine if not r["tip"]]
            dist = [self.p.length_mm - r["est_radial_mm"] for r in shafts]
        if not shafts:
            return None
        j = int(np.argmax(dist))
        d = max(dist[j], 0.0) + self.p.margin_mm
        return -d * shafts[j]["dir_x"], -d * shafts[j]["dir_y"]

    def _bump(self) -> None:
        """Back away sideways from the whiskers' side and turn away from it."""
        self.bumps += 1
        h = math.radians(self.pose.heading_deg - 90.0 * self.head.side)
        d = BUMP_SIDESTEP_MM
        self._translate(d * math.cos(h), d * math.sin(h), "bump", -self.head.side * BUMP_TURN_DEG)

    def _translate(self, dx: float, dy: float, kind: str, turn_deg: float = 0.0) -> bool:
        new = self.pose.translated(dx, dy).moved(0.0, 0.0, turn_deg)
        ok = bool(can_move(self.world, self.pose, self.head, new, 10.0))
        dist = math.hypot(dx, dy)
        if ok:
            noise = 1.0 + self.p.odometry_noise * float(self.odo_rng.standard_normal())
            self.odom = self.odom.translated(dx * noise, dy * noise).moved(0.0, 0.0, turn_deg)
            self.pose = new
        self.moves.append(
            {
                "policy": POLICIES.index(self.policy),
                "episode": self.index,
                "kind": {"step": 0, "reposition": 1, "bump": 2}[kind],
                "done": ok,
                "distance_mm": dist if ok else 0.0,
                "x_mm": self.pose.x_mm,
                "y_mm": self.pose.y_mm,
                "clock_s": self.clock_s,
            }
        )
        seconds = dist / self.p.base_speed_mm_s if ok else 0.05
        self._feed(
            _rest_samples(
                self.head, max(1, int(round(seconds * self.head.sample_rate_hz))), self.rng
            )
        )
        return ok


def _in_order(
    job: Callable[[int], dict[str, Any]],
    n: int,
    workers: int | None,
    tick: Callable[[int], None],
) -> list[dict[str, Any]]:
    """``job(0) ... job(n - 1)`` on ``workers`` processes (None: every core), in index order.

    ``tick(done)`` after each job; each job draws from its own random streams, so the
    results do not depend on the number of workers.
    """
    w = max(1, min(workers if workers is not None else (os.cpu_count() or 1), n))
    done: dict[int, dict[str, Any]] = {}
    if w == 1:
        for k in range(n):
            done[k] = job(k)
            tick(len(done))
    else:
        for k, res in imap_unordered(job, list(range(n)), w):
            done[k] = res
            tick(len(done))
    return [done[k] for k in range(n)]


def _code_digest() -> str:
    """sha256 of the sources the episodes run: this module, ``robots.boxworld``, ``framework``."""
    import vibrissa.framework as fw
    import vibrissa.robots.boxworld as bw

    files = [Path(__file__)]
    for pkg in (bw, fw):
        files += sorted(Path(str(pkg.__file__)).parent.glob("*.py"))
    h = hashlib.sha256()
    for f in files:
        h.update(f.name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()


def _rest_samples(head: WhiskingHead, n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` samples of the head's Hall sensors at rest: the rest output plus their noise."""
    hall = head.hall
    out = hall.offset_v + hall.noise_v * rng.standard_normal((n, head.n_whiskers, 2))
    if hall.adc_bits:
        q = hall.supply_v / (2**hall.adc_bits)
        out = np.round(out / q) * q
    return out


def _sweep_deg_at(head: WhiskingHead, t_s: float) -> float:
    """The commanded housing angle from full retraction (deg) ``t_s`` into a whisk.

    The robot's own motor command (its efference copy), ``A (1 - cos 2 pi f t) / 2``; the
    servo's lag behind it is an error the robot does not know.
    """
    phase = 2.0 * math.pi * head.frequency_hz * max(float(t_s), 0.0)
    return head.amplitude_deg * (1.0 - math.cos(phase)) / 2.0


def _join_episodes(episodes: list[dict[str, Any]], n_window: int) -> dict[str, np.ndarray]:
    rows = [r for e in episodes for r in e["rows"]]
    if not rows:
        raise RuntimeError("no episode detected any contact")
    out: dict[str, np.ndarray] = {}
    for key in rows[0]:
        if key == "window":
            W = np.stack([np.asarray(r["window"], dtype=np.float32)[:, :n_window] for r in rows])
            out[key] = W
        else:
            out[key] = np.array([r[key] for r in rows])
    return out


def _join_moves(episodes: list[dict[str, Any]]) -> dict[str, np.ndarray]:
    rows = [m for e in episodes for m in e["moves"]]
    keys = ("policy", "episode", "kind", "done", "distance_mm", "x_mm", "y_mm", "clock_s")
    if not rows:
        return {k: np.zeros(0) for k in keys}
    return {k: np.array([m[k] for m in rows]) for k in keys}


def framework_protocol(quick: bool = False, seed: int = 0, **overrides: Any) -> FrameworkProtocol:
    """The full session, or a quick one (fewer calibration whisks and episodes)."""
    changes: dict[str, Any] = {k: v for k, v in overrides.items() if v is not None}
    if quick:
        changes = {
            "n_calibration": 120,
            "n_episodes": 4,
            "n_whisks": 10,
            "transfer": False,
            **changes,
        }
    return FrameworkProtocol(seed=seed, **changes)
