"""Every option of every command, declared once: its kind, unit and bounds with their reason.

:data:`CONTRACT` holds one table per command (``"run crunchbot"`` -> parameter name ->
:class:`Spec`). :func:`enforce` wraps each command so that, before its body runs, every
given value is checked against its table (a number finite and within its bounds, a seed
within what a dataset stores, a file input a regular readable file, an output not
colliding with a directory or a file, text free of control characters) and a bad value
is one line naming the option, exit status 2, with nothing done and nothing created; it
also writes each option's bounds into its ``--help``. A command's own checks (how
options combine, what a list or a preset name means) still run after these, before any
work.

The tables are checked against the command line itself (``tests/cli/test_contract.py``):
an option without a row, or a row without an option, fails the tests, so a new option
cannot skip its check; the fuzzer (``tests/cli/test_fuzz_contract.py``) walks them.
"""

from __future__ import annotations

import inspect
import math
import os
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import wraps
from pathlib import Path
from typing import Any

import typer

from vibrissa.cli._common import regular_file
from vibrissa.whisker.geometry import (
    DENSITY_RANGE_KG_M3,
    MAX_LENGTH_MM,
    MIN_RADIUS_MM,
    YOUNGS_MODULUS_RANGE_GPA,
)

__all__ = ["CONTRACT", "Spec", "enforce", "commands", "read_structured"]

#: Largest seed: datasets store it as a signed 64-bit integer.
MAX_SEED = 2**63 - 1
#: Longest text value (a path, a list, an address) any option takes.
MAX_TEXT = 4096

KINDS = (
    "flag",
    "number",
    "integer",
    "seed",
    "choice",
    "text",
    "list",
    "numbers",
    "file",
    "output",
    "refused",
)


