//! Where a macro puts sheets: `Sheets.Add` before the active sheet, `Before:=`, `After:=` and
//! `Count:=`, `ws.Copy` and `ws.Move` anywhere, and what reads a sheet's place (`Sheets(i)`,
//! `ws.Index`, `For Each ws In Sheets`, the SHEET function, a saved file's sheet order) sees
//! the tabs as they now are, while every formula keeps pointing at the same sheet.
//!
//! Expected values are worked out by hand from Microsoft's Excel VBA reference: "Sheets.Add
//! method" ("If Before and After are both omitted, the new sheet is inserted before the
//! active sheet"; "The new worksheet becomes the active sheet"; Count is "the number of sheets
//! to be added"), "Worksheet.Move method" ("The sheet before which the moved sheet will be
//! placed", "You cannot specify Before if you specify After", without either "Excel creates a
//! new workbook"), "Worksheet.Copy method", "Worksheet.Index property" ("the index number of
//! the object within the collection of similar objects") and the SHEET function ("the sheet
//! number of the referenced sheet"). The saved file is read back by openpyxl (sheet order and
//! formulas) and recalculated by LibreOffice (`.ci/run` installs both).

mod common;

use std::path::Path;
use std::process::Command;

use common::openpyxl::openpyxl_available;
use common::sheet::{get_on as get, set_on as set};
use common::vba::{main_fails as fails, run_main as run};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

/// A workbook of sheets `Sheet1` … `SheetN`, so that Excel's name for a new sheet is
/// `Sheet` and the next number whichever way it counts.
fn book_of(n: usize) -> Workbook {
    let mut wb = Workbook::with_sheet();
    for k in 2..=n {
        wb.add_sheet(&format!("Sheet{k}")).unwrap();
    }
    wb
}

const LIST_TABS: &str =
    "    s = \"\"\n    For Each ws In Sheets\n        s = s & ws.Name & \",\"\n    Next\n    Debug.Print s";

#[test]
fn sheets_add_goes_before_the_active_sheet_or_where_before_and_after_say() {
    let mut wb = book_of(2);
    let printed = run(
        &mut wb,
        &format!(
            "    Sheets.Add\n    Debug.Print ActiveSheet.Name; Sheets(1).Name; Sheets(\"Sheet1\").Index\n\
             \x20   Sheets.Add Before:=Sheets(\"Sheet2\")\n    Debug.Print ActiveSheet.Index\n\
             \x20   Set ws = Sheets.Add(After:=Sheets(1), Count:=2)\n\
             \x20   Debug.Print ws.Name; ActiveSheet.Name; Sheets.Count; Sheets(2).Name\n{LIST_TABS}"
        ),
    );
    assert_eq!(
        printed,
        ["Sheet3Sheet3 2 ", " 3 ", "Sheet6Sheet6 6 Sheet5", "Sheet3,Sheet5,Sheet6,Sheet1,Sheet4,Sheet2,"]
    );
    assert_eq!(wb.tab_names(), ["Sheet3", "Sheet5", "Sheet6", "Sheet1", "Sheet4", "Sheet2"]);
    // Ids never move: the first two sheets are still 0 and 1.
    assert_eq!(wb.sheet_names()[..2], ["Sheet1", "Sheet2"]);
}

