"""The page's sidebar: the pump's sliders and switches, presets, pin and reset, the link, the
theme and presentation mode, lab data and the run's download."""

from __future__ import annotations

from collections.abc import Callable

import panel as pn

import windpump

from .buttons import ActionButton
from .inputs import FORMATS, PRESETS, REAL_MACHINE_INPUTS, SWITCHES, PumpInputs
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
    of a closed card or of a tab not yet opened cost the page nothing."""

    def __init__(self, inputs: PumpInputs):
        super().__init__()
        self.inputs = inputs

    def __missing__(self, name: str) -> PromptSlider:
        fmt, _place = FORMATS[name]
        self[name] = built = PromptSlider.from_param(
            self.inputs.param[name],
            format=fmt,
            stylesheets=[*TEXT, FOCUS_CSS],
            sizing_mode="stretch_width",
        )
        return built


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
            self.more_card,
            self.real_card,
            pn.Row(self.pin_button, self.clear_button, sizing_mode="stretch_width"),
            self.reset_button,
            self.copy_link,
            pn.Row(self.present_toggle, self.dark_toggle, sizing_mode="stretch_width"),
            pn.pane.Markdown(
                "**Lab data**: a CSV of windmill speed [rad/s], torque [N·m]", stylesheets=TEXT
            ),
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
