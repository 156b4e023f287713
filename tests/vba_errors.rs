//! What a macro says when it cannot run: syntax errors and runtime errors with the line, a
//! caret and the procedures that were running; the statement and recursion limits; and the
//! refusal of everything that would reach files or programs.

use ncsheet::vba::{self, ErrorKind, MacroError, RunOptions};
use ncsheet::workbook::Workbook;

fn fail_with(src: &str, options: &RunOptions) -> MacroError {
    let mut wb = Workbook::with_sheet();
    match vba::run(&mut wb, src, "bad.bas", options) {
        Ok(out) => panic!("expected an error, the macro ran and printed {:?}", out.printed),
        Err(e) => e,
    }
}

fn fail(src: &str) -> MacroError {
    fail_with(src, &RunOptions::default())
}

fn main_body(body: &str) -> String {
    format!("Sub Main()\n{body}\nEnd Sub\n")
}

#[test]
fn a_syntax_error_shows_the_line_and_a_caret() {
    let e = fail("Sub Main()\n    Dim x\n    x = 1 +* 2\nEnd Sub\n");
    assert_eq!(e.kind, ErrorKind::Syntax);
    assert_eq!(e.to_string(), "bad.bas:3:12: syntax error: expected a value\n 3 |     x = 1 +* 2\n   |            ^");
}

#[test]
fn a_missing_end_if_is_named() {
    let e = fail("Sub Main()\n    If 1 > 0 Then\n        Debug.Print 1\nEnd Sub\n");
    assert_eq!(e.kind, ErrorKind::Syntax);
    assert!(e.message.contains("End If"), "{e}");
}

#[test]
fn names_are_checked_before_the_macro_runs() {
    let cases = [
        ("    x = Foo(1)", "no Function, Sub or sheet function named Foo"),
        ("    x = Sqr(1, 2)", "Sqr takes 1 argument, not 2"),
        ("    Dim x\n    For x = 1 To 2\n    Next y", "Next y closes the For loop over x"),
        // A GoTo may name any label of the procedure, one inside an If or a loop too ("GoTo
        // statement"; tests/vba_trappable_errors.rs), but one the procedure has.
        ("    GoTo Nowhere", "GoTo Nowhere: no label Nowhere in the procedure"),
        ("    Exit Function", "Exit function outside a function"),
        ("    On Error GoTo Nowhere", "no label Nowhere in the procedure"),
        ("    If 1 Then\nInside:\n    End If\n    GoSub Inside", "no label Inside in the procedure's body"),
        ("    x = #13/45/2026#", "#13/45/2026# is not a date"),
    ];
    for (body, message) in cases {
        let e = fail(&main_body(body));
        assert_eq!(e.kind, ErrorKind::Syntax, "{body}");
        assert!(e.message.contains(message), "{body}: {e}");
    }
    let e = fail("Sub Helper()\nEnd Sub\nSub Main()\n    x = Helper\nEnd Sub\n");
    assert!(e.message.contains("Sub Helper has no value"), "{e}");
}

#[test]
fn option_explicit_refuses_an_undeclared_variable() {
    let e = fail("Option Explicit\nSub Main()\n    Dim total\n    totl = total + 1\nEnd Sub\n");
    assert_eq!(
        e.to_string(),
        "bad.bas:4:5: syntax error: variable totl is not declared (Option Explicit): add Dim totl\n\
         \x204 |     totl = total + 1\n   |     ^"
    );
}

#[test]
fn a_runtime_error_shows_the_line_the_caret_and_the_calls() {
    let src = "Function Ratio(a, b)\n    Ratio = a / b\nEnd Function\n\nSub Main()\n    Dim x\n\
               \x20   Debug.Print \"before\"\n    x = Ratio(1, 0)\n    Nc.Rapid x, 0\nEnd Sub\n";
    let e = fail(src);
    assert_eq!(e.kind, ErrorKind::Runtime);
    // "Division by zero (Error 11)" is raised where the division is ([MS-VBAL] 5.6.9.3.4).
    assert_eq!(
        e.to_string(),
        "bad.bas:2:13: error: Division by zero (run-time error 11): a / b\n 2 |     Ratio = a / b\n   |             ^\n\
         \x20 in Function Ratio (called at line 8, column 9)\n  in Sub Main"
    );
    assert_eq!(e.output.printed, ["before"]);
}

