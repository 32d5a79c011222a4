"""What an idle page holds in the server's memory, in-process: N pages built as ``panel serve
app/`` builds them (``app/main.py``: a Bokeh document per page, the app's ``Explorer`` and its
template rendered into it), kept alive, and measured.

Run: python benchmarks/bench_page_memory.py [N] [--views | --every-view] [--top K] [--watchers]
     [--baseline]
     (N = 10 by default; --views: each page also builds its first screen's views, the crank speed
     and the machine, as a page at 1280x720 names them once loaded; --every-view: all seven, as a
     page scrolled to its end; --baseline: without app/server/patches/'s cuts, to compare)

Printed, per page (the mean of N, after one page built first to warm every cache):
- bytes by tracemalloc (what the N pages allocated and still hold), and its top allocation sites
  grouped by the outermost and the innermost frame of this app (``windpump_app``) and by the
  innermost frame in Panel, param or Bokeh;
- objects the garbage collector tracks, by type, and the param watchers by the class of the
  component that holds them and the function they call (``--watchers``).

No timing: this is memory, and it is the same on a busy machine.
"""

from __future__ import annotations

import argparse
import gc
import re
import sys
import tracemalloc
from collections import Counter
from pathlib import Path

FRAMES = 40  # tracemalloc's traceback depth: deep enough to reach the app's frame


def setup(lighter: bool = True) -> None:
    """What ``app/main.py`` does once per process before a page; without ``lighter``, without
    the cuts to a page's memory (``server.patches.lighter_components``, and Bokeh's empty defaults made
    with each model: ``bokeh_properties.empty_defaults_made_when_read`` left out), to compare."""
    import panel as pn

    from windpump_app.server.patches import (
        lighter_components,
        lighter_patches,
        lighter_properties,
        lighter_updates,
        without_mathjax,
        without_webgl,
    )

    pn.extension(notifications=False)
    without_mathjax()
    without_webgl()
    lighter_patches()
    lighter_updates()
    if lighter:
        lighter_properties()
        lighter_components()
        return
    from windpump_app.server.patches import bokeh_properties as defaults

    cut = defaults.empty_defaults_made_when_read
    defaults.empty_defaults_made_when_read = lambda: None  # type: ignore[assignment]
    try:
        lighter_properties()
    finally:
        defaults.empty_defaults_made_when_read = cut  # type: ignore[assignment]


FIRST_SCREEN = ("speed", "machine")  # what a page at 1280x720 shows once loaded


def page(views: bool | tuple[str, ...] = False):
    """One page as ``app/main.py`` builds it (in-process: no session, so its run is drawn at once),
    and with ``views`` the two views of its first screen (or the views it names): its document,
    explorer and template."""
    from bokeh.document import Document
    from panel.io.state import set_curdoc, state

    from windpump_app.explorer import Explorer
    from windpump_app.keyboard import keyboard_and_screen_readers
    from windpump_app.pump import ORDER
    from windpump_app.server.sessions import reopen_when_reconnected, stylesheets_from_this_server
    from windpump_app.uploads import guard_uploads
    from windpump_app.viewport import report_views_seen

    document = Document()
    with set_curdoc(document):
        stylesheets_from_this_server(document)
        keyboard_and_screen_readers(document)
        guard_uploads(document)
        report_views_seen(document, ORDER)
        reopen_when_reconnected(document)
        explorer = Explorer(query={}, defer_views=True, lazy_views=True, start=True)
        explorer.follow_in_link(state.location)
        template = explorer.template()
        with document.models.freeze():
            template.server_doc(document)
        if views:
            explorer.see_views(list(FIRST_SCREEN if views is True else views))
            explorer.show_views()
        document.to_json()  # what the page's websocket sends (PULL-DOC-REPLY)
    return document, explorer, template


LIBRARIES = ("/panel/", "/param/", "/bokeh/")
GROUPS = {
    "outermost app frame (the part of the page being built)": "outer",
    "innermost app frame": "inner",
    "innermost Panel, param or Bokeh frame (the allocation's site)": "library",
}


