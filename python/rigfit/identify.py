"""Pre-calibration and identification on arrays: the numbers ``rigfit
ringdown``, ``rigfit fit-specimen`` and ``rigfit identify`` (``frf``,
``rfs``, ``idim``, ``nimiso``, ``arx``, ``impedance``, ``sensitivity``)
print with ``--json``, as dicts, and the campaign fragment each suggests
(``.fragment``)."""

import json

import numpy as np

from . import _arguments as check
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
    m1, k1 = check.real("m1", m1, positive=True), check.real("k1", k1, positive=True)
    start = check.real("start", start)
    t, f = _arrays(t, f)
    return _report(_rigfit.ringdown_report(t, f, m1=m1, k1=k1, start=start))


def fit_specimen(e, f, *, degree=3):
    """The specimen law (linear elastic, then a plastic polynomial of
    ``degree``) fitted to quasi-static elongation ``e`` (m) and force ``f``
    (N). Returns ``{"fit": {...}}`` as ``rigfit fit-specimen --json`` prints it."""
    degree = check.integer("degree", degree, minimum=1, maximum=5, optional=False)
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
    response = check.text("response", response, optional=False)
    segment = check.integer("segment", segment, minimum=1)
    modes = check.integer("modes", modes, optional=False)
    f_min, f_max = check.real("f_min", f_min), check.real("f_max", f_max)
    min_coherence = check.real("min_coherence", min_coherence, optional=False)
    names, fixed = check.strings("names", names), check.flag("fixed", fixed)
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
    mass = check.real("mass", mass, optional=False, positive=True)
    terms = [terms] if isinstance(terms, str) else check.strings("terms", terms)
    alpha, beta = check.real("alpha", alpha), check.real("beta", beta)
    cutoff = check.real("cutoff", cutoff, positive=True)
    filter_order = check.integer("filter_order", filter_order, minimum=1, optional=False)
    fixed = check.flag("fixed", fixed)
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
    sample_rate = check.real("sample_rate", sample_rate, positive=True)
    gain = check.real("gain", gain, optional=False)
    cutoff = check.real("cutoff", cutoff, optional=False, positive=True)
    filter_order = check.integer("filter_order", filter_order, minimum=1, optional=False)
    decimation = check.integer("decimation", decimation, minimum=1, optional=False)
    fixed = check.flag("fixed", fixed)
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
    f_min = check.real("f_min", f_min, optional=False)
    f_max = check.real("f_max", f_max, optional=False)
    nonlinear = check.text("nonlinear", nonlinear, optional=False)
    segment = check.integer("segment", segment, minimum=1)
    fixed = check.flag("fixed", fixed)
    t, x = _arrays(t, x)
    f = np.ascontiguousarray(np.asarray(f, dtype=np.float64))
    return _report(_rigfit.nimiso_report(t, x, f, f_min=f_min, f_max=f_max, nonlinear=nonlinear,
                                         segment=segment, fixed=fixed))


def _channels(record, name, parts):
    """A record's three channels as contiguous f64 arrays."""
    cols = [np.ascontiguousarray(np.asarray(c, dtype=np.float64)) for c in record]
    if len(cols) != 3:
        from .errors import CampaignError
        raise CampaignError(f"{name}: expected three arrays ({parts}), found {len(cols)}")
    return cols


