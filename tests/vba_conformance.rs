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

// The same holds for a line the grammar cannot read: "Compile on demand" compiles a procedure
// when it is called, so a line of one procedure that does not parse fails that procedure
// when it runs, at its own line and column, and the module's other macros run.
#[test]
fn a_procedure_with_a_line_that_does_not_parse_fails_only_when_run() {
    let broken = "Function Broken()\n    Dim g\n    g = 1 +\n    Broken = g\nEnd Function\n";
    let main = "Sub Main()\n    Debug.Print 3 + 4\nEnd Sub\n";
    assert_eq!(run(&format!("{broken}{main}")).printed, [" 7 "]);
    let calls = "Sub Main()\n    Debug.Print \"before\"\n    On Error Resume Next\n    x = Broken()\nEnd Sub\n";
    let e = run_with(&format!("{broken}{calls}"), &RunOptions::default()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Syntax, "a compile error is not trapped: {e}");
    let span = e.span.unwrap();
    assert_eq!((span.line, span.col), (3, 12), "{e}");
    assert_eq!(e.output.printed, ["before"]);
    // A line outside every procedure still fails the module, as VBA's module-level
    // declarations compile with the first call into it.
    let e = run_with(&format!("Dim x As\n{main}"), &RunOptions::default()).unwrap_err();
    assert_eq!((e.kind, e.span.unwrap().line), (ErrorKind::Syntax, 1), "{e}");
}

