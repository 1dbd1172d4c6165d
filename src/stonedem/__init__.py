"""stonedem: rigid-block dynamics of ancient columns and colonnades, and pushover of masonry walls.

Python sets up, Numba runs the time loop, Python writes self-describing NetCDF.

The public face is :mod:`stonedem.api`, re-exported here and loaded on first use (PEP 562),
so ``import stonedem`` and ``import stonedem.wall`` do not load the 2D engine::

    import stonedem
    ds = stonedem.run_scene("scene.yaml")        # or a dict; stonedem.load_scene(...) first
    stonedem.write_dataset(ds, "out.nc")
    cube = stonedem.open_cube("ramp_drums.nc")   # a study cube of the workflow
"""

from stonedem.version import __version__

# the names of stonedem.api (its __all__), resolved by __getattr__ on first use
_API = (
    "InputError",
    "load_scene",
    "open_cube",
    "open_fragility",
    "open_ida",
    "open_search",
    "run_scene",
    "run_scenes",
    "run_wall",
    "write_dataset",
)

__all__ = [
    "InputError",
    "__version__",
    "load_scene",
    "open_cube",
    "open_fragility",
    "open_ida",
    "open_search",
    "run_scene",
    "run_scenes",
    "run_wall",
    "write_dataset",
]


def __getattr__(name: str):
    if name in _API:
        from stonedem import api

        value = getattr(api, name)
        globals()[name] = value  # later look-ups skip this function
        return value
    raise AttributeError(f"module 'stonedem' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
