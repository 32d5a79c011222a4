"""The design map: stall margin, running speed, time constant and flow over gear ratio and head.

The first question a designer asks of a head and a windmill is which gear ratio R+ = R1/R0 pumps
the most water without stalling. By the averaged theory (Eqs. 19-25, generalised as in
:mod:`windpump.averaging.averaged`) the cycle-mean running speed is ``alpha+ = p (1 + s)`` with
``p = omega_m / R+`` and ``s = sqrt((T_m - u) / (T_m - T_0))``, ``u = M / R+`` the mean load
reflected to the windmill; the flow is ``m 2 R A alpha+ / 2 pi``. As a function of u it is
proportional to ``u (1 + s)``, which rises from 0 and falls to the stall (u = T_m) with one
maximum, where ``3 (T_m - T_0) s^2 + 2 (T_m - T_0) s = T_m``:

    s* = (sqrt(1 + 3 T_m / (T_m - T_0)) - 1) / 3,   R+* = M / (T_m - (T_m - T_0) s*^2).

With T_0 = 0, s* = 1/3 and the best gear puts the stall margin at exactly 9/8. The inertias do
not enter alpha+ (only tau). In a grid's range of ratios the best is R+* clipped to the range.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .. import _kernels
from .._kernels.grid import steady_runs
from ..averaging.theory import (
    cycle_mean,
    effective_inertia,
    load_torque,
    mean_load_torque,
    running_speeds,
)
from ..errors import ParameterError
from ..model.design import WIDEST_RATIO, Design
from ..model.torque import peak_torque
from ..progress import Progress, reporter
from ..run import dynamics  # dynamics.MAX_STEPS read at each map (a test lowers it)
from ..run.dynamics import (
    PACE_STEPS,
    RTOL,
    STIFF_STEPS,
    _stiff_advice,
    _windmill_slope,
    kernel_real_base,
)
from ..run.machine import kernel_rotor
from ..validation import LARGEST, SMALLEST, real_array

MAX_POINTS = 4_000_000
"""Largest design map (heads x gear ratios)."""

MEASURED_TURNS = 10
"""A numeric map measures speed and flow over the last this many revolutions of each run."""

SETTLE_TAUS, FEWEST_TURNS, MOST_TURNS = 8.0, 60, 4000
"""A numeric run lasts SETTLE_TAUS time constants, from FEWEST_TURNS to MOST_TURNS revolutions."""

JUMP = 3.0
"""A rise of alpha+ from one ratio of a map to the next over JUMP times the rises beside it is a
jump (:attr:`DesignMap.jump_gear_ratio`)."""

POINTS_PER_REPORT = 1000
"""A numeric map reports its progress after about this many runs."""


@dataclasses.dataclass(frozen=True)
class DesignMap:
    """A design over a grid of heads (rows) and gear ratios (columns): :func:`design_map`.

    Every 2-D array has the shape ``(len(heads), len(gear_ratios))`` and is NaN where the pump
    cannot run (the stall margin is 1 or less; in a numeric map also where the run stalled).

    Attributes
    ----------
    design : Design
        The design the map varies: R1 = R0 x gear ratio and h, every other field kept.
    gear_ratios : ndarray
        R+ = R1/R0 [-], increasing (the columns).
    heads : ndarray
        h [m], increasing (the rows).
    margin : ndarray
        Stall margin R+ T_m / M [-] (Eq. 22): inf at h = 0.
    alpha_plus : ndarray
        Cycle-mean running crank speed [rad/s] (Eq. 21, or measured in a numeric map).
    tau : ndarray
        Spin-up time constant [s] (Eq. 25; the averaged one in a numeric map too).
    mean_flow : ndarray
        Mean volume flow [m^3/s].
    best_gear_ratio : ndarray
        For each head, the gear ratio in the grid's range that lifts the most water [-]; NaN
        when no ratio in the range runs.
    best_flow : ndarray
        The mean flow at ``best_gear_ratio`` [m^3/s].
    numeric : bool
        Whether the speeds and flows come from full simulations (Eq. 12) rather than Eq. (21).
    """

    design: Design
    gear_ratios: np.ndarray
    heads: np.ndarray
    margin: np.ndarray
    alpha_plus: np.ndarray
    tau: np.ndarray
    mean_flow: np.ndarray
    best_gear_ratio: np.ndarray
    best_flow: np.ndarray
    numeric: bool = False

    @property
    def stall_gear_ratio(self) -> np.ndarray:
        """For each head, the gear ratio where the stall margin is 1 (Eq. 22) [-]: the averaged
        theory's stall boundary; the pump runs at larger ratios."""
        d = self.design
        if d.d_leak > 0.0:  # a leak hole never stalls
            return np.zeros(self.heads.shape)
        if d.rotor is not None:  # the margin is R+ eta_t T_peak / M without a pipe
            M = mean_load_torque(d.deliveries, load_torque(d.rho_w, d.g, self.heads, d.A, d.R))
            pipeless = M / (d.eta_t * float(peak_torque(d)))
            if d.friction_coefficient == 0.0:
                return pipeless
            return _stall_ratio_with_pipe(d, self.heads, pipeless)
        mean_load = cycle_mean(d, head=self.heads).mean_load
        if d.friction_coefficient == 0.0:
            return mean_load / (d.eta_t * d.T_m)
        return _stall_ratio_with_pipe(d, self.heads, mean_load / (d.eta_t * d.T_m))

    @property
    def jump_gear_ratio(self) -> np.ndarray:
        """For each head, the gear ratio at which the averaged pump's running speed jumps up
        [-]: where it starts lifting water in earnest.

        A tight pump's is its stall boundary (:attr:`stall_gear_ratio`): from rest to alpha+.
        A pump with a leak hole never stalls, but at small ratios the averaged equation's only
        steady speed is a slow one at which the hole passes all (or nearly all) the piston
        sweeps; where a faster root of F(alpha) = 0 appears (a fold) the running speed jumps to
        it and the flow with it. Found on the map's grid, each head's largest rise of alpha+
        from one ratio to the next when it is over ``JUMP`` times the rises beside it, then by
        bisection of the averaged theory (Eq. 21 with the real machine's load) to 1/1024 of
        the grid's step; NaN where the grid holds no such jump (a smooth rise, or a jump at or
        below its first ratio or above its last).

        Examples
        --------
        >>> import numpy as np
        >>> from windpump import Design, design_map
        >>> leaky = Design.seed_example().replace(d_leak=0.004)
        >>> m = design_map(leaky, np.linspace(0.5, 8.0, 41), [15.5])
        >>> float(m.stall_gear_ratio[0]), round(float(m.jump_gear_ratio[0]), 2)
        (0.0, 4.01)
        """
        if self.design.d_leak == 0.0:
            return self.stall_gear_ratio
        return _jump_ratio(self.design, self.gear_ratios, self.heads, self.alpha_plus)

    def design_at(self, row: int, column: int) -> Design:
        """The design at heads[row] and gear_ratios[column]."""
        ratio, head = float(self.gear_ratios[column]), float(self.heads[row])
        return self.design.replace(R1=self.design.R0 * ratio, h=head)

    def to_csv(self) -> str:
        """The map as CSV text, one row per grid point, units in the header.

        Examples
        --------
        >>> from windpump import Design, design_map
        >>> text = design_map(Design.seed_example(), [4.0], [3.0]).to_csv()
        >>> text.splitlines()[0]
        'h [m],gear_ratio [-],margin [-],alpha_plus [rad/s],tau [s],mean_flow [m^3/s]'
        """
        heads, ratios = np.meshgrid(self.heads, self.gear_ratios, indexing="ij")
        columns = (heads, ratios, self.margin, self.alpha_plus, self.tau, self.mean_flow)
        header = "h [m],gear_ratio [-],margin [-],alpha_plus [rad/s],tau [s],mean_flow [m^3/s]"
        rows = np.column_stack([np.ravel(column) for column in columns])
        lines = [header] + [",".join(f"{value:.12g}" for value in row) for row in rows]
        return "\n".join(lines) + "\n"


