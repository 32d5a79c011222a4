"""The load on the crank of every delivering face, the net torque at rest, and whether the rotor
starts on its own.

Beyond the paper: it names the phase lag of several cylinders and (footnote 7) a windmill's torque
at rest, which decides whether a pump starts without a kick. Conventions as ``Design``: cylinder k
sees ``theta - 2 pi k / n``; its top face delivers on ``pi < phi mod 2 pi < 2 pi``, the bottom face
(double-acting) on the other half.

The real machine (docs/model.rst, "The real machine"): face k sweeps ``u_k = A |x_c'| theta_dot``
and delivers ``q_k = max(u_k - q_L, 0)`` past its leak hole; the rising main's friction head is
``h_f = K Q^2`` at the delivered flow ``Q = sum q_k``; the face's pressure ``p_k`` is
``rho_w g (h + h_f)`` while it delivers, else what drives u_k through the hole; the load torque is
``sum p_k A |x_c'|``. The pointwise equations are those the compiled kernels run
(:mod:`windpump.model.equations`).
"""

from __future__ import annotations

import math

import numpy as np

from ..validation import LARGEST, finite_array, whole
from .design import Design
from .equations import delivered_flow, face_pressure, leak_capacity
from .equations import lever_arm as _lever
from .kinematics import cylinder_angles, face_levers
from .torque import rest_torque_in_wind
from .wind import MAX_WIND


def faces_load(levers, theta_dot, design: Design, h=None):
    """Load torque on the crank [N m] and delivered flow Q [m^3/s] of faces at crank speed
    theta_dot, from their lever arms: the real machine's load, written once.

    The averaged theory (:mod:`windpump.averaging.revolution`) and :func:`load_torque_on_crank` both call
    it. ``u_k = A R lever_k theta_dot``, ``q_k = max(u_k - q_L, 0)``, ``Q = sum q_k``,
    ``h_f = K Q^2`` (K = ``Design.friction_coefficient``), ``p_k`` by
    :func:`~windpump.model.equations.face_pressure`, load ``sum p_k A R lever_k``.

    Parameters
    ----------
    levers : ndarray
        ``|dx/dtheta| / R`` of every face while it delivers, 0 otherwise [-], faces along the
        first axis (:func:`windpump.model.kinematics.face_levers`).
    theta_dot : float or ndarray
        Crank speed [rad/s], >= 0, broadcasting with ``levers[0]``.
    design : Design
    h : float or ndarray, optional
        Head [m] (the hole's capacity follows it); the design's by default.

    Returns
    -------
    load : ndarray
        The load torque on the crank [N m], the shape of ``levers[0]`` broadcast with theta_dot
        and h.
    Q : ndarray
        The delivered flow [m^3/s], of the same shape.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> load, Q = faces_load(np.array([[1.0]]), 2.0, d)  # one face at mid-stroke, 2 rad/s
    >>> round(float(load[0] / d.load_torque), 12), round(float(Q[0] / (2 * d.A * d.R)), 12)
    (1.0, 1.0)
    """
    h = design.h if h is None else h
    q_L = leak_capacity_at(design, h)
    swept = design.A * design.R * levers * theta_dot
    Q = delivered_flow(swept, q_L).sum(axis=0)
    h_f = design.friction_coefficient * Q * Q
    pressure = face_pressure(swept, q_L, design.rho_w, design.g, h, h_f)
    return (pressure * (design.A * design.R * levers)).sum(axis=0), Q


def leak_capacity_at(design: Design, h):
    """The design's leak capacity q_L [m^3/s] at heads h [m] (``Design.leak_capacity`` at the
    design's own head)."""
    return leak_capacity(design.d_leak, design.Cd_leak, design.g, h)


