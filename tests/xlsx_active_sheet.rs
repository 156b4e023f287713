//! The sheet a macro leaves active is the one the saved file opens on. ECMA-376 Part 1
//! §18.2.30 (`workbookView`): `activeTab` is the 0-based position in `<sheets>` of the sheet
//! shown when the workbook opens, and §18.3.1.87 (`sheetView`): `tabSelected` marks the
//! selected tab(s). openpyxl, an outside reader, reports both (`wb.active`, `views.sheetView[0].tabSelected`).

mod common;

use common::openpyxl::{openpyxl_available, python};
use ncsheet::document::{Document, OpenOptions};
use ncsheet::vba::RunOptions;

/// Three sheets A, B, C written by openpyxl; the file opens on A.
const WRITE_THREE: &str = r#"
import sys
from openpyxl import Workbook
wb = Workbook()
wb.active.title = "A"
wb.active["A1"] = 1
wb.create_sheet("B")["A1"] = 2
wb.create_sheet("C")["A1"] = 3
wb.save(sys.argv[1])
"#;

/// The title of the sheet the file opens on, then each worksheet's and chart sheet's tabSelected.
const READ_ACTIVE: &str = r#"
import sys
from openpyxl import load_workbook
wb = load_workbook(sys.argv[1])
print("active=" + wb.active.title)
for ws in wb.worksheets:
    print(ws.title + " selected=" + str(bool(ws.views.sheetView[0].tabSelected)))
for cs in wb.chartsheets:
    print(cs.title + " selected=" + str(bool(cs.sheetViews.sheetView[0].tabSelected)))
"#;

/// Runs `body` as a macro on openpyxl's three-sheet book and saves it; what openpyxl reads
/// back and the save's losses.
fn run_and_save(body: &str) -> (Vec<String>, Vec<String>) {
    run_and_save_on(WRITE_THREE, body)
}

/// As [`run_and_save`], on the book the python script `write` writes.
fn run_and_save_on(write: &str, body: &str) -> (Vec<String>, Vec<String>) {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("book.xlsx");
    python(write, &[&book]);
    let mut doc = Document::open_file(&book, &OpenOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    doc.run_macro(&src, "active.bas", RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let saved = dir.path().join("saved.xlsx");
    let encoded = doc.encode(&saved).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&saved, encoded.bytes()).unwrap();
    let read = python(READ_ACTIVE, &[&saved]);
    (read.lines().map(str::to_string).collect(), encoded.losses.clone())
}

#[test]
fn a_sheet_a_macro_activates_is_the_one_the_patched_file_opens_on() {
    if !openpyxl_available() {
        return;
    }
    let (read, losses) = run_and_save("    Sheets(\"B\").Activate");
    assert!(!losses.iter().any(|l| l.contains("written anew")), "patched in place: {losses:?}");
    assert_eq!(read, ["active=B", "A selected=False", "B selected=True", "C selected=False"]);
}

#[test]
fn a_changed_cell_and_an_activated_sheet_are_both_saved() {
    if !openpyxl_available() {
        return;
    }
    let (read, _) = run_and_save("    Sheets(\"A\").Range(\"A2\").Value = 5\n    Sheets(\"C\").Activate");
    assert_eq!(read, ["active=C", "A selected=False", "B selected=False", "C selected=True"]);
}

#[test]
fn a_sheet_added_by_a_macro_is_active_in_the_file_written_anew() {
    if !openpyxl_available() {
        return;
    }
    // Excel's Sheets.Add puts the new sheet before the active one (A) and activates it.
    let (read, _) = run_and_save("    Sheets.Add.Name = \"N\"");
    assert_eq!(read, ["active=N", "N selected=True", "A selected=False", "B selected=False", "C selected=False"]);
}

/// Sheets A, B and a chart sheet "Chart" of A's two numbers, written by openpyxl; the file
/// opens on the chart sheet, the only selected tab.
const WRITE_WITH_CHART_SHEET: &str = r#"
import sys
from openpyxl import Workbook
from openpyxl.chart import BarChart, Reference
wb = Workbook()
ws = wb.active
ws.title = "A"
ws["A1"] = 1
ws["A2"] = 2
wb.create_sheet("B")["A1"] = 2
cs = wb.create_chartsheet("Chart")
chart = BarChart()
chart.add_data(Reference(ws, min_col=1, min_row=1, max_row=2))
cs.add_chart(chart)
wb.active = 2
ws.sheet_view.tabSelected = False
cs.sheetViews.sheetView[0].tabSelected = True
wb.save(sys.argv[1])
"#;

/// A file opening on a chart sheet, whose macro activates B: B alone is selected. The chart
/// sheet kept its tabSelected, so two tabs opened as a group.
#[test]
fn a_sheet_activated_in_a_file_opening_on_a_chart_sheet_is_the_only_selected_tab() {
    if !openpyxl_available() {
        return;
    }
    let (read, _) = run_and_save_on(WRITE_WITH_CHART_SHEET, "    Sheets(\"B\").Activate");
    assert_eq!(read, ["active=B", "A selected=False", "B selected=True", "Chart selected=False"]);
}
