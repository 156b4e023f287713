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

/// Rust source with its string literals read as Rust reads them: each literal's offset and
/// text, and the source with every literal's text and every comment blanked (offsets stay
/// the source's), where a `;` is code.
struct Scanned<'a> {
    literals: Vec<(usize, &'a str)>,
    code: Vec<u8>,
}

/// Scans `source` for string literals: plain (`"…"` with `\"` escapes), raw (`r#"…"#`, any
/// number of `#`), byte and C strings (`b"…"`, `br"…"`, `c"…"`). A `"` inside a char literal
/// (`'"'`) or a comment (`//`, `/* */` nested) starts none; a lifetime (`'a`) is no char.
fn scan(source: &str) -> Scanned<'_> {
    let bytes = source.as_bytes();
    let mut scanned = Scanned { literals: Vec::new(), code: bytes.to_vec() };
    let blank = |code: &mut Vec<u8>, from: usize, to: usize| code[from..to].iter_mut().for_each(|b| *b = b' ');
    let mut i = 0;
    while i < bytes.len() {
        let rest = &bytes[i..];
        let in_ident = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if rest.starts_with(b"//") {
            let end = rest.iter().position(|&b| b == b'\n').map_or(bytes.len(), |n| i + n);
            blank(&mut scanned.code, i, end);
            i = end;
        } else if rest.starts_with(b"/*") {
            let end = block_comment_end(bytes, i);
            blank(&mut scanned.code, i, end);
            i = end;
        } else if let Some((open, hashes)) = raw_string_start(bytes, i, in_ident) {
            let close = format!("\"{}", "#".repeat(hashes));
            let end = source[open..].find(&close).map_or(bytes.len(), |n| open + n);
            scanned.literals.push((i, &source[open..end]));
            blank(&mut scanned.code, open, end);
            i = (end + close.len()).min(bytes.len());
        } else if bytes[i] == b'"' {
            let mut end = i + 1;
            while end < bytes.len() && bytes[end] != b'"' {
                end += if bytes[end] == b'\\' { 2 } else { 1 };
            }
            let end = end.min(bytes.len());
            scanned.literals.push((i, &source[i + 1..end]));
            blank(&mut scanned.code, i + 1, end);
            i = end + 1;
        } else if bytes[i] == b'\'' {
            i = after_char_literal(source, i);
        } else {
            i += 1;
        }
    }
    scanned
}

/// The end of the (nested) block comment opening at `i`.
fn block_comment_end(bytes: &[u8], i: usize) -> usize {
    let (mut depth, mut j) = (0, i);
    while j < bytes.len() {
        if bytes[j..].starts_with(b"/*") {
            depth += 1;
            j += 2;
        } else if bytes[j..].starts_with(b"*/") {
            depth -= 1;
            j += 2;
            if depth == 0 {
                return j;
            }
        } else {
            j += 1;
        }
    }
    bytes.len()
}

/// Where the text of a raw string starting at `i` (`r"`, `r#"`, `br##"` …) begins, and its
/// number of `#`; `None` when none starts there. `in_ident`: `i` continues an identifier
/// (`for"` is no raw string).
fn raw_string_start(bytes: &[u8], i: usize, in_ident: bool) -> Option<(usize, usize)> {
    let prefixed = matches!(bytes[i], b'b' | b'c') && bytes.get(i + 1) == Some(&b'r');
    if in_ident || !(bytes[i] == b'r' || prefixed) {
        return None;
    }
    let r = if prefixed { i + 1 } else { i };
    let hashes = bytes[r + 1..].iter().take_while(|&&b| b == b'#').count();
    (bytes.get(r + 1 + hashes) == Some(&b'"')).then_some((r + 2 + hashes, hashes))
}

/// Past the char literal opening at `i` (`'x'`, `'"'`, `'\''`, `'\u{1F600}'`), or just past
/// the `'` of a lifetime or a label (`'a`).
fn after_char_literal(source: &str, i: usize) -> usize {
    let rest = &source[i + 1..];
    if let Some(escaped) = rest.strip_prefix('\\') {
        // The escaped character, then on to the closing quote (`\u{…}` holds none).
        let skip = escaped.chars().next().map_or(0, char::len_utf8);
        return escaped[skip..].find('\'').map_or(source.len(), |n| i + 2 + skip + n + 1);
    }
    match rest.chars().next() {
        Some(c) if rest[c.len_utf8()..].starts_with('\'') => i + 1 + c.len_utf8() + 1,
        _ => i + 1,
    }
}

/// Runs of at least [`LIST`] function-name literals, as (first offset, names) pairs: near
/// each other, with no `;` in the code between them (one inside a literal ends nothing).
fn lists(source: &str, names: &HashSet<String>) -> Vec<(usize, usize)> {
    let scanned = scan(source);
    let hits: Vec<usize> =
        scanned.literals.iter().filter(|(_, text)| names.contains(*text)).map(|(offset, _)| *offset).collect();
    let mut found = Vec::new();
    let mut start = 0;
    for i in 1..=hits.len() {
        let joined =
            i < hits.len() && hits[i] - hits[i - 1] <= GAP && !scanned.code[hits[i - 1]..hits[i]].contains(&b';');
        if !joined {
            if i - start >= LIST {
                found.push((hits[start], i - start));
            }
            start = i;
        }
    }
    found
}

