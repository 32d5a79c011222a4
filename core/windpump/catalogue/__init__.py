"""Windmills you can buy, as their makers publish them: the Aermotor 702's pumping table and the
mill in the model's terms (:mod:`.aermotor`). Imports only the model and below.
"""

from .aermotor import *  # noqa: F403 (its __all__: aermotor_702, aermotor_702_table, ...)
from .aermotor import __all__ as __all__
