"""`vibrissa whisker ...`: inspect and exercise the simulated whisker.

Commands
--------
``presets``
    The built-in whisker presets and all their parameters.
``info``
    Geometry, material, natural frequencies, damping and Hall gain of a whisker.
``static``
    Static equilibrium under a point force.
``push``
    Quasi-static push of a thin pole through the whisker.
``ring``
    Ring-down after releasing a deflected tip; measured frequency and damping.
``whisk``
    Whisk the whisker (its follicle housing turned by the whisking pattern
    generator), in air or into a pole, with or without RCP feedback.

Every command that takes a whisker accepts the same geometry options
(``--preset`` and/or explicit ``--length-mm`` ... ``--damping-ratio``), plus
``--n-elements`` and ``--rigid-follicle``; see :func:`build_geometry`.
"""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
import typer

from vibrissa._validate import finite, in_range, non_negative, positive
from vibrissa.cli._common import (
    echo_json,
    option_renamer,
    print_table,
    solver_limits,
    user_errors,
)

DEFAULT_PRESET = "xy-robot"

#: Geometry fields settable from the command line, with their option names.
GEOMETRY_OPTIONS: dict[str, str] = {
    "length_mm": "--length-mm",
    "base_radius_mm": "--base-radius-mm",
    "tip_radius_mm": "--tip-radius-mm",
    "youngs_modulus_gpa": "--youngs-modulus-gpa",
    "density_kg_m3": "--density-kg-m3",
    "damping_ratio": "--damping-ratio",
}

whisker_app = typer.Typer(
    help="Inspect and exercise the simulated whisker: presets, parameters and natural "
    "frequencies, static bending, pole pushes and ring-down.\n\n"
    "A whisker is chosen with --preset NAME and/or the explicit geometry options "
    "(--length-mm, --base-radius-mm, --tip-radius-mm, --youngs-modulus-gpa, "
    "--density-kg-m3, --damping-ratio); unspecified values come from the preset "
    "(default xy-robot). The follicle's stiffness, depth and inertia always come from "
    "the preset.",
    no_args_is_help=True,
)

# --------------------------------------------------------------------------- options
PresetOpt = Annotated[
    str | None,
    typer.Option(
        "--preset",
        help="Whisker preset (see `vibrissa whisker presets`); default xy-robot. "
        "Explicit geometry options override its values.",
        rich_help_panel="Whisker",
    ),
]
LengthOpt = Annotated[
    float | None,
    typer.Option("--length-mm", help="Free length, base to tip (mm).", rich_help_panel="Whisker"),
]
BaseRadiusOpt = Annotated[
    float | None,
    typer.Option("--base-radius-mm", help="Radius at the base (mm).", rich_help_panel="Whisker"),
]
TipRadiusOpt = Annotated[
    float | None,
    typer.Option(
        "--tip-radius-mm",
        help="Radius at the tip (mm), at most the base radius (linear taper).",
        rich_help_panel="Whisker",
    ),
]
ModulusOpt = Annotated[
    float | None,
    typer.Option(
        "--youngs-modulus-gpa",
        help="Young's modulus of the shaft (GPa).",
        rich_help_panel="Whisker",
    ),
]
DensityOpt = Annotated[
    float | None,
    typer.Option(
        "--density-kg-m3", help="Density of the shaft (kg/m^3).", rich_help_panel="Whisker"
    ),
]
DampingOpt = Annotated[
    float | None,
    typer.Option(
        "--damping-ratio",
        help="Damping ratio of the first bending mode, in [0, 0.5] (dimensionless).",
        rich_help_panel="Whisker",
    ),
]
NElementsOpt = Annotated[
    int | None,
    typer.Option(
        "--n-elements",
        help="Elements along the free shaft, 4-400 (default: the model's default).",
        rich_help_panel="Whisker",
    ),
]
RigidOpt = Annotated[
    bool,
    typer.Option(
        "--rigid-follicle",
        help="Clamp the base: the follicle (and magnet) cannot rotate.",
        rich_help_panel="Whisker",
    ),
]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON instead of text.")]