// "Property Get statement", "Property Let statement": a procedure may be written on one line,
// its statements after colons (`Property Get X(): X = m: End Property`), as the VBE keeps it.
#[test]
fn a_procedure_on_one_line_runs() {
    let class = "Private m As Double\n\
                 Public Property Get X() As Double: X = m: End Property\n\
                 Public Property Let X(v As Double): m = v * 2: End Property\n\
                 Public Function Twice(): Twice = 2 * m: End Function\n";
    let main = "Sub Show(s): Debug.Print s: End Sub\n\
                Sub Main()\n    Dim p As New CPoint\n    p.X = 1.5\n    Show p.X\n    Show p.Twice()\nEnd Sub\n";
    let options = RunOptions { classes: vec![("CPoint".into(), class.into())], ..RunOptions::default() };
    assert_eq!(run_with(main, &options).unwrap_or_else(|e| panic!("{e}")).printed, [" 3 ", " 6 "]);
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

/// Lines a macro prints, its `Main` run in a fresh workbook.
fn printed(body: &str) -> Vec<String> {
    run(&format!("Sub Main()\n{body}\nEnd Sub\n")).printed
}

/// The error a macro stops with.
fn failure(src: &str) -> MacroError {
    run_with(src, &RunOptions::default()).unwrap_err()
}

// [MS-VBAL] 5.2.1.4 "Option Compare" and 5.6.9.5 "Relational Operators": without the
// option (Binary) texts compare by their code units, case counting ("a" is U+0061, after
// "B" U+0042); `Option Compare Text` ignores case. `Like` ("Like operator") and Select Case
// ([MS-VBAL] 5.4.2.10, its tests compare as `=`, `<=` and `>=` do) follow the option too.
const COMPARISONS: &str =
    "    Debug.Print \"a\" = \"A\"\n    Debug.Print \"a\" < \"B\"\n    Debug.Print \"B\" < \"a\"\n\
    \x20   Debug.Print \"abc\" Like \"A*\"\n    Select Case \"x\"\n    Case \"X\": Debug.Print \"X\"\n\
    \x20   Case Is > \"a\": Debug.Print \"after a\"\n    End Select";

#[test]
fn text_compares_by_code_units_by_default_and_without_case_under_option_compare_text() {
    assert_eq!(printed_in("", COMPARISONS), ["False", "False", "True", "False", "after a"]);
    assert_eq!(printed_in("Option Compare Binary", COMPARISONS), ["False", "False", "True", "False", "after a"]);
    assert_eq!(printed_in("Option Compare Text", COMPARISONS), ["True", "True", "False", "True", "X"]);
    // "InStr function", "StrComp function": the compare argument left out (or
    // vbUseCompareOption) is the module's Option Compare.
    let functions =
        "    Debug.Print InStr(\"aXb\", \"x\"); StrComp(\"a\", \"A\"); StrComp(\"a\", \"A\", vbUseCompareOption)";
    assert_eq!(printed_in("", functions), [" 0  1  1 "]);
    assert_eq!(printed_in("Option Compare Text", functions), [" 2  0  0 "]);
    // "Replace function": compare left out is the option too.
    assert_eq!(printed_in("", "    Debug.Print Replace(\"aXa\", \"x\", \"-\")"), ["aXa"]);
    assert_eq!(printed_in("Option Compare Text", "    Debug.Print Replace(\"aXa\", \"x\", \"-\")"), ["a-a"]);
}

// [MS-VBAL] 5.6.9.5 "Relational Operators" and "Comparison operators" (Office VBA reference):
// a String against a numeric type is made a Double (a String that is no number: run-time
// error 13, Type mismatch); a String against a Variant holding a number compares as texts
// ("9" > "10"); a Variant holding a String against a Variant holding a number: the number is
// less. Empty against a String is "".
#[test]
fn a_string_against_a_number_compares_as_vba_says() {
    let out = printed_in(
        "",
        "    Dim s As String, v, n, e\n    s = \"10\": v = \"10\": n = 10\n    Debug.Print s = 10\n    Debug.Print v = 10\n\
         \x20   Debug.Print v = n\n    Debug.Print v > n\n    Debug.Print e = \"\"\n    n = 9\n    Debug.Print s < n\n\
         \x20   On Error Resume Next\n    s = \"abc\"\n    Debug.Print s = 1\n    Debug.Print Err.Number",
    );
    assert_eq!(out, ["True", "True", "False", "True", "True", "True", " 13 "]);
}

// [MS-VBAL] 5.6.9.3 "Arithmetic Operators" and "Trappable errors": an operation that fails
// raises a run-time error, which On Error traps (the variable is not assigned) and which
// stops the macro at its line otherwise: `/`, `\` and `Mod` by zero are 11 ("Division by
// zero"), a String operand that is no number 13 ("Type mismatch"), a result past a Double 6
// ("Overflow"). An error value a Variant holds (`CVErr`, "CVErr function") is no failure.
#[test]
fn failing_arithmetic_raises_the_run_time_error_on_error_traps() {
    let out = printed(
        "    Dim x\n    On Error Resume Next\n    x = 1 / 0\n    Debug.Print Err.Number; TypeName(x)\n    Err.Clear\n\
         \x20   x = 7 \\ 0\n    Debug.Print Err.Number\n    Err.Clear\n    x = 7 Mod 0\n    Debug.Print Err.Number\n\
         \x20   Err.Clear\n    x = \"abc\" + 1\n    Debug.Print Err.Number\n    Err.Clear\n    x = 1E308 * 10\n\
         \x20   Debug.Print Err.Number\n    Err.Clear\n    x = CVErr(xlErrDiv0)\n    Debug.Print Err.Number; TypeName(x)",
    );
    assert_eq!(out, [" 11 Empty", " 11 ", " 11 ", " 13 ", " 6 ", " 0 Error"]);
    let e = failure("Sub Main()\n    Dim x\n    x = 1 / 0\nEnd Sub\n");
    assert!(e.message.contains("Division by zero (run-time error 11)"), "{e}");
    assert_eq!(e.span.unwrap().line, 3);
}

// "Split function": a zero-based, one-dimensional array; the delimiter defaults to a space,
// a "" delimiter gives the whole text as one item, "" gives an array with no items (UBound
// -1), `limit` items at most (the last holds the rest), compare 1 (vbTextCompare) ignores
// case. Its example: Split("a:b:c", ":", 2) is {"a", "b:c"}.
#[test]
fn split_returns_a_zero_based_array() {
    let out = printed(
        "    Dim a, b, c, d, e\n    a = Split(\"x1,y2,,z\", \",\")\n    Debug.Print LBound(a); UBound(a); a(0); a(2) = \"\"; a(3)\n\
         \x20   b = Split(\"one two\")\n    Debug.Print UBound(b); b(1)\n\
         \x20   c = Split(\"a:b:c\", \":\", 2)\n    Debug.Print UBound(c); c(1)\n\
         \x20   d = Split(\"\")\n    Debug.Print UBound(d)\n\
         \x20   e = Split(\"solo\", \",\")\n    Debug.Print LBound(e); UBound(e); e(0)\n\
         \x20   e = Split(\"1X2x3\", \"x\", -1, vbTextCompare)\n    Debug.Print UBound(e); e(1)\n\
         \x20   e = Split(\"abc\", \"\")\n    Debug.Print UBound(e); e(0)",
    );
    assert_eq!(out, [" 0  3 x1Truez", " 1 two", " 1 b:c", "-1 ", " 0  0 solo", " 2 2", " 0 abc"]);
}

// Option Base does not change Split's lower bound ("Split function": zero-based).
#[test]
fn split_is_zero_based_under_option_base_1() {
    let out = run("Option Base 1\nSub Main()\n    Dim a\n    a = Split(\"p q\")\n    Debug.Print LBound(a); a(0)\n\
                   \x20   a = Array(7)\n    Debug.Print LBound(a); UBound(a)\nEnd Sub\n");
    assert_eq!(out.printed, [" 0 p", " 1  1 "]);
}

// "Join function": the items joined with the delimiter, a space when omitted.
#[test]
fn join_puts_the_delimiter_between_items() {
    assert_eq!(value("Join(Array(\"G0\", \"X1\", \"Z-2\"))"), Value::text("G0 X1 Z-2"));
    assert_eq!(value("Join(Split(\"a,b,c\", \",\"), \";\")"), Value::text("a;b;c"));
    assert_eq!(printed("    Debug.Print Join(Array(1, 2.5), \"\")"), ["12.5"]);
}

// "InStrRev function": from the end; a zero-length stringmatch gives start, start past the
// text 0, and a match counts only when it ends at or before start. Examples of Visual
// Basic's page: InStrRev("the quick brown fox jumps over the lazy dog", "the") is 32, with
// start 16 it is 1.
#[test]
fn instr_rev_searches_from_the_end() {
    let s = "\"the quick brown fox jumps over the lazy dog\"";
    assert_eq!(value(&format!("InStrRev({s}, \"the\")")), n(32.0));
    assert_eq!(value(&format!("InStrRev({s}, \"the\", 16)")), n(1.0));
    assert_eq!(value("InStrRev(\"ABCDEFGHCIJK\", \"C\", 2)"), n(0.0));
    assert_eq!(value("InStrRev(\"ABCDEFGHCIJK\", \"C\", 8)"), n(3.0));
    assert_eq!(value("InStrRev(\"abc\", \"\", 2)"), n(2.0));
    assert_eq!(value("InStrRev(\"abc\", \"c\", 9)"), n(0.0));
    assert_eq!(value("InStrRev(\"\", \"c\")"), n(0.0));
    assert_eq!(value("InStrRev(\"aXbx\", \"X\", -1, vbTextCompare)"), n(4.0));
    assert_eq!(value("InStrRev(\"aXbx\", \"X\", -1, vbBinaryCompare)"), n(2.0));
}

// "InStr function": InStr([start,] string1, string2[, compare]); with compare the start is
// required. The page's example: InStr(4, "XXpXXpXXPXXP", "P", 1) is 6 (textual), with 0
// (binary) it is 9.
#[test]
fn instr_with_a_comparison() {
    assert_eq!(value("InStr(4, \"XXpXXpXXPXXP\", \"P\", 1)"), n(6.0));
    assert_eq!(value("InStr(1, \"XXpXXpXXPXXP\", \"P\", 0)"), n(9.0));
    assert_eq!(value("InStr(\"XXpXXpXXPXXP\", \"P\")"), n(9.0));
    assert_eq!(value("InStr(1, \"XXpXXpXXPXXP\", \"W\", vbTextCompare)"), n(0.0));
}

// A textual comparison (vbTextCompare, "InStr function", "InStrRev function", "Split
// function", "Replace function", "Filter function") ignores case beyond ASCII too ("É" is
// "é"), and the positions given and taken are characters, not bytes: "àbécÉ" has "é" at 3,
// "É" at 5.
#[test]
fn text_comparisons_fold_case_beyond_ascii_and_count_characters() {
    assert_eq!(value("InStr(1, \"àbécÉ\", \"É\", vbTextCompare)"), n(3.0));
    assert_eq!(value("InStr(1, \"àbécÉ\", \"É\", vbBinaryCompare)"), n(5.0));
    assert_eq!(value("InStr(4, \"àbécÉ\", \"é\", 1)"), n(5.0));
    assert_eq!(value("InStrRev(\"ÉàéÀ\", \"à\", -1, vbTextCompare)"), n(4.0));
    assert_eq!(value("InStrRev(\"ÉàéÀ\", \"à\", -1, vbBinaryCompare)"), n(2.0));
    assert_eq!(value("InStrRev(\"ÉàéÀ\", \"É\", 3, 1)"), n(3.0));
    let out = printed(
        "    Dim a\n    a = Split(\"xÄyäz\", \"ä\", -1, vbTextCompare)\n    Debug.Print UBound(a); a(0); a(1); a(2)\n\
         \x20   a = Split(\"xÄyäz\", \"ä\")\n    Debug.Print UBound(a); a(0); a(1)\n\
         \x20   Debug.Print Replace(\"ÖlÖl\", \"öl\", \"-\", 1, -1, vbTextCompare); \" \"; Replace(\"ÖlÖl\", \"öl\", \"-\", 2, -1, 1); \
         \" \"; Replace(\"ÖlÖl\", \"öl\", \"-\")\n\
         \x20   a = Filter(Array(\"Straße\", \"ÜBER\", \"über\", \"Ober\"), \"Über\", True, vbTextCompare)\n    Debug.Print UBound(a); a(0); a(1)",
    );
    assert_eq!(out, [" 2 xyz", " 1 xÄyz", "-- l- ÖlÖl", " 1 ÜBERüber"]);
}

// "StrComp function": -1, 0, 1; the page's example: StrComp("ABCD", "abcd", 1) is 0,
// with 0 it is -1, StrComp("abcd", "ABCD") is 1.
#[test]
fn str_comp_orders_texts() {
    assert_eq!(value("StrComp(\"ABCD\", \"abcd\", 1)"), n(0.0));
    assert_eq!(value("StrComp(\"ABCD\", \"abcd\", 0)"), n(-1.0));
    assert_eq!(value("StrComp(\"abcd\", \"ABCD\")"), n(1.0));
    assert_eq!(value("StrComp(\"T10\", \"T10\")"), n(0.0));
    // A textual comparison ignores case beyond ASCII too ("Ä" is "ä"), and a text that is
    // the start of another comes first in either mode.
    assert_eq!(value("StrComp(\"ÄBCD\", \"äbcd\", 1)"), n(0.0));
    assert_eq!(value("StrComp(\"ÄB\", \"äc\", vbTextCompare)"), n(-1.0));
    assert_eq!(value("StrComp(\"ab\", \"AB C\", 1)"), n(-1.0));
    assert_eq!(value("StrComp(\"AB C\", \"ab\", 1)"), n(1.0));
}

// "VarType function" and "VarType constants": vbEmpty 0, vbInteger 2, vbLong 3, vbDouble
// 5, vbString 8, vbError 10, vbBoolean 11, vbArray 8192 added to the items' type (8204 an
// array of Variants, 8194 of Integers); a typed variable answers its declared type.
#[test]
fn var_type_names_the_subtype() {
    let out = printed(
        "    Dim v, i As Integer, l As Long, d As Double, s As String, b As Boolean, a(3) As Integer\n\
         \x20   Debug.Print VarType(v); VarType(i); VarType(l); VarType(d); VarType(s); VarType(b)\n\
         \x20   v = \"x\": Debug.Print VarType(v); VarType(1.5); VarType(True); VarType(CVErr(xlErrNA))\n\
         \x20   Debug.Print VarType(a); VarType(Array(1, 2)); VarType(a) = vbArray + vbInteger",
    );
    assert_eq!(out, [" 0  2  3  5  8  11 ", " 8  5  11  10 ", " 8194  8204 True"]);
}

// "IsMissing function": True for an Optional Variant parameter the call left out; an
// omitted parameter with a default is not missing (it has its default).
#[test]
fn is_missing_tells_a_left_out_optional_variant() {
    let src = "Sub Describe(a, Optional b, Optional c As Variant, Optional d = 5)\n\
               \x20   Debug.Print IsMissing(b); IsMissing(c); IsMissing(d)\nEnd Sub\n\
               Sub Main()\n    Describe 1\n    Describe 1, 2\n    Describe 1, , 3\n    Describe 1, c:=\"x\"\nEnd Sub\n";
    assert_eq!(run(src).printed, ["TrueTrueFalse", "FalseTrueFalse", "TrueFalseFalse", "TrueFalseFalse"]);
}

// "IsArray function": True for an array variable, False for a value.
#[test]
fn is_array_tells_arrays() {
    let out = printed(
        "    Dim a(2), v\n    v = 3\n    Debug.Print IsArray(a); IsArray(v); IsArray(Array()); IsArray(Split(\"a b\"))",
    );
    assert_eq!(out, ["TrueFalseTrueTrue"]);
}

// "CVErr function": an error value from its number; IsError is True for it. Excel's
// xlErrNA is 2042, xlErrDiv0 2007 ("XlCVError enumeration"); a cell receives #N/A.
#[test]
fn cverr_makes_an_error_value() {
    assert_eq!(value("CVErr(xlErrNA)"), Value::Error(ncsheet::formula::error::XlError::NA));
    assert_eq!(value("CVErr(2007)"), Value::Error(ncsheet::formula::error::XlError::Div0));
    let out = printed("    Dim e\n    e = CVErr(xlErrValue)\n    Debug.Print IsError(e); IsError(1)");
    assert_eq!(out, ["TrueFalse"]);
}

// "FormatNumber function": digits after the decimal point (regional default two),
// leading zero, parentheses for negatives and grouping as Tristate (vbTrue -1, vbFalse 0,
// vbUseDefault -2); en-US defaults: a leading zero, a minus sign, grouped thousands.
#[test]
fn format_number_uses_regional_defaults() {
    let out = printed(
        "    Debug.Print FormatNumber(1234.567)\n    Debug.Print FormatNumber(1234.567, 1)\n\
         \x20   Debug.Print FormatNumber(0.5, 2, vbFalse)\n    Debug.Print FormatNumber(-3, 0, , vbTrue)\n\
         \x20   Debug.Print FormatNumber(1234.5, 2, , , vbFalse)",
    );
    assert_eq!(out, ["1,234.57", "1,234.6", ".50", "(3)", "1234.50"]);
}

// "Timer function": seconds elapsed since midnight, by the document's clock here.
#[test]
fn timer_reads_the_document_clock() {
    let mut wb = Workbook::with_sheet();
    // 2026-01-02 06:00:30 as a serial: 46024 + (6 * 3600 + 30) / 86400.
    wb.settings_mut().clock = Some(46024.0 + 21630.0 / 86400.0);
    let out =
        vba::run(&mut wb, "Sub Main()\n    Debug.Print Timer\nEnd Sub\n", "M.bas", &RunOptions::default()).unwrap();
    let seconds: f64 = out.printed[0].trim().parse().unwrap();
    assert!((seconds - 21630.0).abs() < 1e-3, "{seconds}");
}

// "Rnd function": 0 <= Rnd < 1; a negative number gives the same number every time, zero the
// most recent one. "Randomize statement": "To repeat sequences of random numbers, call Rnd with
// a negative argument immediately before using Randomize with a numeric argument. Using
// Randomize with the same value for number does not repeat the previous sequence." A fresh
// session's first Rnd is 0.7055475 (KB 231847's generator from 327680), printed as a Single.
#[test]
fn rnd_is_vbas_generator_and_rnd_minus_one_with_randomize_repeats_it() {
    let out = printed(
        "    Debug.Print Rnd\n\
         \x20   Rnd -1: Randomize 42: a = Rnd: b = Rnd()\n    Rnd -1: Randomize 42\n    c = Rnd: d = Rnd(1)\n\
         \x20   Debug.Print a = c; b = d; a <> b; a >= 0 And a < 1; Rnd(-3) = Rnd(-3); Rnd(0) = Rnd(0)\n\
         \x20   Randomize 42: e = Rnd\n    Randomize 42: Debug.Print e = Rnd",
    );
    assert_eq!(out, [" 0.7055475 ", "TrueTrueTrueTrueTrueTrue", "False"]);
}

// "Erase statement": a fixed-size array's items go back to their defaults (0, "", Empty).
#[test]
fn erase_resets_the_items() {
    let out = printed(
        "    Dim a(1 To 3) As Long, s(2) As String\n    a(2) = 7: s(1) = \"x\"\n    Erase a, s\n\
         \x20   Debug.Print a(2); UBound(a); Len(s(1))",
    );
    assert_eq!(out, [" 0  3  0 "]);
}

// "ChrW function": the character of a Unicode code; "LenB function": bytes (two per
// character of VBA's UTF-16 strings); "StrConv function": vbUpperCase 1, vbLowerCase 2,
// vbProperCase 3 (the first letter of every word a capital).
#[test]
fn chrw_lenb_and_strconv() {
    assert_eq!(value("ChrW(8960) & ChrW$(65)"), Value::text("\u{2300}A"));
    assert_eq!(value("ChrW(-1) = ChrW(65535)"), Value::Bool(true));
    assert_eq!(value("LenB(\"abc\")"), n(6.0));
    assert_eq!(value("StrConv(\"fACE mill\", vbProperCase)"), Value::text("Face Mill"));
    assert_eq!(value("StrConv(\"g-code\", vbUpperCase)"), Value::text("G-CODE"));
    assert_eq!(value("StrConv(\"M30\", 2)"), Value::text("m30"));
}

// "Stop statement": VBA suspends execution for its debugger. ncsheet has none: the macro
// stops there with a message that says so, which On Error does not trap.
#[test]
fn stop_stops_the_macro_with_its_line() {
    let e = failure(
        "Sub Main()\n    On Error Resume Next\n    Debug.Print \"a\"\n    Stop\n    Debug.Print \"b\"\nEnd Sub\n",
    );
    assert!(e.message.contains("Stop statement at line 4"), "{e}");
    assert_eq!((e.span.unwrap().line, e.span.unwrap().col), (4, 5));
    assert_eq!(e.output.printed, ["a"]);
}

// "Val function": &H and &O prefixes read hexadecimal and octal ("Val("&HFFFF")" is -1:
// four hex digits are an Integer); "Format function": `>` writes capitals, `<` small letters.
#[test]
fn val_reads_hex_and_octal_and_format_changes_case() {
    assert_eq!(value("Val(\"&HFF\")"), n(255.0));
    assert_eq!(value("Val(\"&O17\")"), n(15.0));
    assert_eq!(value("Val(\"&HFFFF\")"), n(-1.0));
    assert_eq!(value("Val(\"&H10000\")"), n(65536.0));
    assert_eq!(value("Format(\"g01 x1\", \">\")"), Value::text("G01 X1"));
    assert_eq!(value("Format(\"ABC\", \"<\")"), Value::text("abc"));
}

// "Data type summary": an Integer holds -32,768 to 32,767, a Long -2,147,483,648 to
// 2,147,483,647, a Byte 0 to 255; more is run-time error 6, Overflow, which On Error traps.
#[test]
fn integer_overflow_is_error_6() {
    let e = failure("Sub Main()\n    Dim i As Integer\n    i = 32767\n    i = i + 1\nEnd Sub\n");
    assert!(e.message.contains("overflow"), "{e}");
    assert_eq!(e.span.unwrap().line, 4);
    let out = printed(
        "    Dim i As Integer, l As Long, b As Byte\n    On Error Resume Next\n    i = 40000\n    Debug.Print Err.Number; i\n\
         \x20   Err.Clear\n    l = 40000: Debug.Print Err.Number; l\n    b = 256\n    Debug.Print Err.Number; b",
    );
    assert_eq!(out, [" 6  0 ", " 0  40000 ", " 6  0 "]);
}

// "Function statement": `As type` may name a user-defined type; the Function's value is
// a copy of the record its name holds ([MS-VBAL] 5.4.3.8, Let of a UDT copies each field).
#[test]
fn a_function_returns_a_user_defined_type() {
    let src = "Type Point\n    X As Double\n    Z As Double\nEnd Type\n\
               Function MakePoint(x, z) As Point\n    Dim p As Point\n    p.X = x: p.Z = z\n    MakePoint = p\nEnd Function\n\
               Function Shifted(x) As Point\n    Shifted.X = x + 1\n    Shifted.Z = -1\nEnd Function\n\
               Sub Main()\n    Dim a As Point, b As Point\n    a = MakePoint(2, -3)\n    b = Shifted(a.X)\n\
               \x20   a.X = 10\n    Debug.Print a.X; a.Z; b.X; b.Z\nEnd Sub\n";
    assert_eq!(run(src).printed, [" 10 -3  3 -1 "]);
}

// "Range.Value property": a range of more than one cell gives a two-dimensional array, a
// single row too: Range("A1:C1").Value is (1 To 1, 1 To 3).
#[test]
fn a_one_row_range_value_is_two_dimensional() {
    let out = printed(
        "    Range(\"A1\").Value = 5: Range(\"C1\").Value = \"z\"\n    Dim v\n    v = Range(\"A1:C1\").Value\n\
         \x20   Debug.Print LBound(v, 1); UBound(v, 1); LBound(v, 2); UBound(v, 2); v(1, 1); v(1, 3)",
    );
    assert_eq!(out, [" 1  1  1  3  5 z"]);
}

// "Collection object", "Add method (Collection)", "Item method", "Remove method": Add item,
// key, before, after (positions from 1; Before:=1 puts the item first, After:=n after the
// n-th); a key picks the item whatever its case; Item is the default member (`c(1)`,
// `c("k")`); Remove takes a position or a key; For Each goes through the items in order.
#[test]
fn collection_add_item_remove_and_for_each() {
    let out = printed(
        "    Dim c As New Collection\n    c.Add \"a\"\n    c.Add \"b\", \"kb\"\n    c.Add \"first\", Before:=1\n\
         \x20   c.Add \"z\", \"KZ\", After:=3\n    Debug.Print c.Count; c(1); c.Item(2); c(\"KB\"); c(4); c.Item(\"kz\")\n\
         \x20   c.Remove \"kb\"\n    c.Remove 1\n    s = \"\"\n    For Each x In c\n        s = s & x & \",\"\n    Next\n\
         \x20   Debug.Print s; c.Count",
    );
    assert_eq!(out, [" 4 firstabzz", "a,z, 2 "]);
}

// "Add method (Collection)": a key already used is run-time error 457 ("This key is already
// associated with an element of this collection"); "Item method (Collection)": a position
// outside 1 to Count is error 9, "Subscript out of range", and a key no item has is error 5,
// "Invalid procedure call or argument" (keys ignore case, so "K" is "k"); Remove likewise.
#[test]
fn collection_errors_have_vba_numbers() {
    let out = printed(
        "    Dim c As Collection\n    Set c = New Collection\n    c.Add 1, \"k\"\n    On Error Resume Next\n\
         \x20   c.Add 2, \"K\"\n    Debug.Print Err.Number; c.Count\n    Err.Clear\n    x = c(5)\n    Debug.Print Err.Number\n\
         \x20   Err.Clear\n    x = c(\"nokey\")\n    Debug.Print Err.Number\n    Err.Clear\n    c.Remove 0\n\
         \x20   Debug.Print Err.Number; c.Count\n    Err.Clear\n    c.Remove \"other\"\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 457  1 ", " 9 ", " 5 ", " 9  1 ", " 5 "]);
}

