#!/usr/bin/env bash
# Render an animation on a Slurm cluster as one job array, then assemble it.
#
#   scripts/slurm.sh ANIM.toml --out DIR [--jobs N] [--by tiles|frames|both]
#                    [--partition P] [--time T] [--cpus-per-task C] [--max-running M]
#                    [--retries R] [--envshadow PATH] [--sbatch-arg ARG]... [--wait] [--dry-run]
#                    [-- RENDER FLAGS...]
#
# Plans the render here (`envshadow plan`: DIR/plan.json, DIR/jobs.txt), then submits
#   sbatch --array=0-(N-1) --requeue ...   one task per plan job, each running
#       envshadow render ANIM.toml --job $SLURM_ARRAY_TASK_ID --of N --resume --out DIR
#           --threads $SLURM_CPUS_PER_TASK
#   sbatch --dependency=afterok:<array> --kill-on-invalid-dep=yes ...   envshadow assemble DIR
# DIR, the spec, its input files and the envshadow binary must be at the same paths on every
# node (a shared filesystem, as usual on a cluster). N defaults to 16 (the plan may have fewer
# jobs when the work does not split that far). RENDER FLAGS (after --) go to the plan and to
# every task: --frames, --width, --lights, --method, ... but not --out or --threads.
#
# --partition, --time (e.g. 2:00:00, per task and for the assembly), --cpus-per-task (each
#   task renders with that many threads; default: the CPUs Slurm gives the task) and
#   --max-running (at most M tasks at once: --array=...%M) are passed to sbatch; anything else
#   with --sbatch-arg (repeatable, e.g. --sbatch-arg=--account=render --sbatch-arg=--mem=4G).
# --envshadow PATH: the binary the nodes run (default: this machine's, as found below).
#   Every task first checks that the node's binary has this machine's build
#   (`envshadow version --build`): another build could give other bits.
# --retries R: a task that fails (other than on bad input, exit 2) requeues itself up to R
#   times (default 2). Tasks whose node fails are requeued by Slurm (--requeue).
# --wait: wait for the assembly and exit with its result (0 = every frame assembled).
# --dry-run: print the plan's job count and the sbatch commands with the task scripts; submit
#   nothing and write nothing into DIR.
#
# Run the same command again after a failure or a cancellation: the jobs to submit are judged
# from their files (`envshadow assemble --pending`: a job is done when its every tile image
# matches the SHA-256 it records), so a job whose folder was damaged or deleted is submitted
# again and a complete one is not; each task skips the frames it already has intact (--resume).
# Logs: DIR/logs/render-<array>_<task>.log per task, DIR/logs/assemble-<id>.log,
# DIR/logs/submissions.log (every submission with its Slurm job ids) and DIR/logs/pending.log
# (before each submission, why each job submitted has to be rendered).
# --help: this text on stdout (exit 0).
# Exit: 0 submitted (with --wait: assembled); 1 submission or (with --wait) rendering or
# assembly failed; 2 bad usage or a missing tool.
set -euo pipefail

die() { echo "slurm.sh: $*" >&2; exit 2; }
say() { echo "slurm.sh: $*" >&2; }
# The header above: on stdout for --help (exit 0), on stderr when arguments are missing (exit 2).
help_text() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
usage() { help_text >&2; exit 2; }

spec="" out="" jobs=16 by="" partition="" time_limit="" cpus="" max_running="" retries=2
node_bin="" wait=0 dry=0
sbatch_extra=() flags=()
while [ $# -gt 0 ]; do
    case $1 in
    --out) out=${2:?--out DIR}; shift 2 ;;
    --jobs) jobs=${2:?--jobs N}; shift 2 ;;
    --by) by=${2:?--by tiles|frames|both}; shift 2 ;;
    --partition) partition=${2:?--partition P}; shift 2 ;;
    --time) time_limit=${2:?--time T}; shift 2 ;;
    --cpus-per-task) cpus=${2:?--cpus-per-task C}; shift 2 ;;
    --max-running) max_running=${2:?--max-running M}; shift 2 ;;
    --retries) retries=${2:?--retries R}; shift 2 ;;
    --envshadow) node_bin=${2:?--envshadow PATH}; shift 2 ;;
    --sbatch-arg) sbatch_extra+=("${2:?--sbatch-arg ARG}"); shift 2 ;;
    --sbatch-arg=*) sbatch_extra+=("${1#--sbatch-arg=}"); shift ;;
    --wait) wait=1; shift ;;
    --dry-run) dry=1; shift ;;
    -h | --help) help_text; exit 0 ;;
    --) shift; flags=("$@"); break ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) [ -z "$spec" ] || die "two specs: $spec and $1"; spec=$1; shift ;;
    esac