# --------------------------------------------------------------------------- helpers
def _renamer(extra: dict[str, str] | None = None) -> Any:
    """Rewrites the model's parameter names in a message as option names.

    Always the geometry's (``length_mm`` -> ``--length-mm`` ...), plus ``extra``.
    """
    return option_renamer({**GEOMETRY_OPTIONS, **(extra or {})})


_option_names = _renamer()
#: What to change when a command's whisker (geometry and material) is out of reach.
_STIFFER = "or a stiffer, thicker whisker (--youngs-modulus-gpa, --base-radius-mm)"


def build_geometry(
    preset_name: str | None = None,
    length_mm: float | None = None,
    base_radius_mm: float | None = None,
    tip_radius_mm: float | None = None,
    youngs_modulus_gpa: float | None = None,
    density_kg_m3: float | None = None,
    damping_ratio: float | None = None,
) -> Any:
    """The whisker described by the command-line geometry options.

    Parameters
    ----------
    preset_name : str, optional
        Preset to start from (default ``"xy-robot"``).
    length_mm, base_radius_mm, tip_radius_mm, youngs_modulus_gpa, density_kg_m3, damping_ratio
        Explicit values overriding the preset's (``None``: keep the preset's).

    Returns
    -------
    vibrissa.whisker.geometry.WhiskerGeometry
        The preset itself if nothing is overridden, else a copy named ``"custom"``
        whose ``source`` records the preset and the overrides.

    Raises
    ------
    ValueError
        Naming the offending option (``--length-mm`` etc. or ``--preset``).
    """
    from vibrissa.whisker.geometry import preset

    base_name = DEFAULT_PRESET if preset_name is None else preset_name
    try:
        base = preset(base_name)
    except ValueError as exc:
        raise ValueError(f"--preset: {exc}") from None
    given = {
        "length_mm": length_mm,
        "base_radius_mm": base_radius_mm,
        "tip_radius_mm": tip_radius_mm,
        "youngs_modulus_gpa": youngs_modulus_gpa,
        "density_kg_m3": density_kg_m3,
        "damping_ratio": damping_ratio,
    }
    changes = {k: v for k, v in given.items() if v is not None}
    for key, value in changes.items():
        opt = GEOMETRY_OPTIONS[key]
        if key == "damping_ratio":
            in_range(opt, value, 0.0, 0.5)  # the geometry's own bound (overdamped above)
        else:
            positive(opt, value)
    if not changes:
        return base
    overrides = ", ".join(f"{k}={v:g}" for k, v in changes.items())
    try:
        return base.replace(**changes, name="custom", source=f"preset {base.name} with {overrides}")
    except ValueError as exc:
        raise ValueError(_option_names(str(exc))) from None


#: Longest ring-down simulated by ``vibrissa whisker ring``, s (free ring-downs of the
#: thesis' whiskers decay within about a second).
MAX_RING_DURATION_S = 600.0
#: Most time steps of one ring-down (each recorded: nodes x 3 doubles).
MAX_RING_STEPS = 5_000_000


def build_model(geometry: Any, n_elements: int | None = None, rigid_follicle: bool = False) -> Any:
    """A :class:`~vibrissa.whisker.rod.RodModel`, checking ``--n-elements``."""
    from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS, RodModel

    if n_elements is None:
        n_elements = DEFAULT_N_ELEMENTS
    elif not 4 <= n_elements <= 400:
        raise ValueError(f"--n-elements must lie in [4, 400], got {n_elements}")
    return RodModel(geometry, n_elements, rigid_follicle=rigid_follicle)


def _check_at_mm(at_mm: float, geometry: Any) -> float:
    a = finite("--at-mm", at_mm)
    if not 0.0 < a <= geometry.length_mm:
        raise ValueError(
            f"--at-mm must lie in (0, {geometry.length_mm:g}] mm (the whisker's length), "
            f"got {at_mm:g}"
        )
    return a


def _sensor(model: Any) -> Any:
    """The default Hall sensor calibrated on ``model``'s whisker and discretisation."""
    from vibrissa.whisker.hall import HallSettings

    return HallSettings().calibrate(model.geometry, model.n_elements)


