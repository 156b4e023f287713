//! The `ncsheet` binary as a user runs it: real files in a temporary folder, real exit codes.
//! Expected values are worked out by hand or taken from docs/domain.md, never from our code.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use common::cli::{Invocation, Run};

/// Runs `ncsheet ARGS` in `dir`, feeding `stdin` (or nothing).
fn ncsheet_in(dir: &Path, args: &[&str], stdin: &str) -> Run {
    Invocation { dir: Some(dir), stdin, ..Invocation::default() }.run(args)
}

/// A temporary folder holding `files` (name, content).
fn folder(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

fn read(dir: &tempfile::TempDir, name: &str) -> String {
    fs::read_to_string(dir.path().join(name)).unwrap()
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    names
}

fn repo_file(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

const PARTS: &str = "D,40\nf,2\ntotal,=B1+B2*3\n";

// ---------------------------------------------------------------------------------------
// The shipped sheet

#[test]
fn the_chamfer_sheet_reproduces_the_domain_table() {
    let sheet = repo_file("sheets/chamfer.csv");
    let run = ncsheet_in(Path::new("."), &["eval", sheet.to_str().unwrap(), "B28:D31", "--format", "json"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stderr, "");
    let json: serde_json::Map<String, serde_json::Value> = serde_json::from_str(&run.stdout).unwrap();
    let number = |cell: &str| json[&format!("Sheet1!{cell}")].as_f64().unwrap();
    let label = |cell: &str| json[&format!("Sheet1!{cell}")].as_str().unwrap().to_string();
    // docs/domain.md §1, outer chamfer, D=40 f=2 r=0.8 eA=eB=1: α=45° in column C, α=30° in D.
    let expected = [
        ("XA", 28, 44.262742, 42.325982),
        ("ZA", 29, -4.6, -4.6),
        ("XB", 30, 33.062742, 35.859659),
        ("ZB", 31, 1.0, 1.0),
    ];
    for (name, row, at45, at30) in expected {
        assert_eq!(label(&format!("B{row}")), name);
        let (c, d) = (number(&format!("C{row}")), number(&format!("D{row}")));
        assert!((c - at45).abs() < 5e-7, "{name} at 45°: {c}, docs/domain.md says {at45}");
        assert!((d - at30).abs() < 5e-7, "{name} at 30°: {d}, docs/domain.md says {at30}");
    }
}

#[test]
fn the_chamfer_sheet_prints_as_a_table_without_problems() {
    let sheet = repo_file("sheets/chamfer.csv");
    let run = ncsheet_in(Path::new("."), &["eval", sheet.to_str().unwrap()], "");
    assert_eq!((run.code, run.stderr.as_str()), (0, ""));
    assert!(run.stdout.lines().any(|l| l.starts_with("28  T1") && l.contains("XA")), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------
// eval

#[test]
fn eval_prints_the_sheet_as_a_table() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    // 40 + 2*3 = 46. Numbers right-aligned, text left-aligned, columns two spaces apart.
    assert_eq!(run.stdout, "   A      B\n1  D      40\n2  f       2\n3  total  46\n");
}

#[test]
fn eval_prints_csv_and_json() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "--format", "csv"], "");
    assert_eq!(run.stdout, "D,40\nf,2\ntotal,46\n");
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "--format", "json"], "");
    assert_eq!(
        run.stdout,
        "{\"Sheet1!A1\": \"D\", \"Sheet1!B1\": 40, \"Sheet1!A2\": \"f\", \"Sheet1!B2\": 2, \
         \"Sheet1!A3\": \"total\", \"Sheet1!B3\": 46}\n"
    );
}

