#!/usr/bin/env bash
# A private three-node Slurm cluster on this machine, for tests (tests/it/slurm.rs) and for trying
# scripts/slurm.sh without a real cluster.
#
#   scripts/test-slurm-cluster.sh up DIR      start munged, slurmctld and slurmd n1, n2, n3
#   scripts/test-slurm-cluster.sh down DIR    stop every process of the cluster, by PID
#   scripts/test-slurm-cluster.sh run DIR -- COMMAND...
#                                             up, run COMMAND with the cluster's environment,
#                                             down (also when COMMAND fails or is interrupted)
#   scripts/test-slurm-cluster.sh kill-node DIR NODE
#                                             crash one node: its slurmd and every job step
#                                             process on it, SIGKILL (for failure tests)
#
# Everything lives in DIR (created if needed, must be empty for `up`): munge's own key, socket
# and PID file; one slurm.conf that the daemons and the client commands find through
# SLURM_CONF; state, spool folders, PID files and logs. Nothing under /etc is read or changed
# (slurm.conf names every path itself) and no system service is started. After `up`,
# `source DIR/env.sh` points sbatch, squeue, scontrol... at this cluster.
#
# Needs Debian's slurm-wlm and munge (apt-get install slurm-wlm munge), slurmd -N support
# (Debian's build has it), and root or one user that may run all daemons. The nodes share this
# machine's filesystem, so job output folders are "shared" as on a real cluster.
#
# `down` first cancels the cluster's jobs, then stops slurmd, slurmctld and munged by the PIDs
# they wrote; slurmstepd (one per running job step) outlives a stopped slurmd and ignores
# SIGTERM, so every process that still carries this cluster's SLURM_CONF in its environment is
# then killed by PID as well. Exit: 0 done, 1 a daemon did not start (its log is printed),
# 2 bad usage or Slurm not installed; `down` exits 1 if a process of the cluster survived.
set -euo pipefail

die() { echo "test-slurm-cluster.sh: $*" >&2; exit 2; }
log() { echo "test-slurm-cluster.sh: $*" >&2; }

NODES=(n1 n2 n3)
SBIN=${SLURM_SBIN:-/usr/sbin}

# --- helpers -------------------------------------------------------------------------------

# PID from a file, if it names a live process whose command line contains $2.
live_pid() {
    local file=$1 name=$2 pid
    [ -s "$file" ] || return 1
    pid=$(tr -dc 0-9 <"$file")
    [ -n "$pid" ] && [ -r "/proc/$pid/cmdline" ] || return 1
    tr '\0' ' ' <"/proc/$pid/cmdline" | grep -q -- "$name" || return 1
    echo "$pid"
}

# Whether process $1 carries SLURM_CONF=$2 in its environment.
has_conf() {
    { tr '\0' '\n' <"/proc/$1/environ" | grep -qxF "SLURM_CONF=$2"; } 2>/dev/null
}

# Our own PID and our ancestors' (never kill those, e.g. a test harness run under `run`).
ancestors() {
    local p=$BASHPID
    while [ -n "$p" ] && [ "$p" != 0 ]; do
        echo "$p"
        p=$(awk '/^PPid:/ { print $2 }' "/proc/$p/status" 2>/dev/null || true)
    done
}

# Every process (other than us and our ancestors) started under this cluster's slurm.conf.
cluster_pids() {
    local conf=$1 keep pid
    keep=" $(ancestors | tr '\n' ' ') "
    for d in /proc/[0-9]*; do
        pid=${d#/proc/}
        case $keep in *" $pid "*) continue ;; esac
        if has_conf "$pid" "$conf"; then echo "$pid"; fi
    done
}

# Waits up to $2 tenths of a second for PID $1 to exit; returns 1 if it is still there.
wait_gone() {
    local i
    for ((i = 0; i < $2; i++)); do
        [ -e "/proc/$1" ] || return 0
        # A zombie has exited; its parent reaps it.
        [ "$(awk '/^State:/ { print $2 }' "/proc/$1/status" 2>/dev/null)" != Z ] || return 0
        sleep 0.1
    done
    return 1
}

