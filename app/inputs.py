"""What a student sets: the pump's inputs as a ``param.Parameterized``, presets, and the link's query.

The parameter names are the core's (``L_over_R``, ``R_dagger``, ``h`` ...): they are also the
URL's query keys, so a link reproduces the design and the run on the screen.
"""

from __future__ import annotations

import math
from urllib.parse import urlencode

import param

import windpump
from windpump.catalogue import aermotor_702
from windpump.catalogue.aermotor import CYLINDERS, WHEELS_FT
from windpump.units import M_S_PER_MPH, METRES_PER_FOOT, MM_PER_M

from .escape import as_text

SEED = windpump.Design.seed_example()
SEED_MARGIN = windpump.stall_margin(SEED)

# name: (display format, where its slider sits: the sidebar's "main" list, its "more" card, its
# "real" card (the real machine's losses) or the Wind tab)
FORMATS = {
    "L_over_R": ("0.00", "main"),
    "R_dagger": ("0.0", "main"),
    "h": ("0.0", "main"),
    "diameter": ("0.0", "windmill"),
    "T_m": ("0.00", "main"),
    "omega_m": ("0", "more"),
    "t_end": ("0", "more"),
    "theta_dot0": ("0.0", "more"),
    "theta0": ("0.00", "more"),
    "I0": ("0.00", "more"),
    "I1": ("0.0000", "more"),
    "cylinders": ("0", "main"),
    "T_0": ("0.00", "more"),
    "m_r": ("0.0", "real"),
    "eta_t": ("0.00", "real"),
    "L_main": ("0", "real"),
    "D_main_mm": ("0", "real"),
    "f_main": ("0.000", "real"),
    "d_leak_mm": ("0.0", "real"),
    "Cd_leak": ("0.00", "real"),
    "V": ("0.0", "wind"),
    "mean_wind": ("0.0", "wind"),
    "k": ("0.0", "wind"),
    "time_scale": ("0", "wind"),
    "seed": ("0", "wind"),
}

# The real machine's inputs (windpump.model.design.REAL_MACHINE, diameters in mm): the ideal machine's
# values by default.
REAL_MACHINE_INPUTS = tuple(name for name, (_f, place) in FORMATS.items() if place == "real")

# Switches (check boxes), by name; in the link as true/false.
SWITCHES = ("double_acting",)

# The windmill: the paper's curve, a multiblade wheel of the diameter slider, or an Aermotor 702
# of the catalogue's sizes (``windpump.catalogue``); in the link as ``windmill=``.
WINDMILLS = {
    "eq11": "The paper's curve (Eq. 11)",
    "multiblade": "A multiblade wheel",
    "aermotor": "An Aermotor 702",
}
# The Aermotor's sizes as the catalogue prints them: wheels [ft], cylinders [in] ("1 7/8"),
# strokes; in the link as their numbers (``wheel_ft=8``, ``cylinder_in=1.875``, ``stroke=long``).
CYLINDER_LABELS = {inches: label for label, inches in CYLINDERS.items()}
STROKES = {"long": "Long", "short": "Short"}
# Choices (select boxes), by name: their values as the link writes them.
CHOICES = ("windmill", "wheel_ft", "cylinder_in", "stroke")
# The inputs each windmill uses beside the pump's: the others are set by the windmill, and their
# sliders say so (sidebar.Sidebar).
WINDMILL_INPUTS = {
    "eq11": (),
    "multiblade": ("diameter",),
    "aermotor": ("wheel_ft", "cylinder_in", "stroke"),
}
# The sliders a windmill sets itself: a rotor's curve sets Tₘ, ωₘ and T₀; the Aermotor's catalogue
# also its back gear (R₁/R₀) and its wheel's and crank's inertias.
SET_BY = {
    "eq11": (),
    "multiblade": ("T_m", "omega_m", "T_0"),
    "aermotor": ("T_m", "omega_m", "T_0", "R_dagger", "I0", "I1"),
}


