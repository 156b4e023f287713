//! Macros in document modules, run from the workbook itself: a worksheet button's macro lives
//! in its sheet's module (`Sheet1`), where `Range` and `Cells` without a sheet mean that sheet
//! (VBA: they are members of the module's own Worksheet, `Me`), whatever sheet is active;
//! `ThisWorkbook`'s code means the active sheet. `Workbook_Open` runs only when asked.
//! Expected values are worked out from those rules by hand.

use std::path::Path;
use std::process::Command;

use ncsheet::formula::address::parse_cell;
use ncsheet::io::xlsx::Layout;
use ncsheet::vba::project::{build_project, ModuleKind, NewModule};
use ncsheet::workbook::Workbook;

const WORKBOOK_CLASS: &str = "00020819-0000-0000-C000-000000000046";
const WORKSHEET_CLASS: &str = "00020820-0000-0000-C000-000000000046";

fn document(name: &str, class: &str, code: &str) -> NewModule {
    let source = format!(
        "Attribute VB_Name = \"{name}\"\r\nAttribute VB_Base = \"0{{{class}}}\"\r\n\
         Attribute VB_PredeclaredId = True\r\nAttribute VB_Exposed = True\r\n{code}"
    );
    NewModule { name: name.into(), kind: ModuleKind::DocumentOrClass, source }
}

const SHEET1: &str = "Private Sub Button1_Click()\r
    Worksheets(\"Setup\").Activate\r
    Range(\"A1\").Value = \"button\"\r
    Cells(2, 1).Value = Me.Name\r
    [A3] = Cells(1, 1).Value & \"?\"\r
    ActiveSheet.Range(\"A1\").Value = \"active\"\r
    Sheet2.Range(\"B1\").Value = Sheet1.Range(\"A1\").Value & \"!\"\r
End Sub\r
";

const THIS_WORKBOOK: &str = "Private Sub Workbook_Open()\r
    Worksheets(\"Data\").Range(\"C1\").Value = \"opened\"\r
End Sub\r
Sub Stamp()\r
    Range(\"C2\").Value = ActiveSheet.Name & \" \" & Me.Worksheets.Count\r
End Sub\r
";

/// Sheets `Data` and `Setup` whose code names are `Sheet1` and `Sheet2` (not their names,
/// so that the two cannot be confused), with a sheet module, the workbook's module and a
/// class module.
fn workbook_with_modules(dir: &Path) -> std::path::PathBuf {
    let mut wb = Workbook::new();
    wb.add_sheet("Data").unwrap();
    wb.add_sheet("Setup").unwrap();
    let mut layout = Layout { workbook_code_name: Some("ThisWorkbook".into()), ..Layout::default() };
    for (sheet, code) in [("Data", "Sheet1"), ("Setup", "Sheet2")] {
        layout.sheets.entry(sheet.into()).or_default().code_name = Some(code.into());
    }
    let modules = [
        document("ThisWorkbook", WORKBOOK_CLASS, THIS_WORKBOOK),
        document("Sheet1", WORKSHEET_CLASS, SHEET1),
        document("Sheet2", WORKSHEET_CLASS, ""),
        document(
            "Helper",
            "FCFB3D2A-A0FA-1068-A738-08002B3371B5",
            "Sub Go()\r\n    Range(\"D1\").Value = 1\r\nEnd Sub\r\n",
        ),
    ];
    layout.vba_project = Some(build_project(&modules, 0x4E).unwrap());
    let path = dir.join("buttons.xlsm");
    let encoded = ncsheet::io::encode_save(&wb, Some(&layout), &ncsheet::io::Origin::New, &path).unwrap();
    encoded.write(Default::default()).unwrap();
    path
}

fn run(book: &Path, sub: &str, save: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("run")
        .arg(book)
        .args(["--sub", sub, "--save"])
        .arg(save)
        .output()
        .unwrap()
}

fn text(wb: &Workbook, sheet: &str, cell: &str) -> String {
    wb.value(wb.sheet_id(sheet).unwrap(), parse_cell(cell).unwrap()).to_string()
}

#[test]
fn a_sheet_modules_macro_means_its_own_sheet_and_workbook_open_does_not_run() {
    let dir = tempfile::tempdir().unwrap();
    let book = workbook_with_modules(dir.path());
    let saved = dir.path().join("after.xlsx");
    let out = run(&book, "Sheet1.Button1_Click", &saved);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let wb = ncsheet::io::open(&saved).unwrap().workbook;
    // Setup is active from the first line on, but Range, Cells and [A3] are Sheet1's (Data).
    assert_eq!(text(&wb, "Data", "A1"), "button");
    // Me is the module's Worksheet: its Name is the sheet's name, not the code name.
    assert_eq!(text(&wb, "Data", "A2"), "Data");
    assert_eq!(text(&wb, "Data", "A3"), "button?");
    assert_eq!(text(&wb, "Setup", "A1"), "active");
    // Code names reach their sheets from anywhere: Sheet2 is Setup, Sheet1 is Data.
    assert_eq!(text(&wb, "Setup", "B1"), "button!");
    // Workbook_Open would have written Data!C1: ncsheet runs only the macro asked for.
    assert_eq!(text(&wb, "Data", "C1"), "");
}

#[test]
fn this_workbooks_code_means_the_active_sheet_and_me_is_the_workbook() {
    let dir = tempfile::tempdir().unwrap();
    let book = workbook_with_modules(dir.path());
    let saved = dir.path().join("after.xlsx");
    let out = run(&book, "ThisWorkbook.Stamp", &saved);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let wb = ncsheet::io::open(&saved).unwrap().workbook;
    assert_eq!(text(&wb, "Data", "C2"), "Data 2");
    assert_eq!(text(&wb, "Data", "C1"), "");
}

#[test]
fn a_class_or_form_modules_code_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let book = workbook_with_modules(dir.path());
    let out = run(&book, "Helper.Go", &dir.path().join("after.xlsx"));
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("Helper is a class or UserForm module"), "{err}");
    assert!(!dir.path().join("after.xlsx").exists());
}
