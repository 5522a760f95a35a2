"""The ensemble as a function: histories and costs of many parameter sets in
one call, on the CPU lanes or the GPU."""

import warnings

import numpy as np

from . import _arguments as check
from . import _rigfit
from .errors import CampaignError, Error, GpuFallbackWarning


def _theta(campaign, theta, rows_are_sets=True):
    a = np.asarray(theta, dtype=np.float64)
    if a.ndim == 1:
        a = a[None, :]
    elif not rows_are_sets:
        a = a.T
    if a.ndim != 2:
        raise CampaignError(f"theta: expected an array of shape (S, {len(campaign.genes)}), "
                            f"found shape {np.shape(theta)}")
    return np.ascontiguousarray(a)


def _checked(backend, precision, adapter, threads):
    """The evaluator's keywords, checked before any work."""
    return dict(backend=check.choice("backend", backend, ("auto", "gpu", "cpu")),
                precision=check.choice("precision", precision, ("auto", "f32", "f64")),
                adapter=check.adapter(adapter), threads=check.threads(threads))


def _warn(notes):
    for note in notes:
        note = check.reworded(note)
        warnings.warn(f"rigfit: {note}", GpuFallbackWarning, stacklevel=3)


def simulate(campaign, theta, *, backend="cpu", precision=None, adapter=None, threads=0):
    """Integrates the campaign's rig for every parameter set in ``theta``
    (S, P), the free parameters in ``campaign.genes`` order (the fixed ones
    as the campaign sets them), over every experiment's samples, in one
    ensemble. Returns an array (S, experiments, samples, outputs) at the
    record's sample times (outputs in ``campaign.outputs`` order; an
    experiment shorter than the longest is padded with NaN). ``backend``:
    ``"cpu"`` (the f64 lanes), ``"gpu"`` or ``"auto"``."""
    check.campaign(campaign)
    kwargs = _checked(backend, precision, adapter, threads)
    a = _theta(campaign, theta)
    try:
        out, notes = _rigfit.simulate(campaign._inner, a, **kwargs)
    except Error as e:
        raise check.reword(e)
    _warn(notes)
    return out


class Objective:
    """The campaign's cost (the weighted mean of 1 − R² over its experiments,
    1e30 for a diverged run) of the free parameters, for any optimiser. See
    :meth:`rigfit.Campaign.objective`."""

    def __init__(self, campaign, vectorized=True, *, backend=None, precision=None, adapter=None,
                 threads=0):
        check.campaign(campaign)
        self.campaign = campaign
        self.vectorized = check.flag("vectorized", vectorized)
        self._kwargs = kwargs = _checked(backend, precision, adapter, threads)
        try:
            self._inner = _rigfit.Objective(campaign._inner, **kwargs)
        except Error as e:
            raise check.reword(e)
        self.evaluations = 0
        _warn(self._inner.notes)

    @property
    def bounds(self):
        """(P, 2) bounds, as SciPy's ``bounds=`` takes them."""
        return self.campaign.bounds

    def __call__(self, x):
        a = np.asarray(x, dtype=np.float64)
        if a.ndim == 1:
            self.evaluations += 1
            return float(self._inner.costs(np.ascontiguousarray(a[None, :]))[0])
        if not self.vectorized:
            raise CampaignError(
                f"x: expected a vector of {len(self.campaign.genes)} values (vectorized=False), "
                f"found shape {a.shape}")
        costs = self._inner.costs(np.ascontiguousarray(a.T))
        self.evaluations += len(costs)
        return costs

    def __reduce__(self):
        # The evaluator is opened again where it is unpickled (a worker
        # process of multiprocessing, joblib or submitit).
        return (_objective, (self.campaign, self.vectorized, self._kwargs))


def _objective(campaign, vectorized, kwargs):
    return Objective(campaign, vectorized, **kwargs)
