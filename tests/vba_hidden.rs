//! Rows and columns a macro hides (`Rows(3).Hidden = True`, `Columns("C").Hidden = True`,
//! `r.EntireRow.Hidden`, `r.EntireColumn.Hidden`) read back and are kept in the saved file,
//! both a file written new and an original package patched; shown again, they lose the mark.
//!
//! Expected values from Microsoft's Excel VBA reference, "Range.Hidden property": "Returns or
//! sets a Variant value that indicates if the rows or columns are hidden … The specified
//! range must span an entire column or row" (any other range: run-time error 1004). The saved
//! files are read by openpyxl (`row_dimensions[r].hidden`, `column_dimensions['C'].hidden`),
//! which reads `<row hidden="1">` and `<col hidden="1">` (ECMA-376 Part 1, 18.3.1.73 and
//! 18.3.1.13).

mod common;

use std::path::Path;
use std::process::Command;

use common::openpyxl::{openpyxl_available, python};
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

fn ncsheet(args: &[&Path]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap()
}

/// Runs `macro_text` on `book` with `ncsheet run … --save saved`; what it printed.
fn run_and_save(book: &Path, macro_text: &str, saved: &Path) -> String {
    let bas = book.with_file_name("hide.bas");
    std::fs::write(&bas, macro_text).unwrap();
    let out = ncsheet(&[Path::new("run"), book, &bas, Path::new("--save"), saved]);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    stderr
}

/// openpyxl's reading of which of rows 1–8 and columns A–F of the first sheet are hidden.
fn hidden_by_openpyxl(xlsx: &Path) -> String {
    python(
        "import sys, openpyxl\n\
         ws = openpyxl.load_workbook(sys.argv[1]).worksheets[0]\n\
         rows = [str(r) for r in range(1, 9) if ws.row_dimensions[r].hidden]\n\
         cols = [c for c in 'ABCDEF' if ws.column_dimensions[c].hidden]\n\
         print('rows', ','.join(rows), 'columns', ','.join(cols))",
        &[xlsx],
    )
    .trim()
    .to_string()
}

