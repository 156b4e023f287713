//! The rules of ARCHITECTURE.md, checked against the source tree (in the spirit of
//! rust-analyzer's tidy tests). Each rule is a function over the files of a tree, so that the
//! checker itself is tested on a small fixture tree that breaks every rule once.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// One source file: its path relative to `src/` (with `/`), its text without comments, and
/// that code without its test module (what ships).
struct Source {
    rel: String,
    code: String,
    raw: String,
    shipped: String,
}

/// What a layer (the first folder under `src/`) may import of ours, from ARCHITECTURE.md's
/// picture: formula → eval → workbook → io, nc → document → cli; geometry stands apart; vba
/// runs on a workbook and fills an nc program.
const LAYERS: &[(&str, &[&str])] = &[
    ("formula", &[]),
    ("geometry", &[]),
    ("eval", &["formula", "geometry"]),
    ("workbook", &["formula", "eval"]),
    ("io", &["formula", "eval", "workbook"]),
    ("nc", &["geometry"]),
    ("vba", &["formula", "eval", "workbook", "nc"]),
    // The one type every front end uses: a workbook opened from bytes, with its VBA functions.
    ("document", &["formula", "eval", "workbook", "io", "nc", "vba"]),
    // The workbench's web server, a front end beside cli on the one document.
    ("server", &["formula", "eval", "workbook", "io", "nc", "vba", "geometry", "document"]),
];

/// Where each rule may be broken, on purpose; each entry says why.
const ALLOWED: &[(&str, &str)] = &[];

fn layer_of(rel: &str) -> &str {
    rel.split('/').next().unwrap_or(rel).trim_end_matches(".rs")
}

fn in_cli(rel: &str) -> bool {
    rel == "main.rs" || rel.starts_with("cli/")
}

/// Removes `//` comments (doc comments included) so that rules read code, not prose about it.
fn strip_comments(text: &str) -> String {
    text.lines()
        .map(|line| match find_comment(line) {
            Some(at) => &line[..at],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The byte where a `//` comment starts, outside string literals.
fn find_comment(line: &str) -> Option<usize> {
    let bytes = line.as_bytes();
    let mut in_string = false;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' if in_string => i += 1,
            b'"' => in_string = !in_string,
            b'/' if !in_string && bytes.get(i + 1) == Some(&b'/') => return Some(i),
            _ => {}
        }
        i += 1;
    }
    None
}

/// The workspace's three crates as one tree, each file named as if under one `src/`: the
/// library's files by their path in `crates/ncsheet/src`, the server's under `server/`, the
/// command line's as they are (`main.rs`, `cli/`).
fn read_workspace(root: &Path) -> Vec<Source> {
    let mut files = read_tree(&root.join("crates/ncsheet/src"), "");
    files.extend(read_tree(&root.join("crates/ncsheet-server/src"), "server/"));
    files.extend(read_tree(&root.join("src"), ""));
    files
}

fn read_tree(src: &Path, prefix: &str) -> Vec<Source> {
    let mut files = Vec::new();
    collect_rs(src, &mut files);
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let rel = path.strip_prefix(src).unwrap().to_string_lossy().replace('\\', "/");
            let rel = format!("{prefix}{rel}");
            let raw = fs::read_to_string(&path).unwrap();
            let code = strip_comments(&raw);
            let shipped = code.split("#[cfg(test)]").next().unwrap_or("").to_string();
            Source { rel, code, raw, shipped }
        })
        .collect()
}

