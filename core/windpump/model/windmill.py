"""The windmill's torque and power curves (paper Eq. 11, with a torque at rest T_0) and a fit of
Eq. (11) to measured torques. Where the curve meets the pump's load line is the averaged theory's
(:mod:`windpump.averaging.operating`)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import ParameterError, shown
from ..validation import LARGEST, finite_array, flag, real_array
from .design import Design
from .equations import windmill_torque as _torque_curve
from .torque import torque_in_wind


def windmill_torque(design: Design, omega):
    """Windmill torque T [N m] at windmill speed omega [rad/s] (Eq. 11, with torque at rest), or
    the design's rotor's (:class:`~windpump.Rotor`) at V_ref.

    ``T = T_0 + (T_m - T_0) x (2 - x)`` with ``x = omega/omega_m``: Eq. (11) when T_0 = 0; T_0 at
    rest, peak ``T_m`` at ``omega_m``, zero at the runaway speed
    ``omega_m (1 + sqrt(T_m / (T_m - T_0)))`` (``2 omega_m`` when T_0 = 0), negative (a brake)
    beyond it.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> float(windmill_torque(d, 50.0)), float(windmill_torque(d, 100.0))
    (0.6, 0.0)
    >>> float(windmill_torque(d.replace(T_0=0.2), 0.0))
    0.2
    """
    omega = finite_array("omega", omega, "rad/s", minimum=0.0, maximum=LARGEST)
    if design.rotor is not None:
        return torque_in_wind(design, omega)
    return _torque_curve(omega / design.omega_m, 1.0, design.T_m, design.T_0)


def windmill_power(design: Design, omega):
    """Windmill shaft power T(omega) omega [W] (Eq. 11, with T_0, times omega).

    Examples
    --------
    >>> from windpump import Design
    >>> round(float(windmill_power(Design.seed_example(), 50.0)), 6)
    30.0
    """
    return windmill_torque(design, omega) * finite_array(
        "omega", omega, "rad/s", minimum=0.0, maximum=LARGEST
    )


def shaft_power(design: Design, omega):
    """:func:`windmill_power` at windmill speeds omega [rad/s] >= 0, unchecked: for speeds the
    model worked out itself (a run's, an operating point's), which may pass the 1e12 rad/s a
    caller may ask about (omega_m is up to 1e12, and the runaway speed beyond it) [W]."""
    if design.rotor is not None:
        return torque_in_wind(design, omega) * omega
    return _torque_curve(omega / design.omega_m, 1.0, design.T_m, design.T_0) * omega


@dataclasses.dataclass(frozen=True)
class TorqueFit:
    """A least-squares fit of Eq. (11), optionally with a torque at rest, to measured torques.

    Attributes
    ----------
    T_m : float
        Peak torque [N m].
    omega_m : float
        Speed of the peak [rad/s].
    rms_residual : float
        Root-mean-square of measured minus fitted torque [N m].
    T_0 : float
        Torque at rest [N m]: fitted with ``at_rest=True``, else 0.
    standard_errors : dict
        One standard error for each fitted parameter (``"T_m"``, ``"omega_m"`` and, fitted at
        rest, ``"T_0"``) [their units]: from the residual variance and the linear least-squares
        covariance, carried to these parameters to first order (the delta method).
    """

    T_m: float
    omega_m: float
    rms_residual: float
    T_0: float = 0.0
    standard_errors: dict = dataclasses.field(default_factory=dict)

    POOR = 0.1
    """A fit whose rms residual exceeds this fraction of T_m describes the data poorly."""

    @property
    def relative_residual(self) -> float:
        """The rms residual / T_m [-]."""
        return self.rms_residual / self.T_m

    @property
    def poor(self) -> bool:
        """True when Eq. (11) misses the data by more than ``POOR`` of the peak torque (say,
        columns swapped, or data that do not rise and fall)."""
        return self.relative_residual > self.POOR


FIT_LARGEST = LARGEST
"""Largest speed [rad/s] or torque magnitude [N m] a fit takes (the design's own bound)."""


def _checked_samples(omega, torque) -> tuple[np.ndarray, np.ndarray]:

    checked = []
    for name, values, unit, lowest in (
        ("omega", omega, "rad/s", 0.0),
        ("torque", torque, "N m", -FIT_LARGEST),
    ):
        allowed = f"finite real numbers from {lowest:g} to {FIT_LARGEST:g}"
        array = real_array(name, values, unit).ravel()  # (text, None, ragged: refused)
        outside = ~(np.isfinite(array) & (array >= lowest) & (array <= FIT_LARGEST))
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise ParameterError(name, f"{name}[{i}] = {shown(array[i])}", allowed, unit)
        checked.append(array)
    omega, torque = checked
    if omega.shape != torque.shape:
        raise ParameterError("torque", f"{torque.size} values", f"as many as omega ({omega.size})")
    return omega, torque


def fit_torque_curve(omega, torque, at_rest: bool = False) -> TorqueFit:
    """Fit ``T = T_0 + (T_m - T_0) x (2 - x)``, ``x = omega/omega_m`` (Eq. 11 when T_0 = 0), to
    measured (omega, T) pairs.

    The curve is linear in ``c = T_0``, ``a = 2 (T_m - T_0)/omega_m`` and
    ``b = -(T_m - T_0)/omega_m^2`` (``T = c + a omega + b omega^2``), so the fit is a linear
    least-squares problem; then ``omega_m = -a/(2b)`` and ``T_m = c + a omega_m / 2``. Without
    ``at_rest`` the curve passes through the origin (c = 0, the paper's Eq. 11).

    Parameters
    ----------
    omega : array_like
        Windmill speeds [rad/s], finite, from 0 to 1e12, at least two (three with ``at_rest``) distinct
        values, and more samples than fitted parameters.
    torque : array_like
        Measured torques [N m], finite, from -1e12 to 1e12, the same length. Speeds and torques
        are fitted in units of the largest of each, so any units fit alike.
    at_rest : bool, default False
        Also fit the torque at rest T_0 (footnote 7: a real windmill has one).

    Returns
    -------
    TorqueFit
        The parameters, the rms residual and each parameter's standard error.

    Raises
    ------
    ParameterError
        When the data are not of that form (naming omega or torque, the first value at fault and
        the range), or do not describe a torque that rises then falls.

    Examples
    --------
    >>> fit = fit_torque_curve([10, 25, 50, 75, 90], [0.216, 0.45, 0.6, 0.45, 0.216])
    >>> round(fit.T_m, 3), round(fit.omega_m, 2)
    (0.6, 50.0)
    >>> fit = fit_torque_curve([0, 20, 40, 60, 80], [0.2, 0.456, 0.584, 0.584, 0.456], at_rest=True)
    >>> round(fit.T_0, 3), round(fit.T_m, 3), round(fit.omega_m, 1)
    (0.2, 0.6, 50.0)
    """
    at_rest = flag("at_rest", at_rest)
    omega, torque = _checked_samples(omega, torque)
    fitted = 3 if at_rest else 2
    distinct = np.unique(omega if at_rest else omega[omega > 0]).size
    if distinct < fitted:
        raise ParameterError(
            "omega",
            f"{distinct} distinct speeds",
            f"at least {fitted} distinct speeds" + ("" if at_rest else " > 0"),
            "rad/s",
        )
    # Fitted in units of the fastest speed and the largest torque, so that any units fit alike
    # (omega^2 neither overflows nor underflows), then carried back.
    speed_unit = float(omega.max())
    torque_unit = float(np.abs(torque).max()) or 1.0
    x, y = omega / speed_unit, torque / torque_unit
    columns = [x, x**2] + ([np.ones_like(x)] if at_rest else [])
    design_matrix = np.column_stack(columns)
    scaled, *_ = np.linalg.lstsq(design_matrix, y, rcond=None)
    units = np.array([torque_unit / speed_unit, torque_unit / speed_unit**2, torque_unit])
    coefficients = scaled * units[: scaled.size]
    a, b = coefficients[:2]
    c = coefficients[2] if at_rest else 0.0
    if not (a > 0 and b < 0):
        raise ParameterError(
            "torque",
            "a curve that does not rise then fall",
            "an inverted parabola (Eq. 11)",
            why=f"the best fit has T = {c:.4g} + {a:.4g} omega + {b:.4g} omega^2",
        )
    omega_m = -a / (2 * b)
    if omega_m > 10 * omega.max():
        raise ParameterError(
            "torque",
            "a curve with no visible peak",
            "a torque that peaks near the measured speeds",
            why=f"the fit puts the peak at {omega_m:.4g} rad/s, over 10 x the fastest measured speed",
        )
    T_m = c + a * omega_m / 2
    if at_rest and not 0.0 <= c < T_m:
        raise ParameterError(
            "torque",
            f"a torque at rest of {c:.4g} N m",
            f"a torque at rest from 0 to below the peak ({T_m:.4g} N m)",
        )
    residual = y - design_matrix @ scaled
    errors = _standard_errors(design_matrix, residual, scaled[0], scaled[1], at_rest)
    return TorqueFit(
        T_m=float(T_m),
        omega_m=float(omega_m),
        rms_residual=float(np.sqrt(np.mean(residual**2))) * torque_unit,
        T_0=float(c),
        standard_errors={
            name: error * (speed_unit if name == "omega_m" else torque_unit)
            for name, error in errors.items()
        },
    )


def _standard_errors(design_matrix, residual, a, b, at_rest) -> dict[str, float]:
    """Standard errors of (T_m, omega_m[, T_0]) from those of (a, b[, c]), by the delta method."""
    samples, fitted = design_matrix.shape
    if samples <= fitted:
        return {name: math.nan for name in ("T_m", "omega_m", "T_0")[:fitted]}
    variance = float(residual @ residual) / (samples - fitted)
    covariance = variance * np.linalg.pinv(design_matrix.T @ design_matrix)
    # omega_m = -a/(2b); T_m = c + a omega_m / 2 = c - a^2/(4b); T_0 = c.
    gradients = {
        "T_m": [-a / (2 * b), a * a / (4 * b * b)],
        "omega_m": [-1 / (2 * b), a / (2 * b * b)],
    }
    if at_rest:  # T_m moves with c one for one; omega_m does not depend on c
        gradients = {"T_m": gradients["T_m"] + [1.0], "omega_m": gradients["omega_m"] + [0.0]}
        gradients["T_0"] = [0.0, 0.0, 1.0]
    return {
        name: float(math.sqrt(max(0.0, np.asarray(g) @ covariance @ np.asarray(g))))
        for name, g in gradients.items()
    }
