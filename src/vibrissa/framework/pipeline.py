"""The streaming tactile perception pipeline of thesis 2.5 (figure 2.17).

Samples of every whisker stream in (chunks of any size); on each contact
(:mod:`vibrissa.framework.detect`) the pipeline decides "tip or shaft" from the
posterior of radial distance (chapter 4, a :class:`WhereModel`), classifies tip
contacts for surface angle and texture (chapter 5, a :class:`WhatModel`) and
accumulates their evidence across contacts and whiskers
(:class:`EvidenceAccumulator`) until it decides; then the next tip contact starts
a new surface. Each contact gives one :class:`ContactReport`.

Saved pipelines (:meth:`TactilePipeline.save`) are one file: a JSON header line
(format name and version, vibrissa version, sha256 and size of the payload) and a
pickle payload of the configuration and the fitted models. :meth:`TactilePipeline.load`
checks the header and the checksum before unpickling; unpickling runs code, so
load trusted files only.
"""

from __future__ import annotations

import hashlib
import json
import os
import pickle
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa import __version__
from vibrissa._atomic import atomic_path
from vibrissa._validate import finite, in_range, positive
from vibrissa.data.schema import decode_texture
from vibrissa.framework.detect import ContactDetector, DetectedContact, DetectorSettings
from vibrissa.framework.evidence import EvidenceAccumulator
from vibrissa.framework.models import WhatModel, WhereModel
from vibrissa.framework.reports import (
    ContactReport,
    SurfaceEvidence,
    WhatEstimate,
    WhereEstimate,
    marginal_interval,
)

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "TactilePipeline"]

#: Format name in a saved pipeline's header.
FORMAT_NAME = "vibrissa-tactile-pipeline"
#: Version of the saved format.
FORMAT_VERSION = 1


def _texture_names(codes: np.ndarray) -> list[str]:
    return [str(t) for t in decode_texture(np.asarray(codes, dtype=float))]


