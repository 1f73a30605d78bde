"""Experiments beside the library: the paper's figures and table (``experiments.paper``) and
the GPIS demo (``experiments.demo``). They are not installed with ``tactile_search``; they call
the same core functions as the environment (``tactile_search._core``: the depth prior, the
footprints and metrics, the hand's geometry), so what they measure is what the environment
runs. Run them from the repository's root (``make paper``, ``make demo``).
"""
