//! Inserting and deleting rows, columns and cells (`Workbook::shift_cells`, and VBA's
//! `Range.Delete`, `Range.Insert`, `EntireRow`, `Rows(n)`, `Columns(..)`), with every
//! reference of the workbook following the cells.
//!
//! The expected formulas are LibreOffice 7.4's: the probe book below was built in a
//! headless LibreOffice, each edit made with the sheet's own `removeRange` / `insertCells`
//! (modes ROWS, UP, DOWN, LEFT, COLUMNS), and the formulas and values read back (LibreOffice writes a
//! deleted reference as `A#REF!`, Excel and we as `#REF!`: the values are compared there).
//! Excel's rules for names agree (J. Walkenbach, "Excel 2007 Formulas", "How Excel Maintains
//! Cell and Range Names": a name's range moves with inserted or deleted rows above it, grows
//! with a row inserted inside it, and is `#REF!` once all its rows are deleted). Microsoft's
//! Range.Delete page, for the macros: "If this argument is omitted, Microsoft Excel decides
//! based on the shape of the range."

mod common;

use common::vba::run_main as run;
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::{parse_cell, Pos, Rect};
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::{Axis, SheetEdit, Workbook};

fn at(cell: &str) -> Pos {
    parse_cell(cell).unwrap()
}

fn set(wb: &mut Workbook, sheet: u16, cell: &str, input: &str) {
    wb.set_input(sheet, at(cell), input).unwrap();
}

/// Sheet1: A1:A10 = 1..10, B1:B10 = 100..1000, formulas in C1:C12; Sheet2 reading Sheet1;
/// the name MyR = Sheet1!$A$5:$A$8.
fn probe_book() -> Workbook {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Sheet2").unwrap();
    for i in 1..=10 {
        set(&mut wb, 0, &format!("A{i}"), &i.to_string());
        set(&mut wb, 0, &format!("B{i}"), &(100 * i).to_string());
    }
    let formulas = [
        "=SUM(A1:A10)",
        "=A5",
        "=$A$7",
        "=A3",
        "=SUM(A3:A4)",
        "=SUM(A2:A3)",
        "=SUM(A4:A6)",
        "=B3",
        "=SUM(A1:B10)",
        "=SUM(A:A)",
        "=SUM(A3:A4)+A4",
        "=A$2+$A3",
    ];
    for (i, f) in formulas.iter().enumerate() {
        set(&mut wb, 0, &format!("C{}", i + 1), f);
    }
    wb.define_name("MyR", "Sheet1!$A$5:$A$8", None).unwrap();
    set(&mut wb, 1, "A1", "=Sheet1!A5");
    set(&mut wb, 1, "A2", "=SUM(Sheet1!A1:A10)");
    set(&mut wb, 1, "A3", "=Sheet1!A3");
    set(&mut wb, 1, "A4", "=SUM(MyR)");
    wb
}

/// What a cell must hold after the edit: its formula as we print it (`None`: only the
/// value is compared, where LibreOffice's spelling of #REF! differs) and its value.
type Want = (u16, &'static str, Option<&'static str>, Value);

fn n(x: f64) -> Value {
    Value::Number(x)
}

fn bad() -> Value {
    Value::Error(XlError::Ref)
}

fn check(wb: &Workbook, edit: &str, wants: &[Want]) {
    for (sheet, cell, formula, value) in wants {
        let place = format!("{edit}: sheet {sheet} {cell}");
        if let Some(f) = formula {
            assert_eq!(wb.formula(*sheet, at(cell)).as_deref(), Some(*f), "{place}");
        }
        assert_eq!(&wb.value(*sheet, at(cell)), value, "{place}");
    }
}

fn name_formula(wb: &Workbook) -> String {
    wb.names().into_iter().find(|(n, _, _)| n == "MyR").unwrap().1
}

#[test]
fn deleting_whole_rows_moves_shrinks_and_breaks_references_as_libreoffice() {
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::rows(2, 2, false)).unwrap();
    check(
        &wb,
        "delete rows 3:4",
        &[
            (0, "C1", Some("=SUM(A1:A8)"), n(48.0)),
            (0, "C2", Some("=A3"), n(5.0)),
            // The old C5 (=SUM(A3:A4)): both rows deleted.
            (0, "C3", None, bad()),
            (0, "C4", Some("=SUM(A2:A2)"), n(2.0)),
            (0, "C5", Some("=SUM(A3:A4)"), n(11.0)),
            (0, "C6", None, bad()),
            (0, "C7", Some("=SUM(A1:B8)"), n(4848.0)),
            (0, "C8", Some("=SUM(A:A)"), n(48.0)),
            (0, "C9", None, bad()),
            (0, "C10", None, bad()),
            (0, "A3", None, n(5.0)),
            (0, "C11", None, Value::Blank),
            (1, "A1", Some("=Sheet1!A3"), n(5.0)),
            (1, "A2", Some("=SUM(Sheet1!A1:A8)"), n(48.0)),
            (1, "A3", None, bad()),
            (1, "A4", Some("=SUM(MyR)"), n(26.0)),
        ],
    );
    assert_eq!(name_formula(&wb), "=Sheet1!$A$3:$A$6");
}

