//! Macros reading and writing the workbook: writes are seen by later reads, formulas
//! recalculate, names and other sheets are reachable as a VBA user reaches them.

mod common;

use common::sheet::{get_on as get, n, set_on as set};
use common::vba::run_main as run;
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

#[test]
fn a_write_is_seen_by_the_formulas_that_read_it() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "2");
    set(&mut wb, 0, "A2", "=A1*3");
    let printed = run(
        &mut wb,
        "    Debug.Print \"\" & Range(\"A2\").Value\n    Range(\"A1\").Value = 10\n\
         \x20   Debug.Print \"\" & Range(\"A2\").Value & \" \" & Range(\"A2\") + 1",
    );
    assert_eq!(printed, ["6", "30 31"]);
    assert_eq!(get(&wb, 0, "A2"), n(30.0));
}

#[test]
fn values_are_written_as_if_typed() {
    let mut wb = Workbook::with_sheet();
    run(&mut wb, "    Range(\"A1\").Value = \"12\"\n    Range(\"A2\").Value = \"=A1+1\"\n    Range(\"A3\") = True");
    // As in Excel's VBA: numeric text becomes a number, "=…" a formula.
    assert_eq!(get(&wb, 0, "A1"), n(12.0));
    assert_eq!(get(&wb, 0, "A2"), n(13.0));
    assert_eq!(get(&wb, 0, "A3"), Value::Bool(true));
}

#[test]
fn formula_property_reads_and_writes_formula_text() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "4");
    set(&mut wb, 0, "A2", "5");
    let printed = run(
        &mut wb,
        "    Range(\"B1\").Formula = \"=A1+1\"\n    Debug.Print Range(\"B1\").Formula & \" \" & Range(\"B1\").Value\n\
         \x20   Range(\"C1:C2\").Formula = \"=A1*2\"\n    Range(\"D1:E2\").Formula = \"=$A$1+A1\"",
    );
    assert_eq!(printed, ["=A1+1 5"]);
    // Filling a range moves relative references along, as VBA's Range.Formula does.
    assert_eq!(wb.formula(0, parse_cell("C2").unwrap()).as_deref(), Some("=A2*2"));
    assert_eq!(get(&wb, 0, "C2"), n(10.0));
    // Across columns too, absolute references staying: E1 is $A$1 + B1 = 4 + 5, D2 $A$1 + A2.
    assert_eq!(wb.formula(0, parse_cell("E1").unwrap()).as_deref(), Some("=$A$1+B1"));
    assert_eq!(get(&wb, 0, "E1"), n(9.0));
    assert_eq!(wb.formula(0, parse_cell("D2").unwrap()).as_deref(), Some("=$A$1+A2"));
    assert_eq!(get(&wb, 0, "D2"), n(9.0));
}

#[test]
fn cells_by_row_and_column() {
    let mut wb = Workbook::with_sheet();
    let printed = run(
        &mut wb,
        "    Dim i\n    For i = 1 To 3\n        Cells(i, 2).Value = i * 10\n    Next\n\
         \x20   Debug.Print Cells(3, \"B\").Value & \" \" & Cells(2, 2).Address & \" \" & Range(\"B1:B3\").Cells(2, 1).Value",
    );
    assert_eq!(printed, ["30 $B$2 20"]);
    assert_eq!(get(&wb, 0, "B1"), n(10.0));
}

#[test]
fn worksheets_by_name_and_number_and_as_object_variables() {
    let mut wb = Workbook::with_sheet();
    let data = wb.add_sheet("Data").unwrap();
    set(&mut wb, data, "A1", "21");
    let printed = run(
        &mut wb,
        "    Dim ws\n    Set ws = Worksheets(\"Data\")\n    ws.Range(\"B1\").Value = ws.Range(\"A1\").Value * 2\n\
         \x20   Worksheets(1).Range(\"A1\") = Sheets(\"Data\").Cells(1, 2)\n\
         \x20   Debug.Print ws.Name & \" \" & Worksheets.Count & \" \" & ActiveSheet.Name",
    );
    assert_eq!(printed, ["Data 2 Sheet1"]);
    assert_eq!(get(&wb, data, "B1"), n(42.0));
    assert_eq!(get(&wb, 0, "A1"), n(42.0));
}

