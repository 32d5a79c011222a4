"""The real machine's rows for a step and the split of a segment by parity."""

from __future__ import annotations

from .jit import kernel
from .real_entries import (
    WORKS,
    _entry,
)
from .real_friction import (
    _weighted,
)


def step_rows(rows, e_ref, faces, frozen_time, machine):
    """The real machine's rows at a step's 7 stage nodes as a tuple of tuples, each what the
    ANGLE domain's rates (:func:`angle_rates`) take at its node, worked out before the step so
    that little but the speed's root lies between one stage and the next (the stages are
    sequential: their latency is the step's cost): 2 / j, the delivering faces' |lever arms|
    (6), C and the main's frozen friction torque at e_ref (:func:`_frozen_parts` at the
    weights ``e_ref``, :func:`frozen_energy`),
    ``faces`` (the delivering faces of a segment stepped on :func:`_continued_loads`, its hole's
    windows corrected apart, or -1.0), tau (j - 1) and tau / u (:func:`time_frozen`), A R sum
    |a| and faces q_L. The ideal machine's: ``rows`` as they are. A stage's row taken from the
    array is a view, whose reference is counted atomically as it is made and dropped: 14 atomic
    operations a step, a third of the time of the real machine's steps (eta_t alone)."""


@kernel
def _row(rows, stage, e_ref, faces, frozen_time, machine):
    tau, per_u = frozen_time
    return (
        rows[stage, 10], rows[stage, 1], rows[stage, 2], rows[stage, 3], rows[stage, 4],
        rows[stage, 5], rows[stage, 6],
        _weighted(e_ref, (rows[stage, 7], rows[stage, 16], rows[stage, 17])),
        _weighted(e_ref, (rows[stage, 12], rows[stage, 14], rows[stage, 15])), faces,
        tau * rows[stage, 13], tau * per_u, rows[stage, 11],
        max(faces, 0.0) * machine.real.q_L,  # (faces is -1.0 where the windows are not jumped)
    )  # fmt: skip


def _step_rows(rows, e_ref, faces, frozen_time, machine):
    f, m = frozen_time, machine
    return (
        _row(rows, 0, e_ref, faces, f, m), _row(rows, 1, e_ref, faces, f, m),
        _row(rows, 2, e_ref, faces, f, m), _row(rows, 3, e_ref, faces, f, m),
        _row(rows, 4, e_ref, faces, f, m), _row(rows, 5, e_ref, faces, f, m),
        _row(rows, 6, e_ref, faces, f, m),
    )  # fmt: skip


_entry(step_rows)(
    lambda rows, e_ref, faces, frozen_time, machine: rows, _step_rows, inline="always"
)  # (spliced in: compiled apart, its 98 numbers came back through memory, 0.1 ms a run)


def split_sizes_by_parity(m, m_other, machine):
    """After a segment, (the next segment's sub-steps, the other parity's): the ideal machine
    keeps one m for every segment, (m, m_other) as they are; the real machine one per parity,
    swapped, for its two parities load the crank differently (a single cylinder's delivering
    half has the main's friction and the hole's kinks, its intake half none: one m for both
    made every delivering segment fail its first sub-step and go on off the tables)."""


_entry(split_sizes_by_parity)(
    lambda m, m_other, machine: (m, m_other), lambda m, m_other, machine: (m_other, m)
)


def work_rows(machine):
    """How many rows the work quadratures take in the output: 1, or WORKS."""


_entry(work_rows)(lambda machine: 1, lambda machine: WORKS)


# -- A leak hole's windows, corrected apart (docs/model.rst, "The real machine"). -----------------
#
# Inside a delivering segment a face's hole changes its load only in a window next to each of its
# dead centres, where it sweeps less than the hole passes (u_k <= q_L: 0.005-0.009 rad wide at the
# seed example's running speed). A segment whose windows are narrow is stepped on the loads
# continued past them (:func:`_continued_loads`: smooth, so its steps neither stop at the windows'
# kinks nor leave the tables), and each window's difference, true less continued, is added as a
# jump: the window after the segment's start at its start, the one before its end at its end.