def load_torque_on_crank(design: Design, theta, theta_dot=None):
    """Load torque on the crank at crank angles theta, summed over the delivering faces [N m].

    Without ``theta_dot``: the tight pump at rest (today's static load),
    ``rho_w g h A R sum |sin(phi + theta_c)/cos(theta_c)|`` over the faces delivering at theta
    (Eq. 12's load term, with its sign dropped: it always brakes); at a switch the faces that
    start or stop sit at a dead centre and add nothing, so the sum is continuous.

    With ``theta_dot``: the real machine's load at that crank speed (module docstring): the
    rising main's friction and the leak hole included, ``sum p_k A |x_c'|``. For the ideal
    machine it is the static load at every speed; with a hole it is 0 at rest.

    Parameters
    ----------
    design : Design
    theta : array_like
        Crank angles from TDC [rad].
    theta_dot : array_like, optional
        Crank speeds [rad/s], from 0 to 1e12 (``LARGEST``, as a windmill speed), broadcasting
        with theta: far past any machine; at 1e200 the rising main's friction load
        ``rho_w g K Q^2 A |x_c'|`` overflowed a double (inf, and NaN on the idle faces).

    Returns
    -------
    ndarray
        The load torque [N m], the broadcast shape of theta and theta_dot.

    Raises
    ------
    ParameterError
        Naming ``theta`` or ``theta_dot`` outside their ranges.

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(float(load_torque_on_crank(d, 3 * math.pi / 2) / d.load_torque), 12)  # lever arm -1
    1.0
    >>> float(load_torque_on_crank(d, math.pi / 2))  # intake: no load
    0.0
    >>> holed = d.replace(d_leak=0.004)
    >>> float(load_torque_on_crank(holed, 3 * math.pi / 2, 0.0))  # a hole: no load at rest
    0.0
    """
    theta = finite_array("theta", theta, "rad")
    levers = face_levers(theta, design)
    if theta_dot is None:
        # The faces' flows per unit crank speed are A R |lever arm|, the torques rho_w g h times them.
        per_speed = (design.A * design.R * levers).sum(axis=0)
        return design.rho_w * design.g * design.h * per_speed
    theta_dot = finite_array("theta_dot", theta_dot, "rad/s", minimum=0.0, maximum=LARGEST)
    load, _ = faces_load(levers, theta_dot, design)
    return load


def load_at_speed(design: Design, theta, theta_dot):
    """:func:`load_torque_on_crank` at crank speeds theta_dot [rad/s], unchecked: for a run's own
    angles [rad] and speeds (:func:`windpump.power_budget`), which may pass the 1e12 rad/s a
    caller may ask about."""
    load, _ = faces_load(face_levers(theta, design), theta_dot, design)
    return load


def weight_torque(design: Design, theta):
    """The reciprocating weight's torque on the crank, ``m_r g sum_c x_c'`` [N m].

    The pump stands vertical with top dead centre at the top and x growing downward, so the
    weight helps the crank on the downstroke (intake, x' > 0) and resists the delivering upstroke;
    ``x_c' = dx/dtheta = R sin(phi_c + theta_c)/cos(theta_c)`` at cylinder c's own angle phi_c.
    It averages to 0 over a revolution.

    Parameters
    ----------
    design : Design
    theta : array_like
        Crank angles from TDC [rad].

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example().replace(m_r=2.0)
    >>> round(float(weight_torque(d, math.pi / 2)), 6)  # 2 kg on the crank radius 0.04 m
    0.7848
    """
    theta = finite_array("theta", theta, "rad")
    if design.m_r == 0.0:
        return np.zeros(theta.shape)
    arms = _lever(cylinder_angles(theta, design.cylinders), design.L_over_R)
    return design.m_r * design.g * design.R * arms.sum(axis=0)


def _load_at_rest(design: Design, theta):
    """What the crank must overcome at rest [N m]: the tight pump's static load (0 with a leak
    hole: at rest no pressure builds) less the reciprocating weight's torque."""
    static = 0.0 if design.leak_capacity > 0.0 else load_torque_on_crank(design, theta)
    return static - weight_torque(design, theta)


