"""benchmarks/compile_timeline.py: pairs numba's compile events, checks options first."""

from __future__ import annotations

import pytest


def test_nested_compilations_are_paired_and_only_top_level_ones_are_summed(bench_script) -> None:
    bench = bench_script("compile_timeline")
    events = [
        ["start", 1.0, 0, "m.outer"],
        ["start", 1.5, 1, "m.inner"],
        ["end", 3.5, 1, "m.inner"],
        ["end", 6.0, 0, "m.outer"],
        ["start", 7.0, 0, "m.other"],
        ["end", 7.25, 0, "m.other"],
    ]
    rows = bench.compilations(events)
    assert [(r["function"], r["depth"]) for r in rows] == [
        ("m.outer", 0),
        ("m.inner", 1),
        ("m.other", 0),
    ]
    assert [r["seconds"] for r in rows] == pytest.approx([5.0, 2.0, 0.25])
    assert bench.compile_seconds(rows) == pytest.approx(5.25)


@pytest.mark.parametrize(
    "events",
    [
        [["end", 1.0, 0, "m.f"]],
        [["start", 1.0, 0, "m.f"]],
        [["start", 1.0, 0, "m.f"], ["end", 2.0, 0, "m.g"]],
    ],
)
def test_unpaired_events_are_an_error_naming_the_function(bench_script, events) -> None:
    with pytest.raises(ValueError, match="m.f"):
        bench_script("compile_timeline").compilations(events)


def test_an_unknown_experiment_exits_2_before_any_run(bench_script, tmp_path, capsys) -> None:
    bench = bench_script("compile_timeline")
    out = tmp_path / "t.json"
    with pytest.raises(SystemExit) as exc:
        bench.main(["--experiment", "no-such-thing", "--out", str(out)])
    assert exc.value.code == 2
    assert "no-such-thing" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("kind", ["directory", "fifo", "missing-parent"])
def test_an_out_that_is_not_a_writable_file_exits_2_before_any_run(
    bench_script, tmp_path, capsys, kind
) -> None:
    import os

    out = tmp_path / "out"
    if kind == "directory":
        out.mkdir()
    elif kind == "fifo":
        os.mkfifo(out)
    else:
        out = tmp_path / "no" / "out.json"
    with pytest.raises(SystemExit) as exc:
        bench_script("compile_timeline").main(["--out", str(out)])
    assert exc.value.code == 2
    assert "--out" in capsys.readouterr().err