#[test]
fn hidden_rows_and_columns_read_back_and_a_part_range_is_refused() {
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n\
               Rows(3).Hidden = True\n\
               Range(\"B5\").EntireRow.Hidden = True\n\
               Columns(\"C\").Hidden = True\n\
               Debug.Print Rows(3).Hidden; Rows(4).Hidden; Range(\"A5\").EntireRow.Hidden; IsNull(Rows(\"3:4\").Hidden)\n\
               Rows(3).Hidden = False\n\
               Debug.Print Rows(3).Hidden; Columns(\"C\").Hidden; Range(\"C9\").EntireColumn.Hidden; Columns(\"D\").Hidden\n\
               End Sub\n";
    let out = vba::run(&mut wb, src, "hide.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["TrueFalseTrueTrue", "FalseTrueTrueFalse"]);
    let look = &out.looks.iter().find(|(name, _)| name == "Sheet1").expect("a look").1;
    assert_eq!(look.hidden_rows, [4]);
    assert_eq!(look.hidden_columns, [2]);

    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\nRange(\"A1:B2\").Hidden = True\nEnd Sub\n";
    let err =
        vba::run(&mut wb, src, "hide.bas", &RunOptions::default()).expect_err("a part of a row hidden").to_string();
    assert!(err.contains("1004") && err.contains("entire column or row"), "{err}");
}

#[test]
fn a_new_file_keeps_the_rows_and_columns_a_macro_hid() {
    if !openpyxl_available() {
        eprintln!("skipped: openpyxl is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("parts.csv");
    std::fs::write(&book, "a,b,c,d,e,f\n1,2,3,4,5,6\n7,8,9,10,11,12\n13,14,15,16,17,18\n19,20,21,22,23,24\n").unwrap();
    let saved = dir.path().join("hidden.xlsx");
    run_and_save(
        &book,
        "Sub Main()\n    Rows(3).Hidden = True\n    Range(\"A5\").EntireRow.Hidden = True\n\
         \x20   Columns(\"C\").Hidden = True\n    Range(\"E:F\").EntireColumn.Hidden = True\n\
         \x20   Columns(\"F\").Hidden = False\nEnd Sub\n",
        &saved,
    );
    assert_eq!(hidden_by_openpyxl(&saved), "rows 3,5 columns C,E");
}

#[test]
fn a_patched_original_keeps_what_a_macro_hid_and_loses_what_it_showed() {
    if !openpyxl_available() {
        eprintln!("skipped: openpyxl is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("original.xlsx");
    // The original hides row 4 and column D; rows 1–5 hold values, row 7 none.
    python(
        "import sys, openpyxl\n\
         wb = openpyxl.Workbook()\n\
         ws = wb.active\n\
         for r in range(1, 6):\n    ws.append([r, r * 2, r * 3, r * 4, r * 5])\n\
         ws.row_dimensions[4].hidden = True\n\
         ws.column_dimensions['D'].hidden = True\n\
         wb.save(sys.argv[1])",
        &[&book],
    );
    assert_eq!(hidden_by_openpyxl(&book), "rows 4 columns D");
    let saved = dir.path().join("patched.xlsx");
    let printed = run_and_save(
        &book,
        "Sub Main()\n    Debug.Print Rows(4).Hidden; Columns(\"D\").Hidden; Rows(2).Hidden\n\
         \x20   Rows(4).Hidden = False\n    Columns(\"D\").Hidden = False\n\
         \x20   Rows(2).Hidden = True\n    Rows(7).Hidden = True\n    Columns(\"B\").Hidden = True\n\
         \x20   Range(\"A1\").Value = 10\nEnd Sub\n",
        &saved,
    );
    // The file's marks read back as Excel reads them before the macro changes them.
    assert!(printed.contains("TrueTrueFalse"), "{printed}");
    assert_eq!(hidden_by_openpyxl(&saved), "rows 2,7 columns B");
}

#[test]
fn a_column_shown_again_inside_a_hidden_range_leaves_the_others_hidden() {
    if !openpyxl_available() {
        eprintln!("skipped: openpyxl is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("original.xlsx");
    // One `<col min="4" max="6" hidden="1">` hides D to F.
    python(
        "import sys, openpyxl\n\
         wb = openpyxl.Workbook()\n\
         ws = wb.active\n\
         ws.append([1, 2, 3, 4, 5, 6])\n\
         ws.column_dimensions.group('D', 'F', hidden=True)\n\
         wb.save(sys.argv[1])",
        &[&book],
    );
    let saved = dir.path().join("patched.xlsx");
    let printed = run_and_save(
        &book,
        "Sub Main()\n    Debug.Print Columns(\"C\").Hidden; Columns(\"E\").Hidden; Range(\"D:F\").EntireColumn.Hidden\n\
         \x20   Columns(\"E\").Hidden = False\n    Range(\"A1\").Value = 10\nEnd Sub\n",
        &saved,
    );
    assert!(printed.contains("FalseTrueTrue"), "{printed}");
    assert_eq!(hidden_by_openpyxl(&saved), "rows  columns D,F");
}

// Microsoft's "Change the column width or row height in Excel" gives the sizes' range as
// "0 (hidden)" to 409 points for a row and to 255 characters for a column: a hidden row's
// RowHeight and a hidden column's ColumnWidth read 0, and the height or width set before
// comes back when the line is shown again; a range of hidden and shown rows is Null
// ("Range.RowHeight": "Null if the rows in the specified range aren't all the same height").
#[test]
fn a_hidden_row_is_0_high_and_a_hidden_column_0_wide() {
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n\
               Rows(3).RowHeight = 30\n\
               Columns(\"C\").ColumnWidth = 20\n\
               Rows(3).Hidden = True\n\
               Rows(4).Hidden = True\n\
               Columns(\"C\").Hidden = True\n\
               Debug.Print Rows(3).RowHeight; Rows(4).RowHeight; Rows(5).RowHeight; Columns(\"C\").ColumnWidth\n\
               Debug.Print Rows(\"3:4\").RowHeight; IsNull(Rows(\"4:5\").RowHeight)\n\
               Rows(\"3:4\").Hidden = False\n\
               Columns(\"C\").Hidden = False\n\
               Debug.Print Rows(3).RowHeight; Rows(4).RowHeight; Columns(\"C\").ColumnWidth\n\
               End Sub\n";
    let out = vba::run(&mut wb, src, "hide.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 0  0  15  0 ", " 0 True", " 30  15  20 "]);
}
