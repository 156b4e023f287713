//! Excel binary workbooks (.xlsb) compute Excel's values.
//!
//! No Excel-saved .xlsb is at hand, so `tests/data/xlsb` holds .xlsb files written from
//! Excel-saved .xlsx of the IronCalc corpus by a writer independent of the reader under test
//! (`tests/data/xlsb/make_xlsb.py`, from [MS-XLSB]; README.md there). Each keeps the formulas
//! it could compile to Ptg tokens (other sheets, defined names, shared formulas and `_xlfn.`
//! functions included) and the value Excel cached for each. ncsheet reads the .xlsb,
//! recomputes every formula, and must agree with the value Excel cached in the .xlsx.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::io::xlsx;

/// The least share of the .xlsb formula cells that must compute Excel's value.
const THRESHOLD: f64 = 0.99;

fn xlsb_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/xlsb"))
}

/// (the .xlsb's name without extension, its source .xlsx under the IronCalc corpus).
fn sources() -> Vec<(String, String)> {
    let listing = std::fs::read_to_string(xlsb_dir().join("SOURCES.tsv")).unwrap();
    listing
        .lines()
        .filter(|l| !l.is_empty())
        .map(|l| {
            let (name, source) = l.split_once('\t').unwrap_or_else(|| panic!("SOURCES.tsv: {l}"));
            (name.to_string(), source.to_string())
        })
        .collect()
}

/// The formula cells the writer put in `name`.xlsb, (sheet, cell) as its listing names them.
fn written_formulas(name: &str) -> Vec<(String, String)> {
    let path = xlsb_dir().join(format!("{name}.formulas.tsv"));
    let listing = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    listing
        .lines()
        .map(|l| {
            let mut fields = l.split('\t');
            (fields.next().unwrap().to_string(), fields.next().unwrap().to_string())
        })
        .collect()
}

/// Excel's cached value of each formula cell of the .xlsx, by (sheet name, position), and
/// the file's tolerance for numbers (the corpus's `METADATA!A1`, as tests/xlsx_conformance.rs
/// reads it).
fn excel_values(source: &Path) -> (HashMap<(String, ncsheet::formula::Pos), Value>, Option<f64>) {
    let imported = xlsx::load(source).unwrap_or_else(|e| panic!("{e}"));
    let tolerance = common::metadata_tolerance(&imported.workbook);
    let names = imported.workbook.sheet_names();
    let values = imported
        .cached
        .into_iter()
        .filter(|c| c.pos == c.anchor)
        .map(|c| ((names[c.sheet as usize].clone(), c.pos), c.value))
        .collect();
    (values, tolerance)
}

#[test]
fn xlsb_files_recompute_the_values_excel_cached() {
    let Some(corpus) = common::corpus::root() else { return };
    let (mut compared, mut agree) = (0usize, 0usize);
    let mut left = Vec::new();
    let mut cached_wrong = Vec::new();
    for (name, source) in sources() {
        let (excel, tolerance) = excel_values(&corpus.join(&source));
        let path = xlsb_dir().join(format!("{name}.xlsb"));
        let opened = ncsheet::io::open(&path).unwrap_or_else(|e| panic!("{name}.xlsb: {e}"));
        let wb = &opened.workbook;
        // What the .xlsb stores for each formula, as ncsheet read it (for `eval --check`).
        let stored: HashMap<_, _> = opened.cached.iter().map(|c| ((c.sheet, c.pos), &c.value)).collect();
        let written = written_formulas(&name);
        assert!(!written.is_empty(), "{name}: no formulas listed");
        for (sheet, cell) in written {
            let id = wb.sheet_id(&sheet).unwrap_or_else(|| panic!("{name}.xlsb: no sheet {sheet}"));
            let pos = parse_cell(&cell).unwrap_or_else(|| panic!("{name}: cell {cell}"));
            let want = excel.get(&(sheet.clone(), pos)).unwrap_or_else(|| panic!("{source}: no cached {sheet}!{cell}"));
            compared += 1;
            if !stored.get(&(id, pos)).is_some_and(|v| xlsx::values_agree(want, v)) {
                cached_wrong
                    .push(format!("{name}.xlsb: {sheet}!{cell}: stored {:?}, Excel {want:?}", stored.get(&(id, pos))));
            }
            // The formula must have come through and been computed: a cell read as the
            // constant the file cached, or one keeping that value, is not agreement.
            let computed = wb.is_formula(id, pos) && !wb.keeps_file_value(id, pos);
            let ours = wb.value(id, pos);
            if computed && (xlsx::values_agree(want, &ours) || common::close_within(want, &ours, tolerance)) {
                agree += 1;
                continue;
            }
            let how = if computed { format!("gives {ours:?}") } else { "is not computed".to_string() };
            left.push(format!(
                "{name}.xlsb: {}: {} {how}, Excel {want:?}",
                wb.cell_name(id, pos),
                wb.formula(id, pos).unwrap_or_default()
            ));
        }
    }
    let share = agree as f64 / compared as f64;
    eprintln!("xlsb: {agree} of {compared} formula cells compute Excel's value ({:.2} %)", 100.0 * share);
    eprintln!("left:\n{}", left.join("\n"));
    assert!(cached_wrong.is_empty(), "values the .xlsb stores read wrong:\n{}", cached_wrong.join("\n"));
    // No listed formula reads the clock or chance: every one is compared.
    assert!(compared >= 16000, "only {compared} formula cells compared");
    assert!(share >= THRESHOLD, "{agree} of {compared} agree, below {THRESHOLD}:\n{}", left.join("\n"));
}

