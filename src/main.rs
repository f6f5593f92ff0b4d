//! The `envshadow` binary: parse the command line, run it, report errors with their chain on
//! one line and exit with a documented code (see `envshadow --help`).

mod cli;
mod pure_maths;

use clap::Parser;
use clap::error::ErrorKind;

use envshadow::error::{exit, exit_code};

fn main() {
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            e.exit()
        }
        Err(e) if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
        Err(e) => {
            // clap adds usage and a hint on further lines; one line is easier to grep in a
            // farm's logs, and `--help` has the rest.
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("error: bad arguments");
            cli::say(&format!("{first} (see --help)"));
            std::process::exit(exit::BAD_INPUT);
        }
    };
    if let Err(err) = cli::run(cli) {
        let mut msg = format!("error: {err}");
        for cause in err.chain().skip(1) {
            msg.push_str(&format!(": {cause}"));
        }
        cli::say(&msg);
        std::process::exit(exit_code(&err));
    }
}
