#!/usr/bin/env bash
# Render an animation on several machines over ssh with GNU parallel, then assemble it.
#
#   scripts/farm.sh ANIM.toml --hosts FILE --out DIR [--shared-fs | --no-shared-fs]
#                   [--jobs N] [--by tiles|frames|both] [--envshadow CMD] [--ssh CMD]
#                   [--timeout SECONDS] [--retries N] [-- RENDER FLAGS...]
#
# FILE is a GNU parallel sshloginfile: one host per line as `SLOTS/HOST` (e.g. `2/render1`),
# `#` comments allowed; put ssh options in ~/.ssh/config or --ssh "ssh -F CONFIG", not in FILE.
# RENDER FLAGS (after --) go to `envshadow plan` and to every job: --frames, --width, --lights,
# --threads (slots x threads should not exceed a host's cores), ... but not --out.
#
# --shared-fs (default): DIR, the spec and its inputs are at the same paths on every host,
#   which run CMD (default: this machine's envshadow binary, by absolute path).
# --no-shared-fs: the binary (unless --envshadow is given), the spec and its input files are
#   shipped to each host (--basefile) into ~/.envshadow-farm/RUN, with what a job to run again
#   already has here; each job's folder comes back as a tar file (--return), and when the run
#   ends, however it ends, RUN is removed from every host (its jobs still running there are
#   stopped first).
#
# Before any job starts every host must report the same `envshadow version --build` as this
# machine (another build can give other bits); a host that differs is named and the run is
# refused. Jobs are retried on other hosts (--retries, default hosts + 2) and killed after
# --timeout seconds (default 3600); ssh keepalives notice dead hosts. Run the same command
# again to continue after a failure or an interruption (SIGHUP lets running jobs finish): the
# jobs to run are judged from their files (`envshadow assemble --pending`: a job is done when
# its every tile image matches the SHA-256 it records), so a job that failed, was never run,
# or whose folder was since damaged or deleted runs again, and nothing else; each job skips
# the frames it already has intact (--resume). Logs: DIR/logs/ (joblog, one log per host).
# --help: this text on stdout (exit 0).
# Exit: 0 all frames assembled; 1 jobs failed or assembly incomplete; 2 bad usage or a host
# refused; 129 interrupted.
set -euo pipefail

die() { echo "farm.sh: $*" >&2; exit 2; }
# The header above: on stdout for --help (exit 0), on stderr when arguments are missing (exit 2).
help_text() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
usage() { help_text >&2; exit 2; }

spec="" hosts="" out="" shared=1 jobs="" by="" remote_bin="" ssh_cmd="ssh" timeout=3600 retries=""
flags=()
while [ $# -gt 0 ]; do
    case $1 in
    --hosts) hosts=${2:?--hosts FILE}; shift 2 ;;
    --out) out=${2:?--out DIR}; shift 2 ;;
    --shared-fs) shared=1; shift ;;
    --no-shared-fs) shared=0; shift ;;
    --jobs) jobs=${2:?--jobs N}; shift 2 ;;
    --by) by=${2:?--by tiles|frames|both}; shift 2 ;;
    --envshadow) remote_bin=${2:?--envshadow CMD}; shift 2 ;;
    --ssh) ssh_cmd=${2:?--ssh CMD}; shift 2 ;;
    --timeout) timeout=${2:?--timeout SECONDS}; shift 2 ;;
    --retries) retries=${2:?--retries N}; shift 2 ;;
    -h | --help) help_text; exit 0 ;;
    --) shift; flags=("$@"); break ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) [ -z "$spec" ] || die "two specs: $spec and $1"; spec=$1; shift ;;
    esac
done
[ -n "$spec" ] && [ -n "$hosts" ] && [ -n "$out" ] || usage
[ -f "$spec" ] || die "$spec: no such animation spec"
[ -f "$hosts" ] || die "$hosts: no such host file"
for f in "${flags[@]}"; do
    case $f in --out | --out=*) die "give the output folder with farm.sh --out, not as a render flag" ;; esac
done
for tool in parallel ssh; do
    command -v "$tool" >/dev/null || die "$tool is not installed (Debian: apt-get install parallel openssh-client rsync)"
done
[ $shared = 1 ] || command -v rsync >/dev/null || die "rsync is not installed (needed by --no-shared-fs)"

# This machine's envshadow: $ENVSHADOW, else the release build beside this script, else PATH.
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${ENVSHADOW:-}
[ -n "$bin" ] || { [ -x "$here/target/release/envshadow" ] && bin="$here/target/release/envshadow"; } || true
[ -n "$bin" ] || bin=$(command -v envshadow || true)
[ -n "$bin" ] || die "no envshadow binary: build it (cargo build --release) or set ENVSHADOW"
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")

