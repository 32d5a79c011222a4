"""Entry point of the live explorer: ``panel serve app/`` (a Bokeh directory app)."""

import logging

import panel as pn
from explorer import Explorer
from serving import release_memory

pn.extension(notifications=False)
logging.basicConfig(level=logging.INFO)

pn.state.on_session_destroyed(release_memory)
Explorer().template().servable()
