"""Agents for ``tactile_search/CupboardSearch-v0``: scripted baselines (``agents.scripted``)."""