#[test]
fn brackets_evaluate_formula_text_as_in_a_cell() {
    let mut wb = Workbook::with_sheet();
    let data = wb.add_sheet("Data").unwrap();
    set(&mut wb, data, "A1", "3");
    let printed = run(&mut wb, "    [B3] = 4\n    Debug.Print [B3] * [Data!A1] & \" \" & [SUM(B3, Data!A1)]");
    assert_eq!(printed, ["12 7"]);
    assert_eq!(get(&wb, 0, "B3"), n(4.0));
}

// "Application.Evaluate method": "Using square brackets (for example, "[A1:C5]") is identical
// to calling the Evaluate method with a string argument", and Evaluate of a reference gives a
// Range, so `[A1].NumberFormat` is `Range("A1").NumberFormat` (issue 31). The values follow from
// the members' pages: "Range.Text" shows the number in its format (7 in "0.00" is 7.00),
// "Range.Count" of A1:B2 is 4, "Range.Offset" (1, 0) of A1 is A2, "Range.Copy" with
// Destination writes D1:E2.
#[test]
fn a_bracket_followed_by_members_is_the_range_it_names() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("Start", "=Sheet1!$B$1", None).unwrap();
    let printed = run(
        &mut wb,
        "    [A1:B2].Value = 7\n    [A1].NumberFormat = \"0.00\"\n\
         \x20   Debug.Print [A1].Text & \" \" & [A1:B2].Count & \" \" & [A1].Offset(1, 0).Address\n\
         \x20   [A1:B2].Copy Destination:=[D1]\n    [Start].Offset(2, 0).Value = [D2].Value + 1\n\
         \x20   [D2].ClearContents\n    Debug.Print [ A1 : B2 ].Rows.Count & \" \" & IsEmpty([D2].Value)",
    );
    assert_eq!(printed, ["7.00 4 $A$2", "2 True"]);
    assert_eq!(get(&wb, 0, "E1"), n(7.0));
    assert_eq!(get(&wb, 0, "B3"), n(8.0));
}

#[test]
fn defined_names_through_range_brackets_and_evaluate() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("D", "=Sheet1!$B$2", None).unwrap();
    wb.define_name("XA", "=Sheet1!$B$9", None).unwrap();
    set(&mut wb, 0, "B2", "40");
    let printed = run(
        &mut wb,
        "    Dim D\n    D = 1\n    Range(\"XA\").Value = Range(\"D\").Value + D\n\
         \x20   Debug.Print [XA] & \" \" & Evaluate(\"XA*2\") & \" \" & IsObject(Evaluate(\"XA\")) & IsObject(Evaluate(\"nope\"))",
    );
    // A macro variable D and the workbook's name D are different things, as in VBA; IsObject's
    // Booleans joined with & are "True"/"False" ("& operator").
    assert_eq!(printed, ["41 82 TrueFalse"]);
    assert_eq!(get(&wb, 0, "B9"), n(41.0));
}

#[test]
fn for_each_cell_of_a_range() {
    let mut wb = Workbook::with_sheet();
    for (i, v) in ["1", "2", "3", "4"].iter().enumerate() {
        set(&mut wb, 0, &format!("A{}", i + 1), v);
    }
    let printed = run(
        &mut wb,
        "    Dim c, total\n    For Each c In Range(\"A1:A4\")\n        total = total + c.Value\n\
         \x20       c.Offset(0, 1).Value = c * c\n    Next c\n    Debug.Print \"\" & total",
    );
    assert_eq!(printed, ["10"]);
    assert_eq!(get(&wb, 0, "B4"), n(16.0));
}

