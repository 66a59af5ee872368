//! `kss-bench docs`: the page `docs/benchmarks.md`, generated from the
//! results files in `crates/kss-bench/results/`.
//!
//! The page's sources are the Markdown files of `results/page/`, read in
//! the order of their names and joined with a blank line. Their text goes
//! to the page as it is, except for
//!
//! - `{results}`, replaced by the path from the page to the results folder;
//!   a link `({results}/PATH)` must name a file or folder of the results;
//! - blocks from a line `::: KIND` to a line `:::`, one `key: value` a line
//!   (lists separated by `|`), replaced by what they describe:
//!   - `::: run`: where the figures that follow in the section come from.
//!     `file:` the results file that records the run, `see:` other results
//!     files of it, `date:`, `commit:` (the binary's; several separated by
//!     spaces, or `not recorded`), `command:` (the command as the results
//!     file writes it, or `block N` for its N-th fenced code block; any
//!     number of them), `options-from:` (a `bench.json` whose recorded
//!     methods, workloads and budget are written as options),
//!     `conditions:` (what else ran on the machine, as the results file
//!     says). The date, each commit and each written command must appear
//!     in `file`.
//!   - `::: table`: a table copied from a results file, cell for cell.
//!     `file:`, `under:` (the text of the heading it is under), `index:`
//!     (the N-th table under that heading, 1 if not given), `rows:` (only
//!     the rows whose first cell is one of these, in this order; a row
//!     whose first cell is empty goes with the row before it), `columns:`
//!     (only these columns, by header), `details:` (folded, with this
//!     summary).
//!   - `::: cells`: a table computed from a run's `bench.json`, one row per
//!     workload and method. `file:`, `workloads:`, `methods:`, `columns:`
//!     (from `workload`, `method`, `status`, `wall`, `build`, `events`,
//!     `collisions`, `events / collision`, `µs / event`,
//!     `µs / event after build`, `µs / collision`, `peak RSS (MiB)`,
//!     `peak heap (MiB)`, `allocs / event`).
//!   - `::: machine`: the machines that the reports of the results folder
//!     name (their `Machine:` lines, without the kernel version).
//!
//! Every table names its results file and the date and commit of the
//! `::: run` before it in the same section (a section starts at a `## `
//! heading); a table with no run before it is an error. Every results
//! report (a `.md` file of the results folder or of a folder in it, the
//! sources aside) must be named by a block or a link, so a new results
//! file cannot stay off the page.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Component, Path, PathBuf};

use crate::harness::{BenchRun, CellResult, Status};
use crate::report;
use crate::Method;

/// The folder of the page's sources, inside the results folder.
pub const SOURCES: &str = "page";

/// The command that writes the page, run from the workspace root.
pub const COMMAND: &str = "cargo run -p kss-bench -- docs";

/// The page that goes to `page`, generated from the results folder
/// `results` (its links to results files are relative to `page`'s folder).
pub fn generate(results: &Path, page: &Path) -> Result<String, String> {
    let link = link_prefix(results, page)?;
    let dir = results.join(SOURCES);
    let mut sources: Vec<PathBuf> = fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    sources.sort();
    if sources.is_empty() {
        return Err(format!("{}: no page sources (*.md)", dir.display()));
    }
    let mut gen = Generator {
        results: results.to_path_buf(),
        link,
        named: BTreeSet::new(),
    };
    let mut parts = Vec::new();
    for src in &sources {
        let text = fs::read_to_string(src).map_err(|e| format!("{}: {e}", src.display()))?;
        let name = format!(
            "{SOURCES}/{}",
            src.file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned())
        );
        parts.push(gen.expand(&name, &text)?);
    }
    gen.check_named()?;
    let mut page = parts
        .iter()
        .map(|p| p.trim_end())
        .collect::<Vec<_>>()
        .join("\n\n");
    page.push('\n');
    Ok(page)
}

/// The first line where `actual` and `expected` differ (1-based), with
/// both lines, or `None` if they are equal.
pub fn first_difference(actual: &str, expected: &str) -> Option<String> {
    if actual == expected {
        return None;
    }
    let (a, e): (Vec<&str>, Vec<&str>) = (actual.lines().collect(), expected.lines().collect());
    let i = a.iter().zip(&e).take_while(|(x, y)| x == y).count();
    if i == a.len() && i == e.len() {
        return Some("the lines are the same; the line endings or the final newline differ".into());
    }
    let show = |v: &[&str]| {
        v.get(i)
            .map_or("(end of file)".to_string(), |l| format!("{l:?}"))
    };
    Some(format!(
        "line {}: the file has {}, the generator writes {}",
        i + 1,
        show(&a),
        show(&e)
    ))
}

