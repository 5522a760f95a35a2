#!/usr/bin/env bash
# The throughput table for issue-style reports, in one command on a machine with
# a GPU: builds the bench in release, prints the adapter, date, driver and commit,
# then the driver's statistics of every fitness-kernel variant (registers per
# thread, where the driver offers them), rigfit's candidate-steps/s on the
# shipped example (2 500 RK4 steps per candidate) for the default kernels
# (f32/f64, specialised as a calibration runs them and generic) at each
# population and for every other variant (layouts, no runtime checks, the
# record from storage, longer dispatches) at 65 536, and the CUDA/JAX peers of benches/peers (or $RIGFIT_PEERS)
# at the same populations where Python has numba-cuda or JAX. Output is Markdown.
#
# Environment:
#   RIGFIT_GPU_KIT          a folder made by scripts/gpu-kit.sh: run its stripped
#                           binaries and build nothing (a GPU machine without cargo or
#                           a registry); its Vulkan loader is unpacked where the
#                           machine has none
#   RIGFIT_GPU_BENCH_POPS   populations, comma-separated
#                           (default 4096,16384,65536,262144,1048576,4194304)
#   RIGFIT_GPU_BENCH_PROFILE cargo profile for the bench (default: bench, i.e. release)
#   RIGFIT_GPU_BENCH_CAMPAIGNS  shipped campaigns to time end to end with --backend
#                           gpu, cpu and auto by scripts/backend-table.sh
#                           (comma-separated names under campaigns/, "all" for
#                           every one; default: none)
#   RIGFIT_GPU_BENCH_SKIP   parts to leave out, comma-separated: tests, stats,
#                           kernels, variants, peers
#   RIGFIT_GPU_BENCH_THREADS  fitness-kernel layouts to add as rows, WORKGROUPxVOTE,
#                           comma-separated (default 32x32,128x32,256x32: a warp of
#                           32 votes together; the default rows are 64x8)
#   RIGFIT_GPU_BENCH_KNOBS  other kernel variants to add as rows (the bench's
#                           RIGFIT_BENCH_KNOBS; default unchecked,storage,chunk8192)
#   RIGFIT_GPU_BENCH_VARIANT_POPS  populations at which those rows are timed
#                           (default 65536; the default kernels are timed at
#                           every population of RIGFIT_GPU_BENCH_POPS)
#   RIGFIT_GPU_BENCH_LOGS   folder for the kit's GPU tests' logs (default: a new
#                           temporary folder)
#   RIGFIT_PEERS            folder of the peer scripts (default: benches/peers,
#                           relative to the repository root)
#   RIGFIT_ADAPTER          which adapter (index, PCI bus id or piece of the name)
#   RIGFIT_BENCH_SAMPLES    shorten the record (quick checks of this script only)
set -euo pipefail
cd "$(dirname "$0")/.."

pops="${RIGFIT_GPU_BENCH_POPS:-4096,16384,65536,262144,1048576,4194304}"
profile="${RIGFIT_GPU_BENCH_PROFILE:-bench}"
peers="${RIGFIT_PEERS:-benches/peers}"
skip=",${RIGFIT_GPU_BENCH_SKIP:-},"
steps=2500
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi
export RIGFIT_REQUIRE_GPU=1

