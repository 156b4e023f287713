//! Hostile input (issue 30), a fifth round of variants (session 18): each test is a class the
//! round reached that the earlier fixes did not cover. Values come from outside our code:
//! arithmetic worked by hand in the comments, and LibreOffice 7's results where said.

mod common;

use common::sheet::eval_a1;
use ncsheet::eval::{Value, XlError};
use ncsheet::vba::{ErrorKind, RunOptions};
use ncsheet::workbook::Workbook;

fn number(formula: &str) -> f64 {
    match eval_a1(&format!("={formula}")).0 {
        Value::Number(n) => n,
        other => panic!("{formula}: {other:?}"),
    }
}

fn error(formula: &str) -> XlError {
    match eval_a1(&format!("={formula}")).0 {
        Value::Error(e) => e,
        other => panic!("{formula}: {other:?}, not an error"),
    }
}

/// The doubles above 1.797693134862315E+308 round to 15 digits past the largest double; that
/// infinity made ROUNDDOWN and TRUNC return them unrounded. By hand: 1.7976931348623157E+308
/// is 179769313.48623157 × 10^300, so cut to 10^300 it is 179769313 × 10^300, to 10^307 it is
/// 17 × 10^307, to 10^308 it is 1 × 10^308, and to 10^400 nothing is left (LibreOffice 7
/// gives the same four). Rounded up to 10^300 it is 179769314 × 10^300, past the largest
/// double: #NUM!, not the number unrounded.
#[test]
fn the_largest_doubles_are_rounded_to_their_digits() {
    let max = "1.7976931348623157E+308";
    assert_eq!(number(&format!("TRUNC({max},-300)")), 179769313e300);
    assert_eq!(number(&format!("ROUNDDOWN({max},-300)")), 179769313e300);
    assert_eq!(number(&format!("ROUNDDOWN({max},-307)")), 17e307);
    assert_eq!(number(&format!("TRUNC({max},-308)")), 1e308);
    assert_eq!(number(&format!("TRUNC({max},-400)")), 0.0);
    assert_eq!(error(&format!("ROUNDUP({max},-300)")), XlError::Num);
    // Whole numbers stay as they are, shown on their 15 digits.
    assert_eq!(number(&format!("ROUNDDOWN({max},0)")), f64::MAX);
}

/// Sums of squares past the largest double are #NUM! (LibreOffice 7: #NUM! for each of these),
/// where STEYX's residual, NaN, was clamped to 0 by `max` (STEYX gave 0) and an overflowed
/// denominator was taken for a zero one (#DIV/0!, which says the data do not vary).
#[test]
fn sums_of_squares_past_the_largest_double_are_num() {
    for f in [
        "STEYX({1E+308,1,2},{1,2,3})",
        "STEYX({1E+160,1,2},{1,2,3})",
        "STEYX({1,2,3},{1E+200,1,2})",
        "CORREL({1E+308,1},{1,1E+308})",
        "PEARSON({1E+308,1,2},{1,2,1E+308})",
        "RSQ({1E+308,1,2},{1,2,3})",
    ] {
        assert_eq!(error(f), XlError::Num, "{f}");
    }
    // KURT and SKEW work at their data's scale (session 28, tests/hostile3.rs), so one value
    // near the largest double among small ones has the exact answer of an outlier a among
    // values negligible beside it: by hand, KURT's z are 3/2 and three −1/2, 20/6 · 84/16 −
    // 27/2 = 4; SKEW's are 2/√3 and two −1/√3, 3/2 · (6/(3√3)) = √3.
    assert!((number("KURT(1E+308,1,2,3)") - 4.0).abs() < 1e-12);
    assert!((number("SKEW(1E+308,1,2)") - 3f64.sqrt()).abs() < 1e-12);
    // By hand, ys {1,2,4} over xs {1,2,3}: Sxx = 2, Syy = 42/9, Sxy = 3, so STEYX is
    // √((42/9 − 9/2) / 1) = √(1/6), CORREL 3 / √(2 · 42/9) = 3 / √(28/3).
    assert!((number("STEYX({1,2,4},{1,2,3})") - (1.0f64 / 6.0).sqrt()).abs() < 1e-15);
    assert!((number("CORREL({1,2,3},{1,2,4})") - 3.0 / (28.0f64 / 3.0).sqrt()).abs() < 1e-15);
    // Data that do not vary are still #DIV/0!.
    assert_eq!(error("STEYX({1,2,3},{5,5,5})"), XlError::Div0);
}