def _hall_volts(model: Any, tan_x: float, tan_y: float) -> tuple[float, float]:
    """Noise-free Hall output (V); 2.5 V at rest and whenever the follicle is rigid."""
    sensor = _sensor(model)
    tan = np.zeros(2) if model.rigid_follicle else np.array([tan_x, tan_y])
    v = sensor.ideal_volts(tan)
    return float(v[0]), float(v[1])


def _console() -> Any:
    from rich.console import Console

    return Console(highlight=False, soft_wrap=True)


def _fmt(value: Any) -> str:
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, float | np.floating):
        return f"{float(value):.6g}"
    if isinstance(value, list | tuple | np.ndarray):
        return ", ".join(_fmt(v) for v in value)
    return str(value)


def _print_table(title: str, rows: dict[str, Any]) -> None:
    from rich.table import Table

    table = Table(title=title, show_header=False)
    table.add_column("quantity", style="bold")
    table.add_column("value")
    for key, value in rows.items():
        table.add_row(key, _fmt(value))
    print_table(table)


# --------------------------------------------------------------------------- commands
@whisker_app.command("presets")
@user_errors
def presets_cmd(json_out: JsonOpt = False) -> None:
    """List the built-in whisker presets with all their parameters.

    Lengths and radii in mm, Young's modulus in GPa, density in kg/m^3, follicle
    stiffness in N m/rad, follicle depth in mm, follicle inertia in kg m^2.
    """
    from vibrissa.whisker.geometry import PRESETS

    items = [g.to_dict() for g in PRESETS.values()]
    if json_out:
        echo_json(items)
        return
    from rich.table import Table

    table = Table(title="whisker presets")
    for col in (
        "name",
        "length mm",
        "base r mm",
        "tip r mm",
        "E GPa",
        "rho kg/m3",
        "zeta",
        "follicle N m/rad",
    ):
        table.add_column(col)
    for d in items:
        table.add_row(
            d["name"],
            _fmt(d["length_mm"]),
            _fmt(d["base_radius_mm"]),
            _fmt(d["tip_radius_mm"]),
            _fmt(d["youngs_modulus_gpa"]),
            _fmt(d["density_kg_m3"]),
            _fmt(d["damping_ratio"]),
            _fmt(d["follicle_stiffness_nm_per_rad"]),
        )
    con = _console()
    print_table(table)
    for d in items:
        con.print(f"[bold]{d['name']}[/bold]: {d['source']}")


@whisker_app.command("info")
@user_errors
@solver_limits(f"use another whisker: {_STIFFER[3:]}", _option_names)
def info_cmd(
    preset: PresetOpt = None,
    length_mm: LengthOpt = None,
    base_radius_mm: BaseRadiusOpt = None,
    tip_radius_mm: TipRadiusOpt = None,
    youngs_modulus_gpa: ModulusOpt = None,
    density_kg_m3: DensityOpt = None,
    damping_ratio: DampingOpt = None,
    n_elements: NElementsOpt = None,
    rigid_follicle: RigidOpt = False,
    json_out: JsonOpt = False,
) -> None:
    """Geometry, material and derived properties of a whisker.

    Reports every geometry/material parameter, the number of elements, the first
    three bending natural frequencies (Hz, undamped, from the model), the damped
    frequencies and damping ratios of those modes, mass (kg), base bending
    stiffness (N m^2), the Hall sensor gain (V per unit tangent of the magnet
    angle) and the damping coefficients (mass-proportional alpha in 1/s,
    stiffness-proportional beta of shaft and follicle in s).
    """
    from vibrissa.whisker.hall import calibration_point_mm

    g = build_geometry(
        preset,
        length_mm,
        base_radius_mm,
        tip_radius_mm,
        youngs_modulus_gpa,
        density_kg_m3,
        damping_ratio,
    )
    model = build_model(g, n_elements, rigid_follicle)
    alpha, beta_s, beta_f = model.damping
    zetas, fd = model.modal_damping(alpha, beta_s, beta_f, 3)
    cal_r, cal_d = calibration_point_mm(g)
    out: dict[str, Any] = {
        **g.to_dict(),
        "n_elements": model.n_elements,
        "rigid_follicle": model.rigid_follicle,
        "natural_frequencies_hz": [float(f) for f in model.natural_frequencies_hz[:3]],
        "damped_frequencies_hz": [float(f) for f in fd],
        "modal_damping_ratios": [float(z) for z in zetas],
        "mass_kg": g.mass_kg,
        "bending_stiffness_base_nm2": g.bending_stiffness_base_nm2,
        "hall_gain_v_per_tan": _sensor(model).gain_v,
        "hall_calibration_radius_mm": cal_r,
        "hall_calibration_deflection_mm": cal_d,
        "damping_alpha_per_s": alpha,
        "damping_beta_shaft_s": beta_s,
        "damping_beta_follicle_s": beta_f,
    }
    if json_out:
        echo_json(out)
        return
    rows = {k: v for k, v in out.items() if k != "source"}
    _print_table(f"whisker {g.name}", rows)
    _console().print(f"source: {g.source}")


