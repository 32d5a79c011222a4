"""What a class reads after every move: the readout row (mean flow, volume, τ, …) and the status.

Panel 1.9.4's HTML-based panes re-send their stylesheets, as new objects, with every change of
their text: Bokeh then re-walks every model of the page and the browser restyles the pane (~40 ms
a slider move on the server for seven readouts and the status). These panes send their text
alone; a change of stylesheets or of an alert's type still goes through Panel's own path.
"""

from __future__ import annotations

import html
import math

import panel as pn

import windpump
from windpump import Status
from windpump.readers.quantities import format_quantity
from windpump.units import LITRES_PER_M3

from .styles import COMPACT, ZOOM_VARIABLE, keep_terms, keep_units, px

# Sizes follow the page's zoom (styles.px): presentation mode enlarges every tab's readouts, in
# the browser, with the rest of the page's text: the labels by a quarter (14 -> 17.5 px), the
# numbers a class reads from the back of the room by half (20 -> 30 px: 2 x zoom - 1).
READOUT_CSS = f"""
.readout {{border: 1px solid #bbb; border-radius: 6px; padding: 2px 10px; min-width: 120px}}
.readout .phone {{display: none}}
.readout .label {{font-size: {px(14)}; color: inherit; opacity: 0.85}}
.readout .value {{font-size: calc(20px * (2 * var({ZOOM_VARIABLE}, 1) - 1)); font-weight: bold}}
@media (max-width: 700px) {{
  :host {{margin: 2px 3px !important}}
  .readout {{min-width: 0; padding: 0 6px; line-height: 1.2}}
  .readout .value {{font-size: 16px}}
  .not-phone {{display: none}}
  .phone {{display: inline !important}}
  :host(.pair) {{flex: 1 1 40% !important; max-width: calc(50% - 8px) !important}}
}}
"""
# A readout of a long label (the Wind tab's) takes half a phone's row, its label wrapping: two a
# row rather than one.
PAIR = ["pair"]
# On a phone the readouts share the tabs' pane above the controls (page.NARROW_CSS) with the
# status and the crank speed's chart: tighter boxes (no padding above and below, the number at
# 16 px, the label at 14) put two or three in a row, and the three fit its first screen.
READOUTS = (
    "mean_flow", "volume", "tau", "margin", "peak_to_mean", "ripple", "efficiency", "energy",
    "tsr", "strokes", "cp", "max_head",
)  # fmt: skip
ROTOR_READOUTS = ("tsr", "strokes", "cp", "max_head")  # a wheel's: shown for a rotor design
TAU_LABEL, MARGIN_LABEL = "Spin-up time τ, Eq. (25)", "Stall margin, Eq. (22)"
STATUS_STYLE = {
    Status.RUNNING: "success",
    Status.SLOWING: "warning",
    Status.STALLED: "danger",
    Status.NEVER_STARTED: "warning",
}


