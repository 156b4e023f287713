//! Hostile input (issue 19): text built to crash, exhaust or mislead the engine gives a clear
//! error in its place, never a stack overflow, a panic or a silently wrong value. The
//! tests run on the harness's 2 MiB threads, the smallest stack the engine runs on.

mod common;

use std::io::{Cursor, Write};
use std::path::Path;

use common::cli::Invocation;
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::formula::limits::{MAX_NESTING, MAX_TREE_DEPTH};
use ncsheet::io::xlsx;
use ncsheet::vba::{self, ErrorKind, RunOptions};
use ncsheet::workbook::Workbook;

/// The value of `formula` stored in A1 of an empty sheet (as a file loads it: a formula that
/// does not parse holds `#NAME?`), and the problems listed for it.
fn eval_a1(formula: &str) -> (Value, Vec<String>) {
    let mut wb = Workbook::with_sheet();
    let _ = wb.set_input_deferred(0, parse_cell("A1").unwrap(), formula);
    wb.recalculate();
    let problems = wb.problems().into_iter().map(|p| p.render()).collect();
    (wb.value(0, parse_cell("A1").unwrap()), problems)
}

fn nested(open: &str, inner: &str, close: &str, n: usize) -> String {
    format!("={}{inner}{}", open.repeat(n), close.repeat(n))
}

/// Runs the ncsheet binary in `dir` with `stdin`, under a 2 GiB address-space cap.
fn ncsheet(dir: &Path, args: &[&str], stdin: &str) -> (i32, String, String) {
    let run = Invocation { dir: Some(dir), stdin, memory_kib: Some(2_097_152) }.run(args);
    (run.code, run.stdout, run.stderr)
}

// ---------------------------------------------------------------------------------------
// Depth

#[test]
fn formulas_nested_past_the_limit_are_refused_in_their_cell_with_a_caret() {
    // The caret is under the bracket or sign that opens level 256, or under the `+` that
    // joins the 1,501st term.
    let nth = |text: &str, c: char, n: usize| text.match_indices(c).nth(n - 1).unwrap().0 + 1;
    let cases = [
        (nested("(", "1", ")", 5000), "nested more than 255 levels", '(', MAX_NESTING + 1),
        (nested("ABS(", "1", ")", 5000), "nested more than 255 levels", '(', MAX_NESTING + 1),
        (nested("IF(TRUE,", "1", ")", 5000), "nested more than 255 levels", '(', MAX_NESTING + 1),
        (nested("LET(x,1,", "x", ")", 5000), "nested more than 255 levels", '(', MAX_NESTING + 1),
        (format!("={}1", "-".repeat(20_000)), "nested more than 255 levels", '-', MAX_NESTING + 1),
        (format!("=1{}", "+1".repeat(50_000)), "more than 1500 operators", '+', MAX_TREE_DEPTH as usize),
    ];
    for (formula, message, c, n) in cases {
        let column = nth(&formula, c, n);
        let (value, problems) = eval_a1(&formula);
        assert_eq!(value, Value::Error(XlError::Name), "{message}");
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].contains(message), "{}", problems[0]);
        assert!(problems[0].contains(&format!("^ column {column}:")), "{}", problems[0]);
        assert!(problems[0].lines().next().unwrap().chars().count() < 130, "the caret line is clipped");
    }
}

#[test]
fn formulas_at_the_limits_still_evaluate() {
    // 255 brackets; 254 minus signs (an even count: 1); a chain of 1,500 terms; and both
    // kinds of depth in one formula, the calls counting in the tree's depth.
    assert_eq!(eval_a1(&nested("(", "1", ")", MAX_NESTING)).0, Value::Number(1.0));
    assert_eq!(eval_a1(&format!("={}1", "-".repeat(MAX_NESTING - 1))).0, Value::Number(1.0));
    let chain = format!("=1{}", "+1".repeat(MAX_TREE_DEPTH as usize - 1));
    assert_eq!(eval_a1(&chain).0, Value::Number(1500.0));
    let calls = 200;
    let inner = format!("1{}", "+1".repeat(MAX_TREE_DEPTH as usize - calls - 1));
    let mixed = format!("={}{inner}{}", "ABS(".repeat(calls), ")".repeat(calls));
    assert_eq!(eval_a1(&mixed).0, Value::Number((MAX_TREE_DEPTH as usize - calls) as f64));
    let ifs = nested("IF(TRUE,", "7", ")", 127);
    assert_eq!(eval_a1(&ifs).0, Value::Number(7.0));
}

