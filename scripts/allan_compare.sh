#!/usr/bin/env bash
# Compare `clino allan` with allantools (installed from PyPI into the scripts'
# own virtual environment, /tmp/clino-scripts-venv) on the shared MPU-6050
# record and on simulated records with known N, B, K. See allan_compare.py.
set -euo pipefail
cd "$(dirname "$0")/.."
exec python3 scripts/allan_compare.py "$@"