# Hosts: the last word of each line, without its slots.
mapfile -t host_names < <(sed 's/#.*//' "$hosts" | awk 'NF { h = $NF; sub(/^[0-9]+\//, "", h); print h }')
[ ${#host_names[@]} -gt 0 ] || die "$hosts: no hosts"
slots=$(sed 's/#.*//' "$hosts" | awk 'NF { s = 1; if (match($NF, /^[0-9]+\//)) s = substr($NF, 1, RLENGTH - 1); t += s } END { print t + 0 }')
[ -n "$jobs" ] || jobs=$((slots * 2))
[ -n "$retries" ] || retries=$((${#host_names[@]} + 2))

mkdir -p "$out/logs/hosts"
out=$(cd "$out" && pwd)
logs=$out/logs
spec_abs=$(cd "$(dirname "$spec")" && pwd)/$(basename "$spec")

# ssh: batch mode, keepalives (a dead or hung host is noticed in ~15 s) and one shared
# connection per host (cuts per-job ssh overhead several-fold).
ctl=$(mktemp -d "${TMPDIR:-/tmp}/esfarm.XXXXXX")
ssh_full="$ssh_cmd -o BatchMode=yes -o ConnectTimeout=10 -o ServerAliveInterval=5 -o ServerAliveCountMax=3 -o ControlMaster=auto -o ControlPath=$ctl/%C -o ControlPersist=30"
# At exit, however farm.sh ends (done, a refused host, a failure, a signal): without a shared
# filesystem the hosts keep nothing of the run (clean_hosts, below) and neither does DIR.
hosts_used=0 stage=""
cleanup() {
    if [ $hosts_used = 1 ]; then clean_hosts; fi
    [ -z "$stage" ] || rm -rf "$stage"
    [ $shared = 1 ] || rm -rf "$out/.send"
    for h in "${host_names[@]}"; do $ssh_full -O exit "$h" >/dev/null 2>&1 || true; done
    rm -rf "$ctl"
}
trap cleanup EXIT
interrupt() {
    echo "farm.sh: interrupted; run the same command again to continue" >&2
    exit 129
}
trap interrupt HUP INT TERM

by_flag=()
[ -z "$by" ] || by_flag=(--by "$by")
# The plan's summary goes to farm.log; on failure its whole message (a usage error names the
# argument and a hint on lines of their own) to the terminal too. Its job lines are jobs.txt.
plan_err=$logs/plan.err
if ! "$bin" plan "$spec" --out "$out" --jobs "$jobs" "${by_flag[@]}" "${flags[@]}" >/dev/null 2>"$plan_err"; then
    cat "$plan_err" >>"$logs/farm.log"
    die "envshadow plan failed: $(cat "$plan_err")"
fi
cat "$plan_err" >>"$logs/farm.log" && rm -f "$plan_err"
njobs=$(wc -l <"$out/jobs.txt")
local_build=$("$bin" version --build)
run_id=$(printf '%s' "$local_build $out" | sha256sum | cut -c1-12)
q() { printf '%q' "$1"; }
qflags=""
for f in "${flags[@]}"; do qflags+=" $(q "$f")"; done

par=(parallel --sshloginfile "$hosts" --ssh "$ssh_full")
if [ $shared = 1 ]; then
    rbin=${remote_bin:-$bin}
    job_cmd="cd $(q "$PWD") && $(q "$rbin") render $(q "$spec_abs") --job {1} --of $jobs ${by:+--by $by} --out $(q "$out") --resume$qflags"
    check_cmd="$(q "$rbin") version --build"
else
    # Ship the spec and its inputs with their layout below their common folder, so the
    # spec's relative paths still hold; absolute paths become relative (never --cleanup an
    # original on a host that happens to share the filesystem).
    mapfile -t inputs <"$out/inputs.txt"
    root=$(dirname "${inputs[0]}")
    for f in "${inputs[@]}"; do
        while [ "${f#"$root"/}" = "$f" ]; do root=$(dirname "$root"); done
    done
    [ "$root" != / ] || root=""
    for f in "${inputs[@]}"; do par+=(--basefile "$root/./${f#"$root"/}"); done
    spec_rel=${inputs[0]#"$root"/}
    if [ -n "$remote_bin" ]; then
        rbin=$remote_bin
    else
        stage=$(mktemp -d "$out/.stage.XXXXXX")
        cp "$bin" "$stage/envshadow-farm.bin"
        par+=(--basefile "$stage/./envshadow-farm.bin")
        rbin=./envshadow-farm.bin
    fi
    workdir=.envshadow-farm/$run_id
    par+=(--workdir "$workdir")
    # The job's shell leads its process group (GNU parallel's remote wrapper makes it so) and
    # records it in .pgid/, so that the clean-up below can stop what a killed run left running
    # there before it removes the files. The tar is published under its name only complete.
    # A job that runs again starts from what its folder here holds (shipped as .send/FOLDER.tar,
    # empty for a job without a folder), so it renders only the frames missing or damaged.
    par+=(--transferfile "$out/./.send/{4}.tar")
    job_cmd="mkdir -p .pgid jobs && : >.pgid/\$\$ && { tar xf .send/{4}.tar -C jobs && rm -f .send/{4}.tar && $rbin render $(q "$spec_rel") --job {1} --of $jobs ${by:+--by $by} --out . --resume$qflags && tar cf jobs/{4}.tar.part -C jobs {4} && mv jobs/{4}.tar.part jobs/{4}.tar && rm -rf jobs/{4}; s=\$?; rm -f .pgid/\$\$; exit \$s; }"
    check_cmd="$rbin version --build"
    # Run on each host when the run ends, however it ends: stops this run's jobs still running
    # there (TERM, then KILL after 5 s) and removes everything the run put there. GNU
    # parallel's --cleanup removes only what finished jobs sent and returned.
    host_cleanup="d=$(q "$workdir"); [ -d \"\$d\" ] || exit 0; cd \"\$d\" || exit 1; groups=;"
    host_cleanup+=" for f in .pgid/*; do [ -e \"\$f\" ] && groups=\"\$groups \${f#.pgid/}\"; done;"
    host_cleanup+=" for g in \$groups; do kill -TERM -\$g 2>/dev/null; done; i=0;"
    host_cleanup+=" while [ \$i -lt 50 ]; do alive=; for g in \$groups; do kill -0 -\$g 2>/dev/null && alive=\"\$alive \$g\"; done;"
    host_cleanup+=" groups=\$alive; [ -n \"\$groups\" ] || break; i=\$((i + 1)); sleep 0.1; done;"
    host_cleanup+=" for g in \$groups; do kill -KILL -\$g 2>/dev/null; done;"
    host_cleanup+=" cd ../.. && rm -rf \"\$d\" && { rmdir .envshadow-farm 2>/dev/null; true; }"
fi
clean_hosts() {
    local h cleaners=()
    for h in "${host_names[@]}"; do
        (got=$($ssh_full "$h" "sh -c $(q "$host_cleanup")" 2>&1) ||
            echo "farm.sh: host $h: could not remove ~/$workdir: $(echo "$got" | tail -n 1)" >&2) &
        cleaners+=($!)
    done
    wait "${cleaners[@]}" || true
}

# The build check, before any job: every host runs the check command (shipping the binary
# first without a shared filesystem) and must print this machine's build.
echo "farm.sh: checking that ${#host_names[@]} hosts run $local_build"
bad=0
if [ $shared = 1 ]; then
    for h in "${host_names[@]}"; do
        if ! got=$($ssh_full "$h" "$check_cmd" 2>&1); then
            echo "farm.sh: host $h: cannot run envshadow: $(echo "$got" | tail -n 1)" >&2
            bad=1
        elif [ "$got" != "$local_build" ]; then
            echo "farm.sh: host $h runs $got, this machine $local_build: refused (another build can give other bits)" >&2
            bad=1
        fi
    done
else
    hosts_used=1 # the check ships the binary and the inputs
    check_out=$("${par[@]}" --nonall 'printf "%s\t%s\n" "$PARALLEL_SSHHOST" "$('"$check_cmd"' 2>&1 | tail -n 1)"' 2>&1) || true
    for h in "${host_names[@]}"; do
        got=$(printf '%s\n' "$check_out" | awk -F'\t' -v h="$h" '$1 == h { print $2 }' | head -n 1)
        if [ "$got" != "$local_build" ]; then
            echo "farm.sh: host $h runs ${got:-nothing we could read}, this machine $local_build: refused (another build can give other bits)" >&2
            bad=1
        fi
    done
fi
[ $bad = 0 ] || die "refusing to start: every host must run the same envshadow build"

# The jobs to run, judged from the job folders themselves (not from a log of past runs,
# which cannot know of a file damaged or deleted since): every job whose files are not all
# there and intact. Why each one runs is in farm.log.
todo=$logs/todo.txt
"$bin" assemble "$out" --pending >"$todo.tmp" 2>>"$logs/farm.log" ||
    die "envshadow assemble --pending failed: $(tail -n 1 "$logs/farm.log")"
mv "$todo.tmp" "$todo"
ntodo=$(wc -l <"$todo")
if [ "$ntodo" -lt "$njobs" ]; then
    echo "farm.sh: resuming: $ntodo of $njobs jobs to render; the others' files are complete and match their checksums (why each runs: $logs/farm.log)"
fi
if [ $shared = 0 ]; then
    rm -rf "$out/.send" && mkdir "$out/.send"
    while IFS=$'\t' read -r _ _ _ folder; do
        if [ -d "$out/jobs/$folder" ]; then
            tar cf "$out/.send/$folder.tar" -C "$out/jobs" "$folder"
        else
            tar cf "$out/.send/$folder.tar" -T /dev/null
        fi
    done <"$todo"
fi
# Every attempt of every run, appended; parallel writes no header when appending.
joblog=$logs/joblog
[ -s "$joblog" ] || printf 'Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand\n' >"$joblog"
[ $shared = 1 ] || par+=(--return "$out/./jobs/{4}.tar" --cleanup)

# Each job's output comes back tagged with its host (PARALLEL_SSHHOST, set by parallel on the
# host) and is split into one log per host; anything untagged (parallel's and ssh's own
# messages) goes to farm.log and the terminal.
job_wrapped="o=\$( ($job_cmd) 2>&1); s=\$?; [ -z \"\$o\" ] || printf '%s\n' \"\$o\" | sed \"s|^|\$PARALLEL_SSHHOST	|\"; exit \$s"
# mawk (Debian's awk) reads a pipe in blocks: without -W interactive, the logs below would
# get a job's lines only when a block filled or the run ended.
awk_live=()
if awk -W version 2>/dev/null | grep -q mawk; then awk_live=(-W interactive); fi
interrupted=0 rc=0
if [ "$ntodo" -gt 0 ]; then
    echo "farm.sh: $ntodo jobs on ${#host_names[@]} hosts ($slots slots); per-host logs in $logs/hosts/, job log $logs/joblog"
    "${par[@]}" --joblog "+$joblog" --retries "$retries" --timeout "$timeout" \
        --colsep '\t' -a "$todo" "$job_wrapped" \
        > >(awk "${awk_live[@]}" -F'\t' -v dir="$logs/hosts" -v farm="$logs/farm.log" -v hosts="${host_names[*]}" '
            BEGIN { n = split(hosts, h, " "); for (i = 1; i <= n; i++) known[h[i]] = 1 }
            ($1 in known) { f = dir "/" $1 ".log"; sub(/^[^\t]*\t/, ""); print >> f; fflush(f); next }
            { print >> farm; fflush(farm); print > "/dev/stderr" }') 2>&1 &
    ppid=$!
    trap 'interrupted=1; kill -HUP $ppid 2>/dev/null || true' HUP
    trap 'interrupted=1; kill -TERM $ppid 2>/dev/null || true' INT TERM
    set +e
    while :; do
        wait $ppid
        rc=$?
        kill -0 $ppid 2>/dev/null || break
    done
    set -e
    trap interrupt HUP INT TERM
else
    echo "farm.sh: all $njobs jobs are already rendered (their files match their checksums)"
fi

# Without a shared filesystem, unpack the returned job folders (into a temporary folder
# first, so a half-unpacked folder is never taken for a job).
if [ $shared = 0 ]; then
    for t in "$out"/jobs/*.tar; do
        [ -e "$t" ] || continue
        name=$(basename "$t" .tar)
        tmp="$out/jobs/.unpack.$name"
        rm -rf "$tmp" && mkdir -p "$tmp"
        if tar xf "$t" -C "$tmp" && [ -d "$tmp/$name" ]; then
            rm -rf "$out/jobs/$name" && mv "$tmp/$name" "$out/jobs/$name"
            rm -f "$t"
        else
            echo "farm.sh: could not unpack $t" >&2
        fi
        rm -rf "$tmp"
    done
    clean_hosts
    hosts_used=0
fi

if [ $interrupted = 1 ]; then
    echo "farm.sh: interrupted; jobs that finished are kept: run the same command again to render the rest" >&2
    exit 129
fi
[ "$rc" = 0 ] || echo "farm.sh: $rc jobs failed after $retries attempts; see $logs/joblog and $logs/hosts/" >&2
set +e
"$bin" assemble "$out" 2>&1 | tee -a "$logs/farm.log"
arc=${PIPESTATUS[0]}
set -e
echo "farm.sh: per-host logs in $logs/hosts/ (one file per host), job log $logs/joblog"
[ "$rc" = 0 ] && [ "$arc" = 0 ] || exit 1
