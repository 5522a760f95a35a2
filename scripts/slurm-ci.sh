#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, for the tests that need one
# (tests/series_slurm.rs): `start` installs Debian's slurm-wlm and munge when
# missing, starts munged, slurmctld and slurmd as plain processes (no systemd)
# on 127.0.0.1, and returns once the node is idle and a job step runs; `stop`
# cancels every job, stops exactly the processes `start` started (by PID, each
# checked against /proc/PID/exe) and any job processes left behind, and removes
# the state. `stop` is safe to run twice, or when nothing runs.
#
#   bash scripts/slurm-ci.sh start|stop|env
#
# The configuration lives in $SLURM_CI_DIR (default /tmp/rigfit-slurm-ci), not
# in /etc/slurm: Slurm's commands find it through SLURM_CONF, which
# `eval "$(bash scripts/slurm-ci.sh env)"` exports. SLURM_CI_CPUS sets the CPUs
# the node advertises (default: nproc, at least 4, so that the tests' arrays of
# light tasks can run side by side on a 2-core machine).
# Root only (SlurmUser and SlurmdUser are root). Tested notes on why each
# setting is here: the scheduler's timers (batch_sched_delay=0, sched_interval=2,
# bf_interval=1) make a small array start its tasks within a second;
# cred_expire=10 lets a requeued task start again within about 12 s instead of
# about 3 minutes; proctrack/linuxproc and task/none need no cgroups.
set -euo pipefail

DIR="${SLURM_CI_DIR:-/tmp/rigfit-slurm-ci}"
CONF="$DIR/slurm.conf"
NODE="$(hostname -s)"
PACKAGES=(slurmctld slurmd slurm-client munge)

say() { echo "slurm-ci: $*" >&2; }

# Whether PID runs (a zombie does not: PID 1 here reaps orphans late).
alive() {
    local stat
    stat="$(ps -o stat= -p "$1" 2>/dev/null || true)"
    [ -n "$stat" ] && [ "${stat:0:1}" != Z ]
}

# The PID in pid file $1 if that process runs the executable matching $2.
pid_of() {
    local pid exe
    [ -f "$1" ] || return 1
    pid="$(tr -dc 0-9 <"$1")"
    [ -n "$pid" ] || return 1
    exe="$(readlink "/proc/$pid/exe" 2>/dev/null || true)"
    # shellcheck disable=SC2053 # $2 is a pattern
    [[ "$exe" == $2 ]] && alive "$pid" && echo "$pid"
}

