"""What a closed page leaves behind in the server: nothing of its own.

A served page's components are dropped with its session; anything a class-level or module-level
registry keeps of them is kept for every page a server ever served (a hall of 100, then the next
class...). Here pages are built in-process and dropped, as a closed session drops them, and what
still lives is counted.
"""

from __future__ import annotations

import gc

import panel as pn
from panel.links import Callback
from panel.reactive import Reactive

from windpump_app.explorer import Explorer


def components_alive() -> int:
    """Panel's components anywhere in the process, once the garbage is collected."""
    gc.collect()
    return sum(isinstance(o, Reactive) for o in gc.get_objects())


def a_page_dropped() -> None:
    explorer = Explorer(defer_views=True, lazy_views=True)
    explorer.show_views()
    explorer.template()


def test_a_dropped_page_leaves_none_of_its_components_alive():
    a_page_dropped()  # what the first page imports and caches is not the page's
    before = components_alive()
    for _ in range(2):
        a_page_dropped()
    assert components_alive() == before


def test_panels_link_registry_forgets_a_dropped_pages_buttons():
    """Panel's ``Callback.registry`` holds a component weakly and its JavaScript callbacks
    strongly: a callback whose ``args`` hold the component keeps it (and its page's design)."""
    a_page_dropped()
    gc.collect()
    kept = [source for source in Callback.registry.keys() if isinstance(source, pn.widgets.Button)]
    assert kept == []
