"""Entry point of the live explorer: ``panel serve app/`` (a Bokeh directory app).

The page starts from its URL's query (``?h=5&T_m=0.8``) and keeps the query in step with the
inputs (``Explorer.follow_in_link``), so a link reproduces what is on the screen.
"""

import logging
from functools import partial

import panel as pn

from .compiling import COMPILE, REAL_MACHINE, WHEEL
from .explorer import BINS, Explorer
from .keyboard import keyboard_and_screen_readers
from .link import utf8_keys
from .link_values import link_values_read_safely
from .pump import ORDER
from .server.memory import TIDY
from .server.patches import apply_all
from .server.sessions import (
    READOUTS_FIRST,
    SOLVER_READY,
    first_run_when_ready,
    reopen_when_reconnected,
    session_closed,
    stylesheets_from_this_server,
    wait_for_the_browser,
)
from .server.upload_route import page_opened
from .uploads import guard_uploads
from .viewport import report_views_seen

pn.extension(notifications=False)
document = pn.state.curdoc
link_values_read_safely()  # before pn.state.location reads the link
apply_all()  # Panel's and Bokeh's patches (server.patches), each once per process
stylesheets_from_this_server(document)
keyboard_and_screen_readers(document)
guard_uploads(document, route=page_opened(document))  # a wind or site file by HTTP
report_views_seen(document, ORDER)
reopen_when_reconnected(document)
wait_for_the_browser(document)  # a page loading slowly is built once, not again as it connects
logging.basicConfig(level=logging.INFO)

pn.state.on_session_destroyed(session_closed)
query = utf8_keys(pn.state.session_args)  # ?café=1 named as typed
# ?resolution=full sends every sample instead of min/max bands (benchmarks/bench_app.py's baseline)
full = query.get("resolution", [b""])[0] == b"full"
# The first start after an install compiles the solver in the background: this page opens at
# once and runs its design when the solver is ready (server.sessions.first_run_when_ready).
# So does one opened while a worker compiles the real machine: its link may open one (a deep well)
# or a wheel (the Aermotor's preset)
ready = SOLVER_READY.is_set() and all(COMPILE.ready[p].is_set() for p in (REAL_MACHINE, WHEEL))
explorer = Explorer(
    bins=None if full else BINS, query=query, defer_views=True, lazy_views=True, start=ready
)
explorer.follow_in_link(pn.state.location)  # one way: the page writes its link, reads it once
with document.models.freeze():  # one walk of the models for the page, not one per root
    explorer.template().servable()
# The plots and the machine follow once the page has loaded, and once every other page opening
# meanwhile shows its readouts (server.sessions.ReadoutsFirst): a class opening it at once reads sooner;
# each view only once the page shows it (viewport.report_views_seen): a page nobody scrolls
# builds the two of its first screen.
session_id = document.session_context.id
READOUTS_FIRST.opened(session_id)
TIDY.opened()
TIDY.settle()  # its objects frozen, out of every later collection's walk (server.memory.Tidy)
# partial, not a lambda: Bokeh clears this module's globals once the session has started
if ready:
    pn.state.onload(partial(READOUTS_FIRST.loaded, session_id, document, explorer.show_views))
else:
    pn.state.onload(first_run_when_ready(session_id, document, explorer))