@dataclass(frozen=True)
class Spec:
    """What one option takes.

    Parameters
    ----------
    kind
        ``flag``; ``number`` (a finite real); ``integer``; ``seed`` (0 .. 2**63 - 1);
        ``choice`` (one of ``choices``); ``text`` or ``list`` (a comma list the command
        parses), both free of control characters; ``file`` (an input that must be a
        regular, readable file; ``-`` for standard input if ``stdin``); ``output`` (a
        file, or a directory if ``directory``, to be written); ``refused`` (an option this
        command has but cannot use: any value is refused, saying ``why``); ``numbers`` (a
        comma list of numbers, each within the bounds, none repeating another to within
        1e-9 of its size; integers only if ``whole``; empty: none given).
    low, high
        Bounds of a number or integer (``None``: unbounded on that side).
    open_low
        ``low`` itself excluded (a positive quantity).
    unit
        The unit, as written after a value (``s``, ``mm``).
    why
        Why the bounds are where they are (shown by nothing, kept with the table).
    choices
        The values of a ``choice``.
    directory
        An ``output`` that is a directory.
    stdin
        A ``file`` that may be ``-``.
    structured
        A ``file`` of JSON (or TOML, by its suffix): it is parsed here, with its size and
        nesting bounded (:func:`read_structured`).
    min_magnitude
        A ``number`` is 0 or at least this far from it: a subnormal value such as 5e-324
        passes every bound yet divides to infinity (found by ``scripts/fuzz_cli_slow.py``).
    whole
        ``numbers`` that must be integers.
    """

    kind: str
    low: float | None = None
    high: float | None = None
    open_low: bool = False
    unit: str = ""
    why: str = ""
    choices: tuple[str, ...] = field(default_factory=tuple)
    directory: bool = False
    stdin: bool = False
    structured: bool = False
    min_magnitude: float = 0.0
    whole: bool = False

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"unknown option kind {self.kind!r}")

    # ------------------------------------------------------------------ help
    def bounds_text(self) -> str:
        """The bounds as ``--help`` shows them, e.g. ``0.5 to 3600 s``; empty if none."""
        u = f" {self.unit}" if self.unit else ""
        if self.kind == "refused":
            return f"not for this command: {self.why}"
        if self.kind == "seed":
            return "0 to 2**63 - 1"
        if self.kind not in ("number", "integer", "numbers") or (
            self.low is None and self.high is None
        ):
            return ""
        low, high = self._fmt(self.low), self._fmt(self.high)
        if self.high is None:
            return f"{'>' if self.open_low else '>='} {low}{u}"
        if self.low is None:
            return f"<= {high}{u}"
        if self.open_low:
            return f"> {low} and <= {high}{u}"
        return f"{low} to {high}{u}"

    # ------------------------------------------------------------------ checks
    def check(self, flag: str, value: Any) -> None:
        """Raise ``ValueError`` naming ``flag`` if ``value`` breaks this spec (``None``: unset)."""
        if value is None:
            return
        if isinstance(value, list | tuple):
            for v in value:
                self.check(flag, v)
            return
        kind = self.kind
        if kind == "flag":
            return
        if kind == "refused":
            raise ValueError(f"{flag}: {self.why}")
        if kind in ("number", "integer", "seed"):
            self._check_number(flag, value)
            return
        if kind == "numbers" and isinstance(value, str):
            self._check_numbers(flag, value)
            return
        text = os.fspath(value) if isinstance(value, os.PathLike) else value
        if not isinstance(text, str):
            return  # typer converted it already (an enum, a bool)
        _check_text(flag, text)
        if kind == "choice" and text not in self.choices:
            raise ValueError(f"{flag} must be one of {', '.join(self.choices)}, got {text!r}")
        if kind == "file" and not (self.stdin and text == "-"):
            _check_input_file(flag, Path(text))
            if self.structured:
                read_structured(flag, Path(text))
        if kind == "output" and text != "-":
            _check_output(flag, Path(text), self.directory)

    def _check_numbers(self, flag: str, text: str) -> None:
        _check_text(flag, text)
        if not text.strip():
            return  # none given: the command's default
        values: list[float] = []
        for item in text.split(","):
            try:
                x = float(item)
            except ValueError:
                raise ValueError(f"{flag} must be comma-separated numbers, got {text!r}") from None
            if self.whole and not (math.isfinite(x) and x.is_integer()):
                raise ValueError(f"{flag}: expected whole numbers, got {item.strip()!r}")
            self._check_number(flag, int(x) if self.whole else x, as_integer=False)
            for y in values:
                if abs(x - y) <= 1e-9 * max(abs(x), abs(y)):
                    raise ValueError(
                        f"{flag}: {item.strip()} repeats {y:g} (values closer than 1e-9 of "
                        "their size are the same class written twice)"
                    )
            values.append(x)

    def _check_number(self, flag: str, value: Any, *, as_integer: bool = True) -> None:
        if isinstance(value, bool):
            raise ValueError(f"{flag}: expected a number, got {value!r}")
        if as_integer and self.kind in ("integer", "seed") and not isinstance(value, int):
            raise ValueError(f"{flag}: expected an integer, got {value!r}")
        if not math.isfinite(value):
            raise ValueError(f"{flag} must be finite, got {value!r}")
        low, high = (0, MAX_SEED) if self.kind == "seed" else (self.low, self.high)
        u = f" {self.unit}" if self.unit else ""
        if value != 0 and abs(value) < self.min_magnitude:
            raise ValueError(
                f"{flag} must be 0 or at least {self.min_magnitude:g}{u} from it, got {value!r}"
            )
        below = low is not None and (value <= low if self.open_low else value < low)
        above = high is not None and value > high
        if not (below or above):
            return
        if (self.kind in ("integer", "seed") or self.whole) and below and low in (0, 1):
            word = "non-negative" if low == 0 else "positive"
            raise ValueError(f"{flag}: expected a {word} integer, got {value}")
        if self.kind == "seed":
            raise ValueError(
                f"{flag}: expected an integer at most 2**63 - 1 (what a dataset stores), "
                f"got {value}"
            )
        if below and low == 0:
            word = "positive" if self.open_low else "non-negative"
            raise ValueError(f"{flag} must be {word}, got {value!r}")
        why = f" ({self.why})" if self.why else ""
        if low is None:
            raise ValueError(f"{flag} must be at most {self._fmt(high)}{u}{why}, got {value!r}")
        if high is None:
            raise ValueError(f"{flag} must be at least {self._fmt(low)}{u}{why}, got {value!r}")
        left = "(" if self.open_low else "["
        raise ValueError(
            f"{flag} must lie in {left}{self._fmt(low)}, {self._fmt(high)}]{u}{why}, got {value!r}"
        )

    def _fmt(self, x: float | None) -> str:
        if x is None:
            return ""
        return str(int(x)) if self.kind == "integer" or self.whole else f"{x:g}"


