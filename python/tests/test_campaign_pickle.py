"""A pickled (or deep-copied, or edited) campaign carries the records it was
built from: a worker fits the data the pickled campaign held, whatever the
disk holds by then."""

import copy
import json
import pickle

import numpy as np

import rigfit


def _rewrite(csv, factor):
    """The record at ``csv`` with its measured column scaled."""
    out = []
    for line in csv.read_text().splitlines():
        if line and not line.startswith("#") and line[0] in "-0123456789":
            t, y = line.split(",")
            line = f"{t},{float(y) * factor!r}"
        out.append(line)
    csv.write_text("\n".join(out) + "\n")


def _files(bearing):
    raw = json.loads(bearing.read_text())
    return [bearing.parent / x["data"]["file"] for x in raw["experiments"]]


def test_an_unpickled_campaign_has_its_records_not_the_disks(bearing):
    c = rigfit.Campaign.from_json(bearing)
    theta = c.bounds.mean(axis=1)
    cost, history = c.objective()(theta), rigfit.simulate(c, theta)
    blob = pickle.dumps(c)
    hx, hy = _files(bearing)
    _rewrite(hx, 3.0)
    assert rigfit.Campaign.from_json(bearing).objective()(theta) != cost  # the disk changed
    d = pickle.loads(blob)
    assert d.objective()(theta) == cost
    assert np.array_equal(rigfit.simulate(d, theta), history)
    # Gone from disk altogether: the same.
    hx.unlink()
    hy.unlink()
    e = pickle.loads(blob)
    assert e.objective()(theta) == cost
    # And pickled again from there.
    assert pickle.loads(pickle.dumps(e)).objective()(theta) == cost


def test_a_pickled_objective_scores_the_pickled_records(bearing):
    c = rigfit.Campaign.from_json(bearing)
    f = c.objective()
    theta = c.bounds.mean(axis=1)
    blob = pickle.dumps(f)
    _rewrite(_files(bearing)[0], 0.5)
    assert pickle.loads(blob)(theta) == f(theta)


def test_a_deep_copy_and_an_edit_keep_the_records_read_at_load(bearing):
    c = rigfit.Campaign.from_json(bearing)
    theta = c.bounds.mean(axis=1)
    cost = c.objective()(theta)
    _rewrite(_files(bearing)[1], 2.0)
    d = copy.deepcopy(c)
    # An edit rebuilds the campaign: from the records it holds, not the disk.
    d.params["m"].value = d.params["m"].value
    c.set_params(k_x=dict(value=float(c.params["k_x"].value)))
    assert d.objective()(theta) == cost and c.objective()(theta) == cost
    assert pickle.loads(pickle.dumps(c)).objective()(theta) == cost


def test_records_set_from_memory_survive_a_pickle_and_an_edit(bearing):
    c = rigfit.Campaign.from_json(bearing)
    t = np.arange(500) * 2.56e-4
    c.set_data("hx", {"t_s": t, "force_N": 1e-6 * np.sin(2 * np.pi * 50 * t)})
    theta = c.bounds.mean(axis=1)
    cost = c.objective()(theta)
    d = pickle.loads(pickle.dumps(c))
    d.set_params(m=d.params["m"].value)
    assert d.to_dict()["experiments"][0]["data"]["file"] == "<memory:hx>.csv"
    assert d.objective()(theta) == cost


def test_set_data_keeps_the_other_records_as_the_campaign_holds_them(bearing):
    """Setting one experiment's record rebuilds the campaign from the other
    records it holds, not from the disk they were read from."""
    c = rigfit.Campaign.from_json(bearing)
    theta = c.bounds.mean(axis=1)
    hx, hy = _files(bearing)
    cost = c.objective()(theta)
    frame = {"t_s": [], "force_N": []}
    for line in hy.read_text().splitlines():
        if line and line[0] in "-0123456789":
            t, y = line.split(",")
            frame["t_s"].append(float(t))
            frame["force_N"].append(float(y))
    _rewrite(hx, 3.0)
    assert rigfit.Campaign.from_json(bearing).objective()(theta) != cost  # the disk changed
    c.set_data("hy", frame)  # hy's own numbers again
    assert c.objective()(theta) == cost
