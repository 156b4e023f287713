//! The macros of the Excel-saved .xlsm files of the public corpus, run from the files
//! themselves (`ncsheet run FILE.xlsm --sub Module.Macro`). Each expected effect is worked
//! out by reading the macro (quoted in the test's comment) against the cells Excel saved;
//! macros that need forms, form controls or files are refused by name.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use ncsheet::formula::address::{parse_cell, Pos};
use ncsheet::workbook::Workbook;

fn corpus(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/excel-corpus/public").join(file)
}

/// Runs a macro of `file`, saving the workbook after it into `dir`: what it printed and
/// the workbook saved.
fn run(file: &str, sub: &str, args: &[&str], dir: &Path) -> (Output, Option<Workbook>) {
    run_path(&corpus(file), sub, args, &dir.join("after.xlsx"))
}

/// Runs a macro of the workbook at `path`, saving the workbook after it as `saved`.
fn run_path(path: &Path, sub: &str, args: &[&str], saved: &Path) -> (Output, Option<Workbook>) {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("run")
        .arg(path)
        .args(["--sub", sub])
        .args(args)
        .arg("--save")
        .arg(saved)
        .output()
        .unwrap();
    let wb = out.status.success().then(|| ncsheet::io::open(saved).unwrap().workbook);
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
        // Its module reaches files (`Workbooks`) in another procedure, which VBA compiles only
        // when it runs: the first thing this macro needs and a run has not is the check boxes.
        (calculator, "Module1.StartButton_Click", "CheckBoxes: a sheet's form controls"),
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

const CROSSREF: &str =
    "poi/test-data_spreadsheet_0-www-crossref-org.lib.rivier.edu_education-files_suffix-generator.xlsm";

/// The crossref workbook with a prefix typed into Form!B4 (the name `prefix`, as text) and
/// the number of DOIs into B5 (`noofdois`), saved as .xlsm (its macros kept) in `dir`.
fn crossref_with_prefix(dir: &Path, prefix: &str, count: u32) -> PathBuf {
    let path = dir.join("in.xlsm");
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("set")
        .arg(corpus(CROSSREF))
        .arg(format!("Form!B4='{prefix}"))
        .arg(format!("Form!B5={count}"))
        .arg("-o")
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    path
}

fn text_at(wb: &Workbook, sheet: &str, a1: &str) -> String {
    let id = wb.sheet_id(sheet).unwrap();
    match wb.value(id, parse_cell(a1).unwrap()) {
        ncsheet::eval::Value::Text(t) => t.to_string(),
        other => panic!("{sheet}!{a1} is {other:?}, not text"),
    }
}

fn hidden(wb: &Workbook, sheet: &str) -> bool {
    wb.sheet_visibility(wb.sheet_id(sheet).unwrap()) != ncsheet::workbook::Visibility::Visible
}

/// `CreateDOI` with prefix "10.5555" and 3 DOIs, read step by step:
/// - `Range("prefix").Copy Worksheets("Data_sheet").Range("a2").Resize(1 * Range("noofdois"))`:
///   Data_sheet!A2:A4 get the prefix.
/// - `LastRowColumnA = Cells(Rows.Count, 1).End(xlUp).Row` on Data_sheet (selected): 4, so
///   B2:B4 get the RANDBETWEEN formula: four capitals and four digits.
/// - A2:A1000 and B2:B1000 are copied and pasted as values at workings!A2 and B2; on
///   workings the last row of column A is again 4, so C2:C4 get `=A2 & $D$2 & B2` (D2 holds
///   "/"); C2:C2000's values are pasted at Form!B8: B8:B10 read "10.5555/" and each suffix.
/// - Both helper sheets end hidden again (as the file saved them).
///
/// The suffixes are random, so each is checked by its form and followed from sheet to sheet
/// (Data_sheet's RANDBETWEEN draws anew when the saved file is opened; the pasted values stay).
#[test]
fn crossref_create_doi_fills_the_form_with_prefix_slash_random_suffix() {
    let dir = tempfile::tempdir().unwrap();
    let input = crossref_with_prefix(dir.path(), "10.5555", 3);
    let (out, after) = run_path(&input, "Module1.CreateDOI", &[], &dir.path().join("doi.xlsm"));
    let after = after.unwrap_or_else(|| panic!("{}", stderr(&out)));
    let data = after.sheet_id("Data_sheet").unwrap();
    for row in 2..=4 {
        assert_eq!(text_at(&after, "Data_sheet", &format!("A{row}")), "10.5555");
        let formula = after.input(data, parse_cell(&format!("B{row}")).unwrap()).unwrap();
        assert!(formula.starts_with("=CHAR(RANDBETWEEN(65,90))"), "{formula}");
        let suffix = text_at(&after, "workings", &format!("B{row}"));
        let (letters, digits) = suffix.split_at(4);
        assert!(letters.chars().all(|c| c.is_ascii_uppercase()), "{suffix}");
        assert!(digits.len() == 4 && (1000..=9999).contains(&digits.parse::<u32>().unwrap()), "{suffix}");
        assert_eq!(text_at(&after, "workings", &format!("A{row}")), "10.5555");
        assert_eq!(text_at(&after, "Form", &format!("B{}", row + 6)), format!("10.5555/{suffix}"));
    }
    let form = after.sheet_id("Form").unwrap();
    assert_eq!(after.input(data, parse_cell("A5").unwrap()), None, "only noofdois rows get the prefix");
    assert_eq!(after.input(form, parse_cell("B11").unwrap()), None, "blank rows paste as blanks");
    assert!(hidden(&after, "Data_sheet") && hidden(&after, "workings") && !hidden(&after, "Form"));
}

/// `Reset` after `CreateDOI`: it clears Form!C4 and C5 (blank here: the prefix is in B4, B5),
/// then `Range(Selection, Selection.End(xlDown))` from B8:B10 twice, which reaches B10 (the
/// last filled cell below B8) and clears the DOIs; on Data_sheet from A2:B2 down to A4 (the
/// prefixes and the suffix formulas), on workings from A2:C2 down to row 4. Data_sheet's
/// other columns (C12's DOI formulas, F and G) and workings!D2 stay; both end hidden.
#[test]
fn crossref_reset_clears_what_create_doi_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let input = crossref_with_prefix(dir.path(), "10.5555", 3);
    let doi = dir.path().join("doi.xlsm");
    let (out, _) = run_path(&input, "Module1.CreateDOI", &[], &doi);
    assert!(out.status.success(), "{}", stderr(&out));
    let (out, after) = run_path(&doi, "Module1.Reset", &[], &dir.path().join("reset.xlsm"));
    let after = after.unwrap_or_else(|| panic!("{}", stderr(&out)));
    let before = ncsheet::io::open(&input).unwrap().workbook;
    assert_eq!(changes(&before, &after), []);
    assert!(hidden(&after, "Data_sheet") && hidden(&after, "workings") && !hidden(&after, "Form"));
}

