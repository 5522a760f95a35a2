"""Every bad argument to the package's public functions is refused before
any work with a rigfit exception naming the keyword (never a CLI flag):
rigfit.CampaignError (a ValueError) for a bad value, rigfit.ArgumentTypeError
(a TypeError) for a bad type; never an OverflowError, an AttributeError or a
bare TypeError from the binding."""

import pathlib

import numpy as np
import pytest

import rigfit
from rigfit import _arguments

from conftest import CAMPAIGNS

AA2024 = CAMPAIGNS / "aa2024_t3_synthetic.json"
VALUE, TYPE = rigfit.CampaignError, rigfit.ArgumentTypeError


@pytest.fixture(scope="module")
def campaign():
    return rigfit.Campaign.from_json(AA2024)


def test_the_exceptions_are_rigfits_and_pythons():
    assert issubclass(VALUE, rigfit.Error) and issubclass(VALUE, ValueError)
    assert issubclass(TYPE, rigfit.Error) and issubclass(TYPE, TypeError)
    assert "ArgumentTypeError" in rigfit.__all__


@pytest.mark.parametrize("kwargs, error, name", [
    (dict(generations=-1), VALUE, "generations"),
    (dict(generations=2**70), VALUE, "generations"),
    (dict(generations=0), VALUE, "generations"),
    (dict(generations=2.5), TYPE, "generations"),
    (dict(generations=np.float64(3.0)), TYPE, "generations"),
    (dict(generations="3"), TYPE, "generations"),
    (dict(generations=True), TYPE, "generations"),
    (dict(population=-5), VALUE, "population"),
    (dict(population=2**64), VALUE, "population"),
    (dict(population=np.bool_(True)), TYPE, "population"),
    (dict(seed=-1), VALUE, "seed"),
    (dict(seed=2**64), VALUE, "seed"),
    (dict(seed=1.0), TYPE, "seed"),
    (dict(threads=-1), VALUE, "threads"),
    (dict(threads=1025), VALUE, "threads"),
    (dict(threads=10**30), VALUE, "threads"),
    (dict(threads=False), TYPE, "threads"),
    (dict(target_fitness="high"), TYPE, "target_fitness"),
    (dict(target_fitness=float("nan")), VALUE, "target_fitness"),
    (dict(target_fitness=True), TYPE, "target_fitness"),
    (dict(max_memory="lots"), VALUE, "max_memory"),
    (dict(max_memory="12X"), VALUE, "max_memory"),
    (dict(max_memory="-1G"), VALUE, "max_memory"),
    (dict(max_memory=0), VALUE, "max_memory"),
    (dict(max_memory=True), TYPE, "max_memory"),
    (dict(max_memory=[1]), TYPE, "max_memory"),
    (dict(backend="tpu"), VALUE, "backend"),
    (dict(backend=1), TYPE, "backend"),
    (dict(precision="f16"), VALUE, "precision"),
    (dict(method="pso"), VALUE, "method"),
    (dict(method=1), TYPE, "method"),
    (dict(method=None, adapter=1.5), TYPE, "adapter"),
    (dict(out=3), TYPE, "out"),
    (dict(resume="yes"), TYPE, "resume"),
    (dict(overwrite=1), TYPE, "overwrite"),
    (dict(progress="bar"), TYPE, "progress"),
])
def test_fit_refuses_a_bad_keyword(campaign, kwargs, error, name):
    with pytest.raises(error) as e:
        rigfit.fit(campaign, **kwargs)
    assert name in str(e.value)
    assert "--" not in str(e.value)


@pytest.mark.parametrize("given, hint", [
    ("camp.json", "rigfit.Campaign.from_json('camp.json')"),
    (pathlib.Path("camp.json"), "rigfit.Campaign.from_json('camp.json')"),
    ({"rig": "aa2024_t3"}, "rigfit.Campaign.from_dict"),
    (None, "rigfit.Campaign.from_json(path)"),
    (3, "rigfit.Campaign.from_json(path)"),
])
def test_the_campaign_must_be_a_campaign(given, hint):
    for call in (lambda: rigfit.fit(given), lambda: rigfit.simulate(given, [[1.0]]),
                 lambda: rigfit.Objective(given)):
        with pytest.raises(TYPE) as e:
            call()
        assert str(e.value).startswith("campaign: expected a rigfit.Campaign")
        assert hint in str(e.value)


def test_numpy_scalars_are_accepted(campaign, tmp_path):
    # Checked and passed on: the job is then refused for its memory, before
    # any work, which shows the numpy values got through.
    with pytest.raises(VALUE, match="max_memory"):
        rigfit.fit(campaign, generations=np.int64(3), population=np.int32(8), seed=np.uint64(7),
                   threads=np.int16(1), target_fitness=np.float32(0.5),
                   max_memory=np.float64(1.0), backend="cpu", out=tmp_path / "out")
    assert _arguments.integer("generations", np.int64(3)) == 3
    assert _arguments.real("mass", np.float32(0.5)) == 0.5
    assert _arguments.flag("fixed", np.bool_(True)) is True
    assert rigfit.fit_specimen.__name__  # identify keeps numpy ints too (below)


