"""The result of a fit: what ``rigfit run`` writes, held in memory, with
lmfit-style parameters, numpy arrays, a tidy DataFrame, a text report and an
HTML view for Jupyter."""

import html
import io
import json
import os
import tempfile

import numpy as np

from .errors import DataError
from .params import Parameter, Parameters, _num

#: The files a result holds besides the per-experiment CSVs and figures (not
#: the folder's manifest, rigfit-files.json: that belongs to the folder, and
#: :meth:`FitResult.save` writes the one of the folder it saves into).
_FIXED_FILES = ("result.json", "history.csv", "fitness.svg", "report.html")

#: What every report.html rigfit writes begins with (after its doctype): a
#: file that does not is not replaced by :meth:`FitResult.report`.
_REPORT_MARK = b'<meta name="generator" content="rigfit'



class ExperimentResult:
    """One experiment's fit: R² and the record's columns as numpy arrays
    (``t`` record time in s, ``t_model``, ``measured``, ``model`` (samples,
    outputs), ``residual`` = model output 0 − measurement,
    ``in_fit_window``), the rows and columns of the ``<experiment>.csv``
    ``rigfit run`` writes. From :func:`rigfit.fit` they are the job's own
    numbers in full precision (f64); read back by :func:`rigfit.load_result`
    they are the CSV's, to 7 significant digits (``full_precision`` says
    which)."""

    def __init__(self, summary, csv_bytes, arrays=None, _label=None):
        self.summary = summary
        self.name = summary["name"]
        self.r2 = summary["r2"]
        self.one_minus_r2 = summary["one_minus_r2"]
        self.residual_rms = summary.get("residual_rms")
        self.unit = summary.get("unit", "")
        label = _label or summary.get("csv") or "the experiment's CSV"
        header, table = _read_csv(csv_bytes, label)
        self.columns = header
        model_cols = [i for i, h in enumerate(header) if h.startswith("model_")]
        self.output_columns = [header[i] for i in model_cols]
        #: Whether the arrays are the job's f64 numbers (a fit in this
        #: process, or its pickle) rather than the CSV's 7 digits.
        self.full_precision = arrays is not None
        if arrays is not None:
            self.t = np.asarray(arrays["t"], dtype=float)
            self.t_model = np.asarray(arrays["t_model"], dtype=float)
            self.measured = np.asarray(arrays["measured"], dtype=float)
            self.model = np.asarray(arrays["model"], dtype=float).reshape(len(self.t), -1)
            self.residual = np.asarray(arrays["residual"], dtype=float)
            self.in_fit_window = np.asarray(arrays["in_fit_window"], dtype=bool)
            return
        residual = [i for i, h in enumerate(header) if h.startswith("residual_")]
        if (table.shape[1] != len(header) or len(header) < 5 or not model_cols or not residual
                or header[-1] != "in_fit_window"):
            raise DataError(
                f"{label}: expected the columns t, t_model, measured, model_*, residual_*, "
                f"in_fit_window, found {','.join(header)} ({table.shape[1]} per row)")
        self.t = table[:, 0]
        self.t_model = table[:, 1]
        self.measured = table[:, 2]
        self.model = table[:, model_cols]
        self.residual = table[:, residual[0]]
        self.in_fit_window = table[:, -1].astype(bool)

    def _arrays(self):
        return {"t": self.t, "t_model": self.t_model, "measured": self.measured,
                "model": self.model, "residual": self.residual,
                "in_fit_window": self.in_fit_window}

    @property
    def cleaned_force(self):
        """The model's specimen force (the *cleaned* force) where the rig
        has a ``specimen_force`` output, else ``None``."""
        for i, h in enumerate(self.output_columns):
            if h.startswith("model_specimen_force"):
                return self.model[:, i]
        return None

    def to_dataframe(self):
        """The experiment's CSV as a pandas DataFrame (its columns, with the
        arrays' precision)."""
        import pandas as pd
        header, table = self.columns, np.column_stack(
            [self.t, self.t_model, self.measured, self.model, self.residual, self.in_fit_window])
        df = pd.DataFrame(table, columns=header)
        df["in_fit_window"] = df["in_fit_window"].astype(bool)
        return df

    def __repr__(self):
        return f"<ExperimentResult {self.name!r}: R² = {self.r2:.6f}, {len(self.t)} samples>"