@whisker_app.command("static")
@user_errors
@solver_limits(
    f"use a smaller --force-n {_STIFFER}", _renamer({"force_n": "--force-n", "at_mm": "--at-mm"})
)
def static_cmd(
    force_n: Annotated[
        float,
        typer.Option("--force-n", help="Force (N), along +x, perpendicular to the rest axis."),
    ],
    at_mm: Annotated[
        float, typer.Option("--at-mm", help="Where it acts: arc length from the base (mm).")
    ],
    preset: PresetOpt = None,
    length_mm: LengthOpt = None,
    base_radius_mm: BaseRadiusOpt = None,
    tip_radius_mm: TipRadiusOpt = None,
    youngs_modulus_gpa: ModulusOpt = None,
    density_kg_m3: DensityOpt = None,
    damping_ratio: DampingOpt = None,
    n_elements: NElementsOpt = None,
    rigid_follicle: RigidOpt = False,
    json_out: JsonOpt = False,
) -> None:
    """Static equilibrium under a point force of fixed direction (geometrically nonlinear).

    Reports the base bending moment (N m), sideways deflection of the loaded point
    (mm), its axial shortening toward the base (mm), the follicle rotation (deg) and
    the noise-free Hall outputs (V; 2.5 V at rest and for a rigid follicle).
    """
    g = build_geometry(
        preset,
        length_mm,
        base_radius_mm,
        tip_radius_mm,
        youngs_modulus_gpa,
        density_kg_m3,
        damping_ratio,
    )
    f = finite("--force-n", force_n)
    a = _check_at_mm(at_mm, g)
    model = build_model(g, n_elements, rigid_follicle)
    res = model.static_force(f, a)
    hx, hy = _hall_volts(model, res.tan_x, res.tan_y)
    out = {
        "base_moment_nm": res.base_moment_nm,
        "deflection_mm": res.deflection_mm,
        "axial_shortening_mm": res.axial_shortening_mm,
        "base_angle_deg": res.base_angle_deg,
        "hall_x_v": hx,
        "hall_y_v": hy,
        "tan_x": res.tan_x,
        "tan_y": res.tan_y,
        "force_n": f,
        "at_mm": a,
        "whisker": g.name,
        "n_elements": model.n_elements,
        "rigid_follicle": model.rigid_follicle,
    }
    if json_out:
        echo_json(out)
        return
    _print_table(f"static force {f:g} N at {a:g} mm on {g.name}", out)


