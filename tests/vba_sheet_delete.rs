//! `Worksheet.Delete` from a macro, as Excel's automation uses it: `Worksheets("Merged").Delete`
//! between `Application.DisplayAlerts = False` and `True`, `Sheets(i).Delete`, `ws.Delete`,
//! `ActiveSheet.Delete`.
//!
//! Expected values are worked out by hand from Microsoft's Excel VBA reference and help:
//! "Worksheet.Delete method" (deletes the object; returns True when the user chose Delete, and
//! with DisplayAlerts False no dialog asks), "Worksheets.Count property", "How to correct a
//! #REF! error" (a formula whose sheet was deleted shows #REF!, and so does a defined name
//! referring to it), the message of run-time error 1004 for the last visible sheet ("A
//! workbook must contain at least one visible worksheet"), and "Trappable errors" (424,
//! "Object required", for an object that no longer exists). The saved file is read back by
//! openpyxl and opened and recalculated by LibreOffice (`.ci/run` installs both).

mod common;

use std::path::Path;

use common::openpyxl::{openpyxl_available, python};
use common::sheet::{get_on as get, set_on as set};
use common::vba::{main_fails as fails, run_main as run};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::{Visibility, Workbook};

/// A workbook of the sheets `names`, in that order.
fn book(names: &[&str]) -> Workbook {
    let mut wb = Workbook::new();
    for name in names {
        wb.add_sheet(name).unwrap();
    }
    wb
}

const LIST_TABS: &str =
    "    s = \"\"\n    For Each ws In Sheets\n        s = s & ws.Name & \",\"\n    Next\n    Debug.Print s";

// The sheet leaves Worksheets (Count, index order, For Each, names) and takes its cells with
// it; Delete returns True (the page's value for "the user chose Delete").
#[test]
fn a_deleted_sheet_leaves_the_worksheets_collection() {
    let mut wb = book(&["Sheet1", "Merged", "Sheet3"]);
    set(&mut wb, 1, "A1", "42");
    let printed = run(
        &mut wb,
        &format!(
            "    Application.DisplayAlerts = False\n    Worksheets(\"Merged\").Delete\n\
             \x20   Application.DisplayAlerts = True\n\
             \x20   Debug.Print Worksheets.Count; Sheets(2).Name; Sheets(\"Sheet3\").Index\n{LIST_TABS}\n\
             \x20   Debug.Print Sheets(\"Sheet1\").Delete"
        ),
    );
    assert_eq!(printed, [" 2 Sheet3 2 ", "Sheet1,Sheet3,", "True"]);
    assert_eq!(wb.tab_names(), ["Sheet3"]);
    assert_eq!((wb.sheet_id("Merged"), wb.sheet_id("sheet1")), (None, None));
    // Excel's SHEETS() counts the sheets there are.
    set(&mut wb, 2, "B1", "=SHEETS()");
    assert_eq!(get(&wb, 2, "B1"), Value::Number(1.0));
    // A sheet may take the name again, empty.
    let printed = run(
        &mut wb,
        "    Set ws = Sheets.Add\n    ws.Name = \"Merged\"\n    Debug.Print IsEmpty(ws.Range(\"A1\").Value)",
    );
    assert_eq!(printed, ["True"]);
}

// The Microsoft blog's DeleteWorksheet loop: `Sheets(i).Delete` counting down from
// Sheets.Count, so that the indexes still to visit do not move.
#[test]
fn sheets_i_delete_counting_down() {
    let mut wb = book(&["Keep", "Old", "Keep2", "old2"]);
    let printed = run(
        &mut wb,
        &format!(
            "    For i = Sheets.Count To 1 Step -1\n        If LCase(Left(Sheets(i).Name, 3)) = \"old\" Then Sheets(i).Delete\n\
             \x20   Next\n{LIST_TABS}"
        ),
    );
    assert_eq!(printed, ["Keep,Keep2,"]);
}

