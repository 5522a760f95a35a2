#!/usr/bin/env bash
# The README's test command, and exactly what CI runs (.ci/run calls it).
#
# On a fresh Debian machine it installs Mesa's lavapipe (software Vulkan) so the
# GPU tests have an adapter, and libhdf5-dev for HDF5 records, then runs rustfmt, clippy, rustdoc (its warnings,
# broken intra-doc links among them, fail) and every test, then the
# Python package's checks (scripts/test-python.sh: its wheel and pytest, and
# report.html opened in Debian's Chromium, installed when missing). The GPU
# tests run with RIGFIT_REQUIRE_GPU=1: no adapter is a failure, never a skip.
set -euo pipefail
cd "$(dirname "$0")/.."

have_lavapipe() {
    ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1 \
        && ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'
}

if ! have_lavapipe; then
    echo "test.sh: installing Mesa lavapipe (mesa-vulkan-drivers) for the GPU tests"
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
        mesa-vulkan-drivers libvulkan1
fi

# HDF5 records (and MAT v7.3) are read through the system's libhdf5 (the
# default cargo feature `hdf5`): its headers and pkg-config file to build.
if ! pkg-config --exists hdf5 2>/dev/null; then
    echo "test.sh: installing libhdf5-dev (HDF5 records) and pkg-config"
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
        libhdf5-dev pkg-config
fi

export RIGFIT_REQUIRE_GPU=1
# Mesa's window-system code complains on stderr when this is unset (headless CI).
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi
# `--backend auto` caches what it measured (src/job/backend/): in a folder of
# the run's own, not the user's cache.
RIGFIT_CACHE_DIR="$(mktemp -d)"
export RIGFIT_CACHE_DIR
# Lavapipe is the adapter the tests pin their tolerances on; use all cores.
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"

# No incremental state: a test run builds each crate once, and the incremental
# folder was 2.4 GB of the build (CI's disk once ran out).
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"

echo "test.sh: cargo fmt --check"
cargo fmt --all --check
echo "test.sh: cargo clippy"
cargo clippy --all-targets --locked -- -D warnings
echo "test.sh: cargo doc (broken intra-doc links fail)"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib --locked
# A real single-node Slurm cluster (root only) for tests/series_slurm.rs: its
# packages installed when missing, stopped by PID when this script exits, also
# on failure. Without it that test says it was not asked and passes.
if [ "$(id -u)" -eq 0 ]; then
    echo "test.sh: starting a single-node Slurm (scripts/slurm-ci.sh)"
    trap 'bash scripts/slurm-ci.sh stop' EXIT
    bash scripts/slurm-ci.sh start
    eval "$(bash scripts/slurm-ci.sh env)"
    export RIGFIT_SLURM_TEST=1
else
    echo "test.sh: not root: no Slurm cluster; tests/series_slurm.rs does not run"
fi
echo "test.sh: cargo test"
cargo test --locked --lib --bins --tests
cargo test --locked --doc
echo "test.sh: the Python package (python/: wheel and pytest)"
./scripts/test-python.sh