done
[ -n "$spec" ] && [ -n "$out" ] || usage
[ -f "$spec" ] || die "$spec: no such animation spec"
[[ $jobs =~ ^[1-9][0-9]*$ ]] || die "--jobs $jobs: give a positive whole number"
[[ $retries =~ ^[0-9]+$ ]] || die "--retries $retries: give a whole number"
[ -z "$cpus" ] || [[ $cpus =~ ^[1-9][0-9]*$ ]] || die "--cpus-per-task $cpus: give a positive whole number"
[ -z "$max_running" ] || [[ $max_running =~ ^[1-9][0-9]*$ ]] || die "--max-running $max_running: give a positive whole number"
case $by in "" | tiles | frames | both) ;; *) die "--by $by: give tiles, frames or both" ;; esac
for f in "${flags[@]}"; do
    case $f in
    --out | --out=*) die "give the output folder with slurm.sh --out, not as a render flag" ;;
    --threads | --threads=* | -j) die "the thread count comes from --cpus-per-task, not a render flag" ;;
    --job | --job=* | --of | --of=* | --resume | --tiles | --tiles=* | --region | --region=*)
        die "$f is set per task by slurm.sh; give only the animation's flags after --" ;;
    esac
done
if [ $dry = 0 ]; then
    for tool in sbatch squeue scontrol; do
        command -v "$tool" >/dev/null ||
            die "$tool not found: run this on a Slurm submit host (a login node; perhaps 'module load slurm'), or use --dry-run to see the commands"
    done
fi