// "How to correct a #REF! error": a formula referring to a deleted sheet shows #REF!, and so
// does a defined name; what depends on them recomputes. Excel writes the formula `=#REF!A1*2`;
// ncsheet writes the struck reference as `#REF!` (`=#REF!*2`), its spelling of a deleted
// reference wherever one is deleted (rows, columns, sheets), which it reads back: the value
// is Excel's either way. A name scoped to the sheet goes with it.
#[test]
fn references_to_a_deleted_sheet_become_ref_errors() {
    let mut wb = book(&["Sheet1", "Merged"]);
    set(&mut wb, 1, "A1", "5");
    set(&mut wb, 1, "A2", "7");
    wb.define_name("Total", "=SUM(Merged!$A$1:$A$2)", None).unwrap();
    wb.define_name("Local", "=Merged!$A$1", Some(1)).unwrap();
    set(&mut wb, 0, "A1", "=Merged!A1*2");
    set(&mut wb, 0, "A2", "=Total+1");
    set(&mut wb, 0, "A3", "=IFERROR(A1,\"gone\")");
    set(&mut wb, 0, "A4", "=SUM(Merged!A1:A2,3)");
    set(&mut wb, 0, "A5", "=Merged!Local");
    set(&mut wb, 0, "A6", "=INDIRECT(\"Merged!A2\")");
    assert_eq!(get(&wb, 0, "A1"), Value::Number(10.0));
    assert_eq!(get(&wb, 0, "A2"), Value::Number(13.0));
    assert_eq!(get(&wb, 0, "A3"), Value::Number(10.0));
    assert_eq!(get(&wb, 0, "A5"), Value::Number(5.0));
    run(&mut wb, "    Application.DisplayAlerts = False\n    Sheets(\"Merged\").Delete");
    let at = |c: &str| parse_cell(c).unwrap();
    for cell in ["A1", "A2", "A4", "A5", "A6"] {
        assert_eq!(get(&wb, 0, cell), Value::Error(XlError::Ref), "{cell}");
    }
    assert_eq!(get(&wb, 0, "A3"), Value::text("gone"));
    assert_eq!(wb.formula(0, at("A1")).as_deref(), Some("=#REF!*2"));
    assert_eq!(wb.formula(0, at("A4")).as_deref(), Some("=SUM(#REF!,3)"));
    let names = wb.names();
    assert_eq!(names, [("Total".to_string(), "=SUM(#REF!)".to_string(), None)]);
    // A sheet given the name afterwards is another sheet: the struck references stay struck;
    // INDIRECT reads its text anew, as Excel's does.
    run(&mut wb, "    Set ws = Sheets.Add(After:=Sheets(1))\n    ws.Name = \"Merged\"\n    ws.Range(\"A2\").Value = 9");
    assert_eq!(get(&wb, 0, "A1"), Value::Error(XlError::Ref));
    assert_eq!(get(&wb, 0, "A6"), Value::Number(9.0));
}

// Run-time error 1004 for the last visible sheet (Excel: "A workbook must contain at least
// one visible worksheet"), trappable; nothing is deleted.
#[test]
fn the_last_visible_sheet_cannot_be_deleted() {
    let mut wb = book(&["Shown", "Hidden"]);
    wb.set_sheet_visibility(1, Visibility::Hidden);
    let e = fails(&mut wb, "    Sheets(\"Shown\").Delete");
    assert!(e.contains("1004") && e.contains("at least one visible"), "{e}");
    let printed = run(
        &mut wb,
        "    On Error Resume Next\n    ActiveSheet.Delete\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   Sheets(\"Hidden\").Delete\n    Debug.Print Err.Number; Sheets.Count",
    );
    assert_eq!(printed, [" 1004 ", " 0  1 "]);
    assert_eq!(wb.tab_names(), ["Shown"]);
}