# Sends TERM to the PIDs given, waits up to 5 s, then KILLs what is left.
end_pids() {
    local pid left i
    [ $# -gt 0 ] || return 0
    kill -TERM "$@" 2>/dev/null || true
    for i in $(seq 50); do
        left=()
        for pid in "$@"; do alive "$pid" && left+=("$pid"); done
        [ ${#left[@]} -eq 0 ] && return 0
        sleep 0.1
    done
    kill -KILL "${left[@]}" 2>/dev/null || true
}

install_packages() {
    local missing=() p
    for p in "${PACKAGES[@]}"; do
        [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" = "install ok installed" ] \
            || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    say "installing ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        "${missing[@]}" >/dev/null 2>&1 || {
        say "apt-get install ${missing[*]} failed"
        exit 1
    }
}

start_munge() {
    # A munged that already answers (the machine's own) is used, not restarted.
    if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then return 0; fi
    if [ ! -s /etc/munge/munge.key ]; then
        runuser -u munge -- mungekey --create >/dev/null 2>&1 || mungekey --create
        chown munge:munge /etc/munge/munge.key
    fi
    chmod 0400 /etc/munge/munge.key
    install -d -o munge -g munge -m 0755 /run/munge
    install -d -o munge -g munge -m 0755 "$DIR/munge"
    runuser -u munge -- munged --pid-file="$DIR/munge/munged.pid" </dev/null >/dev/null 2>&1
    local i
    for i in $(seq 50); do
        if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then return 0; fi
        sleep 0.1
    done
    say "munged did not answer"
    exit 1
}

write_conf() {
    local cpus mem overrides=""
    cpus="${SLURM_CI_CPUS:-$(($(nproc) > 4 ? $(nproc) : 4))}"
    mem=$(($(free -m | awk '/^Mem:/ {print $2}') - 1024))
    [ "$cpus" -le "$(nproc)" ] || overrides="SlurmdParameters=config_overrides"
    cat >"$CONF" <<EOF
ClusterName=ci
SlurmctldHost=$NODE(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=cred_expire=10
CredType=cred/munge
MpiDefault=none
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_interval=2,bf_interval=1
ReturnToService=2
StateSaveLocation=$DIR/ctld
SlurmdSpoolDir=$DIR/d
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
MinJobAge=300
KillWait=5
InactiveLimit=0
$overrides
NodeName=$NODE NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
}

# Waits up to $1 tenths of a second for the command after it to succeed.
wait_for() {
    local n="$1" i
    shift
    for i in $(seq "$n"); do
        if "$@"; then return 0; fi
        sleep 0.1
    done
    return 1
}

ctld_up() {
    local out
    out="$(scontrol ping 2>/dev/null || true)"
    [[ "$out" == *"is UP"* ]]
}

node_idle() {
    local out
    out="$(sinfo -h -n "$NODE" -o %T 2>/dev/null || true)"
    [ "$out" = idle ]
}

start() {
    [ "$(id -u)" -eq 0 ] || {
        say "needs root (SlurmUser=root)"
        exit 1
    }
    if pid_of "$DIR/slurmctld.pid" '/usr/sbin/slurmctld*' >/dev/null; then
        say "already running (bash scripts/slurm-ci.sh stop first)"
        exit 1
    fi
    install_packages
    rm -rf "$DIR"
    mkdir -p "$DIR/ctld" "$DIR/d"
    export SLURM_CONF="$CONF"
    start_munge
    write_conf
    slurmctld -f "$CONF" </dev/null >/dev/null 2>&1
    wait_for 100 ctld_up || {
        say "slurmctld did not answer; see $DIR/slurmctld.log"
        exit 1
    }
    slurmd -f "$CONF" -N "$NODE" </dev/null >/dev/null 2>&1
    wait_for 100 node_idle || {
        say "the node did not become idle; see $DIR/slurmd.log"
        exit 1
    }
    local out
    out="$(timeout 30 srun -N1 -n1 -t 1 hostname 2>&1)" || {
        say "a test step failed: $out"
        exit 1
    }
    # The step leaves the node `completing` for a moment.
    wait_for 100 node_idle || {
        say "the node did not become idle after a test step; see $DIR/slurmd.log"
        exit 1
    }
}

stop() {
    export SLURM_CONF="$CONF"
    local ctld slurmd munged pid
    ctld="$(pid_of "$DIR/slurmctld.pid" '/usr/sbin/slurmctld*' || true)"
    if [ -n "$ctld" ]; then
        scancel --quiet --user=root >/dev/null 2>&1 || true
    fi
    slurmd="$(pid_of "$DIR/slurmd.pid" '/usr/sbin/slurmd*' || true)"
    munged="$(pid_of "$DIR/munge/munged.pid" '/usr/sbin/munged*' || true)"
    # The jobs' processes: every slurmstepd (only this cluster runs them here)
    # and all their descendants, from one snapshot of the process table.
    local steps=() descendants=()
    while read -r pid; do steps+=("$pid"); done < <(
        find /proc -maxdepth 2 -name exe -lname '*/slurmstepd*' 2>/dev/null | cut -d/ -f3
    )
    if [ ${#steps[@]} -gt 0 ]; then
        while read -r pid; do descendants+=("$pid"); done < <(
            ps -e -o pid=,ppid= | awk -v roots="${steps[*]}" '
                BEGIN { n = split(roots, r, " "); for (i = 1; i <= n; i++) keep[r[i]] = 1 }
                { parent[$1] = $2; order[NR] = $1 }
                END {
                    do {
                        changed = 0
                        for (i = 1; i <= NR; i++) {
                            p = order[i]
                            if (!(p in keep) && (parent[p] in keep)) { keep[p] = 1; changed = 1; print p }
                        }
                    } while (changed)
                }'
        )
    fi
    end_pids ${ctld:+"$ctld"} ${slurmd:+"$slurmd"}
    end_pids "${steps[@]}" "${descendants[@]}"
    end_pids ${munged:+"$munged"}
    [ "${SLURM_CI_KEEP:-0}" = 1 ] || rm -rf "$DIR"
}

case "${1:-}" in
start) start ;;
stop) stop ;;
env) echo "export SLURM_CONF='$CONF'" ;;
*)
    echo "usage: bash scripts/slurm-ci.sh start|stop|env" >&2
    exit 2
    ;;
esac
