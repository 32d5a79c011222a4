"""Server hooks of the directory app (Bokeh finds them in this file by its name): the server's
start and stop (``server.hooks``), and the page's warm-ups the server runs once their part is
ready, registered here so that the server imports none of the page's tabs."""

from __future__ import annotations

import logging
import time

from .compiling import WIND_TAB
from .server.hooks import WARM_UPS, on_server_loaded, on_server_unloaded

__all__ = ["on_server_loaded", "on_server_unloaded", "warm_the_site_tab", "warm_the_wind_tab"]

log = logging.getLogger("windpump.app")


def warm_the_site_tab() -> None:
    """Read the record a first Site tab reads (``site_record.sample_at``: the default site at the
    default hub height, kept for every page), off the event loop as the server starts: reading it
    imports pvlib and pandas (~0.7 s of CPU on a quiet machine, seconds on a busy one), which the
    first student to open the tab waited for (the Site tab took 8.4 s on a later start)."""
    from .site_inputs import SiteInputs
    from .site_record import sample_at

    started = time.perf_counter()
    site = SiteInputs()
    try:
        sample_at(site.site, site.hub)
    except Exception:  # pvlib missing, or its file: the page's Site tab says why
        log.exception("reading the Site tab's record failed")
        return
    log.info("the Site tab's record read in %.1f s", time.perf_counter() - started)


def warm_the_wind_tab() -> None:
    """Run what a first Wind tab runs (``wind_tab.warm_up``), off the event loop once the solver
    is ready: the server's memory when it is ready for a class holds what every Wind tab shares
    (the modules it imports, the kernels of a run in a wind record, the default gusty day)."""
    from .inputs import PumpInputs
    from .wind_tab import warm_up

    started = time.perf_counter()
    try:
        warm_up(PumpInputs())
    except Exception:  # a page's Wind tab will run it, and say what went wrong
        log.exception("warming the Wind tab failed")
        return
    log.info("the Wind tab's first day run in %.1f s", time.perf_counter() - started)


# The Site tab's record at once (it compiles nothing), the Wind tab's day once its part is ready
WARM_UPS[:] = [(None, warm_the_site_tab), (WIND_TAB, warm_the_wind_tab)]
