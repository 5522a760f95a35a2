"""Shared fixtures: the repository's campaigns, the CLI binary the Python
results are held to, and small, fast copies of shipped campaigns."""

import json
import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CAMPAIGNS = ROOT / "campaigns"


def cli_binary():
    """The rigfit binary: $RIGFIT_BIN, else the root crate's release or debug
    build. A missing binary fails the tests that need it (never a skip)."""
    env = os.environ.get("RIGFIT_BIN")
    if env:
        return env
    for profile in ("release", "debug"):
        p = ROOT / "target" / profile / "rigfit"
        if p.is_file():
            return str(p)
    raise AssertionError("no rigfit binary: build it (cargo build --release) or set RIGFIT_BIN")


@pytest.fixture(scope="session")
def cli():
    path = cli_binary()

    def run(*args, check=True):
        r = subprocess.run([path, "--quiet", *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"rigfit {' '.join(map(str, args))}: exit {r.returncode}\n{r.stderr}")
        return r
    return run


@pytest.fixture
def bearing(tmp_path):
    """The shipped bearing_2dof campaign (two experiments, 500 samples each,
    six free parameters) copied into tmp_path with a small, fast search."""
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    raw["search"] = {"population": 48, "generations": 6, "seed": 3, "checkpoint_every": 1}
    raw["solver"]["backend"] = "cpu"
    raw["output"] = "results"
    for x in raw["experiments"]:
        shutil.copy(CAMPAIGNS / x["data"]["file"], tmp_path / x["data"]["file"])
    path = tmp_path / "bearing.json"
    path.write_text(json.dumps(raw, indent=1))
    return path
