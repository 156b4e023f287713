//! VBA conformance, issue 31: each construct real modules use, with the result Microsoft's
//! VBA language reference (learn.microsoft.com, "Office VBA language reference", page named
//! at each test) or the language specification [MS-VBAL] gives, never our own earlier output.

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::{self, ErrorKind, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run_with(src: &str, options: &RunOptions) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", options)
}

fn run(src: &str) -> RunOutput {
    run_with(src, &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// An expression's value as a cell receives it.
fn value(expr: &str) -> Value {
    let mut wb = Workbook::with_sheet();
    let src = format!("Sub Main()\n    [A1] = {expr}\nEnd Sub\n");
    vba::run(&mut wb, &src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{expr}: {e}"));
    wb.value(0, parse_cell("A1").unwrap())
}

fn n(x: f64) -> Value {
    Value::Number(x)
}

// "Operator precedence": exponentiation ranks above negation, so `-2^2` is -(2^2) = -4
// ([MS-VBAL] 5.6.9.1); a cell's `=-2^2` is 4, Excel ranking negation first.
#[test]
fn negation_binds_looser_than_exponentiation() {
    assert_eq!(value("-2^2"), n(-4.0));
    assert_eq!(value("-2 ^ 2 + 1"), n(-3.0));
    assert_eq!(value("(-2) ^ 2"), n(4.0));
    assert_eq!(value("2 ^ -1"), n(0.5));
    assert_eq!(value("-3 * 2"), n(-6.0));
    let mut wb = Workbook::with_sheet();
    wb.set_input(0, parse_cell("A1").unwrap(), "=-2^2").unwrap();
    assert_eq!(wb.value(0, parse_cell("A1").unwrap()), n(4.0), "cells keep Excel's precedence");
}

// [MS-VBAL] 3.3.2 "Number Tokens": a type character after a number (`#` Double, `!` Single,
// `@` Currency, `%` Integer, `&` Long) types the literal, its value unchanged; "Type
// characters" in the language reference lists them.
#[test]
fn numbers_with_a_type_character() {
    assert_eq!(value("0#"), n(0.0));
    assert_eq!(value("10# / 4"), n(2.5));
    assert_eq!(value("1E10#"), n(1e10));
    assert_eq!(value("1.5!"), n(1.5));
    assert_eq!(value("1@ + 1%"), n(2.0));
    assert_eq!(value("100000&"), n(100_000.0));
    assert_eq!(value("&HFF&"), n(255.0));
    assert_eq!(value("&HFFFF&"), n(65535.0));
    assert_eq!(value("\"a\" & 1"), Value::text("a1"), "& before a space is still concatenation");
    // An Integer literal past 32767 does not compile: "Overflow".
    let e = run_with("Sub Main()\n    x = 40000%\nEnd Sub\n", &RunOptions::default()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Syntax, "{e}");
    assert!(e.message.contains("overflow"), "{e}");
}

// "Is operator": `object Is Nothing` is True for an object variable that refers to no
// object (before Set, after `Set x = Nothing`); `a Is b` is True when both refer to one object.
#[test]
fn is_nothing_and_is_compare_objects() {
    let out = run("Sub Main()\n    Dim r As Range, q As Range\n    Debug.Print r Is Nothing\n\
                   \x20   Set r = Range(\"A1\")\n    Debug.Print r Is Nothing\n    Set q = r\n    Debug.Print q Is r\n\
                   \x20   Set q = Range(\"B1\")\n    Debug.Print q Is r\n    Debug.Print Not r Is Nothing\n\
                   \x20   Set r = Nothing\n    If r Is Nothing Then Debug.Print \"gone\"\nEnd Sub\n");
    assert_eq!(out.printed, ["True", "False", "True", "False", "True", "gone"]);
}

// "Function statement" / "Sub statement": `Static` keeps the procedure's local variables
// between calls.
#[test]
fn static_function_and_sub_keep_their_locals() {
    let out = run("Static Function Counter()\n    Dim n\n    n = n + 1\n    Counter = n\nEnd Function\n\
                   Public Static Sub Tick()\n    Dim t As Long\n    t = t + 10\n    Debug.Print t\nEnd Sub\n\
                   Sub Main()\n    Debug.Print Counter(); Counter(); Counter()\n    Tick\n    Tick\nEnd Sub\n");
    assert_eq!(out.printed, [" 1  2  3 ", " 10 ", " 20 "]);
}

// "#If...Then...#Else directive" and "Compiler constants": on 64-bit Excel for Windows VBA7
// and Win64 are True, Mac is False; a branch not taken is not compiled (a Declare there is
// never seen), and #Const defines a constant for the directives only.
#[test]
fn conditional_compilation_takes_excel_64_bit_windows_branches() {
    let src = "#If VBA7 Then\n    Private Declare PtrSafe Function GetTickCount Lib \"kernel32\" () As LongPtr\n\
               #Else\n    Private Declare Function GetTickCount Lib \"kernel32\" () As Long\n#End If\n\
               #Const DEBUGGING = 0\n\
               Sub Main()\n#If Win64 And Not Mac Then\n    Debug.Print \"win64\"\n#ElseIf Mac Then\n\
               \x20   Debug.Print \"mac\"\n#Else\n    Debug.Print \"win32\"\n#End If\n#If DEBUGGING Then\n\
               \x20   this line is not VBA and is never compiled\n#End If\n    Debug.Print \"done\"\nEnd Sub\n";
    assert_eq!(run(src).printed, ["win64", "done"]);
}

// A Declare'd DLL procedure can be declared but never called: the sandbox holds.
#[test]
fn a_declared_dll_procedure_is_refused_when_called() {
    let src = "Private Declare PtrSafe Function GetTickCount Lib \"kernel32\" () As LongPtr\n\
               Sub Main()\n    Debug.Print GetTickCount()\nEnd Sub\n";
    let e = run_with(src, &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("cannot call into other programs"), "{e}");
    assert_eq!(e.span.unwrap().line, 3);
}

// [MS-VBAL] 3.2.2: a line continuation inside a comment continues the comment.
#[test]
fn a_comment_continued_with_underscore_takes_the_next_line() {
    let src = "Sub Main()\n    ' a comment that goes on _\n      Debug.Print \"not run\"\n\
               \x20   Debug.Print \"run\" ' trailing _\n    and this is comment too\nEnd Sub\n";
    assert_eq!(run(src).printed, ["run"]);
}

// [MS-VBAL] 3.2.2, line continuation: anywhere between tokens, after a member's dot too.
#[test]
fn a_member_access_continued_after_the_dot() {
    let src =
        "Sub Main()\n    Debug.Print Application. _\n        WorksheetFunction. _\n        Max(1, 5, 3)\nEnd Sub\n";
    assert_eq!(run(src).printed, [" 5 "]);
}

fn project_run(own: &str, others: &[(&str, &str)]) -> Result<RunOutput, MacroError> {
    let project = others.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    run_with(own, &RunOptions { project, ..RunOptions::default() })
}

// "Understanding scope and visibility": a Public procedure, constant or variable of a
// standard module is visible to the project's other modules, by name or `Module2.Name`; a
// Private one is not.
#[test]
fn public_code_of_other_modules_is_visible_private_is_not() {
    let module2 = "Attribute VB_Name = \"Module2\"\nOption Explicit\nPublic Const PI As Double = 3.14159\n\
                   Public Function Helper(x)\n    Helper = 2 * x + Hidden()\nEnd Function\n\
                   Private Function Hidden()\n    Hidden = 1\nEnd Function\n";
    let main = "Sub Main()\n    Debug.Print Helper(1); Module2.Helper(2); PI\nEnd Sub\n";
    assert_eq!(project_run(main, &[("Module2", module2)]).unwrap().printed, [" 3  5  3.14159 "]);
    let private = "Sub Main()\n    Debug.Print Hidden()\nEnd Sub\n";
    let e = project_run(private, &[("Module2", module2)]).unwrap_err();
    assert!(e.message.contains("Hidden"), "{e}");
}

#[test]
fn a_name_in_two_modules_is_each_modules_own() {
    let module2 = "Public Function Twice(x)\n    Twice = Helper(x) * 2\nEnd Function\n\
                   Private Function Helper(x)\n    Helper = x + 100\nEnd Function\n";
    let main = "Private Function Helper(x)\n    Helper = x\nEnd Function\n\
                Sub Main()\n    Debug.Print Helper(1); Twice(1)\nEnd Sub\n";
    assert_eq!(project_run(main, &[("Module2", module2)]).unwrap().printed, [" 1  202 "]);
}

#[test]
fn an_error_in_another_module_names_that_module_and_its_line() {
    let module2 = "Public Function Item(i)\n    Dim a(1 To 3)\n    Item = a(i)\nEnd Function\n";
    let main = "Sub Main()\n    Debug.Print Item(5)\nEnd Sub\n";
    let e = project_run(main, &[("Module2", module2)]).unwrap_err();
    assert_eq!((e.file.as_str(), e.span.unwrap().line), ("Module2", 3), "{e}");
}

// VBA compiles a procedure when it is first run ("Compile on demand", the VBE's default): a
// procedure that does not compile fails when it is called, and the module's others run.
#[test]
fn a_procedure_that_does_not_compile_fails_only_when_run() {
    let src = "Sub Broken()\n    x = NoSuchFunction(1)\nEnd Sub\n\
               Sub Main()\n    Debug.Print \"fine\"\nEnd Sub\n";
    assert_eq!(run(src).printed, ["fine"]);
    let calls = "Sub Broken()\n    x = NoSuchFunction(1)\nEnd Sub\n\
                 Sub Main()\n    Debug.Print \"before\"\n    On Error Resume Next\n    Broken\nEnd Sub\n";
    let e = run_with(calls, &RunOptions::default()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Syntax, "a compile error is not trapped: {e}");
    assert_eq!(e.span.unwrap().line, 2);
    assert!(e.message.contains("NoSuchFunction"), "{e}");
    assert_eq!(e.output.printed, ["before"]);
}

// "Miscellaneous constants": vbNewLine is Chr(13) + Chr(10), vbLf Chr(10) alone.
#[test]
fn vb_new_line_is_cr_lf() {
    assert_eq!(value("Len(vbNewLine) & \",\" & Asc(vbNewLine) & \",\" & Len(vbLf)"), Value::text("2,13,1"));
}

// "WorksheetFunction object": each worksheet function is a member of Application as well
// (`Application.Max`, `Application.Transpose`); Application's own members stay members.
#[test]
fn worksheet_functions_through_application() {
    let out = run("Sub Main()\n    Dim t\n    t = Application.Transpose(Array(1, 2, 3))\n\
                   \x20   Debug.Print Application.Max(3, 9, 4); UBound(t, 1); t(2, 1)\n    Debug.Print Application.Name\nEnd Sub\n");
    assert_eq!(out.printed, [" 9  3  2 ", "ncsheet"]);
}
