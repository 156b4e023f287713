//! `Range.RemoveDuplicates` (issue 31). Expected values are worked by hand from Microsoft's
//! pages named at each test: "Range.RemoveDuplicates method" (Columns: "Array of indexes of
//! the columns that contain the duplicate information"; Header: "Specifies whether the first
//! row contains header information. xlNo is the default value") and "Filter for unique values
//! or remove duplicate values" (the first row of each set is kept; what is compared is what
//! the cell shows; text compared without case).

mod common;

use common::sheet::{get, n, set};
use common::vba::run_main;
use ncsheet::eval::Value;
use ncsheet::workbook::Workbook;

fn text(s: &str) -> Value {
    Value::text(s)
}

/// The values of column `col` rows 1..=`rows`.
fn column(wb: &Workbook, col: &str, rows: u32) -> Vec<Value> {
    (1..=rows).map(|r| get(wb, &format!("{col}{r}"))).collect()
}

// The page's own example, `Columns:=Array(1, 2), Header:=xlYes`: rows 3, 6 and 7 repeat
// rows 2, 4 and 5 in columns A and B (Bolt/bolt, BOLT/m8 without case), so rows 2, 4, 5
// stay, move up to rows 2..4, and rows 5..7 of the range are emptied. Column C moves with
// its rows; D (outside the range) and row 8 (below it) do not move.
#[test]
fn rows_repeating_the_key_columns_go_and_the_rest_move_up_inside_the_range() {
    let mut wb = Workbook::with_sheet();
    let rows = [
        ("Name", "Size", "Qty"),
        ("bolt", "M6", "1"),
        ("Bolt", "M6", "2"),
        ("bolt", "M8", "3"),
        ("nut", "M6", "4"),
        ("BOLT", "m8", "5"),
        ("nut", "M6", "6"),
    ];
    for (i, (a, b, c)) in rows.iter().enumerate() {
        set(&mut wb, &format!("A{}", i + 1), a);
        set(&mut wb, &format!("B{}", i + 1), b);
        set(&mut wb, &format!("C{}", i + 1), c);
        set(&mut wb, &format!("D{}", i + 1), &format!("d{}", i + 1));
    }
    set(&mut wb, "A8", "below");
    run_main(&mut wb, "Range(\"A1:C7\").RemoveDuplicates Columns:=Array(1, 2), Header:=xlYes");
    let blank = Value::Blank;
    assert_eq!(
        column(&wb, "A", 8),
        [
            text("Name"),
            text("bolt"),
            text("bolt"),
            text("nut"),
            blank.clone(),
            blank.clone(),
            blank.clone(),
            text("below")
        ]
    );
    assert_eq!(column(&wb, "B", 4), [text("Size"), text("M6"), text("M8"), text("M6")]);
    assert_eq!(column(&wb, "C", 5), [text("Qty"), n(1.0), n(3.0), n(4.0), blank]);
    assert_eq!(get(&wb, "D3"), text("d3"));
    assert_eq!(get(&wb, "D7"), text("d7"));
}

// One column, `Columns:=1` and no Header (xlNo by default): the first row is data too.
// 3, 1, 3, 2, 1 keeps 3, 1, 2. A whole column (`Range("A:A")`) reaches the used rows only.
#[test]
fn one_column_without_a_header() {
    let mut wb = Workbook::with_sheet();
    for (r, v) in ["3", "1", "3", "2", "1"].iter().enumerate() {
        set(&mut wb, &format!("A{}", r + 1), v);
    }
    run_main(&mut wb, "Range(\"A:A\").RemoveDuplicates Columns:=1");
    assert_eq!(column(&wb, "A", 5), [n(3.0), n(1.0), n(2.0), Value::Blank, Value::Blank]);
}

// "Filter for unique values or remove duplicate values": "the comparison of duplicate values
// depends on what appears in the cell, not the underlying value": 38784 (8 March 2006) shown
// as 3/8/2006 and as Mar 8, 2006 is two values; the third cell, shown as 3/8/2006 again, goes.
// A column the range does not have is Excel's run-time error 1004.
#[test]
fn what_the_cell_shows_is_compared() {
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "Range(\"B1:B3\").Value = 38784\nRange(\"B1,B3\").NumberFormat = \"m/d/yyyy\"\n\
         Range(\"B2\").NumberFormat = \"mmm d, yyyy\"\n\
         Range(\"B1:B3\").RemoveDuplicates Columns:=1, Header:=xlNo\n\
         Debug.Print Range(\"B1\").Text & \"|\" & Range(\"B2\").Text & \"|\" & CStr(IsEmpty(Range(\"B3\").Value))\n\
         On Error Resume Next\nRange(\"B1:B3\").RemoveDuplicates Columns:=2\nDebug.Print CStr(Err.Number)",
    );
    assert_eq!(printed, ["3/8/2006|Mar 8, 2006|True", "1004"]);
}
