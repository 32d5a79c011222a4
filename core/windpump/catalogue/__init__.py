"""Windmills you can buy, as their makers publish them: the Aermotor 702's pumping table and the
mill in the model's terms (:mod:`.aermotor`). Imports only the model and below.
"""

from .aermotor import (
    CatalogueRow,
    MillParts,
    aermotor_702,
    aermotor_702_parts,
    aermotor_702_table,
    wheel_inertia,
)

__all__ = [
    "CatalogueRow",
    "MillParts",
    "aermotor_702",
    "aermotor_702_parts",
    "aermotor_702_table",
    "wheel_inertia",
]