// Deleting the active sheet activates the visible sheet to its right, or to its left when it
// was the last (Excel's tabs; hidden ones are passed over).
#[test]
fn the_next_sheet_becomes_active() {
    let mut wb = book(&["A", "B", "C", "D", "E"]);
    wb.set_sheet_visibility(2, Visibility::Hidden);
    let printed = run(
        &mut wb,
        "    Sheets(\"B\").Activate\n    ActiveSheet.Delete\n    Debug.Print ActiveSheet.Name\n\
         \x20   Sheets(\"E\").Activate\n    ActiveSheet.Delete\n    Debug.Print ActiveSheet.Name\n\
         \x20   Sheets(\"A\").Delete\n    Debug.Print ActiveSheet.Name; Sheets.Count",
    );
    assert_eq!(printed, ["D", "D", "D 2 "]);
    assert_eq!(wb.active_sheet(), 3);
}

// A Worksheet variable, or a Range of its cells, kept past the sheet's deletion: using it is
// error 424, "Object required"; never the cells of a sheet made later under the same name.
#[test]
fn a_worksheet_variable_of_a_deleted_sheet_is_an_error() {
    let merged = || {
        let mut wb = book(&["Sheet1", "Merged"]);
        set(&mut wb, 1, "A1", "5");
        wb
    };
    let body = "    Set ws = Sheets(\"Merged\")\n    Set r = ws.Range(\"A1\")\n    ws.Delete\n\
                \x20   Set fresh = Sheets.Add\n    fresh.Name = \"Merged\"\n    fresh.Range(\"A1\").Value = 99\n";
    let e = fails(&mut merged(), &format!("{body}    Debug.Print ws.Name"));
    assert!(e.contains("424") && e.contains("Object required") && e.contains("deleted"), "{e}");
    let e = fails(&mut merged(), &format!("{body}    ws.Range(\"A1\").Value = 1"));
    assert!(e.contains("424"), "{e}");
    let printed = run(
        &mut merged(),
        &format!(
            "{body}    On Error Resume Next\n    x = r.Value\n    Debug.Print Err.Number\n    Err.Clear\n\
             \x20   r.Value = 3\n    Debug.Print Err.Number; Sheets(\"Merged\").Range(\"A1\").Value"
        ),
    );
    assert_eq!(printed, [" 424 ", " 424  99 "]);
}

/// openpyxl's reading of `book`: each sheet in the file's order with A1 and A2 (`data_only`:
/// the values the file cached instead of formulas), then the package's worksheet parts, the
/// workbook's relationships to worksheets and [Content_Types]' worksheet overrides.
fn openpyxl_view(book: &Path, data_only: bool) -> String {
    let script = r#"
import sys, zipfile
from openpyxl import load_workbook
wb = load_workbook(sys.argv[1], data_only=sys.argv[2] == "1")
for ws in wb.worksheets:
    print(ws.title, ws["A1"].value, ws["A2"].value, sep="|")
z = zipfile.ZipFile(sys.argv[1])
parts = sorted(n for n in z.namelist() if n.startswith("xl/worksheets/sheet"))
rels = z.read("xl/_rels/workbook.xml.rels").decode().count("relationships/worksheet\"")
types = z.read("[Content_Types].xml").decode().count("spreadsheetml.worksheet+xml")
print(len(parts), rels, types, sep="|")
"#;
    python(script, &[book, Path::new(if data_only { "1" } else { "0" })])
}

// After a delete, the saved xlsx has no part for the sheet, and its workbook.xml,
// relationships and [Content_Types] agree (openpyxl reads them); LibreOffice opens it and,
// recalculating, finds the values worked out by hand.
#[test]
fn a_saved_book_has_no_part_for_a_deleted_sheet() {
    if !openpyxl_available() {
        return;
    }
    let mut wb = book(&["Sheet1", "Merged", "Sheet3"]);
    set(&mut wb, 1, "A1", "5");
    set(&mut wb, 0, "A1", "=Merged!A1*2");
    set(&mut wb, 0, "A2", "4");
    set(&mut wb, 2, "A1", "=Sheet1!A2+1");
    set(&mut wb, 2, "A2", "=IFERROR(Sheet1!A1,-1)");
    run(&mut wb, "    Application.DisplayAlerts = False\n    Worksheets(\"Merged\").Delete");
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("deleted.xlsx");
    ncsheet::io::save(&wb, &saved).unwrap();
    assert_eq!(openpyxl_view(&saved, false), "Sheet1|=#REF!*2|4\nSheet3|=Sheet1!A2+1|=IFERROR(Sheet1!A1,-1)\n2|2|2\n");
    assert_eq!(openpyxl_view(&saved, true), "Sheet1|#REF!|4\nSheet3|5|-1\n2|2|2\n");
    // ncsheet reads its own file back to the same workbook.
    let back = ncsheet::io::load(&saved).unwrap();
    assert_eq!(back.tab_names(), ["Sheet1", "Sheet3"]);
    assert_eq!(back.value(1, parse_cell("A2").unwrap()), Value::Number(-1.0));
    let Some(soffice) = common::soffice() else { return };
    let profile = common::recalculating_profile(&dir.path().join("profile"));
    let out = dir.path().join("lo");
    common::libreoffice_convert(&soffice, &profile, std::slice::from_ref(&saved), &out);
    let values = openpyxl_view(&out.join("deleted.xlsx"), true);
    assert!(values.starts_with("Sheet1|#REF!|4\nSheet3|5|-1\n"), "{values}");
}