/// A one-sheet xlsx package whose `<sheetData>` is `data`.
fn package(data: &str) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    let mut put = |name: &str, text: &str| {
        zip.start_file(name, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    };
    put(
        "_rels/.rels",
        r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/></Relationships>"#,
    );
    put(
        "xl/workbook.xml",
        r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" xmlns:r="http://schemas.openxmlformats.org/officeDocument/2006/relationships"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#,
    );
    put(
        "xl/_rels/workbook.xml.rels",
        r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet1.xml"/></Relationships>"#,
    );
    put(
        "xl/worksheets/sheet1.xml",
        &format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>{data}</sheetData></worksheet>"#
        ),
    );
    zip.finish().unwrap().into_inner()
}

#[test]
fn a_deep_xlsx_formula_is_refused_in_its_cell_and_the_rest_loads() {
    let deep = format!("1{}", "+1".repeat(50_000));
    let parens = format!("{}1{}", "(".repeat(5000), ")".repeat(5000));
    let data = format!(
        r#"<row r="1"><c r="A1"><f>{deep}</f><v>50001</v></c><c r="B1"><f>{parens}</f><v>1</v></c><c r="C1"><f>2*3</f><v>6</v></c></row>"#
    );
    let imported = xlsx::load_bytes(&package(&data), Path::new("deep.xlsx")).unwrap_or_else(|e| panic!("{e}"));
    let wb = &imported.workbook;
    // A formula ncsheet does not read keeps the value the file cached, as Excel keeps a cell's
    // value when it repairs a formula it cannot read (issue 29); the problem names the limit.
    assert_eq!(wb.value(0, parse_cell("A1").unwrap()), Value::Number(50001.0));
    assert_eq!(wb.value(0, parse_cell("B1").unwrap()), Value::Number(1.0));
    assert_eq!(wb.value(0, parse_cell("C1").unwrap()), Value::Number(6.0));
    let problems: Vec<String> = wb.problems().into_iter().map(|p| p.render()).collect();
    assert!(problems[0].contains("more than 1500 operators"), "{problems:?}");
    assert!(problems[1].contains("nested more than 255 levels"), "{problems:?}");
    assert!(problems.iter().all(|p| p.contains("keeps the value the file cached")), "{problems:?}");
}

fn run_macro(src: &str) -> Result<Vec<String>, vba::MacroError> {
    let mut wb = Workbook::with_sheet();
    let out = vba::run(&mut wb, src, "deep.bas", &RunOptions::default())?;
    Ok(out.printed)
}

#[test]
fn macros_nested_past_the_limit_are_syntax_errors_at_their_line() {
    let ifs = format!("Sub Main()\n{}{}End Sub\n", "If 1 > 0 Then\n".repeat(5000), "End If\n".repeat(5000));
    let continued = format!("Sub Main()\nx = 1{}\nEnd Sub\n", " + _\n1".repeat(50_000));
    let minus = format!("Sub Main()\nx = {}1\nEnd Sub\n", "-".repeat(20_000));
    let nots = format!("Sub Main()\nx = {}True\nEnd Sub\n", "Not ".repeat(5000));
    let parens = format!("Sub Main()\nx = {}1{}\nEnd Sub\n", "(".repeat(5000), ")".repeat(5000));
    let cases = [
        (ifs, 2 + MAX_NESTING, "blocks nested more than 255 levels"),
        (continued, 1 + MAX_TREE_DEPTH as usize, "more than 1500 operators"),
        (minus, 2, "nested more than 255 levels"),
        (nots, 2, "nested more than 255 levels"),
        (parens, 2, "nested more than 255 levels"),
    ];
    for (src, line, message) in cases {
        let e = run_macro(&src).expect_err("refused");
        assert_eq!(e.kind, ErrorKind::Syntax, "{e}");
        assert!(e.to_string().starts_with(&format!("deep.bas:{line}:")), "{e}");
        assert!(e.message.contains(message), "{e}");
    }
}

#[test]
fn a_macro_at_the_block_limit_runs() {
    let n = MAX_NESTING;
    let src =
        format!("Sub Main()\n{}Debug.Print \"deep\"\n{}End Sub\n", "If 1 > 0 Then\n".repeat(n), "End If\n".repeat(n));
    assert_eq!(run_macro(&src).unwrap(), vec!["deep"]);
    let fors =
        format!("Sub Main()\n{}Debug.Print \"loops\"\n{}End Sub\n", "For i = 1 To 1\n".repeat(n), "Next\n".repeat(n));
    assert_eq!(run_macro(&fors).unwrap(), vec!["loops"]);
}

