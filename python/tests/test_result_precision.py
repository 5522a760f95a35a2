"""A fitted result holds the job's own arrays in full precision (f64), not
the 7 significant digits of the CSVs it saves; read back from the files by
rigfit.load_result, it has the CSVs' digits."""

import pickle

import numpy as np

import rigfit


def _worst(a, b):
    """The largest difference of each column of a and b relative to b's largest magnitude."""
    return float((np.abs(a - b).max(axis=0) / np.abs(b).max(axis=0)).max())


def test_fitted_arrays_match_a_full_precision_recomputation(bearing, tmp_path):
    c = rigfit.Campaign.from_json(bearing)
    r = rigfit.fit(c, seed=5, backend="cpu")
    assert r.var_names == c.genes
    # The ensemble integrator at the fitted parameters, in f64.
    h = rigfit.simulate(c, r.x[None, :], backend="cpu")[0]
    back = rigfit.load_result(r.save(tmp_path / "saved"))
    for e, name in enumerate(c.experiments):
        x, csv = r.experiments[name], back.experiments[name]
        assert x.full_precision and not csv.full_precision
        want = h[e, :len(x.t), :]
        held, read = _worst(x.model, want), _worst(csv.model, want)
        print(f"{name}: in memory {held:.2e}, from the CSV {read:.2e} (largest relative difference)")
        assert held < 1e-12, held
        # The CSV's 7 significant digits: a rounding of about 5e-7 of the value.
        assert 1e-9 < read < 1e-6, read
        assert np.array_equal(x.residual, x.model[:, 0] - x.measured)
        assert np.array_equal(x.in_fit_window, csv.in_fit_window)
        np.testing.assert_allclose(x.t, csv.t, rtol=1e-9)
    # A pickle keeps the full-precision arrays; the saved files are those of the fit.
    again = pickle.loads(pickle.dumps(r))
    assert again == r and again.experiments["hx"].full_precision
    assert np.array_equal(again.experiments["hx"].model, r.experiments["hx"].model)
    assert back.files == r.files
