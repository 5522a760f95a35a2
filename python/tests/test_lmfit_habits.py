"""The lmfit and SciPy habits: a residual vector for ``least_squares`` and
lmfit's ``Minimizer`` whose sum of squares is the objective, and lmfit's fit
statistics on a result (covariance, chisqr, redchi, aic, bic, nfev, ndata,
nvarys, success, message)."""

import json
import math

import lmfit
import numpy as np
import pytest
from scipy.optimize import least_squares

import rigfit
from conftest import CAMPAIGNS

SHIPPED = ["inertial_sdof_synthetic.json", "bearing_2dof_channels_synthetic.json",
           "quarter_car_channels_synthetic.json"]


def reference(campaign, name):
    """The reference parameters in genes' order."""
    ref = json.loads((CAMPAIGNS / name).read_text())["params"]
    return np.array([ref[g] for g in campaign.genes])


def window_samples(campaign):
    total = 0
    for name in campaign.experiments:
        a, b = campaign.experiment_info(name)["fit_window"]
        total += b - a
    return total


def random_sets(campaign, count, seed):
    rng = np.random.default_rng(seed)
    lo, hi = campaign.bounds.T
    return lo + rng.random((count, len(lo))) * (hi - lo)


@pytest.mark.parametrize("name", SHIPPED)
def test_the_sum_of_squared_residuals_is_the_objective(name):
    c = rigfit.Campaign.from_json(CAMPAIGNS / name)
    ref = reference(c, name.replace("_channels", "").replace("synthetic.json",
                                                             "reference_params.json"))
    theta = np.vstack([ref, random_sets(c, 5, 7)])
    r = c.residuals(theta)
    assert r.shape == (len(theta), window_samples(c))
    assert np.all(np.isfinite(r))
    costs = c.objective()(theta.T)
    sums = np.sum(r ** 2, axis=1)
    assert np.allclose(sums, costs, rtol=1e-12, atol=0), (sums, costs)
    # One set: a vector, the same as its row.
    one = c.residuals(ref)
    assert one.shape == (window_samples(c),)
    assert np.array_equal(one, r[0])
    assert math.isclose(float(np.sum(one ** 2)), c.objective(vectorized=False)(ref), rel_tol=1e-12)


def test_residuals_carry_the_experiment_weights():
    # Weighting one experiment 4x: each of its residuals grows against the
    # other's by 2 (sqrt of the weight), and the sum is still the objective.
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    c1 = rigfit.Campaign.from_dict(raw, base_dir=CAMPAIGNS)
    raw["experiments"][0]["weight"] = 4.0
    c4 = rigfit.Campaign.from_dict(raw, base_dir=CAMPAIGNS)
    theta = random_sets(c1, 3, 11)
    r1, r4 = c1.residuals(theta), c4.residuals(theta)
    a, b = c1.experiment_info(c1.experiments[0])["fit_window"]
    n0 = b - a
    ratio = (r4[:, :n0] / r1[:, :n0]) / (r4[:, n0 + 1:n0 + 2] / r1[:, n0 + 1:n0 + 2])
    assert np.allclose(ratio, 2.0, rtol=1e-12)
    assert np.allclose(np.sum(r4 ** 2, axis=1), c4.objective()(theta.T), rtol=1e-12, atol=0)


def test_a_run_that_blows_up_gives_a_finite_vector_whose_square_sum_is_the_objective():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_channels_synthetic.json")
    lo, hi = c.bounds.T
    theta = dict(zip(c.genes, lo))
    # A cross stiffness beyond the direct ones: the rig is unstable.
    theta["k_xy"] = hi[c.genes.index("k_xy")]
    x = np.array([theta[g] for g in c.genes])
    cost = c.objective(vectorized=False)(x)
    assert cost == 1e30
    r = c.residuals(x)
    assert np.all(np.isfinite(r))
    assert math.isclose(float(np.sum(r ** 2)), cost, rel_tol=1e-12)


