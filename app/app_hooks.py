"""Server hooks of the directory app: ready before the first student opens the page."""

import windpump


def on_server_loaded(_server_context) -> None:
    """Compile (or load from numba's cache) the solver once, when ``panel serve app/`` starts, so the
    first page opens as fast as the later ones."""
    seed = windpump.Design.seed_example()
    seen = windpump.explore(seed, 600.0)
    windpump.power_budget(seed, seen.run).cycle_means()
    windpump.playback_frames(seen.run)
