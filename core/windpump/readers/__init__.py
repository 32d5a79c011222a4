"""Reading files safely (:mod:`.files`: size, kind and path checks) and lab data
(:mod:`.labdata`: a windmill's measured torques, and the CSV cells every reader shares).
Imports only validation and errors.
"""