#[test]
fn deleting_cells_shifted_up_moves_only_their_columns() {
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::cells(Rect::new(at("A3"), at("A4")), Axis::Rows, false)).unwrap();
    check(
        &wb,
        "delete A3:A4 shift up",
        &[
            (0, "C1", Some("=SUM(A1:A8)"), n(48.0)),
            (0, "C2", Some("=A3"), n(5.0)),
            (0, "C3", Some("=$A$5"), n(7.0)),
            (0, "C4", None, bad()),
            (0, "C5", None, bad()),
            (0, "C6", Some("=SUM(A2:A2)"), n(2.0)),
            (0, "C7", Some("=SUM(A3:A4)"), n(11.0)),
            // Column B did not move, and a range reaching outside column A stays.
            (0, "C8", Some("=B3"), n(300.0)),
            (0, "C9", Some("=SUM(A1:B10)"), n(5548.0)),
            (0, "C10", Some("=SUM(A:A)"), n(48.0)),
            (0, "C11", None, bad()),
            (0, "C12", None, bad()),
            (0, "A9", None, Value::Blank),
            (0, "B3", None, n(300.0)),
            (1, "A1", Some("=Sheet1!A3"), n(5.0)),
            (1, "A2", Some("=SUM(Sheet1!A1:A8)"), n(48.0)),
            (1, "A3", None, bad()),
            (1, "A4", Some("=SUM(MyR)"), n(26.0)),
        ],
    );
    assert_eq!(name_formula(&wb), "=Sheet1!$A$3:$A$6");
}

/// LibreOffice 7.4's probe book after rows 3:4 are inserted.
fn after_inserting_rows_3_4() -> Vec<Want> {
    vec![
        (0, "C1", Some("=SUM(A1:A12)"), n(55.0)),
        (0, "C2", Some("=A7"), n(5.0)),
        (0, "C3", None, Value::Blank),
        (0, "C5", Some("=$A$9"), n(7.0)),
        (0, "C6", Some("=A5"), n(3.0)),
        (0, "C7", Some("=SUM(A5:A6)"), n(7.0)),
        (0, "C8", Some("=SUM(A2:A5)"), n(5.0)),
        (0, "C9", Some("=SUM(A6:A8)"), n(15.0)),
        (0, "C10", Some("=B5"), n(300.0)),
        (0, "C11", Some("=SUM(A1:B12)"), n(5555.0)),
        (0, "C12", Some("=SUM(A:A)"), n(55.0)),
        (0, "C13", Some("=SUM(A5:A6)+A6"), n(11.0)),
        (0, "C14", Some("=A$2+$A5"), n(5.0)),
        (1, "A1", Some("=Sheet1!A7"), n(5.0)),
        (1, "A2", Some("=SUM(Sheet1!A1:A12)"), n(55.0)),
        (1, "A3", Some("=Sheet1!A5"), n(3.0)),
        (1, "A4", Some("=SUM(MyR)"), n(26.0)),
    ]
}

#[test]
fn inserting_whole_rows_grows_the_ranges_they_fall_inside() {
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::rows(2, 2, true)).unwrap();
    check(&wb, "insert rows 3:4", &after_inserting_rows_3_4());
    assert_eq!(name_formula(&wb), "=Sheet1!$A$7:$A$10");
}

#[test]
fn inserting_cells_shifted_down_leaves_ranges_reaching_outside_the_band() {
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::cells(Rect::new(at("A3"), at("A4")), Axis::Rows, true)).unwrap();
    check(
        &wb,
        "insert A3:A4 shift down",
        &[
            (0, "C1", Some("=SUM(A1:A12)"), n(55.0)),
            (0, "C2", Some("=A7"), n(5.0)),
            (0, "C3", Some("=$A$9"), n(7.0)),
            (0, "C4", Some("=A5"), n(3.0)),
            (0, "C6", Some("=SUM(A2:A5)"), n(5.0)),
            (0, "C8", Some("=B3"), n(300.0)),
            (0, "C9", Some("=SUM(A1:B10)"), n(5536.0)),
            (0, "C12", Some("=A$2+$A5"), n(5.0)),
            (0, "A12", None, n(10.0)),
            (1, "A3", Some("=Sheet1!A5"), n(3.0)),
        ],
    );
}

#[test]
fn deleting_and_inserting_columns() {
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::columns(1, 1, false)).unwrap();
    check(
        &wb,
        "delete column B",
        &[
            (0, "B1", Some("=SUM(A1:A10)"), n(55.0)),
            (0, "B8", None, bad()),
            (0, "B9", Some("=SUM(A1:A10)"), n(55.0)),
            (0, "B12", Some("=A$2+$A3"), n(5.0)),
            (0, "C1", None, Value::Blank),
            (1, "A1", Some("=Sheet1!A5"), n(5.0)),
        ],
    );
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::columns(0, 1, true)).unwrap();
    check(
        &wb,
        "insert column A",
        &[
            (0, "C1", None, n(100.0)),
            (0, "D1", Some("=SUM(B1:B10)"), n(55.0)),
            (0, "D3", Some("=$B$7"), n(7.0)),
            (0, "D8", Some("=C3"), n(300.0)),
            (0, "D9", Some("=SUM(B1:C10)"), n(5555.0)),
            (0, "D10", Some("=SUM(B:B)"), n(55.0)),
            (0, "D12", Some("=B$2+$B3"), n(5.0)),
            (1, "A2", Some("=SUM(Sheet1!B1:B10)"), n(55.0)),
        ],
    );
    assert_eq!(name_formula(&wb), "=Sheet1!$B$5:$B$8");
}

#[test]
fn later_edits_reach_the_formulas_that_moved() {
    // The graph follows the edit: a value typed after it recomputes what reads it now.
    let mut wb = probe_book();
    wb.shift_cells(0, SheetEdit::rows(0, 1, false)).unwrap();
    set(&mut wb, 0, "A4", "1000");
    // C1 was C2 (=A5, now =A4).
    assert_eq!(wb.value(0, at("C1")), n(1000.0));
    assert_eq!(wb.value(1, at("A1")), n(1000.0));
}