#[test]
fn an_error_inside_a_function_names_the_call_chain() {
    let src = "Function Inner(v)\n    Inner = Cells(v, 1).Value\nEnd Function\n\
               Function Outer(v)\n    Outer = Inner(v) + 1\nEnd Function\n\
               Sub Main()\n    Debug.Print Outer(0)\nEnd Sub\n";
    let e = fail(src);
    assert_eq!(
        e.to_string(),
        "bad.bas:2:13: error: Cells: the cell would be off the sheet\n 2 |     Inner = Cells(v, 1).Value\n   |             ^\n\
         \x20 in Function Inner (called at line 5, column 13)\n  in Function Outer (called at line 8, column 17)\n  in Sub Main"
    );
}

#[test]
fn an_error_value_explains_itself_with_the_functions_note() {
    let e = fail(&main_body("    If CHAMFER_XA(\"outer\", 40, 2, 95, 0.8, 1, 1) > 0 Then Debug.Print 1"));
    assert!(e.message.starts_with("the If condition is #NUM! ("), "{e}");
    assert!(e.message.contains("90"), "the note says what range alpha must be in: {e}");
}

#[test]
fn typed_variables_refuse_what_they_cannot_hold() {
    let e = fail(&main_body("    Dim d As Double\n    d = \"abc\""));
    assert_eq!(e.message, "d cannot hold \"abc\" (type mismatch)");
    assert_eq!(e.span.unwrap().line, 3);
    let e = fail(&main_body("    Const K = 1\n    K = 2"));
    assert_eq!(e.message, "K is a constant");
}

#[test]
fn the_statement_limit_stops_an_endless_loop_and_can_be_raised() {
    let src = main_body("    Dim n\n    Do While n < 5000\n        n = n + 1\n    Loop\n    Debug.Print \"done\"");
    let small = RunOptions { max_statements: 1000, ..RunOptions::default() };
    let e = fail_with(&src, &small);
    assert_eq!(e.kind, ErrorKind::Limit);
    assert!(e.message.contains("statement limit (1000)"), "{e}");
    assert!(e.message.contains("--max-statements"), "{e}");
    assert!(e.to_string().contains("\n  in Sub Main"), "{e}");
    let line = e.span.unwrap().line;
    assert!((3..=4).contains(&line), "the loop is what was running: {e}");

    let mut wb = Workbook::with_sheet();
    let big = RunOptions { max_statements: 100_000, ..RunOptions::default() };
    assert_eq!(vba::run(&mut wb, &src, "ok.bas", &big).unwrap().printed, ["done"]);

    let e = fail_with(&main_body("    Do\n    Loop"), &small);
    assert_eq!(e.kind, ErrorKind::Limit, "an empty loop counts its turns");
}

#[test]
fn the_recursion_limit_stops_endless_recursion_and_can_be_raised() {
    let src = "Function Depth(n)\n    If n > 0 Then Depth = Depth(n - 1) + 1 Else Depth = 0\nEnd Function\n\
               Sub Main()\n    Debug.Print \"\" & Depth([A1])\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    wb.set_input(0, ncsheet::formula::address::Pos::new(0, 0), "60").unwrap();
    let options = RunOptions { max_depth: 50, ..RunOptions::default() };
    let e = vba::run(&mut wb, src, "deep.bas", &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Limit);
    assert!(e.message.contains("deeper than the limit (50)") && e.message.contains("--max-depth"), "{e}");
    let options = RunOptions { max_depth: 70, ..RunOptions::default() };
    assert_eq!(vba::run(&mut wb, src, "deep.bas", &options).unwrap().printed, ["60"]);
}

