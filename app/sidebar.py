"""The page's sidebar: the pump's sliders and switches, presets, pin and reset, the link, the
theme and presentation mode, lab data and the run's download."""

from __future__ import annotations

from collections.abc import Callable

import panel as pn

import windpump

from .buttons import ActionButton
from .inputs import (
    CYLINDER_LABELS,
    FORMATS,
    PRESETS,
    REAL_MACHINE_INPUTS,
    SET_BY,
    STROKES,
    SWITCHES,
    WINDMILL_INPUTS,
    WINDMILLS,
    PumpInputs,
)
from .keyboard import FOCUS_CSS
from .lab import LabData
from .styles import TEXT, ZOOM_JS, px
from .uploads import RefusedUploads, Reveal

# Two buttons share a row of the sidebar: in presentation mode a label wraps inside its button.
BUTTON_CSS = ".bk-btn { white-space: normal; padding-left: 4px; padding-right: 4px; }"
PRESET_PROMPT = "Choose a preset…"
# The card's title stays one line, like "More parameters"; what it holds is said inside.
REAL_MACHINE_NOTE = (
    "The pump rod, the chain, the rising main and a leak hole: what the paper's ideal machine "
    "leaves out."
)
# A preset's sentence on a phone: its first two lines, ending in "…", so that the controls' pane
# (a fifth of the screen, page.CONTROLS_SHARE) shows the menu, the sentence's start and a slider;
# a tap on it shows it all (a tap hovers, on a touch screen), a tap elsewhere folds it again.
PRESET_NOTE_CSS = [
    *TEXT,
    "@media (max-width: 700px) { p { display: -webkit-box; -webkit-box-orient: vertical; "
    "-webkit-line-clamp: 2; line-clamp: 2; overflow: hidden; margin: 0 0 4px; cursor: pointer; } "
    ":host(:hover) p, :host(:focus-within) p { -webkit-line-clamp: unset; line-clamp: unset; } }",
]
CARD_NOTE_CSS = [*TEXT, f":host {{ font-size: {px(15)}; margin: 0 10px 4px; opacity: 0.85; }}"]


class PromptSlider(pn.widgets.FloatSlider):
    """Panel's float slider without its 50 ms wait for further moves before the server reacts
    (``Syncable._debounce``): a key press or a drag's first move starts the run at once, a third
    of the way to a readout within 100 ms. The run goes off the event loop, one a page at a
    time: moves that arrive while it is under way wait, and only the latest runs next
    (``session.Session.move``), so a drag never queues runs.

    Nor does a move count as Panel's "busy" (``Syncable._busy__ignore``): the page shows no busy
    indicator (``page.page``), and counting it (a uuid and two updates of ``pn.state``'s list of
    busy events a move) was a quarter of Panel's handling of a move on the event loop
    (py-spy while 30 students moved at once)."""

    _debounce = 0
    _busy__ignore = ["value", "value_throttled"]


def slider(label, start, end, step, value, fmt) -> PromptSlider:
    """A slider of the page's kind that no input parameter stands behind (the Mechanisms tab's)."""
    return PromptSlider(
        label=label,
        start=start,
        end=end,
        step=step,
        value=value,
        format=fmt,
        stylesheets=[*TEXT, FOCUS_CSS],
        sizing_mode="stretch_width",
    )


def design_filename(design: windpump.Design) -> str:
    return (
        f"windpump_h{design.h:g}m_LR{design.L_over_R:.3g}_Rdagger{design.R_dagger:.3g}"
        f"_Tm{design.T_m:g}_omegam{design.omega_m:g}.csv"
    )


def card_header(title: str) -> pn.pane.HTML:
    """A card's title at the page's text size (Panel's own title keeps a fixed size)."""
    return pn.pane.HTML(
        f"<b>{title}</b>", stylesheets=[*TEXT, ":host { margin: 2px 6px; text-align: left; }"]
    )


# The card's chevron, in the text's colour: Panel 1.9 strokes it with --background-text-color,
# which the Bootstrap template does not define, and so draws nothing (nothing says it opens).
CHEVRON_CSS = ".card-button > svg { stroke: currentColor; }"


