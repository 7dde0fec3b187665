"""The README benchmark times the command a new user would copy."""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _module():
    spec = importlib.util.spec_from_file_location(
        "bench_readme", ROOT / "benchmarks" / "bench_readme_first_command.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_it_reads_the_readme_s_first_command():
    cmd = _module().first_command((ROOT / "README.md").read_text())
    assert cmd.startswith("python3 -m venv .venv")
    assert "vibrissa reproduce" in cmd


def test_a_readme_without_a_bash_block_is_refused():
    with pytest.raises(ValueError, match="bash"):
        _module().first_command("# nothing here\n")