class PumpInputs(param.Parameterized):
    """The design and the run the explorer shows; defaults are the paper's example (Fig. 3)."""

    L_over_R = param.Number(SEED.L_over_R, bounds=(1.0, 10.0), step=0.05, label="L/R, rod / crank")
    R_dagger = param.Number(
        SEED.R_dagger, bounds=(0.5, 10.0), step=0.1, label="R₁/R₀, sprocket ratio"
    )
    h = param.Number(SEED.h, bounds=(0.0, 300.0), step=0.1, label="Head h [m]")
    windmill = param.Selector(objects=list(WINDMILLS), default="eq11", label="Windmill")
    diameter = param.Number(
        2.4, bounds=(1.5, 6.0), step=0.1, label="Wheel diameter D [m] (8 ft = 2.4 m)"
    )
    wheel_ft = param.Selector(objects=list(WHEELS_FT), default=8, label="Wheel [ft]")
    cylinder_in = param.Selector(
        objects=list(CYLINDERS.values()), default=1.875, label="Cylinder bore [in]"
    )
    stroke = param.Selector(objects=list(STROKES), default="long", label="Stroke")
    T_m = param.Number(SEED.T_m, bounds=(0.05, 5.0), step=0.05, label="Peak torque Tₘ [N·m]")
    omega_m = param.Number(
        SEED.omega_m, bounds=(5.0, 150.0), step=1.0, label="Windmill peak speed ωₘ [rad/s]"
    )
    t_end = param.Number(600.0, bounds=(10.0, 3000.0), step=10.0, label="Duration t_end [s]")
    theta_dot0 = param.Number(3.0, bounds=(0.0, 30.0), step=0.1, label="Kick θ̇₀ [rad/s]")
    theta0 = param.Number(
        math.pi / 2, bounds=(0.0, round(2 * math.pi, 2)), step=0.01, label="Start angle θ₀ [rad]"
    )
    I0 = param.Number(SEED.I0, bounds=(0.01, 10.0), step=0.01, label="Rotor inertia I₀ [kg·m²]")
    I1 = param.Number(SEED.I1, bounds=(0.0005, 1.0), step=0.0005, label="Crank inertia I₁ [kg·m²]")
    cylinders = param.Number(1, bounds=(1, 6), step=1, label="Cylinders n (phase lag 2π/n)")
    T_0 = param.Number(0.0, bounds=(0.0, 4.95), step=0.05, label="Torque at rest T₀ [N·m]")
    double_acting = param.Boolean(False, label="Double-acting pistons (both faces deliver)")
    # The real machine (Design.REAL_MACHINE), the ideal machine by default; diameters in mm
    m_r = param.Number(SEED.m_r, bounds=(0.0, 50.0), step=0.5, label="Rod and piston mass mᵣ [kg]")
    eta_t = param.Number(
        SEED.eta_t, bounds=(0.1, 1.0), step=0.01, label="Chain drive efficiency ηₜ"
    )
    L_main = param.Number(
        SEED.L_main, bounds=(0.0, 100.0), step=1.0, label="Rising main length [m]"
    )
    D_main_mm = param.Number(
        SEED.D_main * MM_PER_M, bounds=(5.0, 100.0), step=1.0, label="Rising main diameter [mm]"
    )
    f_main = param.Number(
        SEED.f_main, bounds=(0.0, 0.2), step=0.005, label="Rising main friction factor f"
    )
    d_leak_mm = param.Number(
        SEED.d_leak * MM_PER_M, bounds=(0.0, 40.0), step=0.1, label="Leak hole diameter [mm]"
    )
    Cd_leak = param.Number(
        SEED.Cd_leak, bounds=(0.05, 1.0), step=0.01, label="Leak discharge coefficient"
    )
    V = param.Number(
        SEED.V_ref, bounds=(0.5, 20.0), step=0.1, label="Steady wind V [m/s] (Tₘ, ωₘ, T₀ at 5 m/s)"
    )
    mean_wind = param.Number(5.0, bounds=(1.0, 12.0), step=0.1, label="Site's mean wind [m/s]")
    k = param.Number(2.0, bounds=(1.2, 4.0), step=0.1, label="Weibull shape k (2: Rayleigh)")
    time_scale = param.Number(60.0, bounds=(5.0, 3600.0), step=5.0, label="Gusts' time scale [s]")
    seed = param.Number(1, bounds=(0, 999), step=1, label="Gusty day number (seed)")

    def names(self) -> list[str]:
        return [*FORMATS, *SWITCHES, *CHOICES]

    def values(self) -> dict[str, float | bool]:
        return {name: getattr(self, name) for name in self.names()}

    def design(self) -> windpump.Design:
        """The design these inputs describe: the paper's example with its radii R and R0 kept,
        in the steady wind V (its curve's T_m, omega_m and T_0 are given at V_ref = 5 m/s)."""
        return self.design_at_v_ref().in_wind(self.V)

    def design_at_v_ref(self) -> windpump.Design:
        """The design with its windmill as the inputs give it, at V_ref (for a wind record): the
        paper's curve (Eq. 11) of the Tₘ, ωₘ and T₀ sliders; a multiblade wheel of the diameter
        slider (``Rotor.multiblade``) on the sliders' pump; or an Aermotor 702 of the catalogue's
        wheel, cylinder and stroke (``windpump.catalogue.aermotor_702``: its back gear, stroke,
        bore and inertias) lifting by the head h."""
        pump = {
            "L_over_R": self.L_over_R,
            "cylinders": round(self.cylinders),
            "double_acting": self.double_acting,
            **self.real_machine(),
        }
        if self.windmill == "aermotor":
            mill = aermotor_702(
                self.wheel_ft, self.cylinder_in, stroke=self.stroke, lift_ft=0.0,
                V_ref=SEED.V_ref, **pump,
            )  # fmt: skip
            return mill.replace(h=self.h)
        pump.update(R_dagger=self.R_dagger, h=self.h, I0=self.I0, I1=self.I1)
        if self.windmill == "multiblade":
            return SEED.with_ratios(**pump).replace(rotor=windpump.Rotor.multiblade(self.diameter))
        return SEED.with_ratios(**pump, T_m=self.T_m, omega_m=self.omega_m, T_0=self.T_0)

    def real_machine(self) -> dict[str, float]:
        """The real machine's Design fields these inputs give [SI units: the mm shown in m]."""
        return {
            "m_r": self.m_r,
            "eta_t": self.eta_t,
            "L_main": self.L_main,
            "D_main": self.D_main_mm / MM_PER_M,
            "f_main": self.f_main,
            "d_leak": self.d_leak_mm / MM_PER_M,
            "Cd_leak": self.Cd_leak,
        }

    def defaults(self) -> dict[str, float | bool]:
        return {name: self.param[name].default for name in self.names()}

    def query(self) -> str:
        """The URL query of the current inputs: only those that differ from their defaults, each
        written as its slider shows it (``h=3.1``, ``cylinders=2``, ``double_acting=true``), or in
        full if its slider's grid cannot show it (a fit's ``T_m=0.5819912``: ``link_text``)."""
        return urlencode(
            {
                name: link_text(name, value)
                for name, value in self.values().items()
                if not self.is_default(name, value)
            }
        )

    def is_default(self, name: str, value: float | bool | str) -> bool:
        """Whether ``value`` is input ``name``'s default, but for the float noise of a slider
        moved in the browser (3 + 0.1 - 0.1 = 3.0000000000000004)."""
        default = self.param[name].default
        if name in CHOICES or isinstance(value, bool) or isinstance(default, bool):
            return value == default
        return abs(value - default) <= 1e-9 * self.param[name].step

    def parse_query(self, query: dict) -> tuple[dict[str, float], list[str]]:
        """Values to apply from a URL query (str or bytes values, lists as Tornado gives them),
        and a notice for each key ignored (unknown, not a number, out of its range, a count that
        is not whole) or given twice (the last is used)."""
        values, notices = {}, []
        for key, raws in query.items():
            raws = list(raws) if isinstance(raws, list | tuple) else [raws]
            texts = [_decoded(raw) for raw in raws] or [""]
            text = texts[-1]
            if len(texts) > 1 and (key in FORMATS or key in SWITCHES or key in CHOICES):
                given = ", ".join(clipped(t) for t in texts[:5]) + (", …" if len(texts) > 5 else "")
                notices.append(
                    f"“{clipped(key)}” is given {len(texts)} times ({given}): the last, "
                    f"“{clipped(text)}”, is used."
                )
            if key in SWITCHES:
                if text.lower() in ("true", "false"):
                    values[key] = text.lower() == "true"
                else:
                    label = self.param[key].label
                    notices.append(
                        f"{label} ({key}) = “{clipped(text)}” ignored: it must be true or false."
                    )
                continue
            if key in CHOICES:
                choice, notice = read_choice(self.param[key], key, text)
                if notice:
                    notices.append(notice)
                else:
                    values[key] = choice
                continue
            if key not in FORMATS:
                if key not in IGNORED_QUERY_KEYS:
                    notices.append(f"“{clipped(key)}” is not a parameter of this page; ignored.")
                continue
            value, notice = self._read_number(key, text)
            if value is not None:
                values[key] = value
            if notice:
                notices.append(notice)
        return values, notices

    def _read_number(self, key: str, text: str) -> tuple[float | None, str]:
        """A link's number for slider ``key`` (None if refused), and what to tell the student
        about it ("" if nothing)."""
        return read_slider_number(self.param[key], key, text, whole=key in COUNTS)


