"""Tests of vibrissa._address_space (a memory limit too low for the libraries to load)."""

from __future__ import annotations

import resource
import subprocess
import sys

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vibrissa._address_space import BASE_MIB, PER_THREAD_MIB, THREADS_VAR, Plan, plan


def test_no_limit_changes_nothing() -> None:
    env: dict[str, str] = {}
    assert plan(None, env, cpus=64) == Plan()
    assert env == {}


def test_a_generous_limit_changes_nothing() -> None:
    assert plan(BASE_MIB + PER_THREAD_MIB * 8, {}, cpus=8) == Plan()


def test_a_tight_limit_starts_as_many_threads_as_fit() -> None:
    assert plan(BASE_MIB + PER_THREAD_MIB * 3 + 1, {}, cpus=64) == Plan(threads=3)
    assert plan(BASE_MIB + PER_THREAD_MIB, {}, cpus=2) == Plan(threads=1)


def test_below_one_thread_is_refused_naming_the_limit() -> None:
    p = plan(200.0, {}, cpus=2)
    assert p.threads is None
    assert p.error is not None and p.error.startswith("error: the memory limit")
    assert "200 MiB" in p.error and f"{BASE_MIB + PER_THREAD_MIB} MiB" in p.error


def test_the_users_thread_count_is_kept_or_named() -> None:
    assert plan(BASE_MIB + PER_THREAD_MIB * 2, {THREADS_VAR: "2"}, cpus=64) == Plan()
    p = plan(BASE_MIB + PER_THREAD_MIB * 2, {THREADS_VAR: "16"}, cpus=64)
    assert p.error is not None and f"{THREADS_VAR}=16" in p.error


@given(st.floats(0, 1e7), st.integers(1, 512), st.sampled_from(["", "0", "x", "3", "-2"]))
def test_the_plan_fits_the_limit_or_refuses(limit: float, cpus: int, given_threads: str) -> None:
    p = plan(limit, {THREADS_VAR: given_threads} if given_threads else {}, cpus=cpus)
    if p.error is None and p.threads is not None:
        assert 1 <= p.threads <= cpus
        assert BASE_MIB + PER_THREAD_MIB * p.threads <= limit
    if p.error is not None:
        assert p.threads is None and "\n" not in p.error


@pytest.mark.parametrize("which", ["RLIMIT_AS", "RLIMIT_DATA"])
def test_the_console_refuses_in_one_line_instead_of_hanging(tmp_path, which) -> None:
    """Issue 33: under ``ulimit -v 200000`` ``identify`` spun in OpenBLAS' allocation
    retries and ignored SIGTERM (killed by SIGKILL after 120 s); at 300-550 MB it was an
    ``ImportError`` traceback, exit 1."""
    limit = 200 * 2**20

    def limited() -> None:
        resource.setrlimit(getattr(resource, which), (limit, limit))

    proc = subprocess.run(
        [sys.executable, "-m", "vibrissa", "identify", "--quick"],
        cwd=tmp_path,
        preexec_fn=limited,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: the memory limit"), proc.stderr
    assert list(tmp_path.iterdir()) == []
