//! A macro's own files (issue 31, scopes 4 and 5): `Open`, `Print #`, `Write #`, `Input #`,
//! `Line Input #`, `Close`, `FreeFile`, `EOF` and Scripting's FileSystemObject, inside the
//! sandbox of `ncsheet run --out-dir DIR` and `--in-file PATH`.
//!
//! The formats are checked against Microsoft's VBA language reference (learn.microsoft.com,
//! "Office VBA language reference", the page named at each test) and [MS-VBAL]; the sandbox
//! runs the real `ncsheet run` binary on a temporary folder, with every spelling of a path
//! out of it.

mod common;

use std::path::Path;
use std::rc::Rc;

use common::cli::{ncsheet, Run};
use ncsheet::vba::{self, ErrorKind, FileAccess, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

// ---- the language, on files in memory ------------------------------------------------------

/// A sandbox with an empty output folder named `out` and the given inputs.
fn sandbox(inputs: &[(&str, &[u8])]) -> RunOptions {
    let inputs = inputs.iter().map(|(n, b)| (n.to_string(), Rc::from(*b))).collect();
    let files = FileAccess {
        out_dir: Some("out".into()),
        inputs,
        read_out_dir: Rc::new(|_| Ok(None)),
        list_out_dir: Rc::new(|| Ok(Vec::new())),
        modified_out_dir: Rc::new(|_| Ok(None)),
    };
    RunOptions { files: Some(files), ..RunOptions::default() }
}

fn run_with(src: &str, options: &RunOptions) -> Result<RunOutput, MacroError> {
    vba::run(&mut Workbook::with_sheet(), src, "Module1.bas", options)
}

fn run(src: &str) -> RunOutput {
    run_with(src, &sandbox(&[])).unwrap_or_else(|e| panic!("{e}"))
}

/// The one file a macro body wrote, as text.
fn written(body: &str) -> String {
    let out = run(&format!("Sub Main()\n{body}\nEnd Sub\n"));
    assert_eq!(out.files.len(), 1, "{:?}", out.files);
    String::from_utf8(out.files[0].1.clone()).unwrap()
}

fn fail(body: &str, options: &RunOptions) -> MacroError {
    match run_with(&format!("Sub Main()\n{body}\nEnd Sub\n"), options) {
        Ok(out) => panic!("ran: {:?}", out.files),
        Err(e) => e,
    }
}

// "Print # statement", its example: a blank line for `Print #1,`, `Tab` to the next print zone
// (zones are 14 columns: "Zone 2" starts in column 15), `Spc(5)` five spaces, `Tab(10)` to
// column 10, a Boolean as False; every line ends with CR LF ([MS-VBAL] 5.4.5: the line
// termination sequence).
#[test]
fn print_writes_the_reference_pages_example() {
    let text = written(
        "    Open \"TESTFILE\" For Output As #1
    Print #1, \"This is a test\"
    Print #1,
    Print #1, \"Zone 1\"; Tab ; \"Zone 2\"
    Print #1, \"Hello\" ; \" \" ; \"World\"
    Print #1, Spc(5) ; \"5 leading spaces \"
    Print #1, Tab(10) ; \"Hello\"
    Dim MyBool
    MyBool = False
    Print #1, MyBool ; \" is a Boolean value\"
    Close #1",
    );
    assert_eq!(
        text,
        "This is a test\r\n\r\nZone 1        Zone 2\r\nHello World\r\n     5 leading spaces \r\n         Hello\r\n\
         False is a Boolean value\r\n"
    );
}

// "Displaying Different Items on a Single Line" (Visual Basic reference): a positive number
// prints with a leading and a trailing space, a negative one with its sign instead of the
// leading space; `,` moves to the next 14-column zone; a trailing `;` keeps the line open
// for the next Print #. "Tab function": a column already passed is taken on the next line.
#[test]
fn print_spaces_numbers_and_zones_as_vba() {
    let text = written(
        "    Open \"n.txt\" For Output As #1
    Print #1, \"X\"; 2; \"Y\"; -7
    Print #1, 1, 2
    Print #1, \"a\";
    Print #1, \"b\"
    Print #1, \"abcdef\"; Tab(3); \"c\"
    Close #1",
    );
    assert_eq!(text, "X 2 Y-7 \r\n 1             2 \r\nab\r\nabcdef\r\n  c\r\n");
}

// "Write # statement", its example: items comma-delimited, strings in quotation marks, a
// blank line for `Write #1,`, Boolean data as #FALSE#, Error data as #ERROR errorcode#;
// "Nothing is written to the file if outputlist data is Empty. However, for Null data, #NULL#
// is written"; dates in the universal format, only the part given when the other is zero.
#[test]
fn write_quotes_and_delimits_as_the_reference_page() {
    let text = written(
        "    Open \"TESTFILE\" For Output As #1
    Write #1, \"Hello World\", 234
    Write #1,
    Dim MyBool
    MyBool = False
    Write #1, MyBool ; \" is a Boolean value\"
    Write #1, True, -1.5, CVErr(2007)
    Write #1, Null, Empty, #1/2/2020#, #1/2/2020 1:45:00 PM#, #1:45:00 PM#
    Close #1",
    );
    assert_eq!(
        text,
        "\"Hello World\",234\r\n\r\n#FALSE#,\" is a Boolean value\"\r\n#TRUE#,-1.5,#ERROR 2007#\r\n\
         #NULL#,,#2020-01-02#,#2020-01-02 13:45:00#,#13:45:00#\r\n"
    );
}

// "Input # statement": data written with Write # reads back item by item (a quoted string
// whole, commas inside it kept; numbers as numbers); "Line Input # statement" reads a line
// up to its CR LF without it; "EOF function" is True once the file is read to its end.
#[test]
fn input_and_line_input_read_back_what_was_written() {
    let out = run("Sub Main()
    Open \"data.txt\" For Output As #1
    Write #1, \"a, b\", 42, True
    Print #1, \"second line\"
    Close #1
    Dim s, n, b, line
    Open \"data.txt\" For Input As #1
    Input #1, s, n, b
    Debug.Print s; \"|\"; n * 2; \"|\"; b
    Do While Not EOF(1)
        Line Input #1, line
        Debug.Print \"[\" & line & \"]\"
    Loop
    Close #1
End Sub
");
    assert_eq!(out.printed, vec!["a, b| 84 |True", "[second line]"]);
}

// "Trappable errors": 62 Input past end of file, 53 File not found, 52 Bad file name or
// number, 55 File already open, 54 Bad file mode; each traps with On Error as VBA's do.
#[test]
fn file_errors_are_vbas_and_trappable() {
    let out = run("Sub Main()
    On Error Resume Next
    Open \"e.txt\" For Output As #1
    Close #1
    Open \"e.txt\" For Input As #1
    Line Input #1, s
    Debug.Print Err.Number
    Err.Clear
    Open \"missing.txt\" For Input As #2
    Debug.Print Err.Number
    Err.Clear
    Print #3, \"x\"
    Debug.Print Err.Number
    Err.Clear
    Open \"f.txt\" For Output As #1
    Debug.Print Err.Number
    Err.Clear
    Print #1, \"x\"
    Debug.Print Err.Number
End Sub
");
    assert_eq!(out.printed, vec![" 62 ", " 53 ", " 52 ", " 55 ", " 54 "]);
}

// "FreeFile function": the next file number not in use, from 1.
#[test]
fn freefile_gives_the_next_unused_number() {
    let out = run("Sub Main()
    Dim a, b
    a = FreeFile
    Open \"a.txt\" For Output As #a
    b = FreeFile()
    Debug.Print a; b
    Close #a
    Debug.Print FreeFile
End Sub
");
    assert_eq!(out.printed, vec![" 1  2 ", " 1 "]);
}

// "CreateTextFile method", "OpenTextFile method" (ForAppending 8, ForReading 1),
// "WriteLine method" (the string and a newline), "Write method" (no newline),
// "FileExists method", "ReadLine method", "AtEndOfStream property".
#[test]
fn filesystemobject_writes_appends_and_reads_text_streams() {
    let out = run("Sub Main()
    Dim fso, ts
    Set fso = CreateObject(\"Scripting.FileSystemObject\")
    Set ts = fso.CreateTextFile(\"prog.nc\", True)
    ts.WriteLine \"G0 X0\"
    ts.Write \"G1 \"
    ts.WriteLine \"X1\"
    ts.Close
    Debug.Print fso.FileExists(\"prog.nc\"); fso.FileExists(\"nope.nc\")
    Set ts = fso.OpenTextFile(\"prog.nc\", ForAppending)
    ts.WriteLine \"M30\"
    ts.Close
    Set ts = fso.OpenTextFile(\"prog.nc\", 1)
    Do Until ts.AtEndOfStream
        Debug.Print ts.ReadLine
    Loop
    ts.Close
End Sub
");
    assert_eq!(out.printed, vec!["TrueFalse", "G0 X0", "G1 X1", "M30"]);
    assert_eq!(out.files, vec![("prog.nc".to_string(), b"G0 X0\r\nG1 X1\r\nM30\r\n".to_vec())]);
}

#[test]
fn a_listed_input_is_read_by_its_file_name_and_never_written() {
    let options = sandbox(&[("points.csv", &b"1.5,2\r\n-3,4\r\n"[..])]);
    let out = run_with(
        "Sub Main()
    Dim x, z
    Open \"points.csv\" For Input As #1
    Do Until EOF(1)
        Input #1, x, z
        Debug.Print x + z
    Loop
    Close #1
End Sub
",
        &options,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, vec![" 3.5 ", " 1 "]);
    let e = fail("    Open \"points.csv\" For Append As #1", &options);
    assert!(e.message.contains("\"points.csv\": refused: it is an input (--in-file)"), "{e}");
}

#[test]
fn a_path_out_of_the_sandbox_stops_the_macro_even_under_on_error() {
    for path in ["..\\x.nc", "../x.nc", "/tmp/x.nc", "C:\\x.nc", "\\\\srv\\share\\x.nc", "CON", "a.txt:s"] {
        let e = fail(&format!("    On Error Resume Next\n    Open \"{path}\" For Output As #1"), &sandbox(&[]));
        assert_eq!(e.kind, ErrorKind::Runtime, "{path}");
        assert!(e.message.contains(&format!("Open \"{path}\": refused: ")), "{path}: {e}");
        assert_eq!(e.span.unwrap().line, 3, "{path}");
    }
    let e = fail(
        "    Set fso = CreateObject(\"Scripting.FileSystemObject\")\n    fso.CreateTextFile \"../x\"",
        &sandbox(&[]),
    );
    assert!(e.message.contains("CreateTextFile \"../x\": refused: "), "{e}");
    let e = fail(
        "    Set fso = CreateObject(\"Scripting.FileSystemObject\")\n    On Error GoTo 0\n    fso.CreateTextFile \"u.txt\", Encoding:=1",
        &sandbox(&[]),
    );
    assert!(e.message.contains("Named argument not found (run-time error 448): CreateTextFile:=Encoding"), "{e}");
    let e = fail(
        "    Set fso = CreateObject(\"Scripting.FileSystemObject\")\n    x = fso.FolderExists(\"C:\\Windows\")",
        &sandbox(&[]),
    );
    assert!(e.message.contains("FolderExists \"C:\\Windows\": refused: "), "{e}");
}

// "GetFileName method", "GetBaseName method", "GetExtensionName method",
// "GetParentFolderName method", "BuildPath method" and "GetDriveName method" work on the path's
// text alone (the values are those of Wine's scrrun tests, which run against Windows' own
// scrrun.dll too). "CreateTextFile method": `Unicode:=True` writes UTF-16 (little-endian, with
// its byte-order mark); "OpenTextFile method": its parameters are filename, iomode, create and
// format, here given by name. "FolderExists method": the folder the workbook is in exists.
#[test]
fn filesystemobject_names_paths_and_takes_named_arguments() {
    let out = run("Sub Main()
    Dim fso, ts, p
    Set fso = CreateObject(\"Scripting.FileSystemObject\")
    p = fso.BuildPath(ThisWorkbook.Path, \"O1000.tar.nc\")
    Debug.Print fso.GetFileName(p); \"|\"; fso.GetBaseName(p); \"|\"; fso.GetExtensionName(p)
    Debug.Print fso.GetParentFolderName(\"C:\\\\cnc\"); \"|\"; fso.GetParentFolderName(\"a/b//\"); \"|\"; fso.GetDriveName(\"D:\\x.nc\")
    Debug.Print fso.BuildPath(\"C:\", \"x.nc\"); \"|\"; fso.BuildPath(\"C:\\cnc\\\", \"\\x.nc\"); \"|\"; fso.GetBaseName(\".nc\")
    Debug.Print fso.FolderExists(ThisWorkbook.Path); fso.FolderExists(ThisWorkbook.Path & \"\\sub\")
    Set ts = fso.CreateTextFile(p, Overwrite:=True, Unicode:=True)
    ts.WriteLine \"G0\"
    ts.Close
    Set ts = fso.OpenTextFile(Filename:=\"plain.nc\", IOMode:=8, Create:=True)
    ts.Write \"M30\"
    ts.Close
End Sub
");
    assert_eq!(out.printed, vec!["O1000.tar.nc|O1000.tar|nc", "C:\\|a|D:", "C:x.nc|C:\\cnc\\x.nc|", "TrueFalse"]);
    assert_eq!(
        out.files,
        vec![
            ("O1000.tar.nc".to_string(), b"\xFF\xFEG\x000\x00\r\x00\n\x00".to_vec()),
            ("plain.nc".to_string(), b"M30".to_vec()),
        ]
    );
}

// Without --out-dir or --in-file the FileSystemObject is refused when the statement runs, as an
// error saying what it needs (not as a syntax error: VBA compiles CreateObject and creates the
// object only when it runs), and On Error does not skip it: the macro would write its program
// nowhere (issue 31).
#[test]
fn a_file_system_object_without_files_says_it_needs_out_dir() {
    let e = fail(
        "    On Error Resume Next\n    Set fso = CreateObject(\"Scripting.FileSystemObject\")",
        &RunOptions::default(),
    );
    assert_eq!(e.kind, ErrorKind::Runtime, "{e}");
    assert!(e.message.contains("file access needs a folder: run with `ncsheet run --out-dir DIR`"), "{e}");
    let span = e.span.unwrap();
    assert_eq!((span.line, span.col), (3, 15), "{e}");
    // A branch that never runs does not stop the macro.
    let src = "Sub Main()\n    If False Then Set fso = CreateObject(\"Scripting.FileSystemObject\")\n    Debug.Print 1\nEnd Sub\n";
    assert_eq!(run_with(src, &RunOptions::default()).unwrap().printed, [" 1 "]);
    // A save dialog has no user to answer it: without `run --input` it stops the run by name,
    // whatever On Error says.
    let e = fail("    On Error Resume Next\n    f = Application.GetSaveAsFilename(\"prog.nc\")", &sandbox(&[]));
    assert!(e.message.contains("Application.GetSaveAsFilename: a macro runs without a user"), "{e}");
    assert!(e.message.contains("--input TEXT"), "{e}");
    assert_eq!(e.span.map(|s| (s.line, s.col)), Some((3, 21)), "{e}");
}

// `run --input` answers the dialogs in the order the macro opens them. What each gives is
// Microsoft's: "InputBox function", the text typed, and "If the user chooses Cancel, the
// function returns a zero-length string"; "Application.InputBox method", the answer as Type
// says (1 a number, 8 a Range; text when Type is omitted) and False for Cancel;
// "Application.GetSaveAsFilename method" and "GetOpenFilename method", the name, or False when
// the user cancels. Past the last answer every dialog is cancelled. The name a save dialog
// gives is a file name as any other: in --out-dir it is written.
#[test]
fn input_answers_the_dialogs_in_order_and_cancels_past_the_last() {
    let src = "Sub Main()\n    Dim s, n, r, f\n    s = InputBox(\"Tool?\", \"Setup\", \"T1\")\n    \
               n = Application.InputBox(\"Passes?\", Type:=1)\n    Set r = Application.InputBox(\"Area?\", Type:=8)\n    \
               f = Application.GetSaveAsFilename(\"prog.nc\")\n    Open f For Output As #1\n    \
               Print #1, s; n * 2; r.Cells.Count\n    Close #1\n    \
               Debug.Print InputBox(\"More?\") = \"\"; Application.InputBox(\"x\"); Application.GetOpenFilename()\n\
               End Sub\n";
    let answers = ["T7", "3", "B2:C4", "part.nc"].map(String::from).to_vec();
    let out = run_with(src, &RunOptions { answers: Some(answers), ..sandbox(&[]) }).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.files.len(), 1, "{:?}", out.files);
    assert_eq!(out.files[0].0, "part.nc");
    assert_eq!(String::from_utf8(out.files[0].1.clone()).unwrap(), "T7 6  6 \r\n");
    assert_eq!(out.printed, ["TrueFalseFalse"]);
    // An answer that is not of the Type asked is refused by name (Excel would ask again).
    let src = "Sub Main()\n    n = Application.InputBox(\"Passes?\", Type:=1)\nEnd Sub\n";
    let e = run_with(src, &RunOptions { answers: Some(vec!["three".into()]), ..sandbox(&[]) }).unwrap_err();
    assert!(e.message.contains("the --input answer \"three\" is not of that type"), "{e}");
}

#[test]
fn reading_only_runs_refuse_every_write() {
    let mut options = sandbox(&[("in.txt", &b"x"[..])]);
    options.files.as_mut().unwrap().out_dir = None;
    let e = fail("    Open \"out.nc\" For Output As #1", &options);
    assert!(
        e.message.contains("\"out.nc\": refused: a macro writes files only inside a folder given with --out-dir"),
        "{e}"
    );
}

#[test]
fn written_bytes_count_against_the_memory_limit() {
    let options = RunOptions { max_memory: 1 << 20, ..sandbox(&[]) };
    let e = fail(
        "    Open \"big.txt\" For Output As #1\n    For i = 1 To 100000\n        Print #1, Space(99)\n    Next",
        &options,
    );
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    assert!(e.message.contains("--max-memory"), "{e}");
}

#[test]
fn text_windows_1252_cannot_hold_is_refused_not_replaced() {
    let e = fail("    Open \"u.txt\" For Output As #1\n    Print #1, ChrW(8364) & ChrW(1046)", &sandbox(&[]));
    assert!(e.message.contains("U+0416"), "{e}");
    // The euro sign is Windows-1252's 0x80.
    let out = run("Sub Main()\n    Open \"e.txt\" For Output As #1\n    Print #1, ChrW(8364)\nEnd Sub\n");
    assert_eq!(out.files, vec![("e.txt".to_string(), b"\x80\r\n".to_vec())]);
}

// VBA writes a character its ANSI code page lacks as "?" (a lossy conversion ncsheet refuses):
// the refusal is ncsheet's, so no On Error skips it and lets the macro go on with the text
// missing from its file (a record too long for Len is VBA's error 59, which it traps: above).
#[test]
fn on_error_does_not_skip_text_windows_1252_cannot_hold() {
    for (open, write) in
        [("Output", "Print #1, ChrW(1046)"), ("Binary", "Put #1, , ChrW(1046)"), ("Random", "Put #1, 1, ChrW(1046)")]
    {
        let e = fail(
            &format!(
                "    On Error Resume Next\n    Open \"u.bin\" For {open} As #1\n    {write}\n    \
                 Debug.Print \"went on\""
            ),
            &sandbox(&[]),
        );
        assert!(e.message.contains("U+0416"), "{write}: {e}");
        assert_eq!(e.span.map(|s| s.line), Some(4), "{write}: {e}");
    }
}

// ---- the sandbox, through `ncsheet run` ---------------------------------------------------

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// A folder with a workbook, a macro and an empty `out` folder; the run's answer.
fn run_macro(dir: &Path, bas: &str, extra: &[&str]) -> Run {
    let book = write(dir, "book.csv", "x\n1.5\n-2\n12.25\n");
    let macro_file = write(dir, "macro.bas", bas);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let mut args = vec!["run", &book, &macro_file, "--out-dir", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    ncsheet(&args)
}

/// Every file under a folder, however deep (symbolic links not followed), by its path there.
fn files_under(root: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut folders = vec![root.to_path_buf()];
    while let Some(dir) = folders.pop() {
        for entry in std::fs::read_dir(dir).unwrap() {
            let entry = entry.unwrap();
            if entry.file_type().unwrap().is_dir() {
                folders.push(entry.path());
            } else {
                out.push(entry.path().strip_prefix(root).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    out.sort();
    out
}

/// A G-code writer as shop macros are written: the program's blocks from the sheet's cells.
const GCODE_WRITER: &str = "Sub Main()
    Dim f As Integer, i As Integer
    f = FreeFile
    Open \"program.nc\" For Output As #f
    Print #f, \"%\"
    Print #f, \"O1001\"
    Print #f, \"G21 G90\"
    For i = 2 To 4
        Print #f, \"N\" & (i - 1) * 10 & \" G01 X\" & Format(Cells(i, 1).Value, \"0.000\") & \" F200\"
    Next i
    Print #f, \"M30\"
    Print #f, \"%\"
    Close #f
End Sub
";

#[test]
fn a_gcode_writer_writes_its_program_into_the_out_dir() {
    let dir = tempfile::tempdir().unwrap();
    let r = run_macro(dir.path(), GCODE_WRITER, &[]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let program = std::fs::read_to_string(dir.path().join("out/program.nc")).unwrap();
    assert_eq!(
        program,
        "%\r\nO1001\r\nG21 G90\r\nN10 G01 X1.500 F200\r\nN20 G01 X-2.000 F200\r\nN30 G01 X12.250 F200\r\nM30\r\n%\r\n"
    );
    assert!(r.stderr.contains("out/program.nc: 92 bytes"), "{}", r.stderr);
    assert_eq!(files_under(dir.path()), vec!["book.csv", "macro.bas", "out/program.nc"]);
}

#[test]
fn a_failing_macro_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let bas = GCODE_WRITER.replace("    Close #f\n", "    Close #f\n    Err.Raise 5\n");
    let r = run_macro(dir.path(), &bas, &[]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("its files were not written: program.nc"), "{}", r.stderr);
    assert_eq!(files_under(dir.path()), vec!["book.csv", "macro.bas"]);
}

#[test]
fn no_spelling_reaches_outside_the_out_dir() {
    let dir = tempfile::tempdir().unwrap();
    let outside = dir.path().join("outside.nc");
    let spellings = [
        "../outside.nc".to_string(),
        "..\\outside.nc".to_string(),
        outside.to_str().unwrap().to_string(),
        "sub/x.nc".to_string(),
        "sub\\..\\..\\outside.nc".to_string(),
        "C:\\outside.nc".to_string(),
        "c:outside.nc".to_string(),
        "\\\\server\\share\\outside.nc".to_string(),
        "//server/share/outside.nc".to_string(),
        "CON".to_string(),
        "nul.txt".to_string(),
        "COM1.nc".to_string(),
        "lpt1".to_string(),
        "a.txt:hidden".to_string(),
    ];
    for path in &spellings {
        for (how, statement) in [
            ("Open", format!("    Open \"{path}\" For Output As #1\n    Print #1, \"G0\"\n    Close #1")),
            ("Open", format!("    Open \"{path}\" For Append As #1")),
            ("Open", format!("    Open \"{path}\" For Input As #1")),
            (
                "CreateTextFile",
                format!(
                    "    Set fso = CreateObject(\"Scripting.FileSystemObject\")\n    Set t = fso.CreateTextFile(\"{path}\")"
                ),
            ),
            (
                "OpenTextFile",
                format!(
                    "    Set fso = CreateObject(\"Scripting.FileSystemObject\")\n    Set t = fso.OpenTextFile(\"{path}\")"
                ),
            ),
        ] {
            let r = run_macro(dir.path(), &format!("Sub Main()\n{statement}\nEnd Sub\n"), &[]);
            assert_eq!(r.code, 1, "{path}: {}", r.stderr);
            assert!(r.stderr.contains(&format!("{how} \"{path}\": refused: ")), "{path}: {}", r.stderr);
            assert_eq!(files_under(dir.path()), vec!["book.csv", "macro.bas"], "{path}");
        }
    }
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_in_the_out_dir_is_neither_read_nor_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let secret = write(dir.path(), "secret.txt", "keep out\n");
    std::fs::create_dir_all(dir.path().join("out")).unwrap();
    std::os::unix::fs::symlink(&secret, dir.path().join("out/link.txt")).unwrap();
    let read = "Sub Main()\n    Open \"link.txt\" For Input As #1\n    Line Input #1, s\n    Debug.Print s\nEnd Sub\n";
    let r = run_macro(dir.path(), read, &[]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("Open \"link.txt\": refused: ") && r.stderr.contains("symbolic link"), "{}", r.stderr);
    assert!(!r.stderr.contains("keep out"), "{}", r.stderr);
    for mode in ["Output", "Append"] {
        let bas = format!(
            "Sub Main()\n    Open \"link.txt\" For {mode} As #1\n    Print #1, \"G0\"\n    Close #1\nEnd Sub\n"
        );
        let r = run_macro(dir.path(), &bas, &[]);
        assert_eq!(r.code, 1, "{mode}: {}", r.stderr);
        assert!(r.stderr.contains("link.txt"), "{mode}: {}", r.stderr);
        assert!(r.stderr.contains("symbolic link"), "{mode}: {}", r.stderr);
        assert_eq!(std::fs::read_to_string(&secret).unwrap(), "keep out\n", "{mode}");
    }
}

#[test]
fn listed_inputs_are_read_and_the_folder_too() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir_all(&data).unwrap();
    let points = write(&data, "points.csv", "10,1\r\n20,2\r\n");
    std::fs::create_dir_all(dir.path().join("out")).unwrap();
    write(&dir.path().join("out"), "header.txt", "(HEADER)\r\n");
    let bas = "Sub Main()
    Dim x, z, head
    Open \"header.txt\" For Input As #2
    Line Input #2, head
    Close #2
    Open \"points.csv\" For Input As #1
    Open \"p.nc\" For Output As #3
    Print #3, head
    Do Until EOF(1)
        Input #1, x, z
        Print #3, \"G1 X\" & x & \" Z\" & z
    Loop
    Close
End Sub
";
    let r = run_macro(dir.path(), bas, &["--in-file", &points]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert_eq!(std::fs::read_to_string(dir.path().join("out/p.nc")).unwrap(), "(HEADER)\r\nG1 X10 Z1\r\nG1 X20 Z2\r\n");
    // Without --in-file the same file is out of reach.
    let r = run_macro(dir.path(), bas, &[]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("Open \"points.csv\": no such file"), "{}", r.stderr);
    assert!(r.stderr.contains("(run-time error 53)"), "{}", r.stderr);
}

#[test]
fn without_out_dir_file_statements_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "book.csv", "x\n1\n");
    let macro_file = write(dir.path(), "macro.bas", GCODE_WRITER);
    let r = ncsheet(&["run", &book, &macro_file]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("a macro cannot touch files or run programs"), "{}", r.stderr);
    assert!(r.stderr.contains("--out-dir"), "{}", r.stderr);
}

#[test]
fn the_macro_cannot_write_over_the_workbook_in_its_out_dir() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "book.csv", "x\n1\n");
    let bas = "Sub Main()\n    Open \"book.csv\" For Output As #1\n    Print #1, \"gone\"\n    Close #1\nEnd Sub\n";
    let macro_file = write(dir.path(), "macro.bas", bas);
    let r = ncsheet(&["run", &book, &macro_file, "--out-dir", dir.path().to_str().unwrap()]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("refusing to overwrite the input file"), "{}", r.stderr);
    assert_eq!(std::fs::read_to_string(&book).unwrap(), "x\n1\n");
}

#[test]
fn run_help_names_the_out_dir_and_the_in_files() {
    let r = ncsheet(&["run", "--help"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(r.stdout.contains("--out-dir <DIR>") && r.stdout.contains("--in-file <PATH>"), "{}", r.stdout);
}

// "Workbook.Path property (Excel)": the folder, without a separator at its end; a macro
// joins a file name to it with "\" or Application.PathSeparator. Here the folder is the
// one --out-dir gives, so such a macro writes there and nowhere else.
#[test]
fn this_workbook_path_is_the_out_dir() {
    let dir = tempfile::tempdir().unwrap();
    let bas = "Sub Main()
    Open ThisWorkbook.Path & \"\\a.nc\" For Output As #1
    Print #1, \"G0 X0\"
    Close #1
    Open ThisWorkbook.Path & Application.PathSeparator & \"b.nc\" For Output As #2
    Print #2, \"M30\"
    Close #2
End Sub
";
    let r = run_macro(dir.path(), bas, &[]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert_eq!(files_under(dir.path()), vec!["book.csv", "macro.bas", "out/a.nc", "out/b.nc"]);
    assert_eq!(std::fs::read_to_string(dir.path().join("out/a.nc")).unwrap(), "G0 X0\r\n");
    // The folder's name is no way out: what follows it is a plain name too.
    let bas = "Sub Main()\n    Open ThisWorkbook.Path & \"\\..\\x.nc\" For Output As #1\nEnd Sub\n";
    let r = run_macro(dir.path(), bas, &[]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("x.nc\": refused: \"..\" leaves the folder"), "{}", r.stderr);
    let e = fail("    x = ThisWorkbook.Path", &RunOptions::default());
    assert!(e.message.contains("ThisWorkbook.Path: a macro's folder is the one given with"), "{e}");
}

// File statements stand in a one-line If too ([MS-VBAL] 5.4.2.8: a single-line If holds
// any statement list), as real macros write `If Not EOF(1) Then Line Input #1, s`.
#[test]
fn file_statements_in_a_one_line_if() {
    let out = run("Sub Main()
    Open \"o.txt\" For Output As #1
    If 1 > 0 Then Print #1, \"yes\" Else Print #1, \"no\"
    Close #1
    Open \"o.txt\" For Input As #1
    If Not EOF(1) Then Line Input #1, s: Debug.Print s
    If EOF(1) Then Close #1
End Sub
");
    assert_eq!(out.printed, vec!["yes"]);
    assert_eq!(out.files, vec![("o.txt".to_string(), b"yes\r\n".to_vec())]);
}

// ---- Kill, Dir, FileLen, FileCopy -----------------------------------------------------------

// "Dir function": the first file name matching the pattern (wildcards * and ?), the next at
// each Dir without arguments, "" when none is left, and after that "" a Dir without a
// pattern is an error (5, "Invalid procedure call or argument"). "FileLen function": the
// length in bytes. "FileCopy statement": copies a file. "Kill statement": deletes files,
// wildcards allowed; "An error occurs if you try to use Kill to delete an open file" (75,
// Path/File access error); a file not there is 53, "File not found".
#[test]
fn kill_dir_filelen_and_filecopy_act_on_the_runs_files() {
    let out = run("Sub Main()
    Open \"b.nc\" For Output As #1: Print #1, \"G0\": Close #1
    Open \"a.nc\" For Output As #1: Print #1, \"G01 X5\": Close #1
    Open \"notes.txt\" For Output As #1: Print #1, \"x\": Close #1
    f = Dir(\"*.nc\")
    Do While f <> \"\"
        Debug.Print f; FileLen(f)
        f = Dir
    Loop
    FileCopy \"a.nc\", \"O1000.nc\"
    Debug.Print FileLen(\"O1000.nc\"); Dir(\"o????.NC\")
    Kill \"a.nc\"
    Debug.Print \"[\" & Dir(\"a.nc\") & \"]\"
    On Error Resume Next
    Kill \"a.nc\"
    Debug.Print Err.Number
    Err.Clear
    f = Dir
    Debug.Print Err.Number
    Err.Clear
    Open \"b.nc\" For Append As #2
    Kill \"b.nc\"
    Debug.Print Err.Number
    Close #2
    Err.Clear
    Kill \"*.txt\"
    Debug.Print Err.Number; \"[\" & Dir(\"notes.txt\") & \"]\"
End Sub
");
    assert_eq!(out.printed, ["a.nc 8 ", "b.nc 4 ", " 8 O1000.nc", "[]", " 53 ", " 5 ", " 75 ", " 0 []"]);
    let names: Vec<&str> = out.files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["b.nc", "O1000.nc"]);
    assert_eq!(out.files[1].1, b"G01 X5\r\n");
    assert!(out.removed.is_empty(), "only files of this run were deleted: {:?}", out.removed);
}

// "Kill statement" deletes a closed file and nothing else: the files open at the time
// ("Open statement": a file number stays tied to its file until Close) keep taking what
// Print # and Put # write ("Put statement": in Binary mode a variable-length String is
// written as its characters), though a file opened before them was killed.
#[test]
fn killing_a_file_leaves_the_files_open_after_it_their_own() {
    let out = run("Sub Main()
    Dim s As String
    Open \"x.txt\" For Output As #1: Print #1, \"X\": Close #1
    Open \"y.txt\" For Output As #2
    Open \"z.bin\" For Binary As #3
    Kill \"x.txt\"
    Print #2, \"Y\"
    s = \"Z\"
    Put #3, 1, s
    Close #2, #3
    Debug.Print \"[\" & Dir(\"x.txt\") & \"]\"; Dir(\"*.*\")
End Sub
");
    assert_eq!(out.printed, ["[]y.txt"]);
    let files: Vec<(&str, &[u8])> = out.files.iter().map(|(n, b)| (n.as_str(), b.as_slice())).collect();
    assert_eq!(files, [("y.txt", &b"Y\r\n"[..]), ("z.bin", &b"Z"[..])]);
}

#[test]
fn kill_removes_a_folder_file_only_when_the_macro_succeeds() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("out")).unwrap();
    write(&dir.path().join("out"), "old.nc", "G0\r\n");
    write(&dir.path().join("out"), "keep.txt", "x");
    let bas =
        "Sub Main()\n    Debug.Print Dir(\"*.nc\"); FileLen(\"old.nc\")\n    Kill ThisWorkbook.Path & \"\\old.nc\"\n\
               \x20   Debug.Print \"[\" & Dir(\"*.nc\") & \"]\"\n    Err.Raise 5\nEnd Sub\n";
    let r = run_macro(dir.path(), bas, &[]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("old.nc 4 \n[]"), "{}", r.stderr);
    assert_eq!(
        files_under(dir.path()),
        ["book.csv", "macro.bas", "out/keep.txt", "out/old.nc"],
        "a failed run deletes nothing"
    );
    let r = run_macro(dir.path(), &bas.replace("    Err.Raise 5\n", ""), &[]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(r.stderr.contains("removed ") && r.stderr.contains("old.nc, by the macro's Kill"), "{}", r.stderr);
    assert_eq!(files_under(dir.path()), ["book.csv", "macro.bas", "out/keep.txt"]);
}

#[test]
fn kill_dir_filelen_and_filecopy_reach_nothing_outside_the_out_dir() {
    let dir = tempfile::tempdir().unwrap();
    let outside = write(dir.path(), "outside.nc", "G0\r\n");
    for path in
        ["../outside.nc", "..\\outside.nc", outside.as_str(), "..\\*.nc", "/*", "C:\\*.*", "\\\\server\\share\\*"]
    {
        for (how, statement) in [
            ("Kill", format!("Kill \"{path}\"")),
            ("Dir", format!("Debug.Print Dir(\"{path}\")")),
            ("FileLen", format!("Debug.Print FileLen(\"{path}\")")),
            ("FileCopy", format!("FileCopy \"{path}\", \"copy.nc\"")),
            ("FileCopy", format!("FileCopy \"macro.bas\", \"{path}\"")),
        ] {
            if how != "Kill" && how != "Dir" && path.contains('*') {
                continue;
            }
            let bas = format!("Sub Main()\n    On Error Resume Next\n    {statement}\nEnd Sub\n");
            let r = run_macro(dir.path(), &bas, &[]);
            assert_eq!(r.code, 1, "{how} {path}: {}", r.stderr);
            assert!(r.stderr.contains(&format!("{how} \"{path}\": refused: ")), "{how} {path}: {}", r.stderr);
            assert_eq!(files_under(dir.path()), ["book.csv", "macro.bas", "outside.nc"], "{how} {path}");
        }
    }
    // MkDir and RmDir stay refused, with the reason, whatever the spelling.
    for statement in ["MkDir \"NC\"", "MkDir \"../NC\"", "RmDir \"NC\"", "MkDir \"/tmp/NC\""] {
        let r =
            run_macro(dir.path(), &format!("Sub Main()\n    On Error Resume Next\n    {statement}\nEnd Sub\n"), &[]);
        assert_eq!(r.code, 1, "{statement}: {}", r.stderr);
        assert!(r.stderr.contains("Dir: refused: ") && r.stderr.contains("symbolic link"), "{statement}: {}", r.stderr);
        assert_eq!(files_under(dir.path()), ["book.csv", "macro.bas", "outside.nc"], "{statement}");
    }
    // Without --out-dir the statements are refused by name, as before.
    let e = fail("    Kill \"a.nc\"", &RunOptions::default());
    assert!(e.message.contains("Kill: a macro cannot touch files"), "{e}");
}

// "Put statement" and "Get statement" (and [MS-VBAL] 5.4.5.11, 5.4.5.7): in a Binary file a
// variable's bytes go one after the other, little-endian: an Integer 2 bytes (-2 is FE FF), a
// Long 4, a Double 8, a Date 8 (its day count as a Double), a Byte 1; a variable-length
// String its characters only ("the number of bytes written equals the number of characters");
// a Variant 2 bytes of its VarType first, a String Variant then 2 bytes of length ("a Variant
// of VarType 8 … 2 bytes identifying the VarType, 2 bytes indicating the length"). Positions
// count from 1; Get reads back by the variable's type (a String for as many characters as it
// holds); "EOF function": True once a Get could not read a whole item; "Loc function": the
// last byte read or written (Binary), the last record (Random); "Seek function": the next
// position. In a Random file a record is `Len` bytes, a String there has its 2-byte length,
// and a Put longer than the record is error 59 ("Bad record length").
#[test]
fn binary_and_random_files_hold_vbas_bytes() {
    let out = run(
        "Sub Main()\n    Dim i As Integer, l As Long, d As Double, s As String, v, t As Date, b As Byte\n\
         \x20   i = -2: l = 70000: d = 1.5: s = \"AB\": v = \"xy\": t = #1/2/2024#: b = 255\n\
         \x20   Open \"B.BIN\" For Binary As #1\n\
         \x20   Put #1, , i\n    Put #1, , l\n    Put #1, , d\n    Put #1, , s\n    Put #1, , v\n    Put #1, , t\n    Put #1, , b\n\
         \x20   Debug.Print LOF(1); Loc(1); Seek(1)\n\
         \x20   Dim i2 As Integer, l2 As Long, d2 As Double, s2 As String, v2, t2 As Date\n    s2 = \"??\"\n\
         \x20   Get #1, 1, i2\n    Get #1, , l2\n    Get #1, , d2\n    Get #1, , s2\n    Get #1, , v2\n    Get #1, , t2\n\
         \x20   Debug.Print i2; l2; d2; s2; \" \"; v2; \" \"; t2; TypeName(t2); EOF(1)\n\
         \x20   Get #1, , b\n    Get #1, , i2\n    Debug.Print b; EOF(1)\n\
         \x20   Seek #1, 3\n    Get #1, , l2\n    Debug.Print l2; Seek(1)\n    Close #1\n\
         \x20   Open \"R.DAT\" For Random As #2 Len = 10\n    Put #2, 2, \"hello\"\n    Put #2, 1, 7&\n\
         \x20   Dim r As String, n As Long\n    Get #2, 2, r\n    Get #2, 1, n\n    Debug.Print r; n; LOF(2); Loc(2)\n\
         \x20   On Error Resume Next\n    Put #2, 1, \"longer than ten\"\n    Debug.Print Err.Number\n    Close\nEnd Sub\n",
    );
    assert_eq!(
        out.printed,
        [
            " 31  31  32 ",
            "-2  70000  1.5 AB xy 1/2/2024DateFalse",
            " 255 True",
            " 70000  7 ",
            "hello 7  20  1 ",
            " 59 "
        ]
    );
    let file = |name: &str| out.files.iter().find(|(n, _)| n == name).map(|(_, b)| b.clone()).unwrap();
    let mut binary = vec![0xFE, 0xFF, 0x70, 0x11, 0x01, 0x00];
    binary.extend(1.5f64.to_le_bytes());
    binary.extend(b"AB");
    binary.extend([8, 0, 2, 0, b'x', b'y']);
    binary.extend(45293f64.to_le_bytes());
    binary.push(0xFF);
    assert_eq!(file("B.BIN"), binary);
    let mut random = vec![7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5, 0];
    random.extend(b"hello");
    random.extend([0, 0, 0]);
    assert_eq!(file("R.DAT"), random);
}

// A Binary or Random file is one of the sandbox's names like any other ("no path outside
// --out-dir by any spelling"), and a listed input is read, never written: Put to it is
// error 75 ("Path/File access error").
#[test]
fn binary_files_keep_to_the_sandbox() {
    for path in ["../B.BIN", "/tmp/B.BIN", "sub/B.BIN", "C:\\B.BIN", "NUL", "\\\\server\\share\\B.BIN"] {
        let e = fail(&format!("    On Error Resume Next\n    Open \"{path}\" For Binary As #1"), &sandbox(&[]));
        assert!(e.message.contains("refused"), "{path}: {e}");
    }
    let options = sandbox(&[("IN.BIN", &[1, 0, 2, 0])]);
    let src = "Sub Main()\n    Dim a As Integer, b As Integer\n    Open \"IN.BIN\" For Binary As #1\n\
               \x20   Get #1, , a\n    Get #1, , b\n    Debug.Print a; b\n    On Error Resume Next\n    Put #1, 1, a\n\
               \x20   Debug.Print Err.Number\nEnd Sub\n";
    let out = run_with(src, &options).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 1  2 ", " 75 "]);
    assert!(out.files.is_empty(), "{:?}", out.files);
}

// "FileDateTime function": "Returns a Variant (Date) that indicates the date and time when a
// file was created or last modified", in local time. It reads the sandbox only, as FileLen: a
// file of --out-dir (its modification time), or one this run writes, which is written when
// the run ends, so at the run's clock; a missing file is error 53 ("File not found"); a listed
// input has no date in the run (its bytes only) and is refused by name.
#[test]
fn file_date_time_is_when_the_file_was_last_modified() {
    use std::time::{Duration, UNIX_EPOCH};
    // 2024-06-15 12:00:00 UTC: the 15th or 16th of June 2024 in every time zone.
    let june = UNIX_EPOCH + Duration::from_secs(1_718_452_800);
    let files = FileAccess {
        out_dir: Some("out".into()),
        inputs: vec![("in.txt".to_string(), Rc::from(&b"x"[..]))],
        read_out_dir: Rc::new(|_| Ok(None)),
        list_out_dir: Rc::new(|| Ok(Vec::new())),
        modified_out_dir: Rc::new(move |name| {
            Ok(match name {
                "a.nc" => Some(june),
                "b.nc" => Some(june + Duration::from_secs(3723)),
                _ => None,
            })
        }),
    };
    let options = RunOptions { files: Some(files), ..RunOptions::default() };
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().clock = Some(45_000.25);
    let src = "Sub Main()\n    Debug.Print TypeName(FileDateTime(\"a.nc\")); Year(FileDateTime(\"a.nc\")); \
               Month(FileDateTime(\"a.nc\"))\n\
               \x20   Debug.Print Round((FileDateTime(\"b.nc\") - FileDateTime(\"a.nc\")) * 86400)\n\
               \x20   Open \"new.nc\" For Output As #1\n    Print #1, \"G0 X0\"\n    Close #1\n\
               \x20   Debug.Print FileDateTime(\"new.nc\") = Now\n\
               \x20   On Error Resume Next\n    x = FileDateTime(\"none.nc\")\n    Debug.Print Err.Number\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "m.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["Date 2024  6 ", " 3723 ", "True", " 53 "]);
    let src = "Sub Main()\n    On Error Resume Next\n    x = FileDateTime(\"in.txt\")\nEnd Sub\n";
    let e = vba::run(&mut wb, src, "m.bas", &options).unwrap_err();
    assert!(e.message.contains("FileDateTime \"in.txt\"") && e.message.contains("--in-file"), "{e}");
}

// The same through `ncsheet run --out-dir`: the folder's file is read for its modification
// time, a symbolic link there is refused as for reading.
#[cfg(unix)]
#[test]
fn file_date_time_reads_the_out_dir() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let file = std::fs::File::create(out.join("old.nc")).unwrap();
    let june = std::time::UNIX_EPOCH + std::time::Duration::from_secs(1_718_452_800);
    file.set_modified(june).unwrap();
    drop(file);
    let bas = "Sub Main()\n    Debug.Print \"year\"; Year(FileDateTime(ThisWorkbook.Path & \"\\old.nc\"))\nEnd Sub\n";
    let r = run_macro(dir.path(), bas, &[]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(r.stderr.contains("year 2024"), "{}", r.stderr);
    std::os::unix::fs::symlink(dir.path().join("book.csv"), out.join("link.nc")).unwrap();
    let r = run_macro(dir.path(), "Sub Main()\n    x = FileDateTime(\"link.nc\")\nEnd Sub\n", &[]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    let refused = r.stderr.contains("FileDateTime \"link.nc\": refused") && r.stderr.contains("symbolic link");
    assert!(refused, "{}", r.stderr);
}

// "Put statement" ([MS-VBAL] 5.4.5.11: "If <data> is a UDT, then the value of each member of
// the UDT is written … in the order in which the members are declared"): a user-defined type
// is written "as if [each element] were written individually, except that there is no padding
// between elements", and in a Binary file "Put writes variable-length strings that are not
// elements of user-defined types without the 2-byte length descriptor" — so a String member
// keeps its 2-byte length; "For any array other than an array in a user-defined type, Put
// writes only the data". "Get statement" reads them back the same way ([MS-VBAL] 5.4.5.7).
// In a Random file a Type value is one record; a whole dynamic array there follows a
// descriptor whose content the reference does not give, and is refused.
#[test]
fn put_and_get_write_types_and_arrays_as_vba_lays_them_out() {
    let src = "Type Part\n    Id As Integer\n    Name As String\n    X As Double\n    Done As Boolean\n    Tag As Variant\n\
               End Type\nSub Main()\n    Dim p As Part, q As Part, a(1 To 3) As Long, b(1 To 3) As Long\n\
               \x20   p.Id = 7: p.Name = \"AB\": p.X = 1.5: p.Done = True: p.Tag = \"x\"\n\
               \x20   a(1) = 1: a(2) = -1: a(3) = 70000\n    Open \"T.BIN\" For Binary As #1\n    Put #1, , p\n    Put #1, , a\n\
               \x20   Get #1, 1, q\n    Get #1, , b\n\
               \x20   Debug.Print q.Id; q.Name; q.X; q.Done; q.Tag; b(1); b(2); b(3); Loc(1); LOF(1)\n    Close #1\n\
               \x20   Open \"T.DAT\" For Random As #2 Len = 21\n    Put #2, 2, p\n    Close #2\nEnd Sub\n";
    let out = run(src);
    assert_eq!(out.printed, [" 7 AB 1.5 Truex 1 -1  70000  33  33 "]);
    let file = |name: &str| out.files.iter().find(|(n, _)| n == name).map(|(_, b)| b.clone()).unwrap();
    let mut part = vec![7, 0, 2, 0, b'A', b'B'];
    part.extend(1.5f64.to_le_bytes());
    part.extend([0xFF, 0xFF, 8, 0, 1, 0, b'x']);
    let mut binary = part.clone();
    binary.extend([1, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF, 0x70, 0x11, 0x01, 0x00]);
    assert_eq!(file("T.BIN"), binary);
    let mut random = vec![0; 21];
    random.extend(&part);
    assert_eq!(file("T.DAT"), random);
    let e = fail(
        "    Dim a() As Long\n    ReDim a(2)\n    Open \"R.DAT\" For Random As #1 Len = 64\n    Put #1, 1, a",
        &sandbox(&[]),
    );
    assert!(e.message.contains("descriptor"), "{e}");
}

// "Put statement": "For any array other than an array in a user-defined type, Put writes only
// the data" — an Integer array of 5 × 10 items is 100 bytes of data (the page's
// `Dim MyArray(1 To 5, 1 To 10) As Integer`). VBA lays an array out with its first index
// varying fastest, which is why "ReDim statement" lets Preserve change only the last
// dimension: a(1, 1), a(2, 1), a(1, 2), … "Get statement" reads it back in the same order.
#[test]
fn put_and_get_write_a_two_dimensional_array_first_index_fastest() {
    let src = "Sub Main()\n    Dim a(1 To 2, 1 To 3) As Integer, b(1 To 2, 1 To 3) As Integer, m(1 To 5, 1 To 10) As Integer\n\
               \x20   For i = 1 To 2\n        For j = 1 To 3\n            a(i, j) = 10 * i + j\n        Next\n    Next\n\
               \x20   Open \"M.BIN\" For Binary As #1\n    Put #1, , a\n    Get #1, 1, b\n    Debug.Print b(2, 1); b(1, 3); LOF(1)\n\
               \x20   Close #1\n    Open \"P.BIN\" For Binary As #2\n    Put #2, , m\n    Debug.Print LOF(2)\n    Close #2\nEnd Sub\n";
    let out = run(src);
    assert_eq!(out.printed, [" 21  13  12 ", " 100 "]);
    let file = out.files.iter().find(|(n, _)| n == "M.BIN").map(|(_, b)| b.clone()).unwrap();
    assert_eq!(file, [11, 0, 21, 0, 12, 0, 22, 0, 13, 0, 23, 0]);
}

// "Put statement": "If the variable being written is a fixed-size array, Put writes only the
// data. No descriptor is written to disk", in a Random file too, as one record; "Get
// statement" reads it back the same way.
#[test]
fn put_and_get_write_a_fixed_size_array_in_a_random_file_as_its_data() {
    let src = "Sub Main()\n    Dim a(1 To 3) As Integer, b(1 To 3) As Integer\n    a(1) = 1: a(2) = 2: a(3) = -1\n\
               \x20   Open \"R.DAT\" For Random As #1 Len = 6\n    Put #1, 2, a\n    Get #1, 2, b\n\
               \x20   Debug.Print b(1); b(3); LOF(1); Loc(1)\n    Close #1\nEnd Sub\n";
    let out = run(src);
    assert_eq!(out.printed, [" 1 -1  12  2 "]);
    let file = out.files.iter().find(|(n, _)| n == "R.DAT").map(|(_, b)| b.clone()).unwrap();
    assert_eq!(file, [0, 0, 0, 0, 0, 0, 1, 0, 2, 0, 0xFF, 0xFF]);
}

// "Put statement": a user-defined type's elements are written one after another without
// padding; a fixed-length String (`String * 4`, "String data type") is its characters alone,
// no length descriptor (only a variable-length String has one), the Integer its 2 bytes
// little-endian. "Get statement" reads the record back the same way.
#[test]
fn put_and_get_write_a_fixed_length_string_field_as_its_characters() {
    let src = "Type TRec\n    name As String * 4\n    n As Integer\nEnd Type\n\
               Sub Main()\n    Dim r As TRec, q As TRec\n    r.name = \"AB\": r.n = 1\n\
               \x20   Open \"T.DAT\" For Binary As #1\n    Put #1, 1, r\n    Get #1, 1, q\n    Close #1\n\
               \x20   Debug.Print \"[\" & q.name & \"]\" & q.n\nEnd Sub\n";
    let out = run(src);
    assert_eq!(out.printed, ["[AB  ]1"]);
    let file = out.files.iter().find(|(n, _)| n == "T.DAT").map(|(_, b)| b.clone()).unwrap();
    assert_eq!(file, [b'A', b'B', b' ', b' ', 1, 0]);
}

// "Put statement": "If the variable being written is a Variant of a numeric type, Put writes
// 2 bytes identifying the VarType of the Variant and then writes the variable"; `v = 5` holds
// an Integer (a literal's type, "TypeName function" answers Integer), so its bytes are
// VarType 2 (vbInteger) and the 2-byte 5, and `w = 70000` a Long (3, then 4 bytes); in a
// Binary file an array's items alone ("No descriptor is written").
#[test]
fn a_variant_number_is_written_with_the_type_it_holds() {
    let out = run(
        "Sub Main()\n    Dim a() As Integer, v, w, v2, w2\n    ReDim a(1)\n    a(0) = 1: a(1) = 2\n\
         \x20   v = 5: w = 70000\n    Open \"V.BIN\" For Binary As #1\n    Put #1, , a\n    Put #1, , v\n    Put #1, , w\n\
         \x20   Get #1, 5, v2\n    Get #1, , w2\n    Debug.Print TypeName(v2); v2; TypeName(w2); w2\n    Close #1\nEnd Sub\n",
    );
    assert_eq!(out.printed, ["Integer 5 Long 70000 "]);
    let bytes = out.files.iter().find(|(n, _)| n == "V.BIN").map(|(_, b)| b.clone()).unwrap();
    assert_eq!(bytes, [1, 0, 2, 0, 2, 0, 5, 0, 3, 0, 0x70, 0x11, 0x01, 0x00]);
}

/// "Print # statement" writes text in the system's ANSI code page, the one the project was
/// written on: a Chinese shop's Excel (code page 936) writes the comment "(刀具 T1)" in GBK, a
/// Japanese one (932) reads "工具径補正" from Shift-JIS with Line Input #. The bytes are Python's
/// gbk and shift_jis codecs' ('(刀具 T1)'.encode('gbk')); before, every file was Windows-1252,
/// so the Chinese comment was refused and the Japanese line read as mojibake.
#[test]
fn text_files_are_written_and_read_in_the_projects_code_page() {
    let chinese = RunOptions { code_page: Some(936), ..sandbox(&[]) };
    let src = "Sub Main()\nOpen \"p.nc\" For Output As #1\nPrint #1, \"(刀具 T1)\"\nClose #1\nEnd Sub\n";
    let out = run_with(src, &chinese).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.files, vec![("p.nc".to_string(), b"(\xb5\xb6\xbe\xdf T1)\r\n".to_vec())]);
    let japanese =
        RunOptions { code_page: Some(932), ..sandbox(&[("t.txt", b"\x8d\x48\x8b\xef\x8c\x61\x95\xe2\x90\xb3\r\n")]) };
    let src = "Sub Main()\nDim s As String\nOpen \"t.txt\" For Input As #1\nLine Input #1, s\nClose #1\n\
               Debug.Print s; Len(s)\nEnd Sub\n";
    assert_eq!(run_with(src, &japanese).unwrap_or_else(|e| panic!("{e}")).printed, ["工具径補正 5 "]);
    // A character the code page has not is refused by name, never replaced.
    let src = "Sub Main()\nOpen \"p.nc\" For Output As #1\nPrint #1, \"Ω\"\nClose #1\nEnd Sub\n";
    let e = run_with(src, &sandbox(&[])).unwrap_err();
    assert!(e.message.contains("has no place in Windows-1252"), "{e}");
    let e = run_with(&src.replace('Ω', "ğ"), &chinese).unwrap_err();
    assert!(e.message.contains("has no place in code page 936 (GBK)"), "{e}");
}
