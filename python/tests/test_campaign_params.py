"""Parameters a user can edit: `campaign.params[...]` edits, `set_params`,
lmfit's `set`/`add` take effect on the campaign (the library validating
them) or raise, never silently ignored; records set from memory survive an
edit; parameter sets given by label are read by label."""

import json

import numpy as np
import pandas as pd
import pytest

import rigfit


def _row(c, name):
    return c.bounds[c.genes.index(name)]


def test_editing_a_parameter_of_campaign_params_rebuilds_the_campaign(bearing):
    c = rigfit.Campaign.from_json(bearing)
    p = c.params
    p["k_x"].min = 1e6
    p["k_x"].max = 2e6
    assert list(_row(c, "k_x")) == [1e6, 2e6]
    assert c.to_dict()["params"]["k_x"]["min"] == 1e6
    # The same objects, up to date, from any access.
    assert p["k_x"].max == 2e6 and c.params["k_x"] is p["k_x"]
    p["k_x"].scale = "linear"
    assert c.params["k_x"].scale == "linear"
    p["k_x"].value = 1.5e6
    assert c.params["k_x"].value == 1.5e6 and c.to_dict()["params"]["k_x"]["init"] == 1.5e6
    # Fixing one takes it out of the genes, at its value.
    before = c.params["c_xy"].value
    c.params["c_xy"].vary = False
    assert "c_xy" not in c.genes and len(c.genes) == c.bounds.shape[0]
    assert not c.params["c_xy"].vary and c.params["c_xy"].value == before
    assert c.to_dict()["params"]["c_xy"] == before
    # lmfit's set: several at once.
    c.params["c_xy"].set(value=10.0, vary=True, min=-50.0, max=50.0)
    assert "c_xy" in c.genes and list(_row(c, "c_xy")) == [-50.0, 50.0]
    assert c.params["c_xy"].value == 10.0
    c.params["m"].value = 3.5
    assert c.to_dict()["params"]["m"] == 3.5 and c.params["m"].value == 3.5


def test_a_fit_after_set_params_uses_the_new_bounds_and_fixed_values(bearing):
    c = rigfit.Campaign.from_json(bearing)
    c.set_params(k_x=dict(min=2.0e6, max=2.2e6), c_xy=dict(vary=False, value=0.0))
    assert "c_xy" not in c.genes
    r = rigfit.fit(c, backend="cpu", seed=4)
    k = r.params["k_x"]
    assert k.vary and (k.min, k.max) == (2.0e6, 2.2e6) and 2.0e6 <= k.value <= 2.2e6
    assert not r.params["c_xy"].vary and r.params["c_xy"].value == 0.0
    assert r.var_names == c.genes


def test_a_bad_edit_raises_naming_the_parameter_and_changes_nothing(bearing):
    c = rigfit.Campaign.from_json(bearing)
    p = c.params
    bounds = c.bounds.copy()
    with pytest.raises(rigfit.CampaignError, match=r"params\.k_x\.max"):
        p["k_x"].min = 5e7
    assert np.array_equal(c.bounds, bounds) and p["k_x"].min == bounds[c.genes.index("k_x"), 0]
    with pytest.raises(rigfit.CampaignError, match=r"'m'.*min and max"):
        p["m"].vary = True
    with pytest.raises(rigfit.CampaignError, match=r"'m'.*fixed parameter has no bounds"):
        p["m"].min = 1.0
    with pytest.raises(rigfit.CampaignError, match="did you mean 'k_x'"):
        c.set_params(k_xx=1.0)
    with pytest.raises(rigfit.CampaignError, match="did you mean 'k_y'"):
        p.add("k_yy", value=1.0, vary=False)
    with pytest.raises(rigfit.ArgumentTypeError, match=r"params\['k_x'\]\.min"):
        p["k_x"].min = "low"
    with pytest.raises(rigfit.CampaignError, match=r"k_x.*unit"):
        p["k_x"].unit = "N/mm"
    with pytest.raises(rigfit.CampaignError, match="cannot be removed"):
        del p["k_x"]
    assert np.array_equal(c.bounds, bounds) and c.genes == rigfit.Campaign.from_json(bearing).genes


def test_assigning_a_parameter_add_and_set_params_from_a_parameters(bearing):
    c = rigfit.Campaign.from_json(bearing)
    c.params["k_y"] = rigfit.Parameter("k_y", value=3e6, min=1e6, max=5e6, vary=True)
    assert list(_row(c, "k_y")) == [1e6, 5e6] and c.params["k_y"].value == 3e6
    c.params.add("c_x", value=100.0, vary=True, min=10.0, max=1000.0)
    assert list(_row(c, "c_x")) == [10.0, 1000.0]
    c.params.add("c_y", value=20.0, vary=False)
    assert "c_y" not in c.genes and c.params["c_y"].value == 20.0
    # A detached copy carries the edits to another campaign.
    d = rigfit.Campaign.from_json(bearing)
    d.set_params(c.params.copy())
    assert d.genes == c.genes and np.array_equal(d.bounds, c.bounds)


