"""The ensemble as a function: histories and costs of many parameter sets in
one call, on the CPU lanes or the GPU."""

import warnings

import numpy as np

from . import _arguments as check
from . import _rigfit
from .errors import CampaignError, Error, GpuFallbackWarning


def _labelled(campaign, theta, name="theta"):
    """A parameter set given by name, read by label against
    ``campaign.genes``: a pandas Series (one set), a DataFrame (a set per
    row), a dict of name -> number (one set) or -> 1-D array (a set per
    element), or lmfit/rigfit ``Parameters``. Returns ``(a, single)``: ``a``
    the (S, P) array in genes' order, ``single`` whether one set was given;
    ``None`` for anything else (read by position). A missing free parameter
    or a name the campaign lacks raises :class:`CampaignError` naming them
    (with a did-you-mean); a fixed parameter's name passes only with the
    value the campaign fixes it at (``set_params`` changes that)."""
    module = type(theta).__module__
    if module.startswith("pandas") and getattr(theta, "ndim", 0) in (1, 2):
        if theta.ndim == 1:
            columns = {str(k): np.asarray([v], dtype=object) for k, v in theta.items()}
            single = True
        else:
            columns = {str(k): np.asarray(theta[k], dtype=object) for k in theta.columns}
            single = False
    elif hasattr(theta, "valuesdict") and callable(theta.valuesdict):
        columns = {str(k): np.asarray([v], dtype=object) for k, v in theta.valuesdict().items()}
        single = True
    elif isinstance(theta, dict):
        columns = {}
        single = True
        for k, v in theta.items():
            v = getattr(v, "value", v)
            a = np.asarray(v, dtype=object)
            if a.ndim > 1:
                raise CampaignError(f"{name}[{k!r}]: expected a number or a 1-D array, "
                                    f"found shape {a.shape}")
            single = single and a.ndim == 0
            columns[str(k)] = a.reshape(-1)
    else:
        return None
    genes = campaign.genes
    numeric = {}
    for k, v in columns.items():
        try:
            numeric[k] = v.astype(np.float64)
        except (TypeError, ValueError):
            raise check.ArgumentTypeError(
                f"{name}[{k!r}]: expected numbers, found {check._found(v[0] if v.size else v)}"
            ) from None
    sizes = {len(v) for v in numeric.values()}
    if len(sizes) > 1:
        raise CampaignError(f"{name}: expected one length for every parameter's values, found "
                            f"{sorted(sizes)}")
    missing = [g for g in genes if g not in numeric]
    extra = [k for k in numeric if k not in genes]
    fixed = {}
    if extra:
        fixed = {p.name: p.value for p in campaign.params.values() if not p.vary}
    unknown = [k for k in extra if k not in fixed]
    if missing or unknown:
        import difflib
        choices = genes + list(fixed)
        parts = []
        for k in unknown:
            close = difflib.get_close_matches(k, choices, n=1)
            parts.append(repr(k) + (f" (did you mean '{close[0]}'?)" if close else ""))
        why = []
        if missing:
            why.append(f"no value for the free parameter(s) {', '.join(map(repr, missing))}")
        if unknown:
            why.append(f"the campaign has no parameter {', '.join(parts)}")
        raise CampaignError(f"{name}: {'; '.join(why)}; expected a value for each of "
                            f"{', '.join(genes) or 'none (the campaign has no free parameter)'}")
    for k in extra:
        v, want = numeric[k], fixed[k]
        if not np.all((v == want) | (np.isnan(v) & (want != want))):
            found = float(v[v != want][0])
            raise CampaignError(
                f"{name}[{k!r}]: '{k}' is fixed at {want!r} in the campaign, found {found!r}; "
                f"change it with campaign.set_params({k}=...) (or params[{k!r}].value = ...)")
    n = sizes.pop() if sizes else 1
    a = np.empty((n, len(genes)), dtype=np.float64)
    for j, g in enumerate(genes):
        a[:, j] = numeric[g]
    return a, single