#[test]
fn the_default_limits_allow_deep_recursion_without_overflowing_the_stack() {
    let src = "Function Depth(n)\n    If n > 0 Then Depth = Depth(n - 1) + 1 Else Depth = 0\nEnd Function\n\
               Sub Main()\n    Debug.Print \"\" & Depth(95)\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    // Test threads have 2 MB of stack; the default depth (100) must fit in it.
    assert_eq!(vba::run(&mut wb, src, "deep.bas", &RunOptions::default()).unwrap().printed, ["95"]);
}

#[test]
fn files_programs_and_the_system_are_out_of_reach() {
    let statements = [
        "    Open \"C:\\out.nc\" For Output As #1",
        "    Print #1, \"G1 X1\"",
        "    Close #1",
        "    Kill \"part.nc\"",
        "    Shell \"rm -rf /\"",
        "    Set o = GetObject(\"x\")",
        "    Workbooks.Open \"other.xlsx\"",
        "    ThisWorkbook.SaveAs \"copy.xlsx\"",
        "    x = Dir(\"*.nc\")",
        "    MkDir \"out\"",
        "    x = Environ(\"HOME\")",
        "    x = VBA.Shell(\"calc\")",
        "    SendKeys \"x\"",
    ];
    for body in statements {
        let e = fail(&main_body(body));
        assert_eq!(e.kind, ErrorKind::Syntax, "{body}");
        assert!(e.message.contains("cannot touch files or run programs"), "{body}: {e}");
        assert!(e.span.unwrap().line >= 2, "{body}: {e}");
    }
    // A Declare line compiles (real modules declare under #If VBA7); calling it is refused.
    let e = fail(
        "Declare Function GetTickCount Lib \"kernel32\" () As Long\nSub Main()\n    x = GetTickCount()\nEnd Sub\n",
    );
    assert_eq!(e.kind, ErrorKind::Syntax);
    assert!(e.message.contains("cannot call into other programs"), "{e}");
    let e = fail(&main_body("    x = InputBox(\"D?\")"));
    assert!(e.message.contains("pass values with --arg"), "{e}");
}

#[test]
fn a_missing_sub_or_argument_is_a_usage_error() {
    let src = "Sub Cut(D)\nEnd Sub\nSub Other()\nEnd Sub\n";
    let e = fail_with(src, &RunOptions { sub: Some("Nope".into()), ..RunOptions::default() });
    assert_eq!(e.kind, ErrorKind::Usage);
    assert_eq!(e.to_string(), "bad.bas: error: no Sub named Nope (the module has: Cut, Other)");
    let e = fail_with(src, &RunOptions { sub: Some("Cut".into()), ..RunOptions::default() });
    assert_eq!(e.message, "Sub Cut needs D: pass --arg D=VALUE");
    let args = vec![("E".to_string(), "1".to_string())];
    let e = fail_with(src, &RunOptions { sub: Some("Cut".into()), args, ..RunOptions::default() });
    assert_eq!(e.message, "Sub Cut has no parameter E (it has: D)");
}

#[test]
fn any_cut_of_the_example_macros_parses_or_says_why_without_panicking() {
    let wb = Workbook::with_sheet();
    for src in [include_str!("../sheets/chamfer.bas"), include_str!("../sheets/cycles.bas")] {
        let lines: Vec<&str> = src.lines().collect();
        for n in 0..lines.len() {
            let cut = lines[..n].join("\n");
            if let Err(e) = vba::parse(&cut, "cut.bas", &wb) {
                assert!(e.span.is_some() && !e.message.is_empty(), "{e}");
            }
            // Every line dropped once, too.
            let dropped: Vec<&str> = lines.iter().enumerate().filter(|(i, _)| *i != n).map(|(_, l)| *l).collect();
            let dropped = dropped.join("\n");
            if vba::parse(&dropped, "dropped.bas", &wb).is_ok() {
                // And it runs to its end or to an error, without a panic.
                let mut wb = Workbook::with_sheet();
                for (cell, v) in [(1, "40"), (2, "2"), (3, "45"), (4, "0.8"), (5, "1"), (6, "1")] {
                    wb.set_input(0, ncsheet::formula::address::Pos::new(cell, 1), v).unwrap();
                }
                let options = RunOptions { max_statements: 100_000, ..RunOptions::default() };
                let _ = vba::run(&mut wb, &dropped, "dropped.bas", &options);
            }
        }
    }
}

