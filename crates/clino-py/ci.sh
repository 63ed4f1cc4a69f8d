#!/usr/bin/env bash
# CI of the Python package: a fresh virtual environment, maturin and the test
# dependencies from PyPI, `pip install ./crates/clino-py` (a release build of
# the extension, profile in crates/clino-py/Cargo.toml), the `clino` binary the
# tests compare with, then pytest. Exits non-zero when anything fails.
#
#   bash crates/clino-py/ci.sh            (from anywhere)
#
# CLINO_BROAD_DIR: the BROAD recordings (default ../shared/data/broad beside
# the repository); the tests that need them are skipped, with the reason, when
# they are absent. CLINO_PY_VENV: where the venv goes (default target/py-venv,
# recreated every run).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
start=$(date +%s)
say() { echo "-- clino-py: $* ($(( $(date +%s) - start )) s)"; }

venv="${CLINO_PY_VENV:-$root/target/py-venv}"
say "fresh venv at $venv"
python3 -m venv --clear "$venv"
py="$venv/bin/python"
"$py" -m pip install -q --upgrade pip
"$py" -m pip install -q maturin numpy pandas pytest dask distributed fsspec

say "the clino binary the tests compare with (release; reused by the extension's build)"
cargo build -q --release -p clino-cli
export CLINO_BIN="$root/target/release/clino"

say "pip install ./crates/clino-py (release build of the extension)"
# the workspace's target directory and release profile: the dependencies the
# release build of the CLI made (earlier in .ci/run, or below) are reused
export CARGO_TARGET_DIR="$root/target"
"$py" -m pip install -q ./crates/clino-py

BROAD="${CLINO_BROAD_DIR:-$root/../shared/data/broad}"
if [ -d "$BROAD" ]; then
    export CLINO_BROAD_DIR="$(cd "$BROAD" && pwd)"
elif [ "${CI:-}" = "true" ]; then
    echo "the BROAD recordings are missing at $BROAD: CI keeps a copy of shared/ beside the clone" >&2
    exit 1
fi

say "pytest"
# run from outside the source tree so the installed package is the one imported
cd "$root/crates/clino-py/tests"
set +e
"$py" -m pytest -q -p no:cacheprovider -o addopts="" .
rc=$?
set -e
if [ $rc -eq 5 ]; then
    echo "clino-py: pytest collected no test" >&2
    exit 1
fi
say "done (pytest exit $rc)"
exit $rc