def closed_card(title: str, build: Callable[[], list]) -> pn.Card:
    """A collapsed card whose contents, ``build()``, are made the first time it opens (a click on
    its header, or ``collapsed = False`` on the server) and kept: a card left closed costs the
    page none of its models."""
    card = pn.Card(
        header=card_header(title),
        collapsed=True,
        sizing_mode="stretch_width",
        stylesheets=[*TEXT, CHEVRON_CSS],
    )

    def fill(_event) -> None:
        if not card.collapsed and not card.objects:
            card.objects = build()

    card.param.watch(fill, "collapsed")
    return card


class Sliders(dict):
    """The sliders of the pump's inputs by name (FORMATS), each built when first asked for: those
    of a closed card or of a tab not yet opened cost the page nothing. A slider the windmill
    chosen sets itself (``SET_BY``: a wheel's Tₘ, ωₘ and T₀) is hidden while it is chosen."""

    def __init__(self, inputs: PumpInputs):
        super().__init__()
        self.inputs = inputs
        inputs.param.watch(self._windmill_chosen, "windmill")
        inputs.param.watch(self._head_end, ["windmill", "h"])

    def __missing__(self, name: str) -> PromptSlider:
        fmt, _place = FORMATS[name]
        self[name] = built = PromptSlider.from_param(
            self.inputs.param[name],
            format=fmt,
            stylesheets=[*TEXT, FOCUS_CSS],
            sizing_mode="stretch_width",
            visible=shown_for(name, self.inputs.windmill),
        )
        if name == "h":
            built.end = head_end(self.inputs)
        return built

    def _windmill_chosen(self, event) -> None:
        for name, built in self.items():
            built.visible = shown_for(name, event.new)

    def _head_end(self, *_events) -> None:
        if "h" in self:
            self["h"].end = head_end(self.inputs)


# [m] the head slider's end for the paper's pump (it stalls at 21 m): its full range, to a
# catalogue mill's lifts (920 ft), for a wheel or a head beyond it (a link's, a preset's)
PAPERS_HEADS = 30.0


def head_end(inputs: PumpInputs) -> float:
    """Where the head's slider ends: at PAPERS_HEADS for the paper's curve (a finer slider where
    its pump works), at the input's bound for a wheel or for a head beyond it."""
    if inputs.windmill == "eq11" and inputs.h <= PAPERS_HEADS:
        return PAPERS_HEADS
    return inputs.param["h"].bounds[1]


def shown_for(name: str, windmill: str) -> bool:
    """Whether input ``name``'s slider shows when ``windmill`` is chosen: not if the windmill
    sets it (``SET_BY``), nor a windmill's own input (the diameter) when another is chosen."""
    own = [n for names in WINDMILL_INPUTS.values() for n in names]
    if name in own:
        return name in WINDMILL_INPUTS[windmill]
    return name not in SET_BY[windmill]


# What the page says under the windmill's choice, about the sliders it sets (hidden meanwhile).
WINDMILL_NOTES = {
    "eq11": "",
    "multiblade": (
        "The wheel's torque curve (the American multiblade's C_Q(λ), ½ ρ π r³ V² C_Q) sets Tₘ, ωₘ "
        "and T₀: their sliders are hidden."
    ),
    "aermotor": (
        "The catalogue's mill sets its wheel (a multiblade), its back gear R₁/R₀, its stroke and "
        "bore, its inertias, Tₘ, ωₘ and T₀: their sliders are hidden. The head h is its lift."
    ),
}


