"""The windmill's torque and power curves (paper Eq. 11) and the pump's load line (Eq. 5)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .averaged import StallError, stall_margin
from .design import Design
from .validation import ParameterError, finite_array


def windmill_torque(design: Design, omega):
    """Windmill torque T [N m] at windmill speed omega [rad/s] (Eq. 11).

    ``T = T_m x (2 - x)`` with ``x = omega/omega_m``: zero at rest and at ``2 omega_m``, peak
    ``T_m`` at ``omega_m``, negative (a brake) beyond ``2 omega_m``.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> float(windmill_torque(d, 50.0)), float(windmill_torque(d, 100.0))
    (0.6, 0.0)
    """
    x = finite_array("omega", omega, "rad/s", minimum=0.0) / design.omega_m
    return design.T_m * x * (2.0 - x)


def windmill_power(design: Design, omega):
    """Windmill shaft power T(omega) omega [W] (Eq. 11 times omega)."""
    return windmill_torque(design, omega) * finite_array("omega", omega, "rad/s", minimum=0.0)


def load_power(design: Design, omega):
    """Mean power the pump draws at steady windmill speed omega [W] (Eq. 5).

    ``P = rho_w g h (A R / pi) (R0 / R1) omega``: a straight line through the origin.

    Examples
    --------
    >>> from windpump import Design
    >>> round(float(load_power(Design.seed_example(), 40.0)), 3)
    4.709
    """
    omega = finite_array("omega", omega, "rad/s", minimum=0.0)
    return design.load_torque / (np.pi * design.R_dagger) * omega


@dataclasses.dataclass(frozen=True)
class OperatingPoint:
    """Where the pump's load line (Eq. 5) meets the windmill's power curve (Eq. 11).

    Attributes
    ----------
    omega : float
        Stable windmill speed [rad/s] (R+ alpha+ omega_m).
    power : float
        Shaft power there [W] (= rho_w g h Q, the hydraulic power at the mean flow Q).
    crank_speed : float
        Crank speed omega / R+ [rad/s].
    flow : float
        Mean pumped flow A R theta_dot / pi [m^3/s] (Eq. 2).
    omega_unstable : float
        The other intersection [rad/s] (R+ alpha- omega_m): below it the pump decelerates.
    power_unstable : float
        Shaft power at omega_unstable [W].
    """

    omega: float
    power: float
    crank_speed: float
    flow: float
    omega_unstable: float
    power_unstable: float


def operating_point(design: Design) -> OperatingPoint:
    """The stable intersection of the load line, Eq. (5), with the windmill's power curve.

    Solves ``T_m x (2 - x) = rho_w g h A R / (pi R+)`` for ``x = omega/omega_m`` and takes the
    larger root, where the windmill torque falls with speed (stable).

    Raises
    ------
    StallError
        When the line misses the curve: the stall margin of Eq. (22) is 1 or less.

    Examples
    --------
    >>> from windpump import Design, operating_point
    >>> op = operating_point(Design.seed_example())
    >>> round(op.omega, 2), round(op.power, 2)
    (94.83, 11.16)
    """
    load = design.load_torque / (math.pi * design.R_dagger)  # torque of the load line [N m]
    discriminant = 1.0 - load / design.T_m
    if discriminant <= 0.0:
        raise StallError(stall_margin(design), "an operating point")
    x_stable = 1.0 + math.sqrt(discriminant)
    x_unstable = 1.0 - math.sqrt(discriminant)
    omega = x_stable * design.omega_m
    omega_unstable = x_unstable * design.omega_m
    crank_speed = omega / design.R_dagger
    return OperatingPoint(
        omega=omega,
        power=float(windmill_power(design, omega)),
        crank_speed=crank_speed,
        flow=design.A * design.R * crank_speed / math.pi,
        omega_unstable=omega_unstable,
        power_unstable=float(windmill_power(design, omega_unstable)),
    )


@dataclasses.dataclass(frozen=True)
class TorqueFit:
    """A least-squares fit of Eq. (11) to measured windmill torques (the paper's Fig. 2).

    Attributes
    ----------
    T_m : float
        Peak torque [N m].
    omega_m : float
        Speed of the peak [rad/s].
    rms_residual : float
        Root-mean-square of measured minus fitted torque [N m].
    """

    T_m: float
    omega_m: float
    rms_residual: float

    POOR = 0.1
    """A fit whose rms residual exceeds this fraction of T_m describes the data poorly."""

    @property
    def relative_residual(self) -> float:
        """rms residual / T_m [-]."""
        return self.rms_residual / self.T_m

    @property
    def poor(self) -> bool:
        """True when Eq. (11) misses the data by more than ``POOR`` of the peak torque (say,
        columns swapped, or data that do not rise and fall)."""
        return self.relative_residual > self.POOR


def fit_torque_curve(omega, torque) -> TorqueFit:
    """Fit ``T = T_m x (2 - x)``, ``x = omega/omega_m`` (Eq. 11), to measured (omega, T) pairs.

    The curve is linear in ``a = 2 T_m/omega_m`` and ``b = -T_m/omega_m^2`` (``T = a omega + b
    omega^2``), so the fit is a linear least-squares problem; then ``omega_m = -a/(2b)`` and
    ``T_m = a omega_m / 2``.

    Parameters
    ----------
    omega : array_like
        Windmill speeds [rad/s], finite and >= 0, at least two distinct values > 0.
    torque : array_like
        Measured torques [N m], finite, the same length.

    Raises
    ------
    ParameterError
        When the data are not of that form, or do not describe a torque that rises then falls.

    Examples
    --------
    >>> fit = fit_torque_curve([10, 25, 50, 75, 90], [0.216, 0.45, 0.6, 0.45, 0.216])
    >>> round(fit.T_m, 3), round(fit.omega_m, 2)
    (0.6, 50.0)
    """
    omega = np.asarray(omega, dtype=float).ravel()
    torque = np.asarray(torque, dtype=float).ravel()
    if omega.shape != torque.shape:
        raise ParameterError("torque", f"{torque.size} values", f"as many as omega ({omega.size})")
    if not (np.all(np.isfinite(omega)) and np.all(np.isfinite(torque))):
        raise ParameterError("omega, torque", "non-finite values", "finite numbers")
    if np.any(omega < 0):
        raise ParameterError("omega", float(omega.min()), ">= 0 everywhere", "rad/s")
    if np.unique(omega[omega > 0]).size < 2:
        raise ParameterError(
            "omega",
            f"{np.unique(omega).size} distinct speeds",
            "at least two distinct speeds > 0",
            "rad/s",
        )
    (a, b), *_ = np.linalg.lstsq(np.column_stack([omega, omega**2]), torque, rcond=None)
    if not (a > 0 and b < 0):
        raise ParameterError(
            "torque",
            "a curve that does not rise then fall",
            "an inverted parabola through 0 (Eq. 11)",
            why=f"the best fit has T = {a:.4g} omega + {b:.4g} omega^2",
        )
    omega_m = -a / (2 * b)
    if omega_m > 10 * omega.max():
        raise ParameterError(
            "torque",
            "a curve with no visible peak",
            "a torque that peaks near the measured speeds",
            why=f"the fit puts the peak at {omega_m:.4g} rad/s, over 10 x the fastest measured speed",
        )
    T_m = a * omega_m / 2
    residual = torque - T_m * (omega / omega_m) * (2 - omega / omega_m)
    return TorqueFit(
        T_m=float(T_m), omega_m=float(omega_m), rms_residual=float(np.sqrt(np.mean(residual**2)))
    )
