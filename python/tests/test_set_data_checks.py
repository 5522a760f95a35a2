"""Records checked when they are given: set_data refuses a record in the
wrong unit before anything runs, with the keyword that fixes it
(``time_scale=``, ``scale=``), reads a DataFrame's time index, and warns of
a record starting long after t = 0 without integrating that stretch to
choose the step."""

import json
import warnings

import numpy as np
import pandas as pd
import pytest

import rigfit
from conftest import CAMPAIGNS

EXAMPLE = CAMPAIGNS / "aa2024_t3_synthetic.json"


def _record():
    return pd.read_csv(CAMPAIGNS / "aa2024_t3_v2_synthetic.csv", comment="#")


def _costs(c):
    """The objective at the bounds' centre and two other points: equal costs
    mean equal records as the fit sees them."""
    lo, hi = c.bounds[:, 0], c.bounds[:, 1]
    theta = np.stack([lo + f * (hi - lo) for f in (0.5, 0.3, 0.7)], axis=1)
    return c.objective()(theta)


def test_a_time_column_in_milliseconds_is_refused_then_read_with_time_scale():
    twin = rigfit.Campaign.from_json(EXAMPLE)
    c = rigfit.Campaign.from_json(EXAMPLE)
    ms = _record()
    ms["t_s"] *= 1e3
    with pytest.raises(ValueError, match=r"fit_window.*3 of the record's 2501 samples") as e:
        c.set_data("v2", ms)
    assert "time_scale=1e-3" in str(e.value)
    assert isinstance(e.value, (rigfit.CampaignError, rigfit.DataError))
    c.set_data("v2", ms, time_scale=1e-3)
    assert c.experiment_info("v2")["samples"] == 2501
    assert c.to_dict()["experiments"][0]["data"]["time_scale"] == 1e-3
    assert np.allclose(_costs(c), _costs(twin), rtol=1e-12)


def test_a_force_in_kilonewtons_is_refused_then_read_with_scale():
    twin = rigfit.Campaign.from_json(EXAMPLE)
    kn = _record()
    kn["force_N"] /= 1e3
    c = rigfit.Campaign.from_json(EXAMPLE)
    with pytest.raises(rigfit.CampaignError, match=r"in kN.*scale=1e3"):
        c.set_data("v2", kn)
    for scale in (1000, {"force_N": 1e3}):
        c = rigfit.Campaign.from_json(EXAMPLE)
        c.set_data("v2", kn, scale=scale)
        assert c.warnings == []
        assert np.allclose(_costs(c), _costs(twin), rtol=1e-9)


def test_bad_scales_are_refused_naming_the_keyword():
    c = rigfit.Campaign.from_json(EXAMPLE)
    rec = _record()
    with pytest.raises(rigfit.CampaignError, match=r"^time_scale=-1\.0: expected a number > 0"):
        c.set_data("v2", rec, time_scale=-1)
    with pytest.raises(rigfit.CampaignError, match=r"^scale=0\.0: expected a non-zero"):
        c.set_data("v2", rec, scale=0)
    with pytest.raises(rigfit.ArgumentTypeError, match=r"^scale: expected a number"):
        c.set_data("v2", rec, scale="kN")
    with pytest.raises(rigfit.CampaignError, match=r"no measured column 'force_kN'.*'force_N'"):
        c.set_data("v2", rec, scale={"force_kN": 1e3})


def test_a_dataframe_time_index_is_read_as_its_column():
    twin = rigfit.Campaign.from_json(EXAMPLE)
    rec = _record()
    c = rigfit.Campaign.from_json(EXAMPLE)
    c.set_data("v2", rec.set_index("t_s"))  # a named index: as reset_index() reads
    assert np.array_equal(_costs(c), _costs(twin))
    # An unnamed index of times, the time column named and absent: the index.
    unnamed = rec.set_index("t_s")
    unnamed.index.name = None
    c = rigfit.Campaign.from_json(EXAMPLE)
    c.set_data("v2", unnamed)
    assert np.array_equal(_costs(c), _costs(twin))
    # Row labels (a filter's kept rows) are not read.
    c = rigfit.Campaign.from_json(EXAMPLE)
    c.set_data("v2", rec[rec["t_s"] >= 0.0])
    assert np.array_equal(_costs(c), _costs(twin))


def test_an_ambiguous_time_index_is_refused():
    rec = _record()
    both = rec.set_index("t_s", drop=False)
    c = rigfit.Campaign.from_json(EXAMPLE)
    with pytest.raises(rigfit.DataError, match="index and one of its columns are both named 't_s'"):
        c.set_data("v2", both)
    floats = rec.copy()
    floats.index = rec["t_s"].to_numpy()
    with pytest.raises(rigfit.DataError, match="unnamed index of floats and a column 't_s'"):
        c.set_data("v2", floats)


def test_a_record_starting_at_1000_s_is_warned_of_when_given():
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_synthetic.json")
    late = pd.read_csv(CAMPAIGNS / raw["experiments"][0]["data"]["file"], comment="#")
    assert len(late) == 500
    late["t_s"] += 1000.0
    # Before the fix the step-doubling estimate integrated the 1000 s from
    # rest three times over (54 s); the Rust test record_plausibility counts
    # that it is not taken.
    with pytest.warns(RuntimeWarning, match=r"starts at t = 1000 s.*\"offset\": -1000"):
        c.set_data("hx", late)
    assert any("starts at t = 1000 s" in w for w in c.warnings)


def test_a_fine_record_gives_no_warning():
    c = rigfit.Campaign.from_json(EXAMPLE)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c.set_data("v2", _record())
    assert c.warnings == []