#[test]
fn an_edit_cutting_through_an_array_is_refused_and_changes_nothing() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "=SEQUENCE(4)");
    set(&mut wb, 0, "B1", "7");
    let refused = wb.shift_cells(0, SheetEdit::rows(1, 1, false));
    let message = refused.unwrap_err().to_string();
    assert!(message.contains("Sheet1!A1"), "{message}");
    assert_eq!(wb.value(0, at("A4")), n(4.0));
    // Shifting the column beside it is fine, and so is deleting the rows the array is in.
    wb.shift_cells(0, SheetEdit::cells(Rect::new(at("B1"), at("B1")), Axis::Rows, false)).unwrap();
    assert_eq!(wb.value(0, at("B1")), Value::Blank);
    wb.shift_cells(0, SheetEdit::rows(0, 4, false)).unwrap();
    assert_eq!(wb.value(0, at("A1")), Value::Blank);
}

#[test]
fn inserting_refuses_to_push_filled_cells_off_the_sheet() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1048576", "1");
    let message = wb.shift_cells(0, SheetEdit::rows(0, 1, true)).unwrap_err().to_string();
    assert!(message.contains("A1048576"), "{message}");
    assert_eq!(wb.value(0, at("A1048576")), n(1.0));
}

fn column(wb: &Workbook, sheet: u16, col: &str, rows: u32) -> Vec<String> {
    (1..=rows).map(|r| wb.value(sheet, at(&format!("{col}{r}"))).to_string()).collect()
}

fn list(wb: &mut Workbook, sheet: u16, items: &[&str]) {
    for (i, t) in items.iter().enumerate() {
        set(wb, sheet, &format!("A{}", i + 1), t);
    }
}

/// The class of macro in Microsoft's support article "Macro to delete duplicate items in a
/// list" (its DelDups_OneList and DelDups_TwoLists): walk a list, delete each later
/// duplicate with `Cells(i, 1).Delete xlShiftUp`. Written anew here; the article's expected
/// result is the list with its duplicates gone, in first-seen order.
#[test]
fn a_macro_deleting_duplicates_with_delete_xlshiftup() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Sheet2").unwrap();
    list(&mut wb, 0, &["a", "b", "a", "c", "b", "d"]);
    list(&mut wb, 1, &["x", "a", "y", "c", "z"]);
    set(&mut wb, 0, "C1", "=COUNTA(A1:A6)");
    run(
        &mut wb,
        r#"
    Dim last As Integer, i As Integer
    Sheets("Sheet1").Range("A1").Select
    Do Until ActiveCell = ""
        i = ActiveCell.Row + 1
        Do While Sheets("Sheet1").Cells(i, 1).Value <> ""
            If Sheets("Sheet1").Cells(i, 1).Value = ActiveCell.Value Then
                Sheets("Sheet1").Cells(i, 1).Delete xlShiftUp
            Else
                i = i + 1
            End If
        Loop
        ActiveCell.Offset(1, 0).Select
    Loop
    Dim master As Range
    For Each master In Sheets("Sheet1").Range("A1:A10")
        For i = 10 To 1 Step -1
            If master.Value <> "" And Sheets("Sheet2").Cells(i, 1).Value = master.Value Then
                Sheets("Sheet2").Cells(i, 1).Delete Shift:=xlShiftUp
            End If
        Next
    Next"#,
    );
    assert_eq!(column(&wb, 0, "A", 6), ["a", "b", "c", "d", "", ""]);
    assert_eq!(column(&wb, 1, "A", 5), ["x", "y", "z", "", ""]);
    // The count's range shrank with the two deleted cells (A1:A4), as a reference does.
    assert_eq!(wb.formula(0, at("C1")).as_deref(), Some("=COUNTA(A1:A4)"));
    assert_eq!(wb.value(0, at("C1")), n(4.0));
}

#[test]
fn rows_and_entire_row_delete_and_insert() {
    let mut wb = Workbook::with_sheet();
    list(&mut wb, 0, &["1", "2", "3", "4", "5", "6"]);
    set(&mut wb, 0, "B1", "=SUM(A1:A6)");
    run(&mut wb, "    Rows(2).Delete\n    Range(\"A3\").EntireRow.Delete\n    Rows(\"1:2\").Insert");
    // 1,2,3,4,5,6 → without 2 → without 4 → two empty rows on top: _,_,1,3,5,6; B1 moved to B3.
    assert_eq!(column(&wb, 0, "A", 6), ["", "", "1", "3", "5", "6"]);
    assert_eq!(wb.formula(0, at("B3")).as_deref(), Some("=SUM(A3:A6)"));
    assert_eq!(wb.value(0, at("B3")), n(15.0));
    run(&mut wb, "    Cells(4, 1).EntireRow.Insert\n    Range(\"A4\").Value = 100");
    // Inserted inside the sum's range: it grows to take the new row in.
    assert_eq!(wb.formula(0, at("B3")).as_deref(), Some("=SUM(A3:A7)"));
    assert_eq!(wb.value(0, at("B3")), n(115.0));
}

