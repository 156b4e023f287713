//! .xls, .xlsb and .ods: read into the same workbook as an .xlsx, computed, and converted to
//! .xlsx by `set -o`, never written in their own format.
//!
//! LibreOffice saves workbooks of the Excel corpus (`tests/data/excel-corpus/ironcalc`) as
//! .ods and .xls; every formula cell whose .xlsx ncsheet computes as Excel cached it must
//! compute the same from the .ods and the .xls (Excel's cached value is the oracle, the
//! conversion must not lose it).

mod common;

use std::path::{Path, PathBuf};

use ncsheet::io::xlsx;

/// Corpus workbooks of functions BIFF8 and ODF both hold (Excel 2003's), with their sheets'
/// arithmetic, comparisons, lookups, database and financial functions.
const WORKBOOKS: &[&str] = &[
    "calc_tests/arithmetic.xlsx",
    "calc_tests/logical.xlsx",
    "calc_tests/range_operator.xlsx",
    "calc_tests/FINANCIAL/PMT.xlsx",
    "calc_tests/LOOKUP_AND_REFERENCE/HVLOOKUP.xlsx",
    "calc_tests/DATABASE/DAVERAGE.xlsx",
];

fn corpus_files() -> Option<Vec<PathBuf>> {
    let root = common::corpus::root()?;
    Some(WORKBOOKS.iter().map(|w| root.join(w)).collect())
}

/// Cells (sheet name, cell, Excel's value) where ncsheet's reading of the .xlsx agrees with
/// Excel's cached value, the clock and chance left out.
fn excel_agreed(path: &Path) -> Vec<(String, ncsheet::formula::Pos, ncsheet::eval::Value)> {
    let imported = xlsx::load(path).unwrap_or_else(|e| panic!("{e}"));
    let (results, _) = common::judge(&imported, &|c| Some(c.value.clone()), &|_| false, &xlsx::values_agree);
    let names = imported.workbook.sheet_names();
    results
        .into_iter()
        .filter(|r| r.verdict == common::Verdict::Agree)
        .map(|r| (names[r.sheet as usize].clone(), r.pos, r.expected.expect("compared")))
        .collect()
}