def arx(t, u, ys, *, mass, f_min, f_max, names=("k2", "c2"), form="linear", segment=None,
        min_coherence=0.9, fixed=False):
    """The transmissibility between two measured points and the element
    between them, as ``rigfit identify arx`` computes them: ``u`` the
    reference channel (the node on the driven side of the element), ``ys``
    the response channels (one array, or a sequence of them: the node across
    the element first, then every node it carries) with their ``mass`` (kg,
    one per response channel), sampled at times ``t`` (s, uniform). Fits the
    element's stiffness and damping (campaign names ``names``) over the lines
    of ``f_min``..``f_max`` (Hz) with a coherence of at least
    ``min_coherence``, and the frequency-domain ARX coefficients of ``form``
    (``"linear"``: Eq. 5, ``"cubic"``: Eq. 6). Returns ``{"welch",
    "element", "arx"}`` as its ``--json`` prints them, with ``.fragment`` and
    ``.spectra``: ``freqs`` (Hz), ``t`` (complex, channels × lines) and
    ``coherence`` (channels × lines)."""
    f_min = check.real("f_min", f_min, optional=False)
    f_max = check.real("f_max", f_max, optional=False)
    names, form = check.strings("names", names), check.text("form", form, optional=False)
    segment = check.integer("segment", segment, minimum=1)
    min_coherence = check.real("min_coherence", min_coherence, optional=False)
    fixed = check.flag("fixed", fixed)
    mass = [check.real("mass", m, optional=False, positive=True)
            for m in np.atleast_1d(np.asarray(mass, dtype=object))]
    t, u = _arrays(t, u)
    ys = np.asarray(ys, dtype=np.float64)
    ys = [np.ascontiguousarray(y) for y in (ys[None, :] if ys.ndim == 1 else ys)]
    report, fragment, spectra = _rigfit.arx_report(
        t, u, ys, mass=mass, f_min=f_min, f_max=f_max, names=list(names), form=form,
        segment=segment, min_coherence=min_coherence, fixed=fixed)
    r = _report((report, fragment))
    r.spectra = {"freqs": np.asarray(spectra["freqs"]),
                 "t": np.asarray(spectra["re"]) + 1j * np.asarray(spectra["im"]),
                 "coherence": np.asarray(spectra["coherence"])}
    return r


def impedance(t, x_impact, y_impact, *, f_min, f_max, mass=None, fixed=False):
    """The 2 × 2 impedance and receptance matrices of a point mass from an
    impact in x (``x_impact``) and one in y (``y_impact``), each a triple of
    arrays (hammer force in N, x and y displacement in m) sampled at times
    ``t`` (s, uniform), and K, C and M (unless ``mass``, kg, is given)
    fitted over ``f_min``..``f_max`` (Hz), as ``rigfit identify impedance``
    computes them. Returns ``{"impedance": {...}}`` as its ``--json`` prints
    it, with ``.fragment`` (the ``bearing_2dof`` rig's parameters)."""
    f_min = check.real("f_min", f_min, optional=False)
    f_max = check.real("f_max", f_max, optional=False)
    mass = check.real("mass", mass, positive=True)
    fixed = check.flag("fixed", fixed)
    t = np.ascontiguousarray(np.asarray(t, dtype=np.float64))
    return _report(_rigfit.impedance_report(
        t, _channels(x_impact, "x_impact", "force, x, y"),
        _channels(y_impact, "y_impact", "force, x, y"), f_min=f_min, f_max=f_max, mass=mass,
        fixed=fixed))


def sensitivity(t, base, changed, *, k1, f_min, f_max, c1=0.0, segment=None, name="k2",
                base_value=None, fixed=False):
    """The change of a quarter car's strut stiffness between two records by
    the experimental sensitivity functions, as ``rigfit identify
    sensitivity`` computes it: ``base`` and ``changed`` each a triple of
    arrays (wheel pan, unsprung mass, sprung mass) sampled at times ``t``
    (s, uniform), the tire's stiffness ``k1`` (N/m) and damping ``c1``
    (N·s/m), the change averaged over ``f_min``..``f_max`` (Hz). Returns
    ``{"welch", "sensitivity"}`` as its ``--json`` prints them, with
    ``.fragment``: ``name`` after the change when ``base_value`` (N/m) gives
    it before."""
    k1 = check.real("k1", k1, optional=False, positive=True)
    c1 = check.real("c1", c1, optional=False)
    f_min = check.real("f_min", f_min, optional=False)
    f_max = check.real("f_max", f_max, optional=False)
    segment = check.integer("segment", segment, minimum=1)
    name = check.text("name", name, optional=False)
    base_value = check.real("base_value", base_value)
    fixed = check.flag("fixed", fixed)
    t = np.ascontiguousarray(np.asarray(t, dtype=np.float64))
    parts = "wheel pan, unsprung, sprung"
    return _report(_rigfit.sensitivity_report(
        t, _channels(base, "base", parts), _channels(changed, "changed", parts), k1=k1,
        f_min=f_min, f_max=f_max, c1=c1, segment=segment, name=name, base_value=base_value,
        fixed=fixed))