/// The path from `page`'s folder to `results`, with `/` separators.
fn link_prefix(results: &Path, page: &Path) -> Result<String, String> {
    let abs = |p: &Path| fs::canonicalize(p).map_err(|e| format!("{}: {e}", p.display()));
    let to = abs(results)?;
    let from = abs(page
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new(".")))?;
    let (t, f): (Vec<Component>, Vec<Component>) =
        (to.components().collect(), from.components().collect());
    let common = t.iter().zip(&f).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".into(); f.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    Ok(if parts.is_empty() {
        ".".into()
    } else {
        parts.join("/")
    })
}

/// A `::: KIND` block.
struct Block {
    kind: String,
    keys: Vec<(String, String)>,
}

impl Block {
    fn get(&self, key: &str) -> Option<&str> {
        self.keys
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    fn all(&self, key: &str) -> Vec<&str> {
        self.keys
            .iter()
            .filter(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
            .collect()
    }

    fn require(&self, key: &str) -> Result<&str, String> {
        self.get(key)
            .ok_or_else(|| format!("`::: {}` needs `{key}:`", self.kind))
    }

    /// A `|`-separated list (empty if the key is absent).
    fn list(&self, key: &str) -> Vec<String> {
        self.get(key).map_or_else(Vec::new, |v| {
            v.split('|').map(|x| x.trim().to_string()).collect()
        })
    }

    fn check_keys(&self, allowed: &[&str]) -> Result<(), String> {
        match self
            .keys
            .iter()
            .find(|(k, _)| !allowed.contains(&k.as_str()))
        {
            Some((k, _)) => Err(format!(
                "`::: {}` has no key `{k}` (keys: {})",
                self.kind,
                allowed.join(", ")
            )),
            None => Ok(()),
        }
    }
}

/// The run that the tables of a section come from.
struct Run {
    date: String,
    commits: String,
}

struct Generator {
    results: PathBuf,
    link: String,
    /// The results files named on the page so far (relative paths).
    named: BTreeSet<String>,
}

/// Collapses runs of white space and drops shell line continuations, so
/// that a command compares equal however its lines are broken.
fn normalize(s: &str) -> String {
    s.replace("\\\n", " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The fenced code blocks of a Markdown text: (opening fence line, content).
fn code_blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut open: Option<(String, Vec<&str>)> = None;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            match open.take() {
                Some((fence, body)) => out.push((fence, body.join("\n"))),
                None => open = Some((line.trim().to_string(), Vec::new())),
            }
        } else if let Some((_, body)) = open.as_mut() {
            body.push(line);
        }
    }
    out
}

/// One Markdown table: header, alignment row, rows of cells.
struct Table {
    header: Vec<String>,
    align: Vec<String>,
    rows: Vec<Vec<String>>,
}

fn cells_of(line: &str) -> Vec<String> {
    let t = line.trim();
    let t = t.strip_prefix('|').unwrap_or(t);
    let t = t.strip_suffix('|').unwrap_or(t);
    t.split('|').map(|c| c.trim().to_string()).collect()
}

fn table_line(cells: &[String]) -> String {
    format!("| {} |", cells.join(" | "))
}

impl Table {
    fn render(&self) -> String {
        let mut lines = vec![table_line(&self.header), table_line(&self.align)];
        lines.extend(self.rows.iter().map(|r| table_line(r)));
        lines.join("\n")
    }
}

/// The level and text of a Markdown heading line.
fn heading(line: &str) -> Option<(usize, &str)> {
    let level = line.chars().take_while(|&c| c == '#').count();
    let rest = &line[level..];
    (level > 0 && rest.starts_with(' ')).then(|| (level, rest.trim()))
}

/// The tables under the heading `under` (up to the next heading of the same
/// or a higher level), outside code blocks.
fn tables_under(text: &str, under: &str) -> Result<Vec<Table>, String> {
    let mut in_code = false;
    let mut level = None;
    let mut found = 0;
    let mut tables = Vec::new();
    let mut current: Vec<&str> = Vec::new();
    let flush = |current: &mut Vec<&str>, tables: &mut Vec<Table>| {
        if current.len() >= 2 {
            tables.push(Table {
                header: cells_of(current[0]),
                align: cells_of(current[1]),
                rows: current[2..].iter().map(|l| cells_of(l)).collect(),
            });
        }
        current.clear();
    };
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        if let Some((l, t)) = heading(line) {
            if t == under {
                found += 1;
                flush(&mut current, &mut tables);
                level = Some(l);
                continue;
            }
            if level.is_some_and(|lv| l <= lv) {
                flush(&mut current, &mut tables);
                level = None;
            }
        }
        if level.is_none() {
            continue;
        }
        if line.trim_start().starts_with('|') {
            current.push(line);
        } else {
            flush(&mut current, &mut tables);
        }
    }
    flush(&mut current, &mut tables);
    match found {
        0 => Err(format!("no heading {under:?}")),
        1 => Ok(tables),
        n => Err(format!("{n} headings {under:?}: name one that is unique")),
    }
}