// A Range object is a reference to its cells, as a formula's is: Excel's `Set r =
// Range("B5")` then `Rows(2).Insert` leaves r on B6 with B5's value, a range cut by a delete
// shrinks, one inserted into grows, whole columns stay whole; one whose cells were all
// deleted is gone, and using it is run-time error 424 ("Object required", Microsoft's
// "Trappable errors"). Held anywhere: a variable, a Collection's item, a With block, a
// Static. Addresses worked by hand from the rows and columns moved; Debug.Print's commas
// go to the next 14-column print zone, a number printed with a space for its sign and one
// after it.
#[test]
fn range_variables_follow_their_cells_through_insert_and_delete() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Other").unwrap();
    let printed = run(
        &mut wb,
        "    Dim r As Range, tall As Range, far As Range, cols As Range, there As Range, c As New Collection
    Static kept As Range
    Set r = Range(\"B5\")
    Set tall = Range(\"B3:B7\")
    Set far = Range(\"C9\")
    Set cols = Range(\"D:E\")
    Set there = Worksheets(\"Other\").Range(\"B5\")
    Set kept = Range(\"A1\")
    c.Add Range(\"D4\")
    r.Value = 7
    Rows(2).Insert
    Debug.Print r.Address, r.Value, tall.Address, c(1).Address, cols.Address, there.Address, kept.Address
    Rows(6).Delete
    Debug.Print tall.Address, far.Address
    With tall
        Columns(\"A\").Insert
        Debug.Print .Address, far.Address, cols.Address
    End With
    Dim a As String
    On Error Resume Next
    a = r.Address
    Debug.Print Err.Number, a = \"\"",
    );
    assert_eq!(
        printed,
        [
            "$B$6           7            $B$4:$B$8     $D$5          $D:$E         $B$5          $A$1",
            "$B$4:$B$7     $C$9",
            "$C$4:$C$7     $D$9          $E:$F",
            " 424          True",
        ]
    );
}

#[test]
fn columns_and_entire_column_delete_and_insert() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "1"), ("B1", "2"), ("C1", "3"), ("D1", "=A1+C1")] {
        set(&mut wb, 0, cell, v);
    }
    run(&mut wb, "    Columns(\"B\").Delete");
    assert_eq!(wb.formula(0, at("C1")).as_deref(), Some("=A1+B1"));
    assert_eq!(wb.value(0, at("C1")), n(4.0));
    run(&mut wb, "    Range(\"B5\").EntireColumn.Insert\n    Columns(\"A:A\").Delete");
    assert_eq!(wb.formula(0, at("C1")).as_deref(), Some("=#REF!+B1"));
    assert_eq!(wb.value(0, at("C1")), bad());
}

#[test]
fn range_delete_and_insert_with_a_shift_and_without_one() {
    let mut wb = Workbook::with_sheet();
    for r in 1..=3 {
        for (c, col) in ["A", "B", "C", "D"].iter().enumerate() {
            set(&mut wb, 0, &format!("{col}{r}"), &format!("{}", r * 10 + c as u32 + 1));
        }
    }
    set(&mut wb, 0, "F1", "=D2");
    run(&mut wb, "    Range(\"A2:B2\").Delete Shift:=xlShiftToLeft");
    // Row 2 was 21,22,23,24: its C and D moved to A and B; F1 follows D2 to B2.
    assert_eq!(column(&wb, 0, "A", 3), ["11", "23", "31"]);
    assert_eq!(wb.formula(0, at("F1")).as_deref(), Some("=B2"));
    assert_eq!(wb.value(0, at("F1")), n(24.0));
    run(&mut wb, "    Range(\"A1:A2\").Insert Shift:=xlShiftToRight");
    // Rows 1 and 2 move right, F1 with them (to G1), and its B2 with them (to C2).
    assert_eq!(wb.value(0, at("B1")), n(11.0));
    assert_eq!(wb.value(0, at("F1")), Value::Blank);
    assert_eq!(wb.formula(0, at("G1")).as_deref(), Some("=C2"));
    assert_eq!(wb.value(0, at("G1")), n(24.0));
    // Wider than tall, without Shift: the cells below move up.
    run(&mut wb, "    Range(\"C3:D3\").Delete");
    assert_eq!(wb.value(0, at("C3")), Value::Blank);
    assert_eq!(wb.value(0, at("A3")), n(31.0));
    // A bad Shift names what it takes.
    let src = "Sub Main()\n    Range(\"A1\").Delete xlShiftDown\nEnd Sub\n";
    let e = vba::run(&mut wb, src, "edits.bas", &RunOptions::default()).unwrap_err().to_string();
    assert!(e.contains("xlShiftUp or xlShiftToLeft"), "{e}");
}

#[test]
fn a_document_row_insert_moves_values_formulas_and_formats() {
    use ncsheet::document::{Document, OpenOptions};
    let csv = b"1,2\n=A1+B1,\n".to_vec();
    let mut doc = Document::open(csv, &OpenOptions::named("parts.csv")).unwrap();
    doc.set(0, at("C1"), "2025-03-12").unwrap();
    let shown = doc.shown(0, at("C1"));
    assert!(shown.contains('/'), "typed as a date, shown as one: {shown}");
    doc.shift_cells(0, SheetEdit::rows(0, 1, true)).unwrap();
    assert_eq!(doc.workbook().formula(0, at("A3")).as_deref(), Some("=A2+B2"));
    assert_eq!(doc.workbook().value(0, at("A3")), n(3.0));
    // The date keeps the look it was typed with, in its new row; row 1 has none.
    assert_eq!(doc.shown(0, at("C2")), shown);
    assert_eq!(doc.shown(0, at("C1")), "");
    doc.shift_cells(0, SheetEdit::rows(1, 1, false)).unwrap();
    assert_eq!(doc.workbook().value(0, at("A2")), bad());
}

#[test]
fn a_spill_and_hidden_rows_move_whole() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A3", "=SEQUENCE(3)");
    set(&mut wb, 0, "B1", "=SUM(A3#)");
    wb.set_row_hidden(0, 4, Some(ncsheet::eval::RowHidden::Manually));
    wb.shift_cells(0, SheetEdit::rows(0, 1, false)).unwrap();
    assert_eq!(column(&wb, 0, "A", 5), ["", "1", "2", "3", ""]);
    // B1 was deleted with row 1; the hidden row 5 is row 4 now.
    assert_eq!(wb.value(0, at("B1")), Value::Blank);
    assert_eq!(wb.hidden_rows(0).iter().map(|&(r, _)| r).collect::<Vec<_>>(), [3]);
    set(&mut wb, 0, "C1", "=SUM(A2#)");
    assert_eq!(wb.value(0, at("C1")), n(6.0));
    wb.shift_cells(0, SheetEdit::rows(0, 1, true)).unwrap();
    assert_eq!(wb.formula(0, at("C2")).as_deref(), Some("=SUM(A3#)"));
    assert_eq!(wb.value(0, at("C2")), n(6.0));
}

#[test]
fn formulas_moved_by_an_edit_are_not_reported_as_replaced() {
    let mut wb = probe_book();
    wb.track_changes();
    wb.shift_cells(0, SheetEdit::rows(0, 1, false)).unwrap();
    let changes = wb.changes().unwrap();
    // C1's formula moved up a row (deleted with row 1 in fact), none was typed over.
    assert!(changes.formulas_replaced.is_empty(), "{:?}", changes.formulas_replaced);
    assert!(changes.inputs.contains(&(0, at("C1"))));
}

#[test]
fn deleting_cells_shifted_left_as_libreoffice() {
    let mut wb = probe_book();
    for (cell, f) in [
        ("E1", "=SUM(A2:D2)"),
        ("E2", "=D2"),
        ("E3", "=SUM(B1:B3)"),
        ("E4", "=C2"),
        ("E5", "=SUM(B2:D2)"),
        ("F2", "=A2"),
    ] {
        set(&mut wb, 0, cell, f);
    }
    wb.shift_cells(0, SheetEdit::cells(Rect::new(at("B2"), at("C2")), Axis::Columns, false)).unwrap();
    check(
        &wb,
        "delete B2:C2 shift left",
        &[
            (0, "E1", Some("=SUM(A2:B2)"), n(2.0)),
            // Row 2's E2 and F2 moved two columns left, their references with them.
            (0, "C2", Some("=B2"), n(0.0)),
            (0, "D2", Some("=A2"), n(2.0)),
            (0, "E2", None, Value::Blank),
            (0, "E3", Some("=SUM(B1:B3)"), n(400.0)),
            (0, "E4", None, bad()),
            (0, "E5", Some("=SUM(B2:B2)"), n(0.0)),
        ],
    );
}

/// `text`'s elements `<name …>` (or `<name …/>`), each as its opening tag.
fn tags<'t>(text: &'t str, name: &str) -> Vec<&'t str> {
    let open = format!("<{name} ");
    text.match_indices(&open).map(|(i, _)| &text[i..i + text[i..].find('>').unwrap() + 1]).collect()
}

fn attr<'t>(tag: &'t str, name: &str) -> Option<&'t str> {
    let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&tag[at..at + tag[at..].find('"')?])
}

