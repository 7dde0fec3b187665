"""The ledger of thesis claims is rendered from the run files, never typed by hand.

``scripts/thesis_claims.py`` evaluates ``vibrissa.thesis.claims`` on ``docs/runs`` and
writes ``docs/runs/claims.json``; ``docs/templates/thesis_claims.md`` prints its table.
"""

from __future__ import annotations

import importlib.util
import json
import re
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "scripts" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


render_docs = _load("render_docs")
thesis_claims = _load("thesis_claims")
TEMPLATE = ROOT / "docs" / "templates" / "thesis_claims.md"


def _row(doc: str, claim_id: str) -> str:
    rows = [r for r in doc.splitlines() if f'<a id="claim-{claim_id}"></a>' in r]
    assert len(rows) == 1, claim_id
    return rows[0]


def _status(row: str) -> str:
    return re.search(r"\*\*(holds|does not hold|not measured)\*\*", row).group(1)


def test_committed_claims_file_is_the_evaluation_of_the_committed_runs():
    assert thesis_claims.main(["--check"]) == 0, (
        "docs/runs/claims.json is stale: run `.venv/bin/python scripts/thesis_claims.py` "
        "and `.venv/bin/python scripts/render_docs.py`"
    )


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_changing_a_run_value_flips_the_rendered_status(tmp_path, factor):
    runs = tmp_path / "runs"
    shutil.copytree(ROOT / "docs" / "runs", runs)
    path = runs / "chapter4.json"
    data = json.loads(path.read_text())
    clfs = data["classifiers"]
    raw = clfs["naive_bayes_raw"]["radius_mm"]["std"]
    clfs["naive_bayes_velocity"]["radius_mm"]["std"] = raw * factor
    path.write_text(json.dumps(data))
    assert thesis_claims.main(["--runs", str(runs)]) == 0
    doc = render_docs.render(TEMPLATE, runs)
    row = _row(doc, "velocity-beats-raw-radius")
    assert _status(row) == ("holds" if factor < 1 else "does not hold")
    assert f"{raw * factor:.2f} mm (velocity)" in row


def test_removing_a_run_file_makes_its_claims_not_measured(tmp_path):
    runs = tmp_path / "runs"
    shutil.copytree(ROOT / "docs" / "runs", runs)
    (runs / "crunchbot_slam.json").unlink()
    assert thesis_claims.main(["--runs", str(runs)]) == 0
    doc = render_docs.render(TEMPLATE, runs)
    row = _row(doc, "map-error-ordering")
    assert _status(row) == "not measured"
    assert "crunchbot_slam.map_error.template.mean" in row


def test_every_claim_has_one_row_in_the_committed_doc():
    from vibrissa.thesis.claims import CLAIMS

    doc = (ROOT / "docs" / "thesis_claims.md").read_text(encoding="utf-8")
    for claim in CLAIMS:
        _status(_row(doc, claim.id))
