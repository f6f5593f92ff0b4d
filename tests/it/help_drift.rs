//! Issue 40: the README and `--help` say what the binary does. Every flag the README shows in
//! code is a flag of some command (or of a tool named below), the `stats.csv` columns and the
//! progress line it quotes are those a render writes, and the defaults its quick start states
//! are those `--help` gives.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::common;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn readme() -> String {
    std::fs::read_to_string(root().join("README.md")).unwrap()
}

/// The text the README shows as code: fenced blocks, indented blocks and inline spans.
fn code_in(markdown: &str) -> Vec<String> {
    let mut code = Vec::new();
    let mut prose = String::new();
    let mut fence: Option<String> = None;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            match fence.take() {
                Some(block) => code.push(block),
                None => fence = Some(String::new()),
            }
        } else if let Some(block) = &mut fence {
            block.push_str(line);
            block.push('\n');
        } else if line.starts_with("    ") && !line.trim().is_empty() {
            code.push(line.to_string());
        } else {
            prose.push_str(line);
            prose.push('\n');
        }
    }
    code.extend(spans(&prose));
    code
}

/// The inline code spans of `text` (between single backticks).
fn spans(text: &str) -> Vec<String> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The long flags (`--name`) in `text`: a `--` not inside a word, then lowercase letters,
/// digits and dashes (`--scene-lights=false` is `--scene-lights`).
fn flags_in(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i + 2 < chars.len() {
        let starts = chars[i] == '-'
            && chars[i + 1] == '-'
            && chars[i + 2].is_ascii_lowercase()
            && (i == 0 || !(chars[i - 1].is_alphanumeric() || matches!(chars[i - 1], '-' | '_')));
        if starts {
            let mut end = i + 2;
            while end < chars.len()
                && (chars[end].is_ascii_lowercase()
                    || chars[end].is_ascii_digit()
                    || chars[end] == '-')
            {
                end += 1;
            }
            found.insert(
                chars[i..end]
                    .iter()
                    .collect::<String>()
                    .trim_end_matches('-')
                    .into(),
            );
            i = end;
        } else {
            i += 1;
        }
    }
    found
}

/// `envshadow ARGS` that must succeed: its stdout.
fn run_ok(args: &[&str]) -> String {
    let out = common::bin().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "envshadow {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The commands `envshadow --help` lists.
fn commands() -> Vec<String> {
    let help = run_ok(&["--help"]);
    let list = help
        .split("Commands:\n")
        .nth(1)
        .expect("envshadow --help lists no commands");
    let commands: Vec<String> = list
        .lines()
        .take_while(|l| !l.trim().is_empty())
        // A command's line starts two spaces in; its description's next lines further.
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect();
    assert!(
        commands.iter().any(|c| c == "render") && commands.len() >= 10,
        "{commands:?}"
    );
    commands
}

/// The options a help page defines, each with its help text on one line: `--spp` → `Samples
/// per pixel, …`. An option's line is indented at most six spaces and starts with `-`; its
/// text follows, indented further, up to the next option.
fn options(help: &str) -> BTreeMap<String, String> {
    let mut found = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in help.lines() {
        let indent = line.len() - line.trim_start().len();
        let trimmed = line.trim_start();
        if indent <= 6 && trimmed.starts_with('-') {
            let long = trimmed
                .split([',', ' ', '[', '<', '='])
                .map(str::trim)
                .find(|w| w.starts_with("--"))
                // `--verbose...`: clap's mark of a flag that may repeat.
                .map(|w| w.trim_end_matches('.').to_string());
            if let Some(long) = &long {
                found.insert(long.clone(), String::new());
            }
            current = long;
        } else if indent == 0 && !trimmed.is_empty() {
            current = None;
        } else if let Some(flag) = &current
            && !trimmed.is_empty()
        {
            let text = found.get_mut(flag).unwrap();
            if !text.is_empty() {
                text.push(' ');
            }
            text.push_str(trimmed);
        }
    }
    found
}

/// Whether `text` holds `token` as a whole word or number: `4` is in "uses 4." but not in
/// "64" nor "4.5"; `out/<model name>` is in "into out/<model name>/".
fn has_token(text: &str, token: &str) -> bool {
    text.match_indices(token).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let mut after = text[at + token.len()..].chars();
        let word = |c: char| c.is_alphanumeric() || c == '_';
        let end = match after.next() {
            None => true,
            Some('.') => !after.next().is_some_and(|c| c.is_ascii_digit()),
            Some(c) => !word(c) && c != '-',
        };
        end && !before.is_some_and(|c| word(c) || c == '.' || c == '-')
    })
}

/// Flags the README shows that belong to other programs: cargo's (the build, install and
/// test commands) and OpenImageIO's `oiiotool` (the compositing example). The project's own
/// scripts' flags are checked against the scripts themselves.
const OTHER_TOOLS: &[&str] = &[
    "--release",
    "--path",
    "--target",
    "--all-targets",
    "--test",
    "--pattern",
    "--over",
    // macOS's `xcode-select --install` (the install section's C toolchain).
    "--install",
];

