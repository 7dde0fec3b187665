"""The thesis' experiments, one package each, every package with the same file roles.

``vibrissa reproduce NAME`` runs the package ``vibrissa.thesis.<name>`` (``-`` for ``_``).
Each package holds, where they apply:

- ``experiment.py``: the registered :class:`~vibrissa.reproduce.registry.Experiment`
  (the only module that imports the registry);
- ``protocol.py``: the simulation protocol (robot, grid, sensor; may import the simulator);
- ``evaluation.py``: the classifiers and the evaluation on a dataset;
- ``report.py``: the report's Markdown sections, tables and discussion;
- ``figures.py``: the experiment's result figures;
- ``values.py``: the thesis' reference numbers, as data and nothing else;
- ``viewer.py`` (CrunchBot): the interactive view of one run.

``evaluation``, ``report``, ``figures`` and ``values`` never import ``vibrissa.whisker``,
``vibrissa.robots`` or ``vibrissa.experiments``, so an imported recording runs through
every evaluation (``tests/test_architecture.py``). Chapters 4 and 5 are XY-robot
experiments: their protocols are the XY robot's (:mod:`vibrissa.experiments.protocols`),
shared with ``vibrissa generate`` and ``vibrissa identify``.
"""