class FitResult:
    """The result of :func:`rigfit.fit` (or :func:`load_result`).

    ``params`` (lmfit-style, with ``value``, ``stderr``, ``interval95``,
    ``min``, ``max``, ``unit``, ``determined``, ``at_bound``), ``correlation``
    (the free parameters' correlation matrix, ``var_names`` its order),
    ``experiments`` (name → :class:`ExperimentResult` with R², residuals and
    model outputs as arrays: in full precision from a fit, to the CSV's 7
    digits from :func:`load_result`), ``r2``, ``fitness`` (the weighted 1 − R²),
    ``summary`` (result.json as a dict), ``fit_report()``,
    ``to_dataframe()``, ``save(folder)``, ``report(path)`` (the HTML report).
    Picklable.
    """

    def __init__(self, files, arrays=None, _folder=None):
        #: file name -> bytes, exactly as ``rigfit run`` wrote them.
        self.files = dict(files)
        arrays = arrays or {}
        self.summary = json.loads(self.files["result.json"])
        label = (lambda n: os.path.join(_folder, n)) if _folder is not None else (lambda n: n)
        s = self.summary
        self.params = Parameters()
        for p in s["parameters"]:
            b = p.get("bounds")
            self.params[p["name"]] = Parameter(
                p["name"], value=p["value"], min=b[0] if b else None, max=b[1] if b else None,
                vary=p["free"], unit=p.get("unit", ""), stderr=p.get("std_error"),
                interval95=tuple(p["interval_95"]) if p.get("interval_95") else None,
                determined=p.get("determined"), at_bound=p.get("at_bound"),
                correlated_with=p.get("correlated_with", ()), elite_range=p.get("elite_range"),
                uncertainty_note=p.get("uncertainty_note"))
        polish = s.get("polish") or {}
        self.var_names = list(polish.get("genes", [p["name"] for p in s["parameters"] if p["free"]]))
        corr = polish.get("correlation")
        self.correlation = (np.array([[np.nan if v is None else v for v in row] for row in corr], dtype=float)
                            if corr else None)
        self.experiments = {
            x["name"]: ExperimentResult(x, self.files[x["csv"]], arrays.get(x["name"]), label(x["csv"]))
            for x in s["experiments"]
        }
        self.fitness = s["fitness"]
        self.r2 = {k: x.r2 for k, x in self.experiments.items()}
        self.seed = s["seed"]
        self.backend = s["backend"]
        self.device = s["device"]
        self.stop_reason = s["stop_reason"]
        self.warnings = list(s.get("warnings", []))

    # -- arrays -------------------------------------------------------
    @property
    def best_values(self):
        """name → value of every parameter (the flat ``params`` of
        result.json, which feeds back as a parameter file)."""
        return dict(self.summary["params"])

    @property
    def x(self):
        """The free parameters' values in the genes' order (SciPy's ``x``)."""
        return np.array([self.params[n].value for n in self.var_names])

    @property
    def stderr(self):
        return np.array([np.nan if self.params[n].stderr is None else self.params[n].stderr
                         for n in self.var_names])

    # -- lmfit's fit statistics ----------------------------------------
    @property
    def covariance(self):
        """The free parameters' covariance matrix (P, P) in :attr:`var_names`
        order and their units, as lmfit's ``covar``: the polish's
        correlation × the standard errors (``C_ij = ρ_ij σ_i σ_j``; a
        log-scale parameter's σ is its value × the error of its log, so its
        rows are the delta method's). ``None`` where the job ran no polish
        or the polish did not determine it; an entry the polish left
        undetermined (a parameter without a standard error) is NaN."""
        if self.correlation is None or not self.var_names:
            return None
        sigma = self.stderr
        if not np.isfinite(sigma).any():
            return None
        cov = self.correlation * np.outer(sigma, sigma)
        cov[np.diag_indices_from(cov)] = sigma ** 2
        return cov

    def _window_counts(self):
        # Samples of each experiment's (or channel's) fit window.
        return {k: int(np.count_nonzero(x.in_fit_window)) for k, x in self.experiments.items()}

    @property
    def ndata(self):
        """Data points fitted: the samples of every experiment's (every
        channel's) fit window, the length of
        :meth:`rigfit.Campaign.residuals`' vector."""
        return sum(self._window_counts().values())

    @property
    def nvarys(self):
        """The free parameters fitted."""
        return sum(1 for p in self.params.values() if p.vary)

    @property
    def nfree(self):
        """``ndata − nvarys``, lmfit's degrees of freedom."""
        return self.ndata - self.nvarys

    @property
    def chisqr(self):
        """lmfit's chi-square: the sum over every fit window of
        ``(model − measured)²``, unweighted, in the records' own units
        squared (a campaign whose channels have different units sums
        each channel's in its own). From the job's residual RMS per
        experiment (full precision) × its window's samples. The cost the
        search minimises is :attr:`fitness` (the weighted 1 − R²), whose
        residuals :meth:`rigfit.Campaign.residuals` gives."""
        counts = self._window_counts()
        total = 0.0
        for name, x in self.experiments.items():
            n = counts[name]
            if x.residual_rms is not None and n > 0:
                total += float(x.residual_rms) ** 2 * n
            else:
                r = x.residual[x.in_fit_window]
                total += float(np.sum(r * r))
        return total

    @property
    def redchi(self):
        """lmfit's reduced chi-square, ``chisqr / (ndata − nvarys)``."""
        nfree = self.nfree
        return self.chisqr / nfree if nfree > 0 else float("nan")

    def _log_likelihood_term(self):
        n = self.ndata
        chisqr = max(self.chisqr, 1e-250)
        return n * np.log(chisqr / n) if n > 0 else float("nan")

    @property
    def aic(self):
        """Akaike's information criterion as lmfit computes it,
        ``ndata · ln(chisqr / ndata) + 2 · nvarys``."""
        return float(self._log_likelihood_term() + 2 * self.nvarys)

    @property
    def bic(self):
        """The Bayesian information criterion as lmfit computes it,
        ``ndata · ln(chisqr / ndata) + ln(ndata) · nvarys``."""
        n = self.ndata
        return float(self._log_likelihood_term() + (np.log(n) if n > 0 else np.nan) * self.nvarys)

    @property
    def nfev(self):
        """Function evaluations the job made: the search's candidates plus
        the polish's (its Jacobian stencils included); the profiles' are
        not counted."""
        polish = self.summary.get("polish") or {}
        return int(self.summary.get("evaluations", 0)) + int(polish.get("evaluations", 0))

    @property
    def success(self):
        """Whether the job ran to its end (not interrupted) and its polish
        converged (so the covariance and the intervals are taken at an
        optimum)."""
        polish = self.summary.get("polish") or {}
        return (self.stop_reason != "interrupted" and polish.get("stop") == "converged")

    @property
    def message(self):
        """Why the search and the polish stopped, in words."""
        polish = self.summary.get("polish")
        text = f"search: {self.stop_reason}"
        if not polish:
            return text + "; no polish was run"
        stops = {"converged": "converged", "max_iterations": "stopped at its iteration limit",
                 "interrupted": "was interrupted", "no_start": "had no start (every start blew up)"}
        why = stops.get(polish.get("stop"), str(polish.get("stop")))
        return f"{text}; polish {why} after {polish.get('iterations', 0)} iteration(s)"

    @property
    def history(self):
        """history.csv (one row per generation logged) as a dict of arrays."""
        header, table = _read_csv(self.files["history.csv"])
        return {h: table[:, i] for i, h in enumerate(header)}

    def to_dataframe(self):
        """Every experiment's samples as one tidy DataFrame (one row per
        experiment, sample and output: ``experiment, t, output, measured,
        model, residual, in_fit_window``)."""
        import pandas as pd
        frames = []
        for name, x in self.experiments.items():
            for i, col in enumerate(x.output_columns):
                frames.append(pd.DataFrame({
                    "experiment": name, "t": x.t, "output": col[len("model_"):],
                    "measured": x.measured if i == 0 else np.nan, "model": x.model[:, i],
                    "residual": x.residual if i == 0 else np.nan,
                    "in_fit_window": x.in_fit_window,
                }))
        return pd.concat(frames, ignore_index=True)

    def params_dataframe(self):
        """The parameters as a DataFrame (one row each)."""
        import pandas as pd
        rows = []
        for p in self.params.values():
            lo, hi = p.interval95 if p.interval95 else (None, None)
            rows.append({"name": p.name, "value": p.value, "stderr": p.stderr, "ci95_low": lo,
                         "ci95_high": hi, "min": p.min, "max": p.max, "vary": p.vary,
                         "determined": p.determined, "at_bound": p.at_bound, "unit": p.unit})
        return pd.DataFrame(rows).set_index("name")

    # -- reports ------------------------------------------------------
    def fit_report(self):
        """A text report in lmfit's shape: fit statistics, the variables with
        their standard errors and 95 % intervals, the fixed values, the
        correlations above 0.1."""
        s = self.summary
        lines = ["[[Fit Statistics]]",
                 f"    campaign           = {s['campaign']} (rig {s['rig']})",
                 f"    backend            = {s['backend']} ({s['device']}, {s['precision']})",
                 f"    search method      = {s.get('search_method', 'ga')}",
                 f"    generations        = {s['generations']}",
                 f"    # function evals   = {self.nfev}",
                 f"    # data points      = {self.ndata}",
                 f"    # variables        = {self.nvarys}",
                 f"    chi-square         = {self.chisqr:.6e}",
                 f"    reduced chi-square = {self.redchi:.6e}",
                 f"    Akaike info crit   = {self.aic:.6f}",
                 f"    Bayesian info crit = {self.bic:.6f}",
                 f"    stop reason        = {s['stop_reason']}",
                 f"    success            = {self.success} ({self.message})",
                 f"    1 - R² (weighted)  = {s['fitness']:.6e}"]
        for name, x in self.experiments.items():
            lines.append(f"    R² {name:<15} = {x.r2:.8f}")
        lines.append("[[Variables]]")
        for p in self.params.values():
            if not p.vary:
                continue
            txt = f"    {p.name + ':':<16} {_num(p.value):>12}"
            if p.stderr is not None:
                rel = abs(p.stderr / p.value) * 100 if p.value else float("nan")
                txt += f" +/- {_num(p.stderr):<11} ({rel:.2f}%)"
            if p.interval95:
                txt += f" 95%: [{_num(p.interval95[0])}, {_num(p.interval95[1])}]"
            txt += f" {p.unit} (bounds [{_num(p.min)}, {_num(p.max)}])"
            if p.at_bound:
                txt += f" AT {str(p.at_bound).upper()} BOUND"
            elif p.determined is False:
                txt += " not determined"
            lines.append(txt)
        fixed = [p for p in self.params.values() if not p.vary]
        if fixed:
            lines.append("[[Fixed]]")
            for p in fixed:
                lines.append(f"    {p.name + ':':<16} {_num(p.value):>12} {p.unit}")
        if self.correlation is not None:
            pairs = []
            n = len(self.var_names)
            for i in range(n):
                for j in range(i + 1, n):
                    c = self.correlation[i, j]
                    if np.isfinite(c) and abs(c) > 0.1:
                        pairs.append((abs(c), self.var_names[i], self.var_names[j], c))
            if pairs:
                lines.append("[[Correlations]] (unreported correlations are < 0.100)")
                for _, a, b, c in sorted(pairs, reverse=True):
                    label = f"C({a}, {b})"
                    lines.append(f"    {label:<28} = {c:+.4f}")
        if self.warnings:
            lines.append("[[Warnings]]")
            lines.extend(f"    {w}" for w in self.warnings)
        return "\n".join(lines)

    def _repr_html_(self):
        s = self.summary
        profiles = {p["name"]: p for p in (s.get("profiles") or {}).get("parameters", [])}
        rows = []
        for p in self.params.values():
            ci = f"[{_num(p.interval95[0])}, {_num(p.interval95[1])}]" if p.interval95 else ""
            prof = profiles.get(p.name, {})
            pi = prof.get("interval")
            pci = ("[" + ", ".join("open" if v is None else _num(v) for v in pi) + "]") if pi else ""
            flag = ("at " + str(p.at_bound) + " bound") if p.at_bound else (
                "" if p.determined in (None, True) else "not determined")
            if prof.get("flag"):
                flag = ", ".join(x for x in (flag, "profile: " + prof["flag"]) if x)
            rows.append(
                "<tr>" + "".join(f"<td>{html.escape(str(v))}</td>" for v in (
                    p.name, _num(p.value), _num(p.stderr), ci, pci,
                    f"[{_num(p.min)}, {_num(p.max)}]" if p.vary else "fixed", p.unit, flag)) + "</tr>")
        r2 = ", ".join(f"{html.escape(k)}: {v:.6f}" for k, v in self.r2.items())
        verdict = (s.get("verdict") or {}).get("line", "")
        warnings = "".join(f"<li>{html.escape(w)}</li>" for w in self.warnings)
        validation = "".join(
            f"<li>validation {html.escape(x['name'])}: R² {x['r2']:.6f}"
            + (f", {x['cost_over_noise_floor']:.2f}× its noise floor"
               if x.get("cost_over_noise_floor") is not None else "") + "</li>"
            for x in (s.get("validation") or {}).get("experiments", []))
        return (f"<h4>rigfit fit: {html.escape(s['campaign'])}</h4>"
                f"<p><b>verdict:</b> {html.escape(verdict)}</p>"
                + (f"<ul>{warnings}</ul>" if warnings else "")
                + f"<p>rig {html.escape(s['rig'])}, {html.escape(self.backend)} "
                f"({html.escape(self.device)}), {s['generations']} generations, "
                f"stop: {html.escape(self.stop_reason)}; R² {r2}</p>"
                + (f"<ul>{validation}</ul>" if validation else "")
                + "<table><tr><th>name</th><th>value</th><th>std error</th>"
                "<th>95 % interval (covariance)</th><th>95 % interval (profile)</th>"
                "<th>bounds</th><th>unit</th><th></th></tr>" + "".join(rows) + "</table>"
                "<p>The whole report, with figures: <code>result.report(path)</code>.</p>")

    def report(self, path, overwrite=False):
        """Writes the job's report.html (the page ``rigfit run`` writes and
        ``rigfit report`` rebuilds: verdict, summary, figures, parameter
        table, correlations, convergence, profiles, validation) to ``path``
        (a file, or a folder to hold ``report.html``) and returns the path.

        Like the CLI it never replaces a file it did not write: an existing
        file is replaced only with ``overwrite=True`` and only when it is a
        rigfit report; a symbolic link is never written through. The file
        is written whole or not at all."""
        path = os.fspath(path)
        if os.path.isdir(path) and not os.path.islink(path):
            path = os.path.join(path, "report.html")
        page = self.files.get("report.html")
        if page is None:
            page = self._build_report()
        _write_new(path, page, overwrite, _REPORT_MARK, "a rigfit report")
        return path

    def _build_report(self):
        # A result read from a folder older than report.html: the page is
        # built from its files, as `rigfit report` would.
        from . import _rigfit
        with tempfile.TemporaryDirectory(prefix="rigfit-report-") as tmp:
            for name, data in self.files.items():
                with open(os.path.join(tmp, name), "wb") as f:
                    f.write(data)
            return _rigfit.report_html(tmp).encode()

    def __repr__(self):
        r2 = ", ".join(f"{k} {v:.6f}" for k, v in self.r2.items())
        return f"<rigfit.FitResult {self.summary['campaign']!r}: R² {r2}>"

    # -- files --------------------------------------------------------
    def save(self, folder, overwrite=False):
        """Writes exactly the files ``rigfit run`` wrote (result.json, the
        experiment CSVs, history.csv, the figures, report.html) into
        ``folder`` (created if missing) and returns it; the arrays read back
        from them by :func:`load_result` carry the CSVs' 7 significant
        digits.

        By the rules of ``rigfit run``'s own outputs: a folder that already
        holds a result is refused unless ``overwrite=True``, which replaces
        only files rigfit wrote there (listed in its ``rigfit-files.json``);
        a file of someone else's, a symbolic link (dangling or not) or a
        folder a running job holds raise ``FileExistsError`` and nothing is
        written. The files are written whole to temporaries first and
        renamed into place only once all are complete: a write that fails
        (a full disk) raises ``OSError`` and leaves the folder as it was."""
        from . import _arguments as check
        from . import _rigfit
        folder = check.path("folder", folder, optional=False)
        overwrite = check.flag("overwrite", overwrite)
        try:
            _rigfit.save_result(folder, list(self.files.items()), overwrite)
        except OSError as e:
            raise check.reword(e)  # the CLI's flags as keywords
        return folder

    def _arrays(self):
        return {k: x._arrays() for k, x in self.experiments.items() if x.full_precision}

    def __getstate__(self):
        return {"files": self.files, "arrays": self._arrays()}

    def __setstate__(self, state):
        self.__init__(state["files"], state.get("arrays"))

    def __eq__(self, other):
        # The same result: the same files (a fit equals what load_result
        # reads back from its saved folder, whose arrays are rounded).
        return isinstance(other, FitResult) and self.files == other.files