impl Generator {
    fn read(&self, rel: &str) -> Result<String, String> {
        fs::read_to_string(self.results.join(rel)).map_err(|e| format!("results file {rel}: {e}"))
    }

    fn file_link(&mut self, rel: &str) -> String {
        self.named.insert(rel.to_string());
        format!("[`{rel}`]({}/{rel})", self.link)
    }

    /// One source file, its blocks replaced and its links checked.
    fn expand(&mut self, source: &str, text: &str) -> Result<String, String> {
        let mut out = String::new();
        let mut run: Option<Run> = None;
        let mut lines = text.lines().enumerate();
        while let Some((i, line)) = lines.next() {
            let at = |msg: String| format!("{source}:{}: {msg}", i + 1);
            if let Some(kind) = line.strip_prefix(":::").map(str::trim) {
                if kind.is_empty() {
                    return Err(at("`:::` closes no block".into()));
                }
                let mut keys = Vec::new();
                loop {
                    let Some((_, l)) = lines.next() else {
                        return Err(at(format!("`::: {kind}` has no closing `:::`")));
                    };
                    if l.trim() == ":::" {
                        break;
                    }
                    let (k, v) = l
                        .split_once(':')
                        .ok_or_else(|| at(format!("expected `key: value`, found {l:?}")))?;
                    keys.push((k.trim().to_string(), v.trim().to_string()));
                }
                let block = Block {
                    kind: kind.to_string(),
                    keys,
                };
                let text = match kind {
                    "run" => self.run(&block).map(|(text, r)| {
                        run = Some(r);
                        text
                    }),
                    "table" => self.table(&block, run.as_ref()),
                    "cells" => self.cells(&block, run.as_ref()),
                    "machine" => self.machine(&block),
                    k => Err(format!("unknown block `::: {k}`")),
                }
                .map_err(at)?;
                out.push_str(&text);
                out.push('\n');
            } else {
                if line.starts_with("## ") {
                    run = None;
                }
                out.push_str(&self.links(line).map_err(at)?);
                out.push('\n');
            }
        }
        Ok(out)
    }

    /// `{results}` replaced; every `({results}/FILE)` names an existing file.
    fn links(&mut self, line: &str) -> Result<String, String> {
        const MARK: &str = "({results}/";
        let mut rest = line;
        while let Some(i) = rest.find(MARK) {
            rest = &rest[i + MARK.len()..];
            let end = rest.find([')', '#']).unwrap_or(rest.len());
            let rel = &rest[..end];
            if !self.results.join(rel).exists() {
                return Err(format!("the link names {rel}, not in the results folder"));
            }
            self.named.insert(rel.to_string());
        }
        Ok(line.replace("{results}", &self.link))
    }

