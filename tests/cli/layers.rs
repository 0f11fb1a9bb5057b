//! The library's modules read as the data flows: parameters and loop description,
//! discretization, polynomial, stability tests, boundaries and `alpha_max`, robust sets and
//! certificates, scenes, export. These tests read the library's sources and check the
//! `crate::` imports between its top-level modules.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's sources.
fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/stabound/src")
}

/// The code of file `f`: the part before its unit tests, without comments (doc comments'
/// links and examples are no imports).
fn code(f: &Path) -> String {
    let text = std::fs::read_to_string(f).unwrap();
    let code = text.split("#[cfg(test)]").next().unwrap();
    code.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The names `code` imports from the crate's root: `x` of every `crate::x` and each
/// first name of a group `crate::{x::.., y}` (over several lines too).
fn crate_names(code: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + 7..];
        let Some(group) = rest.strip_prefix('{') else {
            out.insert(ident(rest));
            continue;
        };
        // the group's items at depth 1, split at its commas
        let (mut depth, mut start) = (1, 0);
        for (k, c) in group.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 1 => {
                    out.insert(ident(&group[start..k]));
                    break;
                }
                '}' => depth -= 1,
                ',' if depth == 1 => {
                    out.insert(ident(&group[start..k]));
                    start = k + 1;
                }
                _ => {}
            }
        }
    }
    out.remove("");
    out
}

/// The modules (or the root's re-exports, such as `Error`) that the library's files
/// `files` import (`crate::name`), outside comments and unit tests.
fn names(files: &[PathBuf]) -> BTreeSet<String> {
    files.iter().flat_map(|f| crate_names(&code(f))).collect()
}

/// Every `.rs` file under `dir`.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(files_under(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out.sort();
    out
}

/// The library's top-level modules (a file `x.rs` or a directory `x/` of its sources, the
/// root `lib.rs` aside) with their files.
fn top_level_modules() -> BTreeMap<String, Vec<PathBuf>> {
    let mut out: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
    for e in std::fs::read_dir(src()).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_stem().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            out.entry(name).or_default().extend(files_under(&p));
        } else if p.extension().is_some_and(|x| x == "rs") && name != "lib" {
            out.entry(name).or_default().push(p);
        }
    }
    out
}

/// The import graph: for each top-level module, the other top-level modules it imports,
/// each with the first of its files that does.
fn graph() -> BTreeMap<String, BTreeMap<String, PathBuf>> {
    let modules = top_level_modules();
    let mut out: BTreeMap<String, BTreeMap<String, PathBuf>> = BTreeMap::new();
    for (m, files) in &modules {
        let edges = out.entry(m.clone()).or_default();
        for f in files {
            for n in crate_names(&code(f)) {
                if n != *m && modules.contains_key(&n) {
                    edges.entry(n).or_insert_with(|| f.clone());
                }
            }
        }
    }
    out
}

/// One cycle of `g` closed by each edge back to a module on the depth-first path.
fn cycles(g: &BTreeMap<String, BTreeMap<String, PathBuf>>) -> Vec<Vec<String>> {
    fn visit(
        g: &BTreeMap<String, BTreeMap<String, PathBuf>>,
        m: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
        out: &mut Vec<Vec<String>>,
    ) {
        path.push(m.to_string());
        for n in g[m].keys() {
            if let Some(k) = path.iter().position(|p| p == n) {
                out.push(path[k..].to_vec());
            } else if !done.contains(n) {
                visit(g, n, path, done, out);
            }
        }
        path.pop();
        done.insert(m.to_string());
    }
    let (mut done, mut out) = (BTreeSet::new(), Vec::new());
    for m in g.keys() {
        if !done.contains(m) {
            visit(g, m, &mut Vec::new(), &mut done, &mut out);
        }
    }
    out
}

/// The import readers see `crate::x` paths and groups over several lines, not comments.
#[test]
fn imports_are_read_from_paths_and_groups() {
    let code = "use crate::a::B;\nuse crate::{\n    c::{D, E},\n    f,\n};\nlet x = crate::g::h();";
    let want: BTreeSet<String> = ["a", "c", "f", "g"].map(String::from).into();
    assert_eq!(crate_names(code), want);
    // the robust searches build on alpha_max: the reader sees that edge
    assert!(
        graph()["robust"].contains_key("amax"),
        "{:?}",
        graph()["robust"]
    );
}

/// No top-level module of the library imports, through others, a module that imports it:
/// each cycle is named with a file making each of its edges.
#[test]
fn top_level_modules_import_no_cycle() {
    let g = graph();
    assert!(g.len() >= 20, "{:?}", g.keys());
    let named: Vec<String> = cycles(&g)
        .iter()
        .map(|c| {
            let edges: Vec<String> = c
                .iter()
                .zip(c.iter().cycle().skip(1))
                .map(|(a, b)| {
                    let f = &g[a][b];
                    format!("{a} -> {b} ({})", f.strip_prefix(src()).unwrap().display())
                })
                .collect();
            edges.join(", ")
        })
        .collect();
    assert!(named.is_empty(), "import cycles:\n{}", named.join("\n"));
}

/// The loop description and the root finder sit below the engines: the element list and
/// the loop import only the parameters, filters and polynomials beneath them (not the
/// quantizers' verdict or the request layer above), and the root finder that the loop
/// curve and the stability tests share imports neither.
#[test]
fn the_loop_and_the_root_finder_import_nothing_above_them() {
    let below = |d: &str, allowed: &[&str]| {
        let above: Vec<String> = names(&files_under(&src().join(d)))
            .into_iter()
            .filter(|m| !allowed.contains(&m.as_str()))
            .collect();
        assert!(above.is_empty(), "{d} imports {above:?}");
    };
    below(
        "elements",
        &[
            "error", "Error", "filter", "params", "poly", "model", "cancel", "elements",
        ],
    );
    below("roots", &["error", "Error", "poly", "cancel", "roots"]);
    let curve = names(&[src().join("curve.rs")]);
    assert!(!curve.contains("stability"), "curve imports {curve:?}");
}

/// A velocity filter is its design (docs/elements.md): outside `filter.rs`, no code of the
/// library, the command line or the Python binding names the second-order low-pass's kind;
/// each takes it by its recursion or by what its design states (its passivity bound, its
/// element's name, its cutoff's reading), so a new filter needs no line there either.
#[test]
fn a_filter_of_a_higher_order_is_named_only_by_its_design() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut read = 0;
    for dir in ["crates/stabound/src", "src", "python/src"] {
        for f in files_under(&root.join(dir)) {
            if f == src().join("filter.rs") {
                continue;
            }
            read += 1;
            assert!(
                !code(&f).contains("FilterKind::Butterworth"),
                "{} names the second-order filter's kind: state what it needs in filter.rs",
                f.display()
            );
        }
    }
    assert!(read >= 100, "{read} files read");
}
