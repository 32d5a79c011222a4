"""Entry point of the live explorer: ``panel serve app/`` (a Bokeh directory app)."""

import logging

import panel as pn
from explorer import Explorer

pn.extension(notifications=False)
logging.basicConfig(level=logging.INFO)

Explorer().template().servable()