def load_result(path):
    """Reads the result ``rigfit run`` (or :meth:`FitResult.save`) left in a
    folder (or its ``result.json``). Its experiments' arrays are read from
    the CSVs, so they carry the CSVs' 7 significant digits (a fit held in
    memory, or pickled, keeps its full-precision arrays). A damaged folder
    (result.json missing or not a rigfit result, a CSV it names missing or
    unreadable, a file named outside the folder) raises
    :class:`rigfit.DataError` naming the file."""
    path = os.fspath(path)
    folder = os.path.dirname(path) if os.path.isfile(path) else path
    files = read_result_files(folder)
    where = os.path.join(folder, "result.json")
    try:
        return FitResult(files, _folder=folder)
    except DataError:
        raise
    except (KeyError, IndexError, TypeError, ValueError, AttributeError, StopIteration) as e:
        what = f"missing key {e}" if isinstance(e, KeyError) else f"{type(e).__name__}: {e}"
        raise DataError(f"{where}: not a rigfit result ({what})") from None


def _inside(folder, name, what):
    """The path of ``name`` in ``folder``; a name that leads outside it (an
    absolute path, ``..``, a symbolic link out of it) raises DataError."""
    where = os.path.join(folder, "result.json")
    if not isinstance(name, str) or not name or "\0" in name:
        raise DataError(f"{where}: {what}: expected a file name, found {name!r}")
    if os.path.isabs(name) or os.path.normpath(name).split(os.sep)[0] == os.pardir:
        raise DataError(
            f"{where}: {what}: {name!r} is outside the result folder; rigfit reads only the "
            "folder's own files")
    full = os.path.join(folder, name)
    root = os.path.realpath(folder)
    real = os.path.realpath(full)
    if os.path.commonpath([root, real]) != root:
        raise DataError(
            f"{full}: leads outside the result folder (to {real}); rigfit reads only the "
            "folder's own files")
    return full


