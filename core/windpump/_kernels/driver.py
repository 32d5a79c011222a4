"""The driver: Eq. (12) from a start to t_end or a stop, segment by segment, sampled on a grid.

Between switches (every pi / n of crank angle, see :mod:`.model`) the crank angle is the
independent variable (:mod:`.stepping`), and a segment is split into m equal sub-steps, m chosen
from the error estimates of the previous segment (for the real machine, of the previous segment
of the same parity; a leak's kink cuts a sub-step in two and the split goes on). Every segment of the same parity loads the crank
the same way (a shift of 2 pi / n turns cylinder k into k - 1), so what a split needs at its stage
nodes is tabulated once per run. Where theta is a poor variable (the crank near rest) or a step
would pass t_end, the run goes on in time as far as the next grid angle or switch.
"""

from __future__ import annotations

import math
import typing

import numpy as np

from .dopri5 import step_factor
from .jit import inline_kernel, kernel
from .model import Machine, segment_at, segment_start
from .real import (
    M_PARTS,
    ROW,
    add_integrals,
    conservative_work,
    energy_slope,
    fill_row,
    friction_at,
    friction_parts,
    friction_since,
    frozen_energy,
    frozen_record,
    frozen_start,
    frozen_work,
    inertia_at,
    inertia_ratio,
    inertia_since,
    jump_work,
    leak_scale,
    less_frozen,
    next_leak_kink,
    no_friction,
    no_integrals,
    not_known,
    open_windows,
    split_sizes_by_parity,
    step_rows,
    time_back,
    time_frozen,
    window_edges,
    window_jump,
    work_rows,
    zero_work,
)
from .samples import FLOW_FACTOR as FLOW_FACTOR  # read by the typed front (__init__)
from .samples import ROWS as ROWS
from .samples import (
    note_event,
    record,
    record_anywhere,
    record_end,
    record_grid_angles,
    record_in_step,
    record_rest,
    time_of_sample,
    with_room,
)
from .stepping import (
    ANGLE,
    LANDED,
    OVER_BUDGET,
    REACHED_T_END,
    RESTING,
    STALLED,
    START,
    STOP,
    advance_in_time,
    dp5_step,
    moves_from_rest,
    next_start,
    off_pace,
    rates,
)
from .tables import (
    C1,
    C2,
    C3,
    grid_tables,
    stage_values,
    stage_work,
    tabulate_segment,
    without_wind,
)
from .wind import has_record, next_kink

M1, M2, M3 = M_PARTS  # and of its moment over a sub-step

# The time per step is a quadrature of 1/theta_dot: its error matters relative to the step's
# duration. At 10 rtol it leaves running designs to the u test and still guards slow starts.
TIME_RTOL_FACTOR = 10.0
MAX_TABLED_SUBSTEPS = 64  # segments split into more equal sub-steps compute their loads
MAX_SUBSTEPS = 2**20  # a segment that needs more is finished in time
FIRST_SUBSTEPS = 4


@kernel
def faces(machine):
    """Delivering faces: stroke volumes 2 R A delivered per revolution."""
    return machine.cylinders * (2 if machine.double_acting else 1)


@kernel
def kinetic(theta, theta_dot, machine):
    """Kinetic energy per unit I_eff, J theta_dot^2 / (2 I_eff) [rad^2/s^2]."""
    return 0.5 * inertia_ratio(theta, machine) * theta_dot * theta_dot


@kernel
def first_segment(theta, machine):
    """The segment holding theta, robust to round-off at a switch."""
    segment = segment_at(theta, machine)
    if segment_start(segment + 1, machine) <= theta:
        segment += 1
    return segment


class Run(typing.NamedTuple):
    """What :func:`integrate` returns."""

    out: np.ndarray  # out[:, :samples]: by rows T ... FLOW_FACTOR (and WORK on), every sample
    samples: int  # the start, the grid samples and the end
    outcome: int  # REACHED_T_END, STALLED, RESTING or OVER_BUDGET
    steps: int  # Dormand-Prince steps taken, rejected ones included
    events: np.ndarray  # events[:, :event_count]: the time (row 0) of every STOP and START (row 1)
    event_count: int


class Limits(typing.NamedTuple):
    """Where a run stops and how closely it follows Eq. (12)."""

    t_end: float  # [s]
    rtol: float  # the steps' relative tolerance [-]
    max_steps: int  # Dormand-Prince steps at most (then OVER_BUDGET)
    pace: int  # every this many steps, OVER_BUDGET if the run is on pace to pass max_steps by
    # t_end (:func:`~.stepping.off_pace`): a stiff run is refused at once, not after max_steps;
    # pace >= max_steps checks no pace (in a wind record a calm stretch may follow)
    mark: np.ndarray  # (steps, t) where the pace's current window began


