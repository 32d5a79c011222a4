"""The Dormand-Prince 5(4) tableau, its continuous extension and step-size rule.

Butcher tableau (Dormand & Prince 1980; Hairer, Norsett & Wanner, *Solving ODEs I*, II.5)::

    0    |
    1/5  | 1/5
    3/10 | 3/40        9/40
    4/5  | 44/45      -56/15       32/9
    8/9  | 19372/6561 -25360/2187  64448/6561 -212/729
    1    | 9017/3168  -355/33      46732/5247  49/176  -5103/18656
    1    | 35/384      0           500/1113    125/192 -2187/6784    11/84
    -----+-----------------------------------------------------------------------
    b    | 35/384      0           500/1113    125/192 -2187/6784    11/84    0
    b^   | 5179/57600  0           7571/16695  393/640 -92097/339200 187/2100 1/40

The last stage row equals b (first same as last), so a step's seventh stage is the next step's
first. ``E = b - b^`` estimates the local error of the 5th-order solution.
"""

from __future__ import annotations

import numpy as np

from .jit import kernel

# Nodes c_i.
C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
NODES = np.array([0.0, C2, C3, C4, C5, 1.0, 1.0])

# Stage matrix a_ij, row by row.
A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656

# 5th-order weights b_i (b2 = b7 = 0), and E_i = b_i - b^_i.
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
E1, E3, E4, E5, E6, E7 = 71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40

# Hairer's continuous extension of order 4 (DOPRI5's contd5): weights of the dense-output term.
D1, D3, D4 = -12715105075 / 11282082432, 87487479700 / 32700410799, -10690763975 / 1880347072
D5, D6, D7 = 701980252875 / 199316789632, -1453857185 / 822651844, 69997945 / 29380423

SAFETY, SHRINK_MOST, GROW_MOST = 0.9, 0.2, 5.0
ORDER = 5


@kernel
def step_factor(err):
    """Step-size multiplier for a scaled error estimate: 0.9 err^(-1/5), clipped to [0.2, 5]."""
    if err == 0.0:
        return GROW_MOST
    return min(GROW_MOST, max(SHRINK_MOST, SAFETY * err ** (-1.0 / ORDER)))


@kernel
def dense_value(sigma, start, end, rate_start, rate_end, dense, h):
    """A component at s + sigma h inside a step, by the order-4 continuous extension.

    ``dense`` is h times the D-weighted sum of the step's stages for that component.
    """
    rise = end - start
    back = h * rate_start - rise
    return start + sigma * (
        rise + (1.0 - sigma) * (back + sigma * (rise - h * rate_end - back + (1.0 - sigma) * dense))
    )