class WindmillChoice(pn.viewable.Viewer):
    """The windmill's choice (``inputs.windmill``) and its own inputs: the multiblade wheel's
    diameter, the Aermotor's wheel, cylinder and stroke; each shown while its windmill is chosen,
    with a line saying which sliders the windmill sets."""

    def __init__(self, inputs: PumpInputs, sliders: Sliders):
        super().__init__()
        look = dict(stylesheets=[*TEXT, FOCUS_CSS], sizing_mode="stretch_width")
        self.select = pn.widgets.Select(
            label="Windmill", options={label: key for key, label in WINDMILLS.items()}, **look
        )
        self.wheel = pn.widgets.Select(
            label="Wheel [ft]",
            options={f"{ft}": ft for ft in inputs.param.wheel_ft.objects},
            **look,
        )
        self.cylinder = pn.widgets.Select(
            label="Bore [in]",
            options={
                CYLINDER_LABELS[inches]: inches for inches in inputs.param.cylinder_in.objects
            },
            **look,
        )
        self.stroke = pn.widgets.Select(
            label="Stroke", options={label: key for key, label in STROKES.items()}, **look
        )

        for widget, name in (
            (self.select, "windmill"),
            (self.wheel, "wheel_ft"),
            (self.cylinder, "cylinder_in"),
            (self.stroke, "stroke"),
        ):
            widget.value = getattr(inputs, name)
            widget.link(inputs, value=name, bidirectional=True)
        self.diameter = sliders["diameter"]
        # a third of the sidebar's width each
        self.aermotor = pn.GridBox(
            self.wheel, self.cylinder, self.stroke, ncols=3, sizing_mode="stretch_width"
        )
        self.note = pn.pane.HTML("", stylesheets=CARD_NOTE_CSS, sizing_mode="stretch_width")
        self.show(inputs.windmill)
        inputs.param.watch(lambda event: self.show(event.new), "windmill")

    def show(self, windmill: str) -> None:
        """The inputs and the note of ``windmill``."""
        self.aermotor.visible = windmill == "aermotor"
        self.note.object = WINDMILL_NOTES[windmill]
        self.note.visible = bool(WINDMILL_NOTES[windmill])

    def __panel__(self) -> pn.Column:
        return pn.Column(
            self.select, self.diameter, self.aermotor, self.note, sizing_mode="stretch_width"
        )


def ideal_machine(inputs: PumpInputs) -> bool:
    """Whether every input of the real machine holds its default (the paper's ideal machine)."""
    return all(inputs.is_default(name, getattr(inputs, name)) for name in REAL_MACHINE_INPUTS)