class Grid(typing.NamedTuple):
    """The output grid of crank angles g delta."""

    delta: float  # pi / n_per_stroke [rad]
    period: int  # grid angles per revolution, 2 n_per_stroke
    per_revolution: int  # stroke volumes delivered per revolution (:func:`faces`)


# How a split's sub-steps ended (:func:`in_angle`): every one taken; one failed (a finer
# split follows); one landed on a kink (a new split from there); theta is a poor variable (on in
# time); the step budget ran out.
SPLIT_DONE, REFINED, ON_KINK, IN_TIME, OUT_OF_STEPS = range(5)


@inline_kernel
def sub_step_tables(machine):
    """Room for the stage values (:func:`stage_values`) of every split of a segment of either
    parity into up to MAX_TABLED_SUBSTEPS sub-steps, none built yet (:func:`tabulate_segment`),
    and Lambda at the end of a segment of each parity."""
    tables = np.empty((2, MAX_TABLED_SUBSTEPS + 1, MAX_TABLED_SUBSTEPS, 8))
    row_tables = np.empty((2, MAX_TABLED_SUBSTEPS + 1, MAX_TABLED_SUBSTEPS, 7, ROW))
    built = np.zeros((2, MAX_TABLED_SUBSTEPS + 1), dtype=np.bool_)
    end_work = (
        conservative_work(segment_start(1, machine), 0, machine),
        conservative_work(segment_start(2, machine), 1, machine),
    )
    return tables, row_tables, built, end_work


@inline_kernel
def start_from_rest(out, n, j, sample_dt, theta0, t_end, W, segment, machine, events, count):
    """A run from rest at theta0: it moves at once, or in a wind record when the wind can turn it
    (resting until then), or never. Returns (outcome, out, n, j, t, events, count): the outcome
    STALLED or RESTING when the run ends here, else -1 and the time the crank starts."""
    waits = has_record(machine.wind)  # a resting crank waits for the wind, to t_end
    start = next_start(0.0, theta0, segment, machine) if waits else 0.0
    if not moves_from_rest(start, theta0, segment, machine) or start >= t_end:
        if not waits:
            return STALLED, out, n, j, 0.0, events, count
        out, n, j = record_rest(out, n, j, sample_dt, 0.0, t_end, theta0, W, segment, machine)
        return RESTING, out, n, j, 0.0, events, count
    if start > 0.0:
        out, n, j = record_rest(out, n, j, sample_dt, 0.0, start, theta0, W, segment, machine)
    events, count = note_event(events, count, start, START)
    return -1, out, n, j, start, events, count


@inline_kernel
def first_grid_index(theta0, delta):
    """The first grid angle g delta past theta0, by its index g."""
    g = int(math.floor(theta0 / delta)) + 1
    if g * delta <= theta0:  # theta0 sits on a grid angle, up to round-off
        g += 1
    return g


@inline_kernel
def end_grid_index(segment, n_per_stroke, sample_dt, machine):
    """The grid index of the segment's end, when the end is a grid angle (else -1, as always on
    a time grid)."""
    ends = (segment + 1) * n_per_stroke
    end_grid = ends // machine.cylinders if ends % machine.cylinders == 0 else -1
    if sample_dt is not None:
        end_grid = -1  # no grid angles on a time grid
    return end_grid


@inline_kernel
def leak_kinks(theta, theta_dot, width, segment, machine, leak_kink, later_kink, kink_segment):
    """The next angles where a face starts or stops delivering through its hole: found for a
    segment at its first speed, used as the run passes them (a landing is up to round-off).
    Returns (the next, the one after, the segment they are of)."""
    if kink_segment != segment:
        leak_kink, later_kink = next_leak_kink(theta, theta_dot, segment, machine)
        kink_segment = segment
    elif theta >= leak_kink - 1e-9 * width:
        leak_kink, later_kink = later_kink, math.inf
    return leak_kink, later_kink, kink_segment


@inline_kernel
def near_rest(k1, torque, h, theta_i, g, delta, sample_dt, u, machine):
    """Whether u may change by more than itself before the next grid angle (on a time grid, as
    far as a grid angle would be: pi / n_per_stroke): theta_dot is near 0, where theta is
    singular (dt/dtheta = 1/theta_dot) but time is not, and the run goes on in time."""
    reach = max(h, delta if sample_dt is not None else g * delta - theta_i)
    return abs(k1[0] + torque * machine.inv_I_eff) * reach >= u


