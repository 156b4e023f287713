//! Hostile input (issue 30), session 25: variants of the classes no earlier round
//! named. What each test expects comes from outside our code: Microsoft's function
//! reference (ATAN2, YEAR), quoted where it is used, and arithmetic worked by hand.

mod common;

use common::sheet::{get, n, set};
use ncsheet::eval::{Value, XlError};
use ncsheet::workbook::Workbook;

/// "ATAN2 function": the angle is "between -pi and pi, excluding -pi", and "where y >= 0,
/// x < 0, ATAN2(x,y) = ATAN(y/x)+PI()". A y of zero made by a negation or a product with a
/// negative number (`-A1`, `A1*-1` with A1 = 0) is a zero like any other: π, never -π. The
/// engine kept IEEE 754's negative zero, whose sign atan2 reads, and gave -π: a tool's angle
/// half a turn the wrong way with no word.
#[test]
fn a_zero_made_negative_is_zero_where_atan2_reads_its_sign() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "0");
    set(&mut wb, "A2", "-0");
    let formulas = ["=ATAN2(-1,0*-1)", "=ATAN2(-1,-A1)", "=ATAN2(-1,A1*-1)", "=ATAN2(-1,-0)", "=ATAN2(-1,A2)"];
    for (row, formula) in formulas.iter().enumerate() {
        set(&mut wb, &format!("B{}", row + 1), formula);
    }
    set(&mut wb, "C1", "=ATAN2(-1,MIN(0*-1,0))");
    set(&mut wb, "C2", "=DEGREES(ATAN2(-1,ROUND(-0.0001,2)))");
    for cell in ["B1", "B2", "B3", "B4", "B5", "C1"] {
        assert_eq!(get(&wb, cell), n(std::f64::consts::PI), "{cell}");
    }
    assert_eq!(get(&wb, "C2"), n(180.0));
    // A typed decimal below the smallest normal double (1e-320, 319 zeros after the point) is
    // 0, as `1E-320` typed is (docs/limits.md, "numbers": Excel keeps no subnormal number).
    set(&mut wb, "A3", &format!("-0.{}1", "0".repeat(319)));
    set(&mut wb, "B6", "=ATAN2(-1,A3)");
    set(&mut wb, "B7", "=A3<0");
    assert_eq!(get(&wb, "B6"), n(std::f64::consts::PI));
    assert_eq!(get(&wb, "B7"), Value::Bool(false));
}

/// "YEAR function": the year is "an integer in the range 1900-9999". A time that rounds up
/// past 9999-12-31's last second (Excel rounds a time to the second, so 2958465.9999999 is
/// midnight of the day after) has no date: `#NUM!`, as that day's own serial 2958466 is.
/// YEAR gave 10000.
#[test]
fn the_last_day_rounded_up_to_the_next_midnight_is_no_date() {
    let mut wb = Workbook::with_sheet();
    let parts = ["=YEAR(x)", "=MONTH(x)", "=DAY(x)", "=WEEKDAY(x)"];
    for (row, part) in parts.iter().enumerate() {
        set(&mut wb, &format!("A{}", row + 1), &part.replace('x', "2958465.9999999"));
        set(&mut wb, &format!("B{}", row + 1), &part.replace('x', "2958466"));
    }
    for row in 1..=4 {
        assert_eq!(get(&wb, &format!("A{row}")), Value::Error(XlError::Num), "A{row}");
        assert_eq!(get(&wb, &format!("B{row}")), Value::Error(XlError::Num), "B{row}");
    }
    // The second before rounds to 23:59:59 of 9999-12-31, the last date.
    set(&mut wb, "C1", "=YEAR(2958465.99998)");
    set(&mut wb, "C2", "=SECOND(2958465.99998)");
    assert_eq!((get(&wb, "C1"), get(&wb, "C2")), (n(9999.0), n(58.0)));
}

/// docs/limits.md, "macro memory": what a macro's variables hold counts against its budget,
/// objects with their fields. 5,000 objects of a class of 20 Double fields hold 100,000
/// Doubles, 8 bytes each ("Double data type"): 800,000 bytes, more than a 512 KiB budget
/// before any slot, name or block is counted. The run stops at the limit; it ran to its end,
/// each object counted as 64 bytes, and 3,500,000 small objects aborted at a 4 GiB cap.
#[test]
fn objects_count_their_fields_against_the_memory_budget() {
    let fields: String = (1..=20).map(|i| format!("Public F{i} As Double\n")).collect();
    let body = "Dim kept(1 To 5000) As Object, i As Long\n\
                For i = 1 To 5000\n    Set kept(i) = New Wide\nNext\nDebug.Print \"made\"";
    let source = format!("Sub Main()\n{body}\nEnd Sub\n");
    let options = ncsheet::vba::RunOptions {
        classes: vec![("Wide".into(), fields)],
        max_memory: 512 << 10,
        ..ncsheet::vba::RunOptions::default()
    };
    let e = match ncsheet::vba::run(&mut Workbook::with_sheet(), &source, "wide.bas", &options) {
        Ok(_) => panic!("5,000 objects of 20 Doubles ran within 512 KiB"),
        Err(e) => e,
    };
    assert_eq!(e.kind, ncsheet::vba::ErrorKind::Limit, "{e}");
    assert!(e.message.contains("more than the 0.5 MiB allowed"), "{e}");
}