/// A copy of a vendored .xlsb in a fresh folder.
fn xlsb_copy(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.xlsb"));
    std::fs::copy(xlsb_dir().join(format!("{name}.xlsb")), &path).unwrap();
    (dir, path)
}

#[test]
fn eval_computes_an_xlsbs_comparisons_as_excel() {
    let (_dir, path) = xlsb_copy("logical");
    // Compare!A2 and B2 hold 1: Excel cached FALSE for `=$A2>$B2` (E2), TRUE for `=$A2>=$B2` (G2).
    let run =
        common::cli::ncsheet(&["eval", path.to_str().unwrap(), "--sheet", "Compare", "E2", "G2", "--format", "csv"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stdout.split_whitespace().collect::<Vec<_>>().join(","), "FALSE,TRUE", "{}", run.stderr);
    let run = common::cli::ncsheet(&["eval", path.to_str().unwrap(), "--sheet", "Compare", "E2", "G2", "--formulas"]);
    assert!(run.stdout.contains("$A2>$B2") && run.stdout.contains("$A2>=$B2"), "{}", run.stdout);
}

#[test]
fn set_converts_an_xlsb_to_xlsx_and_refuses_to_write_it_in_place() {
    let (dir, path) = xlsb_copy("arithmetic");
    let original = std::fs::read(&path).unwrap();
    let out = dir.path().join("out.xlsx");
    // Sheet1!E2 is =C2+D2 with D2 = 2: C2 = 10 gives 12, computed from the converted formula.
    let run = common::cli::ncsheet(&["set", path.to_str().unwrap(), "C2=10", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("written anew as .xlsx"), "{}", run.stderr);
    let run = common::cli::ncsheet(&["eval", out.to_str().unwrap(), "E2", "--formulas"]);
    assert!(run.stdout.contains("=C2+D2"), "{}", run.stdout);
    let run = common::cli::ncsheet(&["eval", out.to_str().unwrap(), "E2"]);
    assert_eq!(run.stdout.trim(), "12", "{}", run.stderr);
    let run = common::cli::ncsheet(&["set", path.to_str().unwrap(), "C2=10", "--in-place"]);
    assert_ne!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("does not write that format"), "{}", run.stderr);
    assert_eq!(std::fs::read(&path).unwrap(), original, "the .xlsb was not touched");
}

#[test]
fn run_works_a_macro_on_an_xlsb() {
    let (dir, path) = xlsb_copy("arithmetic");
    let bas = dir.path().join("m.bas");
    std::fs::write(&bas, "Sub Main()\n  Range(\"C2\").Value = 10\n  Debug.Print Range(\"E2\").Value\nEnd Sub\n")
        .unwrap();
    let run = common::cli::ncsheet(&["run", path.to_str().unwrap(), bas.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.lines().any(|l| l.trim() == "12"), "{}", run.stderr);
}
