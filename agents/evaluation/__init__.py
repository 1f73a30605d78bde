"""Evaluation and reporting: agents named on the command line (``agent_specs``), the
episode rows (``episodes_csv``) and their fingerprints, statistics, the evaluation loop
(``evaluation.evaluate``), the tables and plots (``report``), example GIFs (``gifs``), the
comparison across training seeds (``comparison``) and probe traces (``probe_trace``)."""