kit="${RIGFIT_GPU_KIT:-}"
if [ -n "$kit" ]; then
    if [ ! -f "$kit/KIT" ] || [ ! -f "$kit/rigfit.xz" ] || [ ! -f "$kit/evaluator_throughput.xz" ]; then
        echo "gpu-bench: $kit is not a kit made by scripts/gpu-kit.sh" >&2
        exit 2
    fi
    # The kit's programs are xz-compressed (to travel light): unpacked into a
    # folder of this run's, by xz where the machine has it, else by Python.
    bin="$(mktemp -d)"
    mkdir -p "$bin/tests"
    for f in "$kit"/*.xz "$kit"/tests/*.xz; do
        [ -f "$f" ] || continue
        rel="${f#"$kit"/}"
        out="$bin/${rel%.xz}"
        if command -v xz >/dev/null 2>&1; then
            xz -dc "$f" > "$out"
        else
            python3 -c 'import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.argv[1]), open(sys.argv[2], "wb"))' "$f" "$out"
        fi
        chmod +x "$out"
    done
    if ! ldconfig -p 2>/dev/null | grep -q libvulkan; then
        echo "gpu-bench: no Vulkan loader here; unpacking the kit's" >&2
        for f in "$kit"/gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    # A driver mounted outside the loader's search path (a container's
    # /usr/local/nvidia): named to the loader where it finds no other.
    if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] \
        && ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
        for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; do
            if [ -f "$f" ]; then
                export VK_DRIVER_FILES="$f"
                echo "gpu-bench: the loader's folders hold no driver; using $f" >&2
            fi
        done
    fi
    rigfit_bin="$bin/rigfit"
    # The bench reads its campaign relative to the folder it was built in: give it
    # this checkout's, absolute.
    export RIGFIT_BENCH_CAMPAIGN="${RIGFIT_BENCH_CAMPAIGN:-$PWD/campaigns/aa2024_t3_synthetic.json}"
    bench_table() { "$bin/evaluator_throughput"; }
    built="$(head -1 "$kit/COMMIT")"
    commit="$built (kit)"
    if [ "$(git rev-parse HEAD 2>/dev/null || echo "$built")" != "$built" ]; then
        echo "gpu-bench: warning: the kit was built from $built, this checkout is $(git rev-parse HEAD)" >&2
    fi
else
    run_profile="$profile"
    if [ "$profile" = bench ]; then run_profile=release; fi
    echo "gpu-bench: building (profile $profile)" >&2
    cargo build --profile "$run_profile" --bin rigfit >&2
    cargo bench --profile "$profile" --bench evaluator_throughput --no-run >&2
    rigfit_bin="target/$run_profile/rigfit"
    bench_table() { cargo bench --profile "$profile" --bench evaluator_throughput; }
    commit="$(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (modified)')"
fi

echo "## rigfit GPU throughput"
echo
echo "- date: $(date -u +%Y-%m-%dT%H:%MZ)"
echo "- commit: $commit"
echo "- adapters (\`rigfit devices\`):"
"$rigfit_bin" devices | sed -n 's/^  \(\[.*\)$/  - \1/p'
if command -v nvidia-smi >/dev/null 2>&1; then
    echo "- driver: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1)"
fi
echo

# The kit's GPU tests, on this machine's adapter with RIGFIT_REQUIRE_GPU=1. They
# read the repository's files from the folder they were built in: where that
# folder is missing here, it is made a link to this checkout.
if [ -n "$kit" ] && [ -f "$kit/ROOT" ] && [[ "$skip" != *,tests,* ]]; then
    root="$(cat "$kit/ROOT")"
    if [ ! -e "$root" ]; then
        mkdir -p "$(dirname "$root")"
        ln -s "$PWD" "$root"
    fi
    # The tests that run the command line run it from the build's target folder.
    if [ ! -x "$root/target/release/rigfit" ]; then
        mkdir -p "$root/target/release"
        cp "$bin/rigfit" "$root/target/release/rigfit"
    fi
    logs="${RIGFIT_GPU_BENCH_LOGS:-$(mktemp -d)}"
    mkdir -p "$logs"
    echo "### GPU tests (RIGFIT_REQUIRE_GPU=1, release; logs in $logs)"
    echo
    echo "| test | result | seconds |"
    echo "|---|---|---|"
    for t in "$bin"/tests/*; do
        name="$(basename "$t")"
        start=$(date +%s.%N)
        if (cd "$root" && timeout 300 "$t" > "$logs/$name.log" 2>&1); then
            result="$(grep -E '^test result' "$logs/$name.log" | tail -1 | sed 's/^test result: //; s/; finished.*//')"
        else
            result="FAILED (exit $?): $(grep -E 'panicked|^test .* FAILED' "$logs/$name.log" | head -3 | tr '\n' ' ' | cut -c1-400)"
        fi
        echo "| $name | $result | $(awk "BEGIN { printf \"%.1f\", $(date +%s.%N) - $start }") |"
    done
    echo
fi

threads="${RIGFIT_GPU_BENCH_THREADS-32x32,128x32,256x32}"
knobs="${RIGFIT_GPU_BENCH_KNOBS-unchecked,storage,chunk8192}"
vpops="${RIGFIT_GPU_BENCH_VARIANT_POPS:-65536}"

# The driver's statistics of every variant's fitness kernel (registers per
# thread and the like, where the driver offers them): seconds, no timing.
if [[ "$skip" != *,stats,* ]]; then
    RIGFIT_BENCH_STATS=1 RIGFIT_BENCH_ROWS=gpu RIGFIT_BENCH_POPS=4096 \
        RIGFIT_BENCH_THREADS="$threads" RIGFIT_BENCH_KNOBS="$knobs" \
        bench_table 2>/dev/null | sed -n '/^Driver statistics/,$p'
fi

# rigfit's table: the default kernels (specialised and generic, f32 and f64)
# at every population.
if [[ "$skip" != *,kernels,* ]]; then
    RIGFIT_BENCH_TABLE_ONLY=1 RIGFIT_BENCH_ROWS=gpu RIGFIT_BENCH_POPS="$pops" \
        RIGFIT_BENCH_THREADS="" RIGFIT_BENCH_KNOBS="" \
        bench_table 2>/dev/null | sed -n '/^Shipped example/,$p'
fi

# Every variant (layouts and knobs) beside the default kernels, at the
# variants' populations.
if [[ "$skip" != *,variants,* ]] && [ -n "$threads$knobs" ]; then
    echo "### Kernel variants"
    echo
    RIGFIT_BENCH_TABLE_ONLY=1 RIGFIT_BENCH_ROWS=gpu RIGFIT_BENCH_POPS="$vpops" \
        RIGFIT_BENCH_THREADS="$threads" RIGFIT_BENCH_KNOBS="$knobs" \
        bench_table 2>/dev/null | sed -n '/^| evaluator/,$p'
fi

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
peer_files="cuda_ensemble.py cuda_ensemble_tuned.py jax_ensemble.py"
if [[ "$skip" == *,peers,* ]]; then peer_files=""; fi
for f in $peer_files; do
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
    echo "(no CUDA/JAX peer ran: left out, or Python has neither numba-cuda with a GPU nor JAX)"
fi

# The shipped campaigns end to end, on each path and with `auto`
# (scripts/backend-table.sh, with this run's binary).
campaigns="${RIGFIT_GPU_BENCH_CAMPAIGNS:-}"
if [ -n "$campaigns" ]; then
    echo
    echo "### Shipped campaigns end to end"
    echo
    if [ "$campaigns" = all ]; then
        scripts/backend-table.sh "$rigfit_bin"
    else
        list=""
        for c in ${campaigns//,/ }; do list="$list campaigns/$c.json"; done
        RIGFIT_TABLE_CAMPAIGNS="${list# }" scripts/backend-table.sh "$rigfit_bin"
    fi
fi