#[test]
fn range_members() {
    let mut wb = Workbook::with_sheet();
    let printed = run(
        &mut wb,
        "    Dim r\n    Set r = Range(\"B2:D5\")\n\
         \x20   Debug.Print r.Row & \" \" & r.Column & \" \" & r.Count & \" \" & r.Rows.Count & \" \" & r.Columns.Count\n\
         \x20   Debug.Print r.Offset(1, 1).Address & \" \" & r.Resize(1, 2).Address & \" \" & Range(Cells(1, 1), Cells(2, 3)).Address\n\
         \x20   r.Value = 1\n    Debug.Print \"\" & Application.WorksheetFunction.Sum(r)\n    r.ClearContents\n\
         \x20   Debug.Print \"\" & WorksheetFunction.Sum(Range(\"B2:D5\"))",
    );
    assert_eq!(printed, ["2 2 12 4 3", "$C$3:$E$6 $B$2:$C$2 $A$1:$C$2", "12", "0"]);
}

#[test]
fn a_range_passed_to_a_function_stays_a_range() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "5");
    set(&mut wb, 0, "A2", "7");
    let src =
        "Function Total(r)\n    Dim c\n    For Each c In r\n        Total = Total + c.Value\n    Next\nEnd Function\n\
               Sub Main()\n    Debug.Print \"\" & Total(Range(\"A1:A2\"))\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["12"]);
}

#[test]
fn the_active_sheet_comes_from_the_options_and_activate() {
    let mut wb = Workbook::with_sheet();
    let data = wb.add_sheet("Data").unwrap();
    let src =
        "Sub Main()\n    Range(\"A1\") = 1\n    Worksheets(\"Sheet1\").Activate\n    Range(\"A1\") = 2\nEnd Sub\n";
    let options = RunOptions { sheet: Some("Data".into()), ..RunOptions::default() };
    vba::run(&mut wb, src, "t.bas", &options).unwrap();
    assert_eq!(get(&wb, data, "A1"), n(1.0));
    assert_eq!(get(&wb, 0, "A1"), n(2.0));
}

/// `FormulaR1C1` (Excel's R1C1 notation: `R[n]`/`C[n]` offsets from the formula's cell, `Rn`/
/// `Cn` absolute rows and columns, a bare `R`/`C` the cell's own): written into a range, each
/// cell gets the same R1C1 formula, which is a relative fill in A1 terms; read back in either
/// notation. Expected A1 texts and values are worked out by hand.
#[test]
fn formula_r1c1_writes_and_reads_the_same_tree_as_a1() {
    let mut wb = Workbook::with_sheet();
    let printed = run(
        &mut wb,
        "    Range(\"A1:A3\").Value = 5\n\
         \x20   Range(\"A2\").Value = 7\n\
         \x20   Range(\"B2:B3\").FormulaR1C1 = \"=R[-1]C[-1]*2+R1C1\"\n\
         \x20   Range(\"C1:C3\").Formula = \"=A1+B$2\"\n\
         \x20   Range(\"E1\").FormulaR1C1 = \"=SUM(R1C1:R3C1)+SUM(C1)+COUNT(R2)\"\n\
         \x20   Debug.Print Range(\"B2\").Formula; \" \"; Range(\"B3\").Formula\n\
         \x20   Debug.Print Range(\"C3\").FormulaR1C1; \" \"; Range(\"E1\").Formula\n\
         \x20   Debug.Print Range(\"A1\").FormulaR1C1; \" \"; Range(\"D9\").FormulaR1C1; \"|\"",
    );
    assert_eq!(printed, ["=A1*2+$A$1 =A2*2+$A$1", "=RC[-2]+R2C[-1] =SUM($A$1:$A$3)+SUM($A:$A)+COUNT($2:$2)", "5 |"]);
    // B2 = A1*2 + A1 = 15, B3 = A2*2 + A1 = 19, C3 = A3 + B2 = 20; E1 = 17 + 17 + 3 (row 2:
    // A2, B2, C2 are numbers).
    assert_eq!(get(&wb, 0, "B2"), n(15.0));
    assert_eq!(get(&wb, 0, "B3"), n(19.0));
    assert_eq!(get(&wb, 0, "C3"), n(20.0));
    assert_eq!(get(&wb, 0, "E1"), n(37.0));
}

