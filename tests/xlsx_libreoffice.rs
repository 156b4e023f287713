//! Round trip through LibreOffice: every example and corpus workbook is imported, exported
//! by our writer, recalculated by LibreOffice (headless, forced to recalculate on load) and
//! saved as xlsx again; LibreOffice's results must equal ncsheet's for every formula cell we
//! support. Skipped, with a message, when `soffice` is not installed.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use common::{judge, libreoffice_convert, recalculating_profile, soffice, Verdict};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::Pos;
use ncsheet::io::xlsx;

/// Functions LibreOffice 7.4 does not have (it answers #NAME?), so their cells and what
/// reads them are not compared. Not the library's list of functions Excel stores as
/// dynamic arrays (`calls_dynamic_function` in crates/ncsheet/src/io/xlsx/syntax.rs), though the two
/// share many names: this one is about LibreOffice, and differs (LET, XMATCH and the
/// REGEX functions are not on that list; SWITCH is, and LibreOffice has it).
const LIBREOFFICE_LACKS: &[&str] = &[
    "ANCHORARRAY",
    "ARRAYTOTEXT",
    "BYCOL",
    "BYROW",
    "CHOOSECOLS",
    "CHOOSEROWS",
    "DROP",
    "EXPAND",
    "FILTER",
    "HSTACK",
    "ISOMITTED",
    "LAMBDA",
    "LET",
    "MAKEARRAY",
    "MAP",
    "RANDARRAY",
    "REDUCE",
    "REGEXEXTRACT",
    "REGEXREPLACE",
    "REGEXTEST",
    "SCAN",
    "SEQUENCE",
    "SINGLE",
    "SORT",
    "SORTBY",
    "TAKE",
    "TEXTAFTER",
    "TEXTBEFORE",
    "TEXTSPLIT",
    "TOCOL",
    "TOROW",
    "TRIMRANGE",
    "UNIQUE",
    "VALUETOTEXT",
    "VSTACK",
    "WRAPCOLS",
    "WRAPROWS",
    "XLOOKUP",
    "XMATCH",
];

/// Cells where LibreOffice and ncsheet knowingly differ and Excel does not tell who is
/// right: (file, cell, why).
const KNOWN_DIFFERENCES: &[(&str, &str, &str)] = &[
    // FIXME(io/xlsx): B51 is `=FISHER(@G:G)` (an intersection with a whole column); our copy
    // of it reads as #NAME? in LibreOffice, so C51 = FISHERINV(B51) does too.
    ("FISHER_FISHERINV.xlsx", "'FISHER FISHERINV'!C51", "our copy of FISHER(@G:G) is #NAME? in LibreOffice"),
    // FIXME(io/xlsx): a legacy one-cell INDEX(range, 0) is implicitly intersected by Excel and
    // LibreOffice (#VALUE! outside the range's rows); the import does not know it returns a
    // range, so the copy is written as a dynamic array and LibreOffice shows its first item.
    ("simple_functions.xlsx", "INDEX!H6", "legacy INDEX(range, 0) written back as a dynamic array"),
    // The same for a legacy one-cell OFFSET returning several cells: the range is made at run
    // time, so the import puts no `@` (see tests/xlsx_conformance.rs).
    ("ROW_COLUM.xlsx", "OFFSET!M12", "legacy several-cell OFFSET written back as a dynamic array"),
    ("ROW_COLUM.xlsx", "OFFSET!K43", "legacy several-cell OFFSET written back as a dynamic array"),
];

/// The example sheets and the corpus, except `calc_test_no_export/`: its workbooks use
/// Excel tables (structured references), hidden rows and filters, which the writer does
/// not carry (IronCalc leaves them out of its export tests too).
fn examples() -> Vec<PathBuf> {
    let mut files = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx")];
    common::workbooks(&common::corpus_root(), &mut files);
    files.retain(|f| !f.to_string_lossy().contains("calc_test_no_export"));
    files
}

/// LibreOffice has no boolean type (TRUE is 1) and maps some errors to others (Excel's
/// #NUM! from SQRT(-1) is its #VALUE!); those are not differences of ours.
fn libreoffice_agrees(theirs: &Value, ours: &Value) -> bool {
    match (theirs, ours) {
        (Value::Number(n), Value::Bool(b)) | (Value::Bool(b), Value::Number(n)) => *n == f64::from(u8::from(*b)),
        (Value::Error(_), Value::Error(_)) => true,
        _ => xlsx::values_agree(theirs, ours),
    }
}

