//! Module files in an ANSI code page other than Western (issue 31): the VBA editor exports a
//! module in the system's ANSI code page, which the file does not record, so a .bas with bytes
//! past ASCII that is not UTF-8 is read in the code page the user names (--code-page) or the
//! one the workbook's VBA project declares (its PROJECTCODEPAGE record, [MS-OVBA] 2.3.4.2.1.4),
//! or the one its text is guessed to be in when there is neither, where it was read as
//! Windows-1252 without a word (every byte is some 1252 character, so Cyrillic came out as
//! "Ñóììà").

mod common;

use std::path::{Path, PathBuf};

use common::cli::ncsheet;
use ncsheet::vba::project::read_project;

/// "Сумма прописью" in Windows-1251: Python's `'Сумма прописью'.encode('cp1251')`, whose
/// `bytes.decode('cp1251')` gives the text back; AscW of its first letter is 1057 (U+0421).
const CP1251_TEXT: &[u8] = b"\xD1\xF3\xEC\xEC\xE0 \xEF\xF0\xEE\xEF\xE8\xF1\xFC\xFE";
const TEXT: &str = "Сумма прописью";

/// A module whose fourth line holds the Cyrillic text at column 10.
fn cyrillic_module(dir: &Path) -> PathBuf {
    let mut bas = b"Attribute VB_Name = \"Rus\"\r\nSub Main()\r\n    Dim s As String\r\n    s = \"".to_vec();
    bas.extend_from_slice(CP1251_TEXT);
    bas.extend_from_slice(b"\"\r\n    Debug.Print s; Len(s); AscW(s)\r\nEnd Sub\r\n");
    let path = dir.join("rus.bas");
    std::fs::write(&path, bas).unwrap();
    path
}

/// A folder with the Cyrillic module and a one-cell workbook (book.csv) to run it on.
fn setup() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let bas = cyrillic_module(dir.path());
    let book = dir.path().join("book.csv");
    std::fs::write(&book, "x\n").unwrap();
    (dir, bas, book)
}

