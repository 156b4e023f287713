//! Hostile input (issue 30), an eighth round of variants (session 22): each test is a class
//! the round reached that the earlier fixes did not cover. Values come from outside our code:
//! arithmetic worked by hand, the options each command's `--help` lists.

mod common;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::RunOptions;
use ncsheet::workbook::Workbook;

/// A workbook whose A1 calls `call`, a Function of Module1 holding `source`, each call held
/// to `statements`; the notes of A1.
fn cell_function_notes(source: &str, call: &str, statements: u64) -> Vec<String> {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().functions.statements_per_call = statements;
    wb.set_input(0, parse_cell("A1").unwrap(), call).unwrap();
    let project = common::vba::module1(source);
    assert!(ncsheet::vba::install_functions(&mut wb, &project, RunOptions::default()).is_empty());
    assert_eq!(wb.value(0, parse_cell("A1").unwrap()), Value::Error(ncsheet::eval::XlError::Value));
    wb.notes(0, parse_cell("A1").unwrap())
}

/// A cell's VBA Function that reaches a macro limit is `#VALUE!` with a note; the note told
/// the user to "raise the limit with --max-statements" (or --max-depth, --max-string,
/// --max-array-items), options only `run` has: `eval`, `set`, `export`, `show` and the
/// workbench have none of them (their `--help`), and `run`'s do not reach a cell's calls
/// either. The note now names the limit as fixed there, pointing to docs/limits.md.
#[test]
fn a_cell_functions_limit_notes_name_no_option_the_command_lacks() {
    let cases = [
        ("Function F()\r\n    Do\r\n    Loop\r\nEnd Function\r\n", "the statement limit (1000)"),
        ("Function F()\r\n    F = F()\r\nEnd Function\r\n", "calls nest deeper"),
        ("Function F()\r\n    F = Space(100000000)\r\nEnd Function\r\n", "a string longer than"),
        (
            "Function F()\r\n    Dim a() As Byte\r\n    ReDim a(20000000)\r\nEnd Function\r\n",
            "an array of 20000001 items",
        ),
    ];
    for (source, limit) in cases {
        let notes = cell_function_notes(source, "=F()", 1000);
        let note = notes.iter().find(|n| n.contains(limit)).unwrap_or_else(|| panic!("{limit}: {notes:?}"));
        assert!(!note.contains("--max-"), "{note}");
        assert!(note.contains("a VBA function a cell calls, docs/limits.md"), "{note}");
    }
}

/// `Application.Evaluate("Twice(2)")` of a public Function of the macro's project was Error
/// 2029 (`#NAME?`) with no word why; Excel's Evaluate calls the project's Functions as a
/// cell does. Twice(2) = 4 and Twice(2)+1 = 5, by hand; a call with too many arguments is
/// `#VALUE!` (Error 2015) with the reason in the run, as a cell's would be.
#[test]
fn evaluate_calls_the_macros_own_functions() {
    let module = "Function Twice(x)\n    Twice = x * 2\nEnd Function";
    let body = "Debug.Print Application.Evaluate(\"Twice(2)\")\nDebug.Print Evaluate(\"Twice(2)+1\")\n\
                Debug.Print [Twice(5)]\nDebug.Print IsError(Evaluate(\"Twice(1,2)\"))";
    assert_eq!(common::vba::printed_after(module, body), vec![" 4 ", " 5 ", " 10 ", "True"]);
}

/// A CL record whose block the dialect cannot write (a coordinate past the control's digits,
/// a spindle speed or tool number past its range) was reported as "block 10" of a program
/// that was never written; the error now names the CL file's line and record.
#[test]
fn post_names_the_cl_line_of_a_block_the_dialect_cannot_write() {
    let dir = tempfile::tempdir().unwrap();
    let base = "PARTNO/1\nUNIT/MM\nCUTTER/6.,0,3.,0,0,0,51.\nLOAD/TOOL,1\nSPINDL/12000,RPM,CLW\n\
                FEDRAT/411.48,MMPM\nGOTO/96.4375,-1.4375,2.5\nGOTO/96.4375,-1.4375,-3.\nFINI\n";
    let cases = [
        ("GOTO/96.4375,-1.4375,-3.", "GOTO/1E12,-1.4375,-3.", "line 8 (GOTO)"),
        ("SPINDL/12000", "SPINDL/1200000", "line 5 (SPINDL)"),
        ("LOAD/TOOL,1", "LOAD/TOOL,1000", "line 4 (LOADTL)"),
    ];
    for (from, to, place) in cases {
        let file = dir.path().join("p.cl");
        std::fs::write(&file, base.replace(from, to)).unwrap();
        let args = ["post", file.to_str().unwrap(), "--machine", "ab-head", "--pivot", "0", "--dialect", "iso"];
        let run = common::cli::ncsheet(&args);
        assert_eq!(run.code, 1, "{to}: {}", run.stdout);
        assert!(run.stderr.contains(place) && !run.stderr.contains("block"), "{to}: {}", run.stderr);
    }
}

/// TEXTJOIN of a 4096 × 4096 array converted every item to text before joining them, and
/// only then refused the result past Excel's 32,767 characters: 20 s in a release build,
/// minutes in a debug one. It stops as it passes the limit, as CONCAT does.
#[test]
fn textjoin_stops_at_the_text_limit_not_after_every_item() {
    let (value, notes, _) = common::sheet::eval_a1("=TEXTJOIN(\",\",TRUE,SEQUENCE(4096,4096))");
    assert_eq!(value, Value::Error(ncsheet::eval::XlError::Value));
    assert!(notes.iter().any(|n| n.contains("32767")), "{notes:?}");
    // Below the limit it joins as before: 1 to 5 with "-" (by hand).
    assert_eq!(common::sheet::eval_a1("=TEXTJOIN(\"-\",TRUE,SEQUENCE(5))").0, Value::Text("1-2-3-4-5".into()));
}
