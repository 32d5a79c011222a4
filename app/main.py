"""Entry point of the live explorer: ``panel serve app/`` (a Bokeh directory app)."""

import logging

import panel as pn
from explorer import BINS, Explorer
from serving import release_memory

pn.extension(notifications=False)
logging.basicConfig(level=logging.INFO)

pn.state.on_session_destroyed(release_memory)
# ?resolution=full sends every sample instead of min/max bands (benchmarks/bench_app.py's baseline)
full = pn.state.session_args.get("resolution", [b""])[0] == b"full"
Explorer(bins=None if full else BINS).template().servable()