@whisker_app.command("push")
@user_errors
@solver_limits(
    f"use a smaller --displacement-mm, --friction or --pole-radius-mm {_STIFFER}",
    _renamer({"at_mm": "--at-mm", "pole_radius_mm": "--pole-radius-mm"}),
)
def push_cmd(
    at_mm: Annotated[
        float,
        typer.Option("--at-mm", help="Radial distance of first contact from the base (mm)."),
    ],
    displacement_mm: Annotated[
        float,
        typer.Option(
            "--displacement-mm", help="Sideways (+x) displacement of the pole (mm), >= 0."
        ),
    ],
    friction: Annotated[
        float, typer.Option("--friction", help="Coulomb friction coefficient, >= 0.")
    ] = 0.0,
    pole_radius_mm: Annotated[
        float, typer.Option("--pole-radius-mm", help="Radius of the pole (mm).")
    ] = 0.5,
    preset: PresetOpt = None,
    length_mm: LengthOpt = None,
    base_radius_mm: BaseRadiusOpt = None,
    tip_radius_mm: TipRadiusOpt = None,
    youngs_modulus_gpa: ModulusOpt = None,
    density_kg_m3: DensityOpt = None,
    damping_ratio: DampingOpt = None,
    n_elements: NElementsOpt = None,
    rigid_follicle: RigidOpt = False,
    json_out: JsonOpt = False,
) -> None:
    """Quasi-static push of a thin pole (parallel to y) through the whisker.

    The pole touches the undeformed whisker at --at-mm on its -x side and moves
    --displacement-mm along +x. Reports the base bending moment (N m), the contact
    force (N), where along the whisker the contact ends up (arc length, mm),
    whether the whisker slipped off the pole, and the noise-free Hall outputs (V;
    2.5 V for a rigid follicle). The Hall calibration push is --at-mm 150
    --displacement-mm 60 (4.75 V).
    """
    g = build_geometry(
        preset,
        length_mm,
        base_radius_mm,
        tip_radius_mm,
        youngs_modulus_gpa,
        density_kg_m3,
        damping_ratio,
    )
    a = _check_at_mm(at_mm, g)
    d = non_negative("--displacement-mm", displacement_mm)
    mu = non_negative("--friction", friction)
    rp = positive("--pole-radius-mm", pole_radius_mm)
    model = build_model(g, n_elements, rigid_follicle)
    res = model.push(a, d, friction=mu, pole_radius_mm=rp)
    hx, hy = _hall_volts(model, res.tan_x, res.tan_y)
    out = {
        "base_moment_nm": res.base_moment_nm,
        "base_force_n": res.base_force_n,
        "contact_arc_length_mm": res.contact_arc_length_mm,
        "slipped_off": res.slipped_off,
        "hall_x_v": hx,
        "hall_y_v": hy,
        "normal_force_n": res.normal_force_n,
        "friction_force_n": res.friction_force_n,
        "tan_x": res.tan_x,
        "tan_y": res.tan_y,
        "at_mm": a,
        "displacement_mm": d,
        "friction": mu,
        "whisker": g.name,
        "n_elements": model.n_elements,
        "rigid_follicle": model.rigid_follicle,
    }
    if json_out:
        echo_json(out)
        return
    _print_table(f"pole push {d:g} mm at {a:g} mm on {g.name}", out)


