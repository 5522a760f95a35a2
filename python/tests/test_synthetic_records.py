"""Synthetic records from Python alone (issue 60, item 4, and item 6's
simulate memory): a campaign whose records do not exist yet is built with
``from_dict(..., pending=True)`` and refuses to fit naming the experiment;
``rigfit.simulate(..., t=/dt=, noise=, seed=)`` returns the record as the
campaign reads it, which ``set_data`` takes as it stands, holding the very
numbers the array path gives at those times; a simulation too large for
``max_memory`` is refused before any work."""

import json
import os
import pickle
import time

import numpy as np
import pandas as pd
import pytest

import rigfit

CAMPAIGNS = os.path.join(os.path.dirname(__file__), "..", "..", "campaigns")


def shipped(name):
    return rigfit.Campaign.from_json(os.path.join(CAMPAIGNS, name))


def quarter_car_dict(files=("sweep.csv",)):
    """The two-channel quarter car, its records named but not on disk."""
    with open(os.path.join(CAMPAIGNS, "quarter_car_channels_synthetic.json")) as f:
        d = json.load(f)
    one = d["experiments"][0]
    d["experiments"] = []
    for i, file in enumerate(files):
        x = json.loads(json.dumps(one))
        x["name"] = f"sweep{i}" if len(files) > 1 else "sweep"
        x["data"]["file"] = file
        d["experiments"].append(x)
    d.pop("output", None)
    return d


def mid(campaign):
    return np.array([campaign.params[g].value for g in campaign.genes])


# -- a campaign without its records ---------------------------------------

def test_a_campaign_whose_records_do_not_exist_is_built_and_refuses_to_fit(tmp_path):
    c = rigfit.Campaign.from_dict(quarter_car_dict(), base_dir=tmp_path, pending=True)
    assert c.pending == ["sweep"]
    assert c.genes and c.outputs[0][0] == "sprung_acceleration"
    assert c.to_dict()["experiments"][0]["data"]["file"] == "sweep.csv"
    for call in (lambda: rigfit.fit(c, backend="cpu"), lambda: c.objective(),
                 lambda: rigfit.simulate(c, mid(c))):
        with pytest.raises(rigfit.CampaignError, match="experiment 'sweep' has no record yet: "
                                                       "set_data it"):
            call()
    with pytest.raises(rigfit.CampaignError, match="experiment 'sweep' has no record yet"):
        pickle.dumps(c)
    assert list(tmp_path.iterdir()) == []


def test_without_pending_a_missing_record_is_still_refused(tmp_path):
    with pytest.raises(rigfit.DataError, match="sweep.csv"):
        rigfit.Campaign.from_dict(quarter_car_dict(), base_dir=tmp_path)
    with pytest.raises(rigfit.ArgumentTypeError, match="pending"):
        rigfit.Campaign.from_dict(quarter_car_dict(), base_dir=tmp_path, pending="yes")


def test_each_record_set_takes_an_experiment_off_the_pending_list(tmp_path):
    c = rigfit.Campaign.from_dict(quarter_car_dict(("a.csv", "b.csv")), base_dir=tmp_path,
                                  pending=True)
    assert c.pending == ["sweep0", "sweep1"]
    with pytest.raises(rigfit.CampaignError, match="experiments 'sweep0', 'sweep1' have no "
                                                   "record yet"):
        c.objective()
    df = rigfit.simulate(c, mid(c), dt=1e-3, samples=2001, experiment="sweep1",
                         noise={"sprung_acceleration": 3e-3, "strut_force": 2.0}, seed=1)
    c.set_data("sweep1", df)
    assert c.pending == ["sweep0"]
    with pytest.raises(rigfit.CampaignError, match="experiment 'sweep0' has no record yet"):
        rigfit.fit(c, backend="cpu")
    # A record refused when it is given, while another is still missing:
    # named by its place in the whole campaign.
    flat = df.copy()
    flat["strut_force_N"] = 1.0
    with pytest.raises(rigfit.Error, match=r"experiments\[1\].*<memory:sweep1>"):
        c.set_data("sweep1", flat)
    assert c.pending == ["sweep0"]
    c.set_data("sweep0", rigfit.simulate(c, mid(c), dt=1e-3, samples=2001, experiment="sweep0"))
    assert c.pending == []
    assert np.isfinite(c.objective()(mid(c)))


# -- simulate on a grid -----------------------------------------------------

