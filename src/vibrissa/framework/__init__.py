"""A streaming tactile perception framework (thesis 2.5, figure 2.17): recordings in, surfaces out.

A recording layer: it reads sample streams (simulated or recorded) and never the
simulator. Samples ``(n, n_whiskers, n_channels)`` stream in chunks of any size;
contacts are detected (:class:`ContactDetector`), each is judged "tip or shaft" from
its radial distance (:class:`WhereModel`, chapter 4), tip contacts are classified for
surface angle and texture (:class:`WhatModel`, chapter 5), and the evidence
accumulates across contacts and whiskers (:class:`EvidenceAccumulator`) until a
decision; :class:`TactilePipeline` ties them together and reports each contact
(:class:`ContactReport`). Live input: :class:`StreamGuard` turns timestamped records
(from :func:`open_source`: CSV or JSON lines, a followed file, UDP, serial; or
:func:`replay_dataset`) into the regular chunks the pipeline takes, reporting each kind of
fault once (:class:`StreamIssue`). :class:`TouchMap` maps what was touched: occupancy,
texture and surface direction per cell (:func:`score_touch_map`).
"""

from vibrissa.framework.detect import (
    ContactDetector,
    DetectedContact,
    DetectorSettings,
    contact_windows,
)
from vibrissa.framework.evidence import EvidenceAccumulator, floored_log_posterior
from vibrissa.framework.mapping import TouchMap, score_touch_map
from vibrissa.framework.models import (
    WhatModel,
    WhereModel,
    default_what_estimator,
    default_where_estimator,
    fit_what,
    fit_where,
    model_windows,
)
from vibrissa.framework.pipeline import TactilePipeline
from vibrissa.framework.reports import (
    ContactReport,
    SurfaceEvidence,
    WhatEstimate,
    WhereEstimate,
)
from vibrissa.framework.sources import (
    FORMATS,
    LineParser,
    ReplaySource,
    SerialSource,
    TextSource,
    UdpSource,
    open_source,
    replay_dataset,
)
from vibrissa.framework.stream import ISSUE_KINDS, IssueLog, StreamGuard, StreamIssue

__all__ = [
    "FORMATS",
    "ISSUE_KINDS",
    "ContactDetector",
    "ContactReport",
    "DetectedContact",
    "DetectorSettings",
    "EvidenceAccumulator",
    "IssueLog",
    "LineParser",
    "ReplaySource",
    "SerialSource",
    "StreamGuard",
    "StreamIssue",
    "TextSource",
    "TouchMap",
    "UdpSource",
    "SurfaceEvidence",
    "TactilePipeline",
    "WhatEstimate",
    "WhatModel",
    "WhereEstimate",
    "WhereModel",
    "contact_windows",
    "default_what_estimator",
    "default_where_estimator",
    "fit_what",
    "fit_where",
    "floored_log_posterior",
    "model_windows",
    "open_source",
    "replay_dataset",
    "score_touch_map",
]