    fn run(&mut self, b: &Block) -> Result<(String, Run), String> {
        b.check_keys(&[
            "file",
            "see",
            "date",
            "commit",
            "command",
            "options-from",
            "conditions",
        ])?;
        let file = b.require("file")?;
        let text = self.read(file)?;
        let date = b.require("date")?;
        if !text.contains(date) {
            return Err(format!("{file} does not record the date {date}"));
        }
        let commit = b.require("commit")?;
        let commits: Vec<&str> = if commit == "not recorded" {
            Vec::new()
        } else {
            commit.split_whitespace().collect()
        };
        for c in &commits {
            if !text.contains(c) {
                return Err(format!("{file} does not record the commit {c}"));
            }
        }
        let binary = match commits.as_slice() {
            [] => "the binary's commit not recorded in the results".to_string(),
            [c] => format!("binary of commit {c}"),
            [init @ .., last] => format!("binaries of commits {} and {last}", init.join(", ")),
        };
        let mut head = format!("**Run:** {date}, {binary}");
        if let Some(c) = b.get("conditions") {
            head.push_str(&format!("; {c}"));
        }
        let mut files = vec![self.file_link(file)];
        for f in b.list("see") {
            self.read(&f)?;
            files.push(self.file_link(&f));
        }
        head.push_str(&format!(". Results: {}.", files.join(", ")));
        let mut parts = vec![head];
        let normal = normalize(&text);
        for cmd in b.all("command") {
            if let Some(n) = cmd.strip_prefix("block ") {
                let n: usize = n
                    .trim()
                    .parse()
                    .map_err(|_| format!("`command: block N` needs a number, found {n:?}"))?;
                let blocks = code_blocks(&text);
                let (fence, body) = n
                    .checked_sub(1)
                    .and_then(|i| blocks.get(i))
                    .ok_or_else(|| format!("{file} has {} code blocks, not {n}", blocks.len()))?;
                parts.push(format!("{fence}\n{body}\n```"));
            } else {
                if !normal.contains(&normalize(cmd)) {
                    return Err(format!("{file} does not record the command {cmd:?}"));
                }
                parts.push(format!("```sh\n{cmd}\n```"));
            }
        }
        if let Some(json) = b.get("options-from") {
            let run = self.bench_json(json)?;
            let mut opts = String::new();
            if run.quick {
                opts.push_str("--quick ");
            }
            opts.push_str(&format!(
                "--methods {} --workload {} --budget {}",
                run.methods.join(","),
                run.workloads.join(" "),
                run.budget_seconds
            ));
            if run.cells.iter().any(|c| c.outcome.build_seconds.is_some()) {
                opts.push_str(" --build-time");
            }
            parts.push(format!(
                "The options that {} records:",
                self.file_link(json)
            ));
            parts.push(format!("```sh\n{opts}\n```"));
        }
        let run = Run {
            date: date.to_string(),
            commits: match commits.as_slice() {
                [] => "commit not recorded".into(),
                [c] => format!("commit {c}"),
                [init @ .., last] => format!("commits {} and {last}", init.join(", ")),
            },
        };
        Ok((parts.join("\n\n"), run))
    }

    /// The line under a table: its results file and its run.
    fn source_line(
        &mut self,
        what: &str,
        file: &str,
        detail: &str,
        run: Option<&Run>,
    ) -> Result<String, String> {
        let run = run.ok_or("a table needs a `::: run` before it in its section")?;
        Ok(format!(
            "*{what} {}{detail}; run of {}, {}.*",
            self.file_link(file),
            run.date,
            run.commits
        ))
    }

    fn table(&mut self, b: &Block, run: Option<&Run>) -> Result<String, String> {
        b.check_keys(&["file", "under", "index", "rows", "columns", "details"])?;
        let file = b.require("file")?;
        let under = b.require("under")?;
        let text = self.read(file)?;
        let index: usize = match b.get("index") {
            None => 1,
            Some(n) => n
                .parse()
                .map_err(|_| format!("`index:` needs a number, found {n:?}"))?,
        };
        let mut tables = tables_under(&text, under).map_err(|e| format!("{file}: {e}"))?;
        if index == 0 || index > tables.len() {
            return Err(format!(
                "{file}: {} tables under {under:?}, not {index}",
                tables.len()
            ));
        }
        let mut table = tables.swap_remove(index - 1);
        let rows = b.list("rows");
        if !rows.is_empty() {
            // a row whose first cell is empty goes with the row before it
            let mut groups: Vec<(String, Vec<Vec<String>>)> = Vec::new();
            for r in table.rows {
                let first = r.first().cloned().unwrap_or_default();
                match groups.last_mut() {
                    Some((_, g)) if first.is_empty() => g.push(r),
                    _ => groups.push((first, vec![r])),
                }
            }
            let mut picked = Vec::new();
            for name in &rows {
                let before = picked.len();
                for (_, g) in groups.iter().filter(|(f, _)| f == name) {
                    picked.extend(g.iter().cloned());
                }
                if picked.len() == before {
                    return Err(format!("{file}: no row {name:?} under {under:?}"));
                }
            }
            table.rows = picked;
        }
        let columns = b.list("columns");
        if !columns.is_empty() {
            let idx: Vec<usize> = columns
                .iter()
                .map(|c| {
                    table
                        .header
                        .iter()
                        .position(|h| h == c)
                        .ok_or_else(|| format!("{file}: no column {c:?} under {under:?}"))
                })
                .collect::<Result<_, _>>()?;
            let pick = |r: &[String]| -> Vec<String> {
                idx.iter()
                    .map(|&i| r.get(i).cloned().unwrap_or_default())
                    .collect()
            };
            table = Table {
                header: pick(&table.header),
                align: pick(&table.align),
                rows: table.rows.iter().map(|r| pick(r)).collect(),
            };
        }
        let source = self.source_line("From", file, &format!(", “{under}”"), run)?;
        let body = format!("{}\n\n{source}", table.render());
        Ok(match b.get("details") {
            Some(summary) => {
                format!("<details><summary>{summary}</summary>\n\n{body}\n\n</details>")
            }
            None => body,
        })
    }

