"""Incremental dynamic analysis over record suites, fragility fits and their checks."""
