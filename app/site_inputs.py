"""What the Site tab's student sets: the site, the hub height, the demand, the tank and the restart
rule, as a ``param.Parameterized``, and their part of the page's link (short keys: ``site``,
``hub``, ``demand``, ``tank``, ``restart``; defaults left out)."""

from __future__ import annotations

from urllib.parse import urlencode

import param

from windpump.sites.yearly import DEFAULT_RESTART

from .inputs import clipped, grid_text, read_slider_number

# The records that ship with pvlib, by their link value
SITES = {"greensboro": "Greensboro, NC (TMY3)", "sand_point": "Sand Point, AK (TMY3)"}
UPLOADED = "uploaded"  # a file read in this session: not carried by a link
RESTARTS = {
    "attended": "Attended (V ≥ V_stop)",
    "self": "On its own (V ≥ V_start)",
}  # the core's restarts (windpump.sites.yearly.RESTARTS), labelled; the default is the core's


class SiteInputs(param.Parameterized):
    """The Site tab's inputs; the design is the pump's (its sliders)."""

    site = param.Selector(objects=[*SITES, UPLOADED], default="greensboro", label="Site")
    hub = param.Number(10.0, bounds=(2.0, 40.0), step=0.5, label="Hub height [m]")
    demand = param.Number(10.0, bounds=(0.1, 50.0), step=0.1, label="Demand [m³/day]")
    tank = param.Number(5.0, bounds=(0.0, 100.0), step=0.5, label="Tank [m³]")
    restart = param.Selector(objects=list(RESTARTS), default=DEFAULT_RESTART, label="Restart")

    NUMBERS = ("hub", "demand", "tank")
    CHOICES = ("site", "restart")

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        """The link's keys of the Site tab."""
        return (*cls.CHOICES, *cls.NUMBERS)

    def values(self) -> dict:
        return {name: getattr(self, name) for name in self.keys()}

    def defaults(self) -> dict:
        return {name: self.param[name].default for name in self.keys()}

    def is_default(self, name: str) -> bool:
        value, default = getattr(self, name), self.param[name].default
        if name in self.CHOICES:
            return value == default
        return abs(value - default) <= 1e-9 * self.param[name].step

    def query(self) -> str:
        """The link's query of these inputs: those that differ from their defaults, each as its
        control shows it (``demand=7.5``, ``site=sand_point``)."""
        return urlencode(
            {
                name: self.link_text(name, getattr(self, name))
                for name in self.keys()
                if not self.is_default(name)
            }
        )

    def link_text(self, name: str, value) -> str:
        if name in self.CHOICES:
            return str(value)
        return grid_text(value, self.param[name].step)

    def parse_query(self, query: dict) -> tuple[dict, list[str]]:
        """Values to apply from a link's query (this tab's keys only; str or bytes, lists as
        Tornado gives them; the last of several is used) and a notice for each value ignored."""
        values, notices = {}, []
        for key in self.keys():
            if key not in query:
                continue
            raws = query[key] if isinstance(query[key], list | tuple) else [query[key]]
            raw = raws[-1] if raws else ""
            text = raw.decode("utf-8", "replace") if isinstance(raw, bytes) else str(raw)
            read = self._read_choice if key in self.CHOICES else self._read_number
            value, notice = read(key, text)
            if value is not None:
                values[key] = value
            if notice:
                notices.append(notice)
        return values, notices

    def _read_choice(self, key: str, text: str) -> tuple[str | None, str]:
        label, allowed = self.param[key].label, SITES if key == "site" else RESTARTS
        shown = f"{label} ({key}) = “{clipped(text)}”"
        if text in allowed:
            return text, ""
        if key == "site" and text == UPLOADED:
            return None, f"{shown} ignored: a link cannot carry a file; upload it again."
        return None, f"{shown} ignored: it must be one of {', '.join(allowed)}."

    def _read_number(self, key: str, text: str) -> tuple[float | None, str]:
        return read_slider_number(self.param[key], key, text)