def test_a_detached_copy_and_a_results_params_edit_no_campaign(bearing):
    c = rigfit.Campaign.from_json(bearing)
    q = c.params.copy()
    assert q.campaign is None and c.params.campaign is c
    q["k_x"].min = 1.0
    q["k_x"].vary = False
    assert "k_x" in c.genes and c.params["k_x"].min != 1.0
    again = rigfit.Campaign.from_json(bearing).params
    assert again["k_x"] == c.params["k_x"]


def test_a_name_per_experiment_edits_that_experiment_alone(bearing):
    c = rigfit.Campaign.from_json(bearing)
    names = list(c.params)
    # f_x: experiment hx sets its own, hy keeps the rig's default.
    assert "hx.f_x" in names and "hy.f_x" in names and "f_x" not in names
    theta = c.bounds.mean(axis=1)[None, :]
    before = rigfit.simulate(c, theta)
    c.params["hx.f_x"].value = 2 * c.params["hx.f_x"].value
    after = rigfit.simulate(c, theta)
    assert not np.array_equal(before[:, 0], after[:, 0])
    assert np.array_equal(before[:, 1], after[:, 1])
    assert c.to_dict()["experiments"][0]["params"]["f_x"] == c.params["hx.f_x"].value
    # A bare name edits every experiment's value.
    c.params["tau"].value = 2e-3
    assert [x["params"]["tau"] for x in c.to_dict()["experiments"]] == [2e-3, 2e-3]


def test_an_edit_keeps_the_records_set_from_memory(bearing):
    c = rigfit.Campaign.from_json(bearing)
    raw = json.loads(bearing.read_text())
    x = raw["experiments"][0]
    rows = [r for r in (bearing.parent / x["data"]["file"]).read_text().splitlines()
            if r and not r.startswith("#")]
    frame = pd.DataFrame(np.loadtxt(rows[1:], delimiter=",", ndmin=2), columns=rows[0].split(","))
    frame.iloc[:, 1] *= 1.5  # not the record on disk
    c.set_data(x["name"], frame)
    theta = c.bounds.mean(axis=1)
    cost = c.objective()(theta)
    assert cost != rigfit.Campaign.from_json(bearing).objective()(theta)
    # An edit that cannot change the cost at theta: the search's start.
    c.params["k_x"].value = float(c.params["k_x"].value) * 1.01
    assert c.to_dict()["experiments"][0]["data"]["file"] == "<memory:hx>.csv"
    assert c.objective()(theta) == cost
    c.set_params(m=c.params["m"].value)
    assert c.objective()(theta) == cost


# -- parameter sets by label -----------------------------------------------

def test_a_series_dataframe_or_dict_is_read_by_label(bearing):
    c = rigfit.Campaign.from_json(bearing)
    rng = np.random.default_rng(1)
    lo, hi = c.bounds[:, 0], c.bounds[:, 1]
    theta = lo + (hi - lo) * rng.random((3, len(c.genes)))
    want = rigfit.simulate(c, theta)
    reversed_genes = c.genes[::-1]
    frame = pd.DataFrame(theta[:, ::-1], columns=reversed_genes)
    assert np.array_equal(rigfit.simulate(c, frame), want)
    series = pd.Series(theta[1, ::-1], index=reversed_genes)
    assert np.array_equal(rigfit.simulate(c, series), want[1:2])
    as_dict = dict(zip(reversed_genes, theta[2, ::-1]))
    assert np.array_equal(rigfit.simulate(c, as_dict), want[2:3])
    f = c.objective()
    costs = f(theta.T)
    assert f(series) == costs[1] and f(as_dict) == costs[2]
    assert np.array_equal(f(frame), costs)
    # The campaign's own Parameters (free ones' values by name) too.
    assert f(c.params) == f(np.array([c.params[g].value for g in c.genes]))


def test_missing_unknown_and_changed_fixed_labels_are_refused(bearing):
    c = rigfit.Campaign.from_json(bearing)
    values = dict(zip(c.genes, c.bounds.mean(axis=1)))
    short = dict(values)
    del short["k_x"]
    with pytest.raises(rigfit.CampaignError, match="no value for the free parameter.*'k_x'"):
        rigfit.simulate(c, pd.Series(short))
    typo = dict(short, k_xx=1e6)
    with pytest.raises(rigfit.CampaignError, match="did you mean 'k_x'"):
        c.objective()(typo)
    # A fixed parameter's name passes with the campaign's value only.
    same = dict(values, m=c.params["m"].value)
    assert c.objective()(same) == c.objective()(values)
    with pytest.raises(rigfit.CampaignError, match=r"'m' is fixed at .*set_params"):
        rigfit.simulate(c, dict(values, m=99.0))