def _read_file(full):
    try:
        with open(full, "rb") as f:
            return f.read()
    except OSError as e:
        raise DataError(f"{full}: cannot be read ({e.strerror or e})") from None


def read_result_files(folder):
    """The files of a result folder, by name. Raises :class:`rigfit.DataError`
    naming the file for a missing or damaged result.json, a CSV it names
    that is missing, or a name leading outside the folder."""
    folder = os.fspath(folder)
    where = os.path.join(folder, "result.json")
    if not os.path.isfile(where):
        raise DataError(f"{where}: no result.json here: not a rigfit result folder")
    raw = _read_file(_inside(folder, "result.json", "result.json"))
    try:
        summary = json.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise DataError(f"{where}: not UTF-8 text (byte {e.start})") from None
    except ValueError as e:
        raise DataError(f"{where}: malformed JSON: {e}") from None
    if not isinstance(summary, dict):
        raise DataError(f"{where}: expected a JSON object, found {type(summary).__name__}")
    experiments = summary.get("experiments")
    if not isinstance(experiments, list):
        raise DataError(f"{where}: experiments: expected a list, found {experiments!r:.60}")
    validation = summary.get("validation") or {}
    if not isinstance(validation, dict) or not isinstance(validation.get("experiments", []), list):
        raise DataError(f"{where}: validation: expected an object with an experiments list")
    listed = [("experiments", i, x) for i, x in enumerate(experiments)] + [
        ("validation.experiments", i, x) for i, x in enumerate(validation.get("experiments", []))]
    required, optional = [], list(_FIXED_FILES[1:])
    for key, i, x in listed:
        if not isinstance(x, dict):
            raise DataError(f"{where}: {key}[{i}]: expected an object, found {x!r:.60}")
        if "csv" not in x:
            raise DataError(f"{where}: {key}[{i}]: missing key 'csv'")
        required.append((f"{key}[{i}].csv", x["csv"]))
        if x.get("plot") is not None:
            optional.append(x["plot"])
    files = {"result.json": raw}
    for what, name in required:
        full = _inside(folder, name, what)
        if not os.path.isfile(full):
            raise DataError(f"{full}: missing (result.json names it at {what})")
        files[name] = _read_file(full)
    for name in optional:
        full = _inside(folder, name, name)
        if name not in files and os.path.isfile(full):
            files[name] = _read_file(full)
    return files


