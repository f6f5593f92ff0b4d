//! scripts/chaos.sh keeps its promise on a few faults: random kills of the coordinator, a
//! host or a job (and a full disk where a tmpfs can be mounted) against a small farm on fake
//! hosts, each followed by the same farm command again, lose no frame and no row and change no
//! bit. The README's figure runs it with N = 50.

use std::path::Path;
use std::process::Command;

use crate::common;

#[test]
fn chaos_faults_lose_no_frame_no_row_and_change_no_bit() {
    let tools = [
        "parallel",
        "ssh",
        "rsync",
        "ssh-keygen",
        "pgrep",
        "/usr/sbin/sshd",
    ];
    if !common::require_tools(
        common::this_test!(),
        &tools,
        "apt-get install parallel openssh-server openssh-client rsync procps",
    ) {
        return;
    }
    let o = Command::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/chaos.sh"))
        .args(["6", "--seed", "20261125"])
        .env("ENVSHADOW", env!("CARGO_BIN_EXE_envshadow"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success()
            && stdout.contains("6 faults, 0 frames lost, 0 rows lost, 0 differing frames"),
        "exit {:?}\n{stdout}\n{stderr}",
        o.status.code()
    );
    // Six faults of at least two kinds actually happened.
    let kinds: std::collections::BTreeSet<&str> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("fault "))
        .filter_map(|l| l.split(": ").nth(1))
        .collect();
    assert!(kinds.len() >= 2, "{stdout}");
}