fn collect_rs(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect_rs(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `println!`, `eprintln!`, `print!` and `eprint!` only in cli: lower layers return what
/// they have to say.
fn prints_outside_cli(files: &[Source]) -> Vec<String> {
    let macros = ["println!", "eprintln!", "print!(", "eprint!(", "dbg!("];
    files
        .iter()
        .filter(|f| !in_cli(&f.rel) && !f.rel.ends_with("testing.rs"))
        .filter(|f| macros.iter().any(|m| f.code.contains(m)))
        .map(|f| format!("{}: prints (only cli prints)", f.rel))
        .collect()
}

/// `std::fs` only in io and cli (a unit test may set up its own files).
fn files_touched_outside_io(files: &[Source]) -> Vec<String> {
    files
        .iter()
        .filter(|f| !in_cli(&f.rel) && layer_of(&f.rel) != "io")
        .filter(|f| f.shipped.contains("std::fs") || f.shipped.contains(" fs::"))
        .map(|f| format!("{}: uses std::fs (only io and cli touch files)", f.rel))
        .collect()
}

/// `fs::rename` only in `io/atomic.rs`: every write is the one atomic write.
fn renames_outside_atomic(files: &[Source]) -> Vec<String> {
    files
        .iter()
        .filter(|f| f.rel != "io/atomic.rs")
        .filter(|f| f.shipped.contains("fs::rename") || f.shipped.contains("fs::write("))
        .map(|f| format!("{}: writes or renames a file itself (only io/atomic.rs does)", f.rel))
        .collect()
}

/// The layers of ours a file imports, by `crate::LAYER` paths.
fn imported_layers(code: &str) -> BTreeSet<&str> {
    let mut found = BTreeSet::new();
    for (at, _) in code.match_indices("crate::") {
        let before = code[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        let rest = &code[at + "crate::".len()..];
        let end = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
        found.insert(&rest[..end]);
    }
    for (at, _) in code.match_indices("use crate::{") {
        let rest = &code[at + "use crate::{".len()..];
        let close = rest.find("};").unwrap_or(rest.len());
        for item in rest[..close].split(',') {
            let name = item.trim().split("::").next().unwrap_or("").trim();
            if !name.is_empty() {
                found.insert(name);
            }
        }
    }
    found
}

/// No layer imports one after it (or geometry anything of ours).
fn upward_imports(files: &[Source]) -> Vec<String> {
    let mut out = Vec::new();
    for f in files.iter().filter(|f| !in_cli(&f.rel)) {
        let layer = layer_of(&f.rel);
        let Some((_, allowed)) = LAYERS.iter().find(|(l, _)| *l == layer) else {
            continue;
        };
        for used in imported_layers(&f.code) {
            let known = LAYERS.iter().any(|(l, _)| *l == used);
            if known && used != layer && !allowed.contains(&used) {
                out.push(format!("{}: imports crate::{used} ({layer} may use only {allowed:?})", f.rel));
            }
        }
    }
    out
}

/// Every source file is named in ARCHITECTURE.md, in the section of its layer (`### `crates/ncsheet/src/nc/``),
/// so that `cam.rs` of nc does not pass for `cam.rs` of geometry: a file by its name, a
/// folder's `mod.rs` by its folder (`functions/`) or as `folder/mod.rs`.
fn unmapped_files(files: &[Source], map: &str) -> Vec<String> {
    files
        .iter()
        .filter(|f| !mentioned(&f.rel, section_of(map, &f.rel)))
        .map(|f| format!("{}: not named in ARCHITECTURE.md's section of its layer", f.rel))
        .collect()
}

/// The text of the map's `### ` section whose heading names the file's layer folder
/// (`crates/ncsheet/src/nc/`); the whole map for the crate roots, nothing for a layer without a section.
fn section_of<'a>(map: &'a str, rel: &str) -> &'a str {
    if !rel.contains('/') {
        return map;
    }
    let heading = folder_of(rel);
    let Some(start) = map.lines().position(|l| l.starts_with("### ") && l.contains(&heading)) else {
        return "";
    };
    let offset = |line: usize| map.lines().take(line).map(|l| l.len() + 1).sum::<usize>();
    let end = map.lines().skip(start + 1).position(|l| l.starts_with("## ") || l.starts_with("### "));
    let from = offset(start);
    let to = end.map_or(map.len(), |e| offset(start + 1 + e)).min(map.len());
    &map[from..to]
}

/// The folder a file's layer heads in the map, as the workspace holds it.
fn folder_of(rel: &str) -> String {
    match layer_of(rel) {
        "cli" | "main" => "`src/cli/`".to_string(),
        "server" => "`crates/ncsheet-server/src/`".to_string(),
        layer => format!("`crates/ncsheet/src/{layer}/`"),
    }
}

fn mentioned(rel: &str, map: &str) -> bool {
    let mut parts: Vec<&str> = rel.split('/').collect();
    let file = parts.pop().unwrap_or(rel);
    match (file, parts.last()) {
        ("mod.rs" | "lib.rs" | "main.rs", None) => map.contains(&format!("src/{file}")) || file == "mod.rs",
        ("mod.rs", Some(dir)) => map.contains(&format!("{dir}/")),
        _ => contains_word(map, file),
    }
}

fn contains_word(text: &str, word: &str) -> bool {
    text.match_indices(word).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let after = text[at + word.len()..].chars().next();
        before.is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
            && after.is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
    })
}