def read_slider_number(
    parameter: param.Number, key: str, text: str, *, whole: bool = False
) -> tuple[float | None, str]:
    """A link's ``key=text`` for a slider's ``parameter``: the value (None if refused) and what to
    tell the student ("" if nothing).

    A value in the slider's range is taken exactly (float noise on its grid aside), on the grid or
    off it: the page writes what it holds in full (``grid_text``), so its own link reads back to
    the same design, and a hand-typed ``h=3.14159`` is the head the student asked for (the slider
    sits at it, its label rounded to the slider's decimals)."""
    low, high = parameter.bounds
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    shown = f"{parameter.label} ({key}) = “{clipped(text)}”"
    if not (math.isfinite(value) and low <= value <= high):
        return None, f"{shown} ignored: it must be a number from {low:g} to {high:g}."
    if whole and value != round(value):
        return None, f"{shown} ignored: it must be a whole number from {low:g} to {high:g}."
    snapped = on_grid(value, parameter.step)
    if math.isclose(snapped, value, rel_tol=1e-9, abs_tol=1e-12):  # float noise: 3.0999999999999996
        return snapped, ""
    # Off the grid (a fit, an uploaded design, θ₀ = π/2, a hand-typed 3.14159): taken exactly, as
    # the page writes it (``grid_text``), so a link reopens the readouts it was copied from.
    return value, ""


