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
# measured, whose auto was the GPU wherever an adapter existed).
set -euo pipefail
cd "$(dirname "$0")/.."
bins=("$@")
[ ${#bins[@]} -eq 0 ] && bins=(target/release/rigfit)
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# Seconds since START (date +%s%N), to the millisecond, in shell arithmetic alone.
seconds_since() {
    local ms=$((($(date +%s%N) - $1) / 1000000))
    printf '%d.%03d' $((ms / 1000)) $((ms % 1000))
}

echo "processor: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
echo "flags: $(grep -m1 -o -w 'avx512f' /proc/cpuinfo || echo 'no avx512f'), $(grep -m1 -o -w 'avx2' /proc/cpuinfo || echo 'no avx2')"
echo
header="| campaign | binary | GPU (s) | CPU (s) | auto, first run (s) | auto chose | first ÷ faster | auto, cached (s) | cached ÷ faster | check's estimate GPU / CPU (s) |"
echo "$header"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for c in ${RIGFIT_TABLE_CAMPAIGNS:-campaigns/*.json}; do
    case "$c" in *reference_params*) continue ;; esac
    name="$(basename "$c" .json)"
    for bin in "${bins[@]}"; do
        declare -A secs=([gpu]=nan [cpu]=nan [auto]=nan)
        chose=""
        for b in ${RIGFIT_TABLE_BACKENDS:-gpu cpu auto}; do
            out="$work/out-$b"
            rm -rf "$out" "$work/cache"
            start=$(date +%s%N)
            if RIGFIT_CACHE_DIR="$work/cache" "$bin" run "$c" --backend "$b" --out "$out" --quiet \
                >/dev/null 2>"$work/err"; then
                secs[$b]=$(seconds_since "$start")
                if [ "$b" = auto ]; then
                    chose=$(python3 -c "import json,sys; r=json.load(open('$out/result.json')); print(r['backend'] + ('' if 'backend_trial' in r else ' (no trial)'))")
                fi
            else
                secs[$b]=nan
                echo "  $name $b failed: $(tail -1 "$work/err")" >&2
            fi
        done
        # auto again with the cache the first auto left: no trial.
        acached=nan
        if [ -n "${secs[auto]:-}" ] && [ "${secs[auto]}" != nan ]; then
            start=$(date +%s%N)
            if RIGFIT_CACHE_DIR="$work/cache" "$bin" run "$c" --backend auto --out "$work/out-again" \
                --quiet >/dev/null 2>&1; then
                acached=$(seconds_since "$start")
            fi
            rm -rf "$work/out-again"
        fi
        est=$(RIGFIT_CACHE_DIR="$work/cache" "$bin" --json check "$c" 2>/dev/null | python3 -c "
import json,sys
e=json.load(sys.stdin).get('search_estimate') or {}
print('%.1f / %.1f' % (e.get('gpu_seconds', float('nan')), e.get('cpu_seconds', float('nan'))))" || echo "-")
        ratio=$(python3 -c "
g,c,a=${secs[gpu]},${secs[cpu]},${secs[auto]}
print('%.2f' % (a/min(g,c)))" 2>/dev/null || echo "-")
        cratio=$(python3 -c "
g,c,a=${secs[gpu]},${secs[cpu]},$acached
print('%.2f' % (a/min(g,c)))" 2>/dev/null || echo "-")
        printf '| %s | %s | %.1f | %.1f | %.1f | %s | %s | %.1f | %s | %s |\n' "$name" "$bin" \
            "${secs[gpu]}" "${secs[cpu]}" "${secs[auto]}" "$chose" "$ratio" "$acached" "$cratio" "$est"
        unset secs
    done
done