#[test]
fn a_bad_r1c1_formula_is_an_error_naming_the_notation() {
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n    Range(\"A1\").FormulaR1C1 = \"=R0C1\"\nEnd Sub\n";
    let err = vba::run(&mut wb, src, "r1c1.bas", &RunOptions::default()).unwrap_err().to_string();
    assert!(err.contains("r1c1.bas:2:") && err.contains("(R1C1)") && err.contains("R0 is off the sheet"), "{err}");
}

/// `ActiveCell` starts at A1 (a new workbook); `Range.Select` makes the range the selection
/// and its first cell the active cell; `Activate` of a cell inside the selection moves only
/// the active cell (Excel's behaviour); `Offset` goes from the active cell. "Select works only
/// on the active worksheet ... the Select method will fail unless your procedure activates the
/// worksheet before using the Select method on a range of cells" ("Selecting and Activating
/// Cells"): run-time error 1004, the active sheet unchanged, until the sheet is activated.
#[test]
fn active_cell_and_selection_follow_select_and_activate() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Two").unwrap();
    let printed = run(
        &mut wb,
        "    Debug.Print ActiveCell.Address & \" \" & ActiveCell.Row & \" \" & ActiveCell.Column\n\
         \x20   Range(\"B2\").Select\n\
         \x20   ActiveCell.Offset(1, 1).Value = \"off\"\n\
         \x20   ActiveCell.Value = 3\n\
         \x20   Range(\"B2:C3\").Select\n\
         \x20   Range(\"C3\").Activate\n\
         \x20   Debug.Print Selection.Address; \" \"; ActiveCell.Address; \" \"; ActiveCell.Value\n\
         \x20   Range(\"E5\").Activate\n\
         \x20   Debug.Print Selection.Address; \" \"; ActiveCell.Address\n\
         \x20   On Error Resume Next\n\
         \x20   Worksheets(\"Two\").Range(\"D4\").Select\n\
         \x20   Debug.Print Err.Number; ActiveSheet.Name; \" \"; ActiveCell.Address\n\
         \x20   On Error GoTo 0\n\
         \x20   Worksheets(\"Two\").Activate\n\
         \x20   Worksheets(\"Two\").Range(\"D4\").Select\n\
         \x20   ActiveCell.Value = ActiveSheet.Name",
    );
    assert_eq!(printed, ["$A$1 1 1", "$B$2:$C$3 $C$3 off", "$E$5 $E$5", " 1004 Sheet1 $E$5"]);
    assert_eq!(get(&wb, 0, "B2"), n(3.0));
    assert_eq!(get(&wb, 1, "D4"), Value::text("Two"));
}

// "Sheets.Add method" (Excel VBA reference): "Creates a new worksheet … The new worksheet
// becomes the active sheet"; its return value "represents the new worksheet"; After is "the
// sheet after which the new sheet is added". "Worksheet.Name property" renames the sheet,
// and formulas that refer to it follow (Excel keeps references to the sheet, not its name).
// A new sheet of a workbook holding Sheet1 is named Sheet2.
#[test]
fn sheets_add_after_the_last_sheet_returns_it_and_name_renames_it() {
    let mut wb = Workbook::with_sheet();
    let printed = run(
        &mut wb,
        "    Dim ws As Worksheet\n    Set ws = Sheets.Add(After:=Sheets(Sheets.Count))\n\
         \x20   Debug.Print ws.Name; ActiveSheet.Name; ws.Index; Worksheets.Count\n\
         \x20   Sheets(1).Range(\"A1\").Formula = \"=Sheet2!B1*2\"\n    ws.Name = \"GCode\"\n    ws.Range(\"B1\").Value = 21\n\
         \x20   Worksheets.Add After:=Worksheets(\"GCode\")\n    Debug.Print ActiveSheet.Name; Sheets(3).Name\n\
         \x20   Debug.Print Worksheets(\"gcode\").Range(\"B1\").Value; Sheets(1).Range(\"A1\").Value",
    );
    assert_eq!(printed, ["Sheet2Sheet2 2  2 ", "Sheet3Sheet3", " 21  42 "]);
    assert_eq!(wb.sheet_names(), ["Sheet1", "GCode", "Sheet3"]);
    assert_eq!(wb.formula(0, parse_cell("A1").unwrap()).as_deref(), Some("=GCode!B1*2"));
}

