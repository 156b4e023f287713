//! One-sheet workbook helpers for tests that type cells by address.

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

/// Types `input` into `cell` of the first sheet; an edit refused is the test's to notice
/// through the cell's value.
pub fn set(wb: &mut Workbook, cell: &str, input: &str) {
    let _ = wb.set_input(0, parse_cell(cell).unwrap(), input);
}

/// The value of `cell` of the first sheet.
pub fn get(wb: &Workbook, cell: &str) -> Value {
    wb.value(0, parse_cell(cell).unwrap())
}

pub fn n(v: f64) -> Value {
    Value::Number(v)
}

/// The value of `formula` in A1 of an empty sheet, the notes of that cell, and how long the
/// recalculation took.
pub fn eval_a1(formula: &str) -> (Value, Vec<String>, std::time::Duration) {
    let mut wb = Workbook::with_sheet();
    let _ = wb.set_input_deferred(0, parse_cell("A1").unwrap(), formula);
    let start = std::time::Instant::now();
    wb.recalculate();
    let took = start.elapsed();
    let problems = wb.problems().into_iter().map(|p| p.render()).collect();
    (wb.value(0, parse_cell("A1").unwrap()), problems, took)
}

/// Types `input` into `cell` of sheet `sheet`; the test fails when the edit is refused.
pub fn set_on(wb: &mut Workbook, sheet: u16, cell: &str, input: &str) {
    wb.set_input(sheet, parse_cell(cell).unwrap(), input).unwrap();
}

/// The value of `cell` of sheet `sheet`.
pub fn get_on(wb: &Workbook, sheet: u16, cell: &str) -> Value {
    wb.value(sheet, parse_cell(cell).unwrap())
}