@whisker_app.command("ring")
@user_errors
@solver_limits(
    f"use a smaller --tip-deflection-mm or --dt-ms {_STIFFER}", _renamer({"dt_s": "--dt-ms"})
)
def ring_cmd(
    tip_deflection_mm: Annotated[
        float,
        typer.Option("--tip-deflection-mm", help="Initial static tip deflection along x (mm)."),
    ] = 10.0,
    duration_s: Annotated[
        float, typer.Option("--duration-s", help="Simulated time after release (s).")
    ] = 1.0,
    dt_ms: Annotated[
        float, typer.Option("--dt-ms", help="Integration time step (ms), at most 1.")
    ] = 0.25,
    no_lowpass: Annotated[
        bool,
        typer.Option(
            "--no-lowpass",
            help="Measure on the raw base signal, without the zero-phase low-pass that "
            "isolates the first mode.",
        ),
    ] = False,
    preset: PresetOpt = None,
    length_mm: LengthOpt = None,
    base_radius_mm: BaseRadiusOpt = None,
    tip_radius_mm: TipRadiusOpt = None,
    youngs_modulus_gpa: ModulusOpt = None,
    density_kg_m3: DensityOpt = None,
    damping_ratio: DampingOpt = None,
    n_elements: NElementsOpt = None,
    rigid_follicle: RigidOpt = False,
    json_out: JsonOpt = False,
) -> None:
    """Deflect the tip, release it, and measure the ring-down at the base.

    The base signal is the magnet's tangent tan_x (with --rigid-follicle, which
    holds the magnet still, the slope of the first shaft element instead). It is
    low-passed (4th-order Butterworth, zero phase) at the geometric mean of the
    first two natural frequencies to isolate the first mode, whose decay the
    higher modes otherwise disturb (badly so at a clamped base). The damped
    frequency (Hz) comes from the mean spacing of its zero crossings, the damping
    ratio from a least-squares fit of log|peak| against time over ten half-cycle
    peaks (after the first cycle). Both are compared with the configured damping
    ratio and the model's first natural frequency (undamped, Hz) and damped
    frequency.
    """
    from vibrissa.experiments.ringdown import ring_down_test

    g = build_geometry(
        preset,
        length_mm,
        base_radius_mm,
        tip_radius_mm,
        youngs_modulus_gpa,
        density_kg_m3,
        damping_ratio,
    )
    tip = finite("--tip-deflection-mm", tip_deflection_mm)
    if tip == 0:
        raise ValueError("--tip-deflection-mm must be non-zero, got 0")
    if abs(tip) > 0.5 * g.length_mm:
        raise ValueError(
            f"--tip-deflection-mm must be at most half the whisker's length "
            f"({0.5 * g.length_mm:g} mm), got {tip_deflection_mm:g}"
        )
    # a ring-down decays within seconds; the bound keeps the record (every step, rigid
    # follicle) within memory
    dur = in_range("--duration-s", duration_s, 0.0, MAX_RING_DURATION_S, "s")
    dt = in_range("--dt-ms", dt_ms, 1e-4, 1.0, "ms") * 1e-3
    if dur / dt > MAX_RING_STEPS:
        raise ValueError(
            f"--duration-s {duration_s:g} at --dt-ms {dt_ms:g} is "
            f"{dur / dt:.3g} steps; the limit is {MAX_RING_STEPS:.0e}"
        )
    if dur < 100 * dt:
        raise ValueError(
            f"--duration-s must cover at least 100 steps of --dt-ms, got {duration_s:g}"
        )
    model = build_model(g, n_elements, rigid_follicle)
    meas = ring_down_test(
        model, tip_deflection_mm=tip, duration_s=dur, dt_s=dt, lowpass=not no_lowpass
    )
    f_model, lowpass_hz, signal_name = (
        meas["model_frequency_hz"],
        meas["lowpass_hz"],
        meas["signal"],
    )
    fd = [meas["model_damped_frequency_hz"]]
    meas["n_peaks"] = meas["n_peaks_fitted"]
    out: dict[str, Any] = {
        "frequency_hz": meas["frequency_hz"],
        "damping_ratio": meas["damping_ratio"],
        "configured_damping_ratio": g.damping_ratio,
        "model_frequency_hz": f_model,
        "model_damped_frequency_hz": fd[0],
        "n_peaks_fitted": meas["n_peaks_fitted"],
        "signal": signal_name,
        "lowpass_hz": lowpass_hz,
        "whisker": g.name,
        "n_elements": model.n_elements,
        "rigid_follicle": model.rigid_follicle,
        "tip_deflection_mm": tip,
        "duration_s": dur,
        "dt_s": meas["dt_s"],
    }
    if json_out:
        echo_json(out)
        return
    con = _console()
    con.print(
        f"[bold]ring-down of whisker {g.name}[/bold] ({model.n_elements} elements"
        f"{', rigid follicle' if model.rigid_follicle else ''}): tip deflected "
        f"{tip:g} mm, released, {dur:g} s simulated at dt = {meas['dt_s'] * 1e3:g} ms"
    )
    filt = f", low-passed at {lowpass_hz:.1f} Hz" if lowpass_hz else ", unfiltered"
    con.print(
        f"  model:    first natural frequency {f_model:.2f} Hz "
        f"(damped {fd[0]:.2f} Hz), configured damping ratio {g.damping_ratio:.3f}"
    )
    if meas["frequency_hz"] is None:
        con.print(
            f"  measured: too few half cycles ({meas['n_peaks']}) in the {signal_name} "
            "to measure; try a longer --duration-s or less damping"
        )
        return
    f_m, z_m = meas["frequency_hz"], meas["damping_ratio"]
    z_err = f"{100 * (z_m / g.damping_ratio - 1):+.1f} %" if g.damping_ratio > 0 else "n/a"
    con.print(
        f"  measured: frequency {f_m:.2f} Hz ({100 * (f_m / f_model - 1):+.1f} % vs "
        f"model), damping ratio {z_m:.4f} ({z_err} vs configured) from "
        f"{meas['n_peaks']} half-cycle peaks of the {signal_name}{filt}"
    )


