//! Hostile input, numbers at the edges (issue 30): values that came out silently wrong where a
//! cycle, a criterion or a number near the limits of a double met the engine's shortcuts.

mod common;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::{Iteration, Workbook};

// ---------------------------------------------------------------------------------------
// Iterative calculation: a cycle made by INDEX, OFFSET or INDIRECT

/// A column A1:A`n` where A1 = A`n`+1 and each later cell is the one above plus 1, the link
/// written by `above(row)`, iterated `count` rounds as one recalculation of a loaded file.
fn iterated_chain(n: u32, count: u32, above: impl Fn(u32) -> String) -> Workbook {
    let mut wb = Workbook::with_sheet();
    wb.set_iteration(Some(Iteration { count, max_change: 0.0 }));
    let a = |row: u32| parse_cell(&format!("A{row}")).unwrap();
    wb.set_input_deferred(0, a(1), &format!("=A{n}+1")).unwrap();
    for row in 2..=n {
        wb.set_input_deferred(0, a(row), &format!("={}+1", above(row))).unwrap();
    }
    wb.recalculate();
    wb
}

#[test]
fn a_cycle_through_index_offset_or_indirect_iterates_as_the_plain_chain() {
    // Each round computes A1..A50 in order from 0: round r leaves A1 = 50(r-1)+1 and
    // A50 = 50r, so 10 rounds end at A1 = 451, A50 = 500 (exact arithmetic). LibreOffice
    // (iteration on, 10 steps) gives the INDEX form the values of the plain one too.
    // The cycle of the last three forms is found only once their evaluation links it; the
    // iteration started from what that first evaluation left and ended 2 above.
    let forms: [(&str, fn(u32) -> String); 4] = [
        ("plain", |row| format!("A{}", row - 1)),
        ("INDEX", |row| format!("INDEX(A:A,{})", row - 1)),
        ("OFFSET", |row| format!("OFFSET(A{row},-1,0)")),
        ("INDIRECT", |row| format!("INDIRECT(\"A{}\")", row - 1)),
    ];
    for (name, above) in forms {
        let wb = iterated_chain(50, 10, above);
        let at = |cell: &str| wb.value(0, parse_cell(cell).unwrap());
        assert_eq!((at("A1"), at("A50")), (Value::Number(451.0), Value::Number(500.0)), "{name}");
    }
}
