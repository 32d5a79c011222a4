"""The year hour by hour (:func:`windpump.supply`): the pump's on-off rule and the tank's books.

Both are recurrences (this hour depends on the last), so they loop here compiled; the hourly
flows come from the averaged theory on the package's side.
"""

from __future__ import annotations

import numba
import numpy as np

from .jit import kernel, parallel_kernel


@kernel
def hysteresis(V, V_start, V_stop, attended, running):
    """Fill ``running`` (bool, one per hour) by the rule: a resting pump starts when
    ``V >= V_start``, a running one carries on while ``V >= V_stop`` (``attended``: it runs
    whenever ``V >= V_stop``); at rest before the first hour. Return the number of starts."""
    was = False
    starts = 0
    for h in range(V.size):
        if attended:
            now = V[h] >= V_stop
        else:
            now = V[h] >= V_start or (was and V[h] >= V_stop)
        if now and not was:
            starts += 1
        running[h] = now
        was = now
    return starts


@kernel
def balance(pumped, demand, capacity, level0, delivered, shortfall, spilled, level):
    """One pass of the tank through the hours from ``level0`` [m^3]; return the end level.

    available = level + pumped; delivered = min(demand, available); shortfall = demand -
    delivered; spilled = max(0, available - delivered - capacity); level = available -
    delivered - spilled."""
    now = level0
    for h in range(pumped.size):
        available = now + pumped[h]
        given = min(demand[h], available)
        over = max(0.0, available - given - capacity)
        delivered[h] = given
        shortfall[h] = demand[h] - given
        spilled[h] = over
        now = available - given - over
        level[h] = now
    return now


@kernel
def periodic(pumped, demand, capacity, tolerance, most, delivered, shortfall, spilled, level):
    """Passes of :func:`balance` from a full tank, each from the last one's end level, until a
    pass ends where it began (to ``tolerance`` [m^3]) or ``most`` passes; return the passes."""
    start = capacity
    passes = 0
    while passes < most:
        passes += 1
        end = balance(pumped, demand, capacity, start, delivered, shortfall, spilled, level)
        if abs(end - start) <= tolerance:
            break
        start = end
    return passes


@kernel
def short_total(pumped, demand, capacity, tolerance, most):
    """The year's shortfall [m^3] of the periodic tank (:func:`periodic`), without the arrays."""
    start = capacity
    total = 0.0
    for _ in range(most):
        now = start
        total = 0.0
        for h in range(pumped.size):
            available = now + pumped[h]
            given = min(demand[h], available)
            total += demand[h] - given
            now = available - given - max(0.0, available - given - capacity)
        if abs(now - start) <= tolerance:
            break
        start = now
    return total


@parallel_kernel
def shortfall_map(pumped, demand, capacities, tolerance, most):
    """The periodic year's shortfall [m^3] for every row of ``pumped`` (one per gear ratio) and
    every tank capacity: shape (rows, capacities); rows in parallel.

    Each tank's passes are :func:`short_total`'s, number for number (the same operations in the
    same order); the tanks of a row run side by side through the hours, so the loop over them
    vectorises, and a tank whose level has repeated keeps its total while the others go on."""
    rows = pumped.shape[0]
    count = capacities.size
    out = np.empty((rows, count))
    for i in numba.prange(rows):
        start = capacities.copy()
        level = np.empty(count)
        short = np.empty(count)
        done = np.zeros(count, dtype=np.bool_)
        left = count
        for _ in range(most):
            level[:] = start
            short[:] = 0.0
            for h in range(pumped.shape[1]):
                p = pumped[i, h]
                d = demand[h]
                for j in range(count):
                    available = level[j] + p
                    given = min(d, available)
                    short[j] += d - given
                    level[j] = available - given - max(0.0, available - given - capacities[j])
            for j in range(count):
                if not done[j]:
                    out[i, j] = short[j]
                    if abs(level[j] - start[j]) <= tolerance:
                        done[j] = True
                        left -= 1
                    else:
                        start[j] = level[j]
            if left == 0:
                break
    return out
