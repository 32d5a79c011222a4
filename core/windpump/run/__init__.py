"""The full equation of motion (paper Eq. 12), integrated by the compiled kernels
(:mod:`windpump._kernels`): :mod:`.dynamics` (``simulate``, the design-to-kernel wrapper, budgets
and the run in a wind record), :mod:`.energy` (the power budget), :mod:`.exploration` (a run and
what is read off it, as the explorer shows it) and :mod:`.playback` (frames for an animation).
Imports the averaged theory, the model and below.
"""
