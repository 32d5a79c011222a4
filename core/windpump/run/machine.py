"""A design as the compiled integrator takes it (the design-to-kernel wrapper, in one place):
:func:`kernel_machine` (the ``_kernels.Machine`` of a design and its wind record), the real
machine's and the wind's parts, the first guess of a run's sample count, and whether numba's
cache holds the solver for a design."""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from .. import _kernels
from .._kernels.real import RealBase, real_at
from .._kernels.rotor import RotorTable
from ..averaging.averaged import steady_speeds
from ..errors import StallError
from ..model.design import REAL_MACHINE, Design
from ..model.rotor import Rotor
from ..model.wind import WindRecord
from .result import SAMPLES_PER_STROKE

DEFAULTS = {field.name: field.default for field in dataclasses.fields(Design)}


@functools.lru_cache(maxsize=64)
def ideal_of(design: Design) -> Design:
    """The design as the paper's ideal machine: every field of the real machine at its default
    (the design itself when it is ideal). Remembered for the last designs (a frozen design is
    its own key): :func:`simulate` asks it twice a run, and a checked design costs 35 us."""
    if design.is_ideal:
        return design
    return design.replace(**{name: DEFAULTS[name] for name in REAL_MACHINE})


def kernel_machine(design: Design, record: WindRecord | None = None):
    """The design (and wind record, if any) as the compiled integrator takes them."""
    return _kernels.Machine(
        R_dagger=design.R_dagger,
        T_m=design.T_m,
        T_0=design.T_0,
        omega_m=design.omega_m,
        inv_I_eff=1.0 / design.I_eff,
        load_torque=design.load_torque,
        L_over_R=design.L_over_R,
        cylinders=design.cylinders,
        double_acting=design.double_acting,
        wind=None if record is None else kernel_wind(record, design.V_ref),
        real=None if design.is_ideal else kernel_real(design),
        rotor=kernel_rotor(design),
    )


def kernel_rotor(design: Design):
    """The design's rotor as the compiled integrator takes it (``_kernels.RotorTable``), or
    None for the paper's Eq. (11)."""
    rotor = design.rotor
    if rotor is None:
        return None
    table = rotor_table(rotor.table_tsr, rotor.table_cq)
    return RotorTable(
        address=table.ctypes.data,
        intervals=len(rotor.table_tsr) - 1,
        end_value=rotor.table_cq[-1],
        end_slope=rotor.end_slope,
        radius=rotor.radius,
        torque_scale=rotor.torque_scale,
        V_ref=design.V_ref,
        V_furl=math.inf if rotor.V_furl is None else rotor.V_furl,
    )


TABLES: dict[tuple, np.ndarray] = {}
"""Every rotor table the kernels were given, by its points: kept for good, since a run (in any
thread) reads its numbers by address (``_kernels.rotor.RotorTable``). A process sees a handful
(the multiblade wheel, a catalogue's, a user's): ~8 bytes x 5 a point each."""


def rotor_table(tsr: tuple[float, ...], cq: tuple[float, ...]) -> np.ndarray:
    """The numbers of :class:`~windpump._kernels.rotor.RotorTable` for a C_Q table: its n + 1
    ratios, then the PCHIP's c3, c2, c1 and c0 of its n intervals."""
    key = (tsr, cq)
    if key not in TABLES:
        _, coefficients, _ = Rotor.from_cq(1.0, tsr, cq).kernel_table()
        table = np.concatenate([np.asarray(tsr, dtype=float), coefficients.T.ravel()])
        table.setflags(write=False)
        return TABLES.setdefault(key, table)  # one table a key, whichever thread came first
    return TABLES[key]


def kernel_real(design: Design):
    """The real machine's terms as the compiled integrator takes them (``_kernels.Real``)."""
    return real_at(kernel_real_base(design), 1.0 / design.I_eff, design.load_torque)


def kernel_real_base(design: Design):
    """The real machine's terms a design map's points share (``_kernels.real.RealBase``), or
    None for the ideal machine."""
    if design.is_ideal:
        return None
    return RealBase(
        eta_t=design.eta_t,
        weight_torque=design.m_r * design.g * design.R,
        mass_inertia=design.m_r * design.R**2,
        AR=design.A * design.R,
        leak_per_root_head=design.leak_capacity / math.sqrt(design.h) if design.h > 0 else 0.0,
        friction=design.friction_coefficient,
        rho_g=design.rho_w * design.g,
    )


def solver_is_cached(design: Design) -> bool:
    """Whether numba's on-disk cache holds the integrator compiled for a run of ``design`` in its
    own wind on the angle grid (``simulate``'s defaults), so that its first run loads it rather
    than compiling it (a first start after an install: README, "Measured").

    Reads the cache's index only (no compiling, no loading). False also when it cannot tell.

    Parameters
    ----------
    design : Design
        The wind pump whose run would be compiled (its types matter, not its values).

    Returns
    -------
    bool
    """
    return _kernels.is_cached(kernel_machine(design), sample_dt=None)


def kernel_wind(record: WindRecord, V_ref: float):
    """The record as the kernels take it: V/V_ref at its kinks (steps land on every sample, so
    one on a straight line with its neighbours, or on the flat held past the ends, is left out),
    and the spacing when the samples are even."""
    t, V = record.t, record.V
    if len(t) > 1:  # V is held before the first sample and after the last: flat there
        rise, run = np.diff(V), np.diff(t)
        bends = rise[:-1] * run[1:] != rise[1:] * run[:-1]
        keep = np.concatenate(([rise[0] != 0.0], bends, [rise[-1] != 0.0]))
        keep[0] |= not keep.any()  # a constant record keeps one sample
        t, V = t[keep], V[keep]
    steps = np.diff(t)
    even = len(t) > 1 and bool(np.all(t == t[0] + steps[0] * np.arange(len(t))))
    return _kernels.Wind(
        np.array(t, dtype=float),  # writeable: a read-only array is a driver of its own to numba
        np.ascontiguousarray(V / V_ref),
        float(steps[0]) if even else 0.0,
    )


def first_capacity(
    design: Design,
    t_end: float,
    theta_dot0: float,
    bound: float,
    samples_per_stroke: int = SAMPLES_PER_STROKE,
    sample_dt: float | None = None,
) -> int:
    """A first guess of the sample count, from the averaged theory's running speed (the output
    grows past it if needed), never above ``bound``.

    For a real machine, the ideal machine's running speed (:func:`ideal_of`, closed form): it
    runs at least as fast but for a leak hole, which relieves the load only where a face sweeps
    less than the hole passes (the seed example's 6 mm hole runs it 0.02 % faster); the real
    machine's averaged theory is a quadrature (a hole's ~3 ms a run, a rising main's 0.3 ms),
    and room never written costs nothing."""
    if sample_dt is not None:
        return int(min(math.ceil(bound), t_end / sample_dt + 64))
    try:
        speed = max(theta_dot0, steady_speeds(ideal_of(design))[0])
    except StallError:
        speed = theta_dot0
    expected = 1.05 * speed * t_end / (math.pi / samples_per_stroke) + 64
    return int(min(math.ceil(bound), expected))
