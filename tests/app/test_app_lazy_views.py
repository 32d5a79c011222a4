"""The pump's views built when the page first shows them (``Explorer(lazy_views=True)``, as
`panel serve` builds a page): in-process, the page's report written as the page writes it."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import windpump
from windpump_app.envelope import band
from windpump_app.explorer import Explorer
from windpump_app.figures import HEIGHT, palette
from windpump_app.pump import ORDER, PRESENTATION_GROWTH
from windpump_app.views import BINS

SEED = windpump.Design.seed_example()
LOWER = ("flow", "closeup", "energy", "stall", "operating")  # below a projector's first screen


def expected(design=SEED, t_end=600.0):
    return windpump.explore(design, t_end, math.pi / 2, 3.0)


def served(**options) -> Explorer:
    """A page as `panel serve` builds it, loaded (``show_views``) but not yet reporting."""
    app = Explorer(defer_views=True, lazy_views=True, **options)
    app.show_views()
    return app


def built(app) -> set[str]:
    return set(app.pump.built)


def plain(values):
    """A column as nested lists, whatever holds it (numpy arrays or lists)."""
    if isinstance(values, np.ndarray):
        return values.tolist()
    if isinstance(values, list | tuple):
        return [plain(v) for v in values]
    return values


def placeholder_height(app, name) -> int:
    """The height [px] of view ``name``'s placeholder, as the page draws it."""
    return int(re.search(r"height: (\d+)px", app.pump.slots[name].object).group(1))


def lab_csv(omega, torque) -> bytes:
    return "".join(f"{w},{q}\n" for w, q in zip(omega, torque, strict=True)).encode()


def test_no_view_is_built_until_the_page_says_it_shows_it():
    app = served()
    assert built(app) == set() and "speed" not in app.sources
    app.see_views(["speed", "machine"])  # a projector's first screen
    assert built(app) == {"speed", "machine"} and "flow" not in app.sources
    seen = expected()
    lower, upper = (np.asarray(a) for a in band(seen.run.t, seen.run.theta_dot, BINS)[1:])
    np.testing.assert_array_equal(app.sources["speed"].data["lower"], lower)
    np.testing.assert_array_equal(app.sources["speed"].data["upper"], upper)
    assert app.pump.results.objects[0].objects[0].object is app.pump.speed.figure
    assert app.pump.results.objects[2].css_classes[-1] == "view-flow"  # its placeholder
    app.see_views(["operating"])
    assert built(app) == {"speed", "machine", "operating"}


def test_a_tampered_report_builds_nothing_it_does_not_name():
    app = served()
    app.pump.channel.value = "speed <script>alert(1)</script> flow_figure stalls"
    assert built(app) == {"speed"}


def test_views_seen_before_the_page_has_loaded_are_built_when_it_has():
    app = Explorer(defer_views=True, lazy_views=True)
    app.see_views(["speed", "machine"])  # the page reports at once; the server waits its turn
    assert built(app) == set()
    app.show_views()  # serving.ReadoutsFirst: every other page opening meanwhile has loaded
    assert built(app) == {"speed", "machine"}


def test_moves_redraw_only_the_views_built_and_a_view_built_later_draws_the_latest_run():
    app = served()
    app.see_views(["speed"])
    app.set_values(h=5.0, cylinders=3)
    assert built(app) == {"speed"}
    design = SEED.replace(h=5.0, cylinders=3)
    seen = expected(design)
    app.see_views(["flow", "machine", "stall"])
    flow = band(seen.run.t, 1e3 * seen.run.flow, BINS)
    np.testing.assert_allclose(app.sources["flow"].data["upper"], flow[2], rtol=1e-12)
    assert app.sources["machine_geometry"].data["cylinders"] == [3.0]
    t_end = float(seen.run.t[-1])  # it stalls
    assert app.sources["frames"].data["t"][-1] == pytest.approx(t_end, rel=1e-6)
    sides = np.array(windpump.stall_sides(design))
    ratio = app.sources["stall"].data["value"][1] / app.sources["stall"].data["value"][0]
    assert ratio == pytest.approx(sides[1] / sides[0], rel=1e-12)
    assert f"margin {seen.margin:.3f}" in app.pump.stall.figure.title.text
    assert app.pump.time_range.end == pytest.approx(t_end)