def design_map(
    design: Design,
    gear_ratios,
    heads,
    *,
    numeric: bool = False,
    progress: bool | Progress | None = None,
) -> DesignMap:
    """Stall margin, running speed, time constant and mean flow over gear ratios and heads.

    By the averaged theory (Eqs. 21, 22, 25, generalised to several cylinders, double-acting
    pistons and T_0), vectorised over the grid; the gear ratio R+ is varied through R1 with R0
    fixed, so I_eff = I1 + I0 R+^2 changes with it. For each head the best gear ratio in the
    grid's range is found in closed form (module docstring).

    With ``numeric=True`` every point that runs by the averaged theory is simulated in full
    (Eq. 12, compiled, in parallel over the cores) from theta = 0 at its alpha+, for 8 tau (60
    to 4000 revolutions), and speed and flow are measured over its last 10 revolutions: near the
    stall boundary the speed ripple within a revolution lowers the windmill's mean torque, and
    the real pump runs slower or stalls where the averaged one runs. The best gear ratio is then
    the grid's best, refined by a parabola through it and its neighbours (in log R+).

    Parameters
    ----------
    design : Design
        Every field but R1 and h is kept (cylinders, double_acting, T_0; V_ref: the map is in
        the design's wind).
    gear_ratios : array_like
        R+ = R1/R0 [-], increasing, > 0.
    heads : array_like
        Heads h [m], increasing, >= 0.
    numeric : bool, default False, keyword-only
        Measure speed and flow in full simulations.
    progress : bool, callable or None, keyword-only
        A numeric map's progress: a callable taking (done, total), True or False for a tqdm
        bar or none, None for a bar only in a terminal.

    Returns
    -------
    DesignMap

    Raises
    ------
    ParameterError
        Naming ``gear_ratios`` or ``heads`` when they are empty, not increasing, out of range,
        or the grid is larger than ``MAX_POINTS``.

    Examples
    --------
    >>> import numpy as np
    >>> from windpump import Design, design_map
    >>> m = design_map(Design.seed_example(), np.linspace(0.5, 30, 200), [3.0, 10.0])
    >>> [round(float(r), 3) for r in m.best_gear_ratio]  # margin 9/8 at the best gear
    [0.883, 2.943]
    >>> from windpump.units import SECONDS_PER_DAY
    >>> per_day = m.best_flow * SECONDS_PER_DAY  # m^3/day (32.8 at the paper's R+ = 4)
    >>> [round(float(q)) for q in per_day]
    [104, 31]
    """
    if not isinstance(design, Design):
        raise TypeError(f"design must be a windpump.Design, not {type(design).__name__}")
    ratios = _grid("gear_ratios", gear_ratios, "", 1 / WIDEST_RATIO, WIDEST_RATIO)
    heads = _grid("heads", heads, "m", 0.0, LARGEST)
    _check_corners(design, ratios, heads)
    margin, alpha_plus, tau, mean_flow = _averaged_grid(design, ratios, heads)
    if numeric:
        alpha_plus, tau = _simulated_speeds(design, ratios, heads, alpha_plus, tau, progress)
        mean_flow = design.volume_per_revolution * alpha_plus / (2 * math.pi)
    if numeric or design.d_leak > 0.0 or design.friction_coefficient > 0.0 or design.rotor:
        best_ratio, best_flow = _refined_best(ratios, mean_flow)
    else:
        best_ratio = _best_gear_ratio(design, ratios, heads)
        best = cycle_mean(design, gear_ratio=best_ratio, head=heads)
        best_flow = design.volume_per_revolution * best.alpha_plus / (2 * math.pi)
    return DesignMap(
        design=design,
        gear_ratios=ratios,
        heads=heads,
        margin=margin,
        alpha_plus=alpha_plus,
        tau=tau,
        mean_flow=mean_flow,
        best_gear_ratio=best_ratio,
        best_flow=best_flow,
        numeric=numeric,
    )