# This machine's envshadow: $ENVSHADOW, else the release build beside this script, else PATH.
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${ENVSHADOW:-}
[ -n "$bin" ] || { [ -x "$here/target/release/envshadow" ] && bin="$here/target/release/envshadow"; } || true
[ -n "$bin" ] || bin=$(command -v envshadow || true)
[ -n "$bin" ] && [ -x "$bin" ] || die "no envshadow binary: build it (cargo build --release), set ENVSHADOW or put it on PATH"
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
node_bin=${node_bin:-$bin}
case $node_bin in /*) ;; *) die "--envshadow $node_bin: give an absolute path (the nodes run it from their own folders)" ;; esac
local_build=$("$bin" version --build) || die "$bin version --build failed"

spec_abs=$(cd "$(dirname "$spec")" && pwd)/$(basename "$spec")
q() { printf '%q' "$1"; }
by_flag=()
[ -z "$by" ] || by_flag=(--by "$by")

# Plan here: it checks the spec and flags before anything is submitted, and gives the job count
# (for a dry run into a scratch folder, so DIR is untouched).
if [ $dry = 1 ]; then
    plan_dir=$(mktemp -d "${TMPDIR:-/tmp}/esslurm-plan.XXXXXX")
    trap 'rm -rf "$plan_dir"' EXIT
    case $out in /*) out_abs=$out ;; *) out_abs=$PWD/$out ;; esac
else
    mkdir -p "$out/logs" "$out/slurm"
    out_abs=$(cd "$out" && pwd)
    plan_dir=$out_abs
fi
plan_err=$(mktemp "${TMPDIR:-/tmp}/esslurm-err.XXXXXX")
if ! "$bin" plan "$spec" --out "$plan_dir" --jobs "$jobs" "${by_flag[@]}" --quiet "${flags[@]}" 2>"$plan_err"; then
    # The whole message: a usage error names the argument and a hint on lines of their own.
    msg=$(cat "$plan_err"); rm -f "$plan_err"
    die "envshadow plan failed: $msg"
fi
rm -f "$plan_err"
mapfile -t lines <"$plan_dir/jobs.txt"
njobs=${#lines[@]}
[ "$njobs" -gt 0 ] || die "the plan has no jobs"

# Jobs still to render, judged from the files (a frame's statistics alone would pass a
# truncated or corrupted tile image): every job that is missing, incomplete or damaged, as
# assemble judges it. The tasks check again (--resume). A dry run looks at DIR only when it
# holds the same plan; otherwise a real run would render every job anyway.
todo=()
pending_dir=$out_abs
[ $dry = 0 ] || cmp -s "$plan_dir/plan.json" "$out_abs/plan.json" 2>/dev/null || pending_dir=$plan_dir
pending_err=$(mktemp "${TMPDIR:-/tmp}/esslurm-err.XXXXXX")
if ! pending=$("$bin" assemble "$pending_dir" --pending 2>"$pending_err"); then
    msg=$(tail -n 1 "$pending_err"); rm -f "$pending_err"
    die "envshadow assemble --pending failed: $msg"
fi
[ $dry = 1 ] || cat "$pending_err" >>"$out_abs/logs/pending.log"
rm -f "$pending_err"
while IFS=$'\t' read -r index _rest; do
    [ -z "$index" ] || todo+=("$index")
done <<<"$pending"

# Array indices as ranges: 0-3,5,7-9.
ranges() {
    local s="" start=$1 prev=$1 i
    shift
    for i in "$@" ""; do
        if [ -n "$i" ] && [ "$i" = $((prev + 1)) ]; then prev=$i; continue; fi
        [ -z "$s" ] || s+=,
        if [ "$start" = "$prev" ]; then s+=$start; else s+=$start-$prev; fi
        start=$i prev=$i
    done
    echo "$s"
}

common=(--parsable)
[ -z "$partition" ] || common+=(--partition="$partition")
[ -z "$time_limit" ] || common+=(--time="$time_limit")
common+=("${sbatch_extra[@]}")
name=envshadow-$(basename "$spec" .toml)

render_script=$out_abs/slurm/render.sh
assemble_script=$out_abs/slurm/assemble.sh
qflags=""
for f in "${flags[@]}"; do qflags+=" $(q "$f")"; done
render_body="#!/usr/bin/env bash
# One envshadow plan job per Slurm array task; written by scripts/slurm.sh.
set -uo pipefail
cd $(q "$PWD") || { echo \"cannot enter the submit folder on this node: a shared filesystem is needed\" >&2; exit 1; }
task=\$SLURM_ARRAY_TASK_ID
threads=\${SLURM_CPUS_PER_TASK:-\${SLURM_CPUS_ON_NODE:-1}}
echo \"envshadow job \$task of $njobs (array \${SLURM_ARRAY_JOB_ID}_\$task) on \$(hostname) node \${SLURMD_NODENAME:-?}, attempt \$((\${SLURM_RESTART_COUNT:-0} + 1)), \$threads threads, \$(date -u +%FT%TZ)\"
build=\$($(q "$node_bin") version --build 2>&1)
if [ \"\$build\" != $(q "$local_build") ]; then
    echo \"refused: this node runs '\$build', the plan was made with '$local_build' (another build can give other bits)\" >&2
    exit 2
fi
$(q "$node_bin") render $(q "$spec_abs") --job \"\$task\" --of $jobs${by:+ --by $by} --out $(q "$out_abs") --resume --threads \"\$threads\"$qflags
rc=\$?
echo \"envshadow job \$task exit \$rc, \$(date -u +%FT%TZ)\"
# Bad input (2) fails the same way every time; other failures may be the node's: try again.
if [ \$rc != 0 ] && [ \$rc != 2 ] && [ \"\${SLURM_RESTART_COUNT:-0}\" -lt $retries ]; then
    echo \"requeueing \${SLURM_ARRAY_JOB_ID}_\$task (attempt \$((\${SLURM_RESTART_COUNT:-0} + 1)) of $((retries + 1)))\" >&2
    scontrol requeue \"\${SLURM_ARRAY_JOB_ID}_\$task\" && exit \$rc
fi
exit \$rc
"
assemble_body="#!/usr/bin/env bash
# Stitches the render tasks' job folders into frames; written by scripts/slurm.sh.
set -uo pipefail
echo \"envshadow assemble on \$(hostname), \$(date -u +%FT%TZ)\"
$(q "$node_bin") assemble $(q "$out_abs")
rc=\$?
echo \"envshadow assemble exit \$rc, \$(date -u +%FT%TZ)\"
exit \$rc
"

array_cmd=() assemble_cmd=()
if [ ${#todo[@]} -gt 0 ]; then
    array=$(ranges "${todo[@]}")
    [ -z "$max_running" ] || array+=%$max_running
    array_cmd=(sbatch "${common[@]}" --job-name="$name" --array="$array" --requeue --open-mode=append
        --output="$out_abs/logs/render-%A_%a.log")
    [ -z "$cpus" ] || array_cmd+=(--cpus-per-task="$cpus")
    array_cmd+=("$render_script")
fi
assemble_cmd=(sbatch "${common[@]}" --job-name="$name-assemble" --output="$out_abs/logs/assemble-%j.log")

if [ $dry = 1 ]; then
    echo "# plan: $njobs jobs; ${#todo[@]} to render; this machine's build: $local_build"
    echo "# $render_script:"
    printf '%s' "$render_body" | sed 's/^/#   /'
    echo "# $assemble_script:"
    printf '%s' "$assemble_body" | sed 's/^/#   /'
    if [ ${#array_cmd[@]} -gt 0 ]; then
        printf '%q ' "${array_cmd[@]}"; echo
        printf '%q ' "${assemble_cmd[@]}" --dependency=afterok:ARRAY_ID --kill-on-invalid-dep=yes "$assemble_script"; echo
    else
        printf '%q ' "${assemble_cmd[@]}" "$assemble_script"; echo
    fi
    exit 0
fi

# Scripts are written atomically: a task of an earlier submission may be starting right now.
publish() {
    local tmp
    tmp=$(mktemp "$2.XXXXXX")
    printf '%s' "$1" >"$tmp"
    chmod 755 "$tmp"
    mv -f "$tmp" "$2"
}
publish "$render_body" "$render_script"
publish "$assemble_body" "$assemble_script"

submissions=$out_abs/logs/submissions.log
submit() { # sbatch args... ; prints the job id
    local o
    if ! o=$("$@" 2>&1); then
        say "sbatch failed: $o"
        printf '%s %s\n  failed: %s\n' "$(date -u +%FT%TZ)" "$(printf '%q ' "$@")" "$o" >>"$submissions"
        exit 1
    fi
    o=${o%%;*} # --parsable: "id" or "id;cluster"
    printf '%s %s\n  job %s\n' "$(date -u +%FT%TZ)" "$(printf '%q ' "$@")" "$o" >>"$submissions"
    echo "$o"
}

if [ ${#array_cmd[@]} -gt 0 ]; then
    array_id=$(submit "${array_cmd[@]}")
    say "submitted ${#todo[@]} of $njobs render jobs as array $array_id (tasks $array)"
    assemble_id=$(submit "${assemble_cmd[@]}" --dependency=afterok:"$array_id" --kill-on-invalid-dep=yes "$assemble_script")
    say "submitted the assembly as job $assemble_id, after every task of $array_id succeeds"
else
    assemble_id=$(submit "${assemble_cmd[@]}" "$assemble_script")
    say "all $njobs jobs are already rendered; submitted the assembly as job $assemble_id"
fi
say "logs: $out_abs/logs/ (render-${array_id:-ID}_TASK.log, assemble-$assemble_id.log, submissions.log)"
[ $wait = 1 ] || exit 0

# --wait: follow the assembly job until it ends. (sbatch --wait polls ever more slowly, up
# to half a minute between looks.)
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }
last="" misses=0
while :; do
    if ! info=$(scontrol -o show job "$assemble_id" 2>&1); then
        if grep -q 'Invalid job id' <<<"$info"; then
            say "job $assemble_id is no longer known to Slurm; see $out_abs/logs/assemble-$assemble_id.log"
            exit 1
        fi
        # slurmctld busy or restarting: look again for a few minutes before giving up.
        misses=$((misses + 1))
        [ $misses -lt 60 ] || { say "scontrol keeps failing: $info"; exit 1; }
        [ $misses != 1 ] || say "scontrol failed ($info); trying again"
        sleep 5
        continue
    fi
    misses=0
    state=$(field JobState <<<"$info")
    reason=$(field Reason <<<"$info")
    if [ -n "${array_id:-}" ]; then
        progress=$(squeue -h -r -j "$array_id" -o %T 2>/dev/null | sort | uniq -c | awk '{ printf "%s%s %s", sep, $1, tolower($2); sep = ", " }')
        now="assembly $state; render tasks: ${progress:-none left in the queue}"
    else
        now="assembly $state"
    fi
    [ "$now" = "$last" ] || say "$now"
    last=$now
    case $state in
    COMPLETED)
        say "done: frames in $out_abs"
        exit 0
        ;;
    PENDING | RUNNING | CONFIGURING | COMPLETING | REQUEUED | RESIZING | SUSPENDED) sleep 2 ;;
    *)
        if [ -n "${array_id:-}" ]; then
            failed=$(scontrol -o show job "$array_id" 2>/dev/null | awk '{
                t = ""; s = ""
                for (i = 1; i <= NF; i++) {
                    if ($i ~ /^ArrayTaskId=/) t = substr($i, 13)
                    if ($i ~ /^JobState=/) s = substr($i, 10)
                }
                if (s != "COMPLETED") { printf "%s%s (%s)", sep, t, s; sep = ", " } }')
            [ -z "$failed" ] || say "render tasks that did not succeed: $failed; logs $out_abs/logs/render-${array_id}_TASK.log"
        fi
        if [ "$reason" = DependencyNeverSatisfied ]; then
            say "assembly job $assemble_id was not run: render tasks failed; run the same command again to render what is missing"
        else
            say "assembly job $assemble_id ended $state${reason:+ ($reason)}; see $out_abs/logs/assemble-$assemble_id.log; run the same command again to render what is missing"
        fi
        exit 1
        ;;
    esac
done
