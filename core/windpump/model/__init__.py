"""The model: a design and its pointwise equations (paper Eqs. 1-11).

:mod:`.equations` holds the pointwise equations, written once for numpy and for the compiled
kernels; :mod:`.design` the frozen :class:`~windpump.Design`; :mod:`.groups` its dimensionless
groups; :mod:`.kinematics` the slider-crank (Eq. 1); :mod:`.loads` the load on the crank;
:mod:`.reciprocating` the reciprocating mass; :mod:`.windmill` the windmill's torque curve
(Eq. 11) and its fit to lab data; :mod:`.wind` wind records. Imports only from below: the readers,
validation, errors and units.
"""
