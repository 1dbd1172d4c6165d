"""Files: atomic writes, the variable schema (units and long names) and the NetCDF writer.

The ground floor with :mod:`stonedem.errors` and :mod:`stonedem.entry`: it imports no other
layer, so the wall solver and the record tools write files without loading the 2D engine.
"""
