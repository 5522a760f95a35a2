#!/usr/bin/env bash
# Wall time of every shipped campaign on the GPU path, on the CPU and with
# `--backend auto` (a fresh cache each time, so auto's trial is counted), for
# each rigfit binary given (default: target/release/rigfit), as one markdown
# table. `rigfit check`'s estimate for the chosen path is printed beside it.
#
#   cargo build --release && scripts/backend-table.sh [BINARY...]
#
# Set LP_NUM_THREADS (lavapipe's threads) as the jobs should see it;
# RIGFIT_TABLE_CAMPAIGNS="campaigns/a.json campaigns/b.json" times those alone;
# RIGFIT_TABLE_BACKENDS="gpu cpu" leaves out auto (a binary from before auto
# measured, whose auto was the GPU wherever an adapter existed);
# RIGFIT_TABLE_ROUNDS=N times every cell N times, the binaries alternating
# round by round, and prints each cell's median (on a noisy machine one run
# of a short job can be 30 % off the next).
set -euo pipefail
cd "$(dirname "$0")/.."
bins=("$@")
[ ${#bins[@]} -eq 0 ] && bins=(target/release/rigfit)
rounds="${RIGFIT_TABLE_ROUNDS:-1}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# Seconds since START (date +%s%N), to the millisecond, in shell arithmetic alone.
seconds_since() {
    local ms=$((($(date +%s%N) - $1) / 1000000))
    printf '%d.%03d' $((ms / 1000)) $((ms % 1000))
}
# The median of the numbers given ("nan" where any is).
median() {
    python3 -c "
import statistics, sys
v = [float(x) for x in sys.argv[1:]]
print('nan' if not v or any(x != x for x in v) else statistics.median(v))" "$@"
}

echo "processor: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
echo "flags: $(grep -m1 -o -w 'avx512f' /proc/cpuinfo || echo 'no avx512f'), $(grep -m1 -o -w 'avx2' /proc/cpuinfo || echo 'no avx2')"
[ "$rounds" -gt 1 ] && echo "medians of $rounds rounds, the binaries alternating"
echo
header="| campaign | binary | GPU (s) | CPU (s) | auto, first run (s) | auto chose | first ÷ faster | auto, cached (s) | cached ÷ faster | check's estimate GPU / CPU (s) |"
echo "$header"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for c in ${RIGFIT_TABLE_CAMPAIGNS:-campaigns/*.json}; do
    case "$c" in *reference_params*) continue ;; esac
    name="$(basename "$c" .json)"
    # Every run's seconds, keyed "binary index|column".
    declare -A runs=()
    declare -A chose=()
    declare -A est=()
    for _ in $(seq "$rounds"); do
        for i in "${!bins[@]}"; do
            bin="${bins[$i]}"
            declare -A secs=([gpu]=nan [cpu]=nan [auto]=nan)
            for b in ${RIGFIT_TABLE_BACKENDS:-gpu cpu auto}; do
                out="$work/out-$b"
                rm -rf "$out" "$work/cache"
                start=$(date +%s%N)
                if RIGFIT_CACHE_DIR="$work/cache" "$bin" run "$c" --backend "$b" --out "$out" --quiet \
                    >/dev/null 2>"$work/err"; then
                    secs[$b]=$(seconds_since "$start")
                    if [ "$b" = auto ]; then
                        chose[$i]+="$(python3 -c "import json,sys; r=json.load(open('$out/result.json')); print(r['backend'] + ('' if 'backend_trial' in r else ' (no trial)'))"); "
                    fi
                else
                    secs[$b]=nan
                    echo "  $name $b failed: $(tail -1 "$work/err")" >&2
                fi
            done
            # auto again with the cache the first auto left: no trial.
            acached=nan
            if [ "${secs[auto]}" != nan ]; then
                start=$(date +%s%N)
                if RIGFIT_CACHE_DIR="$work/cache" "$bin" run "$c" --backend auto --out "$work/out-again" \
                    --quiet >/dev/null 2>&1; then
                    acached=$(seconds_since "$start")
                fi
                rm -rf "$work/out-again"
            fi
            est[$i]=$(RIGFIT_CACHE_DIR="$work/cache" "$bin" --json check "$c" 2>/dev/null | python3 -c "
import json,sys
e=json.load(sys.stdin).get('search_estimate') or {}
print('%.1f / %.1f' % (e.get('gpu_seconds', float('nan')), e.get('cpu_seconds', float('nan'))))" || echo "-")
            for col in gpu cpu auto; do
                runs["$i|$col"]+="${secs[$col]} "
            done
            runs["$i|cached"]+="$acached "
            unset secs
        done
    done
    for i in "${!bins[@]}"; do
        # shellcheck disable=SC2086 # each cell's runs, one word each
        {
            g=$(median ${runs["$i|gpu"]})
            c_=$(median ${runs["$i|cpu"]})
            a=$(median ${runs["$i|auto"]})
            ac=$(median ${runs["$i|cached"]})
        }
        ratio=$(python3 -c "print('%.2f' % ($a/min($g,$c_)))" 2>/dev/null || echo "-")
        cratio=$(python3 -c "print('%.2f' % ($ac/min($g,$c_)))" 2>/dev/null || echo "-")
        # The choices of every round, each named once with its count.
        chosen=$(echo "${chose[$i]:-}" | tr ';' '\n' | sed 's/^ //' | grep -v '^$' | sort | uniq -c |
            awk '{n=$1; $1=""; sub(/^ /, ""); printf "%s%s%s", (NR > 1 ? ", " : ""), $0, (n > 1 ? " ×" n : "")}')
        printf '| %s | %s | %.1f | %.1f | %.1f | %s | %s | %.1f | %s | %s |\n' "$name" "${bins[$i]}" \
            "$g" "$c_" "$a" "$chosen" "$ratio" "$ac" "$cratio" "${est[$i]}"
    done
    unset runs chose est
done