def _check_text(flag: str, text: str) -> None:
    if len(text) > MAX_TEXT:
        raise ValueError(f"{flag}: longer than {MAX_TEXT} characters ({len(text)})")
    bad = next((c for c in text if ord(c) < 32 or ord(c) == 127 or 0xD800 <= ord(c) < 0xE000), None)
    if bad is not None:
        raise ValueError(f"{flag}: contains the control or invalid character {bad!r}")


def _check_input_file(flag: str, path: Path) -> None:
    regular_file(flag, path)


#: Largest JSON or TOML input (a mapping, an arena, a baseline) read.
MAX_STRUCTURED_BYTES = 256 * 2**20


def read_structured(flag: str, path: Path) -> Any:
    """Parse a JSON (or, by its suffix, TOML) input with its size and nesting bounded.

    Raises
    ------
    ValueError
        One line naming ``flag``: larger than :data:`MAX_STRUCTURED_BYTES`, not
        UTF-8, not JSON/TOML, or nested deeper than Python's parsers go (a file of
        100,000 brackets raised ``RecursionError``).
    """
    import json
    import tomllib

    _check_input_file(flag, path)
    size = path.stat().st_size
    if size > MAX_STRUCTURED_BYTES:
        raise ValueError(f"{flag}: {path} is {size} bytes, more than {MAX_STRUCTURED_BYTES}")
    toml = path.suffix.lower() == ".toml"
    try:
        text = path.read_text(encoding="utf-8")
        return tomllib.loads(text) if toml else json.loads(text)
    except RecursionError:
        raise ValueError(f"{flag}: {path} is nested too deep to read") from None
    except (UnicodeDecodeError, ValueError) as exc:  # JSONDecodeError, TOMLDecodeError
        kind = "TOML" if toml else "JSON"
        raise ValueError(f"{flag}: {path} is not {kind} ({' '.join(str(exc).split())})") from None


def _check_output(flag: str, path: Path, directory: bool) -> None:
    if directory:
        if path.exists() and not path.is_dir():
            raise ValueError(f"{flag}: {path} is a file, not a directory")
        return
    if path.is_dir():
        raise ValueError(f"{flag}: {path} is a directory, not a file")
    if path.exists() and not path.is_file():
        raise ValueError(f"{flag}: {path} exists and is not a regular file")


# ---------------------------------------------------------------------------- the tables
def _n(
    low: float | None,
    high: float | None,
    unit: str = "",
    why: str = "",
    *,
    open_low: bool = False,
    min_magnitude: float = 0.0,
) -> Spec:
    return Spec(
        "number", low, high, open_low=open_low, unit=unit, why=why, min_magnitude=min_magnitude
    )


def _i(low: int | None, high: int | None, why: str = "") -> Spec:
    return Spec("integer", low, high, why=why)


FLAG = Spec("flag")
TEXT = Spec("text")
LIST = Spec("list")
SEED = Spec("seed", why="datasets store the seed as a signed 64-bit integer")
IN_FILE = Spec("file")
OUT_FILE = Spec("output")
OUT_DIR = Spec("output", directory=True)
WORKERS = _i(1, 4096, "processes; the commands cap them further by this machine's cores")
SCHEDULER = Spec("text", why="a Dask address, tcp://host:port, checked by the command")

GEOMETRY: dict[str, Spec] = {
    "preset": TEXT,
    "length_mm": _n(1.0, MAX_LENGTH_MM, "mm", "the geometry's own range"),
    "base_radius_mm": _n(MIN_RADIUS_MM, MAX_LENGTH_MM / 4, "mm", "1 um is finer than any tip"),
    "tip_radius_mm": _n(MIN_RADIUS_MM, MAX_LENGTH_MM / 4, "mm", "at most the base radius"),
    "youngs_modulus_gpa": _n(*YOUNGS_MODULUS_RANGE_GPA, "GPa", "soft rubber to diamond"),
    "density_kg_m3": _n(*DENSITY_RANGE_KG_M3, "kg/m^3", "aerogel to osmium"),
    "damping_ratio": _n(0.0, 0.5, "", "overdamped above 0.5 (the geometry's own bound)"),
    "n_elements": _i(4, 400, "the rod model's own range"),
}
REPRODUCE: dict[str, Spec] = {
    "quick": FLAG,
    "json_out": FLAG,
    "out": OUT_DIR,
    "seed": SEED,
    "workers": WORKERS,
    "scheduler": SCHEDULER,
    "figures": FLAG,
    "baseline": Spec("file", structured=True),
}