def _read_csv(data, label="the CSV"):
    try:
        text = data.decode() if isinstance(data, bytes) else data
    except UnicodeDecodeError as e:
        raise DataError(f"{label}: not UTF-8 text (byte {e.start})") from None
    lines = [l for l in text.splitlines() if l and not l.startswith("#")]
    if not lines:
        raise DataError(f"{label}: expected a header and rows, found no lines")
    header = lines[0].split(",")
    try:
        table = np.loadtxt(io.StringIO("\n".join(lines[1:])), delimiter=",", ndmin=2)
    except ValueError as e:
        raise DataError(f"{label}: expected rows of numbers ({e})") from None
    if table.size == 0:
        table = table.reshape(0, len(header))
    return header, table


def _write_new(path, data, overwrite, mark, what):
    """Writes ``data`` to ``path`` whole or not at all (a temporary file
    beside it, then renamed over it). An existing ``path`` is replaced only
    with ``overwrite`` and only when it holds ``mark`` near its start (it is
    ``what``); a symbolic link is never written through nor replaced."""
    if os.path.islink(path):
        raise FileExistsError(f"{path} is a symbolic link; rigfit does not write through links")
    if os.path.lexists(path):
        if not overwrite:
            raise FileExistsError(f"{path} already exists; pass overwrite=True to replace it")
        with open(path, "rb") as f:
            head = f.read(4096)
        if mark not in head:
            raise FileExistsError(
                f"{path} is not {what}: rigfit replaces only files it wrote; choose another path")
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
