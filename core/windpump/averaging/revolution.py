"""Revolution means of the real machine at a constant crank speed: the averaged theory's inertia
I-bar, its load L-bar(alpha) and its flow Q-bar(alpha)
(docs/model.rst, "The real machine: averaged theory").

``I-bar = I_eff + m_r sum_c <x_c'^2>`` has a closed form (:func:`reciprocating_inertia`). The load
and the flow are the revolution means of :func:`windpump.model.loads.faces_load` (the pointwise load
the compiled kernels run, never written again here) at the crank speed alpha. They are smooth
between the switches of the faces (theta = k pi / n) and the angles where a face's swept flow
equals its hole's capacity, ``|x'| / R = q_L / (A R alpha)``; so each period 2 pi / n is cut at
those angles and every piece integrated by Gauss-Legendre quadrature, to about round-off.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..model.equations import lever_arm, lever_arm_slope, windmill_torque
from ..model.groups import RunningSpeeds, effective_inertia, load_torque, mean_load_torque
from ..model.kinematics import face_levers
from ..model.loads import faces_load, leak_capacity_at
from ..model.torque import peak_torque, runaway_in_wind, torque_in_wind

GAUSS_NODES, PANELS = 12, 2
"""Gauss-Legendre nodes per panel, and panels per smooth piece of a period."""

CHUNK = 2048
"""Speeds averaged at once (bounds the memory of a map's quadrature)."""

_X, _W = np.polynomial.legendre.leggauss(GAUSS_NODES)


def mean_square_lever(L_over_R):
    """Revolution mean of the lever arm squared, ``<(x'/R)^2> = r / (r + sqrt(r^2 - 1))``
    [-], r = L/R (Eq. 1 differentiated; 1/2 for a long rod).

    ``<sin^2> = 1/2``, the cross term averages to 0 and
    ``<sin^2 cos^2 / (r^2 - sin^2)> = r^2 - 1/2 - r sqrt(r^2 - 1)``.

    Parameters
    ----------
    L_over_R : float or ndarray
        Rod-to-crank ratio r, > 1.

    Examples
    --------
    >>> round(float(mean_square_lever(1e6)), 9), float(mean_square_lever(1.0 + 1e-300))
    (0.5, 1.0)
    """
    r = np.asarray(L_over_R, dtype=float)
    return r / (r + np.sqrt((r - 1.0) * (r + 1.0)))


def reciprocating_inertia(design) -> float:
    """What the reciprocating masses add to the revolution-mean inertia on the crank,
    ``m_r sum_c <x_c'^2> = n m_r R^2 <(x'/R)^2>`` [kg m^2] (:func:`mean_square_lever`), so that
    ``I-bar = I_eff + reciprocating_inertia``.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example().replace(m_r=10.0, L=1e3)  # a long rod: <(x'/R)^2> ~ 1/2
    >>> round(reciprocating_inertia(d) / (10.0 * 0.04**2 / 2), 9)
    1.0
    """
    if design.m_r == 0.0:
        return 0.0
    return design.cylinders * design.m_r * design.R**2 * float(mean_square_lever(design.L_over_R))


@functools.lru_cache(maxsize=64)
def _branches(
    L_over_R: float,
) -> tuple[float, float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The lever arm's peak on (0, pi) (angle, value) and tables of its rising and falling
    branches there (angles, values; the falling branch's values reversed to increase)."""
    from scipy import optimize

    peak = optimize.brentq(lambda phi: lever_arm_slope(phi, L_over_R), 1e-9, math.pi - 1e-9,
                           xtol=1e-15, rtol=1e-15)  # fmt: skip
    top = float(lever_arm(peak, L_over_R))
    rising = np.linspace(0.0, peak, 513)
    falling = np.linspace(math.pi, peak, 513)
    return peak, top, rising, falling, lever_arm(rising, L_over_R), lever_arm(falling, L_over_R)


def _crossings(lam, L_over_R: float):
    """The angles psi1 <= psi2 in [0, pi] where the lever arm equals lam [-] (broadcasting):
    0 and pi where lam <= 0, both the peak where lam is at or above the peak."""
    peak, top, rising, falling, up, down = _branches(L_over_R)
    lam = np.clip(lam, 0.0, top)
    roots = []
    for angles, values, lo, hi in ((rising, up, 0.0, peak), (falling, down, peak, math.pi)):
        psi = np.interp(lam, values, angles)
        for _ in range(3):  # Newton from the table's interpolation, kept on its branch
            slope = lever_arm_slope(psi, L_over_R)
            step = (lever_arm(psi, L_over_R) - lam) / np.where(slope == 0.0, 1.0, slope)
            psi = np.clip(psi - np.where(slope == 0.0, 0.0, step), lo, hi)
        roots.append(np.where(lam >= top, peak, psi))
    return roots[0], roots[1]


def _nodes(lam, design):
    """Quadrature angles [rad] and weights [-] (summing to 1) over one period 2 pi / n for the
    hole ratios lam: shape ``lam.shape + (nodes,)``."""
    n = design.cylinders
    period = 2 * math.pi / n
    psi1, psi2 = _crossings(lam, design.L_over_R)
    cuts = [np.zeros_like(psi1), np.full_like(psi1, math.pi / n), np.full_like(psi1, period)]
    cuts += [np.mod(-psi1, period), np.mod(-psi2, period)]  # the top faces' crossings
    if design.double_acting:
        cuts += [np.mod(psi1, period), np.mod(psi2, period)]  # the bottom faces'
    edges = np.sort(np.stack(cuts, axis=-1), axis=-1)
    fractions = np.linspace(0.0, 1.0, PANELS + 1)
    starts, widths = edges[..., :-1], np.diff(edges, axis=-1)
    panel_starts = starts[..., None] + widths[..., None] * fractions[:-1]
    half = (widths / (2 * PANELS))[..., None, None]
    theta = panel_starts[..., None] + half * (_X + 1.0)
    weight = half * _W / period
    shape = lam.shape + (-1,)
    return theta.reshape(shape), np.broadcast_to(weight, theta.shape).reshape(shape)


def mean_load(design, alpha, h=None):
    """Revolution means of the load torque on the crank [N m] and of the delivered flow
    [m^3/s] at the constant crank speed alpha: ``L-bar(alpha)`` and ``Q-bar(alpha)``.

    The mean over a revolution of :func:`windpump.model.loads.faces_load` (friction of the rising
    main and leak hole included) by Gauss-Legendre quadrature between the load's breaks (module
    docstring). Broadcasts over alpha and h.

    Parameters
    ----------
    design : Design
    alpha : float or ndarray
        Crank speed [rad/s], >= 0.
    h : float or ndarray, optional
        Head [m]; the design's by default.

    Returns
    -------
    load : ndarray
        L-bar [N m], the broadcast shape of alpha and h.
    flow : ndarray
        Q-bar [m^3/s], of the same shape.

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> load, flow = mean_load(d, 20.0)  # the ideal machine: M and A R alpha / pi
    >>> round(float(load / d.mean_load_torque), 12), round(float(flow * math.pi / (d.A * d.R * 20)), 12)
    (1.0, 1.0)
    """
    h = design.h if h is None else np.asarray(h, dtype=float)
    alpha, h = np.broadcast_arrays(np.asarray(alpha, dtype=float), h)
    flat_alpha, flat_h = alpha.ravel(), h.ravel()
    load, flow = np.empty(alpha.size), np.empty(alpha.size)
    for start in range(0, alpha.size, CHUNK):
        part = slice(start, start + CHUNK)
        load[part], flow[part] = _mean_load(design, flat_alpha[part], flat_h[part])
    return load.reshape(alpha.shape), flow.reshape(alpha.shape)


def _mean_load(design, alpha: np.ndarray, h: np.ndarray):
    """:func:`mean_load` of 1-D arrays."""
    swept_at_peak = design.A * design.R * alpha
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(alpha > 0.0, leak_capacity_at(design, h) / swept_at_peak, math.inf)
    theta, weight = _nodes(lam, design)
    load, flow = faces_load(face_levers(theta, design), alpha[:, None], design, h[:, None])
    return (load * weight).sum(axis=-1), (flow * weight).sum(axis=-1)


def friction_load(design) -> float:
    """The rising main's share of the mean load per crank speed squared, ``c`` [N m s^2]:
    without a leak hole ``L-bar(alpha) = M + c alpha^2`` exactly, since the friction head is
    ``K Q^2`` and Q is proportional to alpha (Eq. 18 with a pipe).

    ``c = rho_w g A R K (A R)^2 <(sum |x'|/R)^3>`` over the delivering faces: evaluated once
    as the mean load at 1 rad/s with no head (so no static load and no hole).

    Examples
    --------
    >>> from windpump import Design
    >>> friction_load(Design.seed_example())  # no pipe
    0.0
    """
    if design.friction_coefficient == 0.0:
        return 0.0
    tight = design.replace(d_leak=0.0)
    load, _ = mean_load(tight, 1.0, h=0.0)
    return float(load)


SCAN_POINTS = 48
"""Crank speeds from rest to the runaway speed where F is sampled to bracket its roots."""

BISECTIONS = 200
"""At most this many bisections finish a root the Illinois steps did not: about 12 halve the
logarithm of any ratio of doubles to a factor 4, 54 more the speed to round-off."""

CRAWL_STEP, CRAWL_DECADES = 1e-3, 110
"""Below the scan, speeds CRAWL_STEP apart are tried (at most CRAWL_DECADES of them, down past
the smallest double) for a crawl's largest root."""

ROOT_ITERATIONS = 100
"""At most this many Illinois steps refine a root (a dozen usually bring it to round-off)."""


class Points:
    """Designs varied in gear ratio, head and wind, flattened: F(alpha) of each."""

    def __init__(self, design, gear_ratio, head, V):
        R_dagger = design.R_dagger if gear_ratio is None else np.asarray(gear_ratio, dtype=float)
        h = design.h if head is None else np.asarray(head, dtype=float)
        s = 1.0 if V is None else np.asarray(V, dtype=float) / design.V_ref
        R_dagger, h, s = np.broadcast_arrays(R_dagger, h, s)
        self.shape = R_dagger.shape
        self.design = design
        self.R_dagger, self.h, self.s = R_dagger.ravel(), h.ravel(), s.ravel()
        I_eff = effective_inertia(design.I1, design.I0, self.R_dagger)
        self.I_bar = I_eff + reciprocating_inertia(design)
        if design.rotor is None:
            runaway = design.runaway_speed / design.omega_m  # x where T vanishes at V_ref
            self.runaway = self.s * design.omega_m * runaway / self.R_dagger  # crank [rad/s]
        else:
            self.runaway = runaway_in_wind(design, self.s) / self.R_dagger
        # Without a leak hole the mean load is M + c alpha^2 exactly (friction_load): no quadrature
        self.tight = design.d_leak == 0.0
        self.friction = friction_load(design) if self.tight else 0.0
        self.M = mean_load_torque(
            design.deliveries, load_torque(design.rho_w, design.g, self.h, design.A, design.R)
        )

    def net_torque(self, alpha, which=slice(None)):
        """F(alpha) = eta_t R+ T(R+ alpha) - L-bar(alpha) [N m] of the points ``which``."""
        drive, load = self._drive_and_load(alpha, which, tight=self.tight)
        return drive - load

    def ratio(self, alpha, which=slice(None)):
        """The stall criterion's ratio eta_t R+ T(R+ alpha) / L-bar(alpha) [-] (tight pumps)."""
        drive, load = self._drive_and_load(alpha, which, tight=True)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(load > 0.0, drive / load, np.where(drive > 0.0, math.inf, 0.0))

    def _drive_and_load(self, alpha, which, tight: bool):
        """(eta_t R+ T(R+ alpha), L-bar(alpha)) [N m]: the load M + c alpha^2 when ``tight``,
        else the quadrature of a leak hole's."""
        d = self.design
        R_dagger = self.R_dagger[which]
        if np.ndim(alpha) > np.ndim(R_dagger):
            R_dagger = R_dagger[:, None]
        s = self.s[which].reshape(np.shape(R_dagger))
        if d.rotor is None:
            torque = windmill_torque(R_dagger * alpha / d.omega_m, s, d.T_m, d.T_0)
        else:
            torque = torque_in_wind(d, R_dagger * alpha, s)
        if tight:
            load = self.M[which].reshape(np.shape(R_dagger)) + self.friction * np.square(alpha)
        else:
            load, _ = mean_load(d, alpha, self.h[which].reshape(np.shape(R_dagger)))
        return d.eta_t * R_dagger * torque, load


def numeric_running_speeds(design, *, gear_ratio=None, head=None, V=None):
    """:func:`windpump.averaging.theory.running_speeds` with no closed form (a leak hole, or a
    rotor's torque curve): F scanned from rest to the runaway speed, its largest falling root
    (alpha+) and the rising root below it (alpha-) refined, tau from a central difference, the
    mean flow by quadrature at alpha+ (with a hole) or ``m 2 R A alpha+ / 2 pi``. The stall
    margin is inf with a hole, else the largest ratio of :meth:`Points.ratio` over the crank
    speeds up to the runaway (:func:`largest_ratio`); where it is 1 or less the pump cannot run
    (alpha+ NaN)."""
    points = Points(design, gear_ratio, head, V)
    alpha_plus, alpha_minus = largest_roots(points, points.runaway)
    if points.tight and points.friction == 0.0:  # the largest torque over the mean load
        with np.errstate(divide="ignore"):
            margin = design.eta_t * points.R_dagger * peak_torque(design, points.s) / points.M
    elif points.tight:
        margin = largest_ratio(points)
        alpha_plus = np.where(margin > 1.0, alpha_plus, math.nan)
        alpha_minus = np.where(margin > 1.0, alpha_minus, math.nan)
    else:
        margin = np.full(alpha_plus.shape, math.inf)
    runs = ~np.isnan(alpha_plus)
    rate = slope(points, alpha_plus, runs)
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = np.where(runs, points.I_bar / -rate, math.nan)
    flow = np.full(alpha_plus.shape, math.nan)
    if points.tight:
        flow[runs] = design.volume_per_revolution * alpha_plus[runs] / (2 * math.pi)
    else:
        flow[runs] = mean_load(design, alpha_plus[runs], points.h[runs])[1]
    shape = points.shape
    return RunningSpeeds(
        margin=margin.reshape(shape),
        alpha_plus=alpha_plus.reshape(shape),
        alpha_minus=alpha_minus.reshape(shape),
        tau=tau.reshape(shape),
        mean_flow=flow.reshape(shape),
        I_bar=np.broadcast_to(points.I_bar, alpha_plus.shape).reshape(shape),
    )


GOLDEN_STEPS = 40
"""Golden-section steps that refine the stall margin's largest ratio: 0.618^40 ~ 4e-9 of the
scan's spacing, and the ratio is flat at its peak (an error of ~1e-17 there)."""


def largest_ratio(points: Points):
    """The stall margin of every (tight) point: the largest ``eta_t R+ T(R+ alpha) / L-bar``
    over crank speeds from rest to the runaway [-], sampled on the scan's speeds and refined by
    golden-section search around the best sample (inf with no load)."""
    grid = np.linspace(0.0, 1.0, SCAN_POINTS + 1)
    alpha = points.runaway[:, None] * grid
    ratios = points.ratio(alpha)
    best = np.argmax(ratios, axis=1)
    rows = np.arange(alpha.shape[0])
    lo = alpha[rows, np.maximum(best - 1, 0)]
    hi = alpha[rows, np.minimum(best + 1, grid.size - 1)]
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo.copy(), hi.copy()
    c, d = b - golden * (b - a), a + golden * (b - a)
    fc, fd = points.ratio(c[:, None])[:, 0], points.ratio(d[:, None])[:, 0]
    for _ in range(GOLDEN_STEPS):
        left = fc >= fd  # the peak lies in [a, d]: d becomes c's; else in [c, b]: c becomes d's
        a, b = np.where(left, a, c), np.where(left, d, b)
        kept = np.where(left, fc, fd)  # the inner point that stays inside, and its ratio
        c, d = np.where(left, b - golden * (b - a), d), np.where(left, c, a + golden * (b - a))
        fc, fd = kept, kept
        new = np.where(left, c, d)
        value = points.ratio(new[:, None])[:, 0]
        fc, fd = np.where(left, value, fc), np.where(left, fd, value)
    return np.maximum(ratios.max(axis=1), np.maximum(fc, fd))


def largest_roots(points: Points, upper, crawl: bool = False):
    """The largest root of F in (0, upper) where F falls (alpha+), and the root below it where F
    rises (alpha-) [rad/s], NaN where there is none, of every point: F sampled at SCAN_POINTS
    speeds, the brackets refined by :func:`_root`. F must be < 0 just above ``upper`` (the
    runaway speed: with no load at all, no head, F(upper) is 0 give or take round-off, and the
    scan ends a hair above it). With ``crawl`` also the largest falling root below alpha- (where
    a pump started below alpha- settles)."""
    grid = np.concatenate([[1e-9], np.arange(1, SCAN_POINTS) / SCAN_POINTS, [1.0 + 1e-9]])
    alpha = np.asarray(upper)[:, None] * grid
    positive = points.net_torque(alpha) > 0.0
    index = np.arange(grid.size)
    # The last speed where F > 0 (F falls through 0 above it); below that the last one where
    # F <= 0 (F rises through 0 above it); below that again the last where F > 0.
    last = np.where(positive, index, -1).max(axis=1)
    found = (last >= 0) & (last < grid.size - 1)
    dip = np.where((index < last[:, None]) & ~positive, index, -1).max(axis=1)
    lower = np.where((index < dip[:, None]) & positive, index, -1).max(axis=1)
    starts = [np.where(found, last, 0), dip, lower][: 3 if crawl else 2]
    actives = [found, found & (dip >= 0), found & (dip >= 0) & (lower >= 0)][: len(starts)]
    rows = np.arange(alpha.shape[0])
    start = np.concatenate([np.maximum(j, 0) for j in starts])
    every = np.tile(rows, len(starts))  # the roots of every point refined together
    roots = _root(
        points, alpha[every, start], alpha[every, start + 1], np.concatenate(actives), every
    )
    found_roots = tuple(roots[i * rows.size : (i + 1) * rows.size] for i in range(len(starts)))
    if np.all(last >= 0):
        return found_roots
    # F <= 0 at every scanned speed, from 1e-9 of the runaway speed up: a crawl below the scan
    # (a load through the hole many decades above the windmill's torque; NaN before, issue 36).
    # F > 0 just above rest, so its largest root lies below the scan's first speed: found on
    # speeds a thousandth apart down from there, then refined as the others.
    below = np.flatnonzero(last < 0)
    hi = np.asarray(upper, dtype=float)[below] * grid[0]
    lo = hi * CRAWL_STEP
    for _ in range(CRAWL_DECADES):
        falling = ~(points.net_torque(lo, below) > 0.0) & (lo > 0.0)
        if not falling.any():
            break
        hi = np.where(falling, lo, hi)
        lo = np.where(falling, lo * CRAWL_STEP, lo)
    crawling = _root(points, lo, hi, points.net_torque(lo, below) > 0.0, below)
    found_roots[0][below] = crawling
    return found_roots


def _root(points: Points, lo, hi, active, of):
    """The root of F between lo and hi (where F changes sign) of the points ``of`` where
    active [rad/s], by the Illinois method; NaN elsewhere."""
    which = of[active]
    a, b = lo[active], hi[active]
    fa, fb = points.net_torque(a, which), points.net_torque(b, which)
    for _ in range(ROOT_ITERATIONS):
        open_ = (np.abs(b - a) > 4e-16 * np.abs(b)) & (fb != 0.0)
        if not open_.any():
            break
        i = np.flatnonzero(open_)
        c = b[i] - fb[i] * (b[i] - a[i]) / (fb[i] - fa[i])
        fc = points.net_torque(c, which[i])
        flipped = np.sign(fc) != np.sign(fb[i])
        # Across the root: the old end b becomes a. Same side: halve a's value (Illinois).
        a[i] = np.where(flipped, b[i], a[i])
        fa[i] = np.where(flipped, fb[i], 0.5 * fa[i])
        b[i], fb[i] = c, fc
    else:  # not all converged: bisect the rest (a bracket over many decades: F ~ 1e-22 at one
        # end and -1e50 at the other left a crawl's Illinois steps at its low end; issue 36)
        _bisect(points, a, b, fb, which)
    root = np.full(lo.shape, math.nan)
    root[active] = b
    return root


def _bisect(points: Points, a, b, fb, which) -> None:
    """Bisect the brackets [a, b] (F changes sign; b the estimate, F(b) = fb) of the points
    ``which`` to round-off in place: halved in the speed's logarithm while the ends lie more
    than a factor 4 apart, in the speed after."""
    for _ in range(BISECTIONS):
        open_ = (np.abs(b - a) > 4e-16 * np.abs(b)) & (fb != 0.0)
        if not open_.any():
            return
        i = np.flatnonzero(open_)
        low, high = np.minimum(a[i], b[i]), np.maximum(a[i], b[i])
        with np.errstate(divide="ignore", invalid="ignore"):
            apart = (low > 0.0) & (high > 4.0 * low)
            c = np.where(apart, np.sqrt(low) * np.sqrt(high), 0.5 * (low + high))
        fc = points.net_torque(c, which[i])
        same = np.sign(fc) == np.sign(fb[i])
        a[i] = np.where(same, a[i], b[i])
        b[i], fb[i] = c, fc


def slope(points: Points, alpha, active):
    """F'(alpha) [N m s] of the active points by the five-point central difference."""
    which = np.flatnonzero(active)
    at = alpha[which]
    step = 1e-3 * at
    offsets = np.array([-2.0, -1.0, 1.0, 2.0])
    values = points.net_torque(at[:, None] + step[:, None] * offsets, which)
    result = np.full(alpha.shape, math.nan)
    result[which] = (values[:, 0] - 8.0 * values[:, 1] + 8.0 * values[:, 2] - values[:, 3]) / (
        12.0 * step
    )
    # At a falling root F' < 0; where the five points straddle the hole's kink (a face starts
    # to deliver: u = q_L) they may say otherwise (tau < 0 for a hole near a huge bore; issue
    # 36): the two-point difference across the root itself, F's sign on each side, instead.
    wrong = np.flatnonzero(~(result[which] < 0.0))
    if wrong.size:
        near = at[wrong, None] * (1.0 + np.array([-1e-7, 1e-7]))
        sides = points.net_torque(near, which[wrong])
        result[which[wrong]] = (sides[:, 1] - sides[:, 0]) / (near[:, 1] - near[:, 0])
    return result


SPINUP_PANEL, SPINUP_NODES = 1.0, 8
"""The spin-up's quadrature in sigma = -log|alpha* - alpha| (module :func:`leaky_spinup`): panel
width [-] and Gauss-Legendre nodes per panel."""

NEAR = 1e-7
"""Within this fraction of its steady speed the spin-up follows the linearised equation
(exponential with the time constant; error of order NEAR^2)."""


def leaky_target(points: Points, theta_dot0: float) -> float:
    """The steady speed [rad/s] the averaged equation carries theta_dot0 to (one point): alpha+
    from above the rising root alpha- (or from anywhere when there is none), the largest
    falling root below alpha- from below it; theta_dot0 itself at a root."""
    falling, rising, crawl = largest_roots(points, points.runaway, crawl=True)
    alpha_plus, alpha_minus = float(falling[0]), float(rising[0])
    if math.isnan(alpha_minus) or theta_dot0 > alpha_minus:
        return alpha_plus
    return theta_dot0 if theta_dot0 == alpha_minus else float(crawl[0])


def leaky_spinup(design, t: np.ndarray, theta_dot0: float) -> np.ndarray:
    """Cycle-mean crank speed [rad/s] at times t [s] of ``I-bar alpha' = F(alpha)`` from
    theta_dot0, F with a leak hole (by quadrature).

    The equation is autonomous, so time is a quadrature of the speed: towards the steady speed
    alpha* it approaches, with ``alpha = alpha* - (alpha* - theta_dot0) exp(-sigma)``,
    ``t(sigma) = I-bar int_0^sigma (alpha* - alpha) / F(alpha) dsigma'``, whose integrand is
    smooth and tends to ``-1/F'(alpha*)``. It is integrated by Gauss-Legendre panels up to
    ``|alpha* - alpha| = NEAR alpha*`` and inverted for each t by Newton's method on the panels'
    Legendre interpolants; beyond, the linearised equation's exponential.
    """
    points = Points(design, None, None, None)
    target = leaky_target(points, theta_dot0)
    if not np.isfinite(target) and points.tight and theta_dot0 > 0.0:  # a rotor's pump stalls
        return _decay(points, t, theta_dot0)
    gap = target - theta_dot0
    if gap == 0.0 or not np.isfinite(target):
        return np.full(t.shape, theta_dot0)
    far = math.log(abs(gap) / (NEAR * target)) if abs(gap) > NEAR * target else 0.0
    edges = _panel_edges(design, theta_dot0, target, far)
    width = np.diff(edges)[:, None]
    sigma = edges[:-1, None] + 0.5 * width * (_SX + 1.0)
    speed = target - gap * np.exp(-sigma)
    rate = (
        points.I_bar[0]
        * gap
        * np.exp(-sigma)
        / points.net_torque(speed.ravel()).reshape(sigma.shape)
    )  # dt/dsigma [s]
    coefficients = rate @ _TO_LEGENDRE.T  # each panel's Legendre series in its own x
    # each panel's antiderivative from its left edge, in sigma: legint in x, times dsigma/dx
    integral = np.polynomial.legendre.legint(coefficients, lbnd=-1, axis=1) * (0.5 * width)
    ends = np.concatenate([[0.0], np.cumsum(integral.sum(axis=1))])  # P_j(1) = 1
    tau = points.I_bar[0] / -float(slope(points, np.array([target]), np.array([True]))[0])
    result = np.empty(t.shape)
    tail = t >= ends[-1]
    near_gap = gap * math.exp(-far)
    result[tail] = target - near_gap * np.exp(-(t[tail] - ends[-1]) / tau)
    inside = _invert(t[~tail], edges, ends, integral, coefficients)
    result[~tail] = target - gap * np.exp(-inside)
    return result


DECAY_NODES = 129
"""Crank speeds from the kick down to rest on which a stalling spin-up's time is integrated."""


def stall_time(points: Points, theta_dot0: float) -> float:
    """When ``I-bar alpha' = F(alpha) < 0`` from theta_dot0 reaches rest [s]: ``I-bar int_0^theta_dot0
    dalpha / -F(alpha)`` (one point; F < 0 there), by adaptive quadrature."""
    if theta_dot0 == 0.0:
        return 0.0
    from scipy import integrate  # here, not at import: scipy.integrate takes ~0.5 s to load

    I_bar = float(points.I_bar[0])
    value, _ = integrate.quad(
        lambda a: I_bar / -float(points.net_torque(np.array([a]))[0]), 0.0, theta_dot0,
        epsabs=0.0, epsrel=1e-10, limit=200,
    )  # fmt: skip
    return float(value)


def _decay(points: Points, t: np.ndarray, theta_dot0: float) -> np.ndarray:
    """The speed [rad/s] of a spin-up that decays to rest (F < 0 from the kick down), 0 after:
    ``t(alpha) = I-bar int_alpha^theta_dot0 dalpha' / -F`` on Chebyshev nodes, integrated as
    their PCHIP interpolant and inverted by another."""
    from scipy.interpolate import PchipInterpolator  # (as scipy.integrate, above)

    x = 0.5 * (1.0 - np.cos(np.linspace(0.0, math.pi, DECAY_NODES)))  # 0 .. 1, dense at both ends
    alpha = theta_dot0 * x
    rate = points.I_bar[0] / -points.net_torque(alpha[None, :])[0]  # dt/d(-alpha) [s s/rad]
    elapsed = PchipInterpolator(alpha, rate).antiderivative()
    times = elapsed(theta_dot0) - elapsed(alpha)  # from the kick: decreasing in alpha
    speed = PchipInterpolator(times[::-1], alpha[::-1])(np.minimum(t, times[0]))
    return np.where(t < times[0], np.maximum(speed, 0.0), 0.0)


def _panel_edges(design, theta_dot0: float, target: float, far: float) -> np.ndarray:
    """sigma at the panels' edges [-] up to ``far``: SPINUP_PANEL apart up to 4, three times
    that beyond (the integrand tends to a constant there as exp(-sigma)), finer near the start
    (where a unit of sigma spans most of the way), and one where a face starts to deliver past
    its hole (the load's mean has a kink there)."""
    near = np.arange(0.0, min(far, 4.0), SPINUP_PANEL)
    beyond = np.arange(4.0, far, 3.0 * SPINUP_PANEL)
    start = [x for x in (1 / 16, 1 / 8, 1 / 4, 1 / 2) if x < far]
    edges = list(near) + list(beyond) + start + [far]
    peak = _branches(design.L_over_R)[1]
    delivering = design.leak_capacity / (design.A * design.R * peak)  # the crank speed [rad/s]
    fraction = (target - delivering) / (target - theta_dot0)
    if 0.0 < fraction < 1.0 and -math.log(fraction) < far:
        edges.append(-math.log(fraction))
    return np.unique(edges)


_SX, _SW = np.polynomial.legendre.leggauss(SPINUP_NODES)
_TO_LEGENDRE = np.linalg.inv(np.polynomial.legendre.legvander(_SX, SPINUP_NODES - 1))


def _invert(t, edges, ends, integral, coefficients):
    """sigma [-] at times t inside the panels: where the panel's t(sigma) is t, by Newton's
    method in the panel's x from the linear guess."""
    panel = np.clip(np.searchsorted(ends, t, side="right") - 1, 0, len(ends) - 2)
    start, span = ends[panel], ends[panel + 1] - ends[panel]
    width = edges[panel + 1] - edges[panel]
    x = np.clip(2.0 * (t - start) / np.where(span > 0.0, span, 1.0) - 1.0, -1.0, 1.0)
    degree = integral.shape[1] - 1
    for _ in range(8):
        basis = np.polynomial.legendre.legvander(x, degree)
        excess = start + (basis * integral[panel]).sum(axis=1) - t
        derivative = 0.5 * width * (basis[:, :-1] * coefficients[panel]).sum(axis=1)
        x = np.clip(x - excess / derivative, -1.0, 1.0)
    return edges[panel] + 0.5 * (x + 1.0) * width