// A 3-D reference of the file (`Sheet1:Sheet4!A1`) takes the sheets between its ends; Excel,
// deleting one of them, takes it out of the reference ("Create a 3-D reference to the same
// cell range on multiple worksheets": "Delete: if you delete sheets between Sheet2 and
// Sheet6, Excel removes their values from the calculation"; "Delete an endpoint: if you
// delete Sheet2 or Sheet6, Excel adjusts the calculation to accommodate the range of sheets
// between them"). Sums by hand over 1, 2, 4, 8: 15; Sheet2 gone: 13 (the reference as it
// was); the end Sheet4 gone: 1+4 = 5 (`Sheet1:Sheet3`); Sheet1 gone: 4 (`Sheet3`, one sheet
// left); Sheet3 gone, no sheet left: #REF!. LibreOffice, opening the file saved after the
// second delete, finds 5 in it.
#[test]
fn a_sheet_deleted_from_a_3d_reference_leaves_it() {
    if !openpyxl_available() {
        return;
    }
    let script = r#"
import sys
from openpyxl import Workbook
wb = Workbook()
wb.active.title = "Sheet1"
for name in ["Sheet2", "Sheet3", "Sheet4", "Sheet5"]:
    wb.create_sheet(name)
for name, v in [("Sheet1", 1), ("Sheet2", 2), ("Sheet3", 4), ("Sheet4", 8)]:
    wb[name]["A1"] = v
wb["Sheet5"]["A1"] = "=SUM(Sheet1:Sheet4!A1)"
wb.save(sys.argv[1])
"#;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("span.xlsx");
    python(script, &[&file]);
    let mut wb = ncsheet::io::load(&file).unwrap();
    let at = parse_cell("A1").unwrap();
    assert_eq!(get(&wb, 4, "A1"), Value::Number(15.0));
    let steps: [(&str, Value, &str); 2] = [
        ("Sheet2", Value::Number(13.0), "=SUM(Sheet1:Sheet4!A1)"),
        ("Sheet4", Value::Number(5.0), "=SUM(Sheet1:Sheet3!A1)"),
    ];
    for (sheet, value, formula) in steps {
        run(&mut wb, &format!("    Sheets(\"{sheet}\").Delete"));
        assert_eq!((get(&wb, 4, "A1"), wb.formula(4, at).as_deref()), (value, Some(formula)), "{sheet} deleted");
    }
    let saved = dir.path().join("shrunk.xlsx");
    ncsheet::io::save(&wb, &saved).unwrap();
    run(&mut wb, "    Sheets(\"Sheet1\").Delete");
    assert_eq!((get(&wb, 4, "A1"), wb.formula(4, at).as_deref()), (Value::Number(4.0), Some("=SUM(Sheet3!A1)")));
    run(&mut wb, "    Sheets(\"Sheet3\").Delete");
    assert_eq!(get(&wb, 4, "A1"), Value::Error(XlError::Ref));
    let Some(recalculated) = common::libreoffice_recalculated(&saved, dir.path()) else { return };
    let values = openpyxl_view(&recalculated, true);
    assert!(values.contains("Sheet5|5"), "{values}");
}