/// Formula results by sheet name and cell.
fn results_of(imported: &xlsx::Imported) -> HashMap<(String, Pos), Value> {
    let names = imported.workbook.sheet_names();
    imported.cached.iter().map(|c| ((names[c.sheet as usize].clone(), c.pos), c.value.clone())).collect()
}

/// Each workbook goes to LibreOffice twice, as it was and as our writer wrote it. Our copy
/// must give LibreOffice the same results as the original (else the export changed a
/// formula), and LibreOffice's results must be ncsheet's, except where LibreOffice itself
/// departs from Excel: it computes the same on Excel's own file while ncsheet matches the
/// value Excel cached.
#[test]
fn libreoffice_computes_what_ncsheet_computes() {
    let Some(soffice) = soffice() else {
        println!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (inputs_dir, outputs_dir) = (dir.path().join("in"), dir.path().join("out"));
    std::fs::create_dir_all(&inputs_dir).unwrap();
    std::fs::create_dir_all(&outputs_dir).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut inputs = Vec::new();
    let mut books = Vec::new();
    for path in examples() {
        let imported = xlsx::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let name = path.strip_prefix(&root).unwrap_or(&path).to_string_lossy().replace(['/', '\\'], "__");
        let (original, ours) = (inputs_dir.join(format!("excel__{name}")), inputs_dir.join(format!("ours__{name}")));
        std::fs::copy(&path, &original).unwrap();
        xlsx::save_with_layout(&imported.workbook, &imported.layout, &ours).unwrap_or_else(|e| panic!("{e}"));
        inputs.push(original.clone());
        inputs.push(ours.clone());
        books.push((path, imported, original, ours));
    }
    let profile = recalculating_profile(&dir.path().join("profile"));
    libreoffice_convert(&soffice, &profile, &inputs, &outputs_dir);

    let mut failures = Vec::new();
    let (mut compared, mut agreed, mut departures) = (0, 0, Vec::new());
    for (source, original, original_copy, ours_path) in &books {
        let converted = |p: &PathBuf| xlsx::load(&outputs_dir.join(p.file_name().unwrap()));
        let (lo_original, lo_ours) = match (converted(original_copy), converted(ours_path)) {
            (Ok(a), Ok(b)) => (results_of(&a), results_of(&b)),
            (Err(e), _) => {
                println!("skipped: LibreOffice could not convert the original: {e}");
                continue;
            }
            (_, Err(e)) => {
                failures.push(format!("{}: LibreOffice could not convert our copy: {e}", source.display()));
                continue;
            }
        };
        let excel = results_of(original);
        // Our file read back: its workbook recomputes our values, its cache holds them.
        let ours = xlsx::load(ours_path).unwrap();
        let names = ours.workbook.sheet_names();
        let key = |c: &xlsx::CachedValue| (names[c.sheet as usize].clone(), c.pos);
        let expected = |c: &xlsx::CachedValue| lo_ours.get(&key(c)).cloned();
        let lacks = |info: &common::FormulaInfo| {
            info.spill_ref || info.at_in_call || info.functions.iter().any(|f| LIBREOFFICE_LACKS.contains(&f.as_str()))
        };
        let (results, infos) = judge(&ours, &expected, &lacks, &libreoffice_agrees);
        let file = source.file_name().unwrap().to_string_lossy().to_string();
        for r in results {
            let cell = ours.workbook.cell_name(r.sheet, r.pos);
            let k = (names[r.sheet as usize].clone(), r.pos);
            let theirs = r.expected.clone().expect("compared");
            let formula = ours.workbook.formula(r.sheet, r.anchor).unwrap_or_default();
            // The export must not change what LibreOffice computes, supported or not; except
            // that a function the original misspelled (CONCAT without `_xlfn.`, written by
            // openpyxl) is understood in our copy.
            let changed = lo_original.get(&k).is_some_and(|before| !libreoffice_agrees(before, &theirs));
            let repaired =
                lo_original.get(&k) == Some(&Value::Error(XlError::Name)) && theirs != Value::Error(XlError::Name);
            let known = KNOWN_DIFFERENCES.iter().any(|(f, c, _)| *f == file && *c == cell);
            if changed && !repaired && !known && r.verdict != Verdict::Volatile && !lacks(&infos[&(r.sheet, r.anchor)])
            {
                failures.push(format!(
                    "{}: {cell}: {formula}: LibreOffice gives {:?} on the original, {theirs:?} on our copy",
                    source.display(),
                    lo_original[&k]
                ));
            }
            if matches!(r.verdict, Verdict::Unsupported | Verdict::Volatile | Verdict::Upstream | Verdict::Kept) {
                continue;
            }
            let value = ours.workbook.value(r.sheet, r.pos);
            if excel.get(&k).is_some_and(|e| !xlsx::values_agree(e, &value)) {
                // ncsheet departs from Excel here: the conformance test reports it.
                continue;
            }
            compared += 1;
            if r.verdict == Verdict::Agree {
                agreed += 1;
            } else if !changed && excel.get(&k).is_some_and(|e| xlsx::values_agree(e, &value)) {
                departures
                    .push(format!("{file}: {cell}: {formula}: Excel and ncsheet {value:?}, LibreOffice {theirs:?}"));
            } else if !known {
                failures
                    .push(format!("{}: {cell}: {formula} gives {value:?}, LibreOffice {theirs:?}", source.display()));
            }
        }
    }
    println!("{} workbooks, {compared} formula results compared, {agreed} agree", books.len());
    println!("{} where LibreOffice departs from Excel:\n{}", departures.len(), departures.join("\n"));
    assert!(compared > 1000, "too few cells compared: {compared}");
    assert!(failures.is_empty(), "{} differences:\n{}", failures.len(), failures.join("\n"));
}

/// Implicit intersection of a legacy formula, with names: `Liste` = A1:A5 and `=Liste+Liste2*2`
/// in row 3 (the example). The workbook is written as an old Excel would store it (a
/// plain formula), LibreOffice computes it with intersection, and ncsheet reading
/// LibreOffice's file must show LibreOffice's results.
#[test]
fn a_legacy_formula_intersects_named_ranges_and_results_as_libreoffice_does() {
    use ncsheet::workbook::Workbook;
    let Some(soffice) = soffice() else {
        println!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let mut wb = Workbook::with_sheet();
    for r in 0..5u32 {
        wb.set_input_deferred(0, Pos::new(r, 0), &format!("{}", r + 1)).unwrap();
        wb.set_input_deferred(0, Pos::new(r, 2), &format!("{}", 10 * (r + 1))).unwrap();
    }
    wb.define_name("Liste", "Sheet1!$A$1:$A$5", None).unwrap();
    wb.define_name("Liste2", "Sheet1!$C$1:$C$5", None).unwrap();
    // Typed with `@`, they are written as plain formulas (`Liste+Liste2*2`), as old Excel
    // stores them.
    let formulas = [(2, "=@Liste+@Liste2*2"), (3, "=@Liste*2"), (4, "=@ROW(C2:C5)")];
    for (row, text) in formulas {
        wb.set_input_deferred(0, Pos::new(row, 4), text).unwrap();
    }
    wb.recalculate();
    let ours = dir.path().join("names.xlsx");
    xlsx::save(&wb, &ours).unwrap();
    let profile = recalculating_profile(&dir.path().join("profile"));
    libreoffice_convert(&soffice, &profile, &[ours], &out);
    let converted = xlsx::load(&out.join("names.xlsx")).expect("LibreOffice wrote the workbook");
    let theirs = results_of(&converted);
    for (row, text) in formulas {
        let pos = Pos::new(row, 4);
        let expected = theirs.get(&("Sheet1".to_string(), pos)).unwrap_or_else(|| panic!("{text}: no result"));
        let got = converted.workbook.value(0, pos);
        assert!(libreoffice_agrees(expected, &got), "{text}: ncsheet {got:?}, LibreOffice {expected:?}");
    }
    // It came as a plain formula and was intersected on import.
    assert_eq!(converted.workbook.formula(0, Pos::new(2, 4)).as_deref(), Some("=@Liste+@Liste2*2"));
}
