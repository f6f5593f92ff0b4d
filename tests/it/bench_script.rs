//! scripts/bench-corpus.sh: the corpus bench's table and summaries.

use crate::common;

#[test]
fn bench_corpus_summarises_each_swept_setting_as_a_method() {
    // `scripts/bench-corpus.sh … -- --pixel-majority=true,false` times both settings
    // interleaved in one process (bench labels the one that is not the default); each must
    // get its table row and its own summary lines.
    if !common::require_tools(
        "bench_corpus_summarises_each_swept_setting_as_a_method",
        &["python3"],
        "apt-get install python3",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let corpus = dir.path().join("corpus");
    std::fs::create_dir(&corpus).unwrap();
    std::fs::copy(common::asset("corpus/spot.glb"), corpus.join("spot.glb")).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::process::Command::new("bash")
        .arg(root.join("scripts/bench-corpus.sh"))
        .arg("--corpus")
        .arg(&corpus)
        .arg("--maps")
        .arg(common::asset("studio_small_03_1k.hdr"))
        .args([
            "--size", "48x32", "--lights", "16", "--spp", "4", "--repeat", "1",
        ])
        .args(["--threads", "1", "--work"])
        .arg(dir.path().join("work"))
        .args(["--", "--pixel-majority=true,false"])
        .env("ENVSHADOW_BIN", env!("CARGO_BIN_EXE_envshadow"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for label in [
        "grid-nowarp-uncertainty",
        "grid-nowarp-uncertainty --pixel-majority true",
    ] {
        let row = format!("| spot | studio_small_03_1k | {label} |");
        assert_eq!(stdout.matches(&row).count(), 1, "{row} in\n{stdout}");
        let summary = format!("corpus ({label}): median ");
        assert_eq!(
            stdout.matches(&summary).count(),
            1,
            "{summary} in\n{stdout}"
        );
        // What a traced query costs against brute force's ray, per setting (issue 36).
        let cost = format!("corpus ({label}): a traced query costs a median ");
        assert_eq!(stdout.matches(&cost).count(), 1, "{cost} in\n{stdout}");
    }
    assert!(
        stdout.contains("| traced query ÷ brute ray |"),
        "the table's cost column in\n{stdout}"
    );
}
