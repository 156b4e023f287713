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
