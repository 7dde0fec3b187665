"""benchmarks/profile_kernels.py: attributes samples to functions, checks options first."""

from __future__ import annotations

import json

import pytest

MANGLED = "_ZN8vibrissa7whisker8_kernels{}{}B3v61B38c8tJTIeFIjxB2IKSgI4CrvQClQZ6FczSBAA_3dE5Array"


def _name(python_name: str) -> str:
    return MANGLED.format(len(python_name), python_name)


def test_samples_go_to_the_function_whose_code_holds_them(bench_script) -> None:
    bench = bench_script("profile_kernels")
    table = [(0x1000, _name("band_factor")), (0x2000, _name("add_plane")), (0x500, "NRT_incref")]
    samples = [
        (0x1000, "[JIT] tid 7"),  # a function's first byte
        (0x1FFF, "[JIT] tid 7"),  # its last
        (0x2004, "/tmp/perf-7.map"),
        (0x2008, "[unknown]"),
        (0x0600, "[JIT] tid 7"),
        (0x2004, "/usr/lib/x86_64-linux-gnu/libc.so.6"),  # a shared object, whatever its address
        (0x9000000, "[JIT] tid 7"),  # far beyond the library: other compiled code
        (0x10, "[JIT] tid 7"),  # below every function
    ]
    counts = bench.attribute(samples, table)
    assert counts == {
        "band_factor": 2,
        "add_plane": 2,
        "so:[JIT] tid 7": 2,
        "NRT_incref": 1,
        "so:libc.so.6": 1,
    }
    assert list(counts)[0] in ("band_factor", "add_plane", "so:[JIT] tid 7")  # most first


def test_perf_script_lines_are_parsed_and_junk_skipped(bench_script) -> None:
    bench = bench_script("profile_kernels")
    text = "    7f10b9a13000 ([JIT] tid 18395)\n\n  zz (x)\n 7f10 (/usr/lib/libc.so.6)\n"
    assert bench._parse_perf_script(text) == [
        (0x7F10B9A13000, "[JIT] tid 18395"),
        (0x7F10, "/usr/lib/libc.so.6"),
    ]


@pytest.mark.parametrize(
    "args",
    [
        ["--seconds", "0"],
        ["--seconds", "nan"],
        ["--seconds", "601"],
        ["--frequency", "10"],
        ["--case", "pole"],
    ],
)
def test_bad_options_are_refused_before_any_work(bench_script, tmp_path, monkeypatch, args):
    bench = bench_script("profile_kernels")
    monkeypatch.setattr(bench, "profile_case", lambda *a: pytest.fail("ran before checking"))
    out = tmp_path / "k.json"
    with pytest.raises(SystemExit) as exc:
        bench.main([*args, "--out", str(out)])
    assert exc.value.code == 2
    assert not out.exists()


def test_a_machine_without_perf_is_told_how_to_get_it(bench_script, tmp_path, monkeypatch, capsys):
    bench = bench_script("profile_kernels")
    monkeypatch.setattr(bench.shutil, "which", lambda name: None)
    with pytest.raises(SystemExit) as exc:
        bench.main(["--out", str(tmp_path / "k.json")])
    assert exc.value.code == 2
    assert "linux-perf" in capsys.readouterr().err


def test_writes_each_case_and_the_machine(bench_script, tmp_path, monkeypatch) -> None:
    bench = bench_script("profile_kernels")
    monkeypatch.setattr(bench.shutil, "which", lambda name: "/usr/bin/perf")
    monkeypatch.setattr(bench, "profile_case", lambda c, s, f: {"share": {"add_plane": 1.0}})
    out = tmp_path / "k.json"
    assert bench.main(["--case", "floor", "--seconds", "2", "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert list(doc["cases"]) == ["floor"]
    assert doc["cases"]["floor"]["share"] == {"add_plane": 1.0}
    assert doc["machine"]["cores"] >= 1 and "load_average_at_start" in doc