/// The dialect names are spelled once, in `nc/dialect/`; every list of them (help text
/// included) is derived from `dialect::all()`. A list is a line naming three dialects, or an
/// enum with variants named after two.
fn dialect_lists_outside_nc(files: &[Source]) -> Vec<String> {
    let names = ["linuxcnc", "sinumerik", "heidenhain", "nc31"];
    let mut out = Vec::new();
    for f in files.iter().filter(|f| !f.rel.starts_with("nc/dialect/")) {
        let listing = f.raw.lines().any(|line| {
            let line = line.to_ascii_lowercase();
            names.iter().filter(|n| line.contains(*n)).count() >= 3
        });
        let variants = ["Linuxcnc,", "Sinumerik,", "Heidenhain,", "Nc31,"];
        let as_enum = variants.iter().filter(|v| f.code.contains(*v)).count() >= 2;
        if listing || as_enum {
            out.push(format!("{}: spells a list of dialects (derive it from dialect::all())", f.rel));
        }
    }
    out
}

/// The function library is written against `functions/api.rs`, never against the evaluator
/// itself: only the registry (`functions/mod.rs`) and the API name it.
fn functions_past_the_api(files: &[Source]) -> Vec<String> {
    let library = files.iter().filter(|f| f.rel.starts_with("eval/functions/"));
    library
        .filter(|f| f.rel != "eval/functions/mod.rs" && f.rel != "eval/functions/api.rs")
        .filter(|f| f.code.contains("eval::evaluator") || f.code.contains("super::evaluator"))
        .map(|f| format!("{}: imports the evaluator (use functions::api)", f.rel))
        .collect()
}

/// Files whose shipped code contains `needle` though they are not among `allowed` (paths, or
/// folders ending in `/`), with `why` the rule.
fn only_in(files: &[Source], needle: &str, allowed: &[&str], why: &str) -> Vec<String> {
    files
        .iter()
        .filter(|f| !allowed.iter().any(|a| f.rel == *a || (a.ends_with('/') && f.rel.starts_with(a))))
        .filter(|f| f.shipped.contains(needle))
        .map(|f| format!("{}: {why}", f.rel))
        .collect()
}

/// Precedence lives in one place, the Pratt table of `formula/parse.rs`.
fn pratt_tables_elsewhere(files: &[Source]) -> Vec<String> {
    only_in(files, "PrattParser", &["formula/parse.rs"], "builds a Pratt table (the one is formula/parse.rs's)")
}

/// Only cli exits the process.
fn exits_outside_cli(files: &[Source]) -> Vec<String> {
    only_in(files, "process::exit", &["cli/", "main.rs"], "exits the process (only cli exits)")
}

/// Only cli knows serialisation formats: the core types derive none.
fn serialisation_outside_cli(files: &[Source]) -> Vec<String> {
    only_in(files, "serde", &["cli/", "main.rs", "server/"], "uses serde (only cli and server serialise)")
}

/// Only io/xlsx knows how Excel spells formulas in its files: `_xlfn.` is written there, in the
/// registry's `FilePrefix`, and read (a pasted formula) by the parser.
fn file_spelling_outside_xlsx(files: &[Source]) -> Vec<String> {
    let allowed = ["io/xlsx/", "eval/functions/mod.rs", "formula/parse.rs"];
    only_in(files, "\"_xlfn.", &allowed, "spells Excel's file prefix _xlfn. (only io/xlsx does)")
}

