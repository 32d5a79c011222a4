"""Grashof's condition: which links of a four-bar can turn all the way round.

With s the shortest link, l the longest and p, q the other two, a four-bar with s + l < p + q
(Grashof's) has a link that turns fully relative to the others: the shortest one [1]_. Which
moving link turns relative to the ground depends on where the shortest link is [2]_:

=================  ==========================  ===============================
class              condition                   motion (input r1, output r3)
=================  ==========================  ===============================
``crank-rocker``   s + l < p + q, s = r1       the input turns, the output rocks
``double-crank``   s + l < p + q, s = r6       both turn (a drag link)
``rocker-crank``   s + l < p + q, s = r3       the input rocks, the output turns
``double-rocker``  s + l < p + q, s = r2       both rock; the coupler turns
``change-point``   s + l = p + q               as Grashof's, through a dead centre
``triple-rocker``  s + l > p + q               every moving link rocks
=================  ==========================  ===============================

References
----------
.. [1] F. Grashof, *Theoretische Maschinenlehre*, vol. 2, Leopold Voss, Leipzig (1883).
.. [2] R. L. Norton, *Design of Machinery*, McGraw-Hill, section 2.12 (Grashof's condition,
   Barker's classification).
"""

from __future__ import annotations

from . import _checks as check

CHANGE_POINT = 1e-12
"""|s + l - (p + q)| within this fraction of the links' total length is a change point [-]."""

# The class of a Grashof linkage by its shortest link, in the order ties are settled
BY_SHORTEST = (
    ("r6", "double-crank"),
    ("r1", "crank-rocker"),
    ("r3", "rocker-crank"),
    ("r2", "double-rocker"),
)


def grashof_class(r1: float, r2: float, r3: float, r6: float) -> str:
    """The four-bar's class by Grashof's condition and where its shortest link is.

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], from 1e-100 to 1e100.

    Returns
    -------
    str
        ``"crank-rocker"``, ``"double-crank"``, ``"rocker-crank"``, ``"double-rocker"``,
        ``"change-point"`` or ``"triple-rocker"`` (see the module's table). Where two links tie
        for the shortest, the ground wins, then the input, the output, the coupler.

    Examples
    --------
    >>> grashof_class(1.0, 3.0, 2.5, 3.0), grashof_class(3.0, 3.5, 3.0, 1.0)
    ('crank-rocker', 'double-crank')
    >>> grashof_class(2.0, 2.5, 2.0, 3.0), grashof_class(1.0, 2.0, 2.0, 1.0)
    ('triple-rocker', 'change-point')
    """
    checked = check.link_lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    lengths = dict(zip(("r1", "r2", "r3", "r6"), checked, strict=True))
    s, p, q, l = sorted(lengths.values())  # noqa: E741 (Grashof's letters)
    excess = (s + l) - (p + q)
    if abs(excess) <= CHANGE_POINT * (s + l + p + q):
        return "change-point"
    if excess > 0:
        return "triple-rocker"
    return next(kind for name, kind in BY_SHORTEST if lengths[name] == s)


def is_grashof(r1: float, r2: float, r3: float, r6: float) -> bool:
    """Grashof's condition s + l <= p + q: some link of the four-bar turns fully.

    With the shortest link as input (or ground) it turns all the way round; otherwise every
    moving link rocks between limits, where a branch-following trace ends.

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], from 1e-100 to 1e100.

    Returns
    -------
    bool
        False for a triple-rocker only (:func:`grashof_class`).

    Examples
    --------
    >>> is_grashof(1.0, 3.0, 2.5, 3.0), is_grashof(2.0, 2.5, 2.0, 3.0)
    (True, False)
    """
    return grashof_class(r1, r2, r3, r6) != "triple-rocker"


def input_turns_fully(r1: float, r2: float, r3: float, r6: float) -> bool:
    """Whether the input link r1 can turn all the way round relative to the ground.

    It can when the four-bar is Grashof's (a change point included) and its shortest link is
    the input or the ground: a crank-rocker or a double-crank.

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], from 1e-100 to 1e100.

    Returns
    -------
    bool

    Examples
    --------
    >>> input_turns_fully(1.0, 3.0, 2.5, 3.0), input_turns_fully(3.0, 1.0, 3.5, 3.0)
    (True, False)
    """
    r1, r2, r3, r6 = check.link_lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    return is_grashof(r1, r2, r3, r6) and min(r1, r2, r3, r6) in (r1, r6)
