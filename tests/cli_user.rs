//! The command line as a shop user meets it (issue 18): names where cells go, formulas and
//! formats seen, typed input read as a spreadsheet reads it with a word when it looks wrong,
//! and stdout carrying only what a user redirects. Each test runs the real binary; expected
//! values are worked out by hand here (or by LinuxCNC's rs274), never taken from our code.

mod common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use ncsheet::formula::address::Pos;
use ncsheet::workbook::Workbook;

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

fn ncsheet_with(args: &[&str], stdin: &str) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the ncsheet binary runs");
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    Run {
        code: out.status.code().expect("exited normally"),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

fn ncsheet(args: &[&str]) -> Run {
    ncsheet_with(args, "")
}

fn repo(path: &str) -> String {
    format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// A workbook built around names, as the user's own: alpha in B1, XA = 40 + 2·tan(alpha) in B2.
fn named_workbook(dir: &Path) -> String {
    let mut wb = Workbook::with_sheet();
    wb.set_input(0, Pos::new(0, 0), "alpha").unwrap();
    wb.set_input(0, Pos::new(0, 1), "45").unwrap();
    wb.set_input(0, Pos::new(1, 0), "XA").unwrap();
    wb.set_input(0, Pos::new(1, 1), "=40+2*TAN(RADIANS(alpha))").unwrap();
    wb.define_name("alpha", "=Sheet1!$B$1", None).unwrap();
    wb.define_name("XA", "=Sheet1!$B$2", None).unwrap();
    let path: PathBuf = dir.join("named.xlsx");
    ncsheet::io::save(&wb, &path).unwrap();
    path.to_str().unwrap().to_string()
}

fn number(text: &str) -> f64 {
    text.trim().parse().unwrap_or_else(|_| panic!("not a number: {text:?}"))
}

// ---------------------------------------------------------------------------------------
// 1. stdout carries one thing

#[test]
fn a_redirected_macro_run_is_a_program_rs274_reads() {
    let dir = tempfile::tempdir().unwrap();
    let run = ncsheet(&[
        "run",
        &repo("sheets/chamfer.xlsx"),
        &repo("sheets/chamfer.bas"),
        "--sheet",
        "Outer",
        "--dialect",
        "linuxcnc",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.starts_with('%'), "stdout must start with the program: {}", run.stdout);
    // The macro's Debug.Print line (XA=44.263 …) went to stderr.
    assert!(run.stderr.contains("XA=44.263"), "{}", run.stderr);
    let program = dir.path().join("p.ngc");
    std::fs::write(&program, &run.stdout).unwrap();
    if !common::rs274::available() {
        eprintln!("skipped the rs274 part: rs274 is not installed");
        return;
    }
    let moves = common::rs274::moves(&program).unwrap();
    assert!(moves.iter().any(|m| matches!(m, common::rs274::Move::Feed { .. })), "{moves:?}");
}

// ---------------------------------------------------------------------------------------
// 2. typed input as a spreadsheet reads it, with a word when it looks wrong

#[test]
fn text_that_looks_like_a_formula_a_decimal_comma_or_a_list_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let book = named_workbook(dir.path());
    let out = dir.path().join("out.xlsx");
    let run = ncsheet(&[
        "set",
        &book,
        "B10=TAN(RADIANS(alpha))",
        "B5=0,8",
        "B6=1;2;3",
        "B7=Outer chamfer",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let warnings: Vec<&str> = run.stderr.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 3, "{}", run.stderr);
    assert!(warnings[0].contains("Sheet1!B10") && warnings[0].contains("=TAN(RADIANS(alpha))"), "{warnings:?}");
    assert!(warnings[1].contains("Sheet1!B5") && warnings[1].contains("0.8"), "{warnings:?}");
    assert!(warnings[2].contains("Sheet1!B6") && warnings[2].contains(';'), "{warnings:?}");
}

#[test]
fn a_semicolon_between_arguments_gets_a_hint_and_an_unclosed_parenthesis_its_caret() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let out = dir.path().join("o.csv");
    let run = ncsheet(&["set", &book, "B1==ROUND(A1;4)", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("separated by , (not ;)"), "{}", run.stderr);
    let run = ncsheet(&["set", &book, "B1==SUM(1,2", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 1);
    // The caret under the `(` of SUM( — column 5 of =SUM(1,2.
    let lines: Vec<&str> = run.stderr.lines().collect();
    let caret = lines.iter().find(|l| l.contains('^')).unwrap();
    assert_eq!(caret.trim_start().split(' ').nth(2), Some("5:"), "{}", run.stderr);
    let formula_line = lines[lines.iter().position(|l| l.contains('^')).unwrap() - 1];
    let column = formula_line.find("=SUM(").unwrap() + 4;
    assert_eq!(caret.find('^'), Some(column), "{}", run.stderr);
    assert!(run.stderr.contains("never closed"), "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------
// 3. names everywhere a cell goes

#[test]
fn names_are_cell_arguments_for_eval_and_set() {
    let dir = tempfile::tempdir().unwrap();
    let book = named_workbook(dir.path());
    let run = ncsheet(&["eval", &book, "XA"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!((number(&run.stdout) - 42.0).abs() < 1e-9, "{}", run.stdout);
    let out = dir.path().join("out.xlsx");
    let run = ncsheet(&["set", &book, "alpha=30", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    // set says what it did, on stderr.
    assert!(run.stderr.contains("Sheet1!B1 = 30"), "{}", run.stderr);
    let run = ncsheet(&["eval", out.to_str().unwrap(), "XA", "--raw"]);
    let expected = 40.0 + 2.0 * (30.0f64).to_radians().tan();
    assert!((number(&run.stdout) - expected).abs() < 1e-12, "{}", run.stdout);
    let run = ncsheet(&["eval", &book, "nosuch"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("nosuch") && run.stderr.contains("alpha"), "{}", run.stderr);
}

#[test]
fn the_repl_reads_and_sets_names() {
    let dir = tempfile::tempdir().unwrap();
    let book = named_workbook(dir.path());
    let run = ncsheet_with(&["repl", &book], "alpha\nalpha=30\nXA\nshow XA\nquit\n");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines[0], "45");
    assert_eq!(lines[1], "30");
    let expected = 40.0 + 2.0 * (30.0f64).to_radians().tan();
    assert!((number(lines[2]) - expected).abs() < 1e-9, "{}", run.stdout);
    assert!(run.stdout.contains("=40+2*TAN(RADIANS(alpha))"), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------
// 4. seeing inside a workbook

#[test]
fn show_gives_the_formula_value_and_the_cells_read_and_reading() {
    let dir = tempfile::tempdir().unwrap();
    let book = named_workbook(dir.path());
    let run = ncsheet(&["show", &book, "XA", "B1"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = &run.stdout;
    assert!(text.contains("formula  =40+2*TAN(RADIANS(alpha))"), "{text}");
    assert!(text.contains("reads    B1 (alpha)"), "{text}");
    assert!(text.contains("read by  B2 (XA)"), "{text}");
    assert!(text.contains("value    42"), "{text}");
}

#[test]
fn eval_formulas_prints_formulas_as_typed() {
    let dir = tempfile::tempdir().unwrap();
    let book = named_workbook(dir.path());
    let run = ncsheet(&["eval", &book, "A1:B2", "--formulas"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("=40+2*TAN(RADIANS(alpha))"), "{}", run.stdout);
    assert!(run.stdout.lines().nth(1).unwrap().ends_with("45"), "{}", run.stdout);
}

#[test]
fn info_lists_sheets_names_and_macros() {
    let run = ncsheet(&["info", &repo("sheets/chamfer.xlsx")]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    for sheet in ["Summary", "Outer", "Pipe", "Blind"] {
        assert!(run.stdout.lines().any(|l| l.trim_start().starts_with(sheet)), "{}", run.stdout);
    }
    assert!(run.stdout.contains("=Outer!$B$8"), "{}", run.stdout);
    assert!(run.stdout.contains("macros: none"), "{}", run.stdout);
    assert!(run.stdout.contains("calculation:"), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------
// 5. values as the cell shows them

#[test]
fn eval_prints_with_the_cells_number_format_and_raw_in_full() {
    let book = repo("sheets/chamfer.xlsx");
    // Summary!C5 is XA of the outer chamfer (DOMAIN.md §1: 44.262742), formatted 0.000000.
    let run = ncsheet(&["eval", &book, "Summary!C5"]);
    assert_eq!(run.stdout, "44.262742\n", "{}", run.stderr);
    let run = ncsheet(&["eval", &book, "Summary!C5", "--raw"]);
    // 40 + 2·(√2·0.8 + 1.8 − 0.8) for α = 45°, r = 0.8, eA = 1: 44.2627416997969…
    let exact = 40.0 + 2.0 * (0.8 * 2f64.sqrt() + 1.8 - 0.8);
    assert!(run.stdout.trim().len() > 12, "{}", run.stdout);
    assert!((number(&run.stdout) - exact).abs() < 1e-12, "{}", run.stdout);
}

#[test]
fn a_table_fits_80_columns_when_not_a_terminal_and_width_when_given() {
    let book = repo("sheets/chamfer.xlsx");
    let run = ncsheet(&["eval", &book, "--sheet", "Outer"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.lines().all(|l| l.chars().count() <= 80), "{}", run.stdout);
    let run = ncsheet(&["eval", &book, "--sheet", "Summary", "--width", "50"]);
    assert!(run.stdout.lines().all(|l| l.chars().count() <= 50), "{}", run.stdout);
}

#[test]
fn several_cells_print_aligned() {
    let dir = tempfile::tempdir().unwrap();
    let book = named_workbook(dir.path());
    let run = ncsheet(&["eval", &book, "alpha", "B2", "Sheet1!A1"]);
    let columns: Vec<usize> = run.stdout.lines().map(|l| l.rfind("  ").unwrap()).collect();
    assert!(columns.windows(2).all(|w| w[0] == w[1]), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------
// 8. smaller things

#[test]
fn functions_takes_a_filter() {
    let run = ncsheet(&["functions", "TAN"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.lines().any(|l| l.starts_with("TAN(angle)")), "{}", run.stdout);
    assert!(run.stdout.lines().all(|l| l.split('(').next().unwrap().contains("TAN")), "{}", run.stdout);
    assert!(!run.stdout.contains("ABS("), "{}", run.stdout);
}

#[test]
fn a_semicolon_separated_csv_is_read_as_columns_with_decimal_commas() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "eu.csv", "D;40,5\nf;2\ntotal;=B1+B2*3\n");
    let run = ncsheet(&["eval", &book, "B3"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    // 40.5 + 2·3
    assert_eq!(run.stdout, "46.5\n");
    assert!(run.stderr.contains(";-separated"), "{}", run.stderr);
}

#[test]
fn a_surface_naming_cells_is_refused() {
    let run = ncsheet(&[
        "ballpath",
        "--surface",
        "x2+y2",
        "--radius",
        "1",
        "--x=0:1",
        "--y=0:1",
        "--stepover",
        "0.5",
        "--step",
        "0.5",
    ]);
    assert_eq!(run.code, 1, "{}", run.stdout);
    assert_eq!(run.stdout, "");
    assert!(run.stderr.contains("x2 is a cell reference"), "{}", run.stderr);
}

#[test]
fn other_spreadsheet_files_get_advice_and_a_missing_folder_is_named() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["old.xls", "calc.ods"] {
        let book = write(dir.path(), name, "");
        let run = ncsheet(&["eval", &book]);
        assert_eq!(run.code, 1);
        assert!(run.stderr.contains("save it as .xlsx"), "{}", run.stderr);
    }
    let book = write(dir.path(), "a.csv", "1\n");
    let out = dir.path().join("missing").join("out.csv");
    let run = ncsheet(&["set", &book, "A1=2", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("the folder") && run.stderr.contains("missing does not exist"), "{}", run.stderr);
    assert!(!run.stderr.contains(".ncsheet-"), "{}", run.stderr);
}

#[test]
fn nc_feed_as_a_statement_sets_the_feed() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let bas = write(dir.path(), "m.bas", "Sub Main()\n  Nc.Feed 0.2\n  Nc.Line 10, 0\nEnd Sub\n");
    // A mill (a lathe program is refused without a feed mode, issue 13).
    let run = ncsheet(&["run", &book, &bas, "--dialect", "linuxcnc", "--machine", "mill"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.lines().any(|l| l.contains("G1") && l.contains("F0.2")), "{}", run.stdout);
}

#[test]
fn saving_a_macro_run_says_which_formulas_became_constants() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1,=A1*2\n");
    let bas = write(dir.path(), "m.bas", "Sub Main()\n  Range(\"B1\").Value = 5\nEnd Sub\n");
    let out = dir.path().join("out.csv");
    let run = ncsheet(&["run", &book, &bas, "--save", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("Sheet1!B1") && run.stderr.contains("constants"), "{}", run.stderr);
}

#[test]
fn a_let_bound_lambda_is_called_by_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "x\n");
    let out = dir.path().join("out.csv");
    // Excel: LET(f, LAMBDA(n, n), f(1)) is 1; LAMBDA(n, n*2) applied to 3 is 6.
    let run = ncsheet(&[
        "set",
        &book,
        "B1==LET(f,LAMBDA(n,n),f(1))",
        "B2==LET(g,LAMBDA(n,n*2),g(3))",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("unknown"), "{}", run.stderr);
    let run = ncsheet(&["eval", out.to_str().unwrap(), "B1", "B2"]);
    assert_eq!(run.stdout, "B1  1\nB2  6\n");
    // An unknown function is echoed as typed, not in upper case.
    let run = ncsheet(&["set", &book, "B1==foo(1)", "-o", out.to_str().unwrap()]);
    assert!(run.stderr.contains("=foo(1)") && run.stderr.contains("unknown function foo"), "{}", run.stderr);
}

#[test]
fn check_on_a_file_ncsheet_wrote_does_not_claim_agreement_with_excel() {
    let dir = tempfile::tempdir().unwrap();
    let ours = named_workbook(dir.path());
    let run = ncsheet(&["eval", &ours, "--check"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("Excel,") && !run.stderr.contains("agree with Excel"), "{}", run.stderr);
    assert!(run.stderr.contains("agree with the values ncsheet stored in it"), "{}", run.stderr);
    assert!(run.stderr.contains("its stored values are not Excel's"), "{}", run.stderr);
    // A file Excel saved (its docProps/app.xml names Excel) is still compared with Excel.
    let Some(corpus) = common::corpus::root() else { return };
    let excel = corpus.join("DynamicArrays.xlsx");
    let run = ncsheet(&["eval", excel.to_str().unwrap(), "--check"]);
    assert!(run.stderr.contains("stored values agree with Excel"), "{}", run.stderr);
}