def read_choice(parameter: param.Selector, key: str, text: str) -> tuple[object, str]:
    """A link's ``key=text`` for a select box's ``parameter``: the choice (as the link writes it,
    ``choice_text``) and what to tell the student ("" if nothing)."""
    for choice in parameter.objects:
        if choice_text(choice) == text:
            return choice, ""
    allowed = ", ".join(choice_text(choice) for choice in parameter.objects)
    return None, f"{parameter.label} ({key}) = “{clipped(text)}” ignored: one of {allowed}."


def choice_text(choice: object) -> str:
    """A select box's choice as the link writes it: ``multiblade``, ``8``, ``1.875``, ``long``."""
    return f"{choice:g}" if isinstance(choice, float) else str(choice)


def step_decimals(step: float) -> int:
    """Decimals a slider's step needs: 0.05 -> 2, 0.0005 -> 4, 10.0 -> 0."""
    return len(f"{step:.10f}".rstrip("0").split(".")[1])


def on_grid(value: float, step: float) -> float:
    """``value`` on a slider's grid (multiples of ``step``, as every slider here starts on one),
    to the step's decimals: noise such as 3.0999999999999996 becomes 3.1."""
    return round(round(value / step) * step, step_decimals(step))


def link_text(name: str, value: float | bool | str) -> str:
    """A value as the link carries it: as its slider shows it if it is on the slider's grid
    (``3.1``, ``0.8``, ``2``, ``true``), else in full (``grid_text``); a choice as
    ``choice_text`` writes it (``aermotor``, ``1.875``)."""
    if name in CHOICES:
        return choice_text(value)
    if isinstance(value, bool):
        return str(value).lower()
    return grid_text(value, PumpInputs.param[name].step)


def grid_text(value: float, step: float) -> str:
    """``value`` for a link: to ``step``'s decimals without trailing zeros if it is on the grid
    of multiples of ``step`` (float noise aside), else its shortest text that reads back to the
    same float (``repr``): a fitted Tₘ = 0.5819912 is not written 0.58.

    >>> grid_text(3.0999999999999996, 0.1), grid_text(0.5819912, 0.05), grid_text(99.0, 5.0)
    ('3.1', '0.5819912', '99')
    """
    value = float(value)
    snapped = on_grid(value, step)
    if not math.isclose(snapped, value, rel_tol=1e-9, abs_tol=1e-12):
        text = repr(value)
        return text.removesuffix(".0")  # 99, not 99.0 (time_scale's step is 5)
    text = f"{snapped:.{step_decimals(step)}f}"
    text = text.rstrip("0").rstrip(".") if "." in text else text
    return "0" if text == "-0" else text


def clipped(text: str, limit: int = 40) -> str:
    """A key or value echoed in a notice (from a link or a file), cut to ``limit`` characters (a
    link may be long) and shown as text, never as markup (``escape.as_text``)."""
    return as_text(text if len(text) <= limit else text[: limit - 1] + "…")


def _decoded(raw) -> str:
    return raw.decode("utf-8", "replace") if isinstance(raw, bytes) else str(raw)


# Sliders that count things: a link's value must be a whole number.
COUNTS = ("cylinders", "seed")

# Keys the page itself uses, not inputs.
IGNORED_QUERY_KEYS = {
    "theme", "resolution", "preset", "presentation", "tab", "restored", "units", "embed",
}  # fmt: skip

