//! csv reading and writing through `ncsheet::io`: what a spreadsheet would read, round trips,
//! and errors that name the file and line.

use std::fs;
use std::path::Path;

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::{parse_cell, parse_rect};
use ncsheet::io::{self, Content, ErrorKind, Export};
use ncsheet::workbook::Workbook;

fn load_text(dir: &Path, name: &str, bytes: &[u8]) -> Result<Workbook, io::Error> {
    let path = dir.join(name);
    fs::write(&path, bytes).unwrap();
    io::load(&path)
}

/// The error of a load that must fail (`Workbook` has no `Debug` for `unwrap_err`).
fn load_err(res: Result<Workbook, io::Error>) -> io::Error {
    match res {
        Ok(_) => panic!("the file loaded"),
        Err(e) => e,
    }
}

fn get(wb: &Workbook, cell: &str) -> Value {
    wb.value(0, parse_cell(cell).unwrap())
}

fn text(s: &str) -> Value {
    Value::text(s)
}

#[test]
fn fields_are_read_as_a_spreadsheet_reads_typed_text() {
    let dir = tempfile::tempdir().unwrap();
    let wb = load_text(dir.path(), "a.csv", b"12.5,=A1*2,TRUE,#N/A,'12,50%,hello,=\"a\"&\"b\"\n").unwrap();
    assert_eq!(wb.sheet_names(), ["Sheet1"]);
    assert_eq!(get(&wb, "A1"), Value::Number(12.5));
    assert_eq!(get(&wb, "B1"), Value::Number(25.0));
    assert_eq!(get(&wb, "C1"), Value::Bool(true));
    assert_eq!(get(&wb, "D1"), Value::Error(XlError::NA));
    assert_eq!(get(&wb, "E1"), text("12"));
    assert_eq!(get(&wb, "F1"), Value::Number(0.5));
    assert_eq!(get(&wb, "G1"), text("hello"));
    assert_eq!(get(&wb, "H1"), text("ab"));
}

#[test]
fn blank_lines_are_empty_rows_and_quoted_line_breaks_stay_in_their_cell() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = b"\xEF\xBB\xBF1\r\n\r\n\"two\nlines\",\"a \"\"q\"\"\"\r\n=A1+A6\n\n7\n";
    let wb = load_text(dir.path(), "b.csv", bytes).unwrap();
    assert_eq!(get(&wb, "A1"), Value::Number(1.0));
    assert_eq!(get(&wb, "A2"), Value::Blank);
    assert_eq!(get(&wb, "A3"), text("two\nlines"));
    assert_eq!(get(&wb, "B3"), text("a \"q\""));
    // 1 + 7: the blank line before 7 is row 5, so 7 is in A6.
    assert_eq!(get(&wb, "A4"), Value::Number(8.0));
    assert_eq!(get(&wb, "A5"), Value::Blank);
}

#[test]
fn a_bad_formula_loads_as_an_error_value_and_the_rest_computes() {
    let dir = tempfile::tempdir().unwrap();
    let wb = load_text(dir.path(), "c.csv", b"=1+*2,=2+3\n").unwrap();
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Name));
    assert_eq!(get(&wb, "B1"), Value::Number(5.0));
    assert_eq!(wb.problems().len(), 1);
}

#[test]
fn malformed_files_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let err = load_err(load_text(dir.path(), "q.csv", b"a\nb\n\"c,d\ne\n"));
    assert!(matches!(err.kind, ErrorKind::Malformed { line: 3, .. }), "{err:?}");
    assert!(err.to_string().ends_with("q.csv: line 3: unterminated quoted field (a '\"' opened here is never closed)"));
    let err = load_err(load_text(dir.path(), "latin1.csv", b"ok\nbad \xE9\n"));
    assert!(matches!(err.kind, ErrorKind::Malformed { line: 2, .. }), "{err:?}");
    assert!(err.to_string().contains("latin1.csv: line 2: not UTF-8"), "{err}");
}