#[test]
fn a_deep_surface_is_refused_with_a_caret() {
    let dir = tempfile::tempdir().unwrap();
    let surface = format!("{}x{}", "(".repeat(5000), ")".repeat(5000));
    let args = [
        "ballpath",
        "--surface",
        &surface,
        "--radius",
        "3",
        "--x",
        "0:10",
        "--y",
        "0:10",
        "--stepover",
        "2",
        "--step",
        "2",
    ];
    let (code, _, stderr) = ncsheet(dir.path(), &args, "");
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("^ column 256: nested more than 255 levels"), "{stderr}");
}

/// Extents near f64::MAX overflowed the curvature map's cell count (a panic in debug builds)
/// and the gouge search never ended: lengths past a kilometre are refused, by name.
#[test]
fn a_ball_path_over_a_range_near_the_largest_number_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "ballpath",
        "--surface",
        "0",
        "--radius",
        "3",
        "--x",
        "0:1E308",
        "--y",
        "0:10",
        "--stepover",
        "1E307",
        "--step",
        "1E307",
    ];
    let (code, _, stderr) = ncsheet(dir.path(), &args, "");
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("within ±1000000"), "{stderr}");
}

#[test]
fn the_repl_keeps_its_session_after_a_deep_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("w.csv"), "1\n").unwrap();
    let deep = nested("(", "1", ")", 5000);
    let input = format!("A2=2\nA1={deep}\nA3==A1+A2\nA3\nquit\n");
    let (code, stdout, stderr) = ncsheet(dir.path(), &["repl", "w.csv"], &input);
    assert_eq!(code, 1, "one command failed: {stderr}");
    assert!(stderr.contains("nested more than 255 levels"), "{stderr}");
    // The refused line left A1 as it was (1); the session went on: A3 = 1 + 2.
    assert_eq!(stdout.lines().last(), Some("3"), "{stdout}");
}

// ---------------------------------------------------------------------------------------
// Panics in number formats

#[test]
fn number_formats_past_the_largest_double_give_an_error_not_a_panic() {
    // FIXED rounding to 10^309 or more leaves 0, as Excel shows it.
    assert_eq!(eval_a1("=FIXED(1234.5,-309)").0, Value::Text("0".into()));
    assert_eq!(eval_a1("=FIXED(-1234.5,-400)").0, Value::Text("0".into()));
    for formula in [
        "=TEXT(1E+308,\"0%\")",
        "=TEXT(-1E+308,\"#%\")",
        "=TEXT(1E+308,\"0.0E+0%\")",
        "=TEXT(-1E+308,\"0.0E+0%\")",
        &format!("=TEXT(5,\"0{}\")", "%".repeat(400)),
    ] {
        assert_eq!(eval_a1(formula).0, Value::Error(XlError::Num), "{formula}");
    }
    // Zero stays zero under any number of percent signs.
    assert_eq!(
        eval_a1(&format!("=TEXT(0,\"0{}\")", "%".repeat(400))).0,
        Value::Text(format!("0{}", "%".repeat(400)).into())
    );
}

// ---------------------------------------------------------------------------------------
// Silently wrong

#[test]
fn mod_of_large_numbers_is_the_exact_remainder() {
    // 10^20 = 7 · 14285714285714285714 + 2; 2^53 + 2 = 9007199254740994 = 3 · 3002399751580331 + 1
    // (both are exact doubles, so the exact remainder is the answer).
    assert_eq!(eval_a1("=MOD(1E+20,7)").0, Value::Number(2.0));
    assert_eq!(eval_a1("=MOD(2^53+2,3)").0, Value::Number(1.0));
    assert_eq!(eval_a1("=MOD(-1E+20,7)").0, Value::Number(5.0));
    assert_eq!(eval_a1("=MOD(1E+20,-7)").0, Value::Number(-5.0));
    assert_eq!(eval_a1("=MOD(-3,2)").0, Value::Number(1.0));
}

#[test]
fn every_text_result_past_32767_characters_is_value_error() {
    let over = [
        "=REPT(\"x\",30000)&REPT(\"y\",3000)",
        "=CONCAT(REPT(\"x\",20000),REPT(\"x\",20000))",
        "=SUBSTITUTE(REPT(\"x\",30000),\"x\",REPT(\"y\",30000))",
        // German ß is SS in capitals: UPPER doubles the length.
        "=UPPER(REPT(\"ß\",20000))",
        "=TEXTJOIN(\",\",TRUE,REPT(\"x\",20000),REPT(\"x\",20000))",
        "=LET(a,REPT(\"x\",20000),LOWER(a&a))",
    ];
    for formula in over {
        assert_eq!(eval_a1(formula).0, Value::Error(XlError::Value), "{formula}");
    }
    let (_, problems) = eval_a1(over[0]);
    assert_eq!(problems, vec!["#VALUE!: longer than the 32767 characters of a text (Excel's limit)"]);
    // Exactly 32,767 characters is a text.
    assert_eq!(eval_a1("=LEN(REPT(\"x\",32766)&\"y\")").0, Value::Number(32767.0));
}

