"""Display decimation: a long trace cut to one min/max pair per bin of time, drawn as a band.

The 1,500 revolutions of a run pulse far faster than a screen can draw. Keeping each bin's lowest and
highest sample and filling between them draws the same band the full trace would (the ripple stays
honest) instead of a sub-sample that aliases the pulses into a false pattern.
"""

from __future__ import annotations

import numpy as np


def band(x, y, bins: int | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lowest and highest y in each of ``bins`` equal bins of x (x increasing).

    Returns ``(x_mid, lower, upper)``, one row per non-empty bin, x_mid the middle of the bin's
    samples. A trace of no more than ``bins`` samples (or any trace, with ``bins=None``) comes
    back whole, with lower = upper = y.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n = len(x)
    if bins is None or n <= bins:
        return x, y, y
    starts = np.unique(np.searchsorted(x, np.linspace(x[0], x[-1], bins + 1)[:-1]))
    ends = np.append(starts[1:], n) - 1
    return (
        0.5 * (x[starts] + x[ends]),
        np.minimum.reduceat(y, starts),
        np.maximum.reduceat(y, starts),
    )


def bin_means(x, columns: dict, bins: int | None) -> dict:
    """Each column averaged over ``bins`` equal bins of x (x increasing), with x itself averaged.

    For series that are already smooth (cycle means): fewer points than pixels, and stacked
    columns stay stacked. Short series (or ``bins=None``) come back whole.
    """
    x = np.asarray(x, dtype=float)
    table = {"t": x, **{name: np.asarray(y, dtype=float) for name, y in columns.items()}}
    if bins is None or len(x) <= bins:
        return table
    starts = np.unique(np.searchsorted(x, np.linspace(x[0], x[-1], bins + 1)[:-1]))
    counts = np.diff(np.append(starts, len(x)))
    return {name: np.add.reduceat(y, starts) / counts for name, y in table.items()}
