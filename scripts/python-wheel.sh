#!/usr/bin/env bash
# A portable wheel of the Python package, for a colleague without Rust:
#
#     scripts/python-wheel.sh            # prints the wheel's path, size and tag
#     pip install rigfit-0.1.0-cp39-abi3-manylinux_2_17_x86_64.manylinux2014_x86_64.whl
#
# One abi3 wheel (CPython >= 3.9, any version) for this machine's architecture,
# built with the release profile and stripped. Portable across Linux
# distributions: linked by Zig (the `ziglang` package from PyPI, no system
# install) against glibc 2.17's symbols, so maturin can tag it manylinux2014
# (glibc >= 2.17: any Linux of the last ten years) after checking it needs
# nothing newer. Linked by the system's own linker, the same wheel asks for
# this machine's glibc (2.35 symbols on Debian 12: `manylinux_2_35`, refused by
# pip on older systems). Nothing is published on PyPI; this file is what you
# hand over.
#
# Builds in the workspace's target/ (the command line's); the wheel goes to
# target/wheels/ (or RIGFIT_WHEEL_OUT). The build tools (maturin, ziglang) live
# in a virtual environment of their own, target/python-wheel-tools (or
# RIGFIT_WHEEL_TOOLS), created on first use.
set -euo pipefail
cd "$(dirname "$0")/../python"

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/../target}"
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
out="${RIGFIT_WHEEL_OUT:-$CARGO_TARGET_DIR/wheels}"
tools="${RIGFIT_WHEEL_TOOLS:-$CARGO_TARGET_DIR/python-wheel-tools}"

if [ ! -x "$tools/bin/python" ]; then
    python3 -m venv "$tools"
fi
# Zig 0.13: the version this script was tried with (maturin 1.16).
"$tools/bin/python" -m pip install -q --disable-pip-version-check \
    "maturin>=1.5,<2" "ziglang>=0.13,<0.14"

# maturin finds `python -m ziglang` through the interpreter on PATH.
export PATH="$tools/bin:$PATH"
mkdir -p "$out"
out="$(cd "$out" && pwd -P)"
staging="$(mktemp -d "$out/.build.XXXXXX")"
trap 'rm -rf "$staging"' EXIT
start=$SECONDS
# No libhdf5 can travel in a portable wheel (python/Cargo.toml builds without
# rigfit's feature `hdf5`): HDF5 records are read from Python with h5py.
"$tools/bin/maturin" build --locked --release --strip --zig \
    --compatibility manylinux2014 --out "$staging"

wheels=("$staging"/rigfit-*.whl)
if [ "${#wheels[@]}" -ne 1 ] || [ ! -f "${wheels[0]}" ]; then
    echo "python-wheel.sh: expected one wheel in $staging, found: ${wheels[*]}" >&2
    exit 1
fi
name="$(basename "${wheels[0]}")"
# Only now, complete, does it replace an earlier build of the same name.
mv -f "${wheels[0]}" "$out/$name"
wheel="$out/$name"
tag="${name#rigfit-*-}"
tag="${tag%.whl}"
size="$(du -h "$wheel" | cut -f1)"
echo "python-wheel.sh: built in $((SECONDS - start)) s"
echo "wheel: $wheel"
echo "size:  $size ($(stat -c %s "$wheel") bytes)"
echo "tag:   $tag"
