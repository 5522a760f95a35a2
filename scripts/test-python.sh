#!/usr/bin/env bash
# The Python package's checks (python/): rustfmt and clippy on its crate, the
# wheel built and installed into a fresh virtual environment with what the
# tests need (maturin, pytest, numpy, pandas, SciPy, tqdm, nbclient, ...), then
# pytest. scripts/test.sh runs it after the Rust tests; every failure fails it.
#
# The crate (rigfit-python) is a member of the root workspace: one Cargo.lock,
# one target folder, the root's profiles. It is not a default member, so the
# root's `cargo test` and `cargo clippy` never build it; this script checks it
# with `-p rigfit-python`. The wheel is built with the dev profile
# (dependencies and, by the root's [profile.dev.package.rigfit], the library
# at opt-level 2, as the root's tests build them; no LTO). None of what `cargo
# test` compiled is reused (measured 2026-11-29: the test profile has no debug
# info, the dev profile line tables), so its ~194 units are built once more.
# (The `test` profile would build the module with the test harness, without
# its PyInit symbol.)
#
# RIGFIT_WHEEL is set to the wheel it built: tests/test_wheel_install.py
# installs it into a fresh virtual environment of its own (numpy from PyPI).
set -euo pipefail
cd "$(dirname "$0")/../python"

if ! python3 -c 'import ensurepip, venv' >/dev/null 2>&1; then
    echo "test-python.sh: installing python3 and python3-venv"
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
        python3 python3-venv python3-pip
fi

# The report's browser tests (tests/test_report_in_browser.py) open report.html
# in Debian's Chromium, driven by Playwright (pip, below; it uses this Chromium,
# never a browser of its own download). Missing, it is installed: the tests
# fail, never skip, without it.
if [ ! -x /usr/bin/chromium ]; then
    echo "test-python.sh: installing Chromium (Debian's chromium) for the report's browser tests"
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
        chromium fonts-dejavu-core
fi

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/../target}"
profile="${RIGFIT_WHEEL_PROFILE:-dev}"

step() { echo "test-python.sh: [${SECONDS} s] $*"; }
step "cargo fmt --check (rigfit-python)"
cargo fmt -p rigfit-python --check
step "cargo clippy (rigfit-python)"
cargo clippy -p rigfit-python --all-targets --locked -- -D warnings

venv="${RIGFIT_PYTHON_VENV:-$PWD/.venv}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
step "pip install (maturin, pytest, numpy, pandas, scipy, lmfit, tqdm, nbclient, mypy, playwright, ...)"
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
    "maturin>=1.5,<2" pytest numpy pandas scipy lmfit tqdm nbclient nbformat ipykernel matplotlib \
    mypy "playwright>=1.50,<2"

step "maturin build (profile $profile)"
rm -rf dist
"$venv/bin/maturin" build --locked --profile "$profile" --out dist
wheels=(dist/rigfit-*.whl)
if [ "${#wheels[@]}" -ne 1 ] || [ ! -f "${wheels[0]}" ]; then
    echo "test-python.sh: expected one wheel in python/dist, found: ${wheels[*]}" >&2
    exit 1
fi
export RIGFIT_WHEEL="$PWD/${wheels[0]}"
"$venv/bin/python" -m pip install -q --disable-pip-version-check --force-reinstall --no-deps "$RIGFIT_WHEEL"

# The tests hold the package to the CLI that `cargo test` built.
export RIGFIT_BIN="${RIGFIT_BIN:-$CARGO_TARGET_DIR/debug/rigfit}"
step "pytest"
# Run from tests/ so that `import rigfit` is the installed wheel, not the source folder.
(cd tests && "$venv/bin/python" -m pytest -q -p no:cacheprovider .)
step "done"