/// The `inner` text of the first `<name>…</name>` of `text`.
fn element<'t>(text: &'t str, name: &str) -> &'t str {
    let start = text.find(&format!("<{name}")).unwrap_or_else(|| panic!("no <{name}>"));
    let end = text[start..].find(&format!("</{name}>")).unwrap() + start;
    &text[start..end]
}

fn part(zip: &[u8], name: &str) -> String {
    use std::io::Read;
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(zip)).unwrap();
    let mut text = String::new();
    archive.by_name(name).unwrap().read_to_string(&mut text).unwrap();
    text
}

#[test]
fn a_saved_run_keeps_widths_hidden_rows_heights_and_styles_with_their_moved_cells() {
    use ncsheet::io::xlsx::{Layout, SheetLayout};
    // The book: B3 1.5 shown as 0.000, C3 text, row 4 hidden, column C 20 characters wide.
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "head");
    set(&mut wb, 0, "B3", "1.5");
    set(&mut wb, 0, "C3", "x");
    set(&mut wb, 0, "A6", "end");
    wb.set_row_hidden(0, 3, Some(ncsheet::eval::RowHidden::Manually));
    let mut sheet = SheetLayout::default();
    sheet.look.column_widths = vec![(2, 20.0)];
    sheet.look.number_formats.insert(at("B3"), "0.000".into());
    let mut layout = Layout::default();
    layout.sheets.insert("Sheet1".into(), sheet);
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("book.xlsx");
    std::fs::write(&book, ncsheet::io::xlsx::to_bytes(&wb, &layout).unwrap()).unwrap();
    let macro_file = dir.path().join("edit.bas");
    let src = "Sub Main()\n    Range(\"C3\").Font.Bold = True\n    Rows(5).RowHeight = 30\n    \
               Rows(2).Delete\n    Columns(1).Delete\nEnd Sub\n";
    std::fs::write(&macro_file, src).unwrap();
    let saved = dir.path().join("saved.xlsx");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["run".as_ref(), book.as_os_str(), macro_file.as_os_str(), "--save".as_ref(), saved.as_os_str()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&saved).unwrap();
    let sheet = part(&bytes, "xl/worksheets/sheet1.xml");
    let styles = part(&bytes, "xl/styles.xml");
    // Row 2 and column A deleted, as Excel moves them: B3 is A2, C3 B2, hidden row 4 row 3,
    // row 5's height row 4's, column C's width column B's.
    let row = |r: &str| *tags(&sheet, "row").iter().find(|t| attr(t, "r") == Some(r)).unwrap_or(&"<row >");
    assert_eq!(attr(row("3"), "hidden"), Some("1"), "{sheet}");
    assert_eq!(attr(row("4"), "hidden"), None, "{sheet}");
    assert_eq!(attr(row("4"), "ht"), Some("30"), "{sheet}");
    assert_eq!(attr(row("5"), "ht"), None, "{sheet}");
    let cols = tags(&sheet, "col");
    let wide: Vec<_> = cols.iter().filter(|c| attr(c, "customWidth") == Some("1")).collect();
    assert_eq!(wide.len(), 1, "{sheet}");
    assert_eq!((attr(wide[0], "min"), attr(wide[0], "max")), (Some("2"), Some("2")), "{sheet}");
    let width: f64 = attr(wide[0], "width").unwrap().parse().unwrap();
    assert!((width - 20.0).abs() < 1.0, "{width}");
    // Each cell's style, looked up in styles.xml: A2 shows 0.000, B2 is bold, C2 plain.
    let xfs = tags(element(&styles, "cellXfs"), "xf");
    let fonts: Vec<&str> = element(&styles, "fonts").split("<font>").skip(1).collect();
    let xf = |cell: &str| {
        let c = tags(&sheet, "c").into_iter().find(|t| attr(t, "r") == Some(cell)).unwrap_or("<c >");
        xfs[attr(c, "s").map_or(0, |s| s.parse().unwrap())]
    };
    let code = |cell: &str| {
        let id = attr(xf(cell), "numFmtId").unwrap_or("0");
        tags(&styles, "numFmt")
            .into_iter()
            .find(|f| attr(f, "numFmtId") == Some(id))
            .and_then(|f| attr(f, "formatCode"))
    };
    let bold = |cell: &str| fonts[attr(xf(cell), "fontId").map_or(0, |f| f.parse().unwrap())].contains("<b/>");
    assert_eq!(code("A2"), Some("0.000"), "{sheet}\n{styles}");
    assert_eq!(code("B3"), None);
    assert!(bold("B2"), "{sheet}\n{styles}");
    assert!(!bold("C3") && !bold("A2"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("inserted or deleted"));
}

