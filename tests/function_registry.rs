//! The function table is the one place that knows a function: no list of function names
//! elsewhere in `src/` or `tests/` repeats it (a volatile list, a `_xlfn.` list, a list of functions
//! taking ranges …). Such facts are builder methods on the function's `FnSpec` row.

use std::collections::HashSet;
use std::path::Path;

use ncsheet::eval::functions::REGISTRY;

/// A run of this many registered names as string literals, with no `;` between them, is a
/// list of functions.
const LIST: usize = 3;
/// Literals further apart than this many bytes are not one list.
const GAP: usize = 160;

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src/ is readable") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The byte offsets of string literals in `code` whose text is a registered function name.
fn function_literals(code: &str, names: &HashSet<String>) -> Vec<usize> {
    let mut hits = Vec::new();
    let mut rest = code;
    let mut offset = 0;
    while let Some(open) = rest.find('"') {
        let after = &rest[open + 1..];
        let Some(close) = after.find('"') else { break };
        let literal = &after[..close];
        if names.contains(literal) {
            hits.push(offset + open);
        }
        let consumed = open + close + 2;
        offset += consumed;
        rest = &rest[consumed..];
    }
    hits
}

/// Runs of at least [`LIST`] function-name literals, as (first offset, names) pairs.
fn lists(code: &str, names: &HashSet<String>) -> Vec<(usize, usize)> {
    let hits = function_literals(code, names);
    let mut found = Vec::new();
    let mut start = 0;
    for i in 1..=hits.len() {
        let joined = i < hits.len() && hits[i] - hits[i - 1] <= GAP && !code[hits[i - 1]..hits[i]].contains(';');
        if !joined {
            if i - start >= LIST {
                found.push((hits[start], i - start));
            }
            start = i;
        }
    }
    found
}

/// Lists of names in tests that are no fact about a function the registry could hold, each
/// with why.
const ALLOWED: &[(&str, &str)] = &[
    ("tests/xlsx_libreoffice.rs", "the functions LibreOffice lacks: a fact about another program"),
    ("tests/proptest_parser.rs", "a sample of names to build random formulas from"),
    ("tests/geometry_chamfer_head.rs", "the functions under test, each checked against DOMAIN.md's table"),
    (
        "tests/common/excel_oracle.rs",
        "what the harness's one-sheet environment cannot answer (other cells' formulas, the sheet list)",
    ),
];

/// Names that are also the language's words: TRUE and FALSE are functions and booleans.
fn is_also_a_word(name: &str) -> bool {
    matches!(name, "TRUE" | "FALSE") || name.starts_with("VBA.")
}

#[test]
fn no_list_of_function_names_outside_the_registry() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let registry_dir = root.join("src/eval/functions");
    let names: HashSet<String> = REGISTRY.iter().map(|f| f.name.to_string()).filter(|n| !is_also_a_word(n)).collect();
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("tests"), &mut files);
    let mut offenders = Vec::new();
    // The symbolic derivative's rules are code per function (d/du SIN(u) = COS(u)), not
    // facts about a function that another table could repeat.
    let derivative_rules = root.join("src/eval/diff.rs");
    let allowed = |f: &Path| ALLOWED.iter().any(|(path, _)| f == root.join(path));
    for file in files.iter().filter(|f| !f.starts_with(&registry_dir) && **f != derivative_rules && !allowed(f)) {
        let text = std::fs::read_to_string(file).expect("a source file is readable");
        // Unit tests may stand in for the registry (the formula layer cannot see it).
        let code = text.split("#[cfg(test)]").next().unwrap_or(&text);
        for (offset, count) in lists(code, &names) {
            let line = code[..offset].lines().count();
            offenders.push(format!("{}:{line}: {count} function names", file.strip_prefix(root).unwrap().display()));
        }
    }
    assert!(offenders.is_empty(), "function names listed outside the registry:\n{}", offenders.join("\n"));
}

#[test]
fn the_detector_finds_a_list_and_ignores_scattered_names() {
    let names: HashSet<String> = ["NOW", "TODAY", "RAND", "SUM"].iter().map(|s| s.to_string()).collect();
    assert_eq!(lists(r#"const V: [&str; 3] = ["NOW", "TODAY", "RAND"];"#, &names).len(), 1);
    assert_eq!(lists(r#"match n { "NOW" | "TODAY" | "SUM" => 1, _ => 0 }"#, &names).len(), 1);
    assert!(lists(r#"let a = "NOW"; let b = "TODAY"; let c = "SUM";"#, &names).is_empty());
    assert!(lists(r#"f("NOW", "Sheet1", "x")"#, &names).is_empty());
}

#[test]
fn the_registry_holds_the_facts_the_side_lists_held() {
    use ncsheet::eval::functions::{find, spec, FilePrefix, Outside};
    let f = |name: &str| spec(find(name).unwrap_or_else(|| panic!("{name} is registered")));
    // Volatile: Excel recomputes them at every recalculation.
    assert!(f("NOW").volatile && f("TODAY").volatile && f("OFFSET").volatile && f("INDIRECT").volatile);
    assert!(!f("SUM").volatile);
    // Recomputed at every edit: Excel's volatile functions (Microsoft's "Recalculation"
    // page: NOW, TODAY, RAND, RANDBETWEEN, OFFSET, INDIRECT, INFO, CELL), but OFFSET, whose
    // reach is a graph edge here; INFO and CELL are not volatile here (they read nothing that
    // changes within a session but the cells they are given).
    let mut every_edit: Vec<&str> =
        ncsheet::eval::functions::REGISTRY.iter().filter(|s| s.every_edit).map(|s| s.name).collect();
    every_edit.sort_unstable();
    assert_eq!(every_edit, ["INDIRECT", "NOW", "RAND", "RANDARRAY", "RANDBETWEEN", "TODAY"]);
    assert!(f("OFFSET").volatile && !f("OFFSET").every_edit);
    for s in ncsheet::eval::functions::REGISTRY.iter() {
        assert!(!s.every_edit || s.volatile, "{} is recomputed at every edit but not volatile", s.name);
    }
    // Excel's cached values of NOW and TODAY depend on the moment, of RAND on chance, of INFO
    // on the computer (Microsoft's pages of each).
    assert_eq!((f("NOW").reads, f("TODAY").reads), (Outside::Clock, Outside::Clock));
    assert_eq!((f("RAND").reads, f("RANDARRAY").reads), (Outside::Chance, Outside::Chance));
    assert_eq!(
        (f("INFO").reads, f("SUM").reads, f("OFFSET").reads),
        (Outside::Host, Outside::Nothing, Outside::Nothing)
    );
    // Excel's file spelling (MS-XLSX 2.2.2, future functions).
    assert_eq!(f("XLOOKUP").file_prefix, FilePrefix::Future);
    assert_eq!(f("CONCAT").file_prefix, FilePrefix::Future);
    assert_eq!(f("ISO.CEILING").file_prefix, FilePrefix::None);
    assert_eq!(f("CONCATENATE").file_prefix, FilePrefix::None);
    assert!(f("SEQUENCE").dynamic && !f("SUM").dynamic);
    assert!(f("LAMBDA").reads_trees);
    assert!(f("SUMPRODUCT").array_args.contains(3) && f("INDEX").array_args.contains(0));
    assert!(f("SUMIF").range_args.contains(0) && !f("SUMIF").range_args.contains(1));
}