/// In the engine only the geometry functions (and the surfaces they adapt) use geometry.
fn geometry_used_in_the_engine(files: &[Source]) -> Vec<String> {
    let engine = ["eval/", "workbook/", "io/", "vba/"];
    let users = ["eval/functions/geometry/", "eval/surface.rs"];
    let found = only_in(files, "crate::geometry", &users, "uses geometry (in the engine only functions/geometry does)");
    found.into_iter().filter(|v| engine.iter().any(|e| v.starts_with(e))).collect()
}

fn in_front_end(rel: &str) -> bool {
    in_cli(rel) || rel.starts_with("server/")
}

/// The library's module paths (`eval::dates`) with whether a front end may name them: declared
/// `pub mod`, and not behind the `testing` feature (test helpers are not the facade).
fn library_modules(files: &[Source]) -> Vec<(String, bool)> {
    let mut modules = Vec::new();
    for f in files.iter().filter(|f| !in_front_end(&f.rel)) {
        let path = f.rel.trim_end_matches(".rs");
        let parent = if path == "lib" { String::new() } else { path.trim_end_matches("/mod").replace('/', "::") };
        let mut testing_only = false;
        for line in f.shipped.lines().map(str::trim) {
            if line.starts_with("#[cfg(") {
                testing_only = line.contains("feature = \"testing\"");
                continue;
            }
            let (public, rest) = match line.strip_prefix("pub mod ") {
                Some(rest) => (true, rest),
                None => match line.split_once("mod ") {
                    Some((vis, rest)) if vis.is_empty() || vis.starts_with("pub(") => (false, rest),
                    _ => continue,
                },
            };
            let Some(name) = rest.strip_suffix(';') else { continue };
            let path = if parent.is_empty() { name.to_string() } else { format!("{parent}::{name}") };
            modules.push((path, public && !testing_only));
            testing_only = false;
        }
    }
    modules
}

/// The `ncsheet::` paths a file names: `ncsheet::a::b` and each item of `ncsheet::a::{b::c, d}`.
fn library_paths(code: &str) -> Vec<String> {
    let mut paths = Vec::new();
    for (at, _) in code.match_indices("ncsheet::") {
        if code[..at].chars().next_back().is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &code[at + "ncsheet::".len()..];
        let end = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':')).unwrap_or(rest.len());
        let head = rest[..end].trim_end_matches(':');
        if rest[end..].starts_with('{') && rest[..end].ends_with("::") {
            let close = rest[end..].find('}').map_or(rest.len(), |c| end + c);
            for item in rest[end + 1..close].split(',') {
                paths.push(format!("{head}::{}", item.trim()));
            }
        } else {
            paths.push(head.to_string());
        }
    }
    paths
}