/// `CreateDOI` with the prefix left empty: `If Range("prefix") = "" Then MsgBox "You must
/// enter a prefix into the box"` and `Exit Sub`: the message and no cell changed.
#[test]
fn crossref_create_doi_without_a_prefix_says_so_and_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (out, after) = run(CROSSREF, "Module1.CreateDOI", &[], dir.path());
    let after = after.unwrap_or_else(|| panic!("{}", stderr(&out)));
    assert!(stderr(&out).lines().any(|l| l == "You must enter a prefix into the box"), "{}", stderr(&out));
    assert_eq!(changes(&original(CROSSREF), &after), []);
}

/// `UnhideAll`: `For Each WS In Worksheets: WS.Visible = True`. The file hides Sheet2,
/// "Enrollment Restrictions" and "Variation Results" (`state="hidden"` in its workbook.xml);
/// after the macro every sheet is visible, in the file saved over the original package
/// (.xlsm) and in one written anew (.xlsx), and no cell changed.
#[test]
fn mv_calculator_unhide_all_shows_every_sheet() {
    let file = "poi/test-data_spreadsheet_mv-calculator-final-2-20-2013.xlsm";
    let before = original(file);
    let hidden_before: Vec<String> = before.sheet_names().into_iter().filter(|name| hidden(&before, name)).collect();
    assert_eq!(hidden_before, ["Sheet2", "Enrollment Restrictions", "Variation Results"]);
    for saved in ["after.xlsm", "after.xlsx"] {
        let dir = tempfile::tempdir().unwrap();
        let (out, after) = run_path(&corpus(file), "Module4.UnhideAll", &[], &dir.path().join(saved));
        let after = after.unwrap_or_else(|| panic!("{saved}: {}", stderr(&out)));
        let still: Vec<String> = after.sheet_names().into_iter().filter(|name| hidden(&after, name)).collect();
        assert_eq!(still, Vec::<String>::new(), "{saved}");
        assert_eq!(changes(&before, &after), [], "{saved}");
    }
}