# name: (values, one sentence saying what to look at). A name fits the sidebar's select box in
# presentation mode's text (~26 characters: a select shows its choice on one line and cuts it at
# its edge; tests/browser/test_layout.py measures them).
PRESETS = {
    "The paper's example": (
        {},
        "Kicked at 3 rad/s, the pump spins up over τ ≈ 79 s to α₊ and pulses once per revolution "
        "(the paper's Fig. 3).",
    ),
    "Near the stall boundary": (
        {"h": round(SEED.h * SEED_MARGIN / 1.05, 1), "theta_dot0": 12.0},
        "Stall margin ≈ 1.05: α₋ and α₊ close in, the spin-up is slow, and the ripple shows how "
        "thin the margin is.",
    ),
    "Kicked below α₋": (
        {"theta_dot0": 1.0},
        "A kick below the unstable speed α₋: the windmill cannot overcome the load and the pump "
        "comes to rest: it never starts.",
    ),
    "A light rotor, large ripple": (
        {
            "I0": round(SEED.I0 / 100, 2),
            "I1": 0.0005,
            "h": 6.0,
            "t_end": 60.0,
            "theta0": 0.3,
            "theta_dot0": 5.0,
        },
        "With a hundredth of the inertia the crank speed swings within every revolution: the "
        "averaged theory (Eq. 24) smooths over what the full Eq. (12) shows.",
    ),
    "2 cylinders, torque at rest": (
        {"cylinders": 2.0, "T_0": 0.4, "theta_dot0": 0.0},
        "Two cylinders half a turn apart and a windmill with torque at rest: that torque on the "
        "crank, R†T₀, beats the load "
        "at every angle, so it starts from rest with no kick, and the flow pulses twice a turn.",
    ),
    "A double-acting pump": (
        {"double_acting": True, "h": 1.5},
        "Both faces of the piston deliver: the flow pulses twice per revolution, never stops, and "
        "the load doubles (the margin halves at the same head).",
    ),
    "A deep well, a heavy rod": (
        {
            "h": 25.0,
            "T_m": 2.5,
            "theta_dot0": 6.0,
            "m_r": 15.0,
            "eta_t": 0.8,
            "L_main": 30.0,
            "D_main_mm": 25.0,
        },
        "Water lifted 25 m by a 15 kg steel pump rod through a 30 m rising main of 25 mm, the chain "
        "losing a fifth of the windmill's work: the rotor needs four times the paper's torque "
        "(Tₘ = 2.5 N·m) and a 6 rad/s kick, and the pipe's friction adds up to 5 m of head at the "
        "peak of each stroke.",
    ),
    "A leak hole lets it start": (
        {"T_0": 0.25, "theta0": 4.71, "theta_dot0": 0.0, "d_leak_mm": 3.0},
        "From rest at mid-stroke the windmill's torque at rest on the crank, R†T₀ = 1 N·m, is less "
        "than the tight piston's load "
        "(1.48 N·m): with the leak hole set to 0 the pump never moves. Through a 3 mm hole the "
        "water slips back at rest, the load vanishes and the pump starts on its own; at speed the "
        "hole costs about 4 % of the water (over this run, slow while it spins up, about 6 %: the "
        "volumetric efficiency).",
    ),
    "8-ft Aermotor, 175-ft well": (
        {
            "windmill": "aermotor",
            "h": 175 * METRES_PER_FOOT,
            "V": 15 * M_S_PER_MPH,
            "theta_dot0": 0.0,
            "t_end": 120.0,
        },
        "The catalogue's 8-ft mill on a 1 7/8 in cylinder at its table's 175 ft lift, in a 15 mph "
        "wind: its wheel's torque at rest starts it with no kick, and within seconds it settles "
        "at some 28 strokes a minute and about 160 gal/h (the table says 180), lightly loaded: "
        "at λ ≈ 1.8, past the C_P peak near λ = 1 that a heavier load would bring it to.",
    ),
    "A stalled pump": (
        {"h": 21.0},
        "At h = 21 m the stall margin is below 1 (Eq. 22): the windmill cannot carry the load and "
        "the pump slows to a stop. The close-up shows its last turns.",
    ),
}

FROM_THE_LINK = "Your design, from the link."  # a link's design that is no preset's


def preset_of(inputs: PumpInputs) -> str | None:
    """The preset whose design ``inputs`` hold, as the link carries it (each value as its slider
    shows it); None if none is."""
    defaults = inputs.defaults()
    shown = {name: link_text(name, value) for name, value in inputs.values().items()}
    for name, (values, _sentence) in PRESETS.items():
        preset = {**defaults, **values}
        if all(link_text(key, value) == shown[key] for key, value in preset.items()):
            return name
    return None