@inline_kernel
def scaled_error(err, y, t, u, rtol, width, machine):
    """A sub-step's error, scaled: at most 1 to accept it. u against rtol, the time against
    TIME_RTOL_FACTOR rtol of the step's duration, the leaked volume against :func:`leak_scale`."""
    return max(
        abs(err[0]) / (rtol * u),
        abs(err[2]) / (TIME_RTOL_FACTOR * rtol * max(y[2] - t, 1e-300)),
        abs(err[3]) / (rtol * leak_scale(width, machine)),  # (0 for the ideal machine)
    )


@inline_kernel
def finer_split(ok, scaled, h_step, width, m):
    """After a failed sub-step: (REFINED, the sub-steps of a full segment from now on), or
    (IN_TIME, m) when sub-steps that fine no longer suit theta."""
    needed = width / (h_step * (step_factor(scaled) if ok else 0.25))
    if needed > MAX_SUBSTEPS:
        return IN_TIME, m
    return REFINED, max(m + 1, int(math.ceil(needed)))


@inline_kernel
def next_split_size(width, h, worst):
    """Sub-steps of a full segment, from the worst scaled error of sub-steps h long."""
    return min(MAX_SUBSTEPS, max(1, int(math.ceil(width / (h * step_factor(worst))))))


@inline_kernel
def sub_step_end(last, end, end_work, theta_i, h_step, at_table, tabled, segment, machine):
    """Where a sub-step ends and the conservative work there: the segment's end, exactly, after
    its last sub-step; else from its stage values (``aux``: its last node is the end) unless
    they are of a longer step (one a wind record's kink cut short after a tabled one)."""
    if last:
        return end, end_work
    theta_new = theta_i + h_step
    work = tabled if at_table else conservative_work(theta_new, segment, machine)
    return theta_new, work


@inline_kernel
def wait_for_wind(out, n, j, sample_dt, t, theta, W, t_end, segment, machine, events, count):
    """A crank that stalled at t in a wind record rests until the wind can turn it again (or to
    t_end). Returns (RESTING or -1: it moves again, out, n, j, the time it starts, events,
    count)."""
    events, count = note_event(events, count, t, STOP)
    start = next_start(t, theta, segment, machine)
    rest_end = min(start, t_end)
    out, n, j = record_rest(out, n, j, sample_dt, t, rest_end, theta, W, segment, machine)
    if start >= t_end:
        return RESTING, out, n, j, start, events, count
    events, count = note_event(events, count, start, START)
    return -1, out, n, j, start, events, count


