#!/usr/bin/env bash
# The throughput table for issue-style reports, in one command on a machine with
# a GPU: builds the bench in release, prints the adapter, date, driver and commit,
# then rigfit's candidate-steps/s on the shipped example (2 500 RK4 steps per
# candidate) for every GPU kernel variant (f32/f64, specialised as a calibration
# runs them and generic, every variant the bench has)
# at each population, and the CUDA/JAX peers of benches/peers (or $RIGFIT_PEERS)
# at the same populations where Python has numba-cuda or JAX. Output is Markdown.
#
# Environment:
#   RIGFIT_GPU_BENCH_POPS   populations, comma-separated
#                           (default 4096,16384,65536,262144,1048576,4194304)
#   RIGFIT_GPU_BENCH_PROFILE cargo profile for the bench (default: bench, i.e. release)
#   RIGFIT_PEERS            folder of the peer scripts (default: benches/peers,
#                           relative to the repository root)
#   RIGFIT_ADAPTER          which adapter (index, PCI bus id or piece of the name)
#   RIGFIT_BENCH_SAMPLES    shorten the record (quick checks of this script only)
set -euo pipefail
cd "$(dirname "$0")/.."

pops="${RIGFIT_GPU_BENCH_POPS:-4096,16384,65536,262144,1048576,4194304}"
profile="${RIGFIT_GPU_BENCH_PROFILE:-bench}"
peers="${RIGFIT_PEERS:-benches/peers}"
steps=2500
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi
export RIGFIT_REQUIRE_GPU=1

run_profile="$profile"
if [ "$profile" = bench ]; then run_profile=release; fi
echo "gpu-bench: building (profile $profile)" >&2
cargo build --profile "$run_profile" --bin rigfit >&2
cargo bench --profile "$profile" --bench evaluator_throughput --no-run >&2

echo "## rigfit GPU throughput"
echo
echo "- date: $(date -u +%Y-%m-%dT%H:%MZ)"
echo "- commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (modified)')"
echo "- adapters (\`rigfit devices\`):"
cargo run -q --profile "$run_profile" --bin rigfit -- devices | sed -n 's/^  \(\[.*\)$/  - \1/p'
echo

# rigfit's table: GPU rows only, every variant.
RIGFIT_BENCH_TABLE_ONLY=1 RIGFIT_BENCH_ROWS=gpu RIGFIT_BENCH_POPS="$pops" \
    cargo bench --profile "$profile" --bench evaluator_throughput 2>/dev/null \
    | sed -n '/^Shipped example/,$p'

# The peers, where Python can run them.
peer_ok() {
    case "$1" in
        cuda_*) python3 -c 'from numba import cuda; assert cuda.is_available()' >/dev/null 2>&1 ;;
        jax_*) python3 -c 'import jax' >/dev/null 2>&1 ;;
        *) return 1 ;;
    esac
}
rows=""
if [ ! -d "$peers" ]; then
    echo "gpu-bench: no peer folder at $peers (set RIGFIT_PEERS)" >&2
fi
for f in cuda_ensemble.py cuda_ensemble_tuned.py jax_ensemble.py; do
    [ -f "$peers/$f" ] || continue
    if ! peer_ok "$f"; then
        echo "gpu-bench: $f skipped (Python lacks $(case $f in cuda_*) echo numba-cuda;; *) echo JAX;; esac))" >&2
        continue
    fi
    for prec in f32 f64; do
        row="| $f $prec |"
        for n in ${pops//,/ }; do
            rate=$(timeout 600 python3 "$peers/$f" "$n" "$steps" "$prec" 2>/dev/null \
                | sed -n 's/.*throughput=\([^ ]*\).*/\1/p' | tail -1)
            row="$row ${rate:-—} |"
        done
        rows="$rows$row"$'\n'
    done
done
if [ -n "$rows" ]; then
    head="| peer ($steps steps) |"
    rule="|---|"
    for n in ${pops//,/ }; do head="$head $n |"; rule="$rule---|"; done
    echo "$head"
    echo "$rule"
    printf '%s' "$rows"
    echo
    echo "(peers: candidate-steps/s of the fastest of their own timed runs; python3 FILE POPULATION STEPS PRECISION)"
else
    echo "(no CUDA/JAX peer ran: Python has neither numba-cuda with a GPU nor JAX)"
fi
