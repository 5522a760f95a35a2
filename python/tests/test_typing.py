"""The package is typed: ``py.typed`` and ``.pyi`` stubs ship with it, and
``mypy --strict`` passes on the API as a user calls it (typed_use.py) and
reports a wrong use."""

import os
import pathlib
import subprocess
import sys
import textwrap

import rigfit

HERE = pathlib.Path(__file__).resolve().parent
STUBS = ["__init__", "_rigfit", "campaign", "ensemble", "errors", "fitting", "identify",
         "params", "residuals", "result", "sweep"]


def mypy(path, tmp_path):
    """``mypy --strict`` on ``path`` against the installed package (run from
    an empty folder, so the checkout's sources are not what it reads)."""
    env = {k: v for k, v in os.environ.items() if k not in ("MYPYPATH", "PYTHONPATH")}
    r = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental",
         "--cache-dir", str(tmp_path / "mypy-cache"), "--python-executable", sys.executable,
         str(path)],
        cwd=tmp_path, capture_output=True, text=True, env=env, timeout=600)
    return r.returncode, r.stdout + r.stderr


def test_the_installed_package_ships_its_stubs_and_py_typed():
    folder = pathlib.Path(rigfit.__file__).parent
    assert (folder / "py.typed").is_file()
    missing = [s for s in STUBS if not (folder / f"{s}.pyi").is_file()]
    assert not missing, f"{folder} lacks {missing}"


def test_mypy_strict_passes_on_a_users_calls(tmp_path):
    code, out = mypy(HERE / "typed_use.py", tmp_path)
    assert code == 0, out
    assert "Success" in out


def test_mypy_reports_a_wrong_use(tmp_path):
    wrong = tmp_path / "wrong_use.py"
    wrong.write_text(textwrap.dedent("""\
        import rigfit

        c = rigfit.Campaign.from_json("campaign.json")
        r = rigfit.fit(c, generations="ten")
        label: str = r.chisqr
        c.residuals([1.0, 2.0], backend="tpu")
        n: int = r.covariance
        rigfit.fit(c, populaton=10)
        """))
    code, out = mypy(wrong, tmp_path)
    assert code == 1, out
    for line, what in [(4, '"generations"'), (5, "assignment"), (6, '"backend"'),
                       (7, "assignment"), (8, '"populaton"')]:
        hits = [x for x in out.splitlines() if x.startswith(f"{wrong}:{line}:")
                or x.startswith(f"wrong_use.py:{line}:")]
        assert hits and any(what in h for h in hits), (line, what, out)
