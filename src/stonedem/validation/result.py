"""What a validation returns: :class:`ValidationResult` (stonedem.validation.cases and the
validations beyond the thesis, e.g. :mod:`stonedem.validation.sequence`, which cases imports to
register them)."""

from __future__ import annotations

from dataclasses import dataclass, field

import xarray as xr


@dataclass
class ValidationResult:
    name: str
    dataset: xr.Dataset
    passed: bool
    summary: dict = field(default_factory=dict)
    error: float = float("nan")  # the number held to attrs["tolerance"] (summary table)