    fn bench_json(&self, rel: &str) -> Result<BenchRun, String> {
        let (run, _) = report::read_runs(&[self.results.join(rel)])
            .map_err(|e| format!("results file {rel}: {e}"))?;
        Ok(run)
    }

    fn cells(&mut self, b: &Block, run: Option<&Run>) -> Result<String, String> {
        b.check_keys(&["file", "workloads", "methods", "columns"])?;
        let file = b.require("file")?;
        let data = self.bench_json(file)?;
        let mut workloads = b.list("workloads");
        if workloads.is_empty() {
            workloads = data.workloads.clone();
        }
        let mut methods = b.list("methods");
        if methods.is_empty() {
            methods = data.methods.clone();
        }
        let columns = b.list("columns");
        if columns.is_empty() {
            return Err("`::: cells` needs `columns:`".into());
        }
        let mut table = Table {
            header: columns.clone(),
            align: columns
                .iter()
                .map(|c| {
                    if ["workload", "method", "status"].contains(&c.as_str()) {
                        "---".into()
                    } else {
                        "---:".into()
                    }
                })
                .collect(),
            rows: Vec::new(),
        };
        for w in &workloads {
            for m in &methods {
                let cell = data
                    .cell(w, m)
                    .ok_or_else(|| format!("{file} has no cell {w} {m}"))?;
                let row = columns
                    .iter()
                    .map(|c| cell_value(cell, c))
                    .collect::<Result<_, _>>()?;
                table.rows.push(row);
            }
        }
        let source = self.source_line("Computed from", file, "", run)?;
        Ok(format!("{}\n\n{source}", table.render()))
    }

    fn machine(&mut self, b: &Block) -> Result<String, String> {
        b.check_keys(&[])?;
        let mut machines: Vec<(String, Vec<String>)> = Vec::new();
        for rel in self.reports()? {
            let text = self.read(&rel)?;
            let Some(line) = text.lines().find_map(|l| l.strip_prefix("Machine: ")) else {
                continue;
            };
            // "CPU (n logical cores), m GiB memory, linux KERNEL; built with
            // RUSTC (P profile); run on DATE UTC."
            let parts: Vec<&str> = line.split("; ").collect();
            let hardware = parts[0]
                .rsplit_once(", linux ")
                .map_or(parts[0], |(h, _)| h);
            let built = parts
                .get(1)
                .and_then(|p| p.strip_prefix("built with "))
                .unwrap_or("");
            let what = format!("{hardware}, Linux; {built}");
            match machines.iter_mut().find(|(m, _)| *m == what) {
                Some((_, files)) => files.push(rel),
                None => machines.push((what, vec![rel])),
            }
        }
        if machines.is_empty() {
            return Err("no report of the results names its machine".into());
        }
        let lines: Vec<String> = machines
            .iter()
            .map(|(m, files)| {
                let names: Vec<String> = files.iter().map(|f| format!("`{f}`")).collect();
                format!("- {m} (the `Machine:` line of {})", names.join(", "))
            })
            .collect();
        Ok(lines.join("\n"))
    }

