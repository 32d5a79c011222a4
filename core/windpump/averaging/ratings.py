"""A pump's ratings: the largest head it keeps running against, and the largest it starts against,
in a steady wind (what a catalogue's "maximum lift" answers)."""

from __future__ import annotations

import math

import numpy as np

from ..model.design import LARGEST, Design
from ..model.loads import peak_load_torque
from ..model.torque import rest_torque_in_wind
from ..model.wind import MAX_WIND
from ..validation import flag, magnitude
from .theory import running_speeds

HEAD_ROUNDS, HEADS = 8, 32
"""Heads tried at a time, and how often the bracket is narrowed (by 31^8 ~ 1e12), where the
answer has no closed form (a rising main; a reciprocating mass from rest)."""


def max_head(design: Design, V: float | None = None, *, start: bool = False) -> float:
    """The largest head [m] the pump keeps running against in the steady wind V, or, with
    ``start``, starts against from rest at every crank angle.

    Running: the head at which the stall margin (:func:`windpump.stall_margin`, the largest
    ``eta_t R+ T(R+ alpha) / L-bar(alpha)``) falls to 1 in the wind V. Without a rising main the
    margin is inversely proportional to the head (the mean load is), so the head is
    ``h margin(h)``; with one, found by bracketing. A leak hole never stalls: inf.

    Starting: the head at which ``eta_t R+ T(0, V)`` (the torque at rest on the crank) equals
    the largest torque a resting crank must overcome (:func:`windpump.peak_load_torque`); the
    start criterion of :func:`windpump.starts_from_rest` and :func:`windpump.wind_thresholds`'
    starting wind, which equals V at this head. 0 with no torque at rest (the paper's Eq. 11:
    the pump must be kicked).

    Parameters
    ----------
    design : Design
        Its own head is ignored (but for the start of a pump with a leak hole: see below).
    V : float, optional
        Wind speed [m/s], 0 to 150; the design's V_ref by default.
    start : bool, default False
        The starting rating in place of the running one.

    Returns
    -------
    float
        The head [m]; inf when no head stops it (a leak hole running; a hole starting, whose
        static load the hole takes away, with no reciprocating mass).

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(max_head(d), 2), round(max_head(d, V=2.5), 3)  # the margin 5.1 at h = 3 m
    (15.29, 3.823)
    >>> round(max_head(d.replace(T_0=0.3), start=True), 3)
    2.351
    """
    start = flag("start", start)
    V = design.V_ref if V is None else magnitude("V", V, "m/s", zero=True, highest=MAX_WIND)
    s = V / design.V_ref
    if start:
        return _starting_head(design, s)
    if design.d_leak > 0.0:
        return math.inf
    if V == 0.0:
        return 0.0
    h0 = design.h if design.h > 0.0 else 1.0
    if design.friction_coefficient == 0.0:
        return h0 * float(running_speeds(design, head=h0, V=V).margin)
    return _bracketed(lambda heads: running_speeds(design, head=heads, V=V).margin > 1.0, h0)


def _starting_head(design: Design, s: float) -> float:
    """:func:`max_head` with ``start``: the head where the torque at rest meets the peak load."""
    at_rest = float(design.eta_t * design.R_dagger * rest_torque_in_wind(design, s))
    if design.leak_capacity > 0.0 or design.d_leak > 0.0:
        # the hole takes the static load away at any head: only the masses' weight is left
        return math.inf if at_rest > peak_load_torque(design.replace(h=0.0)) else 0.0
    if at_rest == 0.0:
        return 0.0
    h0 = design.h if design.h > 0.0 else 1.0
    if design.m_r == 0.0:  # the peak load is rho_w g h A R times a shape: proportional to h
        return h0 * at_rest / peak_load_torque(design.replace(h=h0))

    def starts(heads):
        return np.array([at_rest > peak_load_torque(design.replace(h=h)) for h in heads])

    return _bracketed(starts, h0)


def _bracketed(runs, h0: float) -> float:
    """The head [m] where ``runs(heads)`` (True at low heads) turns False: bracketed by powers
    of 10 from h0, then narrowed on HEADS heads at a time."""
    lo, hi = 0.0, h0
    while bool(runs(np.array([hi]))[0]):
        lo, hi = hi, 10.0 * hi
        if hi > LARGEST:
            return math.inf
    for _ in range(HEAD_ROUNDS):
        heads = np.linspace(lo, hi, HEADS)
        running = np.asarray(runs(heads), dtype=bool)
        last = int(np.flatnonzero(running).max()) if running.any() else 0
        lo, hi = heads[last], heads[min(last + 1, HEADS - 1)]
    return float(lo)
