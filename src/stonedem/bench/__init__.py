"""Benchmarks of run time against error, cost per contact and numerical stability (issue 6).

:mod:`stonedem.bench.canonical` defines the three canonical scenes, their exact references and
the error measures; :mod:`stonedem.bench.ours`, :mod:`stonedem.bench.pymunk_engine` and
:mod:`stonedem.bench.mujoco_engine` run them in each engine and return a :class:`Trajectory`.
"""
