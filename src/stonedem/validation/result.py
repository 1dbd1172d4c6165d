"""What a validation returns (:class:`ValidationResult`), apart from the checks so that a
feature's own module of checks (``stonedem.validation.<feature>``, registered in
:data:`stonedem.validation.cases.VALIDATIONS`) needs no import of ``cases``."""

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


def attrs(units, long_name):
    """A variable's attributes: units and long name."""
    return {"units": units, "long_name": long_name}
