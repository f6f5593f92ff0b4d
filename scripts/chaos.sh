#!/usr/bin/env bash
# Random faults against a small farm on fake hosts: after each, the same farm command is run
# again, and the frames must equal a one-process render with exactly one stats.csv row each.
#
#   scripts/chaos.sh N [--seed S] [--keep]
#
# Each fault, picked at random (seeded: the same S gives the same faults and instants):
#   coordinator  SIGKILL to farm.sh and GNU parallel (its process group) mid-run
#   host         a host crashes mid-run: its sshd and every process under it killed
#   job          one running `envshadow render --job` killed with SIGKILL
#   disk         the output folder on a tmpfs too small for the run (only where this user
#                may mount; skipped otherwise, and said so), then grown before the re-run
# at a random instant within about one uninterrupted run. The farm: three sshd hosts on
# loopback (tests/farm-hosts.sh), 8 frames of the shapes turntable in 8 jobs, shared folder.
# Prints one line per fault, then `N faults, F frames lost, R rows lost, D differing frames`;
# exit 0 only when all three are 0. Needs GNU parallel, ssh, sshd, rsync (as scripts/farm.sh)
# and a release build (cargo build --release), or ENVSHADOW=path.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
n="" seed=$$ keep=0
while [ $# -gt 0 ]; do
    case $1 in
    --seed) seed=${2:?--seed S}; shift 2 ;;
    --keep) keep=1; shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) [ -z "$n" ] || { echo "chaos.sh: one N only" >&2; exit 2; }; n=$1; shift ;;
    esac
done
[[ "$n" =~ ^[0-9]+$ ]] && [ "$n" -gt 0 ] || { echo "usage: scripts/chaos.sh N [--seed S] [--keep]" >&2; exit 2; }
bin=${ENVSHADOW:-$root/target/release/envshadow}
[ -x "$bin" ] || { echo "chaos.sh: $bin not built (cargo build --release)" >&2; exit 2; }
for tool in parallel ssh rsync ssh-keygen pgrep; do
    command -v "$tool" >/dev/null || { echo "chaos.sh: $tool is not installed" >&2; exit 2; }
done
[ -x /usr/sbin/sshd ] || { echo "chaos.sh: /usr/sbin/sshd is not installed" >&2; exit 2; }