stop_pid() { # PID WHAT
    kill -TERM "$1" 2>/dev/null || return 0
    wait_gone "$1" 50 || { log "$2 (PID $1) ignored SIGTERM for 5 s: SIGKILL"; kill -KILL "$1" 2>/dev/null || true; wait_gone "$1" 20 || true; }
}

port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

# --- up ------------------------------------------------------------------------------------

up() {
    local dir=$1
    for b in "$SBIN/slurmctld" "$SBIN/slurmd" "$SBIN/munged"; do
        [ -x "$b" ] || die "$b not found: install Slurm and munge (Debian: apt-get install slurm-wlm munge)"
    done
    for b in sbatch squeue scontrol sinfo scancel munge; do
        command -v "$b" >/dev/null || die "$b not found: install Slurm and munge (Debian: apt-get install slurm-wlm munge)"
    done
    mkdir -p "$dir"
    dir=$(cd "$dir" && pwd)
    [ -z "$(ls -A "$dir")" ] || die "$dir is not empty: give an empty or new folder"
    chmod 700 "$dir"
    mkdir -p "$dir"/{munge,state,run,log,spool}
    # Stop whatever did start if a later step fails.
    trap 'rc=$?; if [ $rc != 0 ]; then log "bring-up failed; stopping what started"; down "$dir" || true; fi; exit $rc' EXIT

    # munge: own key, socket, PID file, log and seed; nothing under /etc or /run.
    dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
    chmod 600 "$dir/munge/munge.key"
    local sock=$dir/munge/munge.socket
    "$SBIN/munged" --force --socket="$sock" --key-file="$dir/munge/munge.key" \
        --pid-file="$dir/run/munged.pid" --log-file="$dir/log/munged.log" \
        --seed-file="$dir/munge/munged.seed" 2>>"$dir/log/munged.log" ||
        { cat "$dir/log/munged.log" >&2; log "munged did not start"; exit 1; }
    munge --socket="$sock" -n </dev/null | unmunge --socket="$sock" >/dev/null ||
        { cat "$dir/log/munged.log" >&2; log "munge does not answer on $sock"; exit 1; }

    # Four free ports: slurmctld and one per slurmd (several slurmd on one host need their own).
    local base="" try p ok
    for try in $(shuf -i 20000-60000 -n 20); do
        ok=1
        for p in $try $((try + 1)) $((try + 2)) $((try + 3)); do port_free "$p" || ok=0; done
        [ $ok = 0 ] || { base=$try; break; }
    done
    [ -n "$base" ] || { log "no four free ports found"; exit 1; }

    local host conf=$dir/slurm.conf
    host=$(uname -n)
    host=${host%%.*}
    : >"$dir/plugstack.conf"
    {
        echo "# Private test cluster made by scripts/test-slurm-cluster.sh; every path is in $dir."
        echo "ClusterName=envshadow-test"
        echo "SlurmctldHost=$host(127.0.0.1)"
        echo "SlurmctldPort=$base"
        echo "SlurmUser=$(id -un)"
        echo "SlurmdUser=$(id -un)"
        echo "AuthType=auth/munge"
        echo "CredType=cred/munge"
        # cred_expire: a requeued job waits about this long before it runs again (120 s by default).
        echo "AuthInfo=socket=$sock,cred_expire=10"
        echo "StateSaveLocation=$dir/state"
        echo "SlurmdSpoolDir=$dir/spool/%n"
        echo "SlurmctldPidFile=$dir/run/slurmctld.pid"
        echo "SlurmdPidFile=$dir/run/slurmd-%n.pid"
        echo "SlurmctldLogFile=$dir/log/slurmctld.log"
        echo "SlurmdLogFile=$dir/log/slurmd-%n.log"
        echo "PlugStackConfig=$dir/plugstack.conf"
        echo "ProctrackType=proctrack/linuxproc"
        echo "TaskPlugin=task/none"
        echo "JobAcctGatherType=jobacct_gather/none"
        echo "AccountingStorageType=accounting_storage/none"
        echo "JobCompType=jobcomp/none"
        echo "SwitchType=switch/none"
        echo "MpiDefault=none"
        echo "MailProg=/bin/true"
        echo "SelectType=select/cons_tres"
        echo "SelectTypeParameters=CR_CPU"
        # The nodes are all this machine: take their CPU count from here, not from the hardware.
        echo "SlurmdParameters=config_overrides"
        echo "ReturnToService=2"
        echo "SchedulerParameters=sched_interval=1,bf_interval=1,sched_min_interval=100000"
        echo "SlurmdTimeout=10"
        echo "SlurmctldTimeout=10"
        echo "MessageTimeout=5"
        echo "KillWait=5"
        echo "InactiveLimit=0"
        echo "MinJobAge=600"
        local i=0
        for n in "${NODES[@]}"; do
            i=$((i + 1))
            echo "NodeName=$n NodeHostname=$host NodeAddr=127.0.0.1 Port=$((base + i)) CPUs=2 State=UNKNOWN"
        done
        echo "PartitionName=render Nodes=$(IFS=,; echo "${NODES[*]}") Default=YES MaxTime=INFINITE State=UP"
    } >"$conf"
    export SLURM_CONF=$conf
    cat >"$dir/env.sh" <<EOF
# source this file to use the test cluster in $dir
export SLURM_CONF=$(printf '%q' "$conf")
EOF

    "$SBIN/slurmctld" -i >>"$dir/log/slurmctld.out" 2>&1 ||
        { tail -n 20 "$dir/log/slurmctld.log" "$dir/log/slurmctld.out" >&2 || true; log "slurmctld did not start"; exit 1; }
    for n in "${NODES[@]}"; do
        mkdir -p "$dir/spool/$n"
        "$SBIN/slurmd" -N "$n" >>"$dir/log/slurmd-$n.out" 2>&1 ||
            { tail -n 20 "$dir/log/slurmd-$n.log" "$dir/log/slurmd-$n.out" >&2 || true; log "slurmd $n did not start"; exit 1; }
    done

    # Ready when all three nodes are idle (about a second; give it 60).
    local idle=0 t
    for ((t = 0; t < 600; t++)); do
        idle=$(sinfo -h -N -t idle -o %N 2>/dev/null | sort -u | wc -l || true)
        [ "$idle" -lt ${#NODES[@]} ] || break
        sleep 0.1
    done
    if [ "$idle" -lt ${#NODES[@]} ]; then
        sinfo -N -l >&2 || true
        tail -n 20 "$dir/log/slurmctld.log" >&2 || true
        log "only $idle of ${#NODES[@]} nodes became idle in 60 s"
        exit 1
    fi
    trap - EXIT
    log "cluster up in $dir: ${#NODES[@]} nodes idle, slurmctld on port $base; source $dir/env.sh"
}

# --- down ----------------------------------------------------------------------------------

down() {
    local dir=$1 conf pid
    [ -d "$dir" ] || die "$dir: no such folder"
    dir=$(cd "$dir" && pwd)
    conf=$dir/slurm.conf
    # Our own helper processes must not carry the cluster's SLURM_CONF (they would look like
    # the cluster's leftovers): give it to the client commands only.
    unset SLURM_CONF
    local client=(timeout 10 env "SLURM_CONF=$conf")

    # Cancel every job while slurmctld still answers, so job steps end cleanly.
    if [ -f "$conf" ] && pid=$(live_pid "$dir/run/slurmctld.pid" slurmctld); then
        local jobs t
        jobs=$("${client[@]}" squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ' || true)
        if [ -n "${jobs// /}" ]; then
            # shellcheck disable=SC2086
            "${client[@]}" scancel $jobs 2>/dev/null || true
            for ((t = 0; t < 100; t++)); do
                [ -z "$("${client[@]}" squeue -h -t running,completing -o %A 2>/dev/null || true)" ] && break
                sleep 0.1
            done
        fi
    fi

    for n in "${NODES[@]}"; do
        if pid=$(live_pid "$dir/run/slurmd-$n.pid" slurmd) && has_conf "$pid" "$conf"; then stop_pid "$pid" "slurmd $n"; fi
    done
    if pid=$(live_pid "$dir/run/slurmctld.pid" slurmctld) && has_conf "$pid" "$conf"; then stop_pid "$pid" slurmctld; fi

    # What is left: slurmstepd and job processes (they inherited SLURM_CONF). slurmstepd
    # ignores SIGTERM, so SIGKILL, then check again.
    local left round
    for round in 1 2 3; do
        left=$(cluster_pids "$conf" | tr '\n' ' ')
        [ -n "${left// /}" ] || break
        [ $round != 1 ] || log "killing leftover processes of the cluster: $left"
        # shellcheck disable=SC2086
        kill -KILL $left 2>/dev/null || true
        for pid in $left; do wait_gone "$pid" 30 || true; done
    done
    left=$(cluster_pids "$conf" | tr '\n' ' ')
    local rc=0
    [ -z "${left// /}" ] || { log "processes of the cluster still alive: $left"; rc=1; }

    # munged last: the daemons above needed it to the end.
    if pid=$(live_pid "$dir/run/munged.pid" munged); then stop_pid "$pid" munged; fi
    if pid=$(live_pid "$dir/run/munged.pid" munged); then log "munged (PID $pid) is still running"; rc=1; fi
    rm -f "$dir/munge/munge.socket" "$dir/munge/munge.socket.lock"
    [ $rc != 0 ] || log "cluster in $dir stopped"
    return $rc
}

# --- kill-node ----------------------------------------------------------------------------

kill_node() {
    local dir=$1 node=$2 conf pid p
    dir=$(cd "$dir" && pwd)
    conf=$dir/slurm.conf
    pid=$(live_pid "$dir/run/slurmd-$node.pid" slurmd) || die "node $node is not running"
    # Job processes of that node carry SLURMD_NODENAME=NODE; their slurmstepd parents do not
    # (slurmstepd has slurmd's environment), so take the parents too.
    local victims=("$pid") daemons=("$pid") parent
    for d in /proc/[0-9]*; do
        p=${d#/proc/}
        if has_conf "$p" "$conf" && { tr '\0' '\n' <"/proc/$p/environ" | grep -qxF "SLURMD_NODENAME=$node"; } 2>/dev/null; then
            victims+=("$p")
            parent=$(awk '/^PPid:/ { print $2 }' "/proc/$p/status" 2>/dev/null || true)
            if [ -n "$parent" ] && { tr '\0' ' ' <"/proc/$parent/cmdline" | grep -q '^slurmstepd'; } 2>/dev/null; then
                victims+=("$parent")
                daemons+=("$parent")
            fi
        fi
    done
    # Freeze slurmd and the slurmstepds before any job process dies: a slurmstepd that saw its
    # batch script killed first would report the task FAILED to slurmctld (no requeue), which is
    # not what a crashed node does. A stopped process still dies of SIGKILL.
    kill -STOP "${daemons[@]}" 2>/dev/null || true
    kill -KILL "${daemons[@]}" 2>/dev/null || true
    kill -KILL "${victims[@]}" 2>/dev/null || true
    log "node $node crashed: killed ${victims[*]}"
}

cmd=${1:-}
case $cmd in
up)
    [ $# = 2 ] || die "usage: $0 up DIR"
    up "$2"
    ;;
down)
    [ $# = 2 ] || die "usage: $0 down DIR"
    down "$2"
    ;;
kill-node)
    [ $# = 3 ] || die "usage: $0 kill-node DIR NODE"
    kill_node "$2" "$3"
    ;;
run)
    [ $# -ge 4 ] && [ "$3" = -- ] || die "usage: $0 run DIR -- COMMAND..."
    dir=$2
    shift 3
    up "$dir"
    dir=$(cd "$dir" && pwd)
    trap 'down "$dir"' EXIT
    trap 'exit 130' INT TERM HUP
    export SLURM_CONF=$dir/slurm.conf
    set +e
    "$@"
    rc=$?
    set -e
    exit $rc
    ;;
*) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2; exit 2 ;;
esac
