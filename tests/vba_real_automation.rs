//! Constructs found by real public automation and G-code-writing modules (issue 31, session
//! 19's sample: inventory summaries, sheet sorters, report and G-code writers), each in a small
//! macro of our own with the result Microsoft's Excel VBA reference or [MS-VBAL] gives (the page
//! or section named at each test).

mod common;

use common::sheet::{get_on as get, n, set_on as set};
use common::vba::run_main as run;
use ncsheet::workbook::Workbook;

// "For Each...Next statement": the group is a collection; "Range.Rows property" (Excel):
// "Returns a Range object that represents the rows in the specified range", a collection of
// rows, each a Range as wide as the range; "Range.Columns property" likewise. So `For Each r In
// rng.Rows` visits each row once, `r.Row` its sheet row, `r.Cells.Count` its width.
#[test]
fn for_each_goes_through_the_rows_and_columns_of_a_range() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("B2", "1"), ("C2", "2"), ("B3", "10"), ("C3", "20"), ("B4", "100"), ("C4", "200")] {
        set(&mut wb, 0, cell, v);
    }
    let printed = run(
        &mut wb,
        "    Dim r As Range, c As Range, s As String\n\
         \x20   For Each r In Range(\"B2:C4\").Rows\n\
         \x20       s = s & r.Row & \":\" & r.Cells.Count & \":\" & WorksheetFunction.Sum(r) & \" \"\n\
         \x20   Next r\n\
         \x20   For Each c In Range(\"B2:C4\").Columns\n\
         \x20       s = s & c.Column & \"/\" & c.Rows.Count & \"/\" & c.Cells(3, 1).Value & \" \"\n\
         \x20       c.Cells(4, 1).Value = WorksheetFunction.Sum(c)\n\
         \x20   Next\n\
         \x20   Debug.Print s",
    );
    assert_eq!(printed, ["2:2:3 3:2:30 4:2:300 2/3/100 3/3/200 "]);
    assert_eq!((get(&wb, 0, "B5"), get(&wb, 0, "C5")), (n(111.0), n(222.0)));
}

// "Range.Rows property": the rows of a range of whole rows (`Rows("2:3")`) are whole rows,
// "$2:$2" as "Range.Address property" writes one.
#[test]
fn for_each_row_of_whole_rows_is_a_whole_row() {
    let mut wb = Workbook::with_sheet();
    let printed =
        run(&mut wb, "    Dim r\n    For Each r In Rows(\"2:3\").Rows\n        Debug.Print r.Address\n    Next");
    assert_eq!(printed, ["$2:$2", "$3:$3"]);
}