fn macro_fault(src: &str) -> String {
    run_macro(src).expect_err("the macro stops").to_string()
}

#[test]
fn macro_sizes_past_their_limits_are_errors_not_silent_cuts() {
    // Space(1e9) is not cut to 32,767 spaces: the macro stops there (ncsheet's macro string
    // limit, as VBA's "Out of string space"), naming the limit and the option.
    let e = macro_fault("Sub Main()\nx = Space(1E+9)\nDebug.Print IsError(x)\nEnd Sub\n");
    assert!(e.contains("deep.bas:2:") && e.contains("16777216 characters") && e.contains("--max-string"), "{e}");
    // Doubling a string 40 times stops at the macro string limit, in bounded memory.
    let e = macro_fault("Sub Main()\ns = \"ab\"\nFor i = 1 To 40\ns = s & s\nNext\nDebug.Print IsError(s)\nEnd Sub\n");
    assert!(e.contains("deep.bas:4:") && e.contains("--max-string"), "{e}");
    // VBA's bounds are Longs: 1E+300 overflows.
    let e = macro_fault("Sub Main()\nReDim a(1E+300 To 1E+300)\nEnd Sub\n");
    assert!(e.contains("deep.bas:2:9:") && e.contains("1E+300 is outside a Long"), "{e}");
}

#[test]
fn now_without_parentheses_is_the_call_as_in_vba() {
    let out = run_macro("Sub Main()\nDebug.Print Now > 45000\nDebug.Print Now() - Now < 1\nEnd Sub\n").unwrap();
    assert_eq!(out, vec!["True", "True"]);
}

#[test]
fn text_positions_count_utf16_units_as_excel() {
    // Excel counts in UTF-16 units: U+1F44D (thumbs up) is a surrogate pair, two units.
    let text = |f: &str| eval_a1(f).0;
    assert_eq!(text("=LEN(\"👍\")"), Value::Number(2.0));
    assert_eq!(text("=LEN(\"a👍b\")"), Value::Number(4.0));
    assert_eq!(text("=LEFT(\"👍a\",2)"), Value::Text("👍".into()));
    assert_eq!(text("=RIGHT(\"a👍\",2)"), Value::Text("👍".into()));
    assert_eq!(text("=MID(\"a👍b\",2,2)"), Value::Text("👍".into()));
    assert_eq!(text("=MID(\"a👍b\",4,1)"), Value::Text("b".into()));
    assert_eq!(text("=FIND(\"b\",\"👍b\")"), Value::Number(3.0));
    assert_eq!(text("=SEARCH(\"B\",\"👍b👍b\",4)"), Value::Number(6.0));
    assert_eq!(text("=LEN(REPT(\"é\",3))"), Value::Number(3.0));
    // Every piece MID cuts, against the standard library's reading of those UTF-16 units
    // (a half of a surrogate pair is U+FFFD, as `String::from_utf16_lossy` reads it).
    let sample = "a👍é👍bc";
    let units: Vec<u16> = sample.encode_utf16().collect();
    for start in 1..=units.len() + 1 {
        for count in 0..=units.len() + 1 - start {
            let from = start - 1;
            let want = String::from_utf16_lossy(&units[from..(from + count).min(units.len())]);
            let got = text(&format!("=MID(\"{sample}\",{start},{count})"));
            assert_eq!(got, Value::Text(want.into()), "MID({start},{count})");
        }
    }
}

#[test]
fn the_repl_reads_cr_only_line_endings_as_lines() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("w.csv"), "1\n").unwrap();
    let (code, stdout, stderr) = ncsheet(dir.path(), &["repl", "w.csv"], "A2=5\rA3==A2*2\r\nA3\rquit\r");
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(stdout.lines().collect::<Vec<_>>(), vec!["5", "10", "10"]);
}

#[test]
fn an_unsavable_sheet_name_is_named_briefly() {
    let mut wb = Workbook::with_sheet();
    if wb.add_sheet(&"x".repeat(5000)).is_err() {
        return; // refused on the way in: nothing can reach the writer
    }
    let e = xlsx::to_bytes(&wb, &xlsx::Layout::default()).expect_err("Excel allows 31 characters").to_string();
    assert!(e.contains("1 to 31 characters") && e.contains("this one 5000"), "{e}");
    assert!(e.len() < 200, "{e}");
}