// "Rename a worksheet" (Excel help): a name is at most 31 characters, not blank, without
// : \ / ? * [ ], and not another sheet's: run-time error 1004. (Where `Sheets.Add` puts a
// sheet: tests/vba_sheet_order.rs.)
#[test]
fn bad_sheet_names_are_refused() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Data").unwrap();
    let printed = run(
        &mut wb,
        "    On Error Resume Next\n    For Each n In Array(\"Data\", \"a/b\", \"\", String(32, \"x\"), \"'q\")\n\
         \x20   Err.Clear\n        Sheets(1).Name = n\n        s = s & Err.Number & \",\"\n    Next\n\
         \x20   Debug.Print s; Sheets(1).Name",
    );
    assert_eq!(printed, ["1004,1004,1004,1004,1004,Sheet1"]);
}

// "Workbook.Name property": the workbook's name, its file name with the extension.
#[test]
fn workbook_name_is_the_file_name() {
    let mut wb = Workbook::with_sheet();
    let options = RunOptions { workbook_name: Some("Parts.xlsm".into()), ..RunOptions::default() };
    let out = vba::run(&mut wb, "Sub Main()\n    Debug.Print ThisWorkbook.Name\nEnd Sub\n", "m.bas", &options).unwrap();
    assert_eq!(out.printed, ["Parts.xlsm"]);
}

// "Worksheet.Copy method": "Copies the sheet to another location in the current workbook"
// After the sheet named; the copy holds the same cells and formulas (a reference to the
// original sheet still points there) and is named as Excel names a copy, "Sheet1 (2)";
// "If you don't specify either Before or After, Microsoft Excel creates a new workbook",
// which a run has not: refused.
#[test]
fn worksheet_copy_after_the_last_sheet_copies_cells_and_formulas() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "2");
    set(&mut wb, 0, "A2", "=A1*3");
    set(&mut wb, 0, "B1", "=Sheet1!A1+1");
    let printed = run(
        &mut wb,
        "    Sheets(\"Sheet1\").Copy After:=Sheets(Sheets.Count)\n    Debug.Print ActiveSheet.Name; Sheets.Count\n\
         \x20   Sheets(1).Range(\"A1\").Value = 5\n\
         \x20   Debug.Print Sheets(2).Range(\"A2\").Value; Sheets(2).Range(\"B1\").Value",
    );
    assert_eq!(printed, ["Sheet1 (2) 2 ", " 6  6 "]);
    assert_eq!(wb.formula(1, parse_cell("A2").unwrap()).as_deref(), Some("=A1*3"));
    let e =
        vba::run(&mut wb, "Sub Main()\n    Sheets(1).Copy\nEnd Sub\n", "m.bas", &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("new workbook"), "{e}");
}

/// Deleting the last used column or row takes it out of `UsedRange` ("Worksheet.UsedRange
/// property": the used range of the sheet; the deleted cells are gone, and the cells left
/// lie in A1:B2, then A1:B1). The range only grew before, so a macro walking
/// `UsedRange.Columns.Count` after a delete indexed past its array (a real subtotals module).
#[test]
fn used_range_shrinks_when_its_last_column_or_row_is_deleted() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Range(\"A1:C2\").Value = 1\n    Debug.Print ActiveSheet.UsedRange.Address\n    Columns(\"C\").Delete\n    \
         Debug.Print ActiveSheet.UsedRange.Address\n    Rows(2).Delete\n    Debug.Print ActiveSheet.UsedRange.Address; \
         ActiveSheet.UsedRange.Columns.Count",
    );
    assert_eq!(printed, vec!["$A$1:$C$2", "$A$1:$B$2", "$A$1:$B$1 2 "]);
}