#[test]
fn a_write_to_a_whole_sheet_is_refused_not_attempted() {
    let e = fail(&main_body("    Range(\"A1:XFD1048576\").Value = 1"));
    assert_eq!(e.message, "writing 17179869184 cells at once is more than a macro may (10000000)");
}

/// ncsheet's limits on what one statement may do (docs/limits.md: MAX_WRITE, MAX_FORMULA_WRITE,
/// MAX_PASTE, MAX_FORMATTED_CELLS, MAX_HIDDEN_ROWS) stop the run whatever On Error says, as the
/// statement limit does: a trapped one let the macro go on as if the cells had been written.
/// Two cells make the used range A1:Z500000 (13,000,000 cells) for the paste to clip to.
#[test]
fn on_error_does_not_skip_a_limit_on_what_one_statement_does() {
    let statements = [
        "Range(\"A1:XFD1048576\").Value = 1",
        "Range(\"A1:Z500000\").Formula = \"=1\"",
        "Range(\"A1:Z500000\").Copy Range(\"AA1\")",
        "Range(\"A1:Z500000\").Interior.Color = 255",
        "Rows(\"1:200000\").Hidden = True",
    ];
    for statement in statements {
        for trap in ["On Error Resume Next", "On Error GoTo Handler"] {
            let e = fail(&main_body(&format!(
                "    {trap}\n    Range(\"A1\").Value = 1\n    Range(\"Z500000\").Value = 2\n    {statement}\n    \
                 Debug.Print \"went on\"\n    Exit Sub\nHandler:\n    Debug.Print \"handled\""
            )));
            assert_eq!(e.kind, ErrorKind::Limit, "{statement}: {e}");
            assert!(e.message.contains("more than a macro may"), "{statement}: {e}");
            assert_eq!(e.span.map(|s| s.line), Some(5), "{statement}: {e}");
            assert!(e.output.printed.is_empty(), "{statement}: {:?}", e.output.printed);
        }
    }
}

#[test]
fn vb_object_error_is_the_base_of_an_objects_own_error_numbers() {
    // Microsoft's "Raise method": "For user-defined errors, add your error number to the
    // vbObjectError constant" -- vbObjectError is &H80040000 (-2147221504), so 513 is
    // -2147220991, as Err.Number reads it back.
    let src = "Option Explicit\nSub Main()\n    On Error Resume Next\n    Err.Raise vbObjectError + 513\n    Debug.Print Err.Number; Hex(vbObjectError)\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    let out = vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, vec!["-2147220991 80040000".to_string()]);
}

/// docs/limits.md, "macro statements": a trapped error counts three statements besides the
/// one that raised it (a raise and its handling cost about 1.25 µs, two statements' time;
/// a loop of them ran 21–37 s within the default limit). 25,000 turns of `Err.Raise` under
/// `On Error Resume Next` run 2 statements each (the loop's turn and the raise), 50,000, and
/// with a handler at most 4 (its label and `Resume Next`), 100,000: both within a limit of
/// 120,000 that the errors' 75,000 more pass.
#[test]
fn trapped_errors_count_against_the_statement_limit() {
    let limit = RunOptions { max_statements: 120_000, ..RunOptions::default() };
    for body in [
        "Dim i As Long\n On Error Resume Next\n For i = 1 To 25000\n Err.Raise 5\n Next",
        "Dim i As Long\n On Error GoTo h\n For i = 1 To 25000\n Err.Raise 5\n Next\n Exit Sub\nh:\n Resume Next",
    ] {
        let e = fail_with(&main_body(body), &limit);
        assert_eq!(e.kind, ErrorKind::Limit, "{body}: {e}");
        assert!(e.message.contains("statement limit (120000)"), "{body}: {e}");
    }
}
