"""ringdown and fit_specimen on arrays give the numbers the CLI's --json
prints for the same record."""

import json

import numpy as np

import rigfit
from conftest import CAMPAIGNS


def _two_columns(path):
    rows = [r for r in path.read_text().splitlines() if r.strip() and not r.startswith("#")]
    table = np.loadtxt(rows[1:], delimiter=",", ndmin=2)
    return table[:, 0], table[:, 1]


def test_ringdown_matches_the_cli(cli):
    path = CAMPAIGNS / "ringdown_synthetic.csv"
    t, f = _two_columns(path)
    r = rigfit.ringdown(t, f, m1=7.9)
    want = json.loads(cli("--json", "ringdown", path, "--m1", "7.9").stdout)
    assert r["ringdown"] == want["ringdown"]
    assert r.fragment == want["fragment"]
    assert r["ringdown"]["natural_frequency_hz"] > 0


def test_fit_specimen_matches_the_cli(cli):
    path = CAMPAIGNS / "specimen_quasistatic_synthetic.csv"
    e, f = _two_columns(path)
    r = rigfit.fit_specimen(e, f, degree=3)
    want = json.loads(cli("--json", "fit-specimen", path, "--degree", "3").stdout)
    assert r["fit"] == want["fit"]
    assert r.fragment == want["fragment"]


def test_a_too_short_record_is_a_data_error():
    import pytest
    with pytest.raises(rigfit.DataError):
        rigfit.ringdown([0.0, 1.0], [1.0, 0.0])
