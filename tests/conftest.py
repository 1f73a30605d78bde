"""Hypothesis profiles for the property tests.

``fast`` (the default, what ``make test`` runs) keeps every property test to a handful of
examples so the whole fuzz set finishes in seconds; ``long`` is the soak run of the fuzzers
(``HYPOTHESIS_PROFILE=long pytest tests/test_fuzz_*.py --hypothesis-show-statistics``).
``HYPOTHESIS_MAX_EXAMPLES`` overrides the long profile's per-test budget. Tests scale their
own count from the profile's with ``tests.conftest.examples(weight)``: heavy properties
(building and stepping environments) run fewer examples than cheap ones (validation only).
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "fast",
    max_examples=12,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
settings.register_profile(
    "long",
    max_examples=int(os.environ.get("HYPOTHESIS_MAX_EXAMPLES", "10000")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    print_blob=True,
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "fast"))


def examples(weight: float) -> int:
    """The profile's ``max_examples`` times ``weight`` (at least 5): a test's own budget."""
    return max(5, round(settings.default.max_examples * weight))
