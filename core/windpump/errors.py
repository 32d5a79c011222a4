"""The errors windpump raises on purpose, in one place. All are ``ValueError`` and all pickle, so
a process pool running :func:`windpump.simulate` over many designs gets them back intact."""

from __future__ import annotations

import reprlib
from collections.abc import Mapping

SHOWN = 80
"""Most characters of an input an error message echoes (a 100 MB string gives a short message)."""


def shown(value: object, limit: int = SHOWN) -> str:
    """``repr(value)`` cut to about ``limit`` characters, saying how long it was: what every error
    message shows of an input. Long text, huge integers and long lists are never written out in
    full, not even on the way.

    Examples
    --------
    >>> shown(2.5)
    '2.5'
    >>> shown("x" * 1000, 20)
    "'xxxxxxxxxxxxxxxxxx… (1,000 characters)"
    >>> shown(10**400)
    'an integer of 401 digits'
    >>> import numpy as np
    >>> shown(np.float64("nan")), shown([np.int64(3)]), shown({"theta1": np.float64(1.5)})
    ('nan', '[3]', "{'theta1': 1.5}")
    >>> shown(np.array([1.5, -2.0], dtype=np.float32)), shown(np.zeros((3, 4)))
    ('an array [1.5, -2.0]', 'an array of shape (3, 4)')
    """
    if type(value).__module__ == "numpy" and getattr(value, "ndim", 0) > 0:  # (not its repr:
        size, shape = getattr(value, "size", 0), getattr(value, "shape", ())  # "dtype=float32")
        if size <= 8 and len(shape) == 1:
            return f"an array {shown(value.tolist(), limit)}"  # type: ignore[attr-defined]
        return f"an array of shape {shape}"
    value = _plain(value)
    if isinstance(value, str | bytes | bytearray) and len(value) > limit:
        return f"{repr(value[: limit - 2])[:-1]}… ({len(value):,} characters)"
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 3 * limit:
        digits = len(str(abs(value))) if value.bit_length() < 10_000 else None
        return f"an integer of {digits or f'about {int(value.bit_length() * 0.30103):,}'} digits"
    try:
        text = _SHORT.repr(value)
    except Exception:  # a repr that fails still gives a message
        text = f"<a {type(value).__name__}>"
    if "\n" in text:  # a numpy array's repr: one line
        text = " ".join(text.split())
    return text if len(text) <= limit else f"{text[: limit - 1]}…"


def _plain(value: object) -> object:
    """A numpy scalar as the Python number it holds (numpy 2 writes ``np.float64(nan)``); a
    short list, tuple or dict of them likewise (a dict's keys and values); anything else as it
    is."""
    if type(value).__module__ == "numpy" and getattr(value, "shape", None) == ():
        item = getattr(value, "item", None)
        return item() if callable(item) else value
    if isinstance(value, list | tuple) and type(value) in (list, tuple) and len(value) <= 2 * SHOWN:
        plain = [_plain(x) for x in value]
        return plain if isinstance(value, list) else tuple(plain)
    if type(value) is dict and len(value) <= 2 * SHOWN:
        return {_plain(key): _plain(item) for key, item in value.items()}
    return value


def cut(text: str, limit: int = SHOWN) -> str:
    """``text`` as it is (a path, a cell of a file), cut to about ``limit`` characters.

    Examples
    --------
    >>> cut("lab.csv"), cut("0.216" * 10, 12)
    ('lab.csv', '0.2160.2160… (50 characters)')
    """
    return text if len(text) <= limit else f"{text[: limit - 1]}… ({len(text):,} characters)"


_SHORT = reprlib.Repr()
_SHORT.maxlist = _SHORT.maxtuple = _SHORT.maxdict = _SHORT.maxset = 8
_SHORT.maxstring = _SHORT.maxother = SHOWN
_SHORT.maxlong = SHOWN


class ParameterError(ValueError):
    """A parameter is outside its allowed range.

    Attributes
    ----------
    name : str
        The parameter's name, as the caller spelled it (``"L"``, ``"t_end"``).
    value : object
        The value that was rejected.
    allowed : str
        The allowed range, in words (``"> 0"``, ``"> R = 0.04 m"``).

    Examples
    --------
    >>> import pickle
    >>> error = ParameterError("h", -1.0, "a finite number >= 0", "m")
    >>> str(error)
    'h = -1.0 m is not allowed: h must be a finite number >= 0'
    >>> str(pickle.loads(pickle.dumps(error))) == str(error)
    True
    """

    def __init__(self, name: str, value: object, allowed: str, unit: str = "", why: str = ""):
        self.name, self.value, self.allowed, self.unit, self.why = name, value, allowed, unit, why
        echoed = f"{shown(value)} {unit}".rstrip()
        message = f"{name} = {echoed} is not allowed: {name} must be {allowed}"
        super().__init__(f"{message} ({why})" if why else message)

    def __reduce__(self):
        return type(self), (self.name, self.value, self.allowed, self.unit, self.why)


class DesignFileError(ValueError):
    """A design file (:meth:`windpump.Design.from_json`) is not one this version can read."""


class LabDataError(ValueError):
    """A file that cannot be used (a lab torque file, a wind record, a weather file, or one
    :func:`windpump.readers.files.read_bytes` refuses), with where: ``line`` and ``column`` (1-based) or
    None.

    Examples
    --------
    >>> str(LabDataError("'x' is not a number", 3, 2))
    "line 3, column 2: 'x' is not a number"
    """

    def __init__(self, message: str, line: int | None = None, column: int | None = None):
        self.line, self.column = line, column
        where = f"line {line}" + (f", column {column}" if column else "") if line else ""
        super().__init__(f"{where}: {message}" if where else message)


class StallError(ValueError):
    """The windmill cannot carry the load: the margin of Eq. (22) is 1 or less."""

    def __init__(self, margin: float, what: str):
        self.margin, self.what = margin, what
        super().__init__(
            f"{what} does not exist: the stall margin R+ T_m / (mean load torque) = {margin:.6g} "
            f"must exceed 1 (Eq. 22); the windmill cannot carry this load"
        )

    def __reduce__(self):
        return type(self), (self.margin, self.what)


class NoClosure(ValueError):
    """The loop does not close: it cannot, it is at a dead centre, or Newton-Raphson failed.

    Attributes
    ----------
    reason : str
        ``NoClosure.CANNOT_CLOSE``, ``NoClosure.SINGULAR`` or ``NoClosure.NO_CONVERGENCE``.
    where : dict
        The loop's named inputs when it failed [rad or m], e.g. ``{"theta1": 2.1}``.
    iteration : int or None
        The Newton iterate where it failed; None when the geometry decided before iterating.
    """

    CANNOT_CLOSE = "cannot close"
    SINGULAR = "has a singular Jacobian (a dead centre)"
    NO_CONVERGENCE = "did not converge"

    def __init__(self, reason: str, where: Mapping[str, float], detail: str, iteration=None):
        self.reason, self.where, self.iteration, self.detail = (
            reason,
            dict(where),
            iteration,
            detail,
        )
        at = ", ".join(f"{name} = {value:.6g}" for name, value in self.where.items())
        super().__init__(f"the loop {reason} at {at or 'these inputs'}: {detail}")

    def __reduce__(self):
        return type(self), (self.reason, self.where, self.detail, self.iteration)
