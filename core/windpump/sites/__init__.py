"""A site's year: weather files (:mod:`.weather`), water in a site's wind (:mod:`.site`), the
hours of a year (:mod:`.hours`), a year integrated in full (:mod:`.fullyear`) and the supply from
a tank (:mod:`.yearly`). Imports the full run and below.
"""