def readout_html(label: str, value: str, name: str, tip: str = "") -> str:
    """A label over a value, whose lines break only between its terms (``keep_terms``: never
    between a number and its unit); ``data-name`` lets a test or a script find the value;
    ``tip``, if any, is the box's tooltip (what the numbers mean, in words)."""
    title = f' title="{html.escape(tip, quote=True)}"' if tip else ""
    return (
        f'<div class="readout"{title}><div class="label">{label}</div>'
        f'<div class="value" data-name="{name}">{keep_terms(value)}</div></div>'
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

    def show(self, label: str, value: str, tip: str = "") -> None:
        self.object = readout_html(label, value, self.readout_name, tip)


class Readouts(pn.viewable.Viewer):
    """The row of readouts (``readouts[name]``) and the status line under it."""

    def __init__(self, system: str = "si", **params):
        super().__init__(**params)
        self.system = system  # the units the readouts are shown in: "si" or "us"
        self.readouts = {name: Readout(name) for name in READOUTS}
        self.row = pn.FlexBox(*self.readouts.values(), sizing_mode="stretch_width")
        self.status = StatusAlert(
            "", alert_type="success", stylesheets=COMPACT, sizing_mode="stretch_width"
        )

    def __getitem__(self, name: str) -> Readout:
        return self.readouts[name]

    def show(self, seen: windpump.Exploration) -> None:
        """The run's readouts, then its verdict."""
        figures = seen.intermittency
        started = seen.status is not Status.NEVER_STARTED
        values = {
            "mean_flow": ("Mean flow", flow_text(seen.mean_flow, self.system)),
            "volume": ("Volume pumped", volume_text(seen.pumped_volume, self.system)),
            "tau": (TAU_LABEL, f"{seen.tau:.1f} s" if seen.tau and started else "–"),
            "margin": (MARGIN_LABEL, margin_text(seen.margin)),
            "peak_to_mean": ("Peak / mean flow", f"{figures.peak_to_mean:.2f}" if figures else "–"),
            "ripple": (
                "Speed ripple",
                html.escape(ripple_text(figures.speed_ripple)) if figures else "–",
            ),
            "efficiency": efficiency_readout(seen),
            "energy": energy_readout(seen),
        }
        # The ideal machine delivers what it sweeps: its efficiencies say little, and a projector's
        # first screen has no row to spare. (Others were hidden while the solver compiled:
        # show_averaged; each set once, as a change of it is sent to the page.)
        rotor = seen.design.rotor is not None
        if rotor:
            values.update(rotor_readouts(seen, self.system))
        tips = {"efficiency": EFFICIENCY_TIP, "max_head": MAX_HEAD_TIP}
        for name, readout in self.readouts.items():
            if name in values:
                label, value = values[name]
                readout.show(label, value, tips.get(name, ""))
            readout.visible = (name != "efficiency" or not seen.design.is_ideal) and (
                rotor or name not in ROTOR_READOUTS
            )
        self.status.object, self.status.alert_type = (
            keep_units(f"{status_text(seen)} {start_text(seen)}"),
            STATUS_STYLE[seen.status],
        )

    def show_averaged(self, design: windpump.Design) -> str:
        """While the solver compiles (a first start): the averaged theory's τ (Eq. 25) and stall
        margin (Eq. 22) for ``design``, which need no compiled code (~1 ms; 0.25 s for the deep
        well's real machine), and what it says in a sentence for the status. The full run's
        readouts (the mean flow first) stay empty until its part is ready: they are the page's
        sign that the integration has run. "" for a design the theory refuses."""
        try:
            margin = windpump.stall_margin(design)
            running = margin > 1.0
            alpha_plus = windpump.steady_speeds(design)[0] if running else None
            tau = windpump.time_constant(design) if running else None
        except (windpump.ParameterError, windpump.StallError, ArithmeticError):
            return ""  # its first run says why
        self.readouts["tau"].show(TAU_LABEL, f"{tau:.1f} s" if tau else "–")
        self.readouts["margin"].show(MARGIN_LABEL, margin_text(margin))
        for name, readout in self.readouts.items():  # an empty one's margins shift the row
            readout.visible = name in ("tau", "margin")
        if running:
            return keep_units(
                f"The averaged theory meanwhile: it settles at α₊ = {alpha_plus:.2f} rad/s on "
                f"the crank with τ = {tau:.1f} s (Eqs. 21, 25)."
            )
        return f"The averaged theory meanwhile: margin {margin:.3f} ≤ 1, it cannot carry the load."

    def mark_stale(self, styles: dict) -> None:
        self.row.styles = styles
        self.status.styles = styles

    def __panel__(self) -> pn.Column:
        return pn.Column(self.row, self.status, sizing_mode="stretch_width")


def margin_text(margin: float) -> str:
    """The stall margin (Eq. 22) as a class reads it: endless (the core's inf, a leak hole or no
    head: no load at rest) in words."""
    return "∞ (never stalls)" if math.isinf(margin) else f"{margin:.3f}"


def ripple_text(ripple: float) -> str:
    """The speed ripple (max - min) / mean [-] as a percentage, to what a reader can use of it:
    two significant figures (whole percent from 10 %), and below 0.1 % only that it is so, no
    wider than a number (the crank turns steadily; the paper's example read "0.010 %", three
    decimals of nothing; "below 0.1 %" wrapped a projector's readouts onto a third row).

    >>> ripple_text(0.0001049), ripple_text(0.001234), ripple_text(0.01234), ripple_text(0.1567)
    ('< 0.1 %', '0.12 %', '1.2 %', '16 %')
    >>> ripple_text(12.34), ripple_text(0.0)
    ('1,234 %', '0 %')
    """
    value = 100.0 * ripple
    if value == 0.0:
        return "0 %"
    if value < 0.1:
        return "< 0.1 %"  # escaped where shown: the readout is HTML
    if value >= 10.0:
        return f"{value:,.0f} %"
    decimals = 1 - math.floor(math.log10(value))  # two significant figures
    return f"{value:.{decimals}f} %"


# Why the overall efficiency can stand above the volumetric one with a leak hole (the docs' model,
# Energy): the tooltip of the readout that shows both.
EFFICIENCY_TIP = (
    "Volumetric: water delivered over the volume the pistons swept. Overall: the lifted water's "
    "energy ρ_w g h V over the work spent on the water (the windmill's work less the kinetic and "
    "potential energy stored). With a leak hole the overall can be the higher: water that slips "
    "back through the hole while a piston moves slowly (near its dead centres) was pushed at a "
    "pressure below the head's, so the leak costs less work per litre than lifting does."
)


def percent(value: float) -> str:
    return f"{100 * value:.1f} %" if value == value else "–"  # (NaN: nothing swept, no work)


def efficiency_readout(seen: windpump.Exploration) -> tuple[str, str]:
    """Delivered over swept volume, and lifted water's energy over the windmill's work."""
    volumetric, overall = seen.volumetric_efficiency, seen.overall_efficiency
    return "Efficiency: volumetric, overall", f"{percent(volumetric)}, {percent(overall)}"


def shown_joules(left: list[float], right: list[float]) -> tuple[list[int], list[int]]:
    """Whole joules for the two sides of an energy balance, ``sum(left) = sum(right)``, that add
    up as shown: the left's terms rounded each, the right's each rounded down or up (within 1 J
    of its value), the ones with the largest fractions up, so that their sum is the left's
    ("22 J + 122 J = 143 J" had each term rounded on its own). Where no such choice exists (a
    balance off by a joule or more) each term is rounded on its own, as it is."""
    shown_left = [round(v) for v in left]
    floors = [math.floor(v) for v in right]
    need = sum(shown_left) - sum(floors)
    if not 0 <= need <= len(right):
        return shown_left, [round(v) for v in right]
    by_fraction = sorted(range(len(right)), key=lambda i: floors[i] - right[i])
    shown_right = [f + (i in by_fraction[:need]) for i, f in enumerate(floors)]
    return shown_left, shown_right


def shown_totals(totals: windpump.EnergyTotals) -> dict[str, int]:
    """The run's energy terms in whole joules as the page shows them, in the readout and in the
    Losses view alike: shaft, transmission, friction, leak, spin (gained if positive, given back
    if negative) and water, adding up as shown (``shown_joules``)."""
    spin = totals.kinetic + totals.potential
    losses = [totals.transmission, totals.friction, totals.leak]
    if spin >= 0:
        (work,), (*lost, gained, water) = shown_joules(
            [totals.shaft], [*losses, spin, totals.water]
        )
    else:
        (work, back), (*lost, water) = shown_joules([totals.shaft, -spin], [*losses, totals.water])
        gained = -back
    names = ("transmission", "friction", "leak")
    return {"shaft": work, **dict(zip(names, lost, strict=True)), "spin": gained, "water": water}


def energy_readout(seen: windpump.Exploration) -> tuple[str, str]:
    """The run's energy balance in words that keep the sign: a slowing rotor gives energy back.
    The real machine's losses (chain, rising main, leak) are one term when there are any. The
    shown terms add up to the shown sum (``shown_totals``)."""
    shown = shown_totals(seen.energy_totals)
    spin = shown["spin"]
    left = [shown["shaft"], *([] if spin >= 0 else [-spin])]
    lost = (
        [] if seen.design.is_ideal else [shown["transmission"] + shown["friction"] + shown["leak"]]
    )
    right = [*lost, *([spin] if spin >= 0 else []), shown["water"]]
    words = " = ".join(" + ".join(f"{v:,} J" for v in side) for side in (left, right))
    gained = "gained speed + " if spin >= 0 else ""
    back = "" if spin >= 0 else " + speed given back"
    losses = "" if seen.design.is_ideal else "losses + "
    # "Work" on a phone: the label keeps one line there (page.NARROW_CSS: the first screen)
    work = '<span class="not-phone">Windmill\'s work</span><span class="phone">Work</span>'
    return f"{work}{back} = {losses}{gained}lifted water", words


def running_tsr(design: windpump.Design, omega: float) -> float:
    """A rotor design's tip-speed ratio λ = ω r / V_s [-] at its windmill's speed ``omega``
    [rad/s] in its wind V_ref (V_s: the wind the wheel turns in, capped where it furls); NaN
    where it does not run (``omega`` None or NaN)."""
    rotor = design.rotor
    if rotor is None or omega is None or math.isnan(omega):
        return math.nan
    return float(rotor.tip_speed_ratio(omega, design.V_ref))


MAX_HEAD_TIP = (
    "The largest head at which it keeps running in this steady wind (its stall margin falls to "
    "1), and the largest at which it starts on its own from rest at any crank angle "
    "(windpump.max_head). A catalogue's maximum lift is a rating well below both: the "
    "documentation's validation page sets them side by side."
)


def wind_text(V: float, system: str) -> str:
    """A wind [m/s] as a readout's label says it: 6.71 m/s, or in US units 15 mph.

    >>> wind_text(6.7056, "si"), wind_text(6.7056, "us")
    ('6.71 m/s', '15 mph')
    """
    return format_quantity(V, "wind speed", system, digits=3)


def flow_text(flow: float, system: str) -> str:
    """A mean flow [m^3/s] as the readout shows it: L/s to four decimals, or in US units gallons
    a minute (as a US pump's or well's flow is written) and an hour (as a windmill catalogue
    rates its capacity), each to three significant figures (``windpump.readers.quantities``).

    >>> flow_text(1.68e-4, "us"), flow_text(1.68e-4, "si")
    ('2.66 gpm · 160 gal/h', '0.1680 L/s')
    """
    if system == "us":
        per_minute = format_quantity(flow, "flow per minute", "us", digits=3)
        return f"{per_minute} · {format_quantity(flow, 'flow', 'us', digits=3)}"
    return f"{LITRES_PER_M3 * flow:.4f} L/s"


def volume_text(volume: float, system: str) -> str:
    """A volume [m^3] as the readout shows it: litres to a decimal, or US gallons."""
    if system == "us":
        return format_quantity(volume, "volume", "us", digits=4)
    return f"{LITRES_PER_M3 * volume:.1f} L"


def head_text(head: float, system: str) -> str:
    """A head [m] as the readout shows it (∞: none stops it), in m or, in US units, ft."""
    return "∞" if math.isinf(head) else format_quantity(head, "head", system, digits=4)


def rotor_readouts(seen: windpump.Exploration, system: str = "si") -> dict[str, tuple[str, str]]:
    """A rotor design's readouts where it runs (the averaged running speed α₊: the windmill at
    ω = R† α₊): its tip-speed ratio λ, the pump's strokes a minute, the wheel's power coefficient
    C_P there; and its maximum heads running and starting in its wind (``windpump.max_head``)."""
    design, op = seen.design, seen.operating_point
    tsr = running_tsr(design, op.omega if op is not None else None)
    running = op is not None and math.isfinite(tsr)
    strokes = f"{op.crank_speed * 60.0 / (2.0 * math.pi):.1f} /min" if running else "–"
    cp = f"{float(design.rotor.cp(tsr)):.3f}" if running else "–"
    heads = [windpump.max_head(design), windpump.max_head(design, start=True)]
    shown = ", ".join(head_text(h, system) for h in heads)
    return {
        "tsr": ("Tip-speed ratio λ", f"{tsr:.2f}" if running else "–"),
        "strokes": ("Strokes a minute", strokes),
        "cp": ("C_P where it runs", cp),
        "max_head": (f"Max head in {wind_text(design.V_ref, system)}: running, starting", shown),
    }


def start_text(seen: windpump.Exploration) -> str:
    """Whether the rotor starts on its own: R+ T_0 against the largest load on the crank."""
    d = seen.design
    if d.T_0 == 0.0:
        return "From rest it needs a kick (no torque at rest, T₀ = 0)."
    at_rest = d.rest_torque_on_crank
    peak = windpump.peak_load_torque(d)
    if seen.starts_from_rest and peak == 0.0:  # a leak hole, no reciprocating weight
        return (
            f"It starts on its own from any angle (its torque at rest on the crank "
            f"R†T₀ = {at_rest:.2f} N·m; at rest the water "
            "slips back through the leak hole and the piston carries no load)."
        )
    if seen.starts_from_rest:
        return (
            f"It starts on its own from any angle (its torque at rest on the crank "
            f"R†T₀ = {at_rest:.2f} N·m > peak load {peak:.2f} N·m)."
        )
    return (
        f"It does not start on its own from every angle (its torque at rest on the crank "
        f"R†T₀ = {at_rest:.2f} N·m ≤ peak load {peak:.2f} N·m)."
    )


def status_text(seen: windpump.Exploration) -> str:
    run = seen.run
    if seen.status is Status.RUNNING:
        return (
            f"**Running.** It settles at α₊ = {seen.alpha_plus:.2f} rad/s on the crank "
            f"(windmill {seen.operating_point.omega:.1f} rad/s) with τ = {seen.tau:.1f} s."
        )
    if seen.status is Status.SLOWING:
        when = seen.averaged_t_stall
        return (
            f"**Slowing to a stall.** Margin {seen.margin:.3f} ≤ 1: the windmill cannot carry the "
            f"load; the averaged theory stalls at {when:.0f} s."
            if when
            else "**Slowing to a stall.**"
        )
    if seen.status is Status.STALLED:
        return f"**Stalled** at t = {run.t_stall:.2f} s (stall margin {seen.margin:.3f})."
    if seen.not_started is windpump.NotStarted.NO_KICK:
        return "**Never started.** With no kick (θ̇₀ = 0) this windmill has no torque at rest: give it a kick."
    if seen.not_started is windpump.NotStarted.HELD_AT_REST:
        return "**Never started.** From rest, the torque at rest cannot beat the load at θ₀: give it a kick or raise T₀."
    need = (
        f"α₋ = {seen.alpha_minus:.2f} rad/s" if seen.alpha_minus is not None else "a running margin"
    )
    return (
        f"**Never started.** The kick θ̇₀ = {seen.theta_dot0:.2f} rad/s is below {need}: "
        f"it came to rest at t = {run.t_stall:.2f} s."
    )