// "Dictionary object" with "Add method (Dictionary)", "Item property (Dictionary object)":
// `d(k) = v` replaces the item of a key or adds the key; reading a key not there adds it
// with its item left Empty; "Keys method" and "Items method" give zero-based arrays in the
// order added; "Exists method"; "Remove method" and "RemoveAll method"; For Each goes
// through the keys. Keys compare in binary (case counts) by default, and 1 and "1" are two keys.
#[test]
fn dictionary_members() {
    let out = printed(
        "    Dim d As Object\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    d.Add \"a\", \"Athens\"\n\
         \x20   d.Add \"b\", \"Belgrade\"\n    d(\"c\") = \"Cairo\"\n    d(\"a\") = \"Ankara\"\n\
         \x20   Debug.Print d.Count; d(\"a\"); d.Item(\"c\")\n    Debug.Print d.Exists(\"b\"); d.Exists(\"B\")\n\
         \x20   k = d.Keys\n    its = d.Items\n    Debug.Print LBound(k); UBound(k); k(0); its(2)\n\
         \x20   x = d(\"missing\")\n    Debug.Print d.Count; IsEmpty(d(\"missing\"))\n    d.Remove \"b\"\n    s = \"\"\n\
         \x20   For Each key In d\n        s = s & key & \"=\" & d(key) & \";\"\n    Next\n    Debug.Print s\n\
         \x20   d(1) = \"one\"\n    d(\"1\") = \"text one\"\n    Debug.Print d.Count; d(1)\n    d.RemoveAll\n    Debug.Print d.Count",
    );
    assert_eq!(
        out,
        [" 3 AnkaraCairo", "TrueFalse", " 0  2 aCairo", " 4 True", "a=Ankara;c=Cairo;missing=;", " 5 one", " 0 "]
    );
}

// "Add method (Dictionary)": an existing key is error 457; "Remove method (Dictionary)":
// "An error occurs if the specified key/item pair does not exist" (32811 in Scripting);
// "CompareMode property": vbTextCompare makes "KEY" find "Key", and changing the mode of a
// Dictionary that holds data is an error (5).
#[test]
fn dictionary_errors_and_compare_mode() {
    let out = printed(
        "    Set d = CreateObject(\"Scripting.Dictionary\")\n    Debug.Print d.CompareMode\n    d.Add \"Key\", 1\n\
         \x20   On Error Resume Next\n    d.Add \"Key\", 2\n    Debug.Print Err.Number; d(\"Key\")\n    Err.Clear\n\
         \x20   d.Remove \"nothing here\"\n    Debug.Print Err.Number\n    Err.Clear\n    d.CompareMode = vbTextCompare\n\
         \x20   Debug.Print Err.Number; d.Exists(\"KEY\")\n    Err.Clear\n    Set t = CreateObject(\"scripting.dictionary\")\n\
         \x20   t.CompareMode = vbTextCompare\n    t.Add \"Key\", 1\n    t.Add \"KEY\", 2\n    Debug.Print Err.Number; t.Exists(\"kEy\"); t.CompareMode",
    );
    assert_eq!(out, [" 0 ", " 457  1 ", " 32811 ", " 5 False", " 457 True 1 "]);
}

// "Set statement": Set makes the variable refer to the object, no copy: both names see one
// Collection or Dictionary; `Set` to a `New` object starts another.
#[test]
fn collections_and_dictionaries_are_shared_by_set() {
    let out = printed(
        "    Set d = CreateObject(\"Scripting.Dictionary\")\n    Set d2 = d\n    d2(\"x\") = 5\n    Debug.Print d.Count; d(\"x\")\n\
         \x20   Dim c As New Collection, c2 As Collection\n    Set c2 = c\n    c2.Add 7\n    Debug.Print c.Count; c(1)\n\
         \x20   Set c2 = New Collection\n    Debug.Print c.Count; c2.Count; c Is c2\n\
         \x20   Set d(\"list\") = New Collection\n    d(\"list\").Add 3\n    d(\"list\").Add 4\n\
         \x20   Set l = d(\"list\")\n    l.Add 5\n    s = 0\n    For Each v In d(\"list\")\n        s = s + v\n    Next\n\
         \x20   Debug.Print d(\"list\").Count; s; d(\"list\").Item(3)",
    );
    assert_eq!(out, [" 1  5 ", " 1  7 ", " 1  0 False", " 3  12  5 "]);
}