def test_least_squares_from_near_the_truth_reaches_the_reference():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_channels_synthetic.json")
    truth = reference(c, "bearing_2dof_reference_params.json")
    x0 = truth * np.array([1.08, 0.93, 1.1, 0.9, 1.1, 0.85])
    lo, hi = c.bounds.T
    sol = least_squares(c.residuals, x0, bounds=(lo, hi), x_scale=truth)
    assert sol.success, sol.message
    # Its 95 % intervals from the Jacobian, each experiment's noise its own
    # is not needed here: one pooled variance.
    n, p = sol.fun.size, len(truth)
    s2 = 2 * sol.cost / (n - p)
    cov = np.linalg.inv(sol.jac.T @ sol.jac) * s2
    half = 1.96 * np.sqrt(np.diag(cov))
    assert np.all(np.abs(sol.x - truth) <= half), (sol.x, truth, half)
    assert np.all(np.abs(sol.x - truth) <= 0.02 * np.abs(truth))
    assert math.isclose(2 * sol.cost, c.objective(vectorized=False)(sol.x), rel_tol=1e-10)


def test_lmfit_minimizer_takes_the_residuals_and_parameters_by_name():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_channels_synthetic.json")
    truth = dict(zip(c.genes, reference(c, "bearing_2dof_reference_params.json")))
    params = lmfit.Parameters()
    for name, p in c.params.items():
        if p.vary:
            params.add(name, value=truth[name] * 1.05, min=p.min, max=p.max)
    out = lmfit.Minimizer(c.residuals, params).minimize(method="least_squares")
    assert out.success
    for name, v in truth.items():
        fitted = out.params[name]
        assert abs(fitted.value - v) <= 0.02 * abs(v), (name, fitted.value, v)
    # lmfit's chi-square of these residuals is the objective.
    best = np.array([out.params[g].value for g in c.genes])
    assert math.isclose(out.chisqr, c.objective(vectorized=False)(best), rel_tol=1e-10)
    assert out.ndata == window_samples(c) and out.nvarys == len(c.genes)


def test_residuals_follow_set_data_and_refuse_bad_arguments():
    c = rigfit.Campaign.from_json(CAMPAIGNS / "inertial_sdof_synthetic.json")
    x = random_sets(c, 1, 3)[0]
    before = c.residuals(x)
    import pandas as pd
    frame = pd.read_csv(CAMPAIGNS / "inertial_sdof_synthetic.csv", comment="#")
    frame["force_N"] = frame["force_N"] * 1.5
    c.set_data("sweep", frame)
    after = c.residuals(x)
    assert not np.array_equal(before, after)
    assert math.isclose(float(np.sum(after ** 2)), c.objective(vectorized=False)(x), rel_tol=1e-12)
    with pytest.raises(rigfit.CampaignError, match=r"theta: expected an array of shape \(6,\)"):
        c.residuals(np.zeros(5))
    with pytest.raises(rigfit.CampaignError, match="theta: no value for"):
        c.residuals({c.genes[0]: 1.0})
    with pytest.raises(rigfit.CampaignError, match="theta: expected finite"):
        c.residuals(np.full(6, np.nan))
    with pytest.raises(rigfit.ArgumentTypeError, match="theta"):
        c.residuals("1,2,3")
    with pytest.raises(rigfit.CampaignError, match="backend='tpu'"):
        c.residuals(x, backend="tpu")
    with pytest.raises(rigfit.CampaignError, match="threads=-1"):
        c.residuals(x, threads=-1)


# -- fit statistics ---------------------------------------------------------
@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fit")
    raw = json.loads((CAMPAIGNS / "bearing_2dof_channels_synthetic.json").read_text())
    raw["search"] = {"population": 48, "generations": 8, "seed": 3}
    raw["solver"]["backend"] = "cpu"
    c = rigfit.Campaign.from_dict(raw, base_dir=CAMPAIGNS)
    result = rigfit.fit(c, out=str(tmp / "out"))
    return c, result, tmp


