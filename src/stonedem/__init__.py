"""stonedem: rigid-block dynamics of ancient columns and colonnades, and pushover of masonry walls.

Python sets up, Numba runs the time loop, Python writes self-describing NetCDF.
"""

from stonedem.version import __version__

__all__ = ["__version__"]
