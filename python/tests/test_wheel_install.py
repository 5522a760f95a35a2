"""The wheel scripts/test-python.sh built ($RIGFIT_WHEEL) installs into a
fresh virtual environment with nothing but pip, numpy from PyPI and the
wheel itself (no Rust, no pandas, no tqdm), and works there: the import, the
version, a simulation of a shipped campaign, and ``progress=True`` without
tqdm (a plain progress line, never a ``ModuleNotFoundError``).

Without $RIGFIT_WHEEL, a wheel that is not there, or no way to make a venv,
the test fails; it never skips."""

import json
import math
import os
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

# Run by the fresh environment's interpreter, outside the source tree.
SCRIPT = r'''
import json, pathlib, sys, importlib.util
import numpy as np
import rigfit

report = {"file": rigfit.__file__, "version": rigfit.__version__,
          "tqdm": importlib.util.find_spec("tqdm") is not None,
          "pandas": importlib.util.find_spec("pandas") is not None}
campaigns = pathlib.Path(sys.argv[1])
campaign = rigfit.Campaign.from_json(campaigns / "bearing_2dof_synthetic.json")
theta = np.asarray(campaign.bounds).mean(axis=1)[None, :]
histories = rigfit.simulate(campaign, theta)
report["simulate_shape"] = list(histories.shape)
report["simulate_finite"] = bool(np.isfinite(histories[~np.isnan(histories)]).all()
                                 and (~np.isnan(histories)).any())
try:
    result = rigfit.fit(campaign, seed=1, backend="cpu", population=16, generations=2,
                        out=sys.argv[2], progress=True)
    report["fit"] = "done"
    report["r2"] = float(min(result.r2.values()))
except rigfit.Error as e:
    report["fit"] = "rigfit error"
    report["error"] = f"{type(e).__name__}: {e}"
print("REPORT " + json.dumps(report))
'''


def run(args, **kwargs):
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=900,
                       **kwargs)
    assert r.returncode == 0, f"{' '.join(map(str, args))}: exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


def package_version():
    text = (ROOT / "python" / "pyproject.toml").read_text()
    m = re.search(r'(?m)^version\s*=\s*"([^"]+)"', text)
    assert m, "no version in python/pyproject.toml"
    return m.group(1)


def test_wheel_installs_into_a_fresh_venv_and_runs(tmp_path):
    wheel = os.environ.get("RIGFIT_WHEEL")
    assert wheel, ("RIGFIT_WHEEL is not set: run scripts/test-python.sh, or set it to the "
                   "rigfit-*.whl to install (scripts/python-wheel.sh builds a portable one)")
    wheel = pathlib.Path(wheel)
    assert wheel.is_file(), f"RIGFIT_WHEEL={wheel}: no such file"
    assert re.fullmatch(r"rigfit-[^-]+-cp39-abi3-[^-]+\.whl", wheel.name), \
        f"{wheel.name}: not an abi3 (CPython >= 3.9) wheel of rigfit"

    venv = tmp_path / "venv"
    run([sys.executable, "-m", "venv", venv])
    python = venv / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    # Only the wheel and what it declares (numpy), from PyPI (or pip's cache).
    run([python, "-m", "pip", "install", "-q", "--disable-pip-version-check", wheel], env=env)

    work = tmp_path / "work"
    work.mkdir()
    r = run([python, "-c", SCRIPT, ROOT / "campaigns", work / "fit"], cwd=work, env=env)
    assert "ModuleNotFoundError" not in r.stderr and "ImportError" not in r.stderr, r.stderr
    lines = [x for x in r.stdout.splitlines() if x.startswith("REPORT ")]
    assert len(lines) == 1, r.stdout + r.stderr
    report = json.loads(lines[0][len("REPORT "):])

    # The installed package, not the source folder.
    assert pathlib.Path(report["file"]).resolve().is_relative_to(venv.resolve()), report["file"]
    assert report["version"] == package_version()
    # A bare environment: the optional packages are absent, as a colleague's would be.
    assert not report["tqdm"] and not report["pandas"], report

    # One parameter set, every experiment, every output: (1, E, samples, outputs).
    shape = report["simulate_shape"]
    assert len(shape) == 4 and shape[0] == 1 and shape[1] == 2 and shape[2] > 0, shape
    assert report["simulate_finite"], report

    # progress=True without tqdm: a plain line on stderr, or a rigfit error
    # saying what to install; never an ImportError.
    if report["fit"] == "done":
        assert "gen" in r.stderr, f"no progress line on stderr: {r.stderr!r}"
        assert math.isfinite(report["r2"]), report
    else:
        assert "tqdm" in report["error"], report["error"]