// Excel refuses an insert that would push a filled cell off the sheet ("Microsoft Excel can't
// insert new cells because it would push non-empty cells off the end of the worksheet"); a
// formula in the last row is such a cell as much as a constant is (it was dropped silently).
#[test]
fn inserting_a_row_that_would_push_a_formula_off_the_sheet_is_refused() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "5");
    set(&mut wb, 0, "A1048576", "=A1*2");
    let message = wb.shift_cells(0, SheetEdit::rows(0, 1, true)).unwrap_err().to_string();
    assert!(message.contains("A1048576"), "{message}");
    assert_eq!(wb.formula(0, at("A1048576")).as_deref(), Some("=A1*2"));
    assert_eq!(wb.value(0, at("A1048576")), n(10.0));
}

// An edit Excel refuses from a macro is its run-time error 1004, which On Error traps ("Run-time
// error '1004': Microsoft Excel can't insert new cells because it would push non-empty cells
// off the end of the worksheet"; cutting part of an array, "You can't change part of an
// array", is 1004 too): Err.Number reads 1004 and the cells are as before.
#[test]
fn a_refused_insert_or_delete_in_a_macro_is_error_1004() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, "A1", "=SEQUENCE(4)");
    set(&mut wb, 0, "B1048576", "1");
    let printed = run(
        &mut wb,
        "    On Error Resume Next\n    Rows(2).Delete\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   Rows(1).Insert\n    Debug.Print Err.Number",
    );
    assert_eq!(printed, [" 1004 ", " 1004 "]);
    assert_eq!(wb.value(0, at("A4")), n(4.0));
    assert_eq!(wb.value(0, at("B1048576")), n(1.0));
    let src = "Sub Main()\n    Rows(2).Delete\nEnd Sub\n";
    let e = vba::run(&mut wb, src, "edits.bas", &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("1004") && e.message.contains("Sheet1!A1"), "{e}");
}

// A formula that only moves keeps its stored formula: copies filled down still share one
// (`formula_id`), and a formula whose references changed takes the slot of the one it
// replaces, so inserting and deleting rows over and over (a macro's loop) leaves the store
// as large as it was, with LibreOffice 7.4's formulas and values after the last edit.
#[test]
fn repeated_row_edits_keep_moved_formulas_shared_and_the_store_bounded() {
    let mut wb = probe_book();
    for r in 1..=10 {
        set(&mut wb, 0, &format!("D{r}"), &format!("=A{r}*2"));
    }
    let shared = wb.formula_id(0, at("D1")).unwrap();
    let stored = wb.formula_counts().1;
    for _ in 0..50 {
        wb.shift_cells(0, SheetEdit::rows(2, 2, true)).unwrap();
        wb.shift_cells(0, SheetEdit::rows(2, 2, false)).unwrap();
    }
    assert_eq!(wb.formula_counts().1, stored);
    wb.shift_cells(0, SheetEdit::rows(2, 2, true)).unwrap();
    check(&wb, "insert rows 3:4 after 50 inserts and deletes", &after_inserting_rows_3_4());
    assert_eq!(name_formula(&wb), "=Sheet1!$A$7:$A$10");
    for r in [1, 2, 5, 12] {
        assert_eq!(wb.formula_id(0, at(&format!("D{r}"))), Some(shared), "D{r}");
    }
    assert_eq!(wb.formula(0, at("D12")).as_deref(), Some("=A12*2"));
    assert_eq!(wb.value(0, at("D12")), n(20.0));
    run(&mut wb, "    For i = 1 To 40\n        Rows(1).Insert\n    Next");
    assert_eq!(wb.formula_counts().1, stored);
    assert_eq!(wb.formula(0, at("C41")).as_deref(), Some("=SUM(A41:A52)"));
    assert_eq!(wb.value(0, at("C41")), n(55.0));
}

