"""dem: rigid-block discrete element dynamics of ancient columns and colonnades.

Python sets up, Numba runs the time loop, Python writes self-describing NetCDF.
"""

__version__ = "0.1.0"