/// Converts the corpus workbooks with LibreOffice and checks the converted files compute
/// Excel's values; returns how many cells were compared.
fn converted_files_compute_excels_values(format: &str) -> Option<usize> {
    let files = corpus_files()?;
    let soffice = common::soffice()?;
    let dir = tempfile::tempdir().unwrap();
    // The default profile: LibreOffice keeps Excel's cached values and writes them out.
    let profile = format!("-env:UserInstallation=file://{}", dir.path().join("profile").display());
    let out = dir.path().join(format);
    common::libreoffice_convert_to(&soffice, &profile, &files, &out, format);
    let mut compared = 0;
    let mut wrong = Vec::new();
    for file in &files {
        let converted = out.join(file.file_name().unwrap()).with_extension(format);
        let opened = ncsheet::io::open(&converted).unwrap_or_else(|e| panic!("{e}"));
        let wb = &opened.workbook;
        for (sheet, pos, excel) in excel_agreed(file) {
            let id = wb.sheet_id(&sheet).unwrap_or_else(|| panic!("{}: no sheet {sheet}", converted.display()));
            let ours = wb.value(id, pos);
            compared += 1;
            if !xlsx::values_agree(&excel, &ours) {
                wrong.push(format!(
                    "{}: {}: {} gives {ours:?}, Excel {excel:?}",
                    converted.file_name().unwrap().to_string_lossy(),
                    wb.cell_name(id, pos),
                    wb.formula(id, pos).unwrap_or_default()
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{} of {compared} cells differ:\n{}", wrong.len(), wrong.join("\n"));
    Some(compared)
}

#[test]
fn libreoffice_ods_of_excel_workbooks_compute_excels_values() {
    if let Some(n) = converted_files_compute_excels_values("ods") {
        assert!(n > 500, "only {n} cells compared");
    }
}

#[test]
fn libreoffice_xls_of_excel_workbooks_compute_excels_values() {
    if let Some(n) = converted_files_compute_excels_values("xls") {
        assert!(n > 500, "only {n} cells compared");
    }
}

/// A corpus .xls copied into a fresh folder under `name`.
fn xls_copy(file: &str, name: &str) -> Option<(tempfile::TempDir, PathBuf)> {
    let source = common::corpus::xls_path().join(file);
    if !source.is_file() {
        assert!(std::env::var_os("CI").is_none(), "xls corpus not found at {}", source.display());
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::copy(&source, &path).unwrap();
    Some((dir, path))
}

#[test]
fn eval_reads_an_xls_and_checks_it_against_excels_stored_values() {
    // Named .xlsx: the bytes (a compound file with a Workbook stream) say it is an .xls.
    for name in ["sumifs.xls", "sumifs-misnamed.xlsx"] {
        let Some((_dir, path)) = xls_copy("sumifs.xls", name) else { return };
        let run = common::cli::ncsheet(&["eval", "--check", path.to_str().unwrap()]);
        assert_eq!(run.code, 0, "{name}: {}", run.stderr);
        assert!(run.stderr.contains("stored values agree with Excel"), "{name}: {}", run.stderr);
        // SUMIFS(A2:A9, B2:B9, "=A*", C2:C9, 1): Apples 5 + Artichokes 15 (Excel's cached 20).
        let run = common::cli::ncsheet(&["eval", path.to_str().unwrap(), "C11"]);
        assert_eq!(run.stdout.trim(), "20", "{name}: {}", run.stderr);
    }
}

#[test]
fn set_converts_an_xls_to_xlsx_saying_what_is_lost_and_refuses_to_write_it_in_place() {
    let Some((dir, path)) = xls_copy("sumifs.xls", "sumifs.xls") else { return };
    let original = std::fs::read(&path).unwrap();
    let out = dir.path().join("out.xlsx");
    let run = common::cli::ncsheet(&["set", path.to_str().unwrap(), "A2=10", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("written anew as .xlsx"), "{}", run.stderr);
    // 10 + 15: the formula came through the conversion and computes in the saved file.
    let run = common::cli::ncsheet(&["eval", out.to_str().unwrap(), "C11", "--formulas"]);
    assert!(run.stdout.contains("=SUMIFS("), "{}", run.stdout);
    let run = common::cli::ncsheet(&["eval", out.to_str().unwrap(), "C11"]);
    assert_eq!(run.stdout.trim(), "25", "{}", run.stderr);
    for target in [&path, &dir.path().join("copy.ods"), &dir.path().join("copy.xlsb")] {
        let args: Vec<&str> = if target == &path {
            vec!["set", path.to_str().unwrap(), "A2=10", "--in-place"]
        } else {
            vec!["set", path.to_str().unwrap(), "A2=10", "-o", target.to_str().unwrap()]
        };
        let run = common::cli::ncsheet(&args);
        assert_ne!(run.code, 0, "{}", target.display());
        assert!(run.stderr.contains("does not write that format"), "{}", run.stderr);
    }
    assert_eq!(std::fs::read(&path).unwrap(), original, "the .xls was not touched");
}

#[test]
fn run_works_a_macro_on_an_xls() {
    let Some((dir, path)) = xls_copy("sumifs.xls", "sumifs.xls") else { return };
    let bas = dir.path().join("m.bas");
    std::fs::write(&bas, "Sub Main()\n  Range(\"A2\").Value = 10\n  Debug.Print Range(\"C11\").Value\nEnd Sub\n")
        .unwrap();
    let run = common::cli::ncsheet(&["run", path.to_str().unwrap(), bas.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.lines().any(|l| l.trim() == "25"), "{}", run.stderr);
}