def _no_baseline(name: str) -> Spec:
    return Spec(
        "refused",
        why=f"the {name} report has no 'before' column (radial-distance, angle-texture and "
        "floor-texture have one); compare the two runs' results.json instead",
    )


CONTRACT: dict[str, dict[str, Spec]] = {
    "generate": {
        "protocol": TEXT,
        "out": OUT_FILE,
        "quick": FLAG,
        "radial_distances": LIST,
        "speeds": LIST,
        "angles": LIST,
        "textures": LIST,
        "runs": _i(1, 1_000_000, "grid repetitions (thesis: 2); the memory estimate caps them"),
        "sample_rate_hz": _n(1, 1e6, "Hz", "a Hall sensor read at 1 Hz to 1 MHz"),
        "whisker": TEXT,
        "noise_v": _n(0, 10, "V", "within the sensor's supply"),
        "drift": _n(
            -0.5, 0.5, "", "the protocol's own bound on the stiffness drift", min_magnitude=1e-4
        ),
        "seed": SEED,
        "workers": WORKERS,
        "scheduler": SCHEDULER,
        "chunk_size": _i(1, 100_000, "trials per unit of work"),
        "restart": FLAG,
        "json_out": FLAG,
    },
    "import": {
        "source": IN_FILE,
        "out": OUT_FILE,
        "mapping": Spec("file", structured=True),
        "fmt": Spec("choice", choices=("auto", "mat", "csv", "npz")),
        "signal": TEXT,
        "axis": TEXT,
        "channels": LIST,
        "sample_rate_hz": _n(1e-3, 1e9, "Hz", "a sample every 1000 s to 1 GHz"),
        "time_axis": _i(0, 1, "samples x channels (0) or channels x samples (1)"),
        "label": TEXT,
        "const": TEXT,
        "crop": FLAG,
        "skip_empty": FLAG,
        "trials_last": FLAG,
        "t0_s": _n(-1e6, 1e6, "s", "within a session of about 11 days"),
        "as_json": FLAG,
    },
    "plot": {
        "dataset": IN_FILE,
        "out": OUT_DIR,
        "kind": Spec("choice", choices=("traces", "contours", "all")),
        "channel": TEXT,
        "dpi": _i(20, 600, "readable on screen to print quality"),
    },
    "identify": {"quick": FLAG, "json_out": FLAG},
    "live": {
        "pipeline": IN_FILE,
        "input_": Spec("text", why="- , a file, udp://HOST:PORT or serial://DEVICE"),
        "fmt": Spec("choice", choices=("csv", "jsonl")),
        "follow": FLAG,
        "idle_timeout_s": _n(0, 1e7, "s", "up to about 4 months", open_low=True),
        "rate_hz": _n(0, 1e9, "Hz", "up to 1 GHz", open_low=True),
        "out": OUT_FILE,
        "replay": IN_FILE,
        "speed": _n(0, 1e6, "", "0 plays at once"),
        "trials": TEXT,
        "max_seconds": _n(0, 1e9, "s", "stream time"),
    },
    "fit-pipeline": {
        "out": OUT_FILE,
        "where": IN_FILE,
        "what": IN_FILE,
        "tip_zone_mm": _n(0, 2000, "mm", "within a whisker's length"),
        "decision_threshold": _n(0, 1, "", "a posterior probability"),
        "json_out": FLAG,
    },
    "whisker presets": {"json_out": FLAG},
    "whisker info": {**GEOMETRY, "rigid_follicle": FLAG, "json_out": FLAG},
    "whisker static": {
        "force_n": _n(-1e3, 1e3, "N", "a kilonewton bends any whisker past the model"),
        "at_mm": _n(0, 2000, "mm", "along the whisker", open_low=True),
        **GEOMETRY,
        "rigid_follicle": FLAG,
        "json_out": FLAG,
    },
    "whisker push": {
        "at_mm": _n(0, 2000, "mm", "along the whisker", open_low=True),
        "displacement_mm": _n(0, 2000, "mm", "at most a whisker's length"),
        "friction": _n(0, 10, "", "Coulomb coefficients of real materials are below 10"),
        "pole_radius_mm": _n(0, None, "mm", "below --at-mm (the command checks)", open_low=True),
        **GEOMETRY,
        "rigid_follicle": FLAG,
        "json_out": FLAG,
    },
    "whisker ring": {
        "tip_deflection_mm": _n(
            -2000, 2000, "mm", "at most a whisker's length", min_magnitude=1e-6
        ),
        "duration_s": _n(0.0, 600.0, "s", "the command's own limit on simulated time"),
        "dt_ms": _n(1e-4, 1.0, "ms", "the solver's range"),
        "no_lowpass": FLAG,
        **GEOMETRY,
        "rigid_follicle": FLAG,
        "json_out": FLAG,
    },
    "whisker whisk": {
        "frequency_hz": _n(0, 100, "Hz", "rats whisk at up to about 25 Hz", open_low=True),
        "amplitude_deg": _n(0, 180, "deg", "a half turn", open_low=True),
        "retracted_deg": _n(-180, 180, "deg", "a half turn either way"),
        "whisks": _i(1, 200, "the command's own limit"),
        "pole_at_mm": _n(0, 2000, "mm", "along the whisker", open_low=True),
        "pole_angle_deg": _n(-180, 180, "deg", "a half turn either way"),
        "pole_radius_mm": _n(0, None, "mm", "checked against --pole-at-mm", open_low=True),
        "sigma_z": _n(0, 1e3, "", "RCP gain (eq. 3.3); the thesis uses 0.7 and 2"),
        "tau_z_periods": _n(0, 1e3, "periods", "RCP decay time", open_low=True),
        "control_rate_hz": _n(1, 1e6, "Hz", "at least once a second; the steps are bounded too"),
        "motor_bandwidth_hz": _n(0, 1e4, "Hz", "a servo", open_low=True),
        **GEOMETRY,
        "json_out": FLAG,
    },
    "bench physics": {
        "json_out": FLAG,
        "dt_ms": _n(1e-3, 1.0, "ms", "at least 1 us, at most the solver's 1 ms"),
        "n_elements": _i(4, 400, "the rod model's own range"),
        "repeats": _i(1, 1000, "timed trials"),
        "duration_s": _n(0, 600, "s", "simulated time", open_low=True),
    },
    "reproduce tactile-framework": {**REPRODUCE, "baseline": _no_baseline("tactile-framework")},
    "reproduce radial-distance": {**REPRODUCE, "n_seeds": _i(1, 1000, "repeats of a subset")},
    "reproduce angle-texture": dict(REPRODUCE),
    "reproduce biotact-g1": {
        **REPRODUCE,
        "baseline": _no_baseline("biotact-g1"),
        "distances": Spec(
            "numbers",
            None,
            1000.0,
            unit="mm",
            min_magnitude=1e-6,
            why="the head checks each against itself and its whiskers' reach",
        ),
        "whisk_frequency": Spec(
            "numbers",
            None,
            100.0,
            unit="Hz",
            min_magnitude=1e-6,
            why="rats whisk at up to about 25 Hz; the experiment refuses 0 and below",
        ),
        "n_seeds": _i(0, 1000, "sessions; 0 means one"),
    },
    "reproduce crunchbot-slam": {
        **REPRODUCE,
        "baseline": _no_baseline("crunchbot-slam"),
        "runs": Spec("numbers", 1, 1000, whole=True, why="the thesis ran 20"),
        "seconds": Spec(
            "numbers", 0.5, 3600.0, unit="s", why="one FSM step to an hour of robot time"
        ),
        "particles": Spec("numbers", 1, 10_000, whole=True, why="each carries its own map"),
    },
    "reproduce floor-texture": {
        **REPRODUCE,
        "floors": LIST,
        "n_seeds": _i(1, 1000, "sessions"),
    },
    "reproduce scratchbot": {
        **REPRODUCE,
        "baseline": _no_baseline("scratchbot"),
        "n_seeds": _i(1, 1000, "sessions"),
    },
    "run crunchbot": {
        "out": OUT_DIR,
        "arena": Spec("text", why="a preset name or an arena file, checked by the command"),
        "seconds": _n(0, 3600, "s", "up to an hour of robot time", open_low=True),
        "seed": SEED,
        "particles": _i(1, 10_000, "each particle carries its own map"),
        "mode": Spec("choice", choices=("blob", "geometric", "template")),
        "json_out": FLAG,
    },
}


