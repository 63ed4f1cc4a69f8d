"""Shared helpers for the comparison scripts: a private venv in /tmp and the clino binaries.

Each script calls `ensure_venv([...packages])` first: outside the venv it creates
/tmp/clino-scripts-venv (once), pip-installs the packages there and re-executes
itself with the venv's python. Nothing here is needed by the Rust tests.
"""
import os
import subprocess
import sys

VENV = os.environ.get("CLINO_SCRIPTS_VENV", "/tmp/clino-scripts-venv")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def ensure_venv(packages):
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
    subprocess.check_call([py, "-m", "pip", "install", "-q", *packages])
    os.execv(py, [py, *sys.argv])


def cargo(*args):
    """Run cargo in the workspace (quiet), returning stdout."""
    return subprocess.run(["cargo", *args], cwd=ROOT, check=True, stdout=subprocess.PIPE, text=True).stdout


def clino(*args):
    """Run the clino CLI (built with cargo) and return its stdout."""
    return cargo("run", "-q", "-p", "clino-cli", "--bin", "clino", "--", *args)


def export(dirname):
    """Write the simulated data sets of clino's calibration generator to dirname."""
    cargo("run", "-q", "-p", "clino", "--example", "calib_export", "--", dirname)
