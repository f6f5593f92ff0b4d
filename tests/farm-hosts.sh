#!/usr/bin/env bash
# Pretend ssh hosts on loopback for tests/it/farm.rs: one sshd per host on 127.0.0.(K+1), each
# with its own host key, port, config, pid file and log, all inside DIR. Touches nothing in
# ~/.ssh or /etc/ssh. Processes are found and stopped by PID (checked against their command
# line), never by name.
#
#   farm-hosts.sh start DIR N     start hosts fh1..fhN; writes DIR/ssh_config, DIR/hosts
#   farm-hosts.sh crash DIR K     stop host fhK hard: its sshd and every process under it
#   farm-hosts.sh stop DIR        stop every host started in DIR (and everything under them)
#
# Each host runs commands through a ForceCommand wrapper that gives it its own HOME (its
# "disk": DIR/hK/home) and puts DIR/hK/bin first on PATH (its own envshadow).
set -euo pipefail

cmd=${1:?usage: farm-hosts.sh start|crash|stop DIR [N|K]}
dir=$(cd "${2:?DIR}" && pwd)

# The PIDs of every descendant of $1, deepest first.
descendants() {
    local kid
    for kid in $(pgrep -P "$1" 2>/dev/null || true); do
        descendants "$kid"
        echo "$kid"
    done
}

# Stops host K's sshd and everything under it: SIGSTOP first so nothing forks meanwhile.
stop_host() {
    local k=$1 pidfile="$dir/h$1/sshd.pid" pid kids
    [ -f "$pidfile" ] || return 0
    pid=$(cat "$pidfile")
    if [ -r "/proc/$pid/cmdline" ] && tr '\0' ' ' <"/proc/$pid/cmdline" | grep -qF "$dir/h$k/sshd_config"; then
        kill -STOP "$pid" 2>/dev/null || true
        kids=$(descendants "$pid")
        for p in $kids; do kill -STOP "$p" 2>/dev/null || true; done
        for p in $kids "$pid"; do kill -KILL "$p" 2>/dev/null || true; done
    fi
    rm -f "$pidfile"
}

case $cmd in
start)
    n=${3:?N}
    command -v ssh-keygen >/dev/null && [ -x /usr/sbin/sshd ] || { echo "sshd or ssh-keygen missing" >&2; exit 3; }
    mkdir -p /run/sshd
    user=$(id -un)
    # Ports from this shell's PID so parallel test runs do not collide.
    base=$((20000 + ($$ % 2000) * 10))
    [ -f "$dir/client_key" ] || ssh-keygen -q -t ed25519 -N '' -f "$dir/client_key"
    cp "$dir/client_key.pub" "$dir/authorized_keys"
    : >"$dir/known_hosts"
    : >"$dir/ssh_config"
    : >"$dir/hosts"
    for k in $(seq 1 "$n"); do
        h="$dir/h$k"
        mkdir -p "$h/home" "$h/bin"
        [ -f "$h/host_key" ] || ssh-keygen -q -t ed25519 -N '' -f "$h/host_key"
        port=$((base + k))
        addr="127.0.0.$((k + 1))"
        cat >"$h/wrapper" <<EOF
#!/bin/bash
export HOME="$h/home" PATH="$h/bin:\$PATH"
cd "\$HOME"
if [ -n "\${SSH_ORIGINAL_COMMAND:-}" ]; then exec /bin/bash -c "\$SSH_ORIGINAL_COMMAND"; fi
exec /bin/bash -l
EOF
        chmod +x "$h/wrapper"
        cat >"$h/sshd_config" <<EOF
ListenAddress $addr:$port
HostKey $h/host_key
PidFile $h/sshd.pid
AuthorizedKeysFile $dir/authorized_keys
PermitRootLogin prohibit-password
PasswordAuthentication no
KbdInteractiveAuthentication no
UsePAM no
StrictModes no
ForceCommand $h/wrapper
SetEnv SHLVL=1
MaxStartups 100:30:200
MaxSessions 100
EOF
        /usr/sbin/sshd -t -f "$h/sshd_config"
        /usr/sbin/sshd -f "$h/sshd_config" -E "$h/sshd.log"
        echo "[$addr]:$port $(cut -d' ' -f1,2 "$h/host_key.pub")" | sed "s/^\[$addr\]:$port/fh$k/" >>"$dir/known_hosts"
        cat >>"$dir/ssh_config" <<EOF
Host fh$k
    HostName $addr
    Port $port
    User $user
    HostKeyAlias fh$k
EOF
        echo "1/fh$k" >>"$dir/hosts"
    done
    cat >>"$dir/ssh_config" <<EOF
Host *
    IdentityFile $dir/client_key
    IdentitiesOnly yes
    UserKnownHostsFile $dir/known_hosts
    StrictHostKeyChecking yes
    BatchMode yes
    ConnectTimeout 5
    ServerAliveInterval 2
    ServerAliveCountMax 3
EOF
    # sshd exits 0 even when it cannot bind: wait for each pid file and a real login.
    for k in $(seq 1 "$n"); do
        for _ in $(seq 1 100); do
            if [ -f "$dir/h$k/sshd.pid" ] && ssh -F "$dir/ssh_config" "fh$k" true 2>/dev/null; then
                continue 2
            fi
            sleep 0.1
        done
        echo "host fh$k did not come up; see $dir/h$k/sshd.log" >&2
        exit 1
    done
    ;;
crash)
    stop_host "${3:?K}"
    ;;
stop)
    for h in "$dir"/h*/; do
        k=${h%/}
        k=${k##*/h}
        stop_host "$k"
    done
    ;;
*)
    echo "unknown command $cmd" >&2
    exit 2
    ;;
esac
