#!/usr/bin/env bash
# Type-check the packages and modules that are kept free of mypy errors.
# Settings are in pyproject.toml's [tool.mypy]. Add a package to PACKAGES once
# `.venv/bin/mypy -p <package>` reports no errors for it.
set -euo pipefail

PACKAGES=(
    -p vibrissa.signal
    -p vibrissa.data
    -m vibrissa._atomic
    -m vibrissa._validate
    -m vibrissa._processes
    -p vibrissa.slam
    -p vibrissa.framework
    -p vibrissa.reproduce
    -p vibrissa.thesis
)

cd "$(dirname "${BASH_SOURCE[0]}")/.."
exec .venv/bin/mypy "${PACKAGES[@]}"