/// Lists of names that are no fact about a function the registry holds today, each with why.
const ALLOWED: &[(&str, &str)] = &[
    ("tests/xlsx_libreoffice.rs", "the functions LibreOffice lacks: a fact about another program"),
    ("tests/proptest_parser.rs", "a sample of names to build random formulas from"),
    ("tests/function_registry.rs", "the registry's facts asserted one by one, and this detector's fixtures"),
    ("tests/geometry_chamfer_head.rs", "the functions under test, each checked against docs/domain.md's table"),
    (
        "tests/common/excel_oracle.rs",
        "what the harness's one-sheet environment cannot answer (other cells' formulas, the sheet list)",
    ),
    (
        "crates/ncsheet/src/nc/read/parameters.rs",
        "LinuxCNC's expression operators and functions (MOD, AND, ABS, ROUND…): a fact about another program",
    ),
    ("tests/nc_readback.rs", "random LinuxCNC expressions built from its operators and functions"),
    (
        "crates/ncsheet/src/io/legacy/ods.rs",
        "the names LibreOffice writes for some of Excel's functions: a fact about another program",
    ),
];

/// Names that are also the language's words: TRUE and FALSE are functions and booleans.
fn is_also_a_word(name: &str) -> bool {
    matches!(name, "TRUE" | "FALSE") || name.starts_with("VBA.")
}

#[test]
fn no_list_of_function_names_outside_the_registry() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let registry_dir = root.join("crates/ncsheet/src/eval/functions");
    let names: HashSet<String> = REGISTRY.iter().map(|f| f.name.to_string()).filter(|n| !is_also_a_word(n)).collect();
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("crates"), &mut files);
    rust_files(&root.join("tests"), &mut files);
    let mut offenders = Vec::new();
    // The symbolic derivative's rules are code per function (d/du SIN(u) = COS(u)), not
    // facts about a function that another table could repeat.
    let derivative_rules = root.join("crates/ncsheet/src/eval/diff.rs");
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
fn the_detector_reads_rust_strings_as_rust_does() {
    let names: HashSet<String> = ["NOW", "TODAY", "RAND", "SUM"].iter().map(|s| s.to_string()).collect();
    let list = r#"const V: [&str; 3] = ["NOW", "TODAY", "RAND"];"#;
    // Whatever stands before the list, its three names are found: an escaped quote, a raw
    // string holding quotes, a quote as a char, a lifetime, a comment with a lone quote.
    for before in [
        r#"let s = "say \"hi\" \\"; "#,
        r##"let r = r#"a "quoted" b"#; "##,
        r###"let r = br##"a "# b"##; "###,
        r#"let r = r"a \"; "#,
        r#"let q = '"'; let e = '\''; "#,
        r#"fn f<'a>(x: &'a str) -> char { '\u{22}' } "#,
        "// a \"quote\" and a lone \" here\n",
        "/* \" /* nested \" */ \" */ ",
    ] {
        assert_eq!(lists(&format!("{before}{list}"), &names).len(), 1, "after {before:?}");
    }
    // Names inside one literal (a formula's text) or in a comment are no list.
    assert!(lists(r##"let f = r#"=SUM("NOW", "TODAY", "RAND")"#;"##, &names).is_empty());
    assert!(lists(r#"let f = "\"NOW\", \"TODAY\", \"RAND\"";"#, &names).is_empty());
    assert!(lists("// \"NOW\", \"TODAY\", \"RAND\"\nlet x = 1;", &names).is_empty());
    // A `;` inside a literal between the names does not cut the list.
    assert_eq!(lists(r#"["NOW", ";", "TODAY", "RAND"]"#, &names).len(), 1);
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
    // reach is a graph edge here, and CELL, which reads nothing that changes within a session
    // but the cells it is given. (VBA's own Rnd and Timer, reached only from macros, are
    // not Excel's sheet functions.)
    let mut every_edit: Vec<&str> = ncsheet::eval::functions::REGISTRY
        .iter()
        .filter(|s| s.every_edit && !s.name.starts_with("VBA."))
        .map(|s| s.name)
        .collect();
    every_edit.sort_unstable();
    assert_eq!(every_edit, ["INDIRECT", "INFO", "NOW", "RAND", "RANDARRAY", "RANDBETWEEN", "TODAY"]);
    assert!(f("OFFSET").volatile && !f("OFFSET").every_edit);
    for s in ncsheet::eval::functions::REGISTRY.iter() {
        assert!(!s.every_edit || s.volatile, "{} is recomputed at every edit but not volatile", s.name);
    }
    // Microsoft's "Excel Recalculation" lists INFO among the volatile functions (its
    // answers, "numfile", "recalc", "memavail" …, change with no cell changing).
    assert!(f("INFO").volatile);
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
