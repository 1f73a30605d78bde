"""The benchmark scripts: each prints its figures. Run them as modules from the repository's
root (``python -m benchmarks.soak``, ``python -m benchmarks.gpis_append``, ...; ``make bench``
runs them). They import the package, ``agents`` and ``experiments``; nothing imports them
but their tests."""