fn text(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// "Print # statement"/Debug.Print: `;` puts items side by side, a positive number printed
/// with a leading space and a trailing one ("Str function").
fn printed_line() -> String {
    format!("{TEXT} 14  1057 ")
}

/// With no code page named and no project to declare one, the module's code page is guessed
/// from its text (Windows-1251 here): it is read as written, said on stderr, and a new project
/// is written in it, where before this session it was read as Windows-1252 without a word.
#[test]
fn a_new_project_takes_the_code_page_its_module_is_guessed_to_be_in() {
    let (dir, bas, book) = setup();
    let out = dir.path().join("out.xlsm");
    let done = ncsheet(&["macros", text(&book), "--import", text(&bas), "-o", text(&out)]);
    assert_eq!(done.code, 0, "{}", done.stderr);
    assert!(done.stderr.contains("rus.bas: read in code page 1251, guessed"), "{}", done.stderr);
    let bytes = ncsheet::io::open(&out).unwrap().layout.unwrap().vba_project.unwrap();
    let project = read_project(&bytes).unwrap();
    assert_eq!(project.code_page, 1251);
    let ran = ncsheet(&["run", text(&book), text(&bas)]);
    assert!(ran.code == 0 && ran.stderr.lines().any(|l| l == printed_line()), "{}", ran.stderr);
}

/// "Print # statement" writes in the system's ANSI code page: a module whose code page is
/// guessed from its text (no --code-page, no project) came from a machine with that code page,
/// so its Print # writes the Cyrillic text in Windows-1251 too, the bytes Python's
/// `'Сумма прописью'.encode('cp1251')` gives, where it was refused as no Windows-1252 text.
#[test]
fn a_guessed_modules_text_files_are_written_in_its_code_page() {
    let dir = tempfile::tempdir().unwrap();
    let mut bas = b"Sub Main()\r\n    Open \"out.txt\" For Output As #1\r\n    Print #1, \"".to_vec();
    bas.extend_from_slice(CP1251_TEXT);
    bas.extend_from_slice(b"\"\r\n    Close #1\r\nEnd Sub\r\n");
    let module = dir.path().join("writer.bas");
    std::fs::write(&module, bas).unwrap();
    let book = dir.path().join("book.csv");
    std::fs::write(&book, "x\n").unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let ran = ncsheet(&["run", text(&book), text(&module), "--out-dir", text(&out)]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    assert!(ran.stderr.contains("writer.bas: read in code page 1251, guessed"), "{}", ran.stderr);
    let written = std::fs::read(out.join("out.txt")).unwrap();
    assert_eq!(written, [CP1251_TEXT, b"\r\n"].concat());
}

#[test]
fn a_module_in_the_code_page_named_imports_into_a_project_of_that_code_page_and_runs() {
    let (dir, bas, book) = setup();
    let out = dir.path().join("out.xlsm");
    let done = ncsheet(&["macros", text(&book), "--import", text(&bas), "--code-page", "1251", "-o", text(&out)]);
    assert_eq!(done.code, 0, "{}", done.stderr);
    let bytes = ncsheet::io::open(&out).unwrap().layout.unwrap().vba_project.unwrap();
    let project = read_project(&bytes).unwrap();
    assert_eq!(project.code_page, 1251);
    let rus = project.modules.iter().find(|m| m.name == "Rus").unwrap();
    assert!(rus.source.contains(&format!("s = \"{TEXT}\"")), "{:?}", rus.source);
    let ran = ncsheet(&["run", text(&out), "--sub", "Rus.Main"]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    assert!(ran.stderr.lines().any(|l| l == printed_line()), "{}", ran.stderr);
    // The .bas run on its own reads the same with the same option (and its alias).
    let ran = ncsheet(&["run", text(&book), text(&bas), "--codepage", "1251"]);
    assert!(ran.code == 0 && ran.stderr.lines().any(|l| l == printed_line()), "{}", ran.stderr);
}

/// The workbook's own project declares its code page: a .bas run beside it, or imported into
/// it, is read in that one ([MS-OVBA] 2.3.4.2.1.4 PROJECTCODEPAGE: "the code page for the
/// VBA project"), as the VBA editor of that project would import it. (The second import also
/// reads back the .xlsm the first wrote, whose vbaProject.bin is stored uncompressed: that was
/// refused, "Unsupported compression level".)
#[test]
fn the_projects_code_page_reads_a_module_given_beside_it() {
    let (dir, bas, book) = setup();
    let russian = dir.path().join("ru.xlsm");
    let done = ncsheet(&["macros", text(&book), "--import", text(&bas), "--code-page", "1251", "-o", text(&russian)]);
    assert_eq!(done.code, 0, "{}", done.stderr);
    let ran = ncsheet(&["run", text(&russian), text(&bas)]);
    assert!(ran.code == 0 && ran.stderr.lines().any(|l| l == printed_line()), "{}", ran.stderr);
    let again = dir.path().join("Rus2.bas");
    std::fs::write(&again, std::fs::read(&bas).unwrap()).unwrap();
    let replaced = dir.path().join("ru2.xlsm");
    let done = ncsheet(&["macros", text(&russian), "--import", text(&again), "--replace", "-o", text(&replaced)]);
    assert_eq!(done.code, 0, "{}", done.stderr);
}

#[test]
fn a_code_page_ncsheet_cannot_read_is_a_usage_error_listing_those_it_can() {
    let (_dir, bas, book) = setup();
    let ran = ncsheet(&["run", text(&book), text(&bas), "--code-page", "437"]);
    assert!(
        ran.code != 0 && ran.stderr.contains("'437' is no code page") && ran.stderr.contains("932"),
        "{}",
        ran.stderr
    );
}

// "Asc function" (VBA reference): it "Returns an Integer representing the character code";
// "The AscW function returns the Unicode character code". So AscW("€") is 8364 (U+20AC, where
// Asc gives 128, its Windows-1252 byte), AscW of ChrW(&HFFFF) is the Integer -1, and empty
// text is a run-time error (5, "Invalid procedure call or argument").
#[test]
fn ascw_gives_the_unicode_code_of_the_first_character() {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let printed = common::vba::run_main(
        &mut wb,
        "    Debug.Print AscW(\"€uro\"); Asc(\"€\"); AscW(\"С\"); AscW(ChrW(&HFFFF)); AscW(\"A\")\n\
         \x20   On Error Resume Next\n    Debug.Print AscW(\"\"): Debug.Print Err.Number",
    );
    assert_eq!(printed, [" 8364  128  1057 -1  65 ", " 5 "]);
}

/// A Western module as the VBA editor of a German Excel exports it (Windows-1252: "°" 0xB0,
/// "ö" 0xF6, "ß" 0xDF; Python's `'Größe in °'.encode('cp1252')`) runs without --code-page, as it
/// did before module code pages were checked: Len 10, AscW("°") 176.
#[test]
fn a_western_module_runs_without_a_code_page() {
    let dir = tempfile::tempdir().unwrap();
    let bas = dir.path().join("west.bas");
    std::fs::write(
        &bas,
        b"Attribute VB_Name = \"West\"\r\nSub Main()\r\n    Dim s As String\r\n    s = \"Gr\xF6\xDFe in \xB0\"\r\n    Debug.Print s; Len(s); AscW(Right(s, 1))\r\nEnd Sub\r\n",
    )
    .unwrap();
    let book = dir.path().join("book.csv");
    std::fs::write(&book, "x\n").unwrap();
    let ran = ncsheet(&["run", text(&book), text(&bas)]);
    assert!(ran.code == 0 && ran.stderr.lines().any(|l| l == "Größe in ° 10  176 "), "{}", ran.stderr);
}

/// A UTF-8 module with a character no ANSI Western byte stands for (psychrolib's comments write
/// "kg_H₂O"; U+2082 SUBSCRIPT TWO is not in Microsoft's Windows-1252 table, where Python's
/// `'₂'.encode('cp1252')` fails) cannot go into a project in 1252: the refusal names the
/// character and its line and column in the file, where it named only the module.
#[test]
fn a_character_the_projects_code_page_lacks_is_refused_at_its_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let bas = dir.path().join("psy.bas");
    std::fs::write(&bas, "Function Ratio()\n' Humidity in kg_H₂O per kg\n    Ratio = 1\nEnd Function\n").unwrap();
    let book = dir.path().join("book.csv");
    std::fs::write(&book, "x\n").unwrap();
    let out = dir.path().join("out.xlsm");
    let done = ncsheet(&["macros", text(&book), "--import", text(&bas), "-o", text(&out)]);
    assert!(
        done.code != 0
            && done.stderr.contains("psy: line 2, column 19: '₂' (U+2082) is a character code page 1252 cannot write"),
        "{}",
        done.stderr
    );
}
