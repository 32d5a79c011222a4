"""The errors windpump raises on purpose, in one place. All are ``ValueError`` and all pickle, so
a process pool running :func:`windpump.simulate` over many designs gets them back intact."""

from __future__ import annotations

from collections.abc import Mapping


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
        shown = f"{value!r} {unit}".rstrip()
        message = f"{name} = {shown} is not allowed: {name} must be {allowed}"
        super().__init__(f"{message} ({why})" if why else message)

    def __reduce__(self):
        return type(self), (self.name, self.value, self.allowed, self.unit, self.why)


class DesignFileError(ValueError):
    """A design file (:meth:`windpump.Design.from_json`) is not one this version can read."""


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
