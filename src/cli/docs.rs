//! `envshadow completions SHELL` and `envshadow man`: the shell completion script
//! (clap_complete) and the manual pages (clap_mangen), both made from the clap definitions
//! themselves, so they name every command and flag the binary has.

use std::path::PathBuf;

use anyhow::Context;
use clap::{Args, CommandFactory};

use envshadow::error::Result;

use super::Cli;
use super::talk::{Talk, out};

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

#[derive(Args, Debug)]
pub struct ManArgs {
    /// Write a page per command into DIR (envshadow.1, envshadow-render.1, …) instead of
    /// printing envshadow(1).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Prints the completion script for `args.shell`.
pub fn completions(args: &CompletionsArgs) {
    let mut cmd = Cli::command();
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "envshadow", &mut script);
    out(&String::from_utf8_lossy(&script));
}

/// The manual pages: envshadow(1), then one per command (`envshadow-render(1)`, …), each as
/// its file name and roff text.
pub fn man_pages() -> Result<Vec<(String, Vec<u8>)>> {
    let mut root = Cli::command().disable_help_subcommand(true);
    root.build();
    let mut pages = Vec::new();
    let mut page = |cmd: clap::Command| -> Result<()> {
        let man = clap_mangen::Man::new(cmd)
            .source(format!("envshadow {}", env!("CARGO_PKG_VERSION")))
            .manual("envshadow manual");
        let mut text = Vec::new();
        man.render(&mut text).context("writing a manual page")?;
        pages.push((
            man.get_filename(),
            ascii_roff(&String::from_utf8_lossy(&text)),
        ));
        Ok(())
    };
    page(root.clone())?;
    for sub in root.get_subcommands().filter(|s| !s.is_hide_set()) {
        page(sub.clone())?;
    }
    Ok(pages)
}

/// Roff with every character outside ASCII written as groff's `\[uXXXX]` escape (groff_char(7);
/// mandoc reads it too): the help text's dashes, ellipses and `×` are then read right by any
/// troff, not only by one that runs preconv first, as man-db does.
fn ascii_roff(text: &str) -> Vec<u8> {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_ascii() {
            s.push(c);
        } else {
            s.push_str(&format!("\\[u{:04X}]", c as u32));
        }
    }
    s.into_bytes()
}

/// `envshadow man [--out DIR]`.
pub fn man(args: &ManArgs, talk: Talk) -> Result<()> {
    let pages = man_pages()?;
    let Some(dir) = &args.out else {
        out(&String::from_utf8_lossy(&pages[0].1));
        return Ok(());
    };
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (name, text) in &pages {
        envshadow::output::write_atomic(&dir.join(name), text)?;
    }
    talk.done(&format!(
        "wrote {} manual pages into {} (read one with man {}/envshadow-render.1)",
        pages.len(),
        dir.display(),
        dir.display()
    ));
    Ok(())
}
