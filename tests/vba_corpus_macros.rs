//! The macros of the Excel-saved .xlsm files of the public corpus, run from the files
//! themselves (`ncsheet run FILE.xlsm --sub Module.Macro`). Each expected effect is worked
//! out by reading the macro (quoted in the test's comment) against the cells Excel saved;
//! macros that need forms, form controls or files are refused by name.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use ncsheet::formula::address::{parse_cell, Pos};
use ncsheet::workbook::Workbook;

fn corpus(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/excel-corpus/public").join(file)
}

/// Runs a macro of `file`, saving the workbook after it into `dir`: what it printed and
/// the workbook saved.
fn run(file: &str, sub: &str, args: &[&str], dir: &Path) -> (Output, Option<Workbook>) {
    let saved = dir.join("after.xlsx");
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("run")
        .arg(corpus(file))
        .args(["--sub", sub])
        .args(args)
        .arg("--save")
        .arg(&saved)
        .output()
        .unwrap();
    let wb = out.status.success().then(|| ncsheet::io::open(&saved).unwrap().workbook);
    (out, wb)
}

/// Every cell's input, sheet by sheet, to compare a workbook before and after a macro.
fn inputs(wb: &Workbook) -> Vec<(String, Pos, String)> {
    let mut all = Vec::new();
    for (id, name) in wb.sheet_names().iter().enumerate() {
        let Some(used) = wb.used_rect(id as u16) else { continue };
        for row in used.first.row..=used.last.row {
            for col in used.first.col..=used.last.col {
                let pos = Pos::new(row, col);
                if let Some(text) = wb.input(id as u16, pos) {
                    all.push((name.clone(), pos, text));
                }
            }
        }
    }
    all
}

fn original(file: &str) -> Workbook {
    ncsheet::io::open(&corpus(file)).unwrap().workbook
}

/// The cells that differ between two workbooks, as (sheet, cell, input after).
fn changes(before: &Workbook, after: &Workbook) -> Vec<(String, Pos, String)> {
    let old = inputs(before);
    let new = inputs(after);
    let mut out: Vec<_> = new.iter().filter(|c| !old.contains(c)).cloned().collect();
    for (sheet, pos, _) in &old {
        if !new.iter().any(|(s, p, _)| s == sheet && p == pos) {
            out.push((sheet.clone(), *pos, String::new()));
        }
    }
    out
}

fn cell(sheet: &str, a1: &str, text: &str) -> (String, Pos, String) {
    (sheet.to_string(), parse_cell(a1).unwrap(), text.to_string())
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

const SIMPLE: &str = "poi/test-data_spreadsheet_SimpleMacro.xlsm";
const NAMES: &str = "poi/test-data_spreadsheet_testNames.xlsm";

/// `ActiveCell.FormulaR1C1 = "This is a macro workbook"` then `Range("A2").Select`: the file
/// saved Sheet1 active with C4 its active cell (`<selection activeCell="C4">`), so C4 gets
/// the text (a constant: it does not start with `=`), and selecting changes no cell.
#[test]
fn simple_macro_writes_its_text_into_the_saved_active_cell() {
    let dir = tempfile::tempdir().unwrap();
    let (out, after) = run(SIMPLE, "Module1.TestMacro", &[], dir.path());
    let after = after.unwrap_or_else(|| panic!("{}", stderr(&out)));
    assert_eq!(changes(&original(SIMPLE), &after), [cell("Sheet1", "C4", "This is a macro workbook")]);
}

/// `ActiveCell.FormulaR1C1 = "w"`: Sheet1's saved active cell is C2 (it held 14).
#[test]
fn test_names_macro1_writes_w_into_the_saved_active_cell() {
    let dir = tempfile::tempdir().unwrap();
    let (out, after) = run(NAMES, "Module1.Macro1", &[], dir.path());
    let after = after.unwrap_or_else(|| panic!("{}", stderr(&out)));
    assert_eq!(changes(&original(NAMES), &after), [cell("Sheet1", "C2", "w")]);
}

/// `myFunc = a & "abc"` and `myFunc2 = a & "abc2"`: functions of their argument, which
/// touch no cell.
#[test]
fn test_names_functions_run_and_change_no_cell() {
    for f in ["Module1.myFunc", "Module1.myFunc2"] {
        let dir = tempfile::tempdir().unwrap();
        let (out, after) = run(NAMES, f, &["--arg", "a=x"], dir.path());
        let after = after.unwrap_or_else(|| panic!("{f}: {}", stderr(&out)));
        assert_eq!(changes(&original(NAMES), &after), [], "{f}");
    }
}

/// `MsgBox "bingo"`, `MsgBox "Hello World"`, and a Sub holding only a comment: a message each
/// (on standard error) and no cell changed.
#[test]
fn message_box_macros_say_their_text_and_change_no_cell() {
    let cases = [
        ("poi/test-data_spreadsheet_45431.xlsm", "Module1.Button1_Click", "bingo"),
        ("openpyxl/openpyxl_tests_data_reader_vba+comments.xlsm", "Module1.Button1_Click", "Hello World"),
        ("poi/test-data_spreadsheet_ExcelWithAttachments.xlsm", "Module1.macro_excel", ""),
    ];
    for (file, sub, message) in cases {
        let dir = tempfile::tempdir().unwrap();
        let (out, after) = run(file, sub, &[], dir.path());
        let after = after.unwrap_or_else(|| panic!("{file} {sub}: {}", stderr(&out)));
        assert_eq!(changes(&original(file), &after), [], "{file} {sub}");
        let printed: Vec<String> =
            stderr(&out).lines().filter(|l| !l.starts_with("ncsheet:")).map(str::to_string).collect();
        let want: Vec<&str> = if message.is_empty() { vec![] } else { vec![message] };
        assert_eq!(printed, want, "{file} {sub}");
    }
}

/// Macros that need what a run has not are refused with the thing named, and write nothing:
/// a sheet's check boxes (form controls), a UserForm module, another workbook (a file).
#[test]
fn macros_needing_forms_controls_or_files_are_refused_by_name() {
    let calculator = "poi/test-data_spreadsheet_mv-calculator-final-2-20-2013.xlsm";
    let cases = [
        (calculator, "Module7.coins_med_all_Click2", "CheckBoxes: a sheet's form controls"),
        (calculator, "ThisWorkbook.Workbook_Open", "CheckBoxes: a sheet's form controls"),
        (calculator, "Module1.StartButton_Click", "Workbooks: a macro cannot touch files"),
        ("openpyxl/openpyxl_tests_data_reader_vba-test.xlsm", "AutoComp.SaveCohort", "AutoComp is a class or UserForm"),
    ];
    for (file, sub, said) in cases {
        let dir = tempfile::tempdir().unwrap();
        let (out, after) = run(file, sub, &[], dir.path());
        assert!(after.is_none(), "{file} {sub} ran");
        assert!(stderr(&out).contains(said), "{file} {sub}: {}", stderr(&out));
        assert!(!dir.path().join("after.xlsx").exists());
    }
}