/// Inserting a row inside the used cells moves those below it down by one ("Range.Insert
/// method"), so data in A1:H9 lies in A1:H10 and `UsedRange` is "$A$1:$H$10"; a row inserted
/// below the data moves no cell and leaves it as it was. The extent was moved once by the
/// cells written at their new rows and once more by the insert, so a real subtotals module
/// that inserted three rows saw $A$1:$H$13 where Excel gives $A$1:$H$12.
#[test]
fn used_range_grows_by_the_rows_inserted_inside_it_only() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Range(\"A1:H9\").Value = 1\n    Rows(3).Insert Shift:=xlDown\n    \
         Debug.Print ActiveSheet.UsedRange.Address\n    Rows(30).Insert\n    \
         Debug.Print ActiveSheet.UsedRange.Address\n    Columns(\"B\").Insert\n    \
         Debug.Print ActiveSheet.UsedRange.Address",
    );
    assert_eq!(printed, vec!["$A$1:$H$10", "$A$1:$H$10", "$A$1:$I$10"]);
}

/// `UsedRange` starts at the first used cell, not at A1: Microsoft's "Worksheet.UsedRange
/// property" returns the range used on the sheet, so data only in C3:E9 is "$C$3:$E$9", whose
/// `Row` is 3 and `Rows.Count` 7. A cell given a format or a font of its own is used as
/// well (Excel's used range takes in formatted cells: G12, then B2).
#[test]
fn used_range_starts_at_the_first_used_cell_and_takes_in_formatted_cells() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Range(\"C3\").Value = 1\n    Range(\"E9\").Value = 2\n    With ActiveSheet.UsedRange\n        \
         Debug.Print .Address; .Row; .Column; .Rows.Count; .Columns.Count\n    End With\n    \
         Range(\"G12\").NumberFormat = \"0.00\"\n    Debug.Print ActiveSheet.UsedRange.Address\n    \
         Range(\"B2\").Font.Bold = True\n    Debug.Print ActiveSheet.UsedRange.Address\n    \
         Rows(\"1:2\").Delete\n    Debug.Print ActiveSheet.UsedRange.Address",
    );
    // After the delete the values are in C1:E7 and the format in G10 (B2's row is gone).
    assert_eq!(printed, vec!["$C$3:$E$9 3  3  7  3 ", "$C$3:$G$12", "$B$2:$G$12", "$C$1:$G$10"]);
}

/// Microsoft's "Range.Range property": "When applied to a Range object, the property is
/// relative to the Range object"; "The Range Property" (Office XP developer's guide, aa671846):
/// `Range("B5").Range("B5")` is C9, "n columns to the right and y rows down from the specified
/// cell". So A3 read from B2:D6 is B4, A1:B2 its four top-left cells, and a list of areas
/// moves area by area. The page's example `.Range(.Cells(1, 1), .Cells(5, 3))` of B2:Z22 is
/// B2:D6: Range objects given as corners stay where they are. The macro recorder's relative
/// references (`ActiveCell.Offset(1, 0).Range("A1").Select`) are this property of an Offset.
#[test]
fn range_of_a_range_reads_its_address_from_the_range_s_top_left_cell() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Debug.Print Range(\"B2:D6\").Range(\"A3\").Address & \" \" & Range(\"B5\").Range(\"B5\").Address\n    \
         Debug.Print Range(\"B2:Z22\").Range(\"A1:B2\").Address & \" \" & Range(\"B2\").Range(\"A1,C3\").Address\n    \
         With Range(\"B2:Z22\")\n        Debug.Print .Range(.Cells(1, 1), .Cells(5, 3)).Address\n    End With\n    \
         Range(\"C3\").Select\n    ActiveCell.Offset(1, 0).Range(\"A1\").Select\n    \
         Debug.Print Selection.Range(\"B1\").Address & \" \" & ActiveCell.Address\n    \
         Range(\"B2:D6\").Range(\"A1:B2\").Value = 5\n    Debug.Print \"\" & Application.Sum(Range(\"A1:E7\"))",
    );
    assert_eq!(printed, ["$B$4 $C$9", "$B$2:$C$3 $B$2,$D$4", "$B$2:$D$6", "$D$4 $C$4", "20"]);
}

