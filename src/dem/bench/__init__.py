"""Benchmarks of run time against error, cost per contact and numerical stability (issue 6).

:mod:`dem.bench.canonical` defines the three canonical scenes, their exact references and
the error measures; :mod:`dem.bench.ours`, :mod:`dem.bench.pymunk_engine` and
:mod:`dem.bench.mujoco_engine` run them in each engine and return a :class:`Trajectory`.
"""
