//! The `envshadow` binary: parse the command line, run it, report errors with their chain on
//! one line and exit with a documented code (see `envshadow --help`).

mod cli;
mod pure_maths;

use clap::Parser;

use envshadow::error::exit_code;

fn main() {
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version (stdout, exit 0) and usage errors (stderr, exit 2, which is also
        // our bad-input code) as clap writes them: the whole message, with the argument a
        // command is missing, the usage line and hints such as "tip: a similar argument
        // exists: '--frames'"; coloured only on a terminal.
        Err(e) => e.exit(),
    };
    if let Err(err) = cli::run(cli) {
        let mut msg = format!("error: {err}");
        for cause in err.chain().skip(1) {
            msg.push_str(&format!(": {cause}"));
        }
        // One line, whatever the names in it hold (issue 39: a URI's newline forged a line).
        cli::say(&envshadow::error::escaped(&msg));
        std::process::exit(exit_code(&err));
    }
}