def _grid(name: str, values, unit: str, lowest: float, highest: float) -> np.ndarray:
    """``values`` as a 1-D increasing float array in [lowest, highest], or a ParameterError."""
    array = np.atleast_1d(real_array(name, values, unit))
    if array.ndim != 1 or array.size == 0:
        raise ParameterError(name, f"shape {array.shape}", "a non-empty 1-D sequence", unit)
    bad = ~np.isfinite(array) | (array < lowest) | (array > highest)
    if bad.any():
        limits = f"finite numbers from {lowest:g} to {highest:g}"
        raise ParameterError(name, float(array[bad][0]), limits, unit)
    if np.any(np.diff(array) <= 0.0):
        raise ParameterError(name, f"{array.tolist()[:6]}...", "strictly increasing", unit)
    return array


def _check_corners(design: Design, ratios: np.ndarray, heads: np.ndarray) -> None:
    """Refuse a grid too large, or whose extreme designs are not valid Designs."""
    points = ratios.size * heads.size
    if points > MAX_POINTS:
        raise ParameterError(
            "heads", f"{heads.size} x {ratios.size} gear ratios", f"<= {MAX_POINTS} points"
        )
    for ratio in (ratios[0], ratios[-1]):
        R1 = design.R0 * ratio
        if not SMALLEST <= R1 <= LARGEST:
            raise ParameterError(
                "gear_ratios", float(ratio), f"R0 x ratio from {SMALLEST:g} to {LARGEST:g} m"
            )
    design.replace(h=float(heads[-1]))