// A name's absolute references follow an edit as a lone absolute range does (Walkenbach,
// above: a name's range moves with rows inserted above it); a relative one beside them is
// read from the cell using the name and stays as written. The name was skipped whole: its
// `$A$5` kept pointing at row 5, which after the insert holds 3, not 5.
#[test]
fn a_name_with_a_relative_reference_still_moves_its_absolute_ones() {
    let mut wb = probe_book();
    // Its relative `A1` is the using cell's own address, on Sheet1.
    wb.define_name("Mix", "Sheet1!$A$5*10+Sheet1!A1", None).unwrap();
    set(&mut wb, 1, "B1", "=Mix");
    set(&mut wb, 1, "B3", "=Mix");
    assert_eq!(wb.value(1, at("B1")), n(150.0));
    wb.shift_cells(0, SheetEdit::rows(2, 2, true)).unwrap();
    let mix = wb.names().into_iter().find(|(n, _, _)| n == "Mix").unwrap().1;
    assert_eq!(mix, "=Sheet1!$A$7*10+Sheet1!A1");
    // Sheet2!B1 reads Sheet1!B1 (100), B3 reads Sheet1!B3 (an inserted, empty row).
    assert_eq!(wb.value(1, at("B1")), n(150.0));
    assert_eq!(wb.value(1, at("B3")), n(50.0));
}

// Issue 30: an insertion wrote each moved cell at a new place and kept the cell it left,
// blank, so a loop of `Columns(1).Insert` before a full column made a million cells a turn
// and passed the workbook's cell limit (docs/limits.md) in nine turns. The places an edit
// empties are reused where the moved cells land: the cells hold where Excel puts them (100
// columns right and 100 rows down, CW101:CW1100; the sum of 1..1000 is 500,500), and the
// workbook holds no more cells than before the loop.
#[test]
fn insertions_in_a_loop_keep_the_cells_they_began_with() {
    let mut wb = Workbook::with_sheet();
    for i in 1..=1000 {
        set(&mut wb, 0, &format!("A{i}"), &i.to_string());
    }
    set(&mut wb, 0, "B1", "=SUM(A1:A1000)+A1");
    let cells = wb.cell_count();
    for _ in 0..100 {
        wb.shift_cells(0, SheetEdit::columns(0, 1, true)).unwrap();
        wb.shift_cells(0, SheetEdit::rows(0, 1, true)).unwrap();
    }
    assert_eq!(wb.value(0, at("CW101")), n(1.0));
    assert_eq!(wb.value(0, at("CW1100")), n(1000.0));
    assert_eq!(wb.formula(0, at("CX101")).as_deref(), Some("=SUM(CW101:CW1100)+CW101"));
    assert_eq!(wb.value(0, at("CX101")), n(500_501.0));
    assert_eq!(wb.cell_count(), cells, "the insertions made cells");
    // Deleting them again leaves the sheet as it began.
    for _ in 0..100 {
        wb.shift_cells(0, SheetEdit::columns(0, 1, false)).unwrap();
        wb.shift_cells(0, SheetEdit::rows(0, 1, false)).unwrap();
    }
    assert_eq!(wb.formula(0, at("B1")).as_deref(), Some("=SUM(A1:A1000)+A1"));
    assert_eq!(wb.value(0, at("B1")), n(500_501.0));
    assert_eq!(wb.cell_count(), cells);
}

// Issue 30: a formula summing a small range (`=SUM(B1:Q1)`, at most 16 cells) links each of
// its cells, making the blank ones; they stayed when the formula went or came to read
// elsewhere, so a thousand such formulas pointed at row after row filled the workbook's
// cell limit (docs/limits.md) with cells nothing reads. They go back once nothing links
// them, and so does a cell emptied that no formula reads; cells read again are made again,
// and the sums are what they sum. With the change log kept (a file to save), an emptied
// cell stays: its place is an edit the save writes.
#[test]
fn blank_cells_nothing_links_are_given_back() {
    let mut wb = Workbook::with_sheet();
    let sum_row = |wb: &mut Workbook, i: u32, row: u32| set(wb, 0, &format!("A{i}"), &format!("=SUM(B{row}:Q{row})"));
    for i in 1..=1000 {
        sum_row(&mut wb, i, i);
    }
    assert_eq!(wb.cell_count(), 1000 + 16_000);
    for i in 1..=1000 {
        sum_row(&mut wb, i, i + 1000);
    }
    assert_eq!(wb.cell_count(), 1000 + 16_000, "the rows no formula reads kept their cells");
    for i in 1..=1000 {
        set(&mut wb, 0, &format!("A{i}"), "");
    }
    assert_eq!(wb.cell_count(), 0);
    set(&mut wb, 0, "C5", "7");
    sum_row(&mut wb, 1, 5);
    set(&mut wb, 0, "A2", "=C5*2");
    assert_eq!(wb.value(0, at("A1")), n(7.0));
    assert_eq!(wb.value(0, at("A2")), n(14.0));
    wb.track_changes();
    set(&mut wb, 0, "A2", "");
    assert_eq!(wb.changes().unwrap().inputs, [(0, at("A2"))]);
    assert_eq!(wb.cell_count(), 2 + 16);
}

// The place a reused cell leaves is still an edited place: a csv saved after `Rows(1).Insert`
// has the empty row Excel inserts above the old first row (the csv's own text is kept for
// the places not edited, so a place forgotten with its cell would keep its old "1").
#[test]
fn a_csv_saved_after_an_insertion_has_the_inserted_row_empty() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("three.csv");
    std::fs::write(&book, "1\n2\n3\n").unwrap();
    let macro_file = dir.path().join("m.bas");
    std::fs::write(&macro_file, "Sub Main()\n    Rows(1).Insert\nEnd Sub\n").unwrap();
    let saved = dir.path().join("saved.csv");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["run".as_ref(), book.as_os_str(), macro_file.as_os_str(), "--save".as_ref(), saved.as_os_str()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read_to_string(&saved).unwrap(), "\n1\n2\n3\n");
}

