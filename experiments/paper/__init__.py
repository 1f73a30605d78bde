"""The paper's figures (Figs. 3-9) and a reconstruction table, from the simulated cupboard.

Everything here runs the real scene (``tactile_search._core.Scene``: rapier3d physics, ray-cast
depth camera, compliant finger) and the environment's own map pipeline: the depth prior is
``_core.depth_prior`` (the function the environment calls at reset), touch enters with the
environment's contact noise and skipping rule, and the metrics are the core's
(``_core.footprint_mask``, ``_core.interior_iou`` as in ``info["iou"]``,
``_core.outline_distance``, ``_core.spurious_distance``). Nothing is synthetic except the
Fig. 9 timing rows (``gpis_timing``, the method ``benchmarks.gpis_append`` runs too).

- ``priors``: the prior options compared (each is a set of environment settings).
- ``scripted_touch``: the scripted surface-following finger (the paper's Fig. 4 motion).
- ``episodes``: one scene per seed and jar shape, its touch data and its maps and metrics.
- ``tables``: summaries over seeds, the default prior's choice, CSV and markdown.
- ``figures``: Figs. 3-9.
- ``gpis_timing``: Fig. 9's timing of an incremental append against the full recompute.
- ``cli``: the driver, ``python -m experiments.paper --out docs/paper [--seeds N] [--tiny]``.
"""
