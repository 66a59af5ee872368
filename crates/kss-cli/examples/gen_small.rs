//! Debugging aid: write the small scenario the differential tests use for a
//! family and seed (`kss::gen::generate_small`) as JSON on standard output.
//!
//! `cargo run -p kss-cli --example gen_small -- FAMILY SEED`
fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() != 3 {
        eprintln!("usage: gen_small FAMILY SEED");
        std::process::exit(2);
    }
    let family = kss::gen::Family::from_name(&a[1]).expect("a family name");
    let seed: u64 = a[2].parse().expect("a seed");
    let s = kss::gen::generate_small(family, seed);
    print!("{}", kss::json::write_scenario(&s).expect("serializable"));
}
