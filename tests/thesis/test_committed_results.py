"""The committed chapter-6 results were made by today's code, with their command and commit.

Each file in ``docs/runs`` of a chapter-6 reproduction stores, in ``meta.code``, the
fingerprint of the modules its experiment imports (:mod:`vibrissa.reproduce.provenance`).
Recomputing it on the checkout tells whether the result is still evidence for this code:
when a module the experiment depends on changes what it computes, this test fails until
the result is made again (the failure names the command to run).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vibrissa.reproduce.provenance import code_fingerprint

RUNS = Path(__file__).resolve().parents[2] / "docs" / "runs"
#: Run file -> the experiment package that makes it.
CHAPTER6 = {
    "floor_texture": "vibrissa.thesis.floor_texture",
    "scratchbot": "vibrissa.thesis.scratchbot",
    "biotact_g1": "vibrissa.thesis.biotact_g1",
    "crunchbot_slam": "vibrissa.thesis.crunchbot_slam",
}


@pytest.mark.parametrize("name", sorted(CHAPTER6))
def test_committed_result_was_made_by_this_code(name: str) -> None:
    path = RUNS / f"{name}.json"
    assert path.is_file(), f"{path} is missing: run the reproduction and commit its results.json"
    meta = json.loads(path.read_text())["meta"]
    assert meta.get("command"), f"{name}: no command recorded"
    assert meta.get("commit"), f"{name}: no commit recorded"
    assert not meta.get("quick"), f"{name}: a --quick run is no evidence"
    code = meta.get("code") or {}
    assert code.get("package") == CHAPTER6[name]
    now = code_fingerprint(CHAPTER6[name])
    assert code.get("digest") == now["digest"], (
        f"docs/runs/{name}.json was made by other code (fingerprint {code.get('digest')}, "
        f"this checkout {now['digest']}): rerun `{meta['command']}` and commit its results.json"
    )
