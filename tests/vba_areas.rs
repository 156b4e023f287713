//! Ranges of several areas (issue 31): `Range("C5:D9,G9:H16")`, `Union` of separate ranges,
//! `Intersect` of them, `Areas`, and what Excel does with such a range. Each expected value is
//! worked by hand from the page of Microsoft's Excel VBA reference named at the test.

mod common;

use common::sheet::{get, n, set};
use common::vba::{main_fails, run_main};
use ncsheet::eval::Value;
use ncsheet::workbook::Workbook;

// "Range.Areas property": "For a multiple-area selection, the Areas property returns a
// collection that contains one object for each selected area"; C5:D9 is 5 x 2 = 10 cells and
// G9:H16 8 x 2 = 16, so Count is 26 ("Range.Count property": the cells of the range).
// "Range.Rows property": "If the range is a multiple-area selection, this property returns
// rows from only the first area of the range" (5 rows, 2 columns). Address lists the areas
// in order, joined by the list separator.
#[test]
fn a_list_of_areas_is_one_range_of_them_all() {
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "Dim r As Range\nSet r = Range(\"C5:D9,G9:H16\")\n\
         Debug.Print r.Address\nDebug.Print r.Count & \" \" & r.Cells.Count & \" \" & r.Areas.Count\n\
         Debug.Print r.Areas(2).Address & \" \" & r.Rows.Count & \" \" & r.Columns.Count\n\
         Debug.Print r.Row & \" \" & r.Column & \" \" & TypeName(r) & \" \" & TypeName(r.Areas)\n\
         Debug.Print Range(\"A1\").Areas.Count & \" \" & Range(\"A1\").Areas(1).Address",
    );
    assert_eq!(printed, ["$C$5:$D$9,$G$9:$H$16", "26 26 2", "$G$9:$H$16 5 2", "5 3 Range Areas", "1 $A$1"]);
}

// "Range property": `Range(Cell1, Cell2)` is the range from one corner to the other — the
// rectangle holding both, one area — where `Range("A1:B2,D4")` is two areas.
#[test]
fn two_corners_are_one_rectangle_and_a_list_is_several_areas() {
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "Debug.Print Range(\"A1:B2\", \"D4\").Address & \" \" & Range(\"A1:B2\", \"D4\").Areas.Count\n\
         Debug.Print Range(\"A1:B2,D4\").Address & \" \" & Range(\"A1:B2,D4\").Areas.Count",
    );
    assert_eq!(printed, ["$A$1:$D$4 1", "$A$1:$B$2,$D$4 2"]);
}

// "Application.Union method": the union of separate cells is one Range of two areas;
// "Application.Intersect method": the cells the ranges share, here one cell of each area
// (B1 of A1:B2, D1 of D1:E2), and Nothing when they share none.
#[test]
fn union_and_intersect_of_separate_areas() {
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "Dim u As Range\nSet u = Union(Range(\"A1\"), Range(\"C3\"))\n\
         Debug.Print u.Address & \" \" & u.Count & \" \" & u.Areas.Count\n\
         Set u = Application.Union(Range(\"A1:B2\"), Range(\"D1:E2\"))\n\
         Debug.Print Intersect(u, Range(\"B1:D1\")).Address\n\
         Debug.Print CStr(Intersect(u, Range(\"C5\")) Is Nothing)\n\
         Set u = Nothing\nDim c As Range\n\
         For Each c In Range(\"A1:A4\")\n\
         If u Is Nothing Then Set u = c Else Set u = Union(u, c)\nNext\n\
         Debug.Print u.Address",
    );
    assert_eq!(printed, ["$A$1,$C$3 2 2", "$B$1,$D$1", "True", "$A$1:$A$4"]);
}

