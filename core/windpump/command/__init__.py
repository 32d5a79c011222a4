"""The command line, ``windpump ...``: :mod:`.cli` (the design commands), :mod:`.sitecli` (a site's
year: ``supply``, ``tank``) and :mod:`.cliargs` (the options they share). The top of the ladder.
"""