def test_a_view_built_later_draws_as_if_it_had_been_built_with_the_page():
    """Pinned run, lab points, a move and presentation mode before the views are seen: each view
    then holds what a page that built every view at load holds."""
    omega = np.linspace(5, 95, 10)
    torque = 0.8 * (omega / 45) * (2 - omega / 45)

    def act(app) -> None:
        app.pin()
        app.sidebar.lab.upload.value = lab_csv(omega, torque)  # sets T_m and omega_m: a move
        app.set_values(h=4.0)
        app.sidebar.present_toggle.value = True

    eager, lazy = Explorer(), served()
    lazy.see_views(["speed"])  # one view drawn with the page, the others after
    act(eager)
    act(lazy)
    lazy.see_views(list(ORDER))
    assert built(lazy) == set(ORDER)
    for name in ORDER:
        a, b = eager.pump.built[name], lazy.pump.built[name]
        for key, source in a.sources.items():
            for column, values in source.data.items():
                assert plain(b.sources[key].data[column]) == plain(values), (name, key, column)
        assert b.figure.height == a.figure.height, name
        assert b.figure.title.text_font_size == a.figure.title.text_font_size, name
        items = getattr(a, "items", {})
        assert {k: i.visible for k, i in items.items()} == {
            k: i.visible for k, i in getattr(b, "items", {}).items()
        }, name
    # checked against the core, not only against the eager page
    pinned = expected()  # the paper's example, pinned before the lab file
    ghost = band(pinned.run.t, 1e3 * pinned.run.flow, BINS)
    np.testing.assert_allclose(lazy.sources["flow_ghost"].data["upper"], ghost[2], rtol=1e-12)
    assert lazy.pump.flow.items["pinned run"].visible
    np.testing.assert_allclose(lazy.sources["data"].data["power"], omega * torque)
    assert lazy.pump.operating.items["lab data"].visible
    assert lazy.pump.energy.figure.height == round(HEIGHT * PRESENTATION_GROWTH)
    assert float(lazy.pump.energy.figure.title.text_font_size[:-2]) > 16


def test_a_placeholder_keeps_its_views_height_in_presentation_mode_too():
    app = served()
    heights = {n: placeholder_height(app, n) for n in LOWER}
    assert heights == {n: HEIGHT * 3 // 4 if n == "stall" else HEIGHT for n in LOWER}
    app.sidebar.present_toggle.value = True
    for name in LOWER:
        assert placeholder_height(app, name) == round(PRESENTATION_GROWTH * heights[name])
    app.see_views(list(LOWER))
    grown = {n: round(PRESENTATION_GROWTH * heights[n]) for n in LOWER}
    assert {n: app.pump.built[n].figure.height for n in LOWER} == grown
    app.sidebar.present_toggle.value = False
    assert {n: app.pump.built[n].figure.height for n in LOWER} == heights


def test_clearing_the_pinned_run_reaches_views_built_later():
    app = served()
    app.pin()
    app.clear_pinned()
    app.see_views(["speed", "flow"])
    assert app.sources["speed_ghost"].data["t"] == [] and app.sources["flow_ghost"].data["t"] == []
    assert not app.pump.speed.items["pinned run"].visible


def test_a_view_built_later_on_a_dark_page_draws_in_the_dark_theme():
    app = served(query={"theme": [b"dark"]})
    app.see_views(["operating"])
    assert app.pump.operating.colors == palette(dark=True)


def test_reset_clears_lab_points_for_views_built_later():
    app = served()
    omega = np.linspace(5, 95, 10)
    app.sidebar.lab.upload.value = lab_csv(omega, 0.5 * np.ones(10))
    app.reset()
    app.see_views(["operating"])
    assert len(app.sources["data"].data["omega"]) == 0
    assert not app.pump.operating.items["lab data"].visible


def test_the_views_send_no_copies_of_their_glyphs():
    """Nothing selects or mutes here: the browser makes those glyphs if ever asked (``"auto"``)."""
    from bokeh.models import GlyphRenderer

    app = served()
    app.see_views(list(ORDER))
    renderers = [
        r for view in app.pump.views for r in view.figure.renderers if isinstance(r, GlyphRenderer)
    ]
    assert len(renderers) > 30
    assert {(r.nonselection_glyph, r.muted_glyph) for r in renderers} == {("auto", "auto")}
    assert all(r.glyph is not None and r.glyph.id for r in renderers)


def test_pages_asking_the_same_run_share_it_and_it_goes_with_the_last():
    """A class opening the default page holds the paper's run once, not once a page."""
    import gc

    from windpump_app.session import SHARED_RUNS

    first, second = Explorer(defer_views=True), Explorer(defer_views=True)
    assert first.seen is second.seen
    np.testing.assert_array_equal(first.seen.run.theta_dot, expected().run.theta_dot)
    second.set_values(h=4.0)  # its own run now; the first keeps the paper's
    assert second.seen is not first.seen and second.seen.design.h == 4.0
    assert first.seen.design == SEED
    third = Explorer(defer_views=True, query={"h": [b"4"]})  # asks what the second holds
    assert third.seen is second.seen
    key = (second.seen.design, 600.0, math.pi / 2, 3.0)
    assert SHARED_RUNS.get(key) is second.seen
    del second, third
    gc.collect()
    assert SHARED_RUNS.get(key) is None  # no page holds it: gone
