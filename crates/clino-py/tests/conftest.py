"""Shared fixtures: the built `clino` binary, the BROAD recordings, the shipped excerpt."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
EXCERPT = ROOT / "crates" / "clino" / "data" / "broad_07_excerpt.csv"


def _binary():
    env = os.environ.get("CLINO_BIN")
    if env:
        return Path(env)
    for profile in ("release", "debug"):
        p = ROOT / "target" / profile / "clino"
        if p.exists():
            return p
    w = shutil.which("clino")
    return Path(w) if w else None


@pytest.fixture(scope="session")
def cli():
    """Run the built `clino` binary: cli(*args) -> stdout (raises with stderr on failure)."""
    b = _binary()
    if b is None or not b.exists():
        pytest.skip("no clino binary: build it (cargo build --release -p clino-cli) or set CLINO_BIN")

    def run(*args, check=True):
        r = subprocess.run([str(b), *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"clino {' '.join(map(str, args))} failed:\n{r.stderr}")
        return r

    return run


@pytest.fixture(scope="session")
def broad_dir():
    """The BROAD recordings (CLINO_BROAD_DIR, else ../shared/data/broad beside the repository)."""
    d = os.environ.get("CLINO_BROAD_DIR")
    p = Path(d) if d else ROOT.parent / "shared" / "data" / "broad"
    if not p.is_dir() or not any(p.glob("*.csv")):
        pytest.skip(f"no BROAD recordings at {p} (set CLINO_BROAD_DIR; README, 'The BROAD recordings')")
    return p


@pytest.fixture(scope="session")
def static_record():
    d = os.environ.get("CLINO_BROAD_DIR")
    base = Path(d).parent if d else ROOT.parent / "shared" / "data"
    p = base / "static" / "mpu6050_rest_100hz.csv"
    if not p.exists():
        pytest.skip(f"no static MPU-6050 record at {p}")
    return p


def cli_json(cli, *args):
    return json.loads(cli(*args, "--json").stdout)