#: What to lower when a command runs out of memory (MemoryError), by command.
MEMORY: dict[str, str] = {
    "generate": "--runs, the grid (--radial-distances, --speeds, --angles) or --workers",
    "import": "the recording's size (--crop keeps the shortest length)",
    "plot": "--dpi",
    "identify": "the grids (--quick)",
    "live": "the stream's rate or --max-seconds",
    "fit-pipeline": "the datasets' sizes",
    "whisker ring": "--duration-s, or raise --dt-ms",
    "whisker whisk": "--whisks or --control-rate-hz",
    "bench physics": "--duration-s",
    "run crunchbot": "--seconds or --particles",
    **{
        f"reproduce {name}": "--workers, or use --quick"
        for name in (
            "tactile-framework",
            "radial-distance",
            "angle-texture",
            "biotact-g1",
            "crunchbot-slam",
            "floor-texture",
            "scratchbot",
        )
    },
}


# ---------------------------------------------------------------------------- enforcing
def _flag_of(param: inspect.Parameter) -> str:
    """The option's long flag (``--out``) or the argument's name (``SOURCE``)."""
    infos = [param.default]
    annotation = param.annotation
    infos += list(getattr(annotation, "__metadata__", ()))
    for info in infos:
        if type(info).__name__ == "ArgumentInfo":
            return param.name.upper()
        decls = getattr(info, "param_decls", None)
        if decls is None:
            continue
        longs = [d for d in decls if isinstance(d, str) and d.startswith("--")]
        if longs:
            return max(longs, key=len)
    return "--" + param.name.replace("_", "-")