#: Most whisks of one ``whisk`` run (each a few thousand steps).
MAX_WHISKS = 200
#: Most simulated time of one ``whisk`` run (s), and most control steps in it: a whisk
#: frequency near 0 or a control rate near infinity asked for unbounded work.
MAX_WHISK_SECONDS = 60.0
MAX_CONTROL_STEPS = 6_000_000

_WHISK_NAMES = _renamer(
    {
        "frequency_hz": "--frequency-hz",
        "amplitude_deg": "--amplitude-deg",
        "retracted_deg": "--retracted-deg",
        "sigma_z": "--sigma-z",
        "tau_z_periods": "--tau-z-periods",
        "radial_distance_mm": "--pole-at-mm",
        "contact_angle_deg": "--pole-angle-deg",
        "pole_radius_mm": "--pole-radius-mm",
        "control_rate_hz": "--control-rate-hz",
        "motor bandwidth_hz": "--motor-bandwidth-hz",
        "tau_z_s": "--tau-z-periods",
    }
)


@whisker_app.command("whisk")
@user_errors
@solver_limits(f"use a smaller --amplitude-deg or --frequency-hz {_STIFFER}", _WHISK_NAMES)
def whisk_cmd(
    frequency_hz: Annotated[
        float, typer.Option("--frequency-hz", help="Whisk frequency (Hz), > 0.")
    ] = 4.0,
    amplitude_deg: Annotated[
        float, typer.Option("--amplitude-deg", help="Protraction from full retraction (deg), > 0.")
    ] = 12.0,
    retracted_deg: Annotated[
        float, typer.Option("--retracted-deg", help="Housing angle at full retraction (deg).")
    ] = 0.0,
    whisks: Annotated[int, typer.Option("--whisks", help="Whisks simulated.")] = 3,
    pole_at_mm: Annotated[
        float | None,
        typer.Option(
            "--pole-at-mm",
            help="Radial distance of a vertical pole from the base (mm); omitted: whisking in air.",
        ),
    ] = None,
    pole_angle_deg: Annotated[
        float,
        typer.Option(
            "--pole-angle-deg",
            help="Housing angle at which the straight whisker touches "
            "the pole (deg): beyond full retraction, before full protraction.",
        ),
    ] = 6.0,
    pole_radius_mm: Annotated[
        float, typer.Option("--pole-radius-mm", help="Radius of the pole (mm).")
    ] = 0.5,
    sigma_z: Annotated[
        float, typer.Option("--sigma-z", help="RCP gain (eq. 3.3), >= 0; 0: unmodulated.")
    ] = 0.0,
    tau_z_periods: Annotated[
        float,
        typer.Option("--tau-z-periods", help="RCP decay time constant, in whisk periods (> 0)."),
    ] = 0.25,
    control_rate_hz: Annotated[
        float, typer.Option("--control-rate-hz", help="Control loop rate (Hz).")
    ] = 1000.0,
    motor_bandwidth_hz: Annotated[
        float, typer.Option("--motor-bandwidth-hz", help="Bandwidth of the housing's servo (Hz).")
    ] = 20.0,
    preset: PresetOpt = None,
    length_mm: LengthOpt = None,
    base_radius_mm: BaseRadiusOpt = None,
    tip_radius_mm: TipRadiusOpt = None,
    youngs_modulus_gpa: ModulusOpt = None,
    density_kg_m3: DensityOpt = None,
    damping_ratio: DampingOpt = None,
    n_elements: NElementsOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Whisk the whisker in air or into a pole, with or without RCP feedback.

    A motor turns the follicle housing (:mod:`vibrissa.robots.whisking`): the
    whisking pattern generator's oscillator, protraction suppressed by the RCP
    gating variable (thesis eqs. 3.2-3.3) when --sigma-z > 0. Reports the peak
    Hall x deflection, the contact force and the whisks that touched the pole.
    Every option is checked before anything is simulated.
    """
    from vibrissa.robots.whisking import (
        RCPControl,
        WhiskerSetup,
        WhiskPattern,
        check_pole_placement,
        pole_whisker,
        run_whisking,
    )

    g = build_geometry(
        preset,
        length_mm,
        base_radius_mm,
        tip_radius_mm,
        youngs_modulus_gpa,
        density_kg_m3,
        damping_ratio,
    )
    try:
        pattern = WhiskPattern(frequency_hz, amplitude_deg, retracted_deg)
        ctrl = RCPControl(sigma_z, tau_z_periods)
        if isinstance(whisks, bool) or not 1 <= whisks <= MAX_WHISKS:
            raise ValueError(f"--whisks must lie in [1, {MAX_WHISKS}], got {whisks}")
        positive("control_rate_hz", control_rate_hz)
        positive("motor bandwidth_hz", motor_bandwidth_hz)
        if whisks / frequency_hz > MAX_WHISK_SECONDS:
            raise ValueError(
                f"--frequency-hz: {whisks} whisks at {frequency_hz:g} Hz last "
                f"{whisks / frequency_hz:.3g} s; at most {MAX_WHISK_SECONDS:g} s of whisking "
                "(raise --frequency-hz or lower --whisks)"
            )
        if whisks / frequency_hz * control_rate_hz > MAX_CONTROL_STEPS:
            raise ValueError(
                f"--control-rate-hz: {control_rate_hz:g} Hz over {whisks / frequency_hz:.3g} s "
                f"is more than {MAX_CONTROL_STEPS:,} control steps"
            )
        if pole_at_mm is not None:
            check_pole_placement(pole_at_mm, pole_angle_deg, pattern, pole_radius_mm, g.length_mm)
        model = build_model(g, n_elements)
        setup = (
            WhiskerSetup(model)
            if pole_at_mm is None
            else pole_whisker(model, pole_at_mm, pole_angle_deg, pole_radius_mm)
        )
    except ValueError as exc:
        raise ValueError(_WHISK_NAMES(str(exc))) from None
    res = run_whisking(
        [setup],
        pattern,
        ctrl,
        whisks / frequency_hz,
        control_rate_hz=control_rate_hz,
        motor_bandwidth_hz=motor_bandwidth_hz,
    )
    volts = _sensor(model).ideal_volts(np.column_stack([res.tan_x[0], 0 * res.tan_x[0]]))[:, 0]
    whisk_of = np.minimum((res.time_s * frequency_hz).astype(int), whisks - 1)
    touched = np.zeros(whisks, dtype=bool)
    touched[whisk_of[res.contact_force_n[0] > 0]] = True
    out: dict[str, Any] = {
        "whisker": g.name,
        "frequency_hz": pattern.frequency_hz,
        "amplitude_deg": pattern.amplitude_deg,
        "whisks": whisks,
        "pole_at_mm": pole_at_mm,
        "sigma_z": ctrl.sigma_z,
        "tau_z_periods": ctrl.tau_z_periods,
        "peak_deflection_v": float(np.abs(volts - 2.5).max()),
        "max_contact_force_n": float(res.contact_force_n[0].max()),
        "contact_time_s": float(np.count_nonzero(res.contact_force_n[0] > 0) * res.dt_s),
        "whisks_touching": int(touched.sum()),
        "max_gating": float(res.gating.max()),
    }
    if json_out:
        echo_json(out)
        return
    _print_table(f"whisking {g.name} at {frequency_hz:g} Hz", out)


def register(app: typer.Typer) -> None:
    """Register the ``whisker`` command group on the top-level ``app``."""
    app.add_typer(whisker_app, name="whisker")