/// Every flag of every command, from their `--help`.
fn every_flag() -> BTreeSet<String> {
    let mut known: BTreeSet<String> = options(&run_ok(&["--help"])).into_keys().collect();
    // `help` is clap's, and has no `--help` of its own.
    for c in commands().into_iter().filter(|c| c != "help") {
        known.extend(options(&run_ok(&[&c, "--help"])).into_keys());
    }
    known
}

/// Issue 40: the README named flags `--help` did not have, or no longer had.
#[test]
fn every_flag_the_readme_shows_is_a_real_flag() {
    let known = every_flag();
    // The parser must see the flags, or the check below would pass on nothing.
    for f in [
        "--spp",
        "--out",
        "--frames",
        "--resume",
        "--build",
        "--scene-lights",
    ] {
        assert!(known.contains(f), "{f} not found in any --help: {known:?}");
    }
    let scripts: String = std::fs::read_dir(root().join("scripts"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "sh"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    let shown: BTreeSet<String> = code_in(&readme())
        .iter()
        .flat_map(|c| flags_in(c))
        .collect();
    assert!(shown.contains("--spp") && shown.len() > 40, "{shown:?}");
    let unknown: Vec<&String> = shown
        .iter()
        .filter(|f| {
            !known.contains(*f) && !OTHER_TOOLS.contains(&f.as_str()) && !has_token(&scripts, f)
        })
        .collect();
    assert!(
        unknown.is_empty(),
        "README.md shows flags that no command's --help, script or listed tool has: {unknown:?}"
    );
}

/// The README's example of `line` with every number replaced by `#`: `frame 7 (8/24): 0.41 s`
/// is `frame # (#/#): # s`.
fn shape(line: &str) -> String {
    let mut out = String::new();
    let mut in_number = false;
    for c in line.chars() {
        let digit = c.is_ascii_digit() || (in_number && matches!(c, '.' | ':'));
        if digit && !in_number {
            out.push('#');
        } else if !digit {
            out.push(c);
        }
        in_number = digit;
    }
    out
}

/// A one-frame, 32×24 render of the default animation into `dir`: its stderr.
fn tiny_render(dir: &Path) -> String {
    let out = common::bin()
        .current_dir(root())
        .args(["render", "anims/shapes-turntable.toml", "--width", "32"])
        .args(["--height", "24", "--frames", "0", "--no-report", "--out"])
        .arg(dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    stderr
}

/// Issue 40: the README called the time column `seconds` after it became `thread_seconds`,
/// and quoted a progress line the renderer no longer prints.
#[test]
fn the_readme_quotes_the_stats_columns_and_progress_line_a_render_writes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let stderr = tiny_render(&dir);
    let text = std::fs::read_to_string(dir.join("stats.csv")).unwrap();
    let header: BTreeSet<&str> = text.lines().next().unwrap().split(',').collect();
    assert!(header.contains("frame") && header.len() > 30, "{header:?}");

    let readme = readme();
    let row = readme
        .lines()
        .find(|l| l.starts_with("| `stats.csv` |"))
        .expect("README.md's table of files has no stats.csv row");
    // The row names the columns in code spans; `--spp 1` or `stats.csv` are not columns.
    let named: BTreeSet<String> = spans(row)
        .into_iter()
        .filter(|s| {
            s.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        })
        .collect();
    let stale: Vec<&String> = named
        .iter()
        .filter(|n| !header.contains(n.as_str()))
        .collect();
    let missing: Vec<&&str> = header.iter().filter(|h| !named.contains(**h)).collect();
    assert!(
        stale.is_empty() && missing.is_empty(),
        "README.md's stats.csv row names columns stats.csv does not have: {stale:?}; and \
         leaves out these of its columns: {missing:?}"
    );

    let printed = stderr
        .lines()
        .find(|l| l.starts_with("frame 0 (1/1): "))
        .unwrap_or_else(|| panic!("no progress line for frame 0 in: {stderr}"));
    let quoted: Vec<String> = spans(&readme)
        .into_iter()
        .filter(|s| s.starts_with("frame ") && s.contains("queries traced"))
        .collect();
    assert!(!quoted.is_empty(), "README.md quotes no progress line");
    for q in &quoted {
        assert_eq!(
            shape(q),
            shape(printed),
            "README.md's progress line is not the one a render prints"
        );
    }
}

/// The README's quick-start table: each row's flag and the defaults its last column states
/// (in code spans), for `envshadow render model.glb`.
fn quick_start_table(readme: &str) -> Vec<(String, Vec<String>)> {
    let mut lines = readme.lines().skip_while(|l| {
        !(l.starts_with('|') && l.to_lowercase().contains("default for `render model.glb`"))
    });
    assert!(
        lines.next().is_some(),
        "README.md has no quick-start table of flags with a column \"default for `render \
         model.glb`\""
    );
    lines
        .skip(1)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split('|').map(str::trim).collect();
            let flag = flags_in(cells[0])
                .into_iter()
                .next()
                .unwrap_or_else(|| panic!("no flag in the quick-start row {l}"));
            (flag, spans(cells[cells.len() - 1]))
        })
        .collect()
}