// "For Each...Next statement" over a Range goes through its cells; of several areas, area by
// area ("Range.Areas property"). `.Value =` fills every area, `.ClearContents` clears every
// area, and `.Value` reads the first area's, as a multiple selection's does.
#[test]
fn each_area_is_written_cleared_and_walked() {
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "Range(\"A1:D4\").Value = 7\nRange(\"B2,A1:A2\").Value = 1\n\
         Range(\"D1,D3:D4\").ClearContents\n\
         Dim c As Range, s As String\n\
         For Each c In Range(\"B2,A1:A2\")\n    s = s & c.Address(False, False) & \"=\" & c.Value & \" \"\nNext\n\
         Debug.Print s\n\
         Debug.Print Range(\"C1,A1\").Value & \" \" & WorksheetFunction.Sum(Range(\"A1:A2,C1:C2\"))",
    );
    assert_eq!(printed, ["B2=1 A1=1 A2=1 ", "7 16"]);
    assert_eq!(get(&wb, "D1"), Value::Blank);
    assert_eq!(get(&wb, "D2"), n(7.0));
    assert_eq!(get(&wb, "D4"), Value::Blank);
    assert_eq!(get(&wb, "A3"), n(7.0));
}

// The macro that collects rows with Union and deletes them at once ("Range.EntireRow
// property", "Range.Delete method"): rows 2 and 4 of 1..5 go, 1, 3 and 5 move up.
#[test]
fn rows_collected_by_union_are_deleted_together() {
    let mut wb = Workbook::with_sheet();
    for r in 1..=5 {
        set(&mut wb, &format!("A{r}"), &r.to_string());
    }
    let printed = run_main(
        &mut wb,
        "Dim u As Range\nSet u = Union(Range(\"A2\"), Range(\"B4\"))\n\
         Debug.Print u.EntireRow.Address\nu.EntireRow.Delete",
    );
    assert_eq!(printed, ["$2:$2,$4:$4"]);
    assert_eq!(
        [get(&wb, "A1"), get(&wb, "A2"), get(&wb, "A3"), get(&wb, "A4")],
        [n(1.0), n(3.0), n(5.0), Value::Blank]
    );
}

// "Range.Copy method" on a multiple selection of areas that are not one block: Excel's "This
// action won't work on multiple selections", run-time error 1004, which On Error traps. A
// member ncsheet does not do to several areas is refused naming it, never done to one area.
#[test]
fn what_excel_refuses_on_several_areas_is_refused() {
    let mut wb = Workbook::with_sheet();
    let printed =
        run_main(&mut wb, "On Error Resume Next\nRange(\"A1,C3\").Copy Range(\"E1\")\nDebug.Print CStr(Err.Number)");
    assert_eq!(printed, ["1004"]);
    let message = main_fails(&mut wb, "Range(\"A1,C3\").Resize(2, 2).Value = 1");
    assert!(message.contains("Resize") && message.contains("several areas"), "{message}");
}

// "Range.Select method" of a Range of several areas makes "a multiple-area selection"
// ("Range.Areas property"): Selection is every area (its Address lists them, Areas.Count 2),
// the active cell the first area's first cell, and `Selection.Value = 9` fills every area as a
// multiple selection's value does. `Union(...).Select` the same.
#[test]
fn a_range_of_several_areas_is_selected_whole() {
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "Range(\"A1:B2,D4:E5\").Select\n\
         Debug.Print Selection.Address & \" \" & Selection.Areas.Count & \" \" & ActiveCell.Address\n\
         Union(Range(\"C1\"), Range(\"C3\")).Select\n\
         Selection.Value = 9\n\
         Debug.Print Selection.Address & \" \" & Selection.Count & \" \" & ActiveCell.Address",
    );
    assert_eq!(printed, ["$A$1:$B$2,$D$4:$E$5 2 $A$1", "$C$1,$C$3 2 $C$1"]);
    assert_eq!((get(&wb, "C1"), get(&wb, "C2"), get(&wb, "C3")), (n(9.0), Value::Blank, n(9.0)));
}
