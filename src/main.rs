//! The `envshadow` binary: parse the command line, run it, report errors with their chain and
//! exit with a documented code (see `envshadow --help`).

use clap::Parser;

fn main() {
    let cli = envshadow::cli::Cli::parse();
    if let Err(err) = envshadow::cli::run(cli) {
        let mut msg = format!("error: {err}");
        for cause in err.chain().skip(1) {
            msg.push_str(&format!(": {cause}"));
        }
        eprintln!("{msg}");
        std::process::exit(envshadow::error::exit_code(&err));
    }
}