class TactilePipeline:
    """Contacts -> where (tip or shaft) -> what (angle, texture) -> evidence per surface.

    Parameters
    ----------
    sample_rate_hz : float
        Rate of the stream, Hz.
    n_whiskers, n_channels : int
        Shape of one sample (e.g. 24 whiskers x 2 Hall channels on a BIOTACT G1 head).
    detector : DetectorSettings, optional
    where : WhereModel, optional
        Without it every contact is a tip contact (``p_tip`` 1.0).
    what : WhatModel, optional
        Without it tip contacts are reported but not classified.
    decision_threshold : float, default=0.99
        Posterior at which the evidence about a surface decides.
    tip_probability : float, default=0.5
        A contact is a tip contact when ``p_tip >= tip_probability``.
    min_probability : float, default=1e-3
        Floor of each contact's posterior in the evidence.
    reset_after_decision : bool, default=True
        After a decision, the next tip contact starts a new surface.
    start_time_s : float, default=0.0
        Time of the first sample, s.
    """

    def __init__(
        self,
        sample_rate_hz: float,
        n_whiskers: int,
        n_channels: int,
        *,
        detector: DetectorSettings | None = None,
        where: WhereModel | None = None,
        what: WhatModel | None = None,
        decision_threshold: float = 0.99,
        tip_probability: float = 0.5,
        min_probability: float = 1e-3,
        reset_after_decision: bool = True,
        start_time_s: float = 0.0,
    ) -> None:
        self.sample_rate_hz = positive("sample_rate_hz", sample_rate_hz)
        self.detector_settings = DetectorSettings() if detector is None else detector
        self._detector = ContactDetector(
            n_whiskers, n_channels, self.sample_rate_hz, self.detector_settings
        )
        self.n_whiskers, self.n_channels = int(n_whiskers), int(n_channels)
        if where is not None and not isinstance(where, WhereModel):
            raise TypeError(f"where must be a WhereModel or None, got {type(where).__name__}")
        if what is not None and not isinstance(what, WhatModel):
            raise TypeError(f"what must be a WhatModel or None, got {type(what).__name__}")
        self.where, self.what = where, what
        self.decision_threshold = positive("decision_threshold", decision_threshold)
        self.tip_probability = in_range("tip_probability", tip_probability, 0.0, 1.0)
        self.min_probability = in_range("min_probability", min_probability, 0.0, 1.0)
        if not isinstance(reset_after_decision, bool):
            raise TypeError(f"reset_after_decision must be a bool, got {reset_after_decision!r}")
        self.reset_after_decision = reset_after_decision
        self.start_time_s = finite("start_time_s", start_time_s)
        self._accumulator: EvidenceAccumulator | None = None
        if what is not None:
            rows, self._surface_index = what.surface_classes()
            self._surface_rows = rows
            self._surface_textures = _texture_names(rows[:, 1])
            angles, a_inv = np.unique(rows[:, 0], return_inverse=True)
            codes, t_inv = np.unique(rows[:, 1], return_inverse=True)
            self._angle_marginal = ([float(a) for a in angles], a_inv.ravel())
            self._texture_marginal = (_texture_names(codes), t_inv.ravel())
            self._accumulator = EvidenceAccumulator(
                rows, self.decision_threshold, self.min_probability
            )
        if where is not None:
            cls = where.classes
            self._radial = np.unique(cls[:, where.radial_column], return_inverse=True)
            self._speed = (
                None
                if where.speed_column is None
                else np.unique(cls[:, where.speed_column], return_inverse=True)
            )
            self._tip_values = self._radial[0] >= where.tip_radial_distance_mm
        self.surface_id = 0
        self._fresh_surface_pending = False

    # -- streaming -----------------------------------------------------------------------
    def feed(self, samples: Any) -> list[ContactReport]:
        """Feed a chunk of samples; return the reports of the contacts it completed.

        Parameters
        ----------
        samples : array-like of shape (n, n_whiskers, n_channels)
            Any ``n >= 0``; finite.

        Returns
        -------
        list of ContactReport

        Raises
        ------
        ValueError
            Naming ``samples`` for a wrong shape, NaN or infinite values.
        """
        return self._reports(self._detector.push(samples))

    def flush(self) -> list[ContactReport]:
        """End the stream: report every contact still open (truncated windows padded).

        Returns
        -------
        list of ContactReport
        """
        return self._reports(self._detector.flush())

    def break_stream(self, whiskers: Any = None) -> None:
        """Restart detection of some whiskers (a gap or dropout); see :class:`ContactDetector`.

        Parameters
        ----------
        whiskers : iterable of int or None
            ``None``: all.
        """
        self._detector.break_stream(whiskers)

    def new_surface(self) -> None:
        """The robot moved: start a new evidence accumulation (``surface_id + 1``)."""
        self.surface_id += 1
        self._fresh_surface_pending = False
        if self._accumulator is not None:
            self._accumulator.reset()

    # -- per contact ---------------------------------------------------------------------
    def _time(self, index: int) -> float:
        return self.start_time_s + index / self.sample_rate_hz

    def _reports(self, contacts: list[DetectedContact]) -> list[ContactReport]:
        out = []
        for c in contacts:
            # one contact at a time: a batch's floating-point results may differ in the
            # last bits from one contact's, and the reports must not depend on chunking
            window = c.window[None]
            where = None
            if self.where is not None:
                where = self._where_estimate(
                    self.where.predict_proba(window, self.sample_rate_hz)[0]
                )
            p_tip = 1.0 if where is None else where.p_tip
            tip = p_tip >= self.tip_probability
            what = evidence = decision = None
            if tip:
                if self._fresh_surface_pending:
                    self.new_surface()
                if self.what is not None:
                    p_what = self.what.predict_proba(window, self.sample_rate_hz)[0]
                    what, evidence, decision = self._what(p_what, c.whisker)
            out.append(
                ContactReport(
                    whisker=c.whisker,
                    onset_s=self._time(c.onset_index),
                    end_s=self._time(c.end_index),
                    peak_departure=c.peak_departure,
                    tip=tip,
                    p_tip=float(p_tip),
                    where=where,
                    what=what,
                    evidence=evidence,
                    surface_id=self.surface_id,
                    decision=decision,
                    truncated=c.truncated,
                )
            )
        return out

    def _where_estimate(self, proba: np.ndarray) -> WhereEstimate:
        assert self.where is not None
        values, inv = self._radial
        mass = np.bincount(inv.ravel(), weights=proba, minlength=values.size)
        mean, lo, hi = marginal_interval(values, mass)
        speed = speed_iv = None
        if self._speed is not None:
            sv, s_inv = self._speed
            sm = np.bincount(s_inv.ravel(), weights=proba, minlength=sv.size)
            speed, s_lo, s_hi = marginal_interval(sv, sm)
            speed_iv = (s_lo, s_hi)
        p_tip = float(mass[self._tip_values].sum() / mass.sum())
        return WhereEstimate(mean, (lo, hi), speed, speed_iv, min(1.0, max(0.0, p_tip)))

    def _what(
        self, proba: np.ndarray, whisker: int
    ) -> tuple[WhatEstimate, SurfaceEvidence, dict[str, Any] | None]:
        acc = self._accumulator
        assert acc is not None
        rows = self._surface_rows
        counts = np.bincount(self._surface_index, weights=proba, minlength=rows.shape[0])
        surface_p = np.asarray(counts, dtype=np.float64) / float(counts.sum())
        what = WhatEstimate(*self._marginals(surface_p))
        acc.add(surface_p, whisker)
        post = acc.posterior()
        best = int(np.argmax(post))
        angle_post, texture_post = self._marginals(post)
        evidence = SurfaceEvidence(
            surface_id=self.surface_id,
            n_contacts=acc.n_contacts,
            whiskers=tuple(sorted(acc.whiskers)),
            angle_deg=float(rows[best, 0]),
            texture=self._surface_textures[best],
            probability=float(post[best]),
            decided=acc.decided,
            angle_posterior=angle_post,
            texture_posterior=texture_post,
        )
        decision = None
        if evidence.decided:
            decision = {
                "angle_deg": evidence.angle_deg,
                "texture": evidence.texture,
                "probability": evidence.probability,
                "n_contacts": evidence.n_contacts,
                "whiskers": list(evidence.whiskers),
            }
            if self.reset_after_decision:
                self._fresh_surface_pending = True
        return what, evidence, decision

    def _marginals(self, p: np.ndarray) -> tuple[dict[float, float], dict[str, float]]:
        (av, a_inv), (tv, t_inv) = self._angle_marginal, self._texture_marginal
        am = np.bincount(a_inv, weights=p, minlength=len(av))
        tm = np.bincount(t_inv, weights=p, minlength=len(tv))
        return dict(zip(av, am.tolist(), strict=True)), dict(zip(tv, tm.tolist(), strict=True))

    # -- persistence ---------------------------------------------------------------------
    def _config(self) -> dict[str, Any]:
        return {
            "sample_rate_hz": self.sample_rate_hz,
            "n_whiskers": self.n_whiskers,
            "n_channels": self.n_channels,
            "detector": self.detector_settings.to_dict(),
            "decision_threshold": self.decision_threshold,
            "tip_probability": self.tip_probability,
            "min_probability": self.min_probability,
            "reset_after_decision": self.reset_after_decision,
            "start_time_s": self.start_time_s,
        }

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the configuration and the fitted models to one file, atomically.

        Not the stream's state: a loaded pipeline starts a new stream.

        Parameters
        ----------
        path : path-like
        """
        payload = pickle.dumps(
            {"config": self._config(), "where": self.where, "what": self.what},
            protocol=pickle.HIGHEST_PROTOCOL,
        )
        header = {
            "format": FORMAT_NAME,
            "format_version": FORMAT_VERSION,
            "vibrissa_version": __version__,
            "payload_bytes": len(payload),
            "sha256": hashlib.sha256(payload).hexdigest(),
        }
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as fh:
                fh.write(json.dumps(header, sort_keys=True).encode() + b"\n")
                fh.write(payload)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> TactilePipeline:
        """Read a pipeline written by :meth:`save` (unpickles: trusted files only).

        Parameters
        ----------
        path : path-like

        Returns
        -------
        TactilePipeline
            With a new stream (sample indices from 0).

        Raises
        ------
        ValueError
            Naming ``path``: not a saved pipeline, another format or vibrissa version,
            truncated, or a checksum that does not match.
        """
        p = Path(path)
        try:
            data = p.read_bytes()
        except OSError as exc:
            raise ValueError(f"cannot read {p}: {exc.strerror or exc}") from None
        head, sep, payload = data.partition(b"\n")
        try:
            header = json.loads(head.decode()) if sep else None
        except (UnicodeDecodeError, ValueError):
            header = None
        if not isinstance(header, dict) or header.get("format") != FORMAT_NAME:
            raise ValueError(f"{p} is not a saved vibrissa tactile pipeline")
        if header.get("format_version") != FORMAT_VERSION:
            raise ValueError(
                f"{p} has format version {header.get('format_version')!r}; this vibrissa "
                f"reads version {FORMAT_VERSION}"
            )
        if header.get("vibrissa_version") != __version__:
            raise ValueError(
                f"{p} was saved by vibrissa {header.get('vibrissa_version')!r}, not "
                f"{__version__} (its pickled models may not load): fit and save it again"
            )
        if len(payload) != header.get("payload_bytes"):
            raise ValueError(
                f"{p} is truncated or padded: {len(payload)} payload bytes, "
                f"expected {header.get('payload_bytes')}"
            )
        if hashlib.sha256(payload).hexdigest() != header.get("sha256"):
            raise ValueError(f"{p} is corrupt: its checksum does not match")
        try:
            state = pickle.loads(payload)  # checked above; trusted files only
            config = dict(state["config"])
            config["detector"] = DetectorSettings.from_dict(config["detector"])
            return cls(
                config.pop("sample_rate_hz"),
                config.pop("n_whiskers"),
                config.pop("n_channels"),
                where=state["where"],
                what=state["what"],
                **config,
            )
        except (pickle.UnpicklingError, KeyError, TypeError, AttributeError, EOFError) as exc:
            raise ValueError(f"{p} cannot be loaded: {exc}") from None