def rest_torque(design: Design, theta, V=None):
    """The net torque on the crank at rest, N(theta) [N m]: where it is > 0 a resting crank
    starts to turn.

    ``N = eta_t R+ T_0 s^2 + m_r g sum_c x_c' - (rho_w g h A |x_c'| per delivering face)``,
    s = V / V_ref: the windmill's torque at rest through the chain, the reciprocating weight
    (:func:`weight_torque`) and the tight pump's static load; with a leak hole no pressure
    builds at rest and the last term is 0.

    Parameters
    ----------
    design : Design
    theta : array_like
        Crank angles from TDC [rad].
    V : float or array_like, optional
        Wind speed [m/s], from 0 to 150 (``windpump.model.wind.MAX_WIND``, as a record's and
        :func:`windpump.steady_flow`'s), broadcasting with theta; V_ref by default.

    Returns
    -------
    ndarray
        N(theta) [N m].

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example().replace(T_0=0.3)
    >>> round(float(rest_torque(d, 3 * math.pi / 2)), 4)  # R+ T_0 - rho_w g h A R
    -0.2793
    >>> round(float(rest_torque(d.replace(d_leak=0.004), 3 * math.pi / 2)), 4)  # a hole
    1.2
    """
    theta = finite_array("theta", theta, "rad")
    s = 1.0 if V is None else finite_array("V", V, "m/s", 0.0, MAX_WIND) / design.V_ref
    if design.rotor is not None:  # (a furling wheel's torque stops growing with the wind)
        at_rest = design.R_dagger * rest_torque_in_wind(design, s)
        return design.eta_t * at_rest - _load_at_rest(design, theta)
    return design.eta_t * design.rest_torque_on_crank * s**2 - _load_at_rest(design, theta)


def peak_load_torque(design: Design, samples_per_segment: int = 512) -> float:
    """The largest torque a resting crank must overcome, over all crank angles [N m]:
    ``max (static load - m_r g sum_c x_c')``, the static load 0 with a leak hole.

    For the ideal machine (no reciprocating mass, a tight piston) it is the largest load torque
    on the crank (:func:`load_torque_on_crank`). The load repeats every 2 pi / n of crank angle;
    it is sampled there and its largest sample refined by bounded Brent search. For one
    single-acting cylinder with a long rod it tends to rho_w g h A R (the lever arm's peak, 1 at
    theta = 3 pi / 2); shorter rods raise it. :func:`rest_torque` is
    ``eta_t R+ T_0 s^2`` minus this load at each angle.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(peak_load_torque(d) / d.load_torque, 4)  # L/R = 3.75: the rod adds 3.5 %
    1.0351
    >>> peak_load_torque(d.replace(d_leak=0.004))  # a hole and no reciprocating mass
    0.0
    """
    samples_per_segment = whole("samples_per_segment", samples_per_segment, 1, 1_000_000)
    if design.m_r == 0.0 and (design.load_torque == 0.0 or design.leak_capacity > 0.0):
        return 0.0
    period = 2 * math.pi / design.cylinders
    spacing = period / (2 * samples_per_segment)
    theta = np.arange(2 * samples_per_segment + 1) * spacing
    load = _load_at_rest(design, theta)
    best = theta[int(np.argmax(load))]
    from scipy import optimize  # here, not at import: scipy.optimize takes ~0.5 s to load

    refined = optimize.minimize_scalar(
        lambda angle: -float(_load_at_rest(design, angle)),
        bounds=(best - spacing, best + spacing),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return float(max(load.max(), -refined.fun))


def starts_from_rest(design: Design) -> bool:
    """True when a resting crank turns from any angle: the net torque at rest
    (:func:`rest_torque`) is > 0 at every angle, i.e. eta_t R+ T_0 exceeds
    :func:`peak_load_torque`.

    Otherwise a start from rest (``simulate(..., theta_dot0=0)``) moves only from angles where
    N(theta) > 0, and the pump needs a kick (with T_0 = 0, the paper's windmill, always). A leak
    hole takes the static load away, so a windmill with some torque at rest starts.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> starts_from_rest(d), starts_from_rest(d.replace(T_0=0.4))
    (False, True)
    >>> starts_from_rest(d.replace(T_0=0.1, d_leak=0.004))
    True
    """
    return design.eta_t * design.rest_torque_on_crank > peak_load_torque(design)
