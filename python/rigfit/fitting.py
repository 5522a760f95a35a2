"""``rigfit.fit``: the job ``rigfit run`` runs, from Python."""

import os
import shutil
import tempfile
import warnings

from . import _arguments as check
from . import _rigfit
from ._progress import progress_bar
from .errors import Error, GpuFallbackWarning, Interrupted
from .result import FitResult, read_result_files


def fit(campaign, *, seed=None, backend=None, precision=None, adapter=None, out=None,
        resume=False, overwrite=False, population=None, generations=None,
        target_fitness=None, method=None, threads=0, max_memory=None, progress=False):
    """Calibrates ``campaign``'s free parameters: the genetic algorithm, the
    Levenberg–Marquardt polish and the 95 % intervals, the same job (and for
    the same seed and backend, the same numbers, bit for bit) as ``rigfit
    run``. The GIL is released while it runs.

    ``backend`` (``"auto"``, ``"gpu"``, ``"cpu"``), ``precision`` (``"auto"``,
    ``"f32"``, ``"f64"``), ``adapter``, ``seed``, ``population``,
    ``generations``, ``target_fitness``, ``method`` (``"ga"``, ``"cmaes"``)
    and ``threads`` are the CLI's flags (default: the campaign's). ``out``: the folder the job writes (default: a
    temporary one, removed once the result is read into memory);
    ``resume=True`` continues the checkpoint in ``out``; ``overwrite=True``
    replaces an earlier job's files there.

    ``max_memory``: as ``rigfit run --max-memory``, bytes or a size with K,
    M, G or T (``"512M"``, ``"2G"``); default: the memory available now. A
    job whose estimated memory exceeds it is refused before any work with
    :class:`rigfit.CampaignError` and the CLI's message.

    ``progress``: ``True`` for a ``tqdm.auto`` bar (live in Jupyter), or a
    callable given a dict per generation (``stage="ga"``, ``generation``,
    ``best_cost``, ``median_cost``, ``evaluations``, ...) and per polish
    iteration (``stage="polish"``).

    Ctrl-C stops the job within the generation in flight and raises
    :class:`rigfit.Interrupted` (a KeyboardInterrupt) whose ``checkpoint`` is
    the folder to resume from. Returns a :class:`rigfit.FitResult`.

    A bad argument is refused before any work: a value with
    :class:`rigfit.CampaignError`, a type with :class:`rigfit.ArgumentTypeError`,
    the message naming the keyword.
    """
    check.campaign(campaign)
    seed = check.integer("seed", seed, maximum=check.MAX_SEED)
    backend = check.choice("backend", backend, ("auto", "gpu", "cpu"))
    precision = check.choice("precision", precision, ("auto", "f32", "f64"))
    adapter = check.adapter(adapter)
    out = check.path("out", out)
    resume = check.flag("resume", resume)
    overwrite = check.flag("overwrite", overwrite)
    population = check.integer("population", population, minimum=4)
    generations = check.integer("generations", generations, minimum=1)
    target_fitness = check.real("target_fitness", target_fitness)
    method = check.text("method", method)  # its value: the library's message
    threads = check.threads(threads)
    max_memory = check.max_memory(max_memory)
    progress = check.progress(progress)
    temporary = out is None
    if temporary:
        out = tempfile.mkdtemp(prefix="rigfit-fit-")
        os.rmdir(out)  # a new job wants a folder that is not there yet (or empty)
    out = os.fspath(out)
    callback, close = _progress(progress, campaign, generations)
    try:
        status = _rigfit.run_job(
            campaign._inner, out, resume=resume, overwrite=overwrite, backend=backend,
            precision=precision, adapter=adapter, threads=threads, population=population,
            generations=generations, seed=seed, target_fitness=target_fitness,
            method=method, max_memory=max_memory, progress=callback)
    except BaseException as e:
        if isinstance(e, Error):
            check.reword(e)  # the CLI's flags in the message as keywords
        if temporary:
            # Nobody is told of a temporary folder's checkpoint but by
            # Interrupted (returned, not raised, by run_job): an error,
            # from the job or the progress callback, leaves nothing behind.
            shutil.rmtree(out, ignore_errors=True)
        raise
    finally:
        close()
    _warn(status["notes"])
    if status["interrupted"]:
        if status["checkpoint"]:
            # The call to resume with repeats what shaped this job: a resume
            # with other settings is refused by the checkpoint.
            given = [("backend", backend), ("precision", precision), ("adapter", adapter),
                     ("population", population), ("generations", generations),
                     ("seed", seed), ("target_fitness", target_fitness), ("method", method)]
            again = "".join(f", {k}={v!r}" for k, v in given if v is not None)
            raise Interrupted(
                f"fit interrupted; checkpoint kept in {out}; continue with "
                f"rigfit.fit(campaign, out={out!r}, resume=True{again})", checkpoint=out)
        if temporary:
            shutil.rmtree(out, ignore_errors=True)
        raise Interrupted("fit interrupted before the first generation was complete: "
                          "nothing to keep")
    # The arrays in full precision from the job itself; the files as written.
    result = FitResult(read_result_files(out), arrays=status.get("arrays"))
    if temporary:
        shutil.rmtree(out, ignore_errors=True)
    return result


def _warn(notes):
    for note in notes:
        note = check.reworded(note)
        category = GpuFallbackWarning if "CPU" in note or "cpu" in note else UserWarning
        warnings.warn(f"rigfit: {note}", category, stacklevel=3)


def _progress(progress, campaign, generations):
    """The callback run_job calls, and what closes it."""
    if callable(progress):
        return progress, lambda: None
    if not progress:
        return None, lambda: None
    tqdm = progress_bar()
    total = generations or campaign._info["generations"]
    bars = [tqdm(total=total, desc=campaign.name, unit="gen")]

    def update(p):
        bar = bars[-1]
        if p["stage"] == "ga":
            bar.n = p["generation"] + 1
            bar.set_postfix(best_r2=f"{1 - p['best_cost']:.6f}", refresh=False)
        else:
            if len(bars) == 1:
                # The polish: a second bar counting its iterations.
                bar.close()
                bar = tqdm(desc=f"{campaign.name} polish", unit="it")
                bars.append(bar)
            bar.n = p["iteration"]
            bar.set_postfix(best_r2=f"{1 - p['best_cost']:.6f}", refresh=False)
        bar.refresh()

    def close():
        for bar in bars:
            bar.close()
    return update, close

