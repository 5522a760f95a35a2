"""Pre-calibration and identification on arrays: the numbers ``rigfit
ringdown``, ``rigfit fit-specimen``, ``rigfit identify frf``, ``rfs``,
``idim`` and ``nimiso`` print with
``--json``, as dicts, and the campaign fragment each suggests
(``.fragment``)."""

import json

import numpy as np

from . import _rigfit


class Report(dict):
    """A report dict (the CLI's ``--json`` object) with ``fragment``: the
    campaign keys it suggests (``{"params": {...}}``)."""

    fragment = None
    spectra = None


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


def frf(t, u, y, *, response="displacement", segment=None, modes=1, f_min=None, f_max=None,
        min_coherence=0.8, names=("m", "k", "c"), fixed=False):
    """The H1/H2 frequency response of output ``y`` to input ``u`` (a force,
    N, for the modal m, k, c) at times ``t`` (s, uniform), its coherence, and
    a modal fit of ``modes`` modes (0: none), as ``rigfit identify frf``
    computes them. ``response``: what ``y`` is (``"displacement"``,
    ``"velocity"``, ``"acceleration"``). Returns ``{"welch", "modal",
    "assumes"}`` as the CLI's ``--json`` prints them, with ``.fragment`` and
    ``.spectra``: a dict of ``freqs`` (Hz), ``h1``, ``h2`` (complex) and
    ``coherence`` arrays."""
    t, u = _arrays(t, u)
    y = np.ascontiguousarray(np.asarray(y, dtype=np.float64))
    report, fragment, cols = _rigfit.frf_report(
        t, u, y, response=response, segment=segment, modes=modes, f_min=f_min, f_max=f_max,
        min_coherence=min_coherence, names=list(names), fixed=fixed)
    r = _report((report, fragment))
    freqs, h1r, h1i, h2r, h2i, coh = (np.asarray(c) for c in cols)
    r.spectra = {"freqs": freqs, "h1": h1r + 1j * h1i, "h2": h2r + 1j * h2i, "coherence": coh}
    return r


def rfs(t, x, accel, *, mass, terms=("linear", "viscous"), alpha=None, beta=None, cutoff=None,
        filter_order=4, fixed=False):
    """The restoring-force surface of a single-degree-of-freedom record
    (displacement ``x`` in m, acceleration ``accel`` in m/s², times ``t`` in
    s, the known ``mass`` in kg) and the direct parameter estimate of
    ``terms`` on it (``"linear"``, ``"cubic"``, ``"power-stiffness"``,
    ``"viscous"``, ``"cubic-damping"``, ``"power-damping"``, ``"coulomb"``),
    as ``rigfit identify rfs`` computes them. Returns ``{"dpe": {...}}`` as
    its ``--json`` prints it, with ``.fragment``."""
    t, x = _arrays(t, x)
    a = np.ascontiguousarray(np.asarray(accel, dtype=np.float64))
    return _report(_rigfit.rfs_report(t, x, a, mass=mass, terms=list(terms), alpha=alpha,
                                      beta=beta, cutoff=cutoff, filter_order=filter_order,
                                      fixed=fixed))


def idim(q, force, *, sample_rate=None, t=None, gain=1.0, cutoff=100.0, filter_order=4,
         decimation=10, fixed=False):
    """The inverse-model least squares of ``rigfit identify idim`` (the EMPS
    benchmark's): mass, viscous and Coulomb friction and offset from a
    position ``q`` (m) and a force ``force`` (N per ``gain``: a controller
    voltage times the drive's gain) sampled at ``sample_rate`` (Hz) or at the
    times ``t`` (s). Returns ``{"idim": {...}}`` as its ``--json`` prints it,
    with ``.fragment``."""
    q, force = _arrays(q, force)
    if t is not None:
        t = np.ascontiguousarray(np.asarray(t, dtype=np.float64))
    return _report(_rigfit.idim_report(q, force, sample_rate=sample_rate, t=t, gain=gain,
                                       cutoff=cutoff, filter_order=filter_order,
                                       decimation=decimation, fixed=fixed))


def nimiso(t, x, f, *, f_min, f_max, nonlinear="cubic", segment=None, fixed=False):
    """The reverse-path nonlinear MISO analysis of ``rigfit identify nimiso``
    (``m·ẍ + c·ẋ + k·x + a·g = F`` read backwards): motion ``x`` (m) and
    force ``f`` (N) at times ``t`` (s), ``nonlinear`` the g
    (``"cubic"``: x³, ``"sign-velocity"``: sgn ẋ, ``"quadratic-damping"``:
    |ẋ|·ẋ) and the band ``f_min``..``f_max`` (Hz) it fits. Returns
    ``{"nimiso": {...}}`` as its ``--json`` prints it, with ``.fragment``."""
    t, x = _arrays(t, x)
    f = np.ascontiguousarray(np.asarray(f, dtype=np.float64))
    return _report(_rigfit.nimiso_report(t, x, f, f_min=f_min, f_max=f_max, nonlinear=nonlinear,
                                         segment=segment, fixed=fixed))
