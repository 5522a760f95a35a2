#!/usr/bin/env bash
# Runs rigfit's checks and tests, installing what they need on a fresh machine.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo fmt --check
cargo test --all-targets
