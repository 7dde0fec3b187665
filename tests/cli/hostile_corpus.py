"""A corpus of hostile invocations of the ``vibrissa`` command line (issue 13).

Each case is a command line a careful new user might type that must be refused
before any work: exit status 2, exactly one non-empty line on standard error that
starts with ``error:`` and names the option or path at fault, no traceback, no file
created. Every case runs in an empty directory holding only the files it names in
``given`` (made by :data:`FIXTURES`); none may start a simulation.

Used by ``tests/cli/test_hostile_inputs.py`` (every case in process, a sample through
the installed console script) and ``scripts/hostile_inputs.py`` (every case through
the console script, with counts).
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class Case:
    """One hostile command line.

    Attributes
    ----------
    args
        The arguments after ``vibrissa``.
    names
        Text the error line must contain: the option or path at fault.
    given
        Names of :data:`FIXTURES` to create in the directory first.
    """

    args: tuple[str, ...]
    names: str
    given: tuple[str, ...] = ()

    @property
    def id(self) -> str:
        """A short readable id (for pytest)."""
        return " ".join(a if a else "''" for a in self.args)[:90]


# ------------------------------------------------------------------------ fixtures
def _hdf5_with_bad_root_attributes(path: Path) -> None:
    """An HDF5 file that opens but whose root attributes cannot be read.

    h5netcdf fails half-way through constructing its file object on such a file;
    the object's finaliser then printed a traceback after the error (issue 13,
    finding 7). The damage is placed by search, so the file's layout may change.
    """
    import h5py

    clean = path.with_name(".clean.h5")
    with h5py.File(clean, "w") as f:
        for k in range(40):
            f.attrs[f"attribute_{k:02d}"] = f"value {k} " * 8
        f.create_dataset("signal", data=np.arange(100.0))
    data = clean.read_bytes()
    clean.unlink()
    for start in range(64, len(data) - 64, 16):
        damaged = bytearray(data)
        damaged[start : start + 64] = bytes(64)
        path.write_bytes(bytes(damaged))
        try:
            f = h5py.File(path, "r")
        except Exception:  # not the kind of damage wanted
            continue
        with f:
            try:
                dict(f.attrs)
            except Exception:  # found: opens, attributes unreadable
                return
    raise RuntimeError("no damage that leaves the file openable but its attributes unreadable")


def _small_dataset(path: Path) -> None:
    """A valid vibrissa dataset of 18 synthetic trials (no simulation)."""
    import xarray as xr

    from vibrissa.data import save_dataset

    t = np.arange(-20, 40) / 1000.0
    rows = [(r, s) for r in (80.0, 120.0, 160.0) for s in (36.0, 72.0, 108.0)] * 2
    sig = np.stack(
        [
            np.stack([2.5 + (100 / r) * np.exp(-0.5 * (t / 0.004) ** 2), np.full_like(t, 2.5)])
            for r, _ in rows
        ]
    )
    ds = xr.Dataset(
        {"signal": (("trial", "channel", "time"), sig, {"units": "V"})},
        coords={
            "channel": ["x", "y"],
            "time": t,
            "radial_distance_mm": ("trial", [r for r, _ in rows]),
            "speed_mm_s": ("trial", [s for _, s in rows]),
        },
        attrs={"sample_rate_hz": 1000.0},
    )
    save_dataset(ds, path)


def _example_recording(path: Path) -> None:
    from vibrissa.examples import example_path

    shutil.copyfile(example_path("data_XY_small.mat"), path)


def _bytes(content: bytes) -> Callable[[Path], None]:
    return lambda path: path.write_bytes(content)


_GARBAGE = bytes(np.random.default_rng(13).integers(0, 256, 4096, dtype=np.uint8))

#: File name -> function that makes it (a name ending in "/" is a directory).
FIXTURES: dict[str, Callable[[Path], None]] = {
    "dir/": lambda path: path.mkdir(),
    # a named pipe stands for any file that is not a regular one (devices such as
    # /dev/null, which the old main would have replaced by a plain file)
    "fifo": os.mkfifo,
    "file.txt": _bytes(b"precious\n"),
    "empty.nc": _bytes(b""),
    "garbage.nc": _bytes(_GARBAGE),
    "hdf5-garbage.nc": _bytes(b"\x89HDF\r\n\x1a\n" + _GARBAGE),
    "netcdf3-garbage.nc": _bytes(b"CDF\x01" + _GARBAGE),
    "bad-attributes.nc": _hdf5_with_bad_root_attributes,
    "ds.nc": _small_dataset,
    "empty.mat": _bytes(b""),
    "garbage.mat": _bytes(_GARBAGE),
    "hdf5-garbage.mat": _bytes(b"\x89HDF\r\n\x1a\n" + _GARBAGE),
    "data.mat": _example_recording,
    "file.xyz": _bytes(b"1,2,3\n"),
    "not-json.json": _bytes(b"{this is not json"),
    "not-toml.toml": _bytes(b"[[[ not toml"),
    "unknown-keys.json": _bytes(json.dumps({"signal": "data", "colour": "blue"}).encode()),
    "no-classifiers.json": _bytes(json.dumps({"meta": {}}).encode()),
    # CrunchBot arena files (issue 16): an unknown tile texture, overlapping obstacles,
    # the robot starting inside an obstacle
    "bad-texture.toml": _bytes(
        b'size_m = 1.0\ntiles = [["vinyl", "velvet"], '
        b'["vinyl", "vinyl"]]\nstart = {x_m = 0.3, y_m = 0.3}\n'
    ),
    "overlap.toml": _bytes(
        b"size_m = 1.25\nstart = {x_m = 0.2, y_m = 0.2}\n"
        b"[[obstacles]]\nx_m = 0.5\ny_m = 0.5\nsize_m = 0.3\n"
        b"[[obstacles]]\nx_m = 0.6\ny_m = 0.6\nsize_m = 0.3\n"
    ),
    "inside.json": _bytes(
        json.dumps(
            {
                "size_m": 1.25,
                "start": {"x_m": 0.6, "y_m": 0.6},
                "obstacles": [{"x_m": 0.5, "y_m": 0.5, "size_m": 0.25}],
            }
        ).encode()
    ),
}


def prepare(directory: Path, given: Iterable[str]) -> None:
    """Make the fixtures ``given`` in ``directory``."""
    for name in given:
        FIXTURES[name](directory / name.rstrip("/"))


# --------------------------------------------------------------------------- cases
def _framework_cases(add: Callable[..., None]) -> None:
    """fit-pipeline, live and reproduce tactile-framework (issue 29)."""
    fp = ["fit-pipeline", "--out", "p.vtp"]
    add(fp, "--where")
    add([*fp, "--where", "missing.nc"], "missing.nc")
    add([*fp, "--where", "dir"], "dir", "dir/")
    add([*fp, "--where", "fifo"], "fifo", "fifo")
    add([*fp, "--where", "garbage.nc"], "garbage.nc", "garbage.nc")
    add([*fp, "--what", "ds.nc"], "what", "ds.nc")
    for value in ("2", "0", "nan"):
        add(
            [*fp, "--where", "ds.nc", "--decision-threshold", value],
            "--decision-threshold",
            "ds.nc",
        )
    add([*fp, "--where", "ds.nc", "--tip-zone-mm", "-1"], "--tip-zone-mm", "ds.nc")
    add("fit-pipeline --where ds.nc --out dir", "dir", "ds.nc", "dir/")
    add("live", "--pipeline")
    add("live --pipeline missing.vtp", "missing.vtp")
    add("live --pipeline garbage.nc", "--pipeline", "garbage.nc")
    add("live --pipeline fifo", "fifo", "fifo")
    add("live --pipeline dir", "dir", "dir/")
    tf = ["reproduce", "tactile-framework", "--quick", "--out", "r"]
    add([*tf, "--seed", "-1"], "--seed")
    add([*tf, "--workers", "0"], "--workers")
    add([*tf, "--scheduler", "tcp://h:8786"], "--scheduler")


def _cases() -> list[Case]:
    c: list[Case] = []

    def add(args: str | list[str], names: str, *given: str) -> None:
        c.append(Case(tuple(args.split() if isinstance(args, str) else args), names, given))

    # the top level
    add("--bogus", "--bogus")
    add("bogus-command", "bogus-command")
    # whisker: geometry options, each command's own options
    add("whisker bogus", "bogus")
    add("whisker presets extra", "extra")
    add("whisker presets --json=3", "--json")
    add("whisker info --preset nope", "--preset")
    add(["whisker", "info", "--preset", ""], "--preset")
    for value in ("abc", "", "nan", "inf", "-1", "0", "1e300", "1e20", "0.5"):
        add(["whisker", "info", "--length-mm", value], "--length-mm")
    for value in ("0", "1e300", "nan", "1e-300"):
        add(["whisker", "info", "--base-radius-mm", value], "--base-radius-mm")
    add("whisker info --tip-radius-mm 2", "--tip-radius-mm")
    for value in ("-1", "1e300", "abc", "1e-300"):
        add(["whisker", "info", "--youngs-modulus-gpa", value], "--youngs-modulus-gpa")
    for value in ("1e300", "0", "1e-300"):
        add(["whisker", "info", "--density-kg-m3", value], "--density-kg-m3")
    for value in ("0.7", "1.5", "-0.1", "nan"):
        add(["whisker", "info", "--damping-ratio", value], "--damping-ratio")
    for value in ("0", "3", "401", "abc", "1000000000", "-5"):
        add(["whisker", "info", "--n-elements", value], "--n-elements")
    add("whisker info --rigid-follicle=yes", "--rigid-follicle")
    add("whisker static", "--force-n")
    add("whisker static --force-n 1", "--at-mm")
    for value in ("nan", "inf", "abc"):
        add(["whisker", "static", "--force-n", value, "--at-mm", "100"], "--force-n")
    for value in ("0", "-5", "1e9", "nan"):
        add(["whisker", "static", "--force-n", "1", "--at-mm", value], "--at-mm")
    push = "whisker push --at-mm 150 --displacement-mm 60"
    add("whisker push --at-mm 150 --displacement-mm -1", "--displacement-mm")
    add("whisker push --at-mm 150 --displacement-mm nan", "--displacement-mm")
    add("whisker push --at-mm 500 --displacement-mm 1", "--at-mm")
    add(f"{push} --friction -1", "--friction")
    add(f"{push} --friction inf", "--friction")
    for value in ("0", "-1", "1e6", "nan"):
        add(f"{push} --pole-radius-mm {value}", "--pole-radius-mm")
    for value in ("1e9", "0", "-1", "nan", "abc", "0.001"):
        add(["whisker", "ring", "--duration-s", value], "--duration-s")
    for value in ("0", "2", "nan"):
        add(["whisker", "ring", "--dt-ms", value], "--dt-ms")
    for value in ("0", "1e9", "nan"):
        add(["whisker", "ring", "--tip-deflection-mm", value], "--tip-deflection-mm")
    # whisk (issue 15): frequency <= 0, negative gains, a pole inside the reach at rest
    for value in ("0", "-2", "nan", "1e-9"):
        add(["whisker", "whisk", "--frequency-hz", value], "--frequency-hz")
    add("whisker whisk --control-rate-hz 1e12", "--control-rate-hz")
    for value in ("-0.7", "nan"):
        add(["whisker", "whisk", "--sigma-z", value], "--sigma-z")
    add("whisker whisk --tau-z-periods 0", "--tau-z-periods")
    add("whisker whisk --pole-at-mm 100 --pole-angle-deg 0", "--pole-angle-deg")
    add("whisker whisk --pole-at-mm 100 --pole-angle-deg 45", "--pole-angle-deg")
    add("whisker whisk --pole-at-mm 500", "--pole-at-mm")
    add("whisker whisk --whisks 0", "--whisks")
    # bench
    add("bench bogus", "bogus")
    for value in ("0.3", "0", "-1", "nan", "0.0000025"):
        add(["bench", "physics", "--dt-ms", value], "--dt-ms")
    for value in ("0", "1000"):
        add(["bench", "physics", "--n-elements", value], "--n-elements")
    for value in ("0", "abc", "1000000"):
        add(["bench", "physics", "--repeats", value], "--repeats")
    for value in ("-1", "1e9", "nan"):
        add(["bench", "physics", "--duration-s", value], "--duration-s")
    # generate
    rd = ["generate", "radial-distance", "--out", "x.nc"]
    at = ["generate", "angle-texture", "--out", "x.nc"]
    add("generate", "PROTOCOL")
    add("generate radial-distance", "--out")
    add("generate bogus --out x.nc", "bogus")
    add(["generate", "", "--out", "x.nc"], "PROTOCOL")
    add([*rd, "--textures", "p80"], "--textures")
    add([*at, "--radial-distances", "5000"], "--radial-distances")
    add([*rd, "--radial-distances", ""], "--radial-distances")
    add([*at, "--textures", ""], "--textures")
    add([*rd, "--speeds", "1:2:#100000000"], "--speeds")
    add([*rd, "--speeds", "50:100:0.0000001"], "--speeds")
    add([*rd, "--runs", "1000000000"], "--runs")
    add([*rd, "--speeds", "100,100,100"], "--speeds")
    for value in ("0", "-1", "abc", "1000000"):
        add([*rd, "--quick", "--workers", value], "--workers")
    for value in ("-1", "abc", "1.5"):
        add([*rd, "--quick", "--seed", value], "--seed")
    for value in ("nan", "inf", "-5", "abc", "80:200:20", "1e400", "5:1:1", "1:2:#0"):
        add([*rd, "--radial-distances", value], "--radial-distances")
    for value in ("0", "1e9", "-36"):
        add([*rd, "--speeds", value], "--speeds")
    for value in ("95", "-10", "nan"):
        add([*at, "--angles", value], "--angles")
    add([*at, "--textures", "velvet"], "--textures")
    for value in ("0", "-1", "nan", "inf", "3000", "abc", "1e300"):
        add([*rd, "--sample-rate-hz", value], "--sample-rate-hz")
    for value in ("-0.1", "nan", "inf"):
        add([*rd, "--noise-v", value], "--noise-v")
    for value in ("nan", "5"):
        add([*rd, "--drift", value], "--drift")
    add([*rd, "--whisker", "nope"], "--whisker")
    add([*rd, "--whisker", ""], "--whisker")
    for value in ("0", "abc"):
        add([*rd, "--quick", "--chunk-size", value], "--chunk-size")
    add([*rd, "--quick", "--scheduler", "nonsense"], "--scheduler")
    add([*rd, "--restart=3"], "--restart")
    add("generate radial-distance --quick --out dir", "dir", "dir/")
    add(["generate", "radial-distance", "--quick", "--out", ""], ". is a directory")
    add("generate radial-distance --quick --out file.txt/x.nc", "file.txt", "file.txt")
    add("generate radial-distance --quick --out /proc/x.nc", "/proc")
    add("generate radial-distance --quick --out /sys/x.nc", "/sys")
    add("generate radial-distance --quick --out fifo", "fifo", "fifo")
    # import
    imp = ["import", "data.mat", "--out", "x.nc"]
    add("import", "SOURCE")
    add("import data.mat", "--out", "data.mat")
    add("import missing.mat --out x.nc", "missing.mat")
    add("import dir --out x.nc", "dir", "dir/")
    add("import empty.mat --out x.nc", "empty.mat", "empty.mat")
    add("import garbage.mat --out x.nc", "garbage.mat", "garbage.mat")
    add("import hdf5-garbage.mat --out x.nc", "hdf5-garbage.mat", "hdf5-garbage.mat")
    add("import file.xyz --out x.nc", "file.xyz", "file.xyz")
    add([*imp, "--format", "bogus"], "--format", "data.mat")
    add([*imp, "--mapping", "missing.json"], "missing.json", "data.mat")
    add([*imp, "--mapping", "dir"], "dir", "data.mat", "dir/")
    add([*imp, "--mapping", "not-json.json"], "not-json.json", "data.mat", "not-json.json")
    add([*imp, "--mapping", "not-toml.toml"], "not-toml.toml", "data.mat", "not-toml.toml")
    add([*imp, "--mapping", "unknown-keys.json"], "colour", "data.mat", "unknown-keys.json")
    for value in ("nan", "-1", "0", "abc", "inf"):
        add([*imp, "--sample-rate-hz", value], "--sample-rate-hz", "data.mat")
    for value in ("2", "abc"):
        add([*imp, "--time-axis", value], "--time-axis", "data.mat")
    add([*imp, "--axis", "bad"], "--axis", "data.mat")
    add([*imp, "--label", "bad"], "--label", "data.mat")
    add([*imp, "--const", "=3"], "--const", "data.mat")
    add([*imp, "--t0-s", "nan"], "--t0-s", "data.mat")
    add([*imp, "--channels", ""], "--channels", "data.mat")
    add("import data.mat --out dir", "dir", "data.mat", "dir/")
    add("import data.mat --out file.txt/x.nc", "file.txt", "data.mat", "file.txt")
    add("import data.mat --out /proc/x.nc", "/proc", "data.mat")
    add("import data.mat --out fifo", "fifo", "data.mat", "fifo")
    # plot
    add("plot", "DATASET")
    add("plot missing.nc --out o", "missing.nc")
    add("plot dir --out o", "dir", "dir/")
    for name in (
        "empty.nc",
        "garbage.nc",
        "hdf5-garbage.nc",
        "netcdf3-garbage.nc",
        "bad-attributes.nc",
        "file.txt",
    ):
        add(f"plot {name} --out o", name, name)
    add("plot ds.nc --out file.txt", "file.txt", "ds.nc", "file.txt")
    add("plot ds.nc --out file.txt/o", "file.txt", "ds.nc", "file.txt")
    add("plot ds.nc --out /proc/o", "/proc", "ds.nc")
    add("plot ds.nc --out o --kind bogus", "--kind", "ds.nc")
    for value in ("0", "abc", "100000"):
        add(["plot", "ds.nc", "--out", "o", "--dpi", value], "--dpi", "ds.nc")
    for value in ("99", "z"):
        add(["plot", "ds.nc", "--out", "o", "--channel", value], "--channel", "ds.nc")
    # reproduce
    rp = ["reproduce", "radial-distance", "--quick", "--out", "r"]
    add("reproduce bogus", "bogus")
    for value in ("-1", "abc"):
        add([*rp, "--seed", value], "--seed")
    for value in ("0", "1000000"):
        add([*rp, "--workers", value], "--workers")
    add([*rp, "--n-seeds", "0"], "--n-seeds")
    add("reproduce angle-texture --quick --n-seeds 3", "--n-seeds")
    add("reproduce radial-distance --quick --out file.txt", "file.txt", "file.txt")
    add("reproduce radial-distance --quick --out file.txt/r", "file.txt", "file.txt")
    add("reproduce radial-distance --quick --out /proc/r", "/proc")
    add([*rp, "--baseline", "missing.json"], "missing.json")
    add([*rp, "--baseline", "dir"], "dir", "dir/")
    add([*rp, "--baseline", "not-json.json"], "not-json.json", "not-json.json")
    add([*rp, "--baseline", "no-classifiers.json"], "no-classifiers.json", "no-classifiers.json")
    # the robots of chapter 6
    ft = ["reproduce", "floor-texture", "--quick", "--out", "r"]
    add([*ft, "--floors", "vinyl,shag"], "--floors")
    add([*ft, "--floors", "vinyl"], "--floors")
    add([*ft, "--floors", "vinyl,vinyl"], "--floors")
    add([*ft, "--floors", ""], "--floors")
    add([*ft, "--n-seeds", "0"], "--n-seeds")
    for value in ("-1", "abc"):
        add(["reproduce", "scratchbot", "--quick", "--out", "r", "--seed", value], "--seed")
    add("reproduce scratchbot --quick --out r --workers 0", "--workers")
    add("reproduce scratchbot --quick --out file.txt", "file.txt", "file.txt")
    # crunchbot (issue 16): vibrissa run crunchbot and vibrissa reproduce crunchbot-slam
    rc = ["run", "crunchbot", "--seconds", "5", "--out", "o"]
    add([*rc, "--arena", "bad-texture.toml"], "velvet", "bad-texture.toml")
    add([*rc, "--arena", "overlap.toml"], "overlap.toml", "overlap.toml")
    add([*rc, "--arena", "inside.json"], "inside.json", "inside.json")
    add([*rc, "--arena", "missing.toml"], "missing.toml")
    add([*rc, "--arena", "nowhere"], "--arena")
    add([*rc, "--arena", "file.txt"], "--arena", "file.txt")
    for value in ("0", "-3", "abc"):
        add([*rc, "--particles", value], "--particles")
    for value in ("-1", "0", "nan", "inf", "abc", "0.001", "1e300"):
        add(["run", "crunchbot", "--out", "o", "--seconds", value], "--seconds")
    add([*rc, "--particles", "1000000000000"], "--particles")
    add([*rc, "--seed", "18446744073709551616"], "--seed")
    add(["generate", "radial-distance", "--quick", "--out", "g.nc", "--seed", str(2**64)], "--seed")
    add(["reproduce", "radial-distance", "--quick", "--out", "r", "--seed", str(2**64)], "--seed")
    add([*rc, "--mode", "bogus"], "--mode")
    add([*rc, "--seed", "-1"], "--seed")
    add("run crunchbot --seconds 5 --out file.txt", "file.txt", "file.txt")
    add("run crunchbot --seconds 5", "--out")
    cs = ["reproduce", "crunchbot-slam", "--quick", "--out", "r"]
    for value in ("0", "-3", "2.5", "abc"):
        add([*cs, "--particles", value], "--particles")
    for value in ("-1", "0"):
        add([*cs, "--seconds", value], "--seconds")
    for value in ("0", "1,2"):
        add([*cs, "--runs", value], "--runs")
    for value in ("nonsense", "tcp://host", ""):
        add([*cs, "--scheduler", value], "--scheduler")
    add(
        ["reproduce", "radial-distance", "--quick", "--out", "r", "--scheduler", "x y:1"],
        "--scheduler",
    )
    # scratchbot simulates its conditions on local processes only
    add(
        ["reproduce", "scratchbot", "--quick", "--out", "r", "--scheduler", "tcp://h:8786"],
        "--scheduler",
    )
    _framework_cases(add)
    # identify
    add("identify extra", "extra")
    add("identify --bogus", "--bogus")
    add("identify --quick=1", "--quick")
    return c


#: Every hostile invocation.
CASES: list[Case] = _cases()


# -------------------------------------------------------------------------- outcome
@dataclass
class Outcome:
    """What one invocation did."""

    case: Case
    exit_code: int
    stderr: str
    new_files: list[str]

    @property
    def lines(self) -> list[str]:
        """Non-empty lines on standard error."""
        return [line for line in self.stderr.splitlines() if line.strip()]

    @property
    def traceback(self) -> bool:
        """Whether a traceback was printed."""
        return "Traceback" in self.stderr

    @property
    def one_line(self) -> bool:
        """Exactly one line, ``error: ...``, naming the option or path."""
        lines = self.lines
        return len(lines) == 1 and lines[0].startswith("error:") and self.case.names in lines[0]

    @property
    def refused_cleanly(self) -> bool:
        """Exit status 2, one line naming the culprit, no traceback, nothing created."""
        return self.exit_code == 2 and self.one_line and not self.traceback and not self.new_files

    def problem(self) -> str:
        """What is wrong with the outcome (empty if refused cleanly)."""
        if self.refused_cleanly:
            return ""
        return (
            f"vibrissa {self.case.id}: exit {self.exit_code}, files {self.new_files}, "
            f"stderr {self.stderr!r}"
        )


def _files(directory: Path) -> set[str]:
    return {str(p.relative_to(directory)) for p in directory.rglob("*")}


def run_in_process(case: Case, directory: Path) -> Outcome:
    """Run ``case`` with typer's test runner in ``directory`` (made empty by the caller)."""
    from typer.testing import CliRunner

    from vibrissa.cli import app

    prepare(directory, case.given)
    before = _files(directory)
    with contextlib.chdir(directory):
        res = CliRunner().invoke(app, list(case.args))
    stderr = res.stderr
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        stderr += f"\nTraceback: {type(res.exception).__name__}: {res.exception}"
    return Outcome(case, res.exit_code, stderr, sorted(_files(directory) - before))


def run_console(case: Case, directory: Path, executable: str, timeout_s: float = 300) -> Outcome:
    """Run ``case`` through the installed ``vibrissa`` console script in ``directory``."""
    prepare(directory, case.given)
    before = _files(directory)
    env = {**os.environ, "CI": "1"}
    try:
        proc = subprocess.run(
            [executable, *case.args],
            cwd=directory,
            capture_output=True,
            text=True,
            timeout=timeout_s,
            env=env,
        )
    except subprocess.TimeoutExpired as exc:
        err = exc.stderr.decode() if isinstance(exc.stderr, bytes) else (exc.stderr or "")
        return Outcome(
            case,
            -1,
            err + f"\n(timed out after {timeout_s:g} s)",
            sorted(_files(directory) - before),
        )
    return Outcome(case, proc.returncode, proc.stderr, sorted(_files(directory) - before))