#[test]
fn worksheet_move_changes_places_and_not_what_formulas_point_at() {
    let mut wb = book_of(4);
    set(&mut wb, 0, "A1", "=SHEET()");
    set(&mut wb, 1, "A1", "=SHEET(Sheet4!A1)");
    set(&mut wb, 2, "A1", "7");
    set(&mut wb, 3, "A1", "=Sheet3!A1*2");
    assert_eq!((get(&wb, 0, "A1"), get(&wb, 1, "A1")), (Value::Number(1.0), Value::Number(4.0)));
    let printed = run(
        &mut wb,
        &format!(
            "    Sheets(\"Sheet1\").Move After:=Sheets(\"Sheet3\")\n{LIST_TABS}\n\
             \x20   Sheets(\"Sheet4\").Move Before:=Sheets(1)\n{LIST_TABS}\n\
             \x20   Sheets(2).Move After:=Sheets(2)\n\
             \x20   Debug.Print Sheets(\"Sheet1\").Index; Sheets(\"Sheet4\").Index; Sheets(4).Range(\"A1\").Value\n\
             \x20   Sheets(1).Range(\"A2\").Value = Sheets(1).Range(\"A1\").Value + 1"
        ),
    );
    assert_eq!(printed, ["Sheet2,Sheet3,Sheet1,Sheet4,", "Sheet4,Sheet2,Sheet3,Sheet1,", " 4  1  4 "]);
    // SHEET() on Sheet1 (now the 4th tab) and SHEET(Sheet4!A1) (now the 1st) follow the tabs.
    assert_eq!((get(&wb, 0, "A1"), get(&wb, 1, "A1")), (Value::Number(4.0), Value::Number(1.0)));
    // Sheet4's formula still reads Sheet3, and the macro's Sheets(1) was Sheet4.
    assert_eq!(get(&wb, 3, "A2"), Value::Number(15.0));
    assert_eq!(wb.formula(3, parse_cell("A1").unwrap()).as_deref(), Some("=Sheet3!A1*2"));
}

#[test]
fn worksheet_move_needs_one_place() {
    let mut wb = book_of(2);
    let e = fails(&mut wb, "    Sheets(1).Move");
    assert!(e.contains("new workbook"), "{e}");
    let e = fails(&mut wb, "    Sheets(1).Move Before:=Sheets(2), After:=Sheets(2)");
    assert!(e.contains("1004") && e.contains("not both"), "{e}");
    assert_eq!(wb.tab_names(), ["Sheet1", "Sheet2"]);
}

#[test]
fn worksheet_copy_before_a_sheet_is_placed_there_and_active() {
    let mut wb = book_of(2);
    set(&mut wb, 1, "A1", "3");
    set(&mut wb, 1, "A2", "=A1*5");
    let printed = run(
        &mut wb,
        &format!(
            "    Sheets(\"Sheet2\").Copy Before:=Sheets(1)\n\
             \x20   Debug.Print ActiveSheet.Name; ActiveSheet.Index; Sheets(1).Range(\"A2\").Value\n{LIST_TABS}"
        ),
    );
    assert_eq!(printed, ["Sheet2 (2) 1  15 ", "Sheet2 (2),Sheet1,Sheet2,"]);
    assert_eq!(wb.formula(2, parse_cell("A2").unwrap()).as_deref(), Some("=A1*5"));
}

