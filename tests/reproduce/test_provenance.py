"""Tests of the code fingerprint of an experiment's results."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

from vibrissa.reproduce import provenance
from vibrissa.reproduce.provenance import code_fingerprint, git_commit, module_closure


def test_closure_follows_imports_and_skips_presentation() -> None:
    closure = module_closure("vibrissa.thesis.scratchbot")
    assert "vibrissa.thesis.scratchbot.protocol" in closure
    assert "vibrissa.robots.whisking" in closure  # imported by the protocol
    assert "vibrissa.whisker.rod" in closure  # through the robot, transitively
    assert "vibrissa.thesis.scratchbot.report" not in closure
    assert not any(m.startswith("vibrissa.cli") for m in closure)
    assert "vibrissa.robots.crunchbot.robot" not in closure


def test_fingerprint_is_stable_and_names_its_size() -> None:
    a = code_fingerprint("vibrissa.thesis.floor_texture")
    b = code_fingerprint("vibrissa.thesis.floor_texture")
    assert a == b
    assert len(str(a["digest"])) == 16
    assert a["modules"] == len(module_closure("vibrissa.thesis.floor_texture"))
    assert a != code_fingerprint("vibrissa.thesis.biotact_g1")


def test_code_changes_change_it_docstrings_do_not() -> None:
    # a throwaway copy of a real module under the vibrissa namespace: edit it, re-hash
    src = Path(provenance.__file__).parent.parent / "evaluate" / "spread.py"
    probe = Path(provenance.__file__).parent.parent / "evaluate" / "_fp_probe_tmp.py"
    try:
        shutil.copy(src, probe)
        before = code_fingerprint("vibrissa.evaluate._fp_probe_tmp")["digest"]
        provenance._parsed.cache_clear()
        probe.write_text(probe.read_text().replace('"""Results over', '"""Results (edited) over'))
        assert code_fingerprint("vibrissa.evaluate._fp_probe_tmp")["digest"] == before
        probe.write_text(probe.read_text().replace('SPREAD_KEY = "spread"', 'SPREAD_KEY = "s"'))
        assert code_fingerprint("vibrissa.evaluate._fp_probe_tmp")["digest"] != before
    finally:
        probe.unlink(missing_ok=True)
        provenance._parsed.cache_clear()
        sys.modules.pop("vibrissa.evaluate._fp_probe_tmp", None)


def test_refuses_a_foreign_or_missing_module() -> None:
    with pytest.raises(ValueError, match="vibrissa module"):
        module_closure("numpy")
    with pytest.raises(ValueError, match="no source file"):
        module_closure("vibrissa.no_such_module")


def test_git_commit_outside_a_checkout(tmp_path: Path) -> None:
    assert git_commit(tmp_path) is None


def test_a_packages_re_export_counts_where_it_is_made() -> None:
    """``from vibrissa.data import load_dataset`` counts vibrissa.data.netcdf, not the
    whole package with every importer (a change to the .mat reader staled every chapter-6
    result)."""
    closure = module_closure("vibrissa.thesis.scratchbot")
    assert "vibrissa.data.netcdf" in closure
    assert not any(m.startswith("vibrissa.data.importers") for m in closure)
    assert "vibrissa.data" not in closure
    # what the experiment does run is still there
    assert {"vibrissa.whisker.rod", "vibrissa.robots.whisking"} <= set(closure)
