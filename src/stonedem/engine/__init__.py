"""The 2D rigid-block engine around the compiled kernels: scenes, packing, the run, its dataset.

Stairs inside: ``structures``, ``geometry`` < ``scene`` < ``pack``, ``measures`` < ``quiet``
< ``simulate`` < ``run``.
"""
