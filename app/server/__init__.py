"""The server's room of the explorer: what a long-running classroom server needs besides the
page itself. ``threads`` (the moves' runs, the heavy work, the file readers), ``sessions`` (a
page's session from its opening to its close), ``memory`` (garbage collection, glibc), ``watch``
(the logs, the loop's stalls), ``hooks`` (the server's start and stop, which ``app/app_hooks.py``
hands to Bokeh), ``upload_route`` (files by HTTP), ``policy`` (the Content-Security-Policy),
``proxy`` (several processes behind nginx) and ``patches`` (Panel, Bokeh and param internals).

The page's modules reach the server through ``api`` alone (an import-linter contract in
``pyproject.toml``); the server imports none of the page's tabs.
"""
