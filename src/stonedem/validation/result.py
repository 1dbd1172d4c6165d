"""What a validation returns (:mod:`stonedem.validation.cases` and the validation modules it
registers, such as :mod:`stonedem.validation.links`, which cases imports: so it lives here)."""

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