def test_a_record_on_its_own_grid_holds_the_array_paths_numbers_bit_for_bit():
    # A drive column read from the record, the second experiment (its values
    # the campaign's for that experiment).
    c = shipped("emps_open_loop.json")
    x = c.to_dict()["experiments"][1]
    rec = pd.read_csv(os.path.join(CAMPAIGNS, x["data"]["file"]), comment="#")
    theta = mid(c)
    arrays = rigfit.simulate(c, theta)
    e = c.experiments.index(x["name"])
    n = c.experiment_info(x["name"])["samples"]
    df = rigfit.simulate(c, theta, t=rec["time_s"].to_numpy(), experiment=x["name"],
                         drive=rec["controller_voltage_V"].to_numpy(), substeps=c.substeps)
    assert list(df.columns) == ["time_s", "position_m", "controller_voltage_V"]
    assert np.array_equal(df["time_s"].to_numpy(), rec["time_s"].to_numpy())
    assert np.array_equal(df["controller_voltage_V"].to_numpy(),
                          rec["controller_voltage_V"].to_numpy())
    assert np.array_equal(df["position_m"].to_numpy()[:n], arrays[0, e, :n, 0])


def test_two_channels_on_their_grid_hold_the_array_paths_numbers_bit_for_bit():
    c = shipped("quarter_car_channels_synthetic.json")
    rec = pd.read_csv(os.path.join(CAMPAIGNS, "quarter_car_channels_synthetic.csv"),
                      comment="#")
    theta = mid(c)
    arrays = rigfit.simulate(c, theta)
    df = rigfit.simulate(c, theta, t=rec["t_s"].to_numpy(), substeps=c.substeps)
    outputs = [o for o, _ in c.outputs]
    assert list(df.columns) == ["t_s", "sprung_acceleration_m/s²", "strut_force_N"]
    n = c.experiment_info("sweep.strut_force")["samples"]
    for run, (column, output) in enumerate([("sprung_acceleration_m/s²", "sprung_acceleration"),
                                            ("strut_force_N", "strut_force")]):
        o = outputs.index(output)
        assert np.array_equal(df[column].to_numpy()[:n], arrays[0, run, :n, o])


def test_set_data_takes_the_record_as_it_stands_and_the_truth_scores_nothing(tmp_path):
    c = rigfit.Campaign.from_dict(quarter_car_dict(), base_dir=tmp_path, pending=True)
    truth = mid(c)
    df = rigfit.simulate(c, truth, dt=1e-3, samples=3001)
    assert df.attrs["substeps"] >= 1 and df.attrs["experiment"] == "sweep"
    assert df["t_s"].to_numpy()[-1] == pytest.approx(3.0)
    c.set_data("sweep", df)
    assert c.experiment_info("sweep.strut_force")["samples"] == 3001
    assert c.objective()(truth) < 1e-6


def test_the_columns_are_laid_out_as_the_data_object_reads_them(tmp_path):
    # By position (the defaults: time first, the measured output second),
    # a time column in milliseconds, a scaled output.
    with open(os.path.join(CAMPAIGNS, "quarter_car_synthetic.json")) as f:
        d = json.load(f)
    d["experiments"][0]["data"] = {"file": "q.csv", "time_scale": 1e-3, "scale": 1e3}
    c = rigfit.Campaign.from_dict(d, base_dir=tmp_path, pending=True)
    df = rigfit.simulate(c, mid(c), dt=1e-3, samples=1001)
    out, unit = c.outputs[0]
    assert list(df.columns) == ["t_s", f"{out}_{unit}"]
    assert np.array_equal(df["t_s"].to_numpy(), np.arange(1001) * 1e-3 / 1e-3)
    c.set_data(c.experiments[0], df)
    assert c.experiment_info(c.experiments[0])["dt"] == pytest.approx(1e-3)
    assert c.objective()(mid(c)) < 1e-6
    # A column read at position 2: the one between is written as zeros.
    d["experiments"][0]["data"] = {"file": "q.csv", "time_column": "time", "column": 2}
    c = rigfit.Campaign.from_dict(d, base_dir=tmp_path, pending=True)
    df = rigfit.simulate(c, mid(c), dt=1e-3, samples=11)
    assert list(df.columns) == ["time", "unused_1", f"{out}_{unit}"]
    assert not df["unused_1"].any()