/// A BOM-merge module as automation writes it: the old output sheet deleted (alerts off,
/// errors ignored when there is none), a new one added last and named, the parts of each
/// BOM summed into it.
const BOM_MERGE: &str = r#"
Sub MergeBoms()
    Dim ws As Worksheet, src As Variant, r As Long, last As Long, i As Long, found As Long
    Dim part As String
    Application.DisplayAlerts = False
    On Error Resume Next
    Worksheets("Merged").Delete
    On Error GoTo 0
    Application.DisplayAlerts = True
    Set ws = Worksheets.Add(After:=Worksheets(Worksheets.Count))
    ws.Name = "Merged"
    ws.Range("A1").Value = "Part"
    ws.Range("B1").Value = "Qty"
    last = 1
    For Each src In Array("BOM1", "BOM2")
        r = 2
        Do While Worksheets(src).Cells(r, 1).Value <> ""
            part = Worksheets(src).Cells(r, 1).Value
            found = 0
            For i = 2 To last
                If ws.Cells(i, 1).Value = part Then found = i
            Next
            If found = 0 Then
                last = last + 1
                ws.Cells(last, 1).Value = part
                ws.Cells(last, 2).Value = Worksheets(src).Cells(r, 2).Value
            Else
                ws.Cells(found, 2).Value = ws.Cells(found, 2).Value + Worksheets(src).Cells(r, 2).Value
            End If
            r = r + 1
        Loop
    Next
End Sub
"#;

/// The BOMs the merge reads: bolt 4 + 2, nut 4 + 6, washer 8, pin 1.
fn boms() -> Workbook {
    let mut wb = book(&["Summary", "BOM1", "BOM2"]);
    for (sheet, rows) in [(1, [("bolt", 4), ("nut", 4), ("washer", 8)]), (2, [("bolt", 2), ("pin", 1), ("nut", 6)])] {
        set(&mut wb, sheet, "A1", "Part");
        set(&mut wb, sheet, "B1", "Qty");
        for (i, (part, qty)) in rows.iter().enumerate() {
            set(&mut wb, sheet, &format!("A{}", i + 2), part);
            set(&mut wb, sheet, &format!("B{}", i + 2), &qty.to_string());
        }
    }
    set(&mut wb, 0, "A1", "=SUM(INDIRECT(\"Merged!B2:B20\"))");
    wb
}

/// The Merged sheet's rows as `part=qty`, and the Summary's total.
fn merged_rows(wb: &Workbook) -> (Vec<String>, Value) {
    let sheet = wb.sheet_id("Merged").expect("a Merged sheet");
    let rows =
        (2..=6).map(|r| format!("{}={}", get(wb, sheet, &format!("A{r}")), get(wb, sheet, &format!("B{r}")))).collect();
    (rows, get(wb, 0, "A1"))
}