/// Issue 40: `--spp`'s help said 1 where a model render uses 4, and `--out`'s said `out`
/// where a model render writes to `out/<model name>`. Each default the quick start states is
/// in its flag's `--help`.
#[test]
fn the_quick_starts_defaults_are_the_ones_help_gives() {
    let rows = quick_start_table(&readme());
    assert!(rows.len() >= 5, "{rows:?}");
    let render = options(&run_ok(&["render", "--help"]));
    let mut failures = Vec::new();
    for (flag, defaults) in &rows {
        let Some(help) = render.get(flag) else {
            failures.push(format!("{flag}: not a flag of render"));
            continue;
        };
        if defaults.is_empty() {
            failures.push(format!("{flag}: the README states no default in code"));
        }
        for d in defaults {
            if !has_token(help, d) {
                failures.push(format!("{flag}: README says {d}, --help says: {help}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_drift_checks_read_what_they_mean() {
    assert_eq!(
        flags_in("a --spp 4, `--scene-lights=false` x--no, ---"),
        BTreeSet::from(["--spp".to_string(), "--scene-lights".to_string()])
    );
    assert!(has_token("uses 4.", "4") && !has_token("from 1 to 64", "4"));
    assert!(!has_token("4.5", "4") && has_token("into out/<model name>/", "out/<model name>"));
    assert_eq!(
        shape("frame 7 (8/24): 0.41 s; 0:00:04"),
        "frame # (#/#): # s; #"
    );
    let help = "Options:\n  -n, --lights <N>\n          Number of\n          lights\n\n      \
                --spp[=<N>]\n          Samples\n";
    let o = options(help);
    assert_eq!(o["--lights"], "Number of lights");
    assert_eq!(o["--spp"], "Samples");
    assert_eq!(
        code_in("a `x` b\n```sh\nc --d\n```\n    e\n"),
        vec!["c --d\n", "    e", "x"]
    );
}

/// Issue 40: `lights --scene-lights` meant nothing there (a map has no glTF lights), and
/// `export` took both `--frame` and `--frames`. Each is out of its command's help and refused
/// with a word on what to use.
#[test]
fn flags_that_mean_nothing_to_a_command_are_left_out_and_refused() {
    let lights = options(&run_ok(&["lights", "--help"]));
    assert!(lights.contains_key("--lights") && !lights.contains_key("--scene-lights"));
    let export = options(&run_ok(&["export", "--help"]));
    assert!(export.contains_key("--frame") && !export.contains_key("--frames"));
    let tmp = tempfile::tempdir().unwrap();
    for (args, says) in [
        (
            vec![
                "lights",
                "builtin:sky",
                "-n",
                "8",
                "--scene-lights=false",
                "--png",
            ],
            "--scene-lights: means nothing to lights",
        ),
        (
            vec![
                "export",
                "anims/shapes-turntable.toml",
                "--frames",
                "3",
                "--out",
            ],
            "use --frame N (not --frames 3)",
        ),
    ] {
        // The output path last: refused before anything is written there.
        let out = common::bin()
            .current_dir(root())
            .args(&args)
            .arg(tmp.path().join("x"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(common::error_line(&err).contains(says), "{args:?}: {err}");
    }
}

/// Issue 40: `--resume`'s help said it skipped frames whose files exist; it checks them and
/// the settings they were rendered with.
#[test]
fn resume_help_says_what_it_checks() {
    let render = options(&run_ok(&["render", "--help"]));
    let help = &render["--resume"];
    for says in [
        "SHA-256",
        "other settings or inputs",
        "first difference",
        "--threads",
    ] {
        assert!(
            help.contains(says),
            "--resume's help lacks {says:?}: {help}"
        );
    }
}

/// GitHub's anchor of a heading: lowercase, punctuation dropped, spaces as dashes.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// Issue 40: the README's table of contents (and every link to one of its sections) leads
/// to a heading it has.
#[test]
fn the_readmes_contents_lead_to_its_sections() {
    let readme = readme();
    let headings: BTreeSet<String> = readme
        .lines()
        .filter_map(|l| l.strip_prefix("## ").or_else(|| l.strip_prefix("### ")))
        .map(anchor)
        .collect();
    let links: Vec<&str> = readme
        .split("](#")
        .skip(1)
        .filter_map(|s| s.split(')').next())
        .collect();
    assert!(links.len() >= 20, "no table of contents: {links:?}");
    let broken: Vec<&&str> = links.iter().filter(|l| !headings.contains(**l)).collect();
    assert!(
        broken.is_empty(),
        "README.md links to no heading: {broken:?}"
    );
    assert_eq!(
        anchor("Alpha and the scene file's lights"),
        "alpha-and-the-scene-files-lights"
    );
}
