"""The design map on a fine grid for drawing: a leaky pump's map computed on a coarse grid and
resampled, each side of its jump on its own (issue 38 moved it here from the app)."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..model.design import Design
from ..validation import real_array
from .maps import design_map

COARSE = 41  # a leaky pump's map, points each way, interpolated onto the fine grid: ~1.7 s


@dataclasses.dataclass(frozen=True)
class FineMap:
    """A design map on a fine grid, as a figure draws it.

    Attributes
    ----------
    mean_flow : ndarray
        Mean pumped flow by (head, gear ratio) [m^3/s] (rows: heads); 0 where it stalls.
    edge_gear_ratio : ndarray
        By head: the gear ratio R1/R0 [-] where the pump stops carrying the load (the stall
        line, :attr:`windpump.DesignMap.stall_gear_ratio`), or, with a leak hole, where its speed jumps
        up to delivering (:attr:`windpump.DesignMap.jump_gear_ratio`); NaN where there is none.
    best_gear_ratio : ndarray
        By head: the gear ratio of the largest flow [-].
    """

    mean_flow: np.ndarray
    edge_gear_ratio: np.ndarray
    best_gear_ratio: np.ndarray


def fine_map(design: Design, gear_ratios, heads, coarse: int = COARSE) -> FineMap:
    """The averaged theory's design map (:func:`windpump.design_map`) over ``gear_ratios`` [-] and
    ``heads`` [m], cheap enough to draw.

    Without a leak hole it is the map itself. A leaky pump's averaged theory is a quadrature a
    point (~1 ms; a 160 x 160 map took 25 s): it is mapped on a ``coarse`` x ``coarse`` grid over
    the same spans and interpolated onto the fine one. Where its speed jumps up its flow jumps
    too: interpolated across the jump the coarse grid drew a staircase along it, so each side is
    interpolated from its own values and the two are joined at the jump, over the heads within a
    coarse row of one.

    Parameters
    ----------
    design : Design
        Every input but R1 and h.
    gear_ratios, heads : array_like
        Increasing, evenly spaced grids of R1/R0 [-] and of the head h [m].
    coarse : int
        A leaky pump's coarse grid, points each way (>= 2).

    Examples
    --------
    >>> import numpy as np
    >>> from windpump import Design
    >>> ratios, heads = np.linspace(1.0, 6.0, 50), np.linspace(1.0, 20.0, 40)
    >>> leaky = Design.seed_example().replace(d_leak=0.003, T_0=0.25)
    >>> drawn = fine_map(leaky, ratios, heads)
    >>> drawn.mean_flow.shape, bool(np.isfinite(drawn.edge_gear_ratio).any())
    ((40, 50), True)
    """
    ratios = real_array("gear_ratios", gear_ratios, "-")
    heads = real_array("heads", heads, "m")
    if design.d_leak == 0.0:
        mapped = design_map(design, ratios, heads)
        return FineMap(mapped.mean_flow, mapped.stall_gear_ratio, mapped.best_gear_ratio)
    coarse_ratios = np.linspace(ratios[0], ratios[-1], coarse)
    coarse_heads = np.linspace(heads[0], heads[-1], coarse)
    mapped = design_map(design, coarse_ratios, coarse_heads)
    jump = mapped.jump_gear_ratio
    below, above = one_side(np.nan_to_num(mapped.mean_flow), coarse_ratios, jump)
    left, right = (
        bilinear(side, coarse_ratios, coarse_heads, ratios, heads) for side in (below, above)
    )
    edge = jump_between(jump, coarse_heads, heads)
    flow = np.where(ratios[np.newaxis, :] < edge[:, np.newaxis], left, right)
    return FineMap(flow, edge, np.interp(heads, coarse_heads, mapped.best_gear_ratio))


def one_side(flow: np.ndarray, ratios: np.ndarray, jump: np.ndarray) -> tuple:
    """``flow`` (rows: heads) twice: with each row's values right of its ``jump`` (a ratio, NaN:
    none) given its last one left of it, and with those left of it given its first one right."""
    columns = np.arange(len(ratios))[np.newaxis, :]
    last = np.searchsorted(ratios, np.nan_to_num(jump, nan=np.inf))[:, np.newaxis] - 1
    last = np.clip(last, 0, len(ratios) - 2)  # a NaN row: last left of a jump never reached
    rows = np.arange(len(flow))[:, np.newaxis]
    jumps = np.isfinite(jump)[:, np.newaxis]
    below = np.where(jumps & (columns > last), flow[rows, last], flow)
    above = np.where(jumps & (columns <= last), flow[rows, last + 1], flow)
    return below, above


def bilinear(
    values: np.ndarray, xs: np.ndarray, ys: np.ndarray, at_x: np.ndarray, at_y: np.ndarray
):
    """``values`` on (ys, xs) interpolated onto (at_y, at_x): along x, then along y."""
    rows = np.array([np.interp(at_x, xs, row) for row in values])
    return np.array([np.interp(at_y, ys, column) for column in rows.T]).T


def jump_between(jump: np.ndarray, heads: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The ``jump`` ratios by ``heads`` interpolated at the heads ``at`` (extrapolated along the
    line past its ends); NaN at a head neither of whose two rows has one."""
    known = np.isfinite(jump)
    if not known.any():
        return np.full(at.shape, np.nan)
    ends, jumps = heads[known], jump[known]
    edge = np.interp(at, ends, jumps)
    if len(ends) > 1:  # past the first or last, along the line's end (it leaves the map there)
        for out, k in ((at < ends[0], 0), (at > ends[-1], -2)):
            slope = (jumps[k + 1] - jumps[k]) / (ends[k + 1] - ends[k])
            edge[out] = jumps[k] + slope * (at[out] - ends[k])
    row = np.clip(np.searchsorted(heads, at, side="right") - 1, 0, len(heads) - 2)
    near = known[row] | known[row + 1] | np.isin(at, heads[known])
    return np.where(near, edge, np.nan)
