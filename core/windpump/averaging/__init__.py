"""The averaged theory (paper Eqs. 13-25): the revolution means of the load and the flow
(:mod:`.revolution`), the running speeds and the steady flow in a wind (:mod:`.theory`), the stall
margin, the time constant and the spin-up (:mod:`.averaged`), and the operating point where the
load line meets the windmill's power curve (:mod:`.operating`). Imports only the model and below;
no numba.
"""
