//! Workbooks of the public Excel corpus (`../shared/excel-corpus/public`, saved by Excel)
//! that exercise one feature each: every formula result must be the value Excel cached.
//! The whole corpus is compared in `xlsx_conformance.rs`; these name the feature that fails.

mod common;

use common::{judge, Verdict};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::io::xlsx;

/// Loads a public-corpus workbook and checks every formula result against Excel's; returns
/// how many were compared. `None` (skipped) without the corpus, a failure under CI.
fn agrees_with_excel(rel: &str) -> Option<usize> {
    let root = common::corpus::public_path();
    if !root.is_dir() {
        assert!(std::env::var_os("CI").is_none(), "public Excel corpus not found at {}", root.display());
        eprintln!("skipped: public Excel corpus not found at {}", root.display());
        return None;
    }
    let imported = xlsx::load(&root.join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
    let (results, _) = judge(&imported, &|c| Some(c.value.clone()), &|_| false, &xlsx::values_agree);
    let wrong: Vec<String> = results
        .iter()
        .filter(|r| r.verdict != Verdict::Agree)
        .map(|r| {
            format!(
                "{}: {:?} {} gives {:?}, Excel {:?}",
                imported.workbook.cell_name(r.sheet, r.pos),
                r.verdict,
                imported.workbook.formula(r.sheet, r.anchor).unwrap_or_default(),
                imported.workbook.value(r.sheet, r.pos),
                r.expected
            )
        })
        .collect();
    assert!(wrong.is_empty(), "{rel}:\n{}", wrong.join("\n"));
    Some(results.len())
}

fn all_agree(files: &[&str], at_least: usize) {
    let mut compared = 0;
    for f in files {
        match agrees_with_excel(f) {
            Some(n) => compared += n,
            None => return,
        }
    }
    assert!(compared >= at_least, "{files:?}: only {compared} results compared");
}

#[test]
fn the_1904_date_system_moves_every_date_function_and_text_format() {
    all_agree(
        &["poi/test-data_spreadsheet_DateFormatTests.xlsx", "poi/test-data_spreadsheet_DateFormatNumberTests.xlsx"],
        40,
    );
}

#[test]
fn text_formats_with_conditions_text_sections_and_am_pm() {
    all_agree(
        &[
            "poi/test-data_spreadsheet_FormatChoiceTests.xlsx",
            "poi/test-data_spreadsheet_FormatConditionTests.xlsx",
            "poi/test-data_spreadsheet_TextFormatTests.xlsx",
        ],
        60,
    );
}

#[test]
fn structured_references_name_the_parts_of_excel_tables() {
    all_agree(
        &[
            "poi/test-data_spreadsheet_StructuredReferences.xlsx",
            "poi/test-data_spreadsheet_simple-monthly-budget.xlsx",
            "poi/test-data_spreadsheet_simple-table-named-range.xlsx",
            "poi/test-data_spreadsheet_evaluate_formula_with_structured_table_references.xlsx",
        ],
        15,
    );
}

#[test]
fn three_d_references_take_every_sheet_between_the_two() {
    all_agree(&["poi/test-data_spreadsheet_FormulaSheetRange.xlsx", "poi/test-data_spreadsheet_48703.xlsx"], 3);
}

#[test]
fn a_beta_era_shared_string_table_is_read() {
    let root = common::corpus::public_path();
    if !root.is_dir() {
        assert!(std::env::var_os("CI").is_none(), "public Excel corpus not found at {}", root.display());
        return;
    }
    let imported = xlsx::load(&root.join("poi/test-data_spreadsheet_sample-beta.xlsx")).expect("Excel opens it");
    let wb = &imported.workbook;
    // The file's first string item is "Lorem", its last "at" (A10).
    assert_eq!(wb.value(0, parse_cell("A1").expect("cell")), Value::text("Lorem"));
    assert_eq!(wb.value(0, parse_cell("A10").expect("cell")), Value::text("at"));
}

#[test]
fn a_legacy_array_formula_fills_its_whole_area() {
    // `{=A1}` entered over B1:B2: Excel repeats the scalar in both cells.
    all_agree(&["poi/test-data_spreadsheet_57798.xlsx"], 2);
}
