//! `docs/benchmarks.md` is exactly what `kss-bench docs` makes of the
//! results files in the repository, so the page cannot drift from them.

use std::path::Path;

#[test]
fn the_benchmark_page_is_what_the_results_make() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let results = root.join("results");
    let page = root.join("../../docs/benchmarks.md");
    let expected = kss_bench::docs::generate(&results, &page).unwrap_or_else(|e| {
        panic!("`kss-bench docs` cannot make docs/benchmarks.md from crates/kss-bench/results: {e}")
    });
    let actual = std::fs::read_to_string(&page).expect("read docs/benchmarks.md");
    if let Some(d) = kss_bench::docs::first_difference(&actual, &expected) {
        panic!(
            "docs/benchmarks.md is not what `kss-bench docs` makes of crates/kss-bench/results \
             ({d}). Edit the page's text in crates/kss-bench/results/page/ (not the page), \
             then write the page from the workspace root with `{}`.",
            kss_bench::docs::COMMAND
        );
    }
}