/// Runs `src` on a fresh sheet with a memory budget of `max_memory` bytes: what it printed, or
/// its error's kind and message. It is not timed: a run that does not end is a hang the test
/// run's own limit ends.
fn run_with_memory(src: &str, max_memory: u64) -> Result<Vec<String>, (ErrorKind, String)> {
    let mut wb = Workbook::with_sheet();
    let options = RunOptions { max_memory, ..RunOptions::default() };
    let run = ncsheet::vba::run(&mut wb, src, "main.bas", &options);
    run.map(|o| o.printed).map_err(|e| (e.kind, e.to_string()))
}

/// `Dim t(1 To 100000) As T` where T holds an array of 100,000 items: the records share one
/// default array, and charging the Dim measured it once per record, 10^10 items looked at
/// (minutes; it ended past any test's patience). Measured once, it is immediate.
#[test]
fn an_array_of_records_sharing_a_field_array_is_measured_once() {
    const SRC: &str = "Type T\n    x(1 To 100000) As Double\nEnd Type\n\
                       Sub Main()\n    Dim t(1 To 100000) As T\n    Debug.Print UBound(t(100000).x)\nEnd Sub\n";
    let run = run_with_memory(SRC, RunOptions::default().max_memory);
    assert_eq!(run.map_err(|e| e.1).unwrap().concat().trim(), "100000");
}

/// Writing into each record's array copies the array the records shared: 100 records × 100,000
/// items are 10^7 items (at least 80 MB), past a 16 MiB budget, and the run stops with the
/// limit's message. The copies were charged nowhere: with a million-record Dim the process
/// grew until it aborted at its memory cap.
#[test]
fn writing_into_each_records_array_is_charged_to_the_memory_budget() {
    const SRC: &str = "Type T\n    x(1 To 100000) As Double\nEnd Type\n\
                       Sub Main()\n    Dim t(1 To 100) As T, i\n    For i = 1 To 100\n        t(i).x(1) = i\n    Next\nEnd Sub\n";
    let run = run_with_memory(SRC, 16 << 20);
    let (kind, message) = run.expect_err("the copies pass the budget");
    assert_eq!(kind, ErrorKind::Limit, "{message}");
    assert!(message.contains("--max-memory"), "{message}");
}

/// A workbook saved by ncsheet whose `<calcPr>` is replaced by `calc`, in a temporary folder.
fn with_calc(dir: &std::path::Path, calc: &str) -> std::path::PathBuf {
    let file = dir.join("cycle.xlsx");
    let mut wb = Workbook::with_sheet();
    wb.set_input(0, ncsheet::formula::address::parse_cell("A1").unwrap(), "=B1/2+1").unwrap();
    wb.set_input(0, ncsheet::formula::address::parse_cell("B1").unwrap(), "=A1/2").unwrap();
    ncsheet::io::save(&wb, &file).unwrap();
    let package = std::fs::read(&file).unwrap();
    let mut change = |part: &str, bytes: Vec<u8>| {
        if part != "xl/workbook.xml" {
            return bytes;
        }
        let text = String::from_utf8(bytes).unwrap();
        let text = match text.find("<calcPr") {
            Some(at) => {
                let end = at + text[at..].find("/>").unwrap() + 2;
                format!("{}{calc}{}", &text[..at], &text[end..])
            }
            None => text.replace("</workbook>", &format!("{calc}</workbook>")),
        };
        text.into_bytes()
    };
    let options = zip::write::SimpleFileOptions::default();
    let rewritten = common::rewrite_package(&package, options, &mut change).finish().unwrap().into_inner();
    std::fs::write(&file, rewritten).unwrap();
    file
}

/// A maximum change that is not a finite number ≥ 0 (NaN, INF, -1, 1E+400) is Excel's default
/// 0.001 for `eval`; `info` showed the file's text (`until no change exceeds NaN`), a change
/// no iteration uses (Excel's Maximum Change is a number from 0 up).
#[test]
fn info_shows_the_maximum_change_eval_iterates_to() {
    let dir = tempfile::tempdir().unwrap();
    for delta in ["NaN", "INF", "-1", "1E+400"] {
        let calc = format!(r#"<calcPr iterate="1" iterateCount="100" iterateDelta="{delta}"/>"#);
        let file = with_calc(dir.path(), &calc);
        let info = common::cli::ncsheet(&["info", file.to_str().unwrap()]);
        assert!(info.stdout.contains("at most 100, until no change exceeds 0.001"), "{delta}: {}", info.stdout);
    }
}
