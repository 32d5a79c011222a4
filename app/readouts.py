"""What a class reads after every move: the readout row (mean flow, volume, τ, …) and the status.

Panel 1.9.4's HTML-based panes re-send their stylesheets, as new objects, with every change of
their text: Bokeh then re-walks every model of the page and the browser restyles the pane (~40 ms
a slider move on the server for seven readouts and the status). These panes send their text
alone; a change of stylesheets or of an alert's type still goes through Panel's own path.
"""

from __future__ import annotations

import panel as pn

READOUT_CSS = """
.readout {border: 1px solid #bbb; border-radius: 6px; padding: 2px 10px; min-width: 120px}
.readout .label {font-size: 14px; color: inherit; opacity: 0.85}
.readout .value {font-size: 20px; font-weight: bold}
"""
PRESENTATION_CSS = """
@media (min-width: 701px) {  /* a phone keeps its sizes (styles.zoom_css) */
:host { font-size: 20px; }
.readout .value {font-size: 30px}
.readout .label {font-size: 17px; opacity: 1}
}
"""


def readout_html(label: str, value: str, name: str) -> str:
    """A label over a value; ``data-name`` lets a test or a script find the value."""
    return (
        f'<div class="readout"><div class="label">{label}</div>'
        f'<div class="value" data-name="{name}">{value}</div></div>'
    )


class TextOnlyUpdates:
    """For an HTML-based Panel pane: a new ``object`` updates the model's text and nothing else."""

    def _update(self, ref, model) -> None:
        model.text = self._process_param_change({"object": self.object})["text"]


class StatusAlert(TextOnlyUpdates, pn.pane.Alert):
    """The one-line verdict on the run (running, slowing, stalled, never started)."""


class Readout(TextOnlyUpdates, pn.pane.HTML):
    """One readout: ``show(label, value)`` sends its new text."""

    def __init__(self, name: str, **params):
        super().__init__("", stylesheets=[READOUT_CSS], **params)
        self.readout_name = name

    def show(self, label: str, value: str) -> None:
        self.object = readout_html(label, value, self.readout_name)

    def present(self, large: bool) -> None:
        """Presentation mode: larger values and labels."""
        self.stylesheets = [READOUT_CSS, PRESENTATION_CSS] if large else [READOUT_CSS]
