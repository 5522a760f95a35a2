"""Campaigns as objects: the library's validation and one-line errors."""

import json
import pickle

import numpy as np
import pytest

import rigfit
from conftest import CAMPAIGNS


def test_shipped_example_loads_with_its_genes_and_bounds():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "aa2024_t3_synthetic.json")
    assert c.rig == "tensile4"
    assert c.experiments == ["v2"]
    assert len(c.genes) == 7
    assert c.bounds.shape == (7, 2)
    assert np.all(c.bounds[:, 0] < c.bounds[:, 1])
    k1 = c.params["k1"]
    assert k1.vary and k1.min == 2e9 and k1.max == 3e10 and k1.scale == "log" and k1.unit
    assert not c.params["m1"].vary and c.params["m1"].value == 7.9
    assert c.outputs[0][0] == "load_cell_force"


def test_from_dict_equals_from_json():
    path = CAMPAIGNS / "bearing_2dof_synthetic.json"
    a = rigfit.Campaign.from_json(path)
    b = rigfit.Campaign.from_dict(json.loads(path.read_text()), base_dir=CAMPAIGNS)
    assert a.genes == b.genes
    assert np.array_equal(a.bounds, b.bounds)
    assert a.substeps == b.substeps


def test_a_bad_key_names_the_file_and_the_json_path(tmp_path):
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    raw["experiments"][1]["weight"] = -1.0
    for x in raw["experiments"]:
        x["data"]["file"] = str(CAMPAIGNS / x["data"]["file"])
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(raw))
    with pytest.raises(rigfit.CampaignError) as e:
        rigfit.Campaign.from_json(path)
    msg = str(e.value)
    assert str(path) in msg and "experiments[1].weight" in msg
    assert "\n" not in msg
    assert isinstance(e.value, ValueError) and isinstance(e.value, rigfit.Error)


def test_an_unknown_key_and_malformed_json_are_campaign_errors(tmp_path):
    with pytest.raises(rigfit.CampaignError, match=r"<dict>.*search.*populaton"):
        rigfit.Campaign.from_dict({"name": "x", "rig": "tensile4", "search": {"populaton": 3}})
    path = tmp_path / "broken.json"
    path.write_text('{"name": "x",')
    with pytest.raises(rigfit.CampaignError, match="broken.json:1:"):
        rigfit.Campaign.from_json(path)


def test_a_bad_record_is_a_data_error_naming_the_data_file(tmp_path):
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    for x in raw["experiments"]:
        (tmp_path / x["data"]["file"]).write_text("t_s,force_N\n0,1\n0.001,oops\n0.002,3\n")
    path = tmp_path / "c.json"
    path.write_text(json.dumps(raw))
    with pytest.raises(rigfit.DataError) as e:
        rigfit.Campaign.from_json(path)
    assert "experiments[0].data" in str(e.value) and "bearing_2dof_x_synthetic.csv:3" in str(e.value)


def test_a_missing_file_is_a_campaign_error(tmp_path):
    with pytest.raises(rigfit.CampaignError, match="nothere.json: cannot read"):
        rigfit.Campaign.from_json(tmp_path / "nothere.json")


def test_campaign_pickles():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_synthetic.json")
    d = pickle.loads(pickle.dumps(c))
    assert d.genes == c.genes and np.array_equal(d.bounds, c.bounds)


def test_shipped_rigs_by_id_and_inline():
    rigs = rigfit.shipped_rigs()
    assert "tensile4" in rigs and rigs["tensile4"]["id"] == "tensile4"
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    by_id = rigfit.Campaign.from_dict(raw, base_dir=CAMPAIGNS)
    raw["rig"] = rigs["bearing_2dof"]
    inline = rigfit.Campaign.from_dict(raw, base_dir=CAMPAIGNS)
    assert inline.genes == by_id.genes and inline.outputs == by_id.outputs
