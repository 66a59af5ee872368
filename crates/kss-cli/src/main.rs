//! `kss`: exact kinetic collision detection for moving convex polygons.
//! Run `kss --help` for the commands.

#![forbid(unsafe_code)]

use clap::Parser;

fn main() {
    let cli = kss_cli::cli::Cli::parse();
    if let Err(e) = kss_cli::commands::execute(cli) {
        eprintln!("kss: error: {e}");
        std::process::exit(e.exit_code());
    }
}