@pytest.mark.parametrize("kwargs, error, name", [
    (dict(threads=-1), VALUE, "threads"),
    (dict(threads=5000), VALUE, "threads"),
    (dict(threads=2**64), VALUE, "threads"),
    (dict(threads="4"), TYPE, "threads"),
    (dict(backend="tpu"), VALUE, "backend"),
    (dict(precision=64), TYPE, "precision"),
    (dict(adapter=-1), VALUE, "adapter"),
])
def test_the_ensemble_refuses_a_bad_keyword(campaign, kwargs, error, name):
    theta = np.asarray(campaign.bounds)[:, 0][None, :]
    for call in (lambda: rigfit.simulate(campaign, theta, **kwargs),
                 lambda: campaign.objective(**kwargs)):
        with pytest.raises(error) as e:
            call()
        assert name in str(e.value)


def test_the_objectives_vectorized_is_a_flag(campaign):
    with pytest.raises(TYPE, match="vectorized"):
        campaign.objective("yes")


T = np.arange(64) * 1e-3
X = np.sin(2 * np.pi * 50 * T)


@pytest.mark.parametrize("call, error, name", [
    (lambda: rigfit.fit_specimen(T, X, degree=-1), VALUE, "degree"),
    (lambda: rigfit.fit_specimen(T, X, degree=2**70), VALUE, "degree"),
    (lambda: rigfit.fit_specimen(T, X, degree=0), VALUE, "degree"),
    (lambda: rigfit.fit_specimen(T, X, degree=6), VALUE, "degree"),
    (lambda: rigfit.fit_specimen(T, X, degree=2.0), TYPE, "degree"),
    (lambda: rigfit.fit_specimen(T, X, degree=True), TYPE, "degree"),
    (lambda: rigfit.frf(T, X, X, modes=-1), VALUE, "modes"),
    (lambda: rigfit.frf(T, X, X, modes=2**64), VALUE, "modes"),
    (lambda: rigfit.frf(T, X, X, segment=-8), VALUE, "segment"),
    (lambda: rigfit.frf(T, X, X, f_min="1"), TYPE, "f_min"),
    (lambda: rigfit.frf(T, X, X, names="mkc"), TYPE, "names"),
    (lambda: rigfit.frf(T, X, X, fixed="no"), TYPE, "fixed"),
    (lambda: rigfit.frf(T, X, X, response=3), TYPE, "response"),
    (lambda: rigfit.ringdown(T, X, m1="1"), TYPE, "m1"),
    (lambda: rigfit.ringdown(T, X, k1=-1.0), VALUE, "k1"),
    (lambda: rigfit.rfs(T, X, X, mass=True), TYPE, "mass"),
    (lambda: rigfit.rfs(T, X, X, mass=1.0, filter_order=-1), VALUE, "filter_order"),
    (lambda: rigfit.idim(X, X, sample_rate=1e3, decimation=-1), VALUE, "decimation"),
    (lambda: rigfit.idim(X, X, sample_rate=1e3, filter_order=2**70), VALUE, "filter_order"),
    (lambda: rigfit.idim(X, X, sample_rate=float("inf")), VALUE, "sample_rate"),
    (lambda: rigfit.nimiso(T, X, X, f_min=1, f_max=2, segment=-1), VALUE, "segment"),
    (lambda: rigfit.nimiso(T, X, X, f_min=None, f_max=2), TYPE, "f_min"),
    (lambda: rigfit.arx(T, X, X, mass="1", f_min=1, f_max=2), TYPE, "mass"),
    (lambda: rigfit.arx(T, X, X, mass=1, f_min=1, f_max=2, segment=-1), VALUE, "segment"),
    (lambda: rigfit.impedance(T, (X, X, X), (X, X, X), f_min=1, f_max=[2]), TYPE, "f_max"),
    (lambda: rigfit.sensitivity(T, (X, X, X), (X, X, X), k1=1, f_min=1, f_max=2, segment=-1),
     VALUE, "segment"),
])
def test_identification_refuses_a_bad_keyword(call, error, name):
    with pytest.raises(error) as e:
        call()
    assert name in str(e.value)


def test_identification_takes_numpy_integers():
    # A numpy degree gets through to the fit (which then judges the data).
    with pytest.raises(rigfit.DataError):
        rigfit.fit_specimen(T, X, degree=np.int64(3))


@pytest.mark.parametrize("message, want", [
    ("output folder `o` already holds x; pass --overwrite to replace it or --resume to "
     "continue a checkpoint",
     "output folder `o` already holds x; pass overwrite=True to replace it or resume=True to "
     "continue a checkpoint"),
    ("run it again without --resume to start it", "run it again without resume=True to start it"),
    ("too short (--backend gpu runs it there)", 'too short (backend="gpu" runs it there)'),
    ("chosen by --adapter 1", "chosen by adapter=1"),
    ("raise --max-memory or lower --population 100", "raise max_memory or lower population=100"),
])
def test_the_clis_flags_are_reworded_as_keywords(message, want):
    assert _arguments.reworded(message) == want


def test_a_refusal_from_the_library_names_the_keyword(campaign, tmp_path):
    with pytest.raises(VALUE) as e:
        rigfit.fit(campaign, out=tmp_path, resume=True)
    assert "resume=True" in str(e.value) and "--" not in str(e.value)
