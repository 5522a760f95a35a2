"""Pre-calibration on arrays: the numbers ``rigfit ringdown`` and ``rigfit
fit-specimen`` print with ``--json``, as dicts, and the campaign fragment
each suggests (``.fragment``)."""

import json

import numpy as np

from . import _rigfit


class Report(dict):
    """A report dict (the CLI's ``--json`` object) with ``fragment``: the
    campaign keys it suggests (``{"params": {...}}``)."""

    fragment = None


def _arrays(x, y):
    x = np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    y = np.ascontiguousarray(np.asarray(y, dtype=np.float64))
    return x, y


def _report(pair):
    r = Report(json.loads(pair[0]))
    r.fragment = json.loads(pair[1])
    return r


def ringdown(t, f, *, m1=None, k1=None, start=None):
    """Frequency and damping of a free ring-down (a hammer impact, a
    release, the load cell after a fracture): ``f`` at times ``t`` (s, uniform).
    With the load cell's mass ``m1`` (kg) or stiffness ``k1`` (N/m) also the
    other and the post-fracture damping. Returns ``{"ringdown": {...}}`` as
    ``rigfit ringdown --json`` prints it."""
    t, f = _arrays(t, f)
    return _report(_rigfit.ringdown_report(t, f, m1=m1, k1=k1, start=start))


def fit_specimen(e, f, *, degree=3):
    """The specimen law (linear elastic, then a plastic polynomial of
    ``degree``) fitted to quasi-static elongation ``e`` (m) and force ``f``
    (N). Returns ``{"fit": {...}}`` as ``rigfit fit-specimen --json`` prints it."""
    e, f = _arrays(e, f)
    return _report(_rigfit.specimen_report(e, f, degree=degree))
