"""benchmarks/crunchbot_timestep.py: replaying recorded calls at every step, refusals."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import PoleContact, Trajectory


def _calls(path):
    # one recorded call as profile_crunchbot_calls.py pickles it: a pole driven 1.5 mm
    # into the crunchbot whisker, 100 mm out, at 50 mm/s
    model = RodModel(preset("crunchbot"), 16)
    traj = Trajectory.linear((-1.0, 100.0), (50.0, 0.0), 0.05)
    row = {"wall_s": 1.0, "failed": False}
    with path.open("wb") as fh:
        pickle.dump([(row, (model, PoleContact(), traj, 0.05, (), {"dt_s": 2.5e-4}))], fh)


def test_each_step_is_compared_with_the_finest(bench_script, tmp_path) -> None:
    ct = bench_script("crunchbot_timestep")
    calls, out = tmp_path / "calls.pkl", tmp_path / "out.json"
    _calls(calls)
    assert ct.main([str(calls), "--kind", "pole", "--out", str(out)]) == 0
    res = json.loads(out.read_text())
    assert res["kind"] == "pole" and res["calls"] == 1
    rows = res["rows"]
    assert [r["dt_us"] for r in rows] == [dt * 1e6 for dt in ct.STEPS_S]
    assert rows[-1]["tan_rel_rms_median"] == 0.0  # the reference itself
    assert all(r["calls"] == 1 and r["contact_share_mean"] > 0 for r in rows)
    assert np.isfinite([r["tan_rel_rms_median"] for r in rows]).all()


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["missing.pkl"], "no such file"),
        (["CALLS", "--top", "0"], "--top"),
        (["CORRUPT"], "not a pickle"),
        (["CALLS", "--kind", "x"], "--kind"),
        (["DIR"], "not a regular file"),
    ],
)
def test_bad_arguments_exit_2(bench_script, tmp_path, argv, says, capsys) -> None:
    ct = bench_script("crunchbot_timestep")
    calls = tmp_path / "calls.pkl"
    _calls(calls)
    corrupt = tmp_path / "corrupt.pkl"
    corrupt.write_bytes(calls.read_bytes()[:40])  # a truncated pickle
    named = {
        "CALLS": str(calls),
        "CORRUPT": str(corrupt),
        "DIR": str(tmp_path),
        "missing.pkl": str(tmp_path / "missing.pkl"),
    }
    with pytest.raises(SystemExit) as exc:
        ct.main([named.get(a, a) for a in argv])
    assert exc.value.code == 2
    assert says in capsys.readouterr().err
