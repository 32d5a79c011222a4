"""The load on the crank of every delivering face, and whether the rotor starts on its own.

Beyond the paper: it names the phase lag of several cylinders and (footnote 7) a windmill's torque
at rest, which decides whether a pump starts without a kick. Conventions as ``Design``: cylinder k
sees ``theta - 2 pi k / n``; its top face delivers on ``pi < phi mod 2 pi < 2 pi``, the bottom face
(double-acting) on the other half, each loading the crank with ``rho_w g h A |dx/dtheta|``.
"""

from __future__ import annotations

import math

import numpy as np

from .design import Design
from .kinematics import face_flows
from .validation import whole


def load_torque_on_crank(design: Design, theta):
    """Load torque on the crank at crank angles theta, summed over the delivering faces [N m].

    ``rho_w g h A R sum |sin(phi + theta_c)/cos(theta_c)|`` over the faces delivering at theta
    (Eq. 12's load term, with its sign dropped: it always brakes). At a switch the faces that
    start or stop sit at a dead centre and add nothing, so the sum is continuous.

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(float(load_torque_on_crank(d, 3 * math.pi / 2) / d.load_torque), 12)  # lever arm -1
    1.0
    >>> float(load_torque_on_crank(d, math.pi / 2))  # intake: no load
    0.0
    """
    theta = np.asarray(theta, dtype=float)
    # The faces' flows per unit crank speed are A R |lever arm|, the torques rho_w g h times them.
    per_speed = face_flows(theta, np.ones_like(theta), design).sum(axis=0)
    return design.rho_w * design.g * design.h * per_speed


def peak_load_torque(design: Design, samples_per_segment: int = 512) -> float:
    """The largest load torque on the crank over all crank angles [N m].

    The load repeats every 2 pi / n of crank angle; it is sampled there and its largest sample
    refined by bounded Brent search. For one single-acting cylinder with a long rod it tends to
    rho_w g h A R (the lever arm's peak, 1 at theta = 3 pi / 2); shorter rods raise it.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(peak_load_torque(d) / d.load_torque, 4)  # L/R = 3.75: the rod adds 3.5 %
    1.0351
    """
    samples_per_segment = whole("samples_per_segment", samples_per_segment, 1, 1_000_000)
    if design.load_torque == 0.0:
        return 0.0
    period = 2 * math.pi / design.cylinders
    spacing = period / (2 * samples_per_segment)
    theta = np.arange(2 * samples_per_segment + 1) * spacing
    load = load_torque_on_crank(design, theta)
    best = theta[int(np.argmax(load))]
    from scipy import optimize  # here, not at import: scipy.optimize takes ~0.5 s to load

    refined = optimize.minimize_scalar(
        lambda angle: -float(load_torque_on_crank(design, angle)),
        bounds=(best - spacing, best + spacing),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return float(max(load.max(), -refined.fun))


def starts_from_rest(design: Design) -> bool:
    """True when the windmill's torque at rest turns the crank from any angle: R+ T_0 exceeds
    :func:`peak_load_torque`.

    Otherwise a start from rest (``simulate(..., theta_dot0=0)``) moves only from angles where the
    load is lighter than R+ T_0, and the pump needs a kick (with T_0 = 0, the paper's windmill,
    always).

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> starts_from_rest(d), starts_from_rest(d.replace(T_0=0.4))
    (False, True)
    """
    return design.rest_torque_on_crank > peak_load_torque(design)