def _infos(param: inspect.Parameter) -> Iterator[Any]:
    yield param.default
    yield from getattr(param.annotation, "__metadata__", ())


def commands(app: typer.Typer, prefix: str = "") -> Iterator[tuple[str, Any]]:
    """Every command of ``app`` as (``"group command"``, its typer ``CommandInfo``)."""
    for info in app.registered_commands:
        name = info.name or info.callback.__name__.replace("_", "-")
        yield (f"{prefix} {name}".strip(), info)
    for group in app.registered_groups:
        sub = group.typer_instance
        name = group.name or (sub.info.name if sub is not None else None)
        if sub is not None:
            yield from commands(sub, f"{prefix} {name}".strip())


def enforce(app: typer.Typer) -> None:
    """Check every command's options against :data:`CONTRACT` before its body runs.

    Also appends each option's bounds to its help. Safe to call more than once.

    Raises
    ------
    KeyError
        A command or an option without a row in :data:`CONTRACT` (a programming error:
        the table must grow with the command line).
    """
    for path, info in commands(app):
        func = info.callback
        if getattr(func, "__vibrissa_contract__", None) is not None:
            continue
        table = CONTRACT[path]
        sig = inspect.signature(func)
        flags = {}
        for name, param in sig.parameters.items():
            spec = table[name]
            flags[name] = _flag_of(param)
            shown = spec.bounds_text()
            # brackets around words would be read as rich markup and vanish from the help
            shown = f"({shown})" if spec.kind == "refused" else f"[{shown}]" if shown else ""
            for opt in _infos(param):
                help_text = getattr(opt, "help", None)
                if shown and isinstance(help_text, str) and shown not in help_text:
                    opt.help = f"{help_text} {shown}"
        missing = set(table) - set(sig.parameters)
        if missing:
            raise KeyError(f"{path}: rows without an option: {sorted(missing)}")
        info.callback = _checked(func, sig, table, flags, path)


def _checked(
    func: Callable[..., Any],
    sig: inspect.Signature,
    table: dict[str, Spec],
    flags: dict[str, str],
    path: str,
) -> Callable[..., Any]:
    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        bound = sig.bind_partial(*args, **kwargs)
        try:
            for name, value in bound.arguments.items():
                table[name].check(flags[name], value)
        except ValueError as exc:
            print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
            raise typer.Exit(code=2) from None
        try:
            return func(*args, **kwargs)
        except MemoryError:
            lower = MEMORY.get(path, "the sizes of the work")
            print(f"error: out of memory; ask for less work: lower {lower}", file=sys.stderr)
            raise typer.Exit(code=2) from None

    wrapper.__vibrissa_contract__ = path  # type: ignore[attr-defined]
    return wrapper