def _theta(campaign, theta, rows_are_sets=True):
    """Parameter sets as a contiguous (S, P) array: labelled ones (see
    :func:`_labelled`) by label, anything else by position."""
    labelled = _labelled(campaign, theta)
    if labelled is not None:
        return labelled[0]
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


def simulate(campaign, theta, *, t=None, dt=None, samples=None, experiment=None, noise=None,
             seed=None, drive=None, substeps=None, backend="cpu", precision=None, adapter=None,
             threads=0, max_memory=None):
    """Integrates the campaign's rig for every parameter set in ``theta``
    (S, P), the free parameters in ``campaign.genes`` order (the fixed ones
    as the campaign sets them).

    Without a time grid: over every experiment's samples, in one ensemble.
    Returns an array (S, experiments, samples, outputs) at the record's
    sample times (outputs in ``campaign.outputs`` order; an experiment
    shorter than the longest is padded with NaN). ``backend``: ``"cpu"``
    (the f64 lanes), ``"gpu"`` or ``"auto"``.

    With a time grid (``t=``, the times in s, uniformly spaced; or ``dt=``
    with ``samples=``, from t = 0): a synthetic record of ``experiment``
    (default: the first), which need not have a record yet (see
    :meth:`Campaign.from_dict`'s ``pending``). Returns a pandas DataFrame (a
    dict of columns without pandas; a list of them for a 2-D ``theta``) with
    the columns the experiment's ``data`` object reads: its time column
    (``t / data.time_scale``), each measured channel (the output divided by
    its scale, Gaussian noise of standard deviation ``noise`` added in the
    output's unit: a number, or a dict of output name → σ for an experiment
    with channels) and its drive column (``drive=``, one value per time, in
    the record's unit; required when the experiment reads one), so that
    ``campaign.set_data(experiment, df)`` takes it as it stands. ``seed``
    makes the noise reproducible (``numpy.random.default_rng(seed)``). The
    RK4 step is ``substeps`` per sample, else the one ``rigfit simulate``
    takes for a synthetic record (finer than a fit's, with noise), recorded
    in ``df.attrs["substeps"]``; it runs on the CPU's f64 lanes.

    ``max_memory``: bytes or a size with K, M, G or T (``"512M"``); default:
    the memory available now. A simulation whose histories do not fit is
    refused before any work with :class:`rigfit.CampaignError`."""
    check.campaign(campaign)
    max_memory = check.max_memory(max_memory)
    if t is not None or dt is not None or samples is not None:
        from ._grid import simulate_grid, time_grid
        grid = time_grid(t, dt, samples)
        if backend not in (None, "cpu") or precision not in (None, "auto", "f64") \
                or adapter is not None:
            raise CampaignError(
                "backend: a simulation on a time grid (t= or dt=) runs on the CPU's f64 lanes; "
                "leave backend, precision and adapter out")
        threads = check.threads(threads)
        inner = campaign._values()
        labelled = _labelled(campaign, theta)
        if labelled is not None:
            a, single = labelled
        else:
            a, single = _theta(campaign, theta), np.ndim(theta) < 2
        out, notes = simulate_grid(campaign, inner, a, t=grid, experiment=experiment,
                                   noise=noise, seed=seed, drive=drive, substeps=substeps,
                                   threads=threads, max_memory=max_memory, single=single)
        _warn(notes)
        return out
    for key, value in (("experiment", experiment), ("noise", noise), ("seed", seed),
                       ("drive", drive), ("substeps", substeps)):
        if value is not None:
            raise CampaignError(f"{key}: a synthetic record needs a time grid: give t= (the "
                                f"times in s) or dt= and samples= with it")
    kwargs = _checked(backend, precision, adapter, threads)
    a = _theta(campaign, theta)
    try:
        out, notes = _rigfit.simulate(campaign._inner, a, max_memory=max_memory, **kwargs)
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
        labelled = _labelled(self.campaign, x, "x")
        if labelled is not None:
            a, single = labelled
            costs = self._inner.costs(np.ascontiguousarray(a))
            self.evaluations += len(costs)
            return float(costs[0]) if single else costs
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