class Sidebar(pn.viewable.Viewer):
    """The controls. Their actions are the page's: it wires the buttons (``reset_button``,
    ``pin_button``, ``clear_button``, ``preset``) to itself; ``run_csv()`` is the file to download
    and ``show_points`` draws lab data."""

    def __init__(self, inputs: PumpInputs, dark: bool, run_csv: Callable, show_points: Callable):
        super().__init__()
        self.sliders = Sliders(inputs)
        self.windmill = WindmillChoice(inputs, self.sliders)
        self.switches = {
            name: pn.widgets.Checkbox.from_param(
                inputs.param[name], stylesheets=[*TEXT, FOCUS_CSS], sizing_mode="stretch_width"
            )
            for name in SWITCHES
        }
        self.more_card = self.card("More parameters", "more")
        self.real_card = self.card("Real machine", "real", REAL_MACHINE_NOTE)
        # a preset or a link that sets the real machine opens its card, so the student sees it
        inputs.param.watch(self._open_real_card, list(REAL_MACHINE_INPUTS))
        button = dict(stylesheets=[*TEXT, BUTTON_CSS, FOCUS_CSS], sizing_mode="stretch_width")
        self._page_buttons(button, dark)
        self.refused_upload = RefusedUploads()  # the page's word that it refused a large file
        self.reveal = Reveal()  # scrolls an upload's outcome into view
        self.lab = LabData(inputs, self.reveal, show_points, button)
        self.download = pn.widgets.FileDownload(
            callback=run_csv,
            filename="windpump_run.csv",
            label="Download this run (CSV)",
            color="light",
            **button,
        )

    def _page_buttons(self, button: dict, dark: bool) -> None:
        self.reset_button = ActionButton(
            label="Reset to the paper's example", color="primary", **button
        )
        self.preset = pn.widgets.Select(
            label="Presets", options=[PRESET_PROMPT, *PRESETS], **button
        )
        self.preset_note = pn.pane.Markdown("", visible=False, stylesheets=PRESET_NOTE_CSS)
        self.pin_button = ActionButton(label="Pin this run", **button)
        self.clear_button = ActionButton(label="Clear pinned", disabled=True, **button)
        self.units_switch = pn.widgets.RadioButtonGroup(
            options={"SI units": "si", "US units (ft, gal)": "us"}, **button
        )
        self.present_toggle = pn.widgets.Toggle(label="Presentation mode", **button)
        self.present_toggle.jscallback(value=ZOOM_JS)
        self.copy_link = pn.widgets.Button(label="Copy link to this state", **button)
        # The code reads the button as ``source`` (a click's cb_obj is the event, whose label is
        # nothing), not from args: Panel's Callback.registry holds the button weakly and its
        # callbacks strongly, so a button in its own args outlived its page (every closed page's)
        self.copy_link.js_on_click(code=COPY_LINK_JS)
        self.dark_toggle = pn.widgets.Button(
            label="Light theme" if dark else "Dark theme", **button
        )
        self.dark_toggle.js_on_click(code=DARK_JS)

    def show_design(self, design: windpump.Design) -> None:
        self.download.filename = design_filename(design)

    def _open_real_card(self, *events) -> None:
        if not ideal_machine(events[0].obj):
            self.real_card.collapsed = False

    def cards_as_fresh(self, inputs: PumpInputs) -> None:
        """The Real machine card as a fresh page of ``inputs``' design has it: open on a real
        machine, closed on an ideal one (a preset of an ideal machine chosen after one of a real
        machine left it open over sliders the design does not use)."""
        self.real_card.collapsed = ideal_machine(inputs)

    def card(self, title: str, place: str, note: str = "") -> pn.Card:
        """A collapsed card of the sliders that sit in ``place`` (FORMATS), under a ``note`` of
        what they are if any, empty until first opened (by the student, or by a preset or a link
        that sets one of its inputs): a page whose cards stay closed sends none of their sliders
        (28 of its 184 models)."""

        def build() -> list:
            said = [pn.pane.HTML(note, stylesheets=CARD_NOTE_CSS)] if note else []
            return said + [self.sliders[n] for n, (_f, where) in FORMATS.items() if where == place]

        return closed_card(title, build)

    def __panel__(self) -> pn.Column:
        main = [self.sliders[name] for name, (_f, place) in FORMATS.items() if place == "main"]
        lab = self.lab
        return pn.Column(
            self.preset,
            self.preset_note,
            *main,
            *self.switches.values(),
            # under the pump's sliders: a phone's controls pane shows the presets and a slider
            self.windmill,
            self.more_card,
            self.real_card,
            pn.Row(self.pin_button, self.clear_button, sizing_mode="stretch_width"),
            self.reset_button,
            self.copy_link,
            pn.Row(self.present_toggle, self.dark_toggle, sizing_mode="stretch_width"),
            self.units_switch,
            lab.upload.heading,
            lab.upload,
            self.refused_upload,
            self.reveal,
            lab.message,
            lab.apply_fit,
            lab.note,
            self.download,
            sizing_mode="stretch_width",
        )


COPY_LINK_JS = """
const url = window.location.href
const done = () => {
  source.label = 'Link copied'
  setTimeout(() => { source.label = 'Copy link to this state' }, 2500)
}
if (navigator.clipboard && window.isSecureContext) {
  navigator.clipboard.writeText(url).then(done, () => window.prompt('Copy this link:', url))
} else {
  const area = document.createElement('textarea'); area.value = url; document.body.appendChild(area)
  area.select(); const ok = document.execCommand('copy'); area.remove()
  if (ok) done(); else window.prompt('Copy this link:', url)
}
"""

# The template's theme is set when the page is built: switch it through the link, keeping the state.
DARK_JS = """
const url = new URL(window.location.href)
if (url.searchParams.get('theme') === 'dark') url.searchParams.delete('theme')
else url.searchParams.set('theme', 'dark')
window.location.href = url.toString()
"""