/// openpyxl's reading of `book`: each sheet in the file's order with the formula or value of
/// A1 and A2 (`data_only`: the values the file cached instead of formulas).
fn openpyxl_cells(book: &Path, data_only: bool) -> String {
    let script = r#"
import sys
from openpyxl import load_workbook
wb = load_workbook(sys.argv[1], data_only=sys.argv[2] == "1")
for ws in wb.worksheets:
    print(ws.title, ws["A1"].value, ws["A2"].value, sep="|")
"#;
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(book)
        .arg(if data_only { "1" } else { "0" })
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

// A macro moves, adds and copies sheets; the saved xlsx lists the sheets in their new tab
// order with every cross-sheet formula naming the sheet it meant, and LibreOffice, opening
// the file and recalculating, finds the values worked out by hand: SHEET() of a sheet now
// third is 3, and the references still reach the cells they named.
#[test]
fn a_saved_book_keeps_the_tab_order_and_libreoffice_recomputes_the_same_values() {
    if !openpyxl_available() {
        return;
    }
    let mut wb = book_of(3);
    set(&mut wb, 0, "A1", "10");
    set(&mut wb, 1, "A1", "=Sheet1!A1*2");
    set(&mut wb, 2, "A1", "=SHEET()");
    set(&mut wb, 2, "A2", "=SHEET(Sheet2!A1)+Sheet2!A1");
    run(
        &mut wb,
        "    Sheets(\"Sheet3\").Move Before:=Sheets(1)\n\
         \x20   Sheets.Add After:=Sheets(\"Sheet1\")\n    ActiveSheet.Range(\"A1\").Formula = \"=Sheet2!A1+1\"\n\
         \x20   Sheets(\"Sheet1\").Copy Before:=Sheets(1)",
    );
    // Tabs: Sheet1 (2), Sheet3, Sheet1, Sheet4, Sheet2.
    assert_eq!(get(&wb, 2, "A1"), Value::Number(2.0));
    assert_eq!(get(&wb, 2, "A2"), Value::Number(25.0));
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("order.xlsx");
    ncsheet::io::save(&wb, &book).unwrap();
    let formulas = openpyxl_cells(&book, false);
    assert_eq!(
        formulas,
        "Sheet1 (2)|10|None\nSheet3|=_xlfn.SHEET()|=_xlfn.SHEET(Sheet2!A1)+Sheet2!A1\nSheet1|10|None\n\
         Sheet4|=Sheet2!A1+1|None\nSheet2|=Sheet1!A1*2|None\n"
    );
    let Some(soffice) = common::soffice() else { return };
    let profile = common::recalculating_profile(&dir.path().join("profile"));
    let out = dir.path().join("lo");
    common::libreoffice_convert(&soffice, &profile, std::slice::from_ref(&book), &out);
    let values = openpyxl_cells(&out.join("order.xlsx"), true);
    assert_eq!(values, "Sheet1 (2)|10|None\nSheet3|2|25\nSheet1|10|None\nSheet4|21|None\nSheet2|20|None\n");
}

// A 3-D reference (`Sheet1:Sheet3!A1`) means the sheets whose tabs lie between its ends
// (Excel help, "Create a 3-D reference to the same cell range on multiple worksheets":
// "Insert or copy: if you insert or copy sheets between Sheet2 and Sheet6 […], Excel includes
// all values in cells A2 through A5 from the added sheets in the calculations"; "Move: if you
// move sheets from between Sheet2 and Sheet6 to a location outside the referenced sheet
// range, Excel removes their values from the calculation"). Sums by hand: 1+2+4 = 7; a sheet
// added between the ends holding 16: 23; Sheet2 moved past the end: 1+16+4 = 21. The saved
// file keeps the reference as written, and LibreOffice, recomputing it with the saved tab
// order, finds 21 too.
#[test]
fn a_tab_moved_or_added_between_the_ends_of_a_3d_reference_joins_it() {
    if !openpyxl_available() {
        return;
    }
    let script = r#"
import sys
from openpyxl import Workbook
wb = Workbook()
wb.active.title = "Sheet1"
for name in ["Sheet2", "Sheet3", "Sheet4"]:
    wb.create_sheet(name)
for name, v in [("Sheet1", 1), ("Sheet2", 2), ("Sheet3", 4)]:
    wb[name]["A1"] = v
wb["Sheet4"]["A1"] = "=SUM(Sheet1:Sheet3!A1)"
wb.save(sys.argv[1])
"#;
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("span.xlsx");
    let out = Command::new("python3").arg("-c").arg(script).arg(&book).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut wb = ncsheet::io::load(&book).unwrap();
    assert_eq!(get(&wb, 3, "A1"), Value::Number(7.0));
    run(&mut wb, "    Sheets.Add Before:=Sheets(\"Sheet3\")\n    ActiveSheet.Range(\"A1\").Value = 16");
    assert_eq!(wb.tab_names(), ["Sheet1", "Sheet2", "Sheet5", "Sheet3", "Sheet4"]);
    assert_eq!(get(&wb, 3, "A1"), Value::Number(23.0));
    run(&mut wb, "    Sheets(\"Sheet2\").Move After:=Sheets(\"Sheet4\")");
    assert_eq!(get(&wb, 3, "A1"), Value::Number(21.0));
    let saved = dir.path().join("moved.xlsx");
    ncsheet::io::save(&wb, &saved).unwrap();
    let formulas = openpyxl_cells(&saved, false);
    assert!(formulas.contains("Sheet4|=SUM(Sheet1:Sheet3!A1)|"), "{formulas}");
    let Some(recalculated) = common::libreoffice_recalculated(&saved, dir.path()) else { return };
    let values = openpyxl_cells(&recalculated, true);
    assert_eq!(values, "Sheet1|1|None\nSheet5|16|None\nSheet3|4|None\nSheet4|21|None\nSheet2|2|None\n");
}
