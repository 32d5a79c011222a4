"""Studies of many designs: the design map over gear ratio and head (:mod:`.maps`, with its
resampling for drawing) and sweeps on any executor (:mod:`.studies`). Imports the full run and
below.
"""
