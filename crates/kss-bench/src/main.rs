//! `kss-bench`: kss against the baselines on fixed workloads.
//! Run `kss-bench --help` for the options.

#![forbid(unsafe_code)]

use clap::Parser;

/// Counts live heap bytes and allocations for the cells' memory figures
/// ([`kss_bench::heap`]).
#[global_allocator]
static ALLOCATOR: kss_bench::heap::Counting = kss_bench::heap::Counting;

fn main() {
    let args = kss_bench::cli::BenchArgs::parse();
    if let Err(e) = kss_bench::command::bench(&args) {
        eprintln!("kss-bench: error: {e}");
        std::process::exit(e.exit_code());
    }
}
