//! Debugging aid: write the scenario of a `kss-bench` workload (by its full
//! name, as `kss-bench --list` prints it) as JSON on standard output, to run
//! or profile one cell by hand (`kss run cluster.json`).
//!
//! `cargo run -p kss-bench --example workload -- cluster-k1000 > cluster.json`
fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() != 2 {
        eprintln!("usage: workload NAME");
        std::process::exit(2);
    }
    let w = match kss_bench::workload::Workload::parse(&a[1]) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("workload: {e}");
            std::process::exit(2);
        }
    };
    print!(
        "{}",
        kss::json::write_scenario(&w.scenario()).expect("serializable")
    );
}
