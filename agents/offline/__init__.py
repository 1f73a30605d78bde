"""Datasets for offline learning in Minari's format: the episodes of the scripted teachers and
of the published learned agents on training layouts, with the seeds that replay them and the
reference scores that normalise a return (``python -m agents.datasets``), and behaviour
cloning from such a dataset alone (``python -m agents.behaviour_cloning_from_dataset``).

Modules, one concept each: ``catalogue.py`` (which datasets an id gets, and their ids),
``recording.py`` (an agent's episodes as Minari's episode buffers), ``references.py`` (the
random and oracle baselines' mean returns), ``writing.py`` (a dataset written with its
metadata), ``behaviour_cloning.py`` (a policy cloned from a dataset, evaluated on validation
layouts). Needs the ``datasets`` extra (Minari with HDF5) beside the ``agents`` extra.
"""