def test_fit_statistics_are_lmfits_of_the_results_own_residuals(fitted):
    c, res, _ = fitted
    windows = [x.residual[x.in_fit_window] for x in res.experiments.values()]
    chisqr = sum(float(np.sum(w ** 2)) for w in windows)
    n = sum(w.size for w in windows)
    assert res.ndata == n == window_samples(c) == res.summary["polish"]["residuals"]
    assert res.nvarys == len(c.genes) == 6
    assert math.isclose(res.chisqr, chisqr, rel_tol=1e-9)
    assert math.isclose(res.redchi, chisqr / (n - 6), rel_tol=1e-9)
    assert math.isclose(res.aic, n * math.log(chisqr / n) + 2 * 6, rel_tol=1e-9)
    assert math.isclose(res.bic, n * math.log(chisqr / n) + math.log(n) * 6, rel_tol=1e-9)
    s = res.summary
    assert res.nfev == s["evaluations"] + s["polish"]["evaluations"] > s["evaluations"]
    assert isinstance(res.success, bool)
    assert res.success == (s["polish"]["stop"] == "converged")
    assert s["stop_reason"] in res.message and "polish" in res.message
    report = res.fit_report()
    for label in ("# function evals", "# data points", "# variables", "chi-square",
                  "reduced chi-square", "Akaike info crit", "Bayesian info crit"):
        assert label in report
    assert f"# function evals   = {res.nfev}" in report


def test_covariance_is_the_correlation_times_the_standard_errors(fitted):
    _, res, _ = fitted
    cov = res.covariance
    p = len(res.var_names)
    assert cov.shape == (p, p)
    assert np.allclose(cov, cov.T, rtol=1e-12, atol=0, equal_nan=True)
    assert np.allclose(np.diag(cov), res.stderr ** 2, rtol=1e-15)
    sigma = np.sqrt(np.diag(cov))
    corr = cov / np.outer(sigma, sigma)
    off = ~np.eye(p, dtype=bool)
    assert np.allclose(corr[off], res.correlation[off], rtol=1e-12)
    # Positive semi-definite, as a covariance is.
    assert np.min(np.linalg.eigvalsh(cov)) > -1e-9 * np.max(np.diag(cov))


def test_fit_statistics_survive_save_and_load(fitted):
    _, res, tmp = fitted
    back = rigfit.load_result(tmp / "out")
    assert back.ndata == res.ndata and back.nvarys == res.nvarys and back.nfev == res.nfev
    assert math.isclose(back.chisqr, res.chisqr, rel_tol=1e-12)
    assert np.array_equal(back.covariance, res.covariance)
    assert back.success == res.success and back.message == res.message


def test_no_polish_means_no_covariance(fitted):
    _, res, _ = fitted
    files = dict(res.files)
    summary = json.loads(files["result.json"])
    del summary["polish"]
    for p in summary["parameters"]:
        for k in ("std_error", "interval_95"):
            p.pop(k, None)
    files["result.json"] = json.dumps(summary).encode()
    bare = rigfit.FitResult(files)
    assert bare.covariance is None
    assert bare.success is False
    assert "no polish" in bare.message
    assert bare.nfev == summary["evaluations"]


def test_labelled_parameter_sets_are_read_by_label():
    import pandas as pd
    c = rigfit.Campaign.from_json(CAMPAIGNS / "bearing_2dof_synthetic.json")
    theta = random_sets(c, 2, 5)
    by_position = c.residuals(theta)
    frame = pd.DataFrame(theta, columns=c.genes)[list(reversed(c.genes))]
    assert np.array_equal(c.residuals(frame), by_position)
    series = pd.Series(theta[0], index=c.genes)[::-1]
    assert np.array_equal(c.residuals(series), by_position[0])
    assert np.array_equal(c.residuals(rigfit.Parameters(
        (g, rigfit.Parameter(g, value=v)) for g, v in zip(c.genes, theta[0]))), by_position[0])
    with pytest.raises(rigfit.CampaignError, match="no value for the free parameter"):
        c.residuals(pd.Series(theta[0]))