/// `r.Range(...)` runs off the sheet or onto another sheet: a failing Range, run-time error
/// 1004, which On Error traps as Excel's is.
#[test]
fn range_of_a_range_off_the_sheet_is_error_1004() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    On Error Resume Next\n    Dim r As Range\n    Set r = Range(\"B2\").Range(\"A:A\")\n    \
         Debug.Print Err.Number & \" \" & CStr(r Is Nothing)",
    );
    assert_eq!(printed, ["1004 True"]);
}

/// Microsoft's "Range.Item property": `someRange(1)` is `someRange.Item(1)`; one index walks
/// the first area "left to right before top to bottom", past its cells "as if the area was
/// extended downward" (B2:D6's 4th cell B3, B2:C3's 5th B4); `Item(3, 3)` of B2:C3 is D4, a
/// column may be letters ("AA" 27), and the offsets are from the first area's top-left
/// (Union(Z4:AA6, A1:C3)(1, 1) is $Z$4). The page gives no rule for a row left out
/// (`r(, j)`): it is the range's first row, as the modules that write it expect
/// (`qty = r.Cells(, 1)` for each of a table's `.Rows`, `Split(Cells(, lc).Address, "$")(1)`).
#[test]
fn item_of_a_range_by_one_index_by_row_and_column_and_with_the_row_left_out() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Dim r As Range\n    Set r = Range(\"B2:D6\")\n    \
         Debug.Print r.Item(2).Address & \" \" & r(3).Address & \" \" & r(4).Address & \" \" & Range(\"B2:C3\")(5).Address\n    \
         Debug.Print Range(\"B2:C3\").Item(3, 3).Address & \" \" & r(1, \"AA\").Address & \" \" & \
         Union(Range(\"Z4:AA6\"), Range(\"A1:C3\"))(1, 1).Address\n    \
         Debug.Print r(, 2).Address & \" \" & r.Cells(, 3).Address & \" \" & r.Rows(3).Cells(, 1).Address",
    );
    assert_eq!(printed, ["$C$2 $D$2 $B$3 $B$4", "$D$4 $AB$2 $Z$4", "$C$2 $D$2 $B$4"]);
}

/// The same item read straight after the call that gives the range: `Range("B2:D6")(, 3)` is
/// `Range("B2:D6").Item(, 3)` ("Range.Item property", the row left out the first row as for
/// `r(, j)` above): $D$2, and `Range("B2:D6")(2, 3)` $D$3, `Cells(3, 2).Resize(2, 2)(, 2)`
/// $C$3. An array's index is no Range's: left out, it is "Argument not optional" (error 449,
/// Microsoft's page of that name), never the item at 0.
#[test]
fn item_with_the_row_left_out_straight_after_a_call() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Debug.Print Range(\"B2:D6\")(, 3).Address & \" \" & Range(\"B2:D6\")(2, 3).Address & \" \" & \
         Cells(3, 2).Resize(2, 2)(, 2).Address\n    \
         Dim v: v = Array(Array(1, 2), 3)\n    On Error Resume Next\n    \
         Debug.Print v(0)(, 1)\n    Debug.Print Err.Number",
    );
    assert_eq!(printed, ["$D$2 $D$3 $C$3", " 449 "]);
}
