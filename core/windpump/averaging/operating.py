"""Where the pump's load line (Eq. 5, for m deliveries per revolution) meets the windmill's power
curve (Eq. 11): the operating point of the averaged theory."""

from __future__ import annotations

import dataclasses
import math

from ..model.design import Design
from ..model.windmill import shaft_power
from ..validation import LARGEST, finite_array
from .averaged import steady_speeds
from .revolution import mean_load
from .theory import running_speeds


def load_power(design: Design, omega):
    """Mean power the pump draws from the windmill at steady windmill speed omega [W] (Eq. 5,
    m deliveries; the real machine's load).

    ``P = L-bar(omega / R+) omega / (eta_t R+)``: the revolution mean of the load torque on the
    crank at the crank speed omega / R+ (:func:`windpump.averaging.revolution.mean_load`, with a rising
    main's friction and a leak hole), reflected through the chain of efficiency eta_t. Without
    a pipe or a hole, Eq. (5): ``m rho_w g h (A R / pi) (R0 / R1) omega / eta_t``, a straight
    line through the origin. It meets the windmill's power curve at the operating point
    (:func:`operating_point`).

    Examples
    --------
    >>> from windpump import Design
    >>> round(float(load_power(Design.seed_example(), 40.0)), 3)
    4.709
    >>> round(float(load_power(Design.seed_example().replace(L_main=30.0), 40.0)), 3)
    4.753
    """
    omega = finite_array("omega", omega, "rad/s", minimum=0.0, maximum=LARGEST)
    reflected = design.eta_t * design.R_dagger
    if design.d_leak == 0.0 and design.friction_coefficient == 0.0:
        return design.mean_load_torque / reflected * omega
    load, _flow = mean_load(design, omega / design.R_dagger)
    return load / reflected * omega


@dataclasses.dataclass(frozen=True)
class OperatingPoint:
    """Where the pump's load line (Eq. 5) meets the windmill's power curve (Eq. 11).

    Attributes
    ----------
    omega : float
        Stable windmill speed [rad/s] (R+ alpha+ omega_m).
    power : float
        Shaft power there [W] (:func:`load_power`; the ideal machine's: rho_w g h Q, the
        hydraulic power at the mean flow Q).
    crank_speed : float
        Crank speed omega / R+ [rad/s].
    flow : float
        Mean pumped flow m A R theta_dot / pi [m^3/s] (Eq. 2, m deliveries per revolution);
        the delivered flow's revolution mean with a leak hole.
    omega_unstable : float
        The other intersection [rad/s] (R+ alpha- omega_m): below it the pump decelerates. With
        torque at rest it may be <= 0 (no unstable speed: every kick spins up); NaN with a leak
        hole where there is none.
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

    Solves ``T_0 + (T_m - T_0) x (2 - x) = M / R+`` (M the mean load torque of m deliveries) for
    ``x = omega/omega_m``, the roots of :func:`windpump.steady_speeds` times R+, and takes the
    larger, where the windmill torque falls with speed (stable).

    Raises
    ------
    StallError
        When the line misses the curve: the stall margin is 1 or less.

    Examples
    --------
    >>> from windpump import Design, operating_point
    >>> op = operating_point(Design.seed_example())
    >>> round(op.omega, 2), round(op.power, 2)
    (94.83, 11.16)
    """
    crank_speed, crank_unstable = steady_speeds(design)
    omega = design.R_dagger * crank_speed
    if crank_unstable is None:  # a leak hole, and F > 0 from rest: no unstable speed
        omega_unstable, power_unstable = math.nan, math.nan
    else:
        omega_unstable = design.R_dagger * crank_unstable
        power_unstable = float(shaft_power(design, max(omega_unstable, 0.0)))
    return OperatingPoint(
        omega=omega,
        power=float(shaft_power(design, omega)),
        crank_speed=crank_speed,
        flow=float(running_speeds(design).mean_flow),
        omega_unstable=omega_unstable,
        power_unstable=power_unstable,
    )