#[test]
fn missing_and_unknown_files_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let err = load_err(io::load(&dir.path().join("none.csv")));
    assert!(matches!(err.kind, ErrorKind::Read(_)));
    assert!(err.to_string().contains("none.csv: cannot read: "), "{err}");
    // A file of another program is named as such (a missing one is a read error first).
    std::fs::write(dir.path().join("a.numbers"), b"not a workbook ncsheet reads").unwrap();
    let err = load_err(io::load(&dir.path().join("a.numbers")));
    assert!(matches!(err.kind, ErrorKind::UnknownFormat), "{err:?}");
    // An xlsx that is not there is a read error naming it, like a csv.
    let err = load_err(io::load(&dir.path().join("a.XLSX")));
    assert!(err.to_string().starts_with(&format!("{}: ", dir.path().join("a.XLSX").display())), "{err}");
}

/// Every cell of a few rows, as typed, to compare two workbooks.
fn inputs(wb: &Workbook) -> Vec<Option<String>> {
    let rect = parse_rect("A1:F6").unwrap();
    let mut out = Vec::new();
    for row in rect.first.row..=rect.last.row {
        for col in rect.first.col..=rect.last.col {
            out.push(wb.input(0, ncsheet::formula::Pos::new(row, col)));
        }
    }
    out
}

#[test]
fn saving_and_loading_gives_back_the_same_inputs_and_values() {
    let dir = tempfile::tempdir().unwrap();
    let original =
        b"x,=A2*2,\"a,b\",'=not a formula\n0.1,=SUM(A2:A3),\"line\nbreak\",'007\n1e300,TRUE,#DIV/0!,\"q\"\"q\"\n";
    let wb = load_text(dir.path(), "in.csv", original).unwrap();
    let path = dir.path().join("out.csv");
    io::save(&wb, &path).unwrap();
    let again = io::load(&path).unwrap();
    assert_eq!(inputs(&again), inputs(&wb));
    assert_eq!(again.values(0), wb.values(0));
    assert_eq!(get(&again, "D1"), text("=not a formula"));
    assert_eq!(get(&again, "D2"), text("007"));
    assert_eq!(get(&again, "B2"), Value::Number(0.1 + 1e300));
    // Only the two files: the save went through a temporary file renamed into place.
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn exported_values_read_back_as_the_same_values() {
    let dir = tempfile::tempdir().unwrap();
    let wb = load_text(dir.path(), "in.csv", b"=\"=1\",=\"-x\",=\"TRUE\",=1/3,=1=1,=\"\"\n").unwrap();
    let path = dir.path().join("values.csv");
    io::export(&wb, &path, &Export { sheet: 0, range: None, content: Content::Values }).unwrap();
    assert_eq!(fs::read_to_string(&path).unwrap(), "'=1,'-x,'TRUE,0.333333333333333,TRUE,\n");
    let back = io::load(&path).unwrap();
    assert_eq!(get(&back, "A1"), text("=1"));
    assert_eq!(get(&back, "B1"), text("-x"));
    assert_eq!(get(&back, "C1"), text("TRUE"));
    assert_eq!(get(&back, "E1"), Value::Bool(true));
}

#[test]
fn an_export_range_is_written_whole_even_past_the_used_cells() {
    let dir = tempfile::tempdir().unwrap();
    let wb = load_text(dir.path(), "in.csv", b"1,2\n3,4\n").unwrap();
    let path = dir.path().join("r.csv");
    let what = Export { sheet: 0, range: parse_rect("B2:C3"), content: Content::Values };
    io::export(&wb, &path, &what).unwrap();
    assert_eq!(fs::read_to_string(&path).unwrap(), "4,\n,\n");
}

#[test]
fn a_csv_holds_one_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Other").unwrap();
    let err = io::save(&wb, &dir.path().join("two.csv")).unwrap_err();
    assert!(matches!(err.kind, ErrorKind::OneSheetOnly { sheets: 2 }), "{err:?}");
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_failed_save_leaves_no_file_behind() {
    let dir = tempfile::tempdir().unwrap();
    let wb = Workbook::with_sheet();
    let err = io::save(&wb, &dir.path().join("no/such/folder/x.csv")).unwrap_err();
    assert!(matches!(err.kind, ErrorKind::Write(_)));
    assert!(err.to_string().contains("x.csv: cannot write: "), "{err}");
}