#[test]
fn json_has_booleans_errors_fractions_and_no_blanks() {
    let dir = folder(&[("v.csv", "TRUE,,=1/0\n=1/8,x\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "v.csv", "--format", "json"], "");
    assert_eq!(
        run.stdout,
        "{\"Sheet1!A1\": true, \"Sheet1!C1\": \"#DIV/0!\", \"Sheet1!A2\": 0.125, \"Sheet1!B2\": \"x\"}\n"
    );
}

#[test]
fn eval_prints_named_cells_and_ranges() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "B3"], "");
    assert_eq!(run.stdout, "46\n");
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "B1", "Sheet1!B3"], "");
    assert_eq!(run.stdout, "B1  40\nB3  46\n");
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "B2:B3", "--format", "csv"], "");
    assert_eq!(run.stdout, "2\n46\n");
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "B2:B3", "--sheet", "sheet1"], "");
    assert_eq!(run.stdout, "   B\n2   2\n3  46\n");
}

#[test]
fn an_unknown_sheet_is_a_user_error() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "--sheet", "Nope"], "");
    assert_eq!(run.code, 1);
    assert_eq!(run.stderr, "ncsheet: parts.csv: no sheet named 'Nope' (it has: Sheet1)\n");
}

// ---------------------------------------------------------------------------------------
// Bad input: each a clear message or error value; the rest of the sheet still computes.