// Run twice, the merge gives the same output both times: the second run deletes the first's
// sheet and makes it again (sums by hand: bolt 6, nut 10, washer 8, pin 1; 25 in all).
#[test]
fn a_bom_merge_run_twice_gives_the_same_output() {
    let mut wb = boms();
    let run_merge = |wb: &mut Workbook| {
        let options = ncsheet::vba::RunOptions { sub: Some("MergeBoms".into()), ..Default::default() };
        ncsheet::vba::run(wb, BOM_MERGE, "merge.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    };
    let expected = (["bolt=6", "nut=10", "washer=8", "pin=1", "="].map(String::from).to_vec(), Value::Number(25.0));
    run_merge(&mut wb);
    assert_eq!(merged_rows(&wb), expected);
    run_merge(&mut wb);
    assert_eq!(merged_rows(&wb), expected);
    assert_eq!(wb.tab_names(), ["Summary", "BOM1", "BOM2", "Merged"]);
}

// Front ends see the workbook a macro left (`Document::run_macro`): the sheet gone from the
// tabs, and what the file kept of it (a column's width) not taken over by the sheet made
// under its name; the command line's `run --save` writes it so.
#[test]
fn documents_and_the_command_line_see_the_delete() {
    if !openpyxl_available() {
        return;
    }
    let script = r#"
import sys
from openpyxl import Workbook
wb = Workbook()
wb.active.title = "Sheet1"
wb["Sheet1"]["A1"] = "=Merged!A1*2"
m = wb.create_sheet("Merged")
m["A1"] = 21
m.column_dimensions["A"].width = 30
wb.save(sys.argv[1])
"#;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("book.xlsx");
    python(script, &[&file]);
    let remake = "Sub Main()\n    Application.DisplayAlerts = False\n    Worksheets(\"Merged\").Delete\n\
                  \x20   Worksheets.Add(After:=Sheets(1)).Name = \"Merged\"\n    Sheets(\"Merged\").Range(\"B1\").Value = 1\nEnd Sub\n";
    let mut doc = ncsheet::Document::open_file(&file, &ncsheet::document::OpenOptions::default()).unwrap();
    assert_eq!(doc.workbook().value(0, parse_cell("A1").unwrap()), Value::Number(42.0));
    doc.run_macro(remake, "remake.bas", ncsheet::vba::RunOptions::default()).unwrap();
    assert_eq!(doc.workbook().tab_names(), ["Sheet1", "Merged"]);
    assert_eq!(doc.workbook().value(0, parse_cell("A1").unwrap()), Value::Error(XlError::Ref));
    let saved = dir.path().join("saved.xlsx");
    doc.encode(&saved).unwrap().write(Default::default()).unwrap();
    let widths = r#"
import sys
from openpyxl import load_workbook
wb = load_workbook(sys.argv[1])
print(wb.sheetnames, "A" in wb["Merged"].column_dimensions, wb["Sheet1"]["A1"].value)
"#;
    assert_eq!(common::openpyxl::python(widths, &[&saved]), "['Sheet1', 'Merged'] False =#REF!*2\n");
    // The command line: `run --save`, then `eval` of the saved file.
    let bas = dir.path().join("remake.bas");
    std::fs::write(&bas, remake).unwrap();
    let out = dir.path().join("out.xlsx");
    let ran =
        common::cli::ncsheet(&["run", file.to_str().unwrap(), bas.to_str().unwrap(), "--save", out.to_str().unwrap()]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    // (The file opens on the new sheet, which the macro's Add made active.)
    let shown = common::cli::ncsheet(&["eval", out.to_str().unwrap(), "Sheet1!A1"]);
    assert!(shown.stdout.contains("#REF!"), "{}{}", shown.stdout, shown.stderr);
    let listed = common::cli::ncsheet(&["info", out.to_str().unwrap()]);
    assert!(listed.stdout.contains("Merged") && listed.stdout.contains("Sheet1"), "{}", listed.stdout);
}

// A csv holds one sheet: a macro that adds a sheet and deletes one leaves one, and the csv
// saves. Left with its own sheet, the file keeps its text with the cells edited written anew
// (what was written on the sheet deleted goes with it); left with the sheet added, it is that
// sheet's cells, formulas as typed. Contents by hand from the macros' writes.
#[test]
fn a_csv_left_with_one_sheet_after_add_and_delete_saves() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("book.csv");
    std::fs::write(&file, "1,2\n3,=A2*2\n").unwrap();
    let saved_after = |body: &str| -> String {
        let mut doc = ncsheet::Document::open_file(&file, &ncsheet::document::OpenOptions::default()).unwrap();
        let src = format!("Sub Main()\n    Application.DisplayAlerts = False\n{body}\nEnd Sub\n");
        doc.run_macro(&src, "m.bas", ncsheet::vba::RunOptions::default()).unwrap();
        let encoded = doc.encode(&dir.path().join("saved.csv")).unwrap_or_else(|e| panic!("{e}"));
        String::from_utf8(encoded.bytes().to_vec()).unwrap()
    };
    let own = saved_after(
        "    Worksheets(\"Sheet1\").Range(\"A1\").Value = 7\n    Sheets.Add\n    ActiveSheet.Range(\"C5\").Value = 9\n\
         \x20   ActiveSheet.Delete",
    );
    assert_eq!(own, "7,2\n3,=A2*2\n");
    let added = saved_after(
        "    Sheets.Add\n    ActiveSheet.Range(\"A1\").Value = 5\n    ActiveSheet.Range(\"A2\").Formula = \"=A1+1\"\n\
         \x20   Worksheets(\"Sheet1\").Delete",
    );
    assert_eq!(added, "5\n=A1+1\n");
}

/// `Sheets(Array(…))` is Excel's group of sheets ("Sheets object": "Use Sheets(array) to
/// specify more than one sheet"), by names or tab numbers: `Count`, `Move`/`Copy` keeping the
/// group's order (as dragging selected tabs does: B and C after D give A D B C; copies of A
/// and D before the first tab give "A (2)" "D (2)" in front, "Worksheet.Copy method" naming
/// each copy, the first active), `Delete` of every sheet in it. It was refused.
#[test]
fn a_group_of_sheets_counts_moves_copies_and_deletes_its_sheets() {
    let mut wb = book(&["A", "B", "C", "D"]);
    let printed = run(
        &mut wb,
        "    Debug.Print Sheets(Array(\"A\", \"C\")).Count\n    Sheets(Array(\"B\", \"C\")).Move After:=Sheets(\"D\")\n    \
         Sheets(Array(\"A\", \"D\")).Copy Before:=Sheets(1)\n    Debug.Print ActiveSheet.Name",
    );
    assert_eq!(printed, [" 2 ", "A (2)"]);
    assert_eq!(wb.tab_names(), ["A (2)", "D (2)", "A", "D", "B", "C"]);
    run(&mut wb, "    Worksheets(Array(1, 2)).Delete");
    assert_eq!(wb.tab_names(), ["A", "D", "B", "C"]);
}

// Issue 30: a deleted sheet's cells go with it, and the workbook's cell limit (docs/limits.md)
// counts them no more: a loop adding a sheet, filling a million cells and deleting it met
// the limit in its ninth turn, one sheet left. Five turns here, each sheet holding 2,000
// values and 2,000 formulas reading Sheet1, read by a formula of Sheet1 that becomes #REF!
// ("How to correct a #REF! error"): the workbook ends with its own cells and those five.
// A sheet made after, on the cells given back, computes as any: 1+2+3 = 6, 3+2 = 5.
#[test]
fn a_deleted_sheets_cells_are_given_back() {
    let mut wb = book(&["Sheet1"]);
    set(&mut wb, 0, "A1", "2");
    let before = wb.cell_count();
    run(
        &mut wb,
        "    Application.DisplayAlerts = False
    For i = 1 To 5
        Set ws = Sheets.Add
        ws.Range(\"A1:A2000\").Value = i
        ws.Range(\"B1:B2000\").Formula = \"=A1+Sheet1!$A$1\"
        Sheets(\"Sheet1\").Range(\"B\" & i).Formula = \"=SUM(\" & ws.Name & \"!B1:B4)\"
        ws.Delete
    Next",
    );
    assert_eq!(wb.cell_count(), before + 5, "the deleted sheets kept cells");
    for cell in ["B1", "B5"] {
        assert_eq!(get(&wb, 0, cell), Value::Error(XlError::Ref), "{cell}");
    }
    run(
        &mut wb,
        "    Set ws = Sheets.Add
    ws.Name = \"Last\"
    ws.Range(\"A1:A3\").Value = Application.Transpose(Array(1, 2, 3))
    ws.Range(\"B3\").Formula = \"=A3+Sheet1!$A$1\"
    Sheets(\"Sheet1\").Range(\"C1\").Formula = \"=SUM(Last!A1:A3)\"",
    );
    let last = wb.sheet_id("Last").unwrap();
    assert_eq!(get(&wb, 0, "C1"), Value::Number(6.0));
    assert_eq!(get(&wb, last, "B3"), Value::Number(5.0));
    assert_eq!(wb.cell_count(), before + 5 + 5);
}