// Issue 30: an insertion relinks only the formulas it rewrites or moves and those whose
// edges reach the cells it moves (through a defined name, a 3-D reference, INDIRECT or
// OFFSET), and recomputes what depends on them, where it rebuilt the whole graph and
// recomputed every formula (a second a turn before a full column). The formulas, and the
// values after each edit, are LibreOffice 24.2's: the same book as an xlsx, a row and then a
// column inserted with `insertCells` (ROWS, COLUMNS) and cells set with `setValue`, each
// followed by `calculateAll`, in a headless LibreOffice Basic macro (LibreOffice writes
// `$Sheet1.A:A` where Excel and we write `Sheet1!A:A`). The 3-D reference and INDIRECT's
// text stay on A1 and read the new, empty cell there; the name, OFFSET's reference and the
// plain ones follow their cells.
#[test]
fn an_insertion_recomputes_what_reads_the_moved_cells_through_names_3d_references_and_indirect() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Sheet2").unwrap();
    wb.add_sheet("Sheet3").unwrap();
    for i in 1..=5 {
        set(&mut wb, 0, &format!("A{i}"), &i.to_string());
    }
    set(&mut wb, 1, "A1", "10");
    set(&mut wb, 2, "A1", "100");
    wb.define_name("Tot", "Sheet1!$A$1:$A$5", None).unwrap();
    let formulas = [
        "=SUM(Tot)",
        "=SUM(Sheet1:Sheet3!A1)",
        "=INDIRECT(\"Sheet1!A1\")",
        "=SUM(Sheet1!A:A)",
        "=OFFSET(Sheet1!A1,1,0)",
        "=Sheet1!A3*2",
    ];
    for (i, f) in formulas.iter().enumerate() {
        set(&mut wb, 1, &format!("B{}", i + 1), f);
    }
    let column = |wb: &Workbook| -> Vec<Value> { (1..=6).map(|r| wb.value(1, at(&format!("B{r}")))).collect() };
    let numbers = |xs: [f64; 6]| xs.map(n).to_vec();
    assert_eq!(column(&wb), numbers([15.0, 111.0, 1.0, 15.0, 2.0, 6.0]));
    wb.shift_cells(0, SheetEdit::rows(0, 1, true)).unwrap();
    assert_eq!(column(&wb), numbers([15.0, 110.0, 0.0, 15.0, 2.0, 6.0]));
    assert_eq!(wb.formula(1, at("B5")).as_deref(), Some("=OFFSET(Sheet1!A2,1,0)"));
    assert_eq!(wb.formula(1, at("B6")).as_deref(), Some("=Sheet1!A4*2"));
    set(&mut wb, 0, "A2", "1000");
    set(&mut wb, 0, "A1", "7");
    set(&mut wb, 0, "A4", "30");
    assert_eq!(column(&wb), numbers([1041.0, 117.0, 7.0, 1048.0, 2.0, 60.0]));
    wb.shift_cells(0, SheetEdit::columns(0, 1, true)).unwrap();
    assert_eq!(column(&wb), numbers([1041.0, 110.0, 0.0, 1048.0, 2.0, 60.0]));
    assert_eq!(wb.formula(1, at("B4")).as_deref(), Some("=SUM(Sheet1!B:B)"));
    assert_eq!(wb.formula(1, at("B5")).as_deref(), Some("=OFFSET(Sheet1!B2,1,0)"));
    set(&mut wb, 0, "A1", "5");
    set(&mut wb, 0, "B3", "-1");
    assert_eq!(column(&wb), numbers([1038.0, 115.0, 5.0, 1045.0, -1.0, 60.0]));
}

// Issue 30: a cell given back (a deleted sheet's, a blank one nothing links) keeps the sheet
// and place it left, where another cell may stand now: a scan of a sheet's cells that took
// it for the cell there would move or read it. A sheet filled, deleted and brought back
// (the workbench's undo) and a sheet added after it, each edited by an insertion, hold
// what they were given, where the insertion puts it, and no more cells than they fill.
#[test]
fn cells_given_back_are_not_taken_for_the_cells_now_at_their_places() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Data").unwrap();
    wb.start_journal();
    for i in 1..=50 {
        set(&mut wb, 1, &format!("A{i}"), &i.to_string());
        set(&mut wb, 1, &format!("B{i}"), &format!("=A{i}*2"));
    }
    let record = {
        wb.delete_sheet(1).unwrap();
        wb.take_deleted_sheets().pop().unwrap()
    };
    assert_eq!(wb.cell_count(), 0);
    let new = wb.add_sheet("New").unwrap();
    for i in 1..=10 {
        set(&mut wb, new, &format!("A{i}"), &(i * 100).to_string());
    }
    set(&mut wb, new, "C1", "=SUM(A1:A10)");
    wb.restore_sheet(&record).unwrap();
    assert_eq!(wb.cell_count(), 10 + 1 + 100);
    wb.shift_cells(new, SheetEdit::rows(0, 2, true)).unwrap();
    wb.shift_cells(1, SheetEdit::columns(0, 1, true)).unwrap();
    wb.shift_cells(1, SheetEdit::rows(0, 1, false)).unwrap();
    assert_eq!(wb.value(new, at("A3")), n(100.0));
    assert_eq!(wb.value(new, at("A12")), n(1000.0));
    assert_eq!(wb.value(new, at("C3")), n(5500.0));
    assert_eq!(wb.formula(new, at("C3")).as_deref(), Some("=SUM(A3:A12)"));
    assert_eq!(wb.value(1, at("B1")), n(2.0));
    assert_eq!(wb.value(1, at("C49")), n(100.0));
    assert_eq!(wb.formula(1, at("C49")).as_deref(), Some("=B49*2"));
    assert_eq!(wb.value(1, at("B50")), Value::Blank);
    assert_eq!(wb.cell_count(), 10 + 1 + 98);
}
