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

// "Range.HasFormula property" (Excel): "True if all cells in the range contain formulas; False
// if none of the cells in the range contains a formula; null otherwise." A find-and-replace
// module walks the used range asking `cl.HasFormula()` before it rewrites `cl.Formula`.
#[test]
fn has_formula_is_true_for_all_false_for_none_and_null_for_some() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "1"), ("A2", "=A1*2"), ("B1", "=A1"), ("B2", "=A2+1")] {
        set(&mut wb, 0, cell, v);
    }
    let printed = run(
        &mut wb,
        "    Debug.Print Range(\"A1\").HasFormula & \" \" & Range(\"A2\").HasFormula & \" \" & Cells(2, 1).HasFormula()\n\
         \x20   Debug.Print IsNull(Range(\"A1:A2\").HasFormula) & \" \" & Range(\"B1:B2\").HasFormula & \" \" & Range(\"C1:C9\").HasFormula\n\
         \x20   Debug.Print IsNull(Range(\"A1:B3\").HasFormula) & \" \" & IsNull(Columns(2).HasFormula) & \" \" & IsNull(Cells.HasFormula)",
    );
    assert_eq!(printed, ["False True True", "True True False", "True True True"]);
}
