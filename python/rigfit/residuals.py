"""The campaign's residual vector, for ``scipy.optimize.least_squares`` and
lmfit's ``Minimizer``: every experiment's fit window one after the other,
each sample's ``model − measured`` scaled by ``sqrt(w_e / (W · SS_tot,e))``
(``w_e`` the experiment's weight, ``W`` the sum of the weights, ``SS_tot,e``
the record's spread about its mean over the window), so that
``sum(r**2)`` is the cost :meth:`rigfit.Campaign.objective` returns, the
weighted mean of 1 − R². The residuals the job's local polish minimises."""

import warnings
import numpy as np

from . import _arguments as check
from . import _rigfit
from .ensemble import _checked, _labelled
from .errors import ArgumentTypeError, CampaignError, Error, GpuFallbackWarning

#: The cost the objective gives a run that blew up; its residual vector is
#: ``sqrt(DIVERGED / N)`` in every entry (finite, as ``least_squares``
#: requires), whose sum of squares is this.
DIVERGED = 1.0e30


def _values(campaign, theta):
    """``theta`` as an array: labelled (a dict, lmfit or rigfit
    ``Parameters``, a pandas Series or DataFrame: read by name, as every
    call taking a parameter set reads it, ``rigfit.ensemble._labelled``),
    or numbers in :attr:`Campaign.genes` order."""
    genes = campaign.genes
    labelled = _labelled(campaign, theta)
    if labelled is not None:
        a, single = labelled
        return a[0] if single else a
    if isinstance(theta, (str, bytes)) or theta is None:
        raise ArgumentTypeError(
            f"theta: expected an array of {len(genes)} value(s) ({', '.join(genes)}) or an "
            f"array of shape (S, {len(genes)}), found {check._found(theta)}")
    try:
        a = np.asarray(theta, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"theta: expected numbers, an array of shape ({len(genes)},) or "
            f"(S, {len(genes)}), found {check._found(theta)}") from None
    return a


class Residuals:
    """The residual function of a campaign with one evaluator opened for
    every call (see :meth:`rigfit.Campaign.residuals`)."""

    def __init__(self, campaign, *, backend="cpu", precision=None, adapter=None, threads=0):
        check.campaign(campaign)
        self.campaign = campaign
        kwargs = _checked(backend, precision, adapter, threads)
        try:
            self._inner = _rigfit.Residuals(campaign._inner, **kwargs)
        except Error as e:
            raise check.reword(e)
        _warn(self._inner.notes)

    @property
    def size(self):
        """N, the residuals in a vector: the fit windows' samples."""
        return self._inner.size

    def __call__(self, theta):
        a = _values(self.campaign, theta)
        p = len(self.campaign.genes)
        if a.ndim not in (1, 2) or a.shape[-1] != p:
            raise CampaignError(
                f"theta: expected an array of shape ({p},) or (S, {p}), one column per free "
                f"parameter ({', '.join(self.campaign.genes)}), found shape {a.shape}")
        bad = ~np.isfinite(a)
        if bad.any():
            raise CampaignError(
                f"theta: expected finite numbers, found {a[bad].flat[0]!r}")
        rows = np.ascontiguousarray(a.reshape(-1, p))
        if rows.shape[0] == 0:
            return np.zeros((0, self.size))
        try:
            out, notes = self._inner.of(rows)
        except Error as e:
            raise check.reword(e)
        _warn(notes)
        return out[0] if a.ndim == 1 else out


def _warn(notes):
    for note in notes:
        warnings.warn(f"rigfit: {check.reworded(note)}", GpuFallbackWarning, stacklevel=4)


def residuals(campaign, theta, *, backend="cpu", precision=None, adapter=None, threads=0):
    """:meth:`rigfit.Campaign.residuals`: the evaluator is opened once per
    campaign and keywords, and kept on the campaign for the next call."""
    check.campaign(campaign)
    key = (campaign._inner, backend, precision, adapter, threads)
    cached = campaign.__dict__.get("_residuals_fn")
    try:
        hit = cached is not None and cached[0] == key
    except (TypeError, ValueError):
        hit = False
    if hit:
        fn = cached[1]
    else:
        fn = Residuals(campaign, backend=backend, precision=precision, adapter=adapter,
                       threads=threads)
        campaign.__dict__["_residuals_fn"] = (key, fn)
    return fn(theta)


__all__ = ["DIVERGED", "Residuals", "residuals"]