work=$(mktemp -d /tmp/envshadow-chaos.XXXXXX)
hosts=$work/hosts
out=$work/out
mkdir -p "$hosts"
cleanup() {
    "$root/tests/farm-hosts.sh" stop "$hosts" >/dev/null 2>&1 || true
    mountpoint -q "$out" 2>/dev/null && umount "$out" 2>/dev/null || true
    if [ "$keep" = 1 ]; then echo "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

frames=8
spec=$root/anims/shapes-turntable.toml
flags=(--frames "0..$frames" --width 160 --height 120 --lights 50 --tile 32 --threads 1)

# A seeded generator (xorshift), so a run can be repeated with --seed.
state=$(( (seed * 2654435761 + 1) & 0x7fffffff ))
[ "$state" -ne 0 ] || state=1
random() { # random N: 0..N-1 in $r
    state=$(( state ^ ((state << 13) & 0x7fffffff) ))
    state=$(( state ^ (state >> 17) ))
    state=$(( state ^ ((state << 5) & 0x7fffffff) ))
    r=$(( state % $1 ))
}

start_hosts() { "$root/tests/farm-hosts.sh" start "$hosts" 3 >/dev/null; }
restart_hosts() { "$root/tests/farm-hosts.sh" stop "$hosts" >/dev/null 2>&1 || true; start_hosts; }

# farm.sh in its own process group (so the coordinator can be killed whole); PID in $farm_pid.
start_farm() {
    setsid "$root/scripts/farm.sh" "$spec" --hosts "$hosts/hosts" --out "$out" \
        --ssh "ssh -F $hosts/ssh_config" --envshadow "$bin" --jobs "$frames" --timeout 120 \
        -- "${flags[@]}" >>"$work/farm.log" 2>&1 &
    farm_pid=$!
}

# The running `envshadow render --job` processes of this farm (under the hosts' sshd; their
# command lines name the output folder).
job_pids() {
    local p
    for p in $(pgrep -f -- "render .*--out $out" || true); do
        tr '\0' ' ' <"/proc/$p/cmdline" 2>/dev/null | grep -q -- "--job" && echo "$p"
    done
    return 0
}

# Runs the same farm command until it succeeds (at most 3 times); the exit of the last run.
rerun() {
    local code=1
    reruns=0
    for _ in 1 2 3; do
        reruns=$((reruns + 1))
        start_farm
        if wait "$farm_pid"; then code=0; break; else code=$?; fi
    done
    return $code
}

echo "chaos: seed $seed, work folder $work"
start_hosts
echo "chaos: reference render (one process)"
"$bin" render "$spec" --out "$work/reference" --no-report -q "${flags[@]}"
t0=$(date +%s%N)
start_farm
wait "$farm_pid" || { echo "chaos: an uninterrupted farm run failed; see $work/farm.log" >&2; keep=1; exit 1; }
run_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
need_kb=$(du -sk "$out" | cut -f1)
echo "chaos: an uninterrupted farm run takes ${run_ms} ms and ${need_kb} KB"

# Whether this user may mount a tmpfs (the full-disk fault).
can_mount=0
mkdir -p "$work/probe"
if mount -t tmpfs -o size=1m tmpfs "$work/probe" 2>/dev/null; then
    umount "$work/probe"
    can_mount=1
else
    echo "chaos: full disk: not available here (this user cannot mount a tmpfs); disk faults are skipped"
fi

lost_frames=0 lost_rows=0 differing=0 done_faults=0
kinds=(coordinator host job disk)
i=0
while [ "$done_faults" -lt "$n" ]; do
    i=$((i + 1))
    random 4
    kind=${kinds[$r]}
    if [ "$kind" = disk ] && [ "$can_mount" = 0 ]; then continue; fi
    done_faults=$((done_faults + 1))
    mountpoint -q "$out" 2>/dev/null && umount "$out"
    rm -rf "$out"
    mkdir -p "$out"
    random "$run_ms"
    delay_ms=$r
    what=""
    case $kind in
    disk)
        random 60
        size_kb=$(( need_kb * (20 + r) / 100 ))
        mount -t tmpfs -o "size=${size_kb}k" tmpfs "$out"
        what="output folder on a ${size_kb} KB tmpfs (the run needs ${need_kb} KB)"
        start_farm
        wait "$farm_pid" && code=0 || code=$?
        mount -o remount,size=$(( need_kb * 4 ))k "$out"
        ;;
    *)
        start_farm
        if [ "$kind" = job ]; then
            # A job's instant counts from its start: wait for the first job process (the
            # farm first checks every host's build), then pick it within the rest of the run.
            for _ in $(seq 1 $((run_ms / 20 + 50))); do
                [ -z "$(job_pids)" ] || break
                sleep 0.02
            done
            delay_ms=$((delay_ms / 2))
        fi
        sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
        case $kind in
        coordinator)
            kill -KILL -- "-$farm_pid" 2>/dev/null || true
            what="coordinator killed after ${delay_ms} ms"
            ;;
        host)
            random 3
            "$root/tests/farm-hosts.sh" crash "$hosts" $((r + 1))
            what="host fh$((r + 1)) crashed after ${delay_ms} ms"
            ;;
        job)
            pids=$(job_pids)
            if [ -n "$pids" ]; then
                set -- $pids
                random $#
                shift "$r"
                kill -KILL "$1" 2>/dev/null || true
                what="job process $1 killed after ${delay_ms} ms"
            else
                what="no job running after ${delay_ms} ms (nothing killed)"
            fi
            ;;
        esac
        # (bash's own "Killed" notice for the coordinator's group is not ours to print)
        { wait "$farm_pid"; } 2>/dev/null && code=0 || code=$?
        [ "$kind" = host ] && restart_hosts
        ;;
    esac
    rerun && again=0 || again=$?

    # Every frame as the one-process render wrote it, and exactly one row each.
    f_lost=0 f_diff=0 r_lost=0
    for f in $(seq 0 $((frames - 1))); do
        name=$(printf 'frame_%04d' "$f")
        if [ ! -f "$out/$name.exr" ] || [ ! -f "$out/$name.png" ]; then
            f_lost=$((f_lost + 1))
        elif ! cmp -s "$out/$name.exr" "$work/reference/$name.exr" || ! cmp -s "$out/$name.png" "$work/reference/$name.png"; then
            f_diff=$((f_diff + 1))
        fi
        rows=$(awk -F, -v f="$f" 'NR > 1 && $1 == f' "$out/stats.csv" 2>/dev/null | wc -l)
        [ "$rows" -eq 1 ] || r_lost=$((r_lost + 1))
    done
    lost_frames=$((lost_frames + f_lost)) lost_rows=$((lost_rows + r_lost)) differing=$((differing + f_diff))
    verdict=ok
    [ $((f_lost + r_lost + f_diff)) -eq 0 ] || verdict="FAILED: $f_lost frames lost, $r_lost rows lost, $f_diff differing (log: $work/farm.log)"
    [ "$verdict" = ok ] || keep=1
    echo "fault $done_faults/$n: $kind: $what; farm exit $code; $reruns re-run(s), last exit $again: $verdict"
done
mountpoint -q "$out" 2>/dev/null && umount "$out"
echo "$n faults, $lost_frames frames lost, $lost_rows rows lost, $differing differing frames"
[ $((lost_frames + lost_rows + differing)) -eq 0 ]
