"""The paper's groups in closed form, and the averaged equation's answers: the one home of
``I_eff`` (Eq. 12), the load scale ``rho_w g h A R``, the cycle-mean load torque (Eq. 18), the
windmill's torque at rest on the crank (Eq. 11), and :class:`RunningSpeeds`.

This module imports nothing of the package, so :class:`~windpump.Design` takes its groups from it
(its properties ``I_eff``, ``load_torque``, ``mean_load_torque``, ``rest_torque_on_crank``)
while the averaged theory above the design (:mod:`windpump.averaging.revolution`, :mod:`windpump.averaging.theory`) evaluates
the same expressions over arrays; :mod:`windpump.averaging.theory` re-exports every name here.
"""

from __future__ import annotations

import dataclasses
import math
import typing

__all__ = [
    "RunningSpeeds",
    "effective_inertia",
    "load_torque",
    "mean_load_torque",
    "rest_torque_on_crank",
]

Array = typing.Any  # a float or an ndarray: every expression broadcasts


def effective_inertia(I1: Array, I0: Array, R_dagger: Array) -> Array:
    """Inertia reflected to the crank, ``I1 + I0 R+^2`` [kg m^2] (Eq. 12).

    Parameters
    ----------
    I1, I0 : float or ndarray
        Inertias of the crank side and of the windmill side [kg m^2].
    R_dagger : float or ndarray
        Gear ratio R1/R0 [-].

    Examples
    --------
    >>> effective_inertia(1.0, 0.5, 4.0)
    9.0
    """
    return I1 + I0 * R_dagger**2


def load_torque(rho_w: Array, g: Array, h: Array, A: Array, R: Array) -> Array:
    """Piston force times crank radius, ``rho_w g h A R`` [N m]: the load scale of Eq. (12).

    Parameters
    ----------
    rho_w : float or ndarray
        Water density [kg/m^3].
    g : float or ndarray
        Gravity [m/s^2].
    h : float or ndarray
        Head [m].
    A : float or ndarray
        Piston cross-section [m^2].
    R : float or ndarray
        Crank radius [m].

    Examples
    --------
    >>> round(load_torque(1000.0, 9.81, 3.0, 1e-3, 0.04), 4)
    1.1772
    """
    return rho_w * g * h * A * R


def mean_load_torque(deliveries: Array, load: Array) -> Array:
    """Cycle-mean load torque on the crank, ``m rho_w g h A R / pi`` [N m] (Eq. 18 for m faces).

    Parameters
    ----------
    deliveries : int or ndarray
        Deliveries per crank revolution m [-].
    load : float or ndarray
        The load scale ``rho_w g h A R`` [N m] (:func:`load_torque`).

    Examples
    --------
    >>> mean_load_torque(2, math.pi)
    2.0
    """
    return deliveries * load / math.pi


def rest_torque_on_crank(R_dagger: Array, T_0: Array, s: Array = 1.0) -> Array:
    """The windmill's torque at rest reflected to the crank, ``R+ T_0 s^2`` [N m] (Eq. 11 with
    T_0 at omega = 0, in the wind s = V / V_ref).

    Parameters
    ----------
    R_dagger : float or ndarray
        Gear ratio R1/R0 [-].
    T_0 : float or ndarray
        Torque at rest at V_ref [N m].
    s : float or ndarray, default 1.0
        Wind speed over V_ref [-].

    Examples
    --------
    >>> rest_torque_on_crank(4.0, 0.25, s=2.0)
    4.0
    """
    return R_dagger * T_0 * s**2


@dataclasses.dataclass(frozen=True)
class RunningSpeeds:
    """The averaged equation's answers for designs varied in gear ratio, head and wind, with
    or without a leak hole (:func:`windpump.averaging.theory.running_speeds`); every array has the
    broadcast shape.

    Attributes
    ----------
    margin : ndarray
        Stall margin [-]: the largest ``eta_t R+ T(R+ alpha) / L-bar(alpha)`` over the crank
        speeds where the windmill drives; inf with a leak hole (or no load).
    alpha_plus : ndarray
        Stable running crank speed alpha+ [rad/s]: the largest root of F where F falls; NaN
        where the pump cannot run.
    alpha_minus : ndarray
        The rising root of F below alpha+ [rad/s] (unstable: a pump below it slows); NaN where
        F has none (with a leak hole, where F > 0 from rest up to alpha+). Without a hole it is
        ``CycleMean.alpha_minus`` (<= 0 when the torque at rest beats the mean load).
    tau : ndarray
        Time constant ``I-bar / (-F'(alpha+))`` [s]; NaN where the pump cannot run.
    mean_flow : ndarray
        Revolution mean of the delivered flow at alpha+ [m^3/s]; NaN where it cannot run.
    I_bar : ndarray
        Revolution-mean inertia on the crank [kg m^2].
    """

    margin: Array
    alpha_plus: Array
    alpha_minus: Array
    tau: Array
    mean_flow: Array
    I_bar: Array

    @property
    def runs(self) -> Array:
        """Whether the pump can run: the margin exceeds 1 [bool]."""
        return self.margin > 1.0