#[test]
fn a_formula_that_does_not_parse_is_shown_with_a_caret_and_the_rest_computes() {
    let dir = folder(&[("bad.csv", "1,=1+*2\n=A1+1,=A2*10\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "bad.csv"], "");
    // A cell error is a value: the sheet printed, so the command succeeded.
    assert_eq!(run.code, 0);
    assert_eq!(run.stdout, "   A  B\n1  1  #NAME?\n2  2      20\n");
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines[0], "ncsheet: bad.csv: Sheet1!B1: =1+*2");
    // The caret sits under the `*`, the 4th character of the formula.
    let formula_at = lines[0].find("=1+*2").unwrap();
    assert_eq!(lines[1].find('^'), Some(formula_at + 3), "{}", run.stderr);
    assert!(lines[1].contains("column 4"), "{}", run.stderr);
    assert_eq!(lines.len(), 2);
}

#[test]
fn the_issue_example_names_sheet1_b2() {
    let dir = folder(&[("parts.csv", "5\n=A1*2,=1+*2\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv"], "");
    assert_eq!(run.code, 0);
    assert!(run.stderr.starts_with("ncsheet: parts.csv: Sheet1!B2: =1+*2\n"), "{}", run.stderr);
    assert!(run.stdout.contains("2  10  #NAME?"), "{}", run.stdout);
}

#[test]
fn an_unknown_function_is_name_error_with_a_message() {
    let dir = folder(&[("f.csv", "=FOO(1),=2*3\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "f.csv"], "");
    assert_eq!(run.code, 0);
    assert_eq!(run.stdout, "   A       B\n1  #NAME?  6\n");
    assert!(run.stderr.starts_with("ncsheet: f.csv: Sheet1!A1: =FOO(1)\n"), "{}", run.stderr);
    assert!(run.stderr.contains("unknown function FOO"), "{}", run.stderr);
}

#[test]
fn a_reference_off_the_sheet_is_reported() {
    let dir = folder(&[("off.csv", "=XFE1,=A1048577,7\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "off.csv", "--format", "csv"], "");
    assert_eq!(run.code, 0);
    assert_eq!(run.stdout, "#NAME?,#NAME?,7\n");
    assert!(run.stderr.contains("Sheet1!A1: =XFE1"), "{}", run.stderr);
    assert!(run.stderr.contains("Sheet1!B1: =A1048577"), "{}", run.stderr);
    assert_eq!(run.stderr.matches("off the sheet").count(), 2, "{}", run.stderr);
}

#[test]
fn a_cycle_keeps_zero_and_is_named_while_the_rest_computes() {
    // A circular reference never computed shows 0 in Excel ("displays either a zero or the
    // last calculated value", Microsoft support, "Remove or allow a circular reference").
    let dir = folder(&[("c.csv", "=B1+1,=A1+1,4\n=C1*2\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "c.csv", "--format", "csv"], "");
    assert_eq!(run.code, 0);
    assert_eq!(run.stdout, "0,0,4\n8,,\n");
    assert_eq!(run.stderr, "ncsheet: c.csv: Sheet1!A1: circular reference: Sheet1!A1 -> Sheet1!B1\n");
}

#[test]
fn a_malformed_csv_names_the_file_and_line() {
    let dir = folder(&[("m.csv", "a,b\nc,\"unclosed\nd,e\n")]);
    let run = ncsheet_in(dir.path(), &["eval", "m.csv"], "");
    assert_eq!(run.code, 1);
    assert_eq!(run.stdout, "");
    assert!(run.stderr.starts_with("ncsheet: m.csv: line 2: unterminated quoted field"), "{}", run.stderr);
}

#[test]
fn a_missing_file_is_a_user_error_naming_it() {
    let dir = folder(&[]);
    let run = ncsheet_in(dir.path(), &["eval", "nosuch.csv"], "");
    assert_eq!(run.code, 1);
    assert!(run.stderr.starts_with("ncsheet: nosuch.csv: cannot read: "), "{}", run.stderr);
}

#[test]
fn a_csv_sheet_goes_to_xlsx_and_back_and_other_files_are_refused() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["set", "parts.csv", "B1=50", "-o", "out.xlsx"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    // D = 50, f = 2: total = D + 3·f as the sheet computes it.
    let run = ncsheet_in(dir.path(), &["eval", "out.xlsx", "B3"], "");
    assert_eq!((run.code, run.stdout.as_str()), (0, "56\n"), "{}", run.stderr);
    let run = ncsheet_in(dir.path(), &["eval", "missing.xlsx"], "");
    assert_eq!(run.code, 1);
    assert!(run.stderr.starts_with("ncsheet: missing.xlsx: "), "{}", run.stderr);
    std::fs::write(dir.path().join("parts.txt"), "not a table").unwrap();
    let run = ncsheet_in(dir.path(), &["eval", "parts.txt"], "");
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("parts.txt: unknown file type"), "{}", run.stderr);
}

#[test]
fn usage_errors_exit_with_2() {
    let dir = folder(&[("parts.csv", PARTS)]);
    for args in [
        &["eval"][..],
        &["eval", "parts.csv", "B3:"],
        &["eval", "parts.csv", "--format", "xml"],
        &["set", "parts.csv", "B1=1"],
        &["set", "parts.csv", "B1", "-o", "out.csv"],
        &["set", "parts.csv", "B1=1", "-o", "out.csv", "--in-place"],
        &["export", "parts.csv"],
        &["frobnicate"],
    ] {
        let run = ncsheet_in(dir.path(), args, "");
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
    }
}

// ---------------------------------------------------------------------------------------
// set

#[test]
fn set_writes_a_recalculated_copy_and_keeps_the_input() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["set", "parts.csv", "B1=45", "B2==B1/10", "-o", "out.csv"], "");
    // set says what it did, on stderr (stdout stays empty).
    assert_eq!((run.code, run.stdout.as_str()), (0, ""));
    assert_eq!(run.stderr, "Sheet1!B1 = 45\nSheet1!B2 = 4.5\nsaved out.csv\n");
    assert_eq!(read(&dir, "parts.csv"), PARTS);
    assert_eq!(read(&dir, "out.csv"), "D,45\nf,=B1/10\ntotal,=B1+B2*3\n");
    // 45 + (45/10)*3 = 58.5
    let run = ncsheet_in(dir.path(), &["eval", "out.csv", "B3"], "");
    assert_eq!(run.stdout, "58.5\n");
    assert_eq!(names_in(dir.path()), ["out.csv", "parts.csv"]);
}

#[test]
fn set_in_place_replaces_the_file_and_leaves_nothing_behind() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["set", "parts.csv", "B2=4", "C1=note, with comma", "--in-place"], "");
    assert_eq!((run.code, run.stdout.as_str()), (0, ""));
    assert_eq!(run.stderr, "Sheet1!B2 = 4\nSheet1!C1 = note, with comma\nsaved parts.csv\n");
    // Untouched rows keep their own length (issue 14): no padding to the widest row.
    assert_eq!(read(&dir, "parts.csv"), "D,40,\"note, with comma\"\nf,4\ntotal,=B1+B2*3\n");
    assert_eq!(names_in(dir.path()), ["parts.csv"]);
    let run = ncsheet_in(dir.path(), &["eval", "parts.csv", "B3"], "");
    assert_eq!(run.stdout, "52\n");
}

#[test]
fn set_refuses_to_overwrite_its_input_without_in_place() {
    let dir = folder(&[("parts.csv", PARTS)]);
    for out in ["parts.csv", "./parts.csv"] {
        let run = ncsheet_in(dir.path(), &["set", "parts.csv", "B1=1", "-o", out], "");
        assert_eq!(run.code, 2, "{}", run.stderr);
        assert!(run.stderr.contains("refusing to overwrite the input file parts.csv"), "{}", run.stderr);
        assert!(run.stderr.contains("--in-place"), "{}", run.stderr);
    }
    assert_eq!(read(&dir, "parts.csv"), PARTS);
}

#[test]
fn set_refuses_a_formula_that_does_not_parse_and_writes_nothing() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["set", "parts.csv", "B2==1+*2", "-o", "out.csv"], "");
    assert_eq!(run.code, 1);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines[0], "ncsheet: parts.csv: Sheet1!B2: =1+*2");
    assert_eq!(lines[1].find('^'), Some(lines[0].find("=1+*2").unwrap() + 3));
    assert_eq!(names_in(dir.path()), ["parts.csv"]);
}

#[test]
fn set_empties_a_cell_and_keeps_text_as_text() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run = ncsheet_in(dir.path(), &["set", "parts.csv", "A1=", "A2==x", "A3='12", "-o", "out.csv"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    // `==x` is the formula `=x` (an unknown name); `'12` is the text 12.
    assert_eq!(read(&dir, "out.csv"), ",40\n=x,2\n'12,=B1+B2*3\n");
    assert!(run.stderr.contains("Sheet1!A2: =x"), "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------
// export

const TEXTS: &str = "\
=\"=1+1\",=\"+x\",=\"-y\",=\"@z\",plain
\"=\"\"a,b\"\"\",=\"say \"\"hi\"\"\",=\"12\",-3,=1/4
";

#[test]
fn export_writes_values_and_guards_text_a_spreadsheet_would_run() {
    let dir = folder(&[("t.csv", TEXTS)]);
    let run = ncsheet_in(dir.path(), &["export", "t.csv", "-o", "v.csv"], "");
    assert_eq!((run.code, run.stderr.as_str()), (0, ""));
    // Text starting with = + - @ (and text that looks like a number) gets a leading ';
    // RFC 4180 quotes fields holding , or " and doubles the ". The number -3 stays a number.
    assert_eq!(read(&dir, "v.csv"), "'=1+1,'+x,'-y,'@z,plain\n\"a,b\",\"say \"\"hi\"\"\",'12,-3,0.25\n");
    // ncsheet reads the guarded text back as the same text.
    let run = ncsheet_in(dir.path(), &["eval", "v.csv", "--format", "json", "A1:D1", "C2"], "");
    assert_eq!(
        run.stdout,
        "{\"Sheet1!A1\": \"=1+1\", \"Sheet1!B1\": \"+x\", \"Sheet1!C1\": \"-y\", \"Sheet1!D1\": \"@z\", \
         \"Sheet1!C2\": \"12\"}\n"
    );
}

#[test]
fn export_formulas_writes_what_was_typed() {
    let dir = folder(&[("t.csv", TEXTS)]);
    let run = ncsheet_in(dir.path(), &["export", "t.csv", "-o", "f.csv", "--formulas", "--range", "D2:E2"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(read(&dir, "f.csv"), "-3,=1/4\n");
    let run = ncsheet_in(dir.path(), &["export", "t.csv", "-o", "f.csv", "--formulas", "--range", "A1:B1"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(read(&dir, "f.csv"), "\"=\"\"=1+1\"\"\",\"=\"\"+x\"\"\"\n");
}

#[test]
fn export_a_range_keeps_its_shape_and_sheet() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let run =
        ncsheet_in(dir.path(), &["export", "parts.csv", "-o", "r.csv", "--range", "B2:C3", "--sheet", "Sheet1"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(read(&dir, "r.csv"), "2,\n46,\n");
    let run = ncsheet_in(dir.path(), &["export", "parts.csv", "-o", "parts.csv"], "");
    assert_eq!(run.code, 2);
    assert_eq!(read(&dir, "parts.csv"), PARTS);
}

// ---------------------------------------------------------------------------------------
// repl

#[test]
fn a_piped_repl_session_sets_prints_saves_and_times_each_command() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let script = "B3\nB1=10\nB3\nA1:B2\nB2==B1/4\nsave new.csv\nquit\nB1=99\n";
    let run = ncsheet_in(dir.path(), &["repl", "parts.csv", "--timings"], script);
    assert_eq!(run.code, 0, "{}", run.stderr);
    // 40+6 = 46; then 10+6 = 16; B2 = 10/4 = 2.5.
    assert_eq!(run.stdout, "46\n10\n16\n   A  B\n1  D  10\n2  f   2\n2.5\nsaved new.csv\n");
    let times: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(times.len(), 7, "one timing per command up to quit: {}", run.stderr);
    for t in times {
        let seconds: f64 = t.strip_prefix("time_s=").expect("time_s=<seconds>").parse().unwrap();
        assert!((0.0..60.0).contains(&seconds));
    }
    assert_eq!(read(&dir, "new.csv"), "D,10\nf,=B1/4\ntotal,=B1+B2*3\n");
    assert_eq!(read(&dir, "parts.csv"), PARTS);
}

#[test]
fn a_piped_repl_reports_bad_commands_and_goes_on() {
    let dir = folder(&[("parts.csv", PARTS)]);
    let script = "B2==1+*2\nB2\nbogus\nB1==B3\nB2=3\n";
    let run = ncsheet_in(dir.path(), &["repl", "parts.csv"], script);
    // The broken formula is refused (B2 keeps 2); the cycle is set and named, its new
    // formula showing 0 as in Excel.
    assert_eq!(run.stdout, "2\n0\n3\n");
    assert!(run.stderr.contains("ncsheet: parts.csv: Sheet1!B2: =1+*2\n"), "{}", run.stderr);
    assert!(run.stderr.contains("unknown command 'bogus'"), "{}", run.stderr);
    assert!(run.stderr.contains("circular reference: Sheet1!B1 -> Sheet1!B3"), "{}", run.stderr);
    // Piped, a session with failed commands exits 1 so that a script notices.
    assert_eq!(run.code, 1);
    assert!(run.stderr.ends_with("ncsheet: parts.csv: 2 commands failed\n"), "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------
// functions

#[test]
fn functions_lists_each_with_signature_and_summary() {
    let run = ncsheet_in(Path::new("."), &["functions"], "");
    assert_eq!(run.code, 0);
    let sum = run.stdout.lines().find(|l| l.starts_with("SUM(")).expect("SUM is listed");
    assert!(sum.starts_with("SUM(number1, [number2], ...)"), "{sum}");
    let names: Vec<&str> = run.stdout.lines().map(|l| l.split('(').next().unwrap()).collect();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted);
    // Every row of the function table, once.
    assert_eq!(names.len(), ncsheet::eval::functions::REGISTRY.len());
    for f in ncsheet::eval::functions::REGISTRY.iter() {
        let listed = |l: &&str| l.starts_with(f.signature) && l.contains(f.summary);
        assert!(run.stdout.lines().any(|l| listed(&l)), "{} is not listed", f.name);
    }
}