@inline_kernel
def time_stretch(out, n, j, g, steps, kink, t, theta, theta_dot, W, u, full, end, end_grid,
                 limits, grid, at_grid, sample_dt, segment, machine, events, count):  # fmt: skip
    """On in time (:func:`~.stepping.advance_in_time`) as far as the next grid angle or switch
    (or sample time, or wind kink), where the run goes on, or to a stop or the end. Returns
    (the run's outcome or -1, out, n, j, g, steps, kink, t, theta, theta_dot, W, u, full,
    segment, events, count)."""
    t_end, rtol, max_steps, pace, mark = limits
    delta, period, per_revolution = grid
    target = end if g == end_grid or sample_dt is not None else min(g * delta, end)
    until = min(t_end, kink)
    if sample_dt is not None:
        until = min(until, j * sample_dt)
    outcome, t, theta, theta_dot, W, used = advance_in_time(
        t, theta, theta_dot, W, target, until, segment, machine, rtol, max_steps - steps,
        steps, t_end, max_steps, pace, mark,
    )  # fmt: skip
    steps += used
    out = with_room(out, n, 1)
    if outcome == REACHED_T_END and t < t_end:  # a sample time or a kink
        if sample_dt is not None and t == j * sample_dt:
            n = record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, False)
            j += 1
        if t == kink:
            kink = next_kink(t, machine.wind)
        u, full, outcome = kinetic(theta, theta_dot, machine), False, -1
    elif outcome == STALLED and has_record(machine.wind):  # rest until the wind can turn it
        outcome, out, n, j, t, events, count = wait_for_wind(
            out, n, j, sample_dt, t, theta, W, t_end, segment, machine, events, count
        )
        theta_dot, u = 0.0, 0.0
        if outcome == -1:
            kink = next_kink(t, machine.wind)
            full = theta == segment_start(segment, machine)
    elif outcome != LANDED:
        if outcome == STALLED:
            events, count = note_event(events, count, t, STOP)
        if outcome != OVER_BUDGET:
            n = record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, True)
    else:
        u, full, outcome = kinetic(theta, theta_dot, machine), target == end, -1
        if full:
            segment += 1
        if g == end_grid or (target != end and sample_dt is None):
            strokes_table, flow_table, _, _ = at_grid
            row = g % period
            strokes = (g // period) * per_revolution + strokes_table[row]
            n = record(out, n, t, theta, theta_dot, W, strokes, flow_table[row], False)
            g += 1
    return (outcome, out, n, j, g, steps, kink, t, theta, theta_dot, W, u, full, segment,
            events, count)  # fmt: skip


@inline_kernel
def split_of(m, full, theta, width, n_per_stroke, sample_dt, segment, machine):
    """Split the rest of the segment, from theta to its end, into m_seg equal sub-steps h long
    (m over a full segment ``width`` long), their stage values tabulated or not. Returns (end,
    parity, the end's grid index, m_seg, use_table, h)."""
    end = segment_start(segment + 1, machine)
    end_grid = end_grid_index(segment, n_per_stroke, sample_dt, machine)
    m_seg = m if full else max(1, int(math.ceil(m * (end - theta) / width)))
    use_table = full and m_seg <= MAX_TABLED_SUBSTEPS
    # (over a full segment by the reciprocal, as LLVM has always compiled it: arcp)
    h = (end - theta) * (1.0 / m_seg) if full else (end - theta) / m_seg
    return end, segment % 2, end_grid, m_seg, use_table, h


@inline_kernel
def tabled_end(i, m_seg, first, h, end, C):
    """(Where tabled sub-step i of a split ends, the real machine's C there), for the pieces a
    hole's kink cuts from it."""
    return (end if i == m_seg - 1 else first + (i + 1) * h), C


@inline_kernel
def rest_of_sub_step(theta, first, i, m_seg, h, end):
    """The length from theta, a leak's kink inside sub-step i of a split from ``first``, to
    where that sub-step ends (the segment's end after the last)."""
    return (end if i == m_seg - 1 else first + (i + 1) * h) - theta


@inline_kernel
def leak_cut(theta_i, h, leak_kink):
    """A sub-step's length: h, or as far as a leak's kink inside it. Returns (length, whether
    it ends on the kink)."""
    if theta_i < leak_kink < theta_i + h:  # a face starts or stops delivering inside
        return leak_kink - theta_i, True
    return h, False


@kernel
def step_to_kink(kink, theta_i, h_step, u_free, t, W, k1, y, k7, dense, scratch, scratch_rows,
                 c_at, e_ref, segment, machine):  # fmt: skip
    """A sub-step from theta_i that passed a wind record's kink, taken again only as far as it,
    from where the step's continuous extension puts the kink's time (the rest of the segment
    follows in smaller sub-steps). Returns (ok, y, k7, err, dense, its length)."""
    h_step *= time_of_sample(kink, t, y[2], k1[2], k7[2], dense[1], h_step)
    stage_values(
        theta_i, h_step, segment, machine, scratch, scratch_rows, c_at, not_known(machine), False
    )
    ok, y, k7, err, dense = dp5_step(
        ANGLE, theta_i, u_free, t, t, W, h_step, k1, stage_work(scratch),
        step_rows(scratch_rows, e_ref, -1.0, (0.0, 0.0), machine), segment, machine,
    )  # fmt: skip
    return ok, y, k7, err, dense, h_step


@inline_kernel
def past_sub_step(y, theta_new, u_new, k7, scaled, worst, i, at_kink, at_wind_kink, whole, m,
                  width, h, j_new):  # fmt: skip
    """The state after sub-step i, accepted, to theta_new: (u_free, t, W, theta, u, theta_dot,
    k1, the worst scaled error so far, the next sub-step's index, m, ON_KINK or SPLIT_DONE).
    Past a wind record's kink (up to round-off in its time) the run goes on from there in a new
    split of m sub-steps from the errors so far. Past a leak's kink the split goes on: the rest of
    sub-step i (its index kept), off the tables, then its next sub-steps on them. Only ``whole``
    sub-steps (not cut by a leak's kink) count in the worst error, from which m follows. j_new
    is J / I_eff at theta_new (:func:`~.real.inertia_at`)."""
    theta_dot = math.sqrt(2.0 * u_new / j_new)
    if whole:
        worst = max(worst, scaled)
    status = SPLIT_DONE
    if at_wind_kink:
        m = next_split_size(width, h, worst)
        status = ON_KINK
    if at_wind_kink or not at_kink:
        i += 1
    return y[0], y[2], y[3], theta_new, u_new, theta_dot, k7, worst, i, m, status


@inline_kernel
def after_split(status, i, m_seg, full, m, width, h, worst, segment, past_leak, wholes):
    """After a split's sub-steps: on to the next segment when they all were taken (m from the
    worst scaled error of those a leak's kink did not cut, if any), else on from part of this one
    (from its start only when no step was taken). Returns (segment, full, m)."""
    if status != SPLIT_DONE:
        return segment, full and i == 0 and not past_leak, m
    if (full or m_seg > 1) and wholes:  # a single sub-step of a tail is short by position
        m = next_split_size(width, h, worst)
    return segment + 1, True, m


@inline_kernel
def in_angle(
    out, n, j, g, steps, kink, m, t, theta, theta_dot, u, W, full, segment, leak, tables,
    row_tables, built, scratch, scratch_rows, at_grid, end_work, limits, grid, width,
    n_per_stroke, sample_dt, machine,
):  # fmt: skip
    """Segment after segment in angle, each split into sub-steps (:func:`split_of`) sampled on
    the output grid, until the run reaches t_end on a switch, runs out of steps, or finds theta
    a poor variable (IN_TIME). The segment and sub-step loops share one body: an inlined helper
    taking arrays counts two atomic references per array per call (the sub-step loop as a helper
    of its own, called per segment, took six double-acting cylinders 17 % longer). Returns
    (status, out, n, j, g, steps, kink, m, t, theta, theta_dot, u, W, full, segment, leak, the
    segment's end and its grid index)."""
    t_end, rtol, max_steps, pace, mark = limits
    strokes_table, flow_table, work_table, inertia_table = at_grid
    calm = without_wind(machine)  # for the helpers: a wind record's arrays are counted per call
    m_other = m  # the real machine's sub-steps of a segment of the other parity
    # The real machine's C (the frozen friction's, :mod:`.real`) since the segment began
    c_at = no_friction(calm)
    if not full:
        c_at = friction_since(segment_start(segment, calm), theta, c_at, segment, calm)
    # A segment stepped past its leak hole's windows: its delivering faces (:mod:`.real`)
    faces = -1.0
    # and int (j - 1) since it began (the masses' frozen ripple in the time: :mod:`.real`)
    j_at = no_integrals(calm) if full else inertia_since(theta, segment, calm)
    windows_off = False  # the rest of this segment is stepped on its kinks (it ends past t_end)
    clear_of_window = math.inf  # past here the segment's start window is behind
    edges = window_edges(calm)  # what the windows take at a segment's edges, by parity
    while True:
        end, parity, end_grid, m_seg, use_table, h = split_of(
            m, full, theta, width, n_per_stroke, sample_dt, segment, calm
        )
        if use_table and not built[parity, m_seg]:
            tabulate_segment(parity, m_seg, machine, tables, row_tables, built)
        work = 0.0 if full else conservative_work(theta, segment, machine)
        e_ref = frozen_energy(u, calm)  # the real machine's friction frozen at this energy
        # u less the conservative work (and the frozen friction's): only the windmill and the
        # rest of the losses change it
        u_free = frozen_start(u, work, e_ref, c_at, calm)
        if use_table:
            rows = row_tables[parity, m_seg, 0]
        else:
            rows = scratch_rows
            fill_row(rows[0], theta, segment, machine)
            # (the real machine's C; the ideal machine's rows ignore it)
            rows[0, C1], rows[0, C2], rows[0, C3] = friction_parts(c_at, calm)
        if full or windows_off:
            faces = -1.0
        tau = time_frozen(u, sample_dt is None and not has_record(machine.wind), calm)
        k1 = rates(ANGLE, theta, u_free, t, work, step_rows(rows, e_ref, faces, tau, calm)[0],
                   machine, segment)  # fmt: skip
        jumped = False  # a leak hole's window after the start was jumped (:mod:`.real`)
        u_before, t_before, W_before = u, t, W
        past_t_end = False
        if full and not windows_off and sample_dt is None and not has_record(machine.wind):
            edge = edges[parity][0]
            slope = energy_slope(k1[0], e_ref, edge, calm)
            faces = open_windows(theta, u, slope, h, segment, grid.delta, edge[2], calm)
            if faces >= 0.0:
                jumped, clear_of_window = True, theta + h
            if faces > 0.0:  # (an intake segment's windows are empty: no jump, no call)
                jump, dt, dW = window_jump(
                    theta, u, slope, 1.0, segment, faces, edge[2], scratch_rows, calm
                )  # (the scratch's row 6: a split off the tables has filled only row 0)
                u, t, W = u + jump, t + dt, jump_work(W, dW, calm)
                e_ref = frozen_energy(u, calm)
                u_free = frozen_start(u, work, e_ref, c_at, calm)
                tau = time_frozen(u, True, calm)
                k1 = rates(
                    ANGLE, theta, u_free, t, work, step_rows(rows, e_ref, faces, tau, calm)[0],
                    machine, segment,
                )  # fmt: skip
        if faces >= 0.0:
            leak = (math.inf, math.inf, segment)  # stepped past its kinks
        leak = leak_kinks(theta, theta_dot, width, segment, calm, leak[0], leak[1], leak[2])
        first, worst, status, i = theta, 0.0, SPLIT_DONE, 0
        past_leak = False  # theta is a leak's kink inside sub-step i: its rest is off the tables
        wholes = False  # the split took a sub-step that a leak's kink did not cut
        while i < m_seg:
            if off_pace(steps, t, t_end, max_steps, pace, mark):
                status = OUT_OF_STEPS
                break
            theta_i, h_i = first + i * h, h
            if past_leak:
                theta_i, h_i = theta, rest_of_sub_step(theta, first, i, m_seg, h, end)
            if use_table and not past_leak:
                aux, rows = tables[parity, m_seg, i], row_tables[parity, m_seg, i]
            else:
                aux, rows = scratch, scratch_rows
                known = not_known(calm)
                if use_table:  # (rows of a split into more sub-steps than the tables hold: none)
                    tabled = row_tables[parity, m_seg, i, 6]
                    C = friction_at(tabled[C1], tabled[C2], tabled[C3], calm)
                    known = tabled_end(i, m_seg, first, h, end, C)
                stage_values(theta_i, h_i, segment, machine, aux, rows, c_at, known, False)
            if near_rest(k1, aux[7], h, theta_i, g, grid.delta, sample_dt, u, calm):
                status = IN_TIME
                break
            h_step, at_kink = leak_cut(theta_i, h_i, leak[0])
            if at_kink:
                aux, rows = scratch, scratch_rows
                known = not_known(calm)
                if use_table:  # (rows of a split into more sub-steps than the tables hold: none)
                    tabled = row_tables[parity, m_seg, i, 6]
                    C = friction_at(tabled[C1], tabled[C2], tabled[C3], calm)
                    known = tabled_end(i, m_seg, first, h, end, C)
                stage_values(theta_i, h_step, segment, machine, aux, rows, c_at, known, False)
            c_end = friction_at(rows[6, C1], rows[6, C2], rows[6, C3], calm)  # C at its end
            j_step = inertia_at(  # the time's ripple, j
                rows[6, 8], rows[6, 9], rows[6, 0], rows[6, M1], rows[6, M2], rows[6, M3], calm
            )
            ok, y, k7, err, dense = dp5_step(
                ANGLE, theta_i, u_free, t, t, W, h_step, k1, stage_work(aux),
                step_rows(rows, e_ref, faces, tau, calm),
                segment, machine,
            )  # fmt: skip
            steps += 1
            at_wind_kink = ok and kink < y[2] <= t_end
            if at_wind_kink:  # V(t) has a kink inside: the sub-step goes only as far as it
                ok, y, k7, err, dense, h_step = step_to_kink(
                    kink, theta_i, h_step, u_free, t, W, k1, y, k7, dense, scratch, scratch_rows,
                    c_at, e_ref, segment, machine,
                )  # fmt: skip
                steps += 1
                at_kink = True
                c_end = friction_at(
                    scratch_rows[6, C1], scratch_rows[6, C2], scratch_rows[6, C3], calm
                )
                j_step = inertia_at(
                    scratch_rows[6, 8], scratch_rows[6, 9], scratch_rows[6, 0],
                    scratch_rows[6, M1], scratch_rows[6, M2], scratch_rows[6, M3], calm,
                )  # fmt: skip
            scaled = scaled_error(err, y, t, u, rtol, width, calm)
            # the time's frozen ripple back
            t_new = time_back(y[2], tau, j_step, e_ref, c_at, h_step, calm)
            if t_new > t_end:
                status, past_t_end = IN_TIME, True  # the sub-step would pass t_end: in time
                break
            if not (ok and scaled <= 1.0):
                status, m = finer_split(ok, scaled, h_step, width, m)
                break
            last = i == m_seg - 1 and not at_kink
            theta_new, work = sub_step_end(
                last, end, end_work[parity], theta_i, h_step, not at_wind_kink, aux[6],
                segment, calm,
            )  # fmt: skip
            u_new = y[0] + less_frozen(work, e_ref, c_end, calm)
            W_new = frozen_work(y[3], e_ref, c_end, c_at, calm)
            if last and faces > 0.0:  # a leak hole's window before the end (:mod:`.real`)
                edge = edges[parity][1]
                slope = energy_slope(k7[0], e_ref, edge, calm)
                jump, dt, dW = window_jump(
                    theta_new, u_new, slope, -1.0, segment, faces, edge[2], scratch_rows, calm
                )  # (the sub-step's rows are read)
                u_new, t_new, W_new = u_new + jump, t_new + dt, jump_work(W_new, dW, calm)
            frozen = frozen_record(e_ref, c_at, W_new, tau, j_at, calm)
            if sample_dt is not None:
                out, n, j = record_in_step(
                    out, n, j, sample_dt, theta_i, h_step, t, W, u_free, y, k1, k7, dense,
                    frozen, segment, machine,
                )  # fmt: skip
            else:
                if n + int(h / grid.delta) + 2 > out.shape[1]:  # (a call per sample: +20 %)
                    out = with_room(out, n, int(h / grid.delta) + 2)
                n, g = record_grid_angles(
                    out, n, g, last, end_grid, grid, strokes_table, flow_table, work_table,
                    inertia_table, theta_i, h_step, theta_new, u_new, u_free, t, W, y, k1, k7,
                    dense, frozen, t_new,
                )  # fmt: skip
            whole = not past_leak and (at_wind_kink or not at_kink)  # a leak's kink cut neither end
            wholes = wholes or whole
            c_at, j_at = c_end, add_integrals(j_at, j_step, c_at, h_step, calm)
            u_free, t, W, theta, u, theta_dot, k1, worst, i, m, status = past_sub_step(
                (y[0], y[1], t_new, W_new), theta_new, u_new, k7, scaled, worst, i, at_kink,
                at_wind_kink, whole, m, width, h, j_step[2],
            )  # fmt: skip
            if at_wind_kink:
                kink = next_kink(max(t, kink), machine.wind)
            if status == ON_KINK:
                break
            past_leak = at_kink
            if past_leak:  # on to the leak's next kink
                leak = (leak[1], math.inf, leak[2])
        if jumped and i == 0 and status != SPLIT_DONE:  # nothing taken: the jump is undone
            u, t, W = u_before, t_before, W_before
        if past_t_end and faces >= 0.0 and ((jumped and i == 0) or theta >= clear_of_window):
            # Not in time across a window (its kink unseen): the rest of the segment again, on
            # its kinks, up to t_end
            windows_off, status, leak = True, REFINED, (math.inf, math.inf, -1)
        segment, full, m = after_split(
            status, i, m_seg, full, m, width, h, worst, segment, past_leak, wholes
        )
        if status == SPLIT_DONE:
            m, m_other = split_sizes_by_parity(m, m_other, calm)
            c_at, j_at, windows_off = no_friction(calm), no_integrals(calm), False
        if status == IN_TIME or status == OUT_OF_STEPS or (status == SPLIT_DONE and t >= t_end):
            return (status, out, n, j, g, steps, kink, m, t, theta, theta_dot, u, W, full,
                    segment, leak, end, end_grid)  # fmt: skip


@kernel
def integrate(
    machine, theta0, theta_dot0, t_end, n_per_stroke, sample_dt, rtol, max_steps, pace, capacity
):
    """Integrate Eq. (12) from (theta0, theta_dot0) at t = 0 up to t_end or a stop.

    Samples go on the grid of angles g pi / n_per_stroke or, when sample_dt is a number (not
    None: each grid compiles its own specialisation), of times j sample_dt. In a wind record a
    crank that comes to rest waits (:func:`~.stepping.next_start`) and the run goes on to t_end.
    The run goes in angle (:func:`in_angle`) and, where theta is a poor variable, in time
    (:func:`time_stretch`). Returns a :class:`Run`.
    """
    width, delta = math.pi / machine.cylinders, math.pi / n_per_stroke
    limits = Limits(t_end, rtol, max_steps, pace, np.zeros(2))
    grid = Grid(delta, 2 * n_per_stroke, faces(machine))
    at_grid = grid_tables(n_per_stroke, machine)
    tables, row_tables, built, end_work = sub_step_tables(machine)
    scratch, scratch_rows = np.empty(8), np.empty((7, ROW))  # stage values off the tables
    out = np.empty((ROWS - 1 + work_rows(machine), max(capacity, 2)))
    events, count = np.empty((2, 8)), 0
    t, theta, W = 0.0, theta0, zero_work(machine)
    theta_dot = theta_dot0  # kept beside u: u underflows for theta_dot below about 1e-154
    u = kinetic(theta, theta_dot, machine)
    segment = first_segment(theta0, machine)
    n = record_anywhere(out, 0, t, theta, theta_dot0, W, segment, machine, False)
    j, steps = 1, 0  # the next time sample is j * sample_dt
    if theta_dot0 <= 0.0:
        outcome, out, n, j, t, events, count = start_from_rest(
            out, n, j, sample_dt, theta0, t_end, W, segment, machine, events, count
        )
        if outcome >= 0:
            return Run(out, n, outcome, 0, events, count)
    g = first_grid_index(theta0, delta)  # the next grid angle to sample is g * delta
    kink = next_kink(t, machine.wind)  # steps land on the wind record's samples
    m = FIRST_SUBSTEPS  # sub-steps per segment
    # Whether theta is where the segment starts: tracked, not compared (fastmath may round
    # (j + 1) pi/n and j pi/n differently).
    full = theta == segment_start(segment, machine)
    leak = (math.inf, math.inf, -1)  # (the next leak kink, the one after, of which segment)
    while True:
        status, out, n, j, g, steps, kink, m, t, theta, theta_dot, u, W, full, segment, leak, end, end_grid = (
            in_angle(
                out, n, j, g, steps, kink, m, t, theta, theta_dot, u, W, full, segment, leak,
                tables, row_tables, built, scratch, scratch_rows, at_grid, end_work, limits, grid,
                width, n_per_stroke, sample_dt, machine,
            )
        )  # fmt: skip
        if status == OUT_OF_STEPS:
            return Run(out, n, OVER_BUDGET, steps, events, count)
        if status == SPLIT_DONE:  # on a switch at or past t_end
            out, n = record_end(out, n, t, theta, theta_dot, W, segment, machine)
            return Run(out, n, REACHED_T_END, steps, events, count)
        outcome, out, n, j, g, steps, kink, t, theta, theta_dot, W, u, full, segment, events, count = (
            time_stretch(
                out, n, j, g, steps, kink, t, theta, theta_dot, W, u, full, end, end_grid,
                limits, grid, at_grid, sample_dt, segment, machine, events, count,
            )
        )  # fmt: skip
        if outcome >= 0:
            return Run(out, n, outcome, steps, events, count)


def compile_ahead(machine: Machine) -> list[str]:
    """Compile, for an ideal machine in a steady wind (the first page's), the kernels
    :func:`integrate` calls last, the last first; the names of the kernels compiled (none for
    another machine: its calls have other types).

    numba compiles a kernel's callees as it types the calls, in order, in one thread at a time.
    A second process compiling the last ones while the first compiles ``integrate`` leaves them
    in numba's cache, and the first loads them when it comes to them instead of compiling them
    (app/compiling.py). The signatures are the ones ``integrate``'s calls type on the grid of
    angles: tests/kernels/test_compile.py checks that ``integrate`` compiles none of them again.

    Examples
    --------
    >>> from windpump import Design
    >>> from windpump.run.dynamics import kernel_machine
    >>> compile_ahead(kernel_machine(Design.seed_example()))[0]  # doctest: +SKIP
    'advance_in_time'
    """
    if machine.real is not None or machine.wind is not None:
        return []
    import numba
    from numba import types

    M, f, i, b = numba.typeof(machine), types.float64, types.int64, types.boolean
    a1, a2, a4, a5 = (types.Array(f, dims, "C") for dims in (1, 2, 4, 5))
    u3, u4, u7 = types.UniTuple(f, 3), types.UniTuple(f, 4), types.UniTuple(f, 7)
    grid, frozen = numba.typeof(Grid(0.0, 1, 1)), types.none  # (the ideal machine's frozen)
    ahead = (  # the last first: time_stretch's, then in_angle's from its end
        (advance_in_time, (f, f, f, f, f, f, i, M, f, i, i, f, i, i, a1)),
        (record_grid_angles, (a2, i, i, b, i, grid, a1, a1, a1, a1, *(f,) * 7, u4, u4, u4, u3,
                              frozen, f)),
        (step_to_kink, (*(f,) * 6, u4, u4, u4, u3, a1, a2, f, f, i, M)),
        (dp5_step, (types.literal(ANGLE), *(f,) * 6, u4, u7, a2, i, M)),
        (tabulate_segment, (i, i, M, a4, a5, types.Array(b, 2, "C"))),
    )  # fmt: skip
    for compiled, signature in ahead:
        compiled.compile(signature)
    return [compiled.py_func.__name__ for compiled, _ in ahead]
