"""toothfem's tests. A package so that they and the benchmarks import the test oracles as
``tests.oracles`` (pytest puts the repository root on sys.path for a package's tests)."""