def _averaged_grid(design: Design, ratios: np.ndarray, heads: np.ndarray):
    """margin, alpha+ [rad/s], tau [s] and mean flow [m^3/s] on the grid (rows: heads), NaN
    where margin <= 1: the averaged equation of :mod:`windpump.averaging.theory`, broadcast."""
    speeds = running_speeds(design, gear_ratio=ratios[np.newaxis, :], head=heads[:, np.newaxis])
    return speeds.margin, speeds.alpha_plus, speeds.tau, speeds.mean_flow


def _jump_ratio(
    design: Design, ratios: np.ndarray, heads: np.ndarray, alpha: np.ndarray, steps: int = 10
) -> np.ndarray:
    """:attr:`DesignMap.jump_gear_ratio` of a leaky pump (never stalled: alpha > 0), all heads'
    brackets bisected ``steps`` times at once: the middle is on the fast side when its speed is
    nearer the fast end's."""
    rises = np.diff(alpha, axis=1)
    at = np.argmax(rises, axis=1)
    rows = np.arange(len(heads))
    padded = np.pad(np.abs(rises), ((0, 0), (1, 1)))  # no rise beyond the grid's ends
    beside = np.maximum(padded[rows, at], padded[rows, at + 2])
    rows = np.flatnonzero((rises[rows, at] > JUMP * beside) & (rises[rows, at] > 0.0))
    low, high = ratios[at[rows]], ratios[at[rows] + 1]
    slow, fast = alpha[rows, at[rows]], alpha[rows, at[rows] + 1]
    for _ in range(steps if rows.size else 0):
        middle = 0.5 * (low + high)
        speed = running_speeds(design, gear_ratio=middle, head=heads[rows]).alpha_plus
        up = speed - slow > fast - speed
        low, slow = np.where(up, low, middle), np.where(up, slow, speed)
        high, fast = np.where(up, middle, high), np.where(up, speed, fast)
    edge = np.full(heads.shape, np.nan)
    edge[rows] = high
    return edge


def _best_gear_ratio(design: Design, ratios: np.ndarray, heads: np.ndarray) -> np.ndarray:
    """For each head, R+* of the module docstring clipped to the grid's range; NaN when even the
    largest ratio in the range cannot carry the load (the margin grows with R+). The chain's
    efficiency enters as a mean load M / eta_t."""
    c = design.T_m - design.T_0
    s = (math.sqrt(1.0 + 3.0 * design.T_m / c) - 1.0) / 3.0
    M = cycle_mean(design, head=heads).mean_load
    best = np.clip(M / (design.eta_t * (design.T_m - c * s * s)), ratios[0], ratios[-1])
    return np.where(ratios[-1] * design.eta_t * design.T_m > M, best, np.nan)


def _stall_ratio_with_pipe(design: Design, heads: np.ndarray, pipeless: np.ndarray) -> np.ndarray:
    """For each head, the gear ratio where the margin with a rising main is 1 [-], by bisection
    in log R+ on the closed-form margin: above the pipeless ratio (the pipe adds load), below
    any ratio where the margin exceeds 1."""
    low = np.where(pipeless > 0.0, pipeless, np.nan)
    high = low.copy()
    closed = design.rotor is None
    for _ in range(200):  # the first ratio above the boundary, doubling
        short = _margin(design, high, heads, closed) <= 1.0
        if not short.any():
            break
        high = np.where(short, 2.0 * high, high)
    for _ in range(100 if closed else 60):  # (60 halvings of a factor 2 in log R+: 1e-18)
        middle = np.sqrt(low * high)
        short = _margin(design, middle, heads, closed) <= 1.0
        low, high = np.where(short, middle, low), np.where(short, high, middle)
    return np.where(pipeless > 0.0, high, 0.0)


def _margin(design: Design, gear_ratio, heads, closed: bool):
    """The stall margin at these gear ratios and heads: in closed form (Eq. 11) or not (a rotor;
    NaN ratios, from heads with no load, give NaN)."""
    if closed:
        return cycle_mean(design, gear_ratio=gear_ratio, head=heads).margin
    ratio = np.where(np.isfinite(gear_ratio), gear_ratio, 1.0)
    margin = running_speeds(design, gear_ratio=ratio, head=heads).margin
    return np.where(np.isfinite(gear_ratio), margin, np.nan)


