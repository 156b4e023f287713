//! Issue 31, VBA's control flow where it meets errors: the Error statement, a label defined
//! twice, a GoTo into a With block, and `Resume` / `Resume Next` from an error handler whose
//! label is inside a block. Expected values are worked by hand from [MS-VBAL] (the VBA
//! language specification) and Microsoft's VBA language reference, the page named at each
//! test; where LibreOffice Basic in VBA mode (`Option VBASupport 1`) ran the same macro it
//! printed the same numbers (its own wording for Err.Description).

mod common;

use common::vba::{main_fails, run_main};
use ncsheet::vba::{self, ErrorKind, RunOptions};
use ncsheet::workbook::Workbook;

fn printed(body: &str) -> Vec<String> {
    run_main(&mut Workbook::with_sheet(), body)
}

// [MS-VBAL] 5.4.4.3 "Error Statement" and the reference's "Error statement": `Error n`
// "simulates the occurrence of an error": Err.Number is n and Err.Description "the return
// value of the Error function for the specified Number" (13 "Type mismatch", 11 "Division by
// zero", 9 "Subscript out of range" in "Trappable errors"). The number may be any expression;
// under On Error Resume Next the next statement runs with Err set. In a handler it raises to
// the caller ("On Error statement": an error in an active handler goes to the calling
// procedure), whose handler sees the same number.
#[test]
fn the_error_statement_raises_the_error_it_names() {
    let out = printed(
        "    On Error GoTo H\n    Error 13\n    Debug.Print \"after\"\n    Exit Sub\nH:\n\
         \x20   Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(out, [" 13 Type mismatch"]);
    let out = printed(
        "    Dim n\n    n = 6\n    On Error Resume Next\n    Error n + 5\n    Debug.Print Err.Number; Err.Description\n\
         \x20   Err.Clear\n    Error (9)\n    Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(out, [" 11 Division by zero", " 9 Subscript out of range"]);
    let src = "Sub Inner()\n    On Error GoTo H\n    Error 5\n    Exit Sub\nH:\n    Error Err.Number\nEnd Sub\n\n\
               Sub Main()\n    On Error GoTo H\n    Inner\n    Debug.Print \"not here\"\n    Exit Sub\nH:\n\
               \x20   Debug.Print \"caller\"; Err.Number; Err.Description\nEnd Sub\n";
    let out =
        vba::run(&mut Workbook::with_sheet(), src, "m.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["caller 5 Invalid procedure call or argument"]);
}

// Not trapped, `Error 13` stops the macro at its line with VBA's message and number.
#[test]
fn an_untrapped_error_statement_stops_the_macro_at_its_line() {
    let src = "Sub Main()\n    Debug.Print \"before\"\n    Error 13\n    Debug.Print \"after\"\nEnd Sub\n";
    let err = vba::run(&mut Workbook::with_sheet(), src, "m.bas", &RunOptions::default()).expect_err("error 13");
    assert_eq!(err.kind, ErrorKind::Runtime, "{err}");
    assert!(err.message.contains("Type mismatch") && err.message.contains("13"), "{err}");
    assert_eq!(err.span.map(|s| s.line), Some(3), "{err}");
    assert_eq!(err.output.printed, ["before"]);
}

// [MS-VBAL] 5.4.1.1 "Statement Labels": a label names one line of its procedure; VBA refuses
// a second at compile time ("Duplicate label"), here one in the body and one inside an If.
// The compile error is the procedure's own ([MS-VBAL] 4.2: a module's procedures compile
// apart): the module's other procedures run, and calling the bad one stops the macro naming
// the second label's line and column.
#[test]
fn a_label_defined_twice_is_a_compile_error_of_its_procedure() {
    let src = "Sub Good()\n    Debug.Print \"good\"\nEnd Sub\n\n\
               Sub Bad()\n    GoTo Twice\n    If True Then\nTwice:\n        Debug.Print \"first\"\n    End If\n\
               Twice:\n    Debug.Print \"second\"\nEnd Sub\n\n\
               Sub Main()\n    Good\n    Bad\nEnd Sub\n";
    let err = vba::run(&mut Workbook::with_sheet(), src, "m.bas", &RunOptions::default()).expect_err("Duplicate label");
    assert_eq!(err.kind, ErrorKind::Syntax, "{err}");
    assert!(err.message.contains("Twice") && err.message.contains("Duplicate label"), "{err}");
    assert_eq!(err.span.map(|s| (s.line, s.col)), Some((11, 1)), "{err}");
    assert_eq!(err.output.printed, ["good"]);
}

// "Object variable or With block variable not set (Error 91)": one of its causes is "The
// target of a GoTo statement is inside a With block"; "a With...End With block must be
// initialized by executing the With statement entry point" ([MS-VBAL] 5.4.2.21, the With
// statement). So `.Count` after a GoTo into the inner With is error 91, trappable, never the
// outer With's object (whose Count is 1). A `Resume label` into a With is the same jump (the
// handler turned off first: the On Error GoTo in force would trap the 91 and resume again).
#[test]
fn a_goto_or_resume_into_a_with_block_leaves_it_without_its_object() {
    let out = printed(
        "    Dim outer As New Collection, inner As New Collection\n    outer.Add 1\n    inner.Add 1\n    inner.Add 2\n\
         \x20   On Error GoTo H\n    With outer\n        GoTo Inside\n        With inner\nInside:\n\
         \x20           Debug.Print .Count\n        End With\n    End With\n    Exit Sub\nH:\n\
         \x20   Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(out, [" 91 Object variable or With block variable not set"]);
    let err = main_fails(
        &mut Workbook::with_sheet(),
        "    Dim c As New Collection\n    On Error GoTo H\n    Error 11\n    Exit Sub\nH:\n    On Error GoTo 0\n    Resume There\n\
         \x20   With c\nThere:\n        Debug.Print .Count\n    End With",
    );
    assert!(err.contains("(run-time error 91)"), "{err}");
}

// [MS-VBAL] 5.4.4.2 and the reference's "Resume statement": `Resume` "resumes execution with
// the statement that caused the error", `Resume Next` "with the statement immediately
// following" it, wherever the handler's label is ("On Error statement": any line label of the
// procedure). Here the failing statement is inside a For loop inside an If, the handler
// inside a Select Case arm reached only by the error. Worked by hand: 6 / (i - 2 + d) fails
// at i = 2 while d = 0; with Resume the handler sets d = 1 and the division runs again
// (6 / 1), then i = 3 adds 6 / 2: totals -6, 0, 3 (LibreOffice printed the same lines). With
// Resume Next the failing line is skipped once: -6, -6, then 6 / 2 at i = 3: -3.
#[test]
fn resume_and_resume_next_go_back_into_the_loop_from_a_handler_in_a_select() {
    let body = |resume: &str| {
        format!(
            "    Dim i As Integer, d As Integer, total As Double, tries As Integer\n    On Error GoTo H\n\
             \x20   If tries = 0 Then\n        For i = 1 To 3\n            total = total + 6 / (i - 2 + d)\n\
             \x20           Debug.Print \"i=\" & i & \" total=\" & total\n        Next i\n    End If\n\
             \x20   Debug.Print \"end \" & total & \" tries \" & tries\n    Exit Sub\n    Select Case tries\n\
             \x20   Case 5\n        Debug.Print \"case 5\"\n    Case Else\nH:\n        tries = tries + 1\n\
             \x20       d = 1\n        {resume}\n    End Select"
        )
    };
    assert_eq!(printed(&body("Resume")), ["i=1 total=-6", "i=2 total=0", "i=3 total=3", "end 3 tries 1"]);
    assert_eq!(printed(&body("Resume Next")), ["i=1 total=-6", "i=2 total=-6", "i=3 total=-3", "end -3 tries 1"]);
}

// The handler inside the failing loop's own body ("Resume statement" as above, and "Resume
// without error (Error 20)": a Resume when no error is being handled is error 20, which the
// On Error GoTo in force traps). At i = 1: the division fails, H prints, Resume Next goes on
// after the division, which is H's line: it prints again; that Resume Next has no error to
// end: error 20, trapped: H prints a third time and Resume Next goes on after the failing
// Resume, at Next. The same at i = 2, then the loop ends. Before, ncsheet refused this Resume.
#[test]
fn resume_next_from_a_handler_inside_the_failing_loop_goes_on_in_the_loop() {
    let out = printed(
        "    Dim i As Long, x\n    For i = 1 To 2\n        On Error GoTo H\n        x = 1 / 0\nH:\n\
         \x20       Debug.Print \"h\"; i; Err.Number\n        Resume Next\n    Next i\n    Debug.Print \"done\"",
    );
    assert_eq!(out, ["h 1  11 ", "h 1  0 ", "h 1  20 ", "h 2  11 ", "h 2  0 ", "h 2  20 ", "done"]);
}

// A handler inside the With and the loop around the failing statement has that With's object
// (the With statement ran: "With statement"), and its Resume Next goes on in that loop
// ([MS-VBAL] 5.4.4.2): at i = 1 the division fails, H prints the Collection's Count and first
// item, Resume Next goes on with `GoTo Skip`; at i = 2 the division gives 100.
#[test]
fn a_handler_inside_the_running_with_and_loop_keeps_the_object_and_the_loop() {
    let out = printed(
        "    Dim c As New Collection, i As Integer\n    c.Add 10\n    c.Add 20\n    With c\n        For i = 1 To 2\n\
         \x20           On Error GoTo H\n            Debug.Print 100 / (i - 1)\n            GoTo Skip\nH:\n\
         \x20           Debug.Print \"h\"; .Count; .Item(i)\n            Resume Next\nSkip:\n        Next i\n    End With",
    );
    assert_eq!(out, ["h 2  10 ", " 100 "]);
}

// Hostile input: a handler that turns itself off with `On Error GoTo -1` and jumps back to
// the failing line runs again at the next error, nested one level deeper each time (the
// failing statement waits for its Resume). Before the native stack runs out it is VBA's
// error 28, "Out of stack space" ("Out of stack space (Error 28)"), at the failing line
// (docs/limits.md), never a crash.
#[test]
fn handlers_that_nest_without_end_stop_with_error_28() {
    let src = "Sub Main()\n    Dim n As Long, x\n    On Error GoTo H\nAgain:\n    n = n + 1\n    x = 1 / 0\nH:\n\
               \x20   On Error GoTo -1\n    If n < 1000000 Then GoTo Again\nEnd Sub\n";
    let err = vba::run(&mut Workbook::with_sheet(), src, "m.bas", &RunOptions::default()).expect_err("error 28");
    assert!(err.message.contains("Out of stack space (run-time error 28)"), "{err}");
    assert_eq!(err.span.map(|s| s.line), Some(6), "{err}");
}

// [MS-VBAL] 5.4.2.9 "Single-line If Statement": the statements after `Then` (and after `Else`)
// are a list-or-label, `[":"] same-line-statement *(":" [same-line-statement])`: they may start
// with a colon (`If n = 0 Then: GoTo Done`, written by real modules), a statement may be left
// out between colons or after the last one, and "if-with-empty-then" (`If x Then Else y = 1`)
// has no statement before Else. 5.4.2.8 "If Statement": `Then` is followed by EOS, any run of
// colons and line ends, so `If x Then:` at a line's end opens a block closed by End If.
#[test]
fn a_single_line_if_takes_the_colons_its_grammar_allows() {
    let out = printed(
        "    Dim a As Long, b As Long\n\
         \x20   If a = 0 Then: a = 5\n    Debug.Print a\n\
         \x20   If a = 0 Then Else b = 7\n    Debug.Print b\n\
         \x20   If a = 5 Then a = 6: : b = 8\n    Debug.Print a; b\n\
         \x20   If a = 6 Then a = 1: Else: a = 2\n    Debug.Print a\n\
         \x20   If a = 9 Then a = 3 Else: a = 4\n    Debug.Print a\n\
         \x20   If a = 4 Then a = 10:\n    Debug.Print a\n\
         \x20   If a = 10 Then:\n        a = 11\n    End If\n    Debug.Print a\n\
         \x20   If a = 0 Then: GoTo Done\n    Debug.Print \"on\"\n\
         Done:",
    );
    assert_eq!(out, [" 5 ", " 7 ", " 6  8 ", " 1 ", " 4 ", " 10 ", " 11 ", "on"]);
}