// The macro memory budget counts what Collections and Dictionaries hold as it counts arrays.
#[test]
fn collection_items_count_against_the_memory_budget() {
    let src = "Sub Main()\n    Dim c As New Collection\n    For i = 1 To 1000\n        c.Add Space(1000000)\n    Next\nEnd Sub\n";
    let options = RunOptions { max_memory: 64 << 20, ..RunOptions::default() };
    let e = run_with(src, &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    let src = "Sub Main()\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    For i = 1 To 1000\n\
               \x20       d(i) = Space(1000000)\n    Next\nEnd Sub\n";
    let e = run_with(src, &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
}

// "Keys method": "The following code illustrates use of the Keys method" with a loop
// `For i = 0 To d.Count - 1`: the array is zero-based, under Option Base 1 too.
#[test]
fn dictionary_keys_are_zero_based_under_option_base_1() {
    let src = "Option Base 1\nSub Main()\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    d(\"a\") = 1: d(\"b\") = 2\n\
               \x20   k = d.Keys\n    its = d.Items()\n    Debug.Print LBound(k); UBound(k); k(0); LBound(its); its(1)\nEnd Sub\n";
    assert_eq!(run(src).printed, [" 0  1 a 0  2 "]);
}

// CreateObject makes Scripting.Dictionary and nothing else: a file system object stays refused.
#[test]
fn create_object_of_another_class_is_refused() {
    let e = failure("Sub Main()\n    Set f = CreateObject(\"Scripting.FileSystemObject\")\nEnd Sub\n");
    assert!(e.message.contains("file access needs a folder"), "{e}");
    let e = failure("Sub Main()\n    Set f = New Class1\nEnd Sub\n");
    assert!(e.message.contains("New Class1"), "{e}");
}

// ---- class modules --------------------------------------------------------------------

/// A macro run with the project's class modules (name, source), as `run` gives them.
fn with_classes(main: &str, classes: &[(&str, &str)]) -> Result<RunOutput, MacroError> {
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    run_with(main, &RunOptions { classes, ..RunOptions::default() })
}

/// A class module as the VBA editor stores it: its attributes, a private count, a public
/// variable, a Sub, a Property Get/Let pair and a Function calling its own Property Get.
const COUNTER: &str = "Attribute VB_Name = \"Counter\"\nAttribute VB_PredeclaredId = False\nOption Explicit\n\
    Private n As Long\nPublic Label As String\n\
    Public Sub Add(Optional amount As Long = 1)\n    n = n + amount\nEnd Sub\n\
    Public Property Get Count() As Long\n    Count = n\nEnd Property\n\
    Public Property Let Count(v As Long)\n    If v < 0 Then Exit Property\n    n = v\nEnd Property\n\
    Public Function Twice() As Long\n    Twice = 2 * Count\nEnd Function\n";

// "Writing a property procedure", "Property Get statement", "Property Let statement" and
// "Dim statement" (`New` "enables implicit creation of an object"): each object made by New
// has its own copy of the class module's variables; its public Subs, Functions, properties
// and Public variables are its members ([MS-VBAL] 5.2.4.1, class modules).
#[test]
fn each_object_of_a_class_has_its_own_variables_and_members() {
    let main = "Sub Main()\n    Dim a As New Counter, b As Counter\n    Set b = New Counter\n    a.Add\n    a.Add 5\n\
                \x20   b.Count = 10\n    b.Count = -1\n    b.Label = \"b\"\n    Debug.Print a.Count; b.Count; a.Twice(); b.Label\nEnd Sub\n";
    assert_eq!(with_classes(main, &[("Counter", COUNTER)]).unwrap().printed, [" 6  10  12 b"]);
}

// "Set statement": "Set … creates a reference to the object …; two or more object variables
// can refer to the same object", and a change through one is seen through the others (by
// a procedure given the object too); "Is operator" compares the references.
#[test]
fn set_shares_one_object_and_is_compares_the_references() {
    let main = "Sub Bump(c As Counter)\n    c.Add 10\nEnd Sub\n\
                Function Made(start) As Counter\n    Set Made = New Counter\n    Made.Count = start\nEnd Function\n\
                Sub Main()\n    Dim a As Counter, b As Counter, c As Counter\n    Set a = New Counter\n    Set b = a\n\
                \x20   b.Add 3\n    Bump a\n    Debug.Print a.Count\n    Debug.Print a Is b\n    Debug.Print a Is c\n\
                \x20   Debug.Print c Is Nothing\n    Set c = Made(7)\n    Debug.Print c.Count\n    Debug.Print a Is c\nEnd Sub\n";
    let out = with_classes(main, &[("Counter", COUNTER)]).unwrap();
    assert_eq!(out.printed, [" 13 ", "True", "False", "True", " 7 ", "False"]);
}

// "Me keyword": "The Me keyword behaves like an implicitly declared variable … the instance
// of the class where the code is running"; objects go into Collections and Dictionaries by
// reference ("Add method", "Item property"), and `Property Set` assigns an object.
#[test]
fn me_property_set_and_objects_in_collections() {
    let node = "Public Value As Double\nPrivate mOwner As Object\n\
                Public Function Self() As Object\n    Set Self = Me\nEnd Function\n\
                Public Sub AddTo(c As Collection)\n    c.Add Me\nEnd Sub\n\
                Public Property Set Owner(o As Object)\n    Set mOwner = o\nEnd Property\n\
                Public Property Get Owner() As Object\n    Set Owner = mOwner\nEnd Property\n";
    let main = "Sub Main()\n    Dim c As New Collection, n As Node, i As Long, total As Double\n    For i = 1 To 3\n\
                \x20       Set n = New Node\n        n.Value = i * 1.5\n        n.AddTo c\n    Next\n\
                \x20   For Each x In c\n        total = total + x.Value\n    Next\n    Debug.Print c.Count; total\n\
                \x20   Debug.Print n.Self() Is n\n    Debug.Print c(1) Is n\n\
                \x20   Set d = CreateObject(\"Scripting.Dictionary\")\n    Set c(2).Owner = n\n    d.Add \"k\", c(2)\n\
                \x20   Debug.Print d(\"k\").Owner.Value\n    Debug.Print d(\"k\").Owner Is c(3)\nEnd Sub\n";
    let out = with_classes(main, &[("Node", node)]).unwrap();
    assert_eq!(out.printed, [" 3  9 ", "True", "False", " 4.5 ", "True"]);
}

// "Initialize event": it "occurs when an instance of the class is created"; "Terminate
// event": it "occurs when all references to an instance of an object are removed from
// memory by setting all the variables that refer to the object to Nothing or when the last
// reference to the object goes out of scope".
#[test]
fn class_initialize_and_terminate_run_at_the_first_and_last_reference() {
    let probe = "Private Sub Class_Initialize()\n    Debug.Print \"init\"\nEnd Sub\n\
                 Private Sub Class_Terminate()\n    Debug.Print \"term\"\nEnd Sub\n";
    let main = "Sub Use()\n    Dim p As Probe\n    Set p = New Probe\n    Debug.Print \"using\"\nEnd Sub\n\
                Sub Main()\n    Dim a As Probe, b As Probe\n    Set a = New Probe\n    Set b = a\n    Set a = Nothing\n\
                \x20   Debug.Print \"b holds it\"\n    Set b = Nothing\n    Use\n    Debug.Print \"end\"\nEnd Sub\n";
    let out = with_classes(main, &[("Probe", probe)]).unwrap();
    assert_eq!(out.printed, ["init", "b holds it", "term", "init", "using", "term", "end"]);
}

// "Object variable or With block variable not set (Error 91)" for a member of a variable
// that holds no object; "Object doesn't support this property or method (Error 438)" for a
// member its class has not, a Private one too.
#[test]
fn members_of_nothing_and_members_a_class_has_not_are_errors_91_and_438() {
    let main = "Sub Main()\n    Dim c As Counter\n    On Error Resume Next\n    c.Add\n    Debug.Print Err.Number\n\
                \x20   Err.Clear\n    Set c = New Counter\n    c.Missing\n    Debug.Print Err.Number\n    Err.Clear\n\
                \x20   x = c.n\n    Debug.Print Err.Number\nEnd Sub\n";
    let out = with_classes(main, &[("Counter", COUNTER)]).unwrap();
    assert_eq!(out.printed, [" 91 ", " 438 ", " 438 "]);
    let e =
        with_classes("Sub Main()\n    Dim c As Counter\n    c.Add\nEnd Sub\n", &[("Counter", COUNTER)]).unwrap_err();
    assert!(e.message.contains("Object variable or With block variable not set"), "{e}");
    assert_eq!(e.span.unwrap().line, 3, "{e}");
}

// A class's procedures are members of its objects, not names of the project ("Understanding
// scope and visibility"): a standard module calling one by name does not compile.
#[test]
fn a_class_modules_procedures_are_not_names_of_the_project() {
    let e = with_classes("Sub Main()\n    Debug.Print Twice()\nEnd Sub\n", &[("Counter", COUNTER)]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Syntax, "{e}");
    assert!(e.message.contains("Twice"), "{e}");
}

// The objects count against the memory budget as Collections do, and a linked list of
// 100,000 of them is let go without taking the native stack.
#[test]
fn objects_count_against_the_memory_budget() {
    let link = "Public Text As String\nPublic Next_ As Object\n";
    let chain = "Sub Main()\n    Dim head As Object, n As Object\n    For i = 1 To 100000\n        Set n = New Link\n\
                 \x20       n.Text = Space(200)\n        Set n.Next_ = head\n        Set head = n\n    Next\nEnd Sub\n";
    let options =
        RunOptions { classes: vec![("Link".into(), link.into())], max_memory: 4 << 20, ..RunOptions::default() };
    let e = run_with(chain, &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    let options = RunOptions { max_memory: 256 << 20, ..options };
    run_with(chain, &options).unwrap_or_else(|e| panic!("{e}"));
}

// [MS-VBAL] 5.6.13 "Index Expressions": an index applies to the value a call or a default
// member gives, in the same expression. "Split function": Split gives a zero-based array, so
// `Split("a,b,c", ",")(1)` is "b"; a Dictionary's or a Collection's item that is an array
// is indexed as `d(k)(i)` and `d.Item(k)(i)`; a Function's array result as `F()(i)`, with
// the bounds the Function gave it ("Function statement": an array is returned by assigning
// the array to the name); `d.Keys()(0)` is the first key ("Keys method": a zero-based array).
#[test]
fn what_a_call_or_an_item_gives_is_indexed_in_the_same_expression() {
    let out = run("Option Base 1\nFunction Bounded()\n    Dim a(3 To 5)\n    a(3) = \"three\": a(5) = \"five\"\n\
                   \x20   Bounded = a\nEnd Function\nSub Main()\n    Set d = CreateObject(\"Scripting.Dictionary\")\n\
                   \x20   d.Add \"p\", Split(\"x,y,z\", \",\")\n    Debug.Print d(\"p\")(0); d.Item(\"p\")(2)\n\
                   \x20   Set c = New Collection\n    c.Add Split(\"u,v\", \",\")\n    Set inner = New Collection\n\
                   \x20   inner.Add \"first\": inner.Add \"second\"\n    c.Add inner\n    Debug.Print c(1)(1); c(2)(2); c.Item(2)(1)\n\
                   \x20   Debug.Print Split(\"a,b,c\", \",\")(1); Bounded()(5); Bounded()(3); d.Keys()(0)\n\
                   \x20   n = d(\"p\")(1) & \"!\"\n    Debug.Print n\nEnd Sub\n");
    assert_eq!(out.printed, ["xz", "vsecondfirst", "bfivethreep", "y!"]);
    // Past the bounds the Function gave: "Subscript out of range (Error 9)".
    let e = run_with(
        "Function Bounded()\n    Dim a(3 To 5)\n    Bounded = a\nEnd Function\nSub Main()\n    x = Bounded()(2)\nEnd Sub\n",
        &RunOptions::default(),
    )
    .unwrap_err();
    assert!(e.message.contains("run-time error 9"), "{e}");
}

// "Key property" (Scripting's Dictionary): `d.Key(key) = newkey` replaces a key, the item
// and its place kept (the reference's DicDemo: after d.Key("c") = "d", d.Item("d") is
// "Cairo"); a key not there is a run-time error, and a new key already there is error 457
// ("This key is already associated with an element of this collection").
#[test]
fn a_dictionary_key_is_renamed_in_place() {
    let out = run("Sub Main()\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    d.Add \"a\", \"Athens\"\n\
                   \x20   d.Add \"b\", \"Belgrade\"\n    d.Add \"c\", \"Cairo\"\n    d.Key(\"c\") = \"d\"\n\
                   \x20   Debug.Print d.Item(\"d\"); d.Exists(\"c\"); Join(d.Keys, \",\")\n    On Error Resume Next\n\
                   \x20   d.Key(\"a\") = \"b\"\n    Debug.Print Err.Number; d(\"a\")\n    Err.Clear\n\
                   \x20   d.Key(\"zz\") = \"y\"\n    Debug.Print Err.Number <> 0; d.Count\nEnd Sub\n");
    assert_eq!(out.printed, ["CairoFalsea,b,d", " 457 Athens", "True 3 "]);
}

// Scripting's Dictionary keeps a key as the Variant given and compares numbers by value: what
// Wine's scrrun tests check against Windows' own scrrun.dll (dlls/scrrun/tests/dictionary.c):
// `test_Exists`, the Integer 0 and the Single 0 are one key (the second Add fails,
// CTL_E_KEY_ALREADY_EXISTS, 457); `test_Add`, the Singles 2175 and 6259 are two keys and the
// Long 2175 is the first's; `test_Keys` and `test_IEnumVARIANT`, Keys and For Each give a key
// back with its type (VT_R4, VT_I4, VT_I2); `test_hash_value`, a LongLong (VT_I8) is refused
// with CTL_E_ILLEGALFUNCTIONCALL (5), Empty and Null are keys. A text key never matches a
// number ("1" and 1, `dictionary_members`); Null matches only Null.
#[test]
fn dictionary_keys_keep_their_type_and_numbers_match_by_value() {
    let out = printed(
        "    Set d = CreateObject(\"Scripting.Dictionary\")\n    On Error Resume Next\n    d.Add CInt(0), \"zero\"\n\
         \x20   d.Add CSng(0), \"again\"\n    Debug.Print Err.Number; d.Exists(CSng(0)); d.Count\n    Err.Clear\n\
         \x20   d.Add CSng(2175), 1\n    d.Add CSng(6259), 2\n    d.Add CLng(2175), 3\n    Debug.Print Err.Number; d.Count\n    Err.Clear\n\
         \x20   d.Add 5^, 4\n    Debug.Print Err.Number; d.Count\n    Err.Clear\n\
         \x20   d.Add Null, \"null\"\n    Debug.Print Err.Number; d.Exists(Null); d.Count\n\
         \x20   k = d.Keys\n    Debug.Print TypeName(k(0)); \" \"; TypeName(k(1)); \" \"; VarType(d.Keys()(3))\n\
         \x20   s = \"\"\n    For Each key In d\n        s = s & TypeName(key) & \";\"\n    Next\n    Debug.Print s",
    );
    assert_eq!(
        out,
        [" 457 True 1 ", " 457  3 ", " 5  3 ", " 0 True 4 ", "Integer Single  1 ", "Integer;Single;Single;Null;"]
    );
    // Wine's scrrun dictionary.c: `numeric_key_eq` compares two numbers as Singles (True is
    // -1), and `empty_matches_key` matches Empty with a numeric zero or "" both ways.
    let out = printed(
        "    Set d = CreateObject(\"Scripting.Dictionary\")\n    d.Add 1, \"one\"\n    d.Add True, \"true\"\n\
         \x20   Debug.Print d.Exists(1.00000001); d.Exists(1.001); d(-1)\n    d.Add Empty, \"empty\"\n\
         \x20   Debug.Print d.Exists(0); d.Exists(\"\"); d.Exists(False); d.Count\n    On Error Resume Next\n    d.Add 0#, 1\n\
         \x20   Debug.Print Err.Number",
    );
    assert_eq!(out, ["TrueFalsetrue", "TrueTrueTrue 3 ", " 457 "]);
}

// "Split function": the reference's example assigns Split's result to `Dim arrSplitStrings1()
// As String`, which only a `String()` can be ("Split function" returns a String array; so
// "TypeName function" gives "String()" and "VarType function" vbArray + vbString, 8200).
// [MS-VBAL] 5.4.3.1.2 (Let assignment to an array element): a Variant holding an array of a
// declared type (`v = a` with `Dim a() As Long`) holds that typed array, and an item Let
// into it is converted to the item type, "7" becoming the Long 7 and "abc" a type mismatch
// ("Trappable errors": 13).
#[test]
fn split_gives_a_string_array_and_a_typed_array_in_a_variant_converts_its_items() {
    let out = printed(
        "    s = Split(\"a,b\", \",\")\n    Debug.Print TypeName(s); VarType(s); TypeName(Filter(s, \"a\"))\n\
         \x20   Dim parts() As String\n    parts = Split(\"x y\")\n    Debug.Print UBound(parts); parts(1)\n\
         \x20   s(0) = 5\n    Debug.Print TypeName(s(0))\n\
         \x20   Dim a() As Long\n    ReDim a(2)\n    v = a\n    v(0) = \"7\"\n    Debug.Print TypeName(v); \" \"; TypeName(v(0)); v(0) + 1\n\
         \x20   On Error Resume Next\n    v(1) = \"abc\"\n    Debug.Print Err.Number",
    );
    assert_eq!(out, ["String() 8200 String()", " 1 y", "String", "Long() Long 8 ", " 13 "]);
}

// Objects as Dictionary keys ("Add method (Dictionary)": a key may be any type but an
// array) are not ncsheet's: its keys are values, and Keys gives them as an array of values.
// The macro is refused with the reason, not keyed by something else.
#[test]
fn an_object_as_a_dictionary_key_is_refused_with_the_reason() {
    for add in ["d.Add c, 1", "d(c) = 1", "x = d.Exists(c)", "d.Add New Collection, 1"] {
        let src = format!(
            "Sub Main()\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    Set c = New Collection\n    {add}\nEnd Sub\n"
        );
        let e = run_with(&src, &RunOptions::default()).unwrap_err();
        assert!(e.message.contains("cannot be a Dictionary key"), "{add}: {e}");
        assert_eq!(e.span.unwrap().line, 4, "{add}: {e}");
    }
}

// "TypeName function": the reference's examples (a String variable "String", an Integer
// "Integer", a Currency "Currency", an array of Integers "Integer()"), an object's class
// ("Collection", "Dictionary", "Range"), "Nothing" for an object variable that refers to no
// object and for Nothing itself, "Empty" for an unassigned Variant. "VarType function": an
// object is vbObject (9). "IsObject function": True for an object variable, Nothing included.
#[test]
fn typename_vartype_and_isobject_of_objects() {
    let out = run("Sub Main()\n    Dim StrVar As String, IntVar As Integer, CurVar As Currency, v\n\
                   \x20   Dim ArrayVar(1 To 5) As Integer\n    Set c = New Collection\n\
                   \x20   Set d = CreateObject(\"Scripting.Dictionary\")\n    Set x = c\n    Set x = Nothing\n\
                   \x20   Debug.Print TypeName(StrVar); \" \"; TypeName(IntVar); \" \"; TypeName(CurVar); \" \"; TypeName(ArrayVar)\n\
                   \x20   Debug.Print TypeName(c); \" \"; TypeName(d); \" \"; TypeName(Nothing); \" \"; TypeName(x); \" \"; TypeName(v)\n\
                   \x20   Debug.Print TypeName(Range(\"A1\")); \" \"; TypeName(5); \" \"; TypeName(2.5); \" \"; TypeName(\"s\")\n\
                   \x20   Debug.Print VarType(c); VarType(d); VarType(x) = vbObject\n\
                   \x20   Debug.Print IsObject(c); IsObject(d); IsObject(x); IsObject(v); IsObject(5); IsObject(Range(\"A1\"))\n\
                   End Sub\n");
    assert_eq!(
        out.printed,
        [
            "String Integer Currency Integer()",
            "Collection Dictionary Nothing Nothing Empty",
            "Range Integer Double String",
            " 9  9 True",
            "TrueTrueTrueFalseFalseTrue",
        ]
    );
}

// [MS-VBAL] 5.6.9.3 "Arithmetic Operators": `+ - * \ Mod` on two Integer operands have the
// declared type Integer (Byte on two Bytes, Long when one is a Long), and a result past the
// type's range is run-time error 6, whatever the variable it goes to; a Variant operand
// makes the operation a Variant's, which widens. "Overflow (Error 6)": `x = 2000 * 365` in a
// Long is an overflow (two Integer literals), `CLng(2000) * 365` is not.
#[test]
fn integer_arithmetic_overflows_in_its_declared_type() {
    let overflow = |body: &str| {
        let src = format!("Sub Main()\n    Dim a As Integer, l As Long, y As Byte, x As Long, b\n{body}\nEnd Sub\n");
        let e = run_with(&src, &RunOptions::default()).unwrap_err();
        assert!(e.message.contains("Overflow (run-time error 6)"), "{body}: {e}");
    };
    overflow("    x = 2000 * 365");
    overflow("    a = 200: b = a * 200");
    overflow("    l = 50000: b = l * l");
    overflow("    y = 200: b = y + y");
    overflow("    a = 32767: b = a + 1");
    overflow("    b = 3000000000# \\ 2");
    overflow("    b = 3000000000# Mod 7");
    let out = run("Sub Main()\n    Dim a As Integer, l As Long, y As Byte, x As Long, d As Double\n\
                   \x20   x = CLng(2000) * 365\n    a = 200: l = 200: y = 200: d = 200: v = 200\n\
                   \x20   Debug.Print x; a * l; y + 100; d * 200; v * 200; a / 3 > 66; a * 2.5; a \\ 7; a Mod 7\n\
                   \x20   On Error Resume Next\n    b = a * 200\n    Debug.Print Err.Number; IsEmpty(b)\nEnd Sub\n");
    assert_eq!(out.printed, [" 730000  40000  300  40000  40000 True 500  28  4 ", " 6 True"]);
}

// [MS-VBAL] 5.6.8 "New Expressions": `New class-name` is an expression (classified as a
// value, the new object), so it is an argument too: `Fill New Collection` passes a new Collection to the Sub, and
// `Set c = Filled(New Collection)` sets c to the one the Function filled and returned.
#[test]
fn new_is_an_expression_an_argument_too() {
    let out = run("Sub Fill(c)\n    c.Add \"one\"\nEnd Sub\nFunction Filled(c)\n    c.Add \"two\"\n    Set Filled = c\n\
                   End Function\nFunction CountOf(c)\n    CountOf = c.Count\nEnd Function\nSub Main()\n    Fill New Collection\n\
                   \x20   Call Fill(New Collection)\n    Debug.Print CountOf(New Collection)\n    Set c = Filled(New Collection)\n\
                   \x20   Debug.Print TypeName(c); c.Count; c(1)\nEnd Sub\n");
    assert_eq!(out.printed, [" 0 ", "Collection 1 two"]);
}

// ---- Null -------------------------------------------------------------------------------

// "IsNull function": "Expressions that you might expect to evaluate to True …, such as If
// Var = Null and If Var <> Null, are always False. This is because any expression containing
// a Null is itself Null and, therefore, False": arithmetic, negation, Not and comparisons
// with Null are Null, `Null = Null` too, and `If` takes Null as False.
#[test]
fn null_propagates_through_arithmetic_and_comparisons() {
    let out = printed(
        "    x = Null\n    Debug.Print x + 1\n    Debug.Print x = x\n    Debug.Print IsNull(x * 2); IsNull(x = 1); IsNull(1 < x)\n\
         \x20   Debug.Print IsNull(y); IsNull(\"\")\n    If x = Null Then Debug.Print \"equal\" Else Debug.Print \"not true\"\n\
         \x20   If Not x Then Debug.Print \"not\" Else Debug.Print \"Not Null is Null\"\n    Debug.Print -x\n\
         \x20   Select Case x\n        Case Null: Debug.Print \"case\"\n        Case Else: Debug.Print \"else\"\n    End Select",
    );
    assert_eq!(out, ["Null", "Null", "TrueTrueTrue", "FalseFalse", "not true", "Not Null is Null", "Null", "else"]);
}

// "& operator": "If both expressions are Null, result is Null. However, if only one
// expression is Null, that expression is treated as a zero-length string"; the "And
// operator", "Or operator", "Xor operator" and "Imp operator" pages' tables for Null.
#[test]
fn null_in_concatenation_and_logic() {
    let out = printed(
        "    Debug.Print \"a\" & Null & \"b\"\n    Debug.Print IsNull(Null & Null)\n\
         \x20   Debug.Print Null And False; IsNull(Null And True); Null Or True; IsNull(Null Or False)\n\
         \x20   Debug.Print False Imp Null; IsNull(True Imp Null); Null Imp True; IsNull(Null Xor True)",
    );
    assert_eq!(out, ["ab", "True", "FalseTrueTrueTrue", "TrueTrueTrueTrue"]);
}

// "Invalid use of Null (Error 94)": Null assigned to a variable that is not a Variant; a
// Variant holds it ("VarType function": vbNull is 1).
#[test]
fn null_into_a_typed_variable_is_error_94() {
    let out = printed(
        "    Dim n As Long, s As String, v\n    On Error Resume Next\n    n = Null\n    Debug.Print Err.Number\n\
         \x20   Err.Clear\n    s = Null\n    Debug.Print Err.Number\n    v = Null\n    Debug.Print IsNull(v); VarType(v)",
    );
    assert_eq!(out, [" 94 ", " 94 ", "True 1 "]);
    let e = failure("Sub Main()\n    Dim d As Double\n    d = Null\nEnd Sub\n");
    assert!(e.message.contains("Invalid use of Null"), "{e}");
}

// [MS-VBAL] 6.1.2, the Strings module's Chr: "If the argument is not in the range 0 to 255,
// Error Number 5 ("Invalid procedure call or argument") is raised unless the implementation
// supports a character set with a larger code point range"; 128 to 255 are the code page's,
// Windows-1252 in a Western Excel ("Character set (128-255)": 128 is €, 150 the en dash).
// Asc is its inverse in that code page ("Asc function").
#[test]
fn chr_takes_codes_0_to_255_of_the_code_page() {
    assert_eq!(value("Chr(65) & Chr$(176)"), Value::text("A\u{b0}"));
    assert_eq!(value("Chr(128) = ChrW(8364)"), Value::Bool(true));
    assert_eq!(value("Chr(150) = ChrW(8211)"), Value::Bool(true));
    assert_eq!(value("Asc(Chr(128))"), n(128.0));
    assert_eq!(value("Asc(ChrW(8211))"), n(150.0));
    for code in ["256", "300", "8364"] {
        let out = run(&format!(
            "Sub Main()\n    Dim v\n    v = \"kept\"\n    On Error Resume Next\n    v = Chr({code})\n\
             \x20   Debug.Print Err.Number; v\nEnd Sub\n"
        ));
        assert_eq!(out.printed, [" 5 kept"], "Chr({code})");
    }
}

// [MS-VBAL] 5.4.2.4 "For Each Statement": the bound variable is Let-assigned each element
// of the array in turn, so a Variant bound variable holds each item with its subtype: the
// items of a Date array, and the Dates a Variant array or a Collection holds, are Dates
// (TypeName "Date", VarType 7, shown as dates).
#[test]
fn for_each_over_dates_gives_dates() {
    let out = run("Sub Main()\n    Dim d(1 To 2) As Date, v(1), c As New Collection, x, s\n\
                   \x20   d(1) = #1/2/2020#: d(2) = #3/4/2021#\n    v(0) = #5/6/2022#: v(1) = \"t\"\n\
                   \x20   c.Add #7/8/2023#\n    For Each x In d\n        s = s & TypeName(x) & \" \" & x & \";\"\n    Next\n\
                   \x20   For Each x In v\n        s = s & VarType(x) & \";\"\n    Next\n\
                   \x20   For Each x In c\n        s = s & TypeName(x) & \" \" & x\n    Next\n    Debug.Print s\nEnd Sub\n");
    assert_eq!(out.printed, ["Date 1/2/2020;Date 3/4/2021;7;8;Date 7/8/2023"]);
}

// ---- numbers in Variants ----------------------------------------------------------------

/// The lines `Sub Main` with `body` prints, after the module-level `module`.
fn printed_in(module: &str, body: &str) -> Vec<String> {
    run(&format!("{module}\nSub Main()\n{body}\nEnd Sub\n")).printed
}

// [MS-VBAL] 3.3.2 "Number Tokens": a whole decimal literal's declared type is Integer if it
// fits -32,768 to 32,767, else Long if it fits, else Double; a type character says it (`&`
// Long, `^` LongLong, `#` Double, `!` Single, `@` Currency). "Variant data type": "numeric
// Variant data is maintained in its original data type within the Variant", so `x = 5`
// holds an Integer ("TypeName function", "VarType function": vbInteger 2, vbLong 3,
// vbSingle 4, vbDouble 5, vbCurrency 6, vbLongLong 20).
#[test]
fn a_variant_holds_a_literal_with_its_declared_type() {
    let out = printed_in(
        "",
        "    Dim a, b, c, d, e, f, g, h, k\n    a = 5: b = 40000: c = 3000000000#: d = 2.5: e = 5&\n\
         \x20   f = 5^: g = 5!: h = 5@: k = 3000000000\n\
         \x20   Debug.Print TypeName(a); \" \"; TypeName(b); \" \"; TypeName(c); \" \"; TypeName(d); \" \"; TypeName(e)\n\
         \x20   Debug.Print TypeName(f); \" \"; TypeName(g); \" \"; TypeName(h); \" \"; TypeName(k); \" \"; TypeName(&HFF)\n\
         \x20   Debug.Print VarType(a); VarType(b); VarType(c); VarType(e); VarType(f); VarType(g); VarType(h)\n\
         \x20   Debug.Print TypeName(-32768); \" \"; TypeName(-32767 - 1); \" \"; TypeName(32767 + 0)",
    );
    assert_eq!(
        out,
        [
            "Integer Long Double Double Long",
            "LongLong Single Currency Double Integer",
            " 2  3  5  3  20  4  6 ",
            // Eric Lippert's VBScript quiz, part two (VB6 agrees): -32768 is the negation of
            // the Long 32768; -32767 - 1 is an Integer minus an Integer.
            "Long Integer Integer",
        ]
    );
}

// [MS-VBAL] 5.6.9.3 "Arithmetic Operators": `+ - *` on two Integers are an Integer, an Integer
// and a Long a Long, a Double with either a Double; 5.6.9.3.5 `/` is a Double, 5.6.9.3.8 `^` a
// Double, 5.6.9.3.6-7 `\` and `Mod` an Integer on Integers and a Long beside a Double. "Variant
// data type": a Variant's Byte, Integer, Long or Single result past its type's range "is
// promoted within the Variant to the next larger data type": Byte to Integer, Integer to
// Long, Long to Double; a declared Integer still overflows (run-time error 6).
#[test]
fn variant_arithmetic_keeps_integer_types_and_widens_past_their_range() {
    let out = printed_in(
        "",
        "    Dim x, y, l, t As Byte, b, z\n    x = 200: l = 2147483647: t = 200: b = t\n\
         \x20   y = x * 200\n    Debug.Print TypeName(x + 1); \" \"; TypeName(y); y; TypeName(l + 1); l + 1\n\
         \x20   Debug.Print TypeName(x / 2); \" \"; TypeName(x \\ 3); \" \"; TypeName(x Mod 3); \" \"; TypeName(x ^ 2)\n\
         \x20   Debug.Print TypeName(b); \" \"; TypeName(b + b); b + b; TypeName(x + 0.5); \" \"; TypeName(2.5 \\ 1)\n\
         \x20   z = 32767: z = z + 1\n    Debug.Print TypeName(z); z; TypeName(-x); \" \"; TypeName(x + 1&); \" \"; TypeName(True + 1)\n\
         \x20   z = -32768: z = -z\n    Debug.Print TypeName(z); z; TypeName(Empty + 1); \" \"; TypeName(\"2\" + 1)",
    );
    assert_eq!(
        out,
        [
            "Integer Long 40000 Double 2147483648 ",
            "Double Integer Integer Double",
            "Byte Integer 400 Double Long",
            "Long 32768 Integer Long Integer",
            "Long 32768 Integer Double",
        ]
    );
    let declared = "Sub Main()\n    Dim a As Integer\n    a = 200\n    v = a * 200\nEnd Sub\n";
    let e = run_with(declared, &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("Overflow (run-time error 6)"), "{e}");
}

// [MS-VBAL] 5.3.1.11: an array passed ByRef is the caller's variable itself, so an error
// binding another parameter ("Overflow (Error 6)": 40000 to an Integer) or assigning an item
// a value its type cannot hold ("Type mismatch (Error 13)") leaves the caller its array, with
// its bounds and what it held, after On Error Resume Next.
#[test]
fn an_array_passed_by_reference_stays_the_callers_when_the_call_fails() {
    let module = "Sub S(n As Integer, x() As Long)\n    x(1) = 7\nEnd Sub\n\
                  Sub V(x)\n    x(2) = \"abc\"\nEnd Sub\n";
    let out = printed_in(
        module,
        "    Dim a(1 To 2) As Long\n    a(1) = 5\n    On Error Resume Next\n    S 40000, a\n\
         \x20   Debug.Print Err.Number; TypeName(a); a(1)\n    Err.Clear\n    V a\n\
         \x20   Debug.Print Err.Number; TypeName(a); UBound(a); a(1)",
    );
    assert_eq!(out, [" 6 Long() 5 ", " 13 Long() 2  5 "]);
}

// [MS-VBAL] 5.3.1.11: a Variant parameter is bound to the argument's value with its value
// type, and a ByRef one gives back what the procedure made of it; 5.3.1.2: a Function's
// result is what its name was assigned. "Type conversion functions": CInt gives an Integer,
// CLng a Long, CLngLng a LongLong, CDbl a Double. A whole number's type changes none of its
// text (CStr, Str, Format) or comparisons.
#[test]
fn a_number_keeps_its_type_through_calls_and_conversions() {
    let module = "Function Seven()\n    Seven = 7\nEnd Function\n\
                  Function Kind(p)\n    Kind = TypeName(p)\nEnd Function\nSub Twice(ByRef p)\n    p = p * 2\nEnd Sub\n";
    let out = printed_in(
        module,
        "    Dim v, w\n    v = Seven()\n    w = 20000\n    Twice w\n\
         \x20   Debug.Print TypeName(Seven()); \" \"; TypeName(v); \" \"; Kind(5); \" \"; Kind(v + 70000); \" \"; Kind(1.5); \" \"; TypeName(w); w\n\
         \x20   Debug.Print TypeName(CInt(2.5)); \" \"; TypeName(CLng(2)); \" \"; TypeName(CLngLng(2)); \" \"; TypeName(CDbl(2)); \" \"; VarType(CLng(2))\n\
         \x20   v = 5\n    Debug.Print CStr(v); \"|\"; Str(v); \"|\"; Format(v); \"|\"; v = 5#; \"|\"; v < 5.5; \"|\"; IsNumeric(v)\n\
         \x20   v = CLng(5): w = v: Debug.Print TypeName(w); \" \"; TypeName(Abs(-v)); \" \"; TypeName(Int(2.5))",
    );
    assert_eq!(
        out,
        [
            "Integer Integer Integer Long Double Long 40000 ",
            "Integer Long LongLong Double  3 ",
            "5| 5|5|True|True|True",
            "Long Long Double",
        ]
    );
}

// "Type conversion functions": CByte gives a Byte (0 to 255), CSng a Single (±3.402823E38),
// CCur a Currency (four decimal places, ±922,337,203,685,477.5807); a value past the type's
// range is run-time error 6, Overflow ("VarType function": vbSingle 4, vbCurrency 6, vbByte 17).
#[test]
fn cbyte_csng_and_ccur_give_their_types() {
    let out = printed_in(
        "",
        "    Dim v\n    v = CByte(200.5)\n\
         \x20   Debug.Print TypeName(v); v; TypeName(CSng(1.5)); CSng(1.5); TypeName(CCur(1.23456)); CCur(1.23456)\n\
         \x20   Debug.Print VarType(CByte(1)); VarType(CSng(1)); VarType(CCur(1)); TypeName(v + 100)\n\
         \x20   On Error Resume Next\n    v = CByte(256)\n    Debug.Print Err.Number;\n    Err.Clear\n    v = CByte(-1)\n\
         \x20   Debug.Print Err.Number;\n    Err.Clear\n    v = CCur(1E+16)\n    Debug.Print Err.Number;\n    Err.Clear\n\
         \x20   v = CSng(1E+39)\n    Debug.Print Err.Number",
    );
    assert_eq!(out, ["Byte 200 Single 1.5 Currency 1.2346 ", " 17  4  6 Integer", " 6  6  6  6 "]);
}

// The language reference names the type of the number some functions give in a Variant:
// "InStr function" and "InStrRev function" a Variant (Long), "StrComp function" a Variant
// (Integer), "Rnd function" a Single.
#[test]
fn library_functions_give_numbers_of_their_documented_types() {
    let out = printed_in(
        "",
        "    Dim v
    v = InStr(\"abc\", \"b\")
\
         \x20   Debug.Print TypeName(v); \" \"; TypeName(InStrRev(\"abc\", \"c\")); \" \"; TypeName(StrComp(\"a\", \"b\")); \" \"; TypeName(Rnd)",
    );
    assert_eq!(out, ["Long Long Integer Single"]);
}

// [MS-VBAL] 3.3.5.3: a name in square brackets is a foreign name, here a member of a
// worksheet (`ws.[A1]`), which Excel's Worksheet evaluates: "Using square brackets (for
// example, "[A1:C5]") is identical to calling the Evaluate method with a string argument"
// ("Worksheet.Evaluate method"), on that sheet.
#[test]
fn a_bracketed_member_of_a_sheet_is_its_evaluate() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("cfg").unwrap();
    wb.set_input(1, parse_cell("A1").unwrap(), "out").unwrap();
    wb.set_input(1, parse_cell("B2").unwrap(), "4").unwrap();
    let src = "Sub Main()\n    Debug.Print Sheets(\"cfg\").[A1] & \"\\x.nc\"; Sheets(2).[B2*10]\n\
               \x20   Sheets(\"cfg\").[C3] = 7\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["out\\x.nc 40 "]);
    assert_eq!(wb.value(1, parse_cell("C3").unwrap()), n(7.0));
}

// "WorksheetFunction.Floor_Precise method" and "…Ceiling_Precise": a worksheet function whose
// name holds a dot is a member with an underscore there; the values are the FLOOR.PRECISE and
// CEILING.PRECISE pages' examples (FLOOR.PRECISE(-3.2,-1) = -4, (3.2,1) = 3; CEILING.PRECISE(4.3)
// = 5, (-4.3) = -4).
#[test]
fn worksheet_functions_with_a_dot_are_members_with_an_underscore() {
    assert_eq!(value("WorksheetFunction.Floor_Precise(-3.2, -1)"), n(-4.0));
    assert_eq!(value("Application.WorksheetFunction.Floor_Precise(3.2, 1)"), n(3.0));
    assert_eq!(value("WorksheetFunction.Ceiling_Precise(4.3)"), n(5.0));
    assert_eq!(value("Application.Ceiling_Precise(-4.3)"), n(-4.0));
}

// [MS-VBAL] 5.4.2.3 "For Statement": the bound variable is Let-assigned the start value, then
// at each Next its value plus the step, so a Variant counter holds the start's type, then that
// of `counter + step` (5.6.9.3.3), widened past its range as a Variant's sum is ("Variant data
// type"): 32766 To 32768 counts two Integers and a Long.
#[test]
fn a_variant_for_counter_holds_the_type_of_its_start_and_steps() {
    let out = printed_in(
        "",
        "    Dim i, s\n    For i = 1 To 2: s = s & TypeName(i) & \" \": Next\n    s = s & TypeName(i) & \"|\"\n\
         \x20   For i = 32766 To 32768: s = s & TypeName(i) & \" \": Next\n    s = s & \"|\"\n\
         \x20   For i = 1 To 2 Step 0.5: s = s & TypeName(i) & \" \": Next\n    s = s & \"|\"\n\
         \x20   For i = 1& To 1: s = s & TypeName(i): Next\n    Debug.Print s",
    );
    assert_eq!(out, ["Integer Integer Integer|Integer Integer Long |Integer Double Double |Long"]);
}

// [MS-VBAL] 5.6.13.1 "Index Expressions": an index applied to a variable whose Variant holds
// an array names that array's element as a variable, so `a(1)(2) = 7` changes the array held
// by `a(1)`, keeping its bounds (2.2: an array value carries them); arrays are copied on
// assignment (5.4.3.8 "Let Statement"), so the array assigned from and a copy stay as they were.
#[test]
fn an_item_of_an_array_held_by_an_array_item_is_assigned() {
    let out = run("Sub Main()\n    Dim A(1 To 2), b(1 To 3)\n    b(1) = 1: b(2) = 2: b(3) = 3\n    A(1) = b\n\
                   \x20   A(1)(2) = 7\n    Debug.Print A(1)(2)\n    Debug.Print b(2)\n    Debug.Print LBound(A(1))\n\
                   \x20   A(2) = Array(Array(1, 2), Array(3, 4))\n    A(2)(1)(0) = \"x\"\n    Debug.Print A(2)(1)(0) & A(2)(0)(0)\n\
                   \x20   Dim v\n    v = A\n    v(1)(3) = 9\n    Debug.Print A(1)(3)\n    Debug.Print v(1)(3)\n\
                   \x20   Set A(2)(0)(1) = New Collection\n    Set c = A(2)(0)(1)\n    c.Add 5\n\
                   \x20   Set d = A(2)(0)(1)\n    Debug.Print d.Count\n\
                   \x20   On Error Resume Next\n    A(1)(4) = 1\n    Debug.Print Err.Number\n    Err.Clear\n\
                   \x20   A(1)(1)(1) = 1\n    Debug.Print Err.Number\nEnd Sub\n");
    assert_eq!(out.printed, [" 7 ", " 2 ", " 1 ", "x1", " 3 ", " 9 ", " 1 ", " 9 ", " 13 "]);
}

// [MS-VBAL] 5.6.13.1 "Index Expressions" and 5.3.1.11 (ByRef arguments): an argument `b(i)`
// passed ByRef is the element itself, its index evaluated once when the argument list is
// evaluated, left to right ("Calling Sub and Function procedures": arguments in order).
#[test]
fn a_byref_item_argument_evaluates_its_index_once() {
    let out = run("Dim k\nFunction NextIndex()\n    k = k + 1\n    Debug.Print \"index \" & k\n    NextIndex = k\nEnd Function\n\
                   Sub Twice(v, w)\n    v = v * 10\n    Debug.Print \"w \" & w\nEnd Sub\n\
                   Sub Main()\n    Dim b(1 To 3)\n    b(1) = 1: b(2) = 2: b(3) = 3\n    Twice b(NextIndex()), NextIndex()\n\
                   \x20   Debug.Print b(1) & \" \" & b(2) & \" \" & b(3)\nEnd Sub\n");
    assert_eq!(out.printed, ["index 1", "index 2", "w 2", "10 2 3"]);
}

// [MS-VBAL] 5.4.3.8 "Let Statement" and 5.6.13.1 "Index Expressions": `o.Field(i) = v` names
// the element of the array the object's public Variant variable holds; an item takes an array.
// A class cannot declare a Public array itself ("Constants, fixed-length strings, arrays,
// user-defined types, and Declare statements not allowed as Public members of an object
// module"): `tests/vba_real_h5.rs` holds that refusal.
#[test]
fn an_item_of_an_objects_public_array_is_assigned() {
    let class = "Public Items As Variant\n";
    let out = with_classes(
        "Sub Main()\n    Dim o As New Holder\n    o.Items = Array(1, 2, 3)\n    o.Items(1) = 9\n\
         \x20   o.Items(2) = Array(7, 8)\n    Debug.Print o.Items(1) + 2.5\n    v = o.Items\n    Debug.Print v(2)(1)\n\
         \x20   On Error Resume Next\n    o.Items(4) = 1\n    Debug.Print Err.Number\nEnd Sub\n",
        &[("Holder", class)],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 11.5 ", " 8 ", " 9 "]);
}

// Excel reads a VBA array of arrays given to a worksheet function as a two-dimensional array,
// one row per inner array. "WorksheetFunction.Transpose method": rows become columns, and the
// result comes back to VBA 1-based in both dimensions; a one-dimensional array is a row (so its
// transpose is an n × 1 array) and an n × 1 array's transpose a one-dimensional array from 1.
// "WorksheetFunction.Index method": row and column count from 1 whatever the array's bounds.
#[test]
fn worksheet_functions_read_an_array_of_arrays_as_rows() {
    let out = run("Sub Main()\n    t = Application.Transpose(Array(Array(1, 2, 3), Array(4, 5, 6)))\n\
                   \x20   Debug.Print LBound(t, 1) & UBound(t, 1) & LBound(t, 2) & UBound(t, 2) & t(3, 2) & t(1, 2)\n\
                   \x20   u = WorksheetFunction.Transpose(Array(10, 20, 30))\n\
                   \x20   Debug.Print LBound(u, 1) & UBound(u, 1) & LBound(u, 2) & UBound(u, 2) & u(2, 1)\n\
                   \x20   w = Application.Transpose(u)\n    Debug.Print LBound(w) & UBound(w) & w(3)\n\
                   \x20   j = Array(Array(1, 2), Array(3, 4))\n    Debug.Print Application.Index(j, 2, 1)\n\
                   \x20   Dim z(0 To 2, 0 To 1)\n    z(2, 1) = 42\n    Debug.Print Application.Index(z, 3, 2)\n\
                   \x20   On Error Resume Next\n    x = Application.Transpose(Array(Array(1, 2), Array(3, 4, 5)))\n\
                   \x20   Debug.Print Err.Number <> 0\nEnd Sub\n");
    assert_eq!(out.printed, ["131264", "131120", "1330", " 3 ", " 42 ", "True"]);
}

// [MS-VBAL] 2.2 ("an array value carries its bounds") and "Function statement" (an array is
// returned by assigning it to the name): a Function's array handed straight to another call,
// `F(G())`, keeps the bounds G gave it, as `x = G()` does, whatever the Option Base.
#[test]
fn a_functions_array_passed_to_another_call_keeps_its_bounds() {
    let out = run("Function G()\n    Dim a(3 To 5)\n    a(3) = 1: a(5) = 5\n    G = a\nEnd Function\n\
                   Function G2()\n    Dim a(1 To 2, 2 To 3)\n    a(2, 3) = 7\n    G2 = a\nEnd Function\n\
                   Function F(v)\n    F = LBound(v) & UBound(v)\nEnd Function\nFunction Id(v)\n    Id = v\nEnd Function\n\
                   Sub S(ByVal v)\n    Debug.Print \"S\" & LBound(v)\nEnd Sub\n\
                   Function Small() As Integer\n    Small = 7\nEnd Function\n\
                   Sub Main()\n    Debug.Print F(G())\n    Debug.Print F(Id(G()))\n    x = Id(Id(G()))\n\
                   \x20   Debug.Print LBound(x) & UBound(x)\n    S G()\n    y = Id(G2())\n    Debug.Print LBound(y, 2) & y(2, 3)\n\
                   \x20   Debug.Print UBound(Id(G())) & Id(G())(5)\n    Debug.Print TypeName(Id(Small()))\nEnd Sub\n");
    assert_eq!(out.printed, ["35", "35", "35", "S3", "27", "55", "Integer"]);
}

// "Array function": a Variant containing an array, of one item too (`Array(3)`, bounds 0 To 0
// without Option Base); "Split function": a zero-based one-dimensional array, one item for a
// text without the delimiter. Stored as an item of an array, each stays an array (2.2).
#[test]
fn an_array_of_one_item_stored_as_an_item_stays_an_array() {
    let out = run("Sub Main()\n    Dim b(1 To 2)\n    b(1) = Array(3)\n    b(2) = Split(\"a\", \",\")\n\
                   \x20   Debug.Print UBound(b(1)) & b(1)(0) & UBound(b(2)) & b(2)(0)\n    Debug.Print IsArray(b(1))\nEnd Sub\n");
    assert_eq!(out.printed, ["030a", "True"]);
}

// [MS-VBAL] 5.2.3.1 (an array's declared type may be a UDT: `Dim pts(1 To 3) As TPoint`, each
// element a UDT value of that Type), 5.4.3.8 "Let Statement" (assigning a UDT copies it: `q =
// pts(1): q.x = 9` leaves pts(1) as it was), 5.3.1.11 (a ByRef argument `pts(3)` is the element
// itself, so the Sub's change comes back), "ReDim statement" (Preserve keeps the items; without
// it they are the Type's defaults again), "UBound function", "With statement" (`With pts(1)`
// names the element itself).
#[test]
fn arrays_of_a_user_defined_type() {
    let out = run("Type TPoint\n    x As Double\n    y As Double\nEnd Type\n\
                   Type TSeg\n    a As TPoint\n    b As TPoint\nEnd Type\n\
                   Function MakePoint(x As Double, y As Double) As TPoint\n    Dim p As TPoint\n    p.x = x: p.y = y\n    MakePoint = p\nEnd Function\n\
                   Sub ShiftX(p As TPoint, d As Double)\n    p.x = p.x + d\nEnd Sub\n\
                   Function SumX(a() As TPoint) As Double\n    Dim i As Long\n    For i = LBound(a) To UBound(a)\n        SumX = SumX + a(i).x\n    Next\nEnd Function\n\
                   Sub ScaleY(a() As TPoint)\n    a(2).y = a(2).y * 10\nEnd Sub\n\
                   Sub Main()\n    Dim pts(1 To 3) As TPoint\n    pts(1).x = 1.5\n    pts(2) = MakePoint(2, 4)\n    pts(3).y = 7\n\
                   \x20   ShiftX pts(3), 0.25\n    Debug.Print pts(1).x & \",\" & pts(2).x & \",\" & pts(2).y & \",\" & pts(3).x & \",\" & pts(3).y\n\
                   \x20   Debug.Print SumX(pts) & \" \" & LBound(pts) & UBound(pts)\n    ScaleY pts\n    Debug.Print pts(2).y\n\
                   \x20   Dim q As TPoint\n    q = pts(1)\n    q.x = 9\n    With pts(1)\n        .y = -1\n    End With\n    Debug.Print pts(1).x & \" \" & q.x & \" \" & pts(1).y & q.y\n\
                   \x20   Dim d() As TPoint\n    ReDim d(2)\n    d(2).x = 5\n    ReDim Preserve d(4)\n    d(4).y = 6\n\
                   \x20   Debug.Print UBound(d) & d(2).x & d(4).y & d(0).x\n    ReDim d(1)\n    Debug.Print UBound(d) & d(1).x\n\
                   \x20   Dim segs(1 To 2) As TSeg\n    segs(2).a.x = 3\n    segs(2).b = pts(2)\n    Debug.Print segs(2).a.x + segs(2).b.y\n\
                   \x20   Debug.Print TypeName(pts)\nEnd Sub\n");
    assert_eq!(out.printed, ["1.5,2,4,0.25,7", "3.75 13", " 40 ", "1.5 9 -10", "4560", "10", " 43 ", "TPoint()"]);
}

// "String data type": a fixed-length String (`String * 10`) always holds its length of
// characters; [MS-VBAL] 5.5.1.2 (Let-coercion to String * length): a longer text is cut to its
// first characters, a shorter one padded on the right with spaces, a number is made a String
// first (`s = s & "x"` on a full one drops the "x"). A Type's field `String * 4` is one too.
#[test]
fn fixed_length_strings_pad_and_truncate() {
    let out = run("Type TRec\n    name As String * 4\n    n As Integer\nEnd Type\n\
                   Sub Main()\n    Dim s As String * 10\n    s = \"abc\"\n    Debug.Print \"[\" & s & \"]\" & Len(s)\n\
                   \x20   s = \"0123456789ABC\"\n    Debug.Print \"[\" & s & \"]\"\n    s = 12.5\n    s = s & \"x\"\n    Debug.Print \"[\" & s & \"]\"\n\
                   \x20   Dim r As TRec, q As TRec\n    r.name = \"T1\"\n    Debug.Print \"[\" & r.name & \"]\" & Len(r.name)\n\
                   \x20   r.name = \"ENDMILL\": r.n = 1\n    Debug.Print r.name\n    Dim t(1 To 2) As String * 3\n    t(1) = \"abcdef\"\n\
                   \x20   Debug.Print t(1) & Len(t(2))\n    q = r\n    q.name = \"Z\"\n    Debug.Print \"[\" & q.name & \"]\" & r.name\nEnd Sub\n");
    assert_eq!(
        out.printed,
        ["[abc       ]10", "[0123456789]", "[12.5      ]", "[T1  ]4", "ENDM", "abc3", "[Z   ]ENDM"]
    );
}

// "Type statement": a field may be an array, with its bounds (`x(1 To 100) As Double`) or
// dynamic (`v() As Double`), sized by "ReDim statement" (`ReDim p.v(5)`, Preserve keeping the
// items); [MS-VBAL] 5.4.3.8: assigning the Type copies its arrays too (`q = p: q.x(3) = 7`
// leaves p.x(3)); an item assigned is let-coerced to the field's type ("2.5" is 2.5); an index
// past the bounds is run-time error 9 ("Subscript out of range"); LBound/UBound give the
// field's own bounds.
#[test]
fn a_types_field_can_be_an_array() {
    let out = run("Type TPath\n    n As Long\n    x(1 To 100) As Double\nEnd Type\n\
                   Type TBuf\n    v() As Double\n    tag As String\nEnd Type\n\
                   Sub Main()\n    Dim p As TPath, q As TPath\n    p.x(3) = 2\n    p.x(100) = \"2.5\"\n    p.n = 3\n    q = p\n    q.x(3) = 7\n\
                   \x20   Debug.Print p.x(3) & \" \" & p.x(100) & \" \" & q.x(3) & \" \" & LBound(p.x) & \" \" & UBound(p.x) & \" \" & p.x(1)\n\
                   \x20   Dim b As TBuf\n    ReDim b.v(5)\n    b.v(5) = 1.5\n    ReDim Preserve b.v(7)\n    b.v(7) = 2\n\
                   \x20   Debug.Print UBound(b.v) & \" \" & b.v(5) & \" \" & b.v(7) & \" \" & b.v(0)\n\
                   \x20   Dim ps(1 To 2) As TPath\n    ps(2).x(4) = 9\n    Debug.Print ps(2).x(4) + ps(1).x(4)\n\
                   \x20   On Error Resume Next\n    p.x(101) = 1\n    Debug.Print Err.Number\nEnd Sub\n");
    assert_eq!(out.printed, ["2 2.5 7 1 100 0", "7 1.5 2 0", " 9 ", " 9 "]);
}

// [MS-VBAL]'s fixed-length String: `string-length = constant-name / INTEGER`, the constant's
// value a whole number from 1 to 65,526; "String data type": the variable always holds that
// many characters (padded with spaces). So `Const W = 10` … `Dim s As String * W` is a
// String * 10, in a procedure, at module level and in a Type's field, and a Const made of
// other constants (`Const N = W * 2 - 5`) serves too; a length past 65,526 is refused.
#[test]
fn a_fixed_length_string_takes_a_constant_as_its_length() {
    let out = run(
        "Const W = 10\nConst N = W * 2 - 5\nType TRec\n    name As String * W\nEnd Type\n\
                   Dim g As String * N\n\
                   Sub Main()\n    Const K = 3\n    Dim s As String * W, t As String * K, r As TRec\n\
                   \x20   s = \"abc\": t = \"abcdef\": r.name = \"x\": g = \"y\"\n\
                   \x20   Debug.Print \"[\" & s & \"]\" & Len(s) & \"[\" & t & \"]\" & Len(r.name) & Len(g)\nEnd Sub\n",
    );
    assert_eq!(out.printed, ["[abc       ]10[abc]1015"]);
    let refused = vba::run(
        &mut Workbook::with_sheet(),
        "Const BIG = 70000\nSub Main()\n    Dim s As String * BIG\nEnd Sub\n",
        "test.bas",
        &RunOptions::default(),
    );
    assert!(refused.unwrap_err().message.contains("65526"));
}

// "Understanding scope and visibility": a constant declared in a procedure is visible only
// within that procedure. So a procedure's own `Const W = 5` sizes its own `String * W`, and
// a procedure after it reads the module's `Const W = 10` ([MS-VBAL] string-length =
// constant-name).
#[test]
fn a_procedures_constant_sizes_no_string_of_a_later_procedure() {
    let out = run("Const W = 10\nSub A()\n    Const W = 5\n    Dim s As String * W\n    Debug.Print Len(s)\nEnd Sub\n\
         Sub Main()\n    A\n    Dim s As String * W\n    Debug.Print Len(s)\nEnd Sub\n");
    assert_eq!(out.printed, [" 5 ", " 10 "]);
}

// ---- dates: DateAdd, DateDiff, DatePart and the names of days and months ---------------

/// What `Debug.Print` shows of each expression, in order.
fn shown(exprs: &[&str]) -> Vec<String> {
    let body: Vec<String> = exprs.iter().map(|e| format!("    Debug.Print {e}")).collect();
    printed_in("", &body.join("\n"))
}

/// The run-time error `expr` raises, by its number (0: none).
fn error_of(expr: &str) -> String {
    let body = format!("    Dim x\n    On Error Resume Next\n    x = {expr}\n    Debug.Print CStr(Err.Number)");
    printed_in("", &body).concat()
}

// "DateAdd function": "DateAdd won't return an invalid date": DateAdd("m", 1, "31-Jan-95")
// is 28-Feb-95, and from 31-Jan-96 29-Feb-96 (a leap year); "w" adds the days themselves
// (Sunday to Saturday all count); a number that is no Long is rounded first; a date before
// the year 100 "an error occurs" (run-time error 5). The result is a Date.
#[test]
fn date_add_keeps_month_ends_and_adds_every_interval() {
    let d = "DateSerial(2024, 1, 31) + TimeSerial(10, 30, 0)";
    assert_eq!(
        shown(&[
            "DateAdd(\"m\", 1, \"31-Jan-95\")",
            "DateAdd(\"m\", 1, \"31-Jan-96\")",
            "DateAdd(\"yyyy\", 1, DateSerial(2024, 2, 29))",
            &format!("DateAdd(\"q\", 1, {d})"),
            &format!("DateAdd(\"M\", -2, {d})"),
            &format!("DateAdd(\"y\", 1, {d})"),
            &format!("DateAdd(\"d\", 1.6, {d})"),
            // 2024-02-02 is a Friday: one "w" later is the Saturday.
            "DateAdd(\"w\", 1, DateSerial(2024, 2, 2))",
            &format!("DateAdd(\"ww\", -1, {d})"),
            &format!("DateAdd(\"h\", 14, {d})"),
            &format!("DateAdd(\"n\", -631, {d})"),
            &format!("DateAdd(\"s\", 90, {d})"),
            &format!("TypeName(DateAdd(\"d\", 1, {d}))"),
        ]),
        [
            "2/28/1995",
            "2/29/1996",
            "2/28/2025",
            "4/30/2024 10:30:00 AM",
            "11/30/2023 10:30:00 AM",
            "2/1/2024 10:30:00 AM",
            "2/2/2024 10:30:00 AM",
            "2/3/2024",
            "1/24/2024 10:30:00 AM",
            "2/1/2024 12:30:00 AM",
            "1/30/2024 11:59:00 PM",
            "1/31/2024 10:31:30 AM",
            "Date",
        ]
    );
    assert_eq!(error_of("DateAdd(\"yyyy\", -2000, DateSerial(1999, 1, 1))"), "5");
    assert_eq!(error_of("DateAdd(\"d\", 1, DateSerial(9999, 12, 31))"), "5");
    assert_eq!(error_of("DateAdd(\"x\", 1, Date)"), "5", "an interval that is none of the settings");
}

// "DateDiff function": a Long; Dec 31 to the next Jan 1 is 1 "yyyy"; "w" from a Monday
// counts the Mondays after it up to date2 (date2 counted, date1 not); "ww" counts the
// Sundays (the first day of the week) after date1 up to and including date2; date1 later
// than date2 gives a negative number; "y" and "d" count days.
#[test]
fn date_diff_counts_the_boundaries_crossed() {
    // 2024-01-01 is a Monday, 2024-01-07 and 2024-01-14 Sundays.
    let d = |m: u32, day: u32| format!("DateSerial(2024, {m}, {day})");
    assert_eq!(
        shown(&[
            "CStr(DateDiff(\"yyyy\", DateSerial(2023, 12, 31), DateSerial(2024, 1, 1)))",
            &format!("CStr(DateDiff(\"w\", {}, {}))", d(1, 1), d(1, 15)),
            &format!("CStr(DateDiff(\"w\", {}, {}))", d(1, 1), d(1, 14)),
            &format!("CStr(DateDiff(\"ww\", {}, {}))", d(1, 7), d(1, 14)),
            &format!("CStr(DateDiff(\"ww\", {}, {}))", d(1, 6), d(1, 7)),
            &format!("CStr(DateDiff(\"ww\", {}, {}, vbMonday))", d(1, 6), d(1, 7)),
            &format!("CStr(DateDiff(\"ww\", {}, {}, vbMonday))", d(1, 7), d(1, 8)),
            &format!("CStr(DateDiff(\"d\", {}, {}))", d(3, 1), d(2, 1)),
            &format!("CStr(DateDiff(\"y\", {}, {}))", d(2, 1), d(3, 1)),
            &format!("CStr(DateDiff(\"m\", {}, {}))", d(1, 31), d(2, 1)),
            &format!("CStr(DateDiff(\"q\", {}, {}))", d(3, 31), d(4, 1)),
            &format!("CStr(DateDiff(\"h\", {} + TimeSerial(23, 59, 0), {}))", d(1, 1), d(1, 2)),
            &format!("CStr(DateDiff(\"n\", {}, {} + TimeSerial(1, 0, 0)))", d(1, 1), d(1, 1)),
            &format!("CStr(DateDiff(\"s\", {}, {}))", d(1, 2), d(1, 1)),
            &format!("TypeName(DateDiff(\"d\", {}, {}))", d(1, 1), d(1, 2)),
        ]),
        ["1", "2", "1", "1", "1", "0", "1", "-29", "29", "1", "1", "1", "60", "-86400", "Long"]
    );
    // Seconds from 100-01-01 to 9999-12-31 pass a Long's range: Overflow.
    assert_eq!(error_of("DateDiff(\"s\", DateSerial(100, 1, 1), DateSerial(9999, 12, 31))"), "6");
}

// "DatePart function": an Integer; "w" is the day of the week counted from firstdayofweek;
// "ww" the week of the year, week 1 being the week of January 1 unless firstweekofyear says
// vbFirstFourDays (the first week with four days of the new year: ISO 8601's weeks with
// vbMonday, which Microsoft's "Format or DatePart functions can return wrong week number for
// last Monday in Year" quotes: 2021-01-03 is in week 53 of 2020, 2021-01-04 in week 1) or
// vbFirstFullWeek (the first whole week).
#[test]
fn date_part_gives_each_part_and_the_week_of_the_year() {
    let at = "DateSerial(2024, 8, 15) + TimeSerial(13, 45, 30)";
    let parts: Vec<String> = ["yyyy", "q", "m", "y", "d", "w", "h", "n", "s"]
        .iter()
        .map(|i| format!("CStr(DatePart(\"{i}\", {at}))"))
        .collect();
    let parts: Vec<&str> = parts.iter().map(String::as_str).collect();
    // 2024-08-15 is a Thursday, day 31 + 29 + 31 + 30 + 31 + 30 + 31 + 15 = 228 of a leap year.
    assert_eq!(shown(&parts), ["2024", "3", "8", "228", "15", "5", "13", "45", "30"]);
    assert_eq!(
        shown(&[
            &format!("CStr(DatePart(\"w\", {at}, vbMonday))"),
            "CStr(DatePart(\"ww\", DateSerial(2022, 1, 1)))",
            "CStr(DatePart(\"ww\", DateSerial(2022, 1, 2)))",
            "CStr(DatePart(\"ww\", DateSerial(2000, 12, 31)))",
            "CStr(DatePart(\"ww\", DateSerial(2021, 1, 3), vbMonday, vbFirstFourDays))",
            "CStr(DatePart(\"ww\", DateSerial(2021, 1, 4), vbMonday, vbFirstFourDays))",
            "CStr(DatePart(\"ww\", DateSerial(2020, 12, 31), vbMonday, vbFirstFourDays))",
            "CStr(DatePart(\"ww\", DateSerial(2024, 12, 31), vbMonday, vbFirstFourDays))",
            "CStr(DatePart(\"ww\", DateSerial(2022, 1, 1), vbSunday, vbFirstFullWeek))",
            "CStr(DatePart(\"ww\", DateSerial(2022, 1, 2), vbSunday, vbFirstFullWeek))",
            "TypeName(DatePart(\"d\", Date))",
        ]),
        ["4", "1", "2", "54", "53", "1", "53", "1", "52", "1", "Integer"]
    );
    assert_eq!(error_of("DatePart(\"w\", Date, 8)"), "5", "a first day of the week past 0 to 7");
}

// "Weekday function" with its firstdayofweek, "WeekdayName function" and "MonthName
// function" (en-US names; abbreviate gives the short ones), and their constants vbSunday (1)
// … vbSaturday (7) and vbUseSystemDayOfWeek (0: the system's, Sunday in en-US).
#[test]
fn weekday_and_the_names_of_days_and_months() {
    // 2024-01-01 is a Monday.
    assert_eq!(
        shown(&[
            "CStr(Weekday(DateSerial(2024, 1, 1)))",
            "CStr(Weekday(DateSerial(2024, 1, 1), vbMonday))",
            "CStr(Weekday(DateSerial(2024, 1, 1), vbSaturday))",
            "CStr(Weekday(DateSerial(2024, 1, 1), vbUseSystemDayOfWeek))",
            "WeekdayName(1)",
            "WeekdayName(1, True, vbMonday)",
            "WeekdayName(Weekday(DateSerial(2024, 1, 1)))",
            "WeekdayName(7, False, vbWednesday)",
            "MonthName(2)",
            "MonthName(12, True)",
            "CStr(vbSunday + vbSaturday + vbFirstJan1 + vbFirstFourDays + vbFirstFullWeek)",
        ]),
        ["2", "1", "3", "2", "Sunday", "Mon", "Monday", "Tuesday", "February", "Dec", "14"]
    );
    assert_eq!(error_of("MonthName(13)"), "5");
    assert_eq!(error_of("WeekdayName(0)"), "5");
}

// "DateValue function" (its example: DateValue("February 12, 1969")), "TimeValue function"
// (its example: TimeValue("4:35:17 PM")), each a Date; a Date's other part is left out.
// "DateSerial function" outside 100-01-01 to 9999-12-31 is run-time error 5 (Microsoft KB
// Q77393, "DateSerial function returns error 5 for year 10000").
#[test]
fn date_value_time_value_and_date_serial_out_of_range() {
    assert_eq!(
        shown(&[
            "DateValue(\"February 12, 1969\")",
            "TimeValue(\"4:35:17 PM\")",
            "DateValue(DateSerial(2024, 3, 1) + TimeSerial(6, 0, 0))",
            "TimeValue(DateSerial(2024, 3, 1) + TimeSerial(6, 0, 0))",
            "TypeName(DateValue(\"1/2/2020\"))",
        ]),
        ["2/12/1969", "4:35:17 PM", "3/1/2024", "6:00:00 AM", "Date"]
    );
    assert_eq!(error_of("DateSerial(10000, 1, 1)"), "5");
    assert_eq!(error_of("DateSerial(9999, 12, 32)"), "5");
    assert_eq!(error_of("DateSerial(9999, 12, 31)"), "0");
}

// "ByRef argument type mismatch" (Office VBA reference, vblr6.chm1011308): a variable given
// to a ByRef parameter "must have the precise data type expected in the procedure" — an
// Integer variable where a Long is expected does not compile, a Variant where an Integer is
// neither; "you can pass the argument in its own set of parentheses" to have it converted, and
// the original keeps its value. KB 158472: an item of a Variant array where an Integer is.
// A compile error is the calling procedure's alone (compiled on demand).
#[test]
fn a_variable_of_another_type_given_by_ref_does_not_compile() {
    let subs = "Sub Inc(ByRef n As Integer)\n    n = n + 1\nEnd Sub\n\
                Sub Twice(n As Long)\n    n = n * 2\nEnd Sub\n\
                Sub Bang(s As String)\n    s = s & \"!\"\nEnd Sub\n\
                Sub Fill(a() As Long)\n    a(1) = 7\nEnd Sub\n\
                Sub Show(ByVal n As Integer)\n    Debug.Print n\nEnd Sub\n";
    let mismatch = |body: &str, arg: &str| {
        let src = format!("{subs}Sub Other()\n    Debug.Print \"other\"\nEnd Sub\nSub Main()\n{body}\nEnd Sub\n");
        let e = run_with(&src, &RunOptions::default()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Syntax, "{body}: {e}");
        assert!(e.message.starts_with("ByRef argument type mismatch"), "{body}: {e}");
        assert!(e.message.contains(arg), "{body}: {e}");
        assert!(e.output.printed.is_empty(), "{body}: the procedure does not start: {e}");
        let other = src.replace("Sub Main()", "Sub Main0()").replace("Sub Other()", "Sub Main()");
        assert_eq!(run(&other).printed, ["other"], "{body}: only the calling procedure fails");
    };
    mismatch("    Debug.Print \"start\"\n    Dim l As Long\n    Inc l", "l is a Long");
    mismatch("    Dim i As Integer\n    Twice i", "i is an Integer");
    mismatch("    Dim v\n    v = \"a\"\n    Bang v", "v is a Variant");
    mismatch("    Dim d As Double\n    Call Inc(d)", "d is a Double");
    mismatch("    Dim d As Double\n    x = 1\n    Inc n:=d", "d is a Double");
    mismatch("    Dim x(3) As Double\n    Fill x", "x is a Double array");
    mismatch("    Dim v(3)\n    Inc v(1)", "v(…) is a Variant");
    // Converted: the variable in its own parentheses, an expression, a literal, a ByVal
    // parameter; the same type passes the variable itself.
    let ok = format!(
        "{subs}Sub Main()\n    Dim l As Long, i As Integer, x(3) As Long, d As Double\n    l = 5\n    Inc (l)\n    \
         Call Inc((l))\n    Inc l + 0\n    Inc 3\n    d = 2.5\n    Show d\n    Debug.Print l\n    i = 4\n    Inc i\n    \
         Debug.Print i\n    Fill x\n    Debug.Print x(1)\n    Twice x(1)\n    Debug.Print x(1)\nEnd Sub\n"
    );
    assert_eq!(run(&ok).printed, [" 2 ", " 5 ", " 5 ", " 7 ", " 14 "]);
}

// "Filter Function" (Visual Basic 6 reference): "An error occurs if sourcearray is Null or is
// not a one-dimensional array"; Join's sourcearray is a "One-dimensional array" too ("Join
// function"). The numbers are those Microsoft's Visual Basic runtime keeps for Visual Basic 6
// code, in the Exceptions tables of "Join Function (Visual Basic)" (5, "SourceArray is not
// one dimensional") and "Filter Function (Visual Basic)" (9, "Source is Nothing or is not a
// one-dimensional array"). Raised, trappable, where Join gave #VALUE! as its value.
#[test]
fn join_and_filter_of_no_one_dimensional_array_raise_errors() {
    let out = run("Sub Main()\n    Dim m(1, 1), v, r\n    v = 5\n    On Error Resume Next\n\
                   \x20   r = Join(\"abc\", \",\"): Debug.Print Err.Number: Err.Clear\n\
                   \x20   r = Join(v): Debug.Print Err.Number: Err.Clear\n\
                   \x20   r = Join(Null): Debug.Print Err.Number: Err.Clear\n\
                   \x20   r = Join(m): Debug.Print Err.Number: Err.Clear\n\
                   \x20   r = Filter(\"abc\", \"a\"): Debug.Print Err.Number: Err.Clear\n\
                   \x20   r = Filter(m, \"a\"): Debug.Print Err.Number: Err.Clear\n\
                   \x20   Debug.Print Join(Filter(Array(\"ab\", \"c\", \"ba\"), \"a\"), \"+\"); Err.Number\nEnd Sub\n");
    assert_eq!(out.printed, [" 5 ", " 5 ", " 5 ", " 5 ", " 9 ", " 9 ", "ab+ba 0 "]);
    let e = run_with("Sub Main()\n    Debug.Print Join(\"abc\")\nEnd Sub\n", &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("Join") && e.message.contains("one-dimensional"), "{e}");
}

// "Len function": "Returns a Long containing the number of characters in a string or the
// number of bytes required to store a variable". The page's own example: Len(MyInt) 2 for an
// Integer, Len(Customer) 42 for its CustomerRecord (an Integer, a String * 10 and a String * 30,
// "the size as it will be written to the file"), Len(MyString) 11 for "Hello World" in a
// Variant ("Len treats it the same as a String"), Len(MyCur) 8 for a Currency. The other
// sizes are the storage sizes of "Data type summary" (Byte 1, Boolean 2, Long and Single 4,
// Double and Date 8), an array's item its item type's (Long: 4), a Type's fixed array its
// items' (3 Integers: 6), LenB of a Long its 4 bytes; a String variable is its characters.
#[test]
fn len_of_a_typed_variable_is_the_bytes_it_takes() {
    let out = run("Type CustomerRecord\n    ID As Integer\n    Name As String * 10\n    Address As String * 30\nEnd Type\n\
                   Type Triple\n    v(1 To 3) As Integer\n    k As Byte\nEnd Type\n\
                   Sub Main()\n    Dim Customer As CustomerRecord\n    Dim MyInt As Integer, MyCur As Currency\n    \
                   Dim MyString, MyLen\n    MyString = \"Hello World\"\n    \
                   Debug.Print Len(MyInt) & \" \" & Len(Customer) & \" \" & Len(MyString) & \" \" & Len(MyCur)\n    \
                   Dim b As Byte, t As Boolean, l As Long, s As Single, d As Double, w As Date, tx As String\n    \
                   l = 123456: tx = \"abc\"\n    \
                   Debug.Print Len(b) & \" \" & Len(t) & \" \" & Len(l) & \" \" & Len(s) & \" \" & Len(d) & \" \" & Len(w) & \" \" & Len(tx)\n    \
                   Dim a(3) As Long, tr As Triple\n    \
                   Debug.Print Len(a(1)) & \" \" & Len(tr) & \" \" & LenB(l) & \" \" & TypeName(Len(l))\nEnd Sub\n");
    assert_eq!(out.printed, ["2 42 11 8", "1 2 4 4 8 8 3", "4 7 4 Long"]);
}

// "DoEvents function": it "yields execution so that the operating system can process other
// events" and returns "zero in all other applications" than stand-alone Visual Basic, so in
// Excel `DoEvents` in a loop does nothing a macro sees and `n = DoEvents` is 0. Real macros call
// it in their long loops; it was "no Sub named DoEvents".
#[test]
fn do_events_yields_and_answers_zero() {
    let out = run(
        "Sub Main()\n    Dim i As Long, n\n    For i = 1 To 3\n        DoEvents\n        s = s & i\n    Next\n    \
                   n = DoEvents()\n    Debug.Print s; n; DoEvents\nEnd Sub\n",
    );
    assert_eq!(out.printed, ["123 0  0 "]);
}

// "Beep statement" sounds a tone, "Application.Wait method" pauses the macro until a time,
// and `Calculate` alone is Excel's global Application.Calculate ("Application.Calculate
// method"): none changes a value or a file, so a macro runs on past them; they were "no Sub
// named Beep", "no Sub named Calculate" and Application.Wait refused as not modelled.
#[test]
fn beep_wait_and_calculate_run_on() {
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n    [A1] = 2\n    [B1] = \"=A1*3\"\n    Beep\n    Calculate\n    \
               Application.Wait Now + TimeValue(\"0:00:01\")\n    Debug.Print [B1].Value\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 6 "]);
}
