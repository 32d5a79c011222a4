"""The Site tab's wind records: the two typical years pvlib ships, or a file uploaded (TMY3, EPW or
the Wind tab's CSV, at most 10 MB: a bad file is explained and the record stays as it was), each
at the hub height the tab asks for. Reading a file and a record at a height are the core's work
and may run in a thread (``read_upload``, ``at``); the rest changes the message, on the loop."""

from __future__ import annotations

import functools
import logging
from pathlib import Path

import panel as pn

import windpump
from windpump.readers.labdata import check_file_size
from windpump.readers.quantities import display_unit

from .escape import as_text
from .inputs import clipped
from .server.api import in_a_process
from .site_inputs import SITES, UPLOADED
from .styles import TEXT
from .uploads import (
    SITE_CLASS,
    SITE_SIZE,
    WIND_MAX_BYTES,
    Encoded,
    FileUpload,
    chosen,
    decoded,
    refused_size,
)

WHAT = "a year of hourly weather"  # the core's refusal: "(... needs far fewer)"
SIZE = SITE_SIZE  # the page's refusal: "(...)"
SUFFIXES = (".csv", ".epw", ".txt", ".tsv")
log = logging.getLogger("windpump.app")


@functools.lru_cache(maxsize=2)
def sample(name: str) -> windpump.WindRecord:
    """A typical year pvlib ships, read once for the server."""
    return windpump.sample_site(name)


@functools.lru_cache(maxsize=16)
def sample_at(name: str, hub: float) -> windpump.WindRecord:
    """A shipped year at the hub height [m], kept: a move of the demand reuses the same record."""
    return sample(name).at_height(hub)


def read_upload(data: bytes | Encoded, filename: str) -> windpump.WindRecord:
    """A weather file's record from an upload's bytes (served, read in the file-reading process:
    ``serving.in_a_process``), named after the file when it names no station (a CSV). An empty
    file is the core's to refuse: it says what the file needs."""
    data = decoded(data)
    check_file_size(len(data), WIND_MAX_BYTES, what=WHAT)
    record = in_a_process(windpump.read_weather, data)
    if record.name:
        return record
    name = Path(filename).stem or "uploaded"
    return windpump.WindRecord(record.t, record.V, record.height, name, record.month)


class SiteRecords:
    """The tab's records: ``at(site, hub)``; an upload's control and message (``controls``)."""

    def __init__(self):
        self.uploaded: windpump.WindRecord | None = None
        self.uploaded_name = ""
        self._at: tuple = ()  # (hub, the uploaded record at it)

    def controls(self, message_class: str) -> tuple[pn.widgets.FileInput, pn.pane.Alert]:
        self.upload = FileUpload(
            "Your own site",
            "a TMY3 or EPW file, or a CSV of time, wind speed [m/s]",
            accept=",".join(SUFFIXES),
            css_classes=[SITE_CLASS],  # the page's size check knows it by this
            stylesheets=TEXT,
            sizing_mode="stretch_width",
        )
        self.message = pn.pane.Alert(
            "", alert_type="danger", visible=False, stylesheets=TEXT, css_classes=[message_class]
        )
        return self.upload, self.message

    def chosen(self) -> bytes | Encoded | None:
        return chosen(self.upload)

    def at(self, site: str, hub: float) -> windpump.WindRecord:
        """The site's record at the hub height [m]."""
        if site != UPLOADED:
            return sample_at(site, hub)
        if self.uploaded is None:
            raise ValueError("no file has been uploaded: choose one, or a site of the list")
        if not self._at or self._at[0] != hub or self._at[1] is not self.uploaded:
            self._at = (hub, self.uploaded, self.uploaded.at_height(hub))
        return self._at[2]

    def reading(self, filename: str) -> None:
        """Say that the file ``filename`` is being read (off the event loop: ``read_upload``)."""
        self.message.object = f"Reading {clipped(filename) or 'the file'}…"
        self.message.alert_type, self.message.visible = "info", True

    def accept(self, record: windpump.WindRecord | Exception, filename: str) -> bool:
        """``read_upload``'s record becomes the uploaded site (True), or the error it raised is
        explained in the message and nothing changes (False)."""
        self.message.alert_type = "danger"
        if isinstance(record, Exception):
            said = as_text(record)
            if not isinstance(record, ValueError):  # a bug: say so, log it, keep the page alive
                log.error("reading a weather file failed", exc_info=record)
                said = f"{type(record).__name__}: {as_text(record)}"
            self.message.object = f"This weather file cannot be used: {said}"
            self.message.visible = True
            return False
        self.uploaded, self.uploaded_name = record, record.name or Path(filename).stem
        self.message.visible = False
        return True

    def refuse_size(self, size: int) -> None:
        """The page stopped a file over the limit before sending it: say so."""
        message = refused_size("weather", size, SIZE)
        if message is not None:
            self.say(message)

    def say(self, message: str, alert_type: str = "danger") -> None:
        self.message.object, self.message.alert_type, self.message.visible = (
            message,
            alert_type,
            True,
        )

    def describe(self, site: str, hub: float, system: str = "si") -> str:
        """A line on the record: where, the station, the hub's height [m], in ``system``'s
        units (``"si"``: "10 m"; ``"us"``: "32.8 ft", pint's)."""
        record = sample(site) if site != UPLOADED else self.uploaded
        where = SITES.get(site, f"the uploaded file *{as_text(self.uploaded_name)}*")
        name = f" ({as_text(record.name)})" if record is not None and record.name else ""
        feet, unit = display_unit("height", system)
        height = f"{hub:g} m" if system == "si" else f"{feet * hub:.1f} {unit}"
        return f"**{where}**{name}, the hub at {height}."


HOURS_IN_A_YEAR = (8760, 8784)  # a typical year, a leap year
ATTENDED_HINT = (
    "Choose “Attended” under “Restart after a calm” to have someone start it whenever the wind "
    "can carry it."
)


def span(hours: int) -> str:
    """The record's span in words: "the year" (8760 or 8784 h), "N days" or "N h"."""
    if hours in HOURS_IN_A_YEAR:
        return "the year"
    if hours % 24 == 0:
        days = hours // 24
        return f"{days} day{'' if days == 1 else 's'}"
    return f"{hours} h"


LOLP_TARGET = 0.05  # the readout's "smallest tank for 5 %", and a year that meets its demand
MOSTLY_SHORT = 0.5  # a year that leaves half its demand or more undelivered: a red box


def supply_status(supplied) -> tuple[str, str]:
    """What the year's run says of itself, as a status box's (text, alert type): its starts, or
    why it never starts (and, when it restarts on its own, the tab's option that helps). Green
    only for a year that meets its demand (loss of load within ``LOLP_TARGET``): a pump that ran
    1 h of the year, 99.9 % of its demand short, once said so in a green box."""
    if supplied.why:
        hint = f" {ATTENDED_HINT}" if supplied.restart == "self" else ""
        why = supplied.why[0].upper() + supplied.why[1:]
        return f"**The pump never starts.** {why}.{hint}", "warning"
    starts = supplied.starts
    runs = (
        f"{supplied.totals.running_hours:,d} h of {span(supplied.hours)}, "
        f"starting {starts:,d} time{'' if starts == 1 else 's'}"
    )
    if supplied.lolp <= LOLP_TARGET:
        return f"**The pump runs** {runs}.", "success"
    short = f"{100 * supplied.lolp:.1f} % of the demand goes undelivered"
    if supplied.lolp < MOSTLY_SHORT:
        return f"**The pump runs** {runs}, but {short}.", "warning"
    return f"**The pump falls far short.** It runs {runs}, and {short}.", "danger"
