//! Probe workbooks that vary the features of issue #11 beyond what the Excel corpora show:
//! structured references (spaces, `'#`, `'[`, `#This Row`, totals rows, tables on other
//! sheets), 3D references, legacy array formulas, the 1904 date system, defined names,
//! iterative calculation, TEXT's number formats, which error wins, and an engineering design
//! sheet (rounding, trigonometry, lookups, display digits).
//!
//! How they were made (`tests/data/libreoffice/make.sh`): `make.py` writes `NAME.xlsx` with
//! openpyxl, formulas in Excel's file spelling and no cached values; LibreOffice 7.4
//! recalculates it on load and saves `NAME.lo.xlsx`, whose cached values are the oracle.
//! ncsheet loads `NAME.xlsx` and must compute every value LibreOffice cached, except the
//! cells of [`EXCEL_NOT_LIBREOFFICE`]: where LibreOffice does not do what Excel documents,
//! Excel's value is asserted instead (or, where no Excel source settles it, the cell is
//! left out with the reason).

use std::path::{Path, PathBuf};

use ncsheet::eval::value::Value;
use ncsheet::io::xlsx;

/// What Excel gives where LibreOffice differs.
#[derive(Debug)]
enum Excel {
    Num(f64),
    Text(&'static str),
    Err(&'static str),
    /// Excel's value is not settled by any source at hand: the cell is not compared.
    Unknown,
}

use Excel::*;

/// (probe, cell, Excel's value, why LibreOffice differs).
const EXCEL_NOT_LIBREOFFICE: &[(&str, &str, Excel, &str)] = &[
    // Excel shows the decimal point a format asks for even with no digit after it.
    ("text_formats", "T!B21", Text("."), "`.#` of 0: Excel keeps the point"),
    ("text_formats", "T!J21", Text("."), "`.#` of 0.03125: Excel keeps the point"),
    ("text_formats", "T!I21", Text("12."), "`.#` of 12: Excel keeps the point"),
    ("text_formats", "T!K21", Text("100000000."), "`.#`: Excel keeps the point"),
    ("text_formats", "T!B23", Text("."), "`#.##` of 0: Excel keeps the point"),
    ("text_formats", "T!I23", Text("12."), "`#.##` of 12: Excel keeps the point"),
    ("text_formats", "T!K23", Text("100000000."), "`#.##`: Excel keeps the point"),
    ("text_formats", "T!B33", Text("0."), "`0.###` of 0: Excel keeps the point"),
    ("text_formats", "T!I33", Text("12."), "`0.###` of 12: Excel keeps the point"),
    ("text_formats", "T!K33", Text("100000000."), "`0.###`: Excel keeps the point"),
    // Serial 0 is Excel's 1900-01-00 and 1 is 1900-01-01 (LibreOffice counts from
    // 1899-12-30); negative serials are not dates (#VALUE!), nor past 9999-12-31.
    ("text_formats", "T!B14", Text("0-Jan-00"), "serial 0 in the 1900 system"),
    ("text_formats", "T!C14", Text("1-Jan-00"), "serial 1.25"),
    ("text_formats", "T!D14", Err("#VALUE!"), "a negative serial is no date"),
    ("text_formats", "T!E14", Text("0-Jan-00"), "serial 0.33"),
    ("text_formats", "T!G14", Err("#VALUE!"), "a negative serial is no date"),
    ("text_formats", "T!H14", Text("3-Jan-00"), "serial 3.14 (1900-01-03)"),
    ("text_formats", "T!I14", Text("12-Jan-00"), "serial 12"),
    ("text_formats", "T!J14", Text("0-Jan-00"), "serial 0.03"),
    ("text_formats", "T!K14", Err("#VALUE!"), "past 9999-12-31"),
    ("text_formats", "T!B40", Text("1900-01-00 00:00"), "serial 0"),
    ("text_formats", "T!C40", Text("1900-01-01 06:00"), "serial 1.25"),
    ("text_formats", "T!D40", Err("#VALUE!"), "a negative serial is no date"),
    ("text_formats", "T!E40", Text("1900-01-00 08:00"), "serial 0.33"),
    ("text_formats", "T!G40", Err("#VALUE!"), "a negative serial is no date"),
    ("text_formats", "T!H40", Text("1900-01-03 03:23"), "serial 3.14"),
    ("text_formats", "T!I40", Text("1900-01-12 00:00"), "serial 12"),
    ("text_formats", "T!J40", Text("1900-01-00 00:45"), "serial 0.03"),
    ("text_formats", "T!K40", Err("#VALUE!"), "past 9999-12-31"),
    ("text_formats", "T!B41", Text("0 days"), "serial 0: day 0"),
    ("text_formats", "T!C41", Text("1 days"), "serial 1.25"),
    ("text_formats", "T!D41", Err("#VALUE!"), "a negative serial is no date"),
    ("text_formats", "T!E41", Text("0 days"), "serial 0.33"),
    ("text_formats", "T!G41", Err("#VALUE!"), "a negative serial is no date"),
    ("text_formats", "T!H41", Text("3 days"), "serial 3.14"),
    ("text_formats", "T!I41", Text("12 days"), "serial 12"),
    ("text_formats", "T!J41", Text("0 days"), "serial 0.03"),
    ("text_formats", "T!K41", Err("#VALUE!"), "past 9999-12-31"),
    ("text_formats", "T!F11", Text("29629629:23:02"), "elapsed hours of a valid serial"),
    ("text_formats", "T!K11", Err("#VALUE!"), "past 9999-12-31"),
    ("text_formats", "T!F30", Text("1777777763:02"), "elapsed minutes of a valid serial"),
    ("text_formats", "T!K30", Err("#VALUE!"), "past 9999-12-31"),
    ("text_formats", "T!K31", Err("#VALUE!"), "past 9999-12-31"),
    // Negative times: LibreOffice prints a signed duration; Excel has no negative dates.
    ("text_formats", "T!D11", Err("#VALUE!"), "a negative time"),
    ("text_formats", "T!G11", Err("#VALUE!"), "a negative time"),
    ("text_formats", "T!D30", Err("#VALUE!"), "a negative time"),
    ("text_formats", "T!G30", Err("#VALUE!"), "a negative time"),
    ("text_formats", "T!D31", Err("#VALUE!"), "a negative time"),
    ("text_formats", "T!G31", Err("#VALUE!"), "a negative time"),
    // 0.3333333333 days is 07:59:59.9999971: Excel rounds to the shown hundredths first.
    ("text_formats", "T!E31", Text("00:00.00"), "mm:ss.00 rounds the whole time"),
    // TEXT's General is a cell's General in a standard-width column: 11 characters.
    ("text_formats", "T!E32", Text("0.333333333"), "General in 11 characters"),
    ("text_formats", "T!D27", Unknown, "minus sign with a [<0] condition: no Excel source"),
    ("text_formats", "T!G27", Unknown, "minus sign with a [<0] condition: no Excel source"),
    // LibreOffice 7.4 misreads structured references to whole-table areas (`Parts[#All]` is
    // #NAME?, `ROW(Parts[#Headers])` #VALUE!); Excel's values follow from the table
    // `Parts` = 'Parts Data'!A1:F6 (header row 1, data rows 2–5, totals row 6).
    ("tables", "Use!A5", Num(6.0), "ROWS(Parts[#All]): header, 4 data rows, totals"),
    ("tables", "Use!A6", Num(4.0), "ROWS(Parts[#Data])"),
    ("tables", "Use!A7", Num(4.0), "ROWS(Parts): a table's name alone is its data"),
    ("tables", "Use!A8", Num(6.0), "COLUMNS(Parts[#All])"),
    ("tables", "Use!A9", Num(6.0), "COUNTA(Parts[#Headers]): six headers"),
    ("tables", "Use!A12", Num(0.5), "INDEX(Parts[#All],MATCH(\"c\",…),3): row 4 of #All is c"),
    ("tables", "Use!A22", Num(1.0), "ROW(Parts[#Headers])"),
    ("tables", "Use!A23", Num(6.0), "ROW(Parts[#Totals])"),
    ("tables", "Use!A24", Num(2.0), "MATCH(\"Qty\",Parts[#Headers],0)"),
    ("tables", "Use!A28", Num(400.0), "MAX(Parts[#Data])"),
    // COUNTBLANK counts the empty cells of its range: D1 and D2 of Feb are both empty.
    ("three_d", "Summary!A14", Num(2.0), "LibreOffice counts one of two empty cells"),
];

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/libreoffice")
}

fn excel_value(expected: &Excel) -> Option<Value> {
    match expected {
        Num(n) => Some(Value::Number(*n)),
        Text(t) => Some(Value::text(*t)),
        Err(e) => Some(Value::Error(e.parse().expect("an error literal"))),
        Unknown => None,
    }
}

/// Every disagreement of one probe with LibreOffice (or, on the exception list, with Excel).
fn differences(probe: &str) -> Vec<String> {
    let ours = xlsx::load(&data().join(format!("{probe}.xlsx"))).expect("the probe loads");
    let oracle = xlsx::load(&data().join(format!("{probe}.lo.xlsx"))).expect("LibreOffice's save loads");
    let wb = &ours.workbook;
    let mut out = Vec::new();
    for c in &oracle.cached {
        let cell = wb.cell_name(c.sheet, c.pos);
        let got = wb.value(c.sheet, c.pos);
        let exception = EXCEL_NOT_LIBREOFFICE.iter().find(|(p, at, ..)| *p == probe && *at == cell);
        let (expected, by) = match exception {
            Some((_, _, excel, _)) => match excel_value(excel) {
                Some(v) => (v, "Excel"),
                None => continue,
            },
            None => (c.value.clone(), "LibreOffice"),
        };
        if !xlsx::values_agree(&expected, &got) {
            let formula = wb.formula(c.sheet, c.anchor).unwrap_or_default();
            out.push(format!("{probe}: {cell}: {formula}: {by} {expected:?}, ncsheet {got:?}"));
        }
    }
    assert!(!oracle.cached.is_empty(), "{probe}: LibreOffice's save holds no values");
    out
}

fn check(probe: &str) {
    let diffs = differences(probe);
    assert!(diffs.is_empty(), "{} cells differ:\n{}", diffs.len(), diffs.join("\n"));
}

#[test]
fn text_number_formats_fractions_scaling_and_sections() {
    check("text_formats");
}

#[test]
fn structured_references_with_spaces_quotes_this_row_and_totals() {
    check("tables");
}

#[test]
fn three_d_references_with_quoted_and_reversed_sheet_names() {
    check("three_d");
}

#[test]
fn legacy_array_formulas_of_every_size_fill_their_area() {
    check("cse");
}
