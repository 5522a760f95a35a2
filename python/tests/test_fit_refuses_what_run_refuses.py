"""rigfit.fit makes the checks rigfit run makes before any work: a job whose
estimated memory exceeds the limit is refused with the CLI's message (its
flags spelled as the keyword arguments) and leaves no folder behind."""

import re

import pytest

import rigfit


def _cli_error(r):
    assert r.returncode == 2, r.stderr
    return r.stderr.split("rigfit: error: ", 1)[1].splitlines()[0]


def test_a_job_over_max_memory_is_refused_with_runs_message(bearing, cli, tmp_path):
    want = _cli_error(cli("run", bearing, "--backend", "cpu", "--max-memory", "1M",
                          "--out", tmp_path / "cli", check=False))
    with pytest.raises(rigfit.CampaignError) as e:
        rigfit.fit(rigfit.Campaign.from_json(bearing), backend="cpu", max_memory="1M",
                   out=tmp_path / "py")
    assert str(e.value) == want.replace("--max-memory", "max_memory")
    assert "search.population: expected a job that fits in 1.00 MiB" in str(e.value)
    assert not (tmp_path / "py").exists()
    # A size in bytes is the same limit.
    with pytest.raises(rigfit.CampaignError, match="fits in 1.00 MiB"):
        rigfit.fit(rigfit.Campaign.from_json(bearing), backend="cpu", max_memory=1 << 20)
    with pytest.raises(rigfit.CampaignError, match="max_memory: expected a size"):
        rigfit.fit(rigfit.Campaign.from_json(bearing), backend="cpu", max_memory="lots")


def test_a_population_over_the_memory_available_is_refused(bearing, cli, tmp_path):
    n = 10 ** 9
    want = _cli_error(cli("run", bearing, "--backend", "cpu", "--population", n,
                          "--out", tmp_path / "cli", check=False))
    with pytest.raises(rigfit.CampaignError) as e:
        rigfit.fit(rigfit.Campaign.from_json(bearing), backend="cpu", population=n,
                   out=tmp_path / "py")
    # The memory available moves between the two calls.
    available = re.compile(r"fits in [0-9.]+ [KMGT]?i?B")
    expect = want.replace(f"--population {n}", f"population={n}").replace("--max-memory",
                                                                          "max_memory")
    assert available.sub("fits in …", str(e.value)) == available.sub("fits in …", expect)
    assert str(e.value).startswith(f"population={n}: expected a job that fits in ")
    assert not (tmp_path / "py").exists()
