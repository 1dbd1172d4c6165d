"""The fault-injection suite's marker: ``slow`` tests run a small Snakemake study several
times (``python3 -m pytest tests/faults -m "not slow"`` leaves them out)."""


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "slow: a fault test that runs the small study several times (20-60 s)"
    )
