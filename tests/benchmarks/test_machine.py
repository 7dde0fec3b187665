"""benchmarks/_machine.py: what the benchmarks record of the machine they ran on."""

from __future__ import annotations

import os


def test_machine_names_cores_cpu_memory_and_python(bench_script) -> None:
    m = bench_script("_machine").machine()
    assert set(m) == {"cores", "cpu", "memory_gb", "python", "platform"}
    assert m["cores"] == os.cpu_count() and m["python"].count(".") == 2
    if os.path.exists("/proc/cpuinfo"):
        assert m["cpu"]  # the model name, e.g. "AMD EPYC" or "Intel(R) Xeon(R) ..."
    assert m["memory_gb"] is None or m["memory_gb"] > 0
