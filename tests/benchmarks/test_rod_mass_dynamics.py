"""benchmarks/rod_mass_dynamics.py: the start of a release, and the speed rows."""

from __future__ import annotations

import importlib

import pytest

simulate_module = importlib.import_module("vibrissa.whisker.simulate")


def test_the_row_sum_start_is_passive_where_the_exact_one_overshoots(bench_script) -> None:
    rdm = bench_script("rod_mass_dynamics")
    ours = rdm.release("consistent", "row sums", 2.5e-4)
    exact = rdm.release("consistent", "exact", 2.5e-4)
    assert ours["max_pct"] <= 0.1  # the passivity test's allowance
    assert exact["first_step_pct"] > 0.1  # why simulate does not start from M^-1 F
    assert exact["first_step_pct"] > 10 * abs(ours["first_step_pct"])
    # the exact start is put in for the measurement only
    assert simulate_module._initial_acceleration.__name__ == "_initial_acceleration"


def test_speed_rows_name_their_rod(bench_script) -> None:
    rdm = bench_script("rod_mass_dynamics")
    row = rdm.speed("consistent", 8, 1)
    assert row["mass"] == "consistent" and row["n_elements"] == 8
    assert row["real_time_factor"] > 0 and row["newton_iterations"] > 0
    assert row["peak_follicle_moment_nm"] == pytest.approx(2.764e-3, rel=0.01)


@pytest.mark.parametrize("argv", [["--repeats", "0"], ["--repeats", "x"]])
def test_bad_arguments_exit_2(bench_script, argv, capsys) -> None:
    rdm = bench_script("rod_mass_dynamics")
    with pytest.raises(SystemExit) as exc:
        rdm.main(argv)
    assert exc.value.code == 2
    assert "--repeats" in capsys.readouterr().err