def test_noise_is_gaussian_in_each_outputs_unit_and_reproducible(tmp_path):
    c = rigfit.Campaign.from_dict(quarter_car_dict(), base_dir=tmp_path, pending=True)
    theta = mid(c)
    clean = rigfit.simulate(c, theta, dt=1e-3, samples=4001)
    sigmas = {"sprung_acceleration": 3e-3, "strut_force": 2.0}
    a = rigfit.simulate(c, theta, dt=1e-3, samples=4001, noise=sigmas, seed=5,
                        substeps=clean.attrs["substeps"])
    b = rigfit.simulate(c, theta, dt=1e-3, samples=4001, noise=sigmas, seed=5,
                        substeps=clean.attrs["substeps"])
    other = rigfit.simulate(c, theta, dt=1e-3, samples=4001, noise=sigmas, seed=6,
                            substeps=clean.attrs["substeps"])
    pd.testing.assert_frame_equal(a, b)
    assert not np.array_equal(a["strut_force_N"], other["strut_force_N"])
    for column, sigma in (("sprung_acceleration_m/s²", 3e-3), ("strut_force_N", 2.0)):
        d = a[column].to_numpy() - clean[column].to_numpy()
        assert abs(d.std() / sigma - 1) < 0.1 and abs(d.mean()) < 0.1 * sigma
    # Parameters by name; a dict of arrays is a set per element.
    named = dict(zip(c.genes, theta))
    pd.testing.assert_frame_equal(rigfit.simulate(c, named, dt=1e-3, samples=101),
                                  rigfit.simulate(c, theta, dt=1e-3, samples=101))
    two = rigfit.simulate(c, {k: [v, v] for k, v in named.items()}, dt=1e-3, samples=101)
    assert isinstance(two, list) and len(two) == 2
    # Several parameter sets: one record each.
    many = rigfit.simulate(c, np.vstack([theta, theta]), dt=1e-3, samples=101)
    assert isinstance(many, list) and len(many) == 2
    pd.testing.assert_frame_equal(many[0], many[1])


@pytest.mark.parametrize("kwargs, match", [
    (dict(t=np.arange(10) * 1e-3, dt=1e-3), "t= alone"),
    (dict(t=[0.0, 1e-3, 3e-3, 4e-3]), "uniformly spaced"),
    (dict(t=[0.0, 2e-3, 1e-3]), "strictly increasing"),
    (dict(dt=1e-3), "samples"),
    (dict(dt=-1e-3, samples=10), "dt"),
    (dict(dt=1e-3, samples=10, noise=0.1), "2 channels"),
    (dict(dt=1e-3, samples=10, noise={"strut_forse": 0.1}), "did you mean 'strut_force'"),
    (dict(dt=1e-3, samples=10, noise={"strut_force": -1.0}), "standard deviation"),
    (dict(dt=1e-3, samples=10, experiment="sweeep"), "did you mean 'sweep'"),
    (dict(dt=1e-3, samples=10, drive=np.zeros(10)), "reads no drive column"),
    (dict(dt=1e-3, samples=10, backend="gpu"), "CPU"),
    (dict(noise=0.1), "needs a time grid"),
    (dict(seed=1), "needs a time grid"),
])
def test_a_bad_grid_or_noise_is_refused_naming_the_keyword(tmp_path, kwargs, match):
    c = shipped("quarter_car_channels_synthetic.json")
    with pytest.raises((rigfit.CampaignError, rigfit.ArgumentTypeError), match=match):
        rigfit.simulate(c, mid(c), **kwargs)


def test_a_drive_column_must_be_given_on_a_grid():
    c = shipped("emps_open_loop.json")
    with pytest.raises(rigfit.CampaignError, match="controller_voltage_V"):
        rigfit.simulate(c, mid(c), dt=1e-3, samples=10)
    with pytest.raises(rigfit.CampaignError, match="10 values"):
        rigfit.simulate(c, mid(c), dt=1e-3, samples=10, drive=np.zeros(9))


# -- memory -------------------------------------------------------------------

def test_a_simulation_larger_than_max_memory_is_refused_before_any_work():
    c = shipped("quarter_car_channels_synthetic.json")
    theta = np.broadcast_to(mid(c), (2_000_000, len(c.genes)))
    started = time.perf_counter()
    with pytest.raises(rigfit.CampaignError, match=r"max_memory.*1\.0+ GiB.*2000000 parameter"):
        rigfit.simulate(c, theta, max_memory="1G")
    with pytest.raises(rigfit.CampaignError, match="max_memory"):
        rigfit.simulate(c, theta[:100_000], t=np.arange(100_000) * 1e-3, max_memory="1G")
    assert time.perf_counter() - started < 5
    with pytest.raises(rigfit.CampaignError, match="max_memory"):
        rigfit.simulate(c, theta[:1], max_memory="0")
    # Within the limit it runs.
    assert rigfit.simulate(c, theta[:2], max_memory="1G").shape[0] == 2