def _simulated_speeds(design, ratios, heads, alpha_plus, tau, progress):
    """alpha+ measured in full simulations of every running point, and tau where they ran."""
    shape = alpha_plus.shape
    x = np.broadcast_to(ratios[np.newaxis, :], shape).ravel()
    loads = load_torque(design.rho_w, design.g, heads, design.A, design.R)
    load = np.broadcast_to(loads[:, np.newaxis], shape).ravel()
    kick = np.nan_to_num(alpha_plus.ravel(), nan=0.0)
    turns = np.clip(SETTLE_TAUS * tau.ravel() * kick / (2 * math.pi), FEWEST_TURNS, MOST_TURNS)
    t_end = np.where(kick > 0.0, turns * 2 * math.pi / np.where(kick > 0.0, kick, 1.0), 0.0)
    inv_I_eff = 1.0 / effective_inertia(design.I1, design.I0, x)
    # A rotor too light for its windmill at a point is refused before any run, as simulate does
    # (the run would take MAX_STEPS, ~20-60 s, to find it: check_work).
    light = STIFF_STEPS * _windmill_slope(design, x) * inv_I_eff * t_end > dynamics.MAX_STEPS
    _refuse_stiff(design, x, heads[np.arange(x.size) // ratios.size], np.where(light, _kernels.OVER_BUDGET, -1),
                  inv_I_eff, t_end)  # fmt: skip
    # Runs differ in cost (slow stalls, many fast turns): a shuffled order balances the cores.
    order = np.random.default_rng(0).permutation(x.size)
    speed = np.full(x.size, np.nan)
    report = reporter(progress, x.size, "design map")
    base = np.array([design.T_m, design.T_0, design.omega_m, design.L_over_R])
    for start in range(0, x.size, POINTS_PER_REPORT):
        chunk = order[start : start + POINTS_PER_REPORT]
        measured, _, outcomes = steady_runs(
            x[chunk], inv_I_eff[chunk], load[chunk], kick[chunk], t_end[chunk], base,
            design.cylinders, design.double_acting, MEASURED_TURNS, RTOL, dynamics.MAX_STEPS, PACE_STEPS,
            kernel_real_base(design), kernel_rotor(design),
        )  # fmt: skip
        speed[chunk] = measured
        _refuse_stiff(
            design, x[chunk], heads[chunk // ratios.size], outcomes, inv_I_eff[chunk],
            t_end[chunk],
        )  # fmt: skip
        report(min(start + POINTS_PER_REPORT, x.size), x.size)
    speed = speed.reshape(shape)
    return speed, np.where(np.isnan(speed), np.nan, tau)


def _refuse_stiff(design, ratios, heads, outcomes, inv_I_eff, t_end) -> None:
    """Refuse a map where a run needed more than MAX_STEPS steps (as :func:`windpump.simulate`
    refuses that design), rather than leave NaN there as if it stalled, with the advice that
    fits the design at that gear ratio and head (``dynamics._stiff_advice``)."""
    stiff = np.flatnonzero(outcomes == _kernels.OVER_BUDGET)
    if stiff.size:
        i = stiff[0]
        try:
            there = design.replace(R1=design.R0 * float(ratios[i]), h=float(heads[i]))
            advice = _stiff_advice(there, float(t_end[i]))
        except ParameterError:  # a gear ratio whose R1 is out of the range (no advice there)
            advice = "map other gear ratios and heads"
        raise ParameterError(
            "design",
            f"I_eff = {1.0 / inv_I_eff[i]:.3g} kg m^2 at gear ratio {ratios[i]:.6g}, "
            f"head {heads[i]:.6g} m",
            "a design whose crank speed settles over more than a crank revolution",
            why=f"{stiff.size} run(s) of this map need more than the integrator's step budget: "
            f"the design is too stiff there: {advice}",
        )


def _refined_best(ratios: np.ndarray, flow: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each row, the grid's best ratio and flow, refined by a parabola in log R+ through the
    best point and its two neighbours when all three ran."""
    rows = flow.shape[0]
    best_ratio, best_flow = np.full(rows, np.nan), np.full(rows, np.nan)
    logs = np.log(ratios)
    for row in range(rows):
        if np.all(np.isnan(flow[row])):
            continue
        j = int(np.nanargmax(flow[row]))
        best_ratio[row], best_flow[row] = ratios[j], flow[row, j]
        if 0 < j < len(ratios) - 1 and np.all(np.isfinite(flow[row, j - 1 : j + 2])):
            a, b, c = np.polyfit(logs[j - 1 : j + 2], flow[row, j - 1 : j + 2], 2)
            if a < 0.0:
                peak = -b / (2 * a)
                best_ratio[row] = math.exp(peak)
                best_flow[row] = (a * peak + b) * peak + c
    return best_ratio, best_flow