/// Front ends name only public library modules, never the test helpers.
fn front_ends_past_the_facade(files: &[Source]) -> Vec<String> {
    let modules = library_modules(files);
    let mut out = Vec::new();
    for f in files.iter().filter(|f| in_front_end(&f.rel)) {
        for path in library_paths(&f.code) {
            let mut module = String::new();
            for segment in path.split("::").map(str::trim) {
                let child = if module.is_empty() { segment.to_string() } else { format!("{module}::{segment}") };
                match modules.iter().find(|(m, _)| *m == child) {
                    Some((_, true)) => module = child,
                    Some((_, false)) => {
                        out.push(format!("{}: reaches ncsheet::{child}, not public API of the library", f.rel));
                        break;
                    }
                    None => break,
                }
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

fn check(files: &[Source], map: &str) -> Vec<String> {
    let mut found = Vec::new();
    found.extend(prints_outside_cli(files));
    found.extend(files_touched_outside_io(files));
    found.extend(renames_outside_atomic(files));
    found.extend(upward_imports(files));
    found.extend(unmapped_files(files, map));
    found.extend(dialect_lists_outside_nc(files));
    found.extend(functions_past_the_api(files));
    found.extend(pratt_tables_elsewhere(files));
    found.extend(exits_outside_cli(files));
    found.extend(serialisation_outside_cli(files));
    found.extend(file_spelling_outside_xlsx(files));
    found.extend(geometry_used_in_the_engine(files));
    found.extend(front_ends_past_the_facade(files));
    found
}

#[test]
fn the_tree_keeps_the_rules_of_architecture_md() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let map = fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
    let mut found = check(&read_workspace(root), &map);
    found.retain(|v| !ALLOWED.iter().any(|(prefix, _)| v.starts_with(prefix)));
    assert!(found.is_empty(), "ARCHITECTURE.md's rules are broken:\n{}", found.join("\n"));
}

/// A fixture tree that breaks each rule once: the checker must name every break.
#[test]
fn the_checker_finds_each_broken_rule() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path();
    let write = |rel: &str, text: &str| {
        let path = src.join(rel);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, text).unwrap();
    };
    write("lib.rs", "pub mod eval;\n");
    write(
        "eval/mod.rs",
        "fn f() { println!(\"hi\"); }\n// println! in a comment is fine\npub mod value;\nmod evaluator;\n\
         #[cfg(feature = \"testing\")]\npub mod testing;\n",
    );
    write("eval/value.rs", "use crate::workbook::Workbook;\nfn g() { std::fs::read(\"x\"); }\n");
    write("io/csv.rs", "fn h() { fs::rename(a, b); }\n");
    write("geometry/head.rs", "use crate::{eval::Value, formula};\n");
    write("cli/ballpath.rs", "/// Dialect: iso, linuxcnc, sinumerik or heidenhain\nconst D: u8 = 1;\n");
    write(
        "cli/mod.rs",
        "use ncsheet::eval::evaluator::Ctx;\nuse ncsheet::eval::{value::Value, testing::n};\n\
         fn main() { println!(\"cli may print\"); }\n",
    );
    write(
        "eval/functions/math/basic.rs",
        "use crate::eval::evaluator::Ctx;\n#[cfg(test)]\nfn t() { std::fs::write(\"t\", \"\").unwrap(); }\n",
    );
    write("eval/dates.rs", "use pest::pratt_parser::PrattParser;\nfn q() { std::process::exit(1) }\n");
    write("workbook/mod.rs", "#[derive(serde::Serialize)]\nstruct W;\nconst P: &str = \"_xlfn.\";\n");
    write("io/cam.rs", "use crate::geometry::cam;\n#[cfg(test)]\nconst T: &str = \"_xlfn.\";\n");
    let map = "# Map\n`crates/ncsheet/src/lib.rs`\n### `crates/ncsheet/src/eval/`\n`eval/`, `value.rs`, `basic.rs`, `dates.rs`, `csv.rs`\n\
               ### `crates/ncsheet/src/io/`\n`cam.rs`\n### `crates/ncsheet/src/workbook/`\n`workbook/`\n### `crates/ncsheet/src/geometry/`\n`head.rs`\n\
               ### `src/cli/` and `src/main.rs`\n`cli/`\n";
    let found = check(&read_tree(src, ""), map);
    let expect = [
        "eval/mod.rs: prints",
        "eval/value.rs: uses std::fs",
        "io/csv.rs: writes or renames",
        "eval/value.rs: imports crate::workbook",
        "geometry/head.rs: imports crate::eval",
        "geometry/head.rs: imports crate::formula",
        "cli/ballpath.rs: not named",
        "cli/mod.rs: reaches ncsheet::eval::evaluator",
        "cli/mod.rs: reaches ncsheet::eval::testing",
        "cli/ballpath.rs: spells a list of dialects",
        "eval/functions/math/basic.rs: imports the evaluator",
        "io/csv.rs: not named",
        "eval/dates.rs: builds a Pratt table",
        "eval/dates.rs: exits the process",
        "workbook/mod.rs: uses serde",
        "workbook/mod.rs: spells Excel's file prefix",
        "io/cam.rs: uses geometry",
        "io/cam.rs: imports crate::geometry",
    ];
    for e in expect {
        assert!(found.iter().any(|v| v.starts_with(e)), "not found: {e}\nfound:\n{}", found.join("\n"));
    }
    assert_eq!(found.len(), expect.len(), "unexpected findings:\n{}", found.join("\n"));
}