    /// The results reports: `.md` files of the results folder and of the
    /// folders in it, the page's sources aside.
    fn reports(&self) -> Result<Vec<String>, String> {
        let list = |dir: &Path| -> Result<Vec<PathBuf>, String> {
            let mut v: Vec<PathBuf> = fs::read_dir(dir)
                .map_err(|e| format!("{}: {e}", dir.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .collect();
            v.sort();
            Ok(v)
        };
        let mut out = Vec::new();
        for p in list(&self.results)? {
            let name = p
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned());
            if p.is_dir() && name != SOURCES {
                for q in list(&p)? {
                    if q.extension().is_some_and(|x| x == "md") {
                        let sub = q
                            .file_name()
                            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
                        out.push(format!("{name}/{sub}"));
                    }
                }
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(name);
            }
        }
        Ok(out)
    }

    fn check_named(&self) -> Result<(), String> {
        let missing: Vec<String> = self
            .reports()?
            .into_iter()
            .filter(|r| !self.named.contains(r))
            .collect();
        if missing.is_empty() {
            Ok(())
        } else {
            Err(format!(
                "results files the page does not name: {} (add them to a section in {SOURCES}/)",
                missing.join(", ")
            ))
        }
    }
}

/// One column of a `::: cells` table for one cell.
fn cell_value(c: &CellResult, column: &str) -> Result<String, String> {
    let o = &c.outcome;
    let ok = o.status == Status::Ok;
    let (events, collisions) = (o.counters.events, o.counters.collisions);
    let per = |x: f64, n: u64| {
        if !ok || n == 0 {
            String::new()
        } else {
            report::format_sig(x / n as f64)
        }
    };
    Ok(match column {
        "workload" => c.workload.clone(),
        "method" => Method::parse(&c.method).map_or_else(|_| c.method.clone(), |m| m.label()),
        "status" => o.status.text(),
        "wall" if ok => report::human_seconds(o.wall_seconds),
        "wall" => o.status.text(),
        "build" => o
            .build_seconds
            .filter(|_| ok)
            .map_or(String::new(), report::human_seconds),
        "events" if ok => events.to_string(),
        "collisions" if ok => collisions.to_string(),
        "events" | "collisions" => String::new(),
        "events / collision" => per(events as f64, collisions),
        "µs / event" => per(o.wall_seconds * 1e6, events),
        "µs / event after build" => match (
            o.counters.ns_per_event_after_build(o.wall_seconds),
            o.build_seconds,
        ) {
            (Some(ns), _) if ok => report::format_sig(ns / 1e3),
            (Some(_), _) => String::new(),
            (None, Some(b)) => per((o.wall_seconds - b) * 1e6, events),
            (None, None) => String::new(),
        },
        "µs / collision" => per(o.wall_seconds * 1e6, collisions),
        "peak RSS (MiB)" => o
            .peak_rss_kib
            .filter(|_| ok)
            .map_or(String::new(), |k| format!("{:.1}", k as f64 / 1024.0)),
        "peak heap (MiB)" => report::peak_heap_mib(o).map_or(String::new(), |m| format!("{m:.1}")),
        "allocs / event" => {
            report::allocations_per_event(o).map_or(String::new(), |x| format!("{x:.1}"))
        }
        other => return Err(format!("`::: cells` has no column {other:?}")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_under_a_heading_stop_at_the_next_heading_of_its_level() {
        let text = "# A\n\n## B\n\n| x | y |\n| --- | ---: |\n| 1 | 2 |\n|  | 3 |\n\n\
                    ### C\n\n| z |\n| --- |\n| 4 |\n\n## D\n\n| w |\n| --- |\n| 5 |\n";
        let t = tables_under(text, "B").expect("found");
        assert_eq!(t.len(), 2);
        assert_eq!(t[0].header, ["x", "y"]);
        assert_eq!(t[0].rows, [vec!["1", "2"], vec!["", "3"]]);
        assert_eq!(t[1].rows, [vec!["4"]]);
        assert!(tables_under(text, "E").is_err());
    }

    #[test]
    fn commands_compare_however_their_lines_are_broken() {
        assert_eq!(normalize("a  b \\\n   c\n"), "a b c");
    }

    #[test]
    fn links_from_the_page_to_the_results() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let page = root.join("../../docs/benchmarks.md");
        assert_eq!(
            link_prefix(&root.join("results"), &page).expect("paths"),
            "../crates/kss-bench/results"
        );
    }

    #[test]
    fn first_difference_names_the_line() {
        assert_eq!(first_difference("a\nb\n", "a\nb\n"), None);
        let d = first_difference("a\nb\n", "a\nc\n").expect("differs");
        assert!(d.starts_with("line 2:"), "{d}");
        let d = first_difference("a\n", "a\nc\n").expect("differs");
        assert!(d.contains("(end of file)"), "{d}");
    }
}
