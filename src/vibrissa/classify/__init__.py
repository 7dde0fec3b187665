"""The thesis' classifiers as scikit-learn estimators (Evans 2011, chapter 4).

Inputs are trials ``X`` of shape ``(n_trials, n_channels, n_timepoints)`` (or
2-D, one channel); labels ``y`` are 1-D or ``(n_trials, n_targets)``, each
distinct row a joint class (e.g. radial distance and speed), see
:mod:`vibrissa.classify._base`. Every estimator records the sample rate it was
fitted at and refuses data at another (:class:`SampleRateMixin`:
``fit(X, y, sample_rate_hz=fs)``, ``Estimator.from_dataset(ds)``;
:func:`sample_rate_fit_params` and :func:`check_sample_rate` for Pipelines).

========================================  ==================================
:class:`StaticBeamClassifier`             static beam equation, 4.3.1
:class:`FrequencyTemplateClassifier`      |FFT| templates, 4.3.2
:class:`TimeTemplateClassifier`           low-passed signal templates, 4.3.3
:class:`FeatureRegressionClassifier`      f1/f2 + polynomial regression, 4.3.4
:class:`StationaryNaiveBayes`             stationary naive Bayes, 4.3.5
:class:`RecordingWindow`                  filter whole recordings, cut onset/peak window
:func:`chapter4_classifiers`              the chapter-4 line-up (thesis presets)
========================================  ==================================
"""

from vibrissa.classify._base import (
    EstimatorTags,
    SampleRateMixin,
    TrialClassifier,
    check_sample_rate,
    dataset_sample_rate,
    estimator_tags,
    fitted_sample_rate,
    sample_rate_fit_params,
)
from vibrissa.classify._chapter4 import (
    CHAPTER4_KEYS,
    CHAPTER4_ONE_SET,
    chapter4_classifiers,
    onset_window,
    peak_window,
)
from vibrissa.classify._feature import (
    FeatureRegressionClassifier,
    contact_features,
    polynomial_powers,
)
from vibrissa.classify._naive_bayes import StationaryNaiveBayes
from vibrissa.classify._spectral import FrequencyTemplateClassifier
from vibrissa.classify._static_beam import (
    DEFAULT_SPEED_MM_S,
    StaticBeamClassifier,
    base_moment_nm,
    static_beam_radius_mm,
    thesis_parameter_grid,
)
from vibrissa.classify._template import TimeTemplateClassifier, nearest_template_scores
from vibrissa.classify._windows import RecordingWindow

__all__ = [
    "CHAPTER4_KEYS",
    "CHAPTER4_ONE_SET",
    "RecordingWindow",
    "onset_window",
    "peak_window",
    "DEFAULT_SPEED_MM_S",
    "FeatureRegressionClassifier",
    "FrequencyTemplateClassifier",
    "StaticBeamClassifier",
    "StationaryNaiveBayes",
    "TimeTemplateClassifier",
    "EstimatorTags",
    "SampleRateMixin",
    "TrialClassifier",
    "check_sample_rate",
    "dataset_sample_rate",
    "estimator_tags",
    "fitted_sample_rate",
    "sample_rate_fit_params",
    "base_moment_nm",
    "chapter4_classifiers",
    "contact_features",
    "nearest_template_scores",
    "polynomial_powers",
    "static_beam_radius_mm",
    "thesis_parameter_grid",
]

# chapter 5 (angle, speed and texture; see docs/chapter5.md)
from vibrissa.classify._chapter5 import (
    CHAPTER5_KEYS,
    CHAPTER5_TARGETS,
    TEXTURE_CODES,
    JointLikelihoodNaiveBayes,
    SignalTransform,
    SpeedFirstClassifier,
    chapter5_classifiers,
    decode_texture,
    encode_texture,
    resonance_hz,
)
from vibrissa.classify._rocket import MiniRocketClassifier
from vibrissa.classify._sequential import (
    SequentialEvidenceClassifier,
    accumulate_evidence,
    draw_sequences,
)
from vibrissa.classify._texture_features import (
    FeaturePolynomialClassifier,
    chapter5_features,
)

__all__ += [
    "CHAPTER5_KEYS",
    "CHAPTER5_TARGETS",
    "TEXTURE_CODES",
    "FeaturePolynomialClassifier",
    "JointLikelihoodNaiveBayes",
    "MiniRocketClassifier",
    "SequentialEvidenceClassifier",
    "SignalTransform",
    "SpeedFirstClassifier",
    "accumulate_evidence",
    "chapter5_classifiers",
    "chapter5_features",
    "decode_texture",
    "draw_sequences",
    "encode_texture",
    "resonance_hz",
]
