"""Lab data in the sidebar: a CSV of measured windmill speed and torque, fitted to Eq. (11) by the
core, its T_m and omega_m applied to the sliders when the fit is good."""

from __future__ import annotations

import logging
from collections.abc import Callable

import panel as pn

import windpump

from .buttons import ActionButton
from .keyboard import FOCUS_CSS
from .server.api import Newest, in_a_process, off_the_loop
from .session import sentence
from .styles import TEXT
from .uploads import Encoded, FileUpload, Reveal, chosen, decoded

log = logging.getLogger("windpump.app")

# An upload's outcome, by the CSS class that scrolls it into view (uploads.Reveal)
LAB_MESSAGE, LAB_NOTE = "lab-message", "lab-note"


def fitted(data: bytes | Encoded) -> tuple[windpump.TorqueTable, windpump.TorqueFit]:
    """A lab file read (served, in the file-reading process: ``serving.in_a_process``) and
    Eq. (11) fitted to it; the core's ValueError says why a file cannot be used."""
    table = in_a_process(windpump.read_torque_csv, decoded(data))
    return table, windpump.fit_torque_curve(table.omega, table.torque)


class LabData:
    """The upload, its outcome and the offer to apply a poor fit. ``show_points(omega, power)``
    draws the measurements; a fit applied sets ``inputs``' T_m and omega_m."""

    def __init__(self, inputs, reveal: Reveal, show_points: Callable, button: dict):
        self.inputs = inputs
        self.reveal = reveal
        self.show_points = show_points
        self.upload = FileUpload(
            "Lab data",
            "a CSV of windmill speed [rad/s], torque [N·m]",
            accept=".csv,.txt,.tsv",
            stylesheets=[*TEXT, FOCUS_CSS],
            sizing_mode="stretch_width",
        )
        self.message = pn.pane.Alert(
            "", alert_type="danger", visible=False, stylesheets=TEXT, css_classes=[LAB_MESSAGE]
        )
        self.note = pn.pane.Markdown("", visible=False, stylesheets=TEXT, css_classes=[LAB_NOTE])
        self.apply_fit = ActionButton(
            label="Apply this fit anyway", color="warning", visible=False, **button
        )
        self.pending_fit: windpump.TorqueFit | None = None
        self.files = Newest()  # the file last chosen: its fit is shown, not an earlier one's
        self.upload.param.watch(lambda *_e: self.load(chosen(self.upload)), ["value", "filename"])
        self.apply_fit.on_click(lambda _e: self.apply(self.pending_fit))

    def load(self, data: bytes | Encoded | None) -> None:
        """A CSV of windmill speed [rad/s] and torque [N m]: fit Eq. (11); apply T_m and omega_m
        if the fit is good, else show it with a warning and apply it only on request. Read and
        fitted off the event loop (``serving.off_the_loop``, the file read in the file-reading
        process: a 1 MB file is ~0.1 s of pure Python); the newest file wins."""
        self.apply_fit.visible = False
        self.pending_fit = None
        if data is None:
            self.files.supersede()
            return
        self.files.ask(object(), lambda: fitted(data), self._fitted, off_the_loop)

    def _fitted(self, outcome) -> None:
        if isinstance(outcome, Exception):
            if not isinstance(outcome, ValueError):  # a bug: say so, log it, keep the page alive
                log.error("reading a lab file failed", exc_info=outcome)
                outcome = ValueError(f"{type(outcome).__name__}: {outcome}")
            self.refuse(outcome)
            return
        table, fit = outcome
        self.show_points(table.omega, table.power)
        summary = (
            f"Fitted Eq. (11) to {len(table.omega)} points: Tₘ = {fit.T_m:.3f} N·m, "
            f"ωₘ = {fit.omega_m:.1f} rad/s (rms residual {fit.rms_residual:.3g} N·m, "
            f"{100 * fit.relative_residual:.0f} % of Tₘ)."
        )
        if fit.poor:
            self._poor(fit, summary)
            return
        self.message.visible = False
        self.apply(fit, summary)

    def _poor(self, fit: windpump.TorqueFit, summary: str) -> None:
        outside = self.outside_sliders(fit)
        self.message.object = (
            f"**A poor fit.** {summary} Eq. (11) misses these data by more than "
            f"{100 * fit.POOR:.0f} % of Tₘ: are the columns speed, then torque? "
            + (
                f"It cannot be applied: {'; '.join(outside)}. Nothing was changed."
                if outside
                else "Not applied."
            )
        )
        self.message.alert_type = "warning"
        self.message.visible = True
        self.pending_fit = None if outside else fit
        self.apply_fit.visible = not outside  # offer only what can be applied
        self.reveal.show(LAB_MESSAGE)

    def refuse_size(self, size: int) -> None:
        """The page stopped a file over the size limit before sending it: say so, in the
        core's words; a size within the limit (tampered) is ignored."""
        try:
            windpump.readers.labdata.check_file_size(size)
        except ValueError as error:
            self.refuse(error)

    def refuse(self, error: ValueError) -> None:
        self.apply_fit.visible = False
        self.pending_fit = None
        self.message.object = f"**Could not use that file.** {sentence(error)} Nothing was changed."
        self.message.alert_type = "danger"
        self.message.visible = True
        self.reveal.show(LAB_MESSAGE)

    def outside_sliders(self, fit: windpump.TorqueFit) -> list[str]:
        """Why the fit cannot be set on the sliders: each value outside its slider's range."""
        return [
            f"{self.inputs.param[name].label} = {value:.3g} is outside {low:g}–{high:g}"
            for name, value in (("T_m", fit.T_m), ("omega_m", fit.omega_m))
            for low, high in [self.inputs.param[name].bounds]
            if not low <= value <= high
        ]

    def apply(self, fit: windpump.TorqueFit | None, summary: str = "") -> None:
        if fit is None:
            return
        outside = self.outside_sliders(fit)
        if outside:
            self.apply_fit.visible = False
            self.message.object = (
                f"**The fit cannot be applied:** {'; '.join(outside)}. Nothing was changed."
            )
            self.message.alert_type = "danger"
            self.message.visible = True
            self.reveal.show(LAB_MESSAGE)
            return
        self.apply_fit.visible = False
        self.note.object = (
            summary or f"Applied the fit: Tₘ = {fit.T_m:.3f} N·m, ωₘ = {fit.omega_m:.1f} rad/s."
        )
        self.note.visible = True
        # a fit of Eq. (11): the paper's curve, whichever windmill was chosen
        self.inputs.param.update(windmill="eq11", T_m=fit.T_m, omega_m=fit.omega_m)
        self.reveal.show(LAB_NOTE)

    def hide(self) -> None:
        """Reset: no message, note or offer left."""
        for pane in (self.note, self.message, self.apply_fit):
            pane.visible = False
