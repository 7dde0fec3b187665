"""The orchestration layer: the registry of thesis experiments and their runs.

``vibrissa reproduce NAME`` and ``vibrissa reproduce --list`` go through here.
Nothing below this layer (``whisker``, ``robots``, ``experiments``, ``data``,
``signal``, ``classify``, ``evaluate``) imports it.

- :mod:`~vibrissa.reproduce.registry`: :class:`Experiment`, :func:`register`,
  :func:`experiments`, :func:`get_experiment`;
- :mod:`~vibrissa.reproduce.pipeline`: :func:`run_experiment` (dataset cache ->
  evaluation -> results envelope -> Markdown and HTML report);
- the experiments themselves: one package each in :mod:`vibrissa.thesis`.
"""

from vibrissa.reproduce.pipeline import (
    cached_dataset,
    check_job_arguments,
    dataset_path,
    run_experiment,
)
from vibrissa.reproduce.registry import (
    Evaluation,
    Experiment,
    Option,
    experiments,
    get_experiment,
    register,
)

__all__ = [
    "Evaluation",
    "Experiment",
    "Option",
    "cached_dataset",
    "check_job_arguments",
    "dataset_path",
    "experiments",
    "get_experiment",
    "register",
    "run_experiment",
]
