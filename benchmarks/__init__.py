"""The benchmarks: run time against error, cost per contact, numerical stability, ensembles,
rounding and the scripts behind the notebook's measurements (issues 6, 32, 33, 44, 45).

Not part of the installed package: run them from a checkout as ``python -m benchmarks.kernel``
and the like (``snakemake bench`` runs the main ones). :mod:`benchmarks.canonical` defines the
three canonical scenes, their exact references and the error measures; :mod:`benchmarks.ours`,
:mod:`benchmarks.pymunk_engine` and :mod:`benchmarks.mujoco_engine` run them in each engine and
return a :class:`Trajectory`; :mod:`benchmarks.options` is the scripts' command-line kit.
The dated folders hold results kept in the repository: ``ensemble/`` the equivalence
baselines, ``rounding/`` the rounding band, ``device/`` the GPU runs.
"""