def normalised(document) -> str:
    """A document's JSON as a page's websocket sends it, with the ids, Panel's names and object
    addresses it carries numbered in order of appearance (they differ from page to page): two
    pages built alike give the same text."""
    from bokeh.core.json_encoder import serialize_json

    text = serialize_json(document.to_json(), pretty=False)
    ids: dict[str, str] = {}
    pattern = r"\b(p\d+|[A-Z][A-Za-z0-9]*?\d{5}|\d{12,})\b"
    return re.sub(pattern, lambda m: ids.setdefault(m.group(1), f"id{len(ids)}"), text)


def where(trace, group: str) -> str:
    """An allocation's site by its traceback (oldest frame first), as ``group`` names it."""
    frames = list(trace)
    if group == "library":
        for frame in reversed(frames):
            for library in LIBRARIES:
                if library in frame.filename:
                    name = frame.filename.split(library)[-1]
                    return f"{library.strip('/')}/{name}:{frame.lineno}"
        return "(other)"
    import windpump_app

    app = str(Path(windpump_app.__file__).parent)
    ours = [frame for frame in frames if frame.filename.startswith(app)]
    if not ours:
        return "(no app frame: the template, the document)"
    frame = ours[0] if group == "outer" else ours[-1]
    return f"{Path(frame.filename).name}:{frame.lineno}"


def watchers_of(objects) -> Counter:
    """Param watchers among ``objects``, by the class of the component watched and the callback."""
    from param.parameterized import Watcher

    found: Counter = Counter()
    for obj in objects:
        if type(obj) is Watcher:
            owner = obj.inst if obj.inst is not None else obj.cls
            owner_name = (
                type(owner).__name__ if obj.inst is not None else getattr(owner, "__name__", "?")
            )
            fn = getattr(obj.fn, "__qualname__", None) or type(obj.fn).__name__
            found[f"{owner_name} <- {fn}"] += 1
    return found


def measure(
    n: int, views: bool | tuple[str, ...], top: int, show_watchers: bool, lighter: bool = True
) -> dict:
    setup(lighter)
    page(views)  # warm: imports, class-level caches, the shared run
    gc.collect()
    before_ids = {id(obj) for obj in gc.get_objects()}
    tracemalloc.start(FRAMES)
    first = tracemalloc.take_snapshot()
    pages = [page(views) for _ in range(n)]
    gc.collect()
    last = tracemalloc.take_snapshot()
    tracemalloc.stop()
    new = [obj for obj in gc.get_objects() if id(obj) not in before_ids]
    stats = last.compare_to(first, "traceback")
    total = sum(stat.size_diff for stat in stats)
    shown = {False: "", True: " with their first screen's views"}.get(views, " with every view")
    print(f"{n} pages{shown}: ", end="")
    print(f"{total / n / 1e6:.3f} MB a page by tracemalloc, {len(new) / n:,.0f} gc objects a page")
    for label, group in GROUPS.items():
        grouped: Counter = Counter()
        for stat in stats:
            grouped[where(stat.traceback, group)] += stat.size_diff
        print(f"\n  top {top} by {label} [kB a page]")
        for site, size in grouped.most_common(top):
            print(f"    {size / n / 1e3:8.1f}  {site}")
    types = Counter(type(obj).__qualname__ for obj in new)
    print(f"\n  top {top} gc object types [a page]")
    for name, count in types.most_common(top):
        print(f"    {count / n:8.1f}  {name}")
    if show_watchers:
        watchers = watchers_of(new)
        print(f"\n  param watchers: {sum(watchers.values()) / n:.0f} a page; top {top}")
        for name, count in watchers.most_common(top):
            print(f"    {count / n:8.1f}  {name}")
    del pages
    return {"bytes": total / n, "objects": len(new) / n}


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("n", nargs="?", type=int, default=10)
    parser.add_argument("--views", action="store_true", help="build the first screen's views")
    parser.add_argument("--every-view", action="store_true", help="build all seven views")
    parser.add_argument("--top", type=int, default=20)
    parser.add_argument("--watchers", action="store_true")
    parser.add_argument(
        "--baseline", action="store_true", help="without the cuts to a page's memory, to compare"
    )
    args = parser.parse_args(argv)
    from windpump_app.pump import ORDER

    views = tuple(ORDER) if args.every_view else args.views
    return measure(args.n, views, args.top, args.watchers, not args.baseline)


if __name__ == "__main__":
    sys.exit(main() and None)
