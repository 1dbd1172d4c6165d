"""Installed ground-motion records (package data).

pyproject.toml maps the package ``stonedem._records`` onto the top-level ``records/`` folder, so
``pip install .`` ships ``records/*.nc`` (and its README) as ``stonedem/_records/``, and
:func:`stonedem.motion.records.resolve_record` finds them by name in any install. In a source
checkout this file is only what setuptools' package discovery finds; names are looked up
in ``records/`` itself.
"""
