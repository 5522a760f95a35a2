#!/usr/bin/env bash
# Prepares, on a machine without a GPU, what scripts/gpu-bench.sh needs on a GPU
# machine that has neither a compiler nor a package registry: the stripped release
# `rigfit` and throughput bench, and the Vulkan loader's Debian packages, in the
# folder .gpukit/ (git ignores it). Then, on the GPU machine, in a checkout of the
# same commit with .gpukit/ beside it:
#
#     RIGFIT_GPU_KIT=.gpukit scripts/gpu-bench.sh > table.md
#
# builds nothing: it unpacks the loader where the machine has none, and runs the kit's
# binaries and the CUDA/JAX peers. .gpukit/COMMIT names the commit the binaries were
# built from; gpu-bench.sh prints it and warns when the checkout differs.
#
# The kit also holds the GPU tests, built in release and stripped (.gpukit/tests/),
# every program xz-compressed (the kit and checkout travel under 64 MiB),
# which gpu-bench.sh runs there with RIGFIT_REQUIRE_GPU=1; they read the repository's
# files from the folder they were built in, recorded in .gpukit/ROOT.
#
# Environment:
#   RIGFIT_GPU_KIT_NO_GL=1   leave the loader packages out (a machine that has them)
#   RIGFIT_GPU_KIT_TESTS     the GPU tests to build into the kit, comma-separated
#                            (default: the parity tests below; "" for none)
set -euo pipefail
cd "$(dirname "$0")/.."

kit=.gpukit
if [ -e "$kit" ] && [ ! -f "$kit/KIT" ]; then
    echo "gpu-kit: $kit exists and is not a kit this script made; move it away first" >&2
    exit 2
fi
rm -rf "$kit"
mkdir -p "$kit/gl"
echo "made by scripts/gpu-kit.sh" > "$kit/KIT"

echo "gpu-kit: building rigfit and the throughput bench (release)" >&2
cargo build --release --locked --bin rigfit >&2
bench=$(cargo bench --locked --bench evaluator_throughput --no-run --message-format=json 2>/dev/null |
    python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") \
            and m["target"]["name"] == "evaluator_throughput":
        print(m["executable"])')
if [ -z "$bench" ]; then
    echo "gpu-kit: cargo named no evaluator_throughput executable" >&2
    exit 1
fi
cp target/release/rigfit "$kit/rigfit"
cp "$bench" "$kit/evaluator_throughput"
strip "$kit/rigfit" "$kit/evaluator_throughput"

# The GPU tests, each an executable of its own.
tests="${RIGFIT_GPU_KIT_TESTS-gpu_cpu_parity,gpu_rig_parity,gpu_controller_parity,gpu_channels_parity,gpu_measured_column_drive,gpu_multi_experiment_parity,gpu_mixed_drive_modes,gpu_specialised_kernels,gpu_polish_residuals,gpu_split_batches,gpu_uniform_record,gpu_exp_matches_std,gpu_kernel_statistics}"
if [ -n "$tests" ]; then
    echo "gpu-kit: building the GPU tests (release): $tests" >&2
    mkdir -p "$kit/tests"
    args=()
    for t in ${tests//,/ }; do args+=(--test "$t"); done
    cargo test --release --locked --no-run --message-format=json "${args[@]}" 2>/dev/null |
        python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") \
            and "test" in m["target"]["kind"]:
        print(m["target"]["name"], m["executable"])' |
        while read -r name exe; do
            cp "$exe" "$kit/tests/$name"
            strip "$kit/tests/$name"
        done
    for t in ${tests//,/ }; do
        if [ ! -x "$kit/tests/$t" ]; then
            echo "gpu-kit: cargo built no test $t" >&2
            exit 1
        fi
    done
    pwd > "$kit/ROOT"
fi

# Compressed to travel light (about a third of the size): gpu-bench.sh unpacks them.
echo "gpu-kit: compressing the programs (xz)" >&2
for f in "$kit/rigfit" "$kit/evaluator_throughput" "$kit"/tests/*; do
    [ -f "$f" ] || continue
    xz -9 -T0 "$f"
done
git rev-parse HEAD > "$kit/COMMIT"
git diff --quiet HEAD || echo "modified" >> "$kit/COMMIT"

if [ -z "${RIGFIT_GPU_KIT_NO_GL:-}" ]; then
    echo "gpu-kit: downloading the Vulkan loader packages (amd64)" >&2
    lists=$(mktemp -d)
    mkdir -p "$lists/partial"
    o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 "-oDir::State::Lists=$lists")
    apt-get "${o[@]}" update >&2
    (cd "$kit/gl" && apt-get "${o[@]}" download libvulkan1 >&2)
    rm -rf "$lists"
fi
du -sh "$kit" >&2
echo "gpu-kit: ready in $kit (commit $(head -1 "$kit/COMMIT"))" >&2
