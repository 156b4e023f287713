//! Constructs that stopped real public engineering modules (issue 31, session 19's sample:
//! steam tables, friction factors, matrix routines, interpolation UDFs), each in a small macro
//! of our own with the result Microsoft's VBA language reference or [MS-VBAL] (the page or
//! section named at each test) gives.

use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

/// What the macro's `Debug.Print`s wrote, line by line.
fn printed(src: &str) -> Vec<String> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}")).printed
}

// [MS-VBAL] 3.3.5.2 "Reserved Identifiers and IDENTIFIER": Step is none of the reserved
// identifiers (statement keywords, marker keywords, operators, …); only the For statement's
// step clause (5.4.2.3) reads the word. So a variable or parameter may be named `step`, and
// named in a call as `step:=` ([MS-VBAL] 5.6.16.8), while `For … Step` still steps.
#[test]
fn step_is_a_name_outside_a_for_statement() {
    let src = "Function Seq(start As Variant, n As Integer, Optional step = 1) As Variant\n\
               \x20   Dim a(), i As Integer\n    ReDim a(1 To n)\n\
               \x20   For i = 1 To n Step 1\n        a(i) = start + (i - 1) * step\n    Next i\n    Seq = a\nEnd Function\n\
               Sub Main()\n    Dim step As Double, k As Integer, s As String\n    step = 0.5\n\
               \x20   For k = 6 To 1 Step -2\n        s = s & k\n    Next k\n\
               \x20   Debug.Print Join(Seq( _\n        start:=5, _\n        n:=3, _\n        step:=2), \",\"); step; s\nEnd Sub\n";
    assert_eq!(printed(src), ["5,7,9 0.5 642"]);
}

// "Array function": Array returns "a Variant containing an array" of its arguments, and a
// Variant holding an array holds the whole array with its bounds ([MS-VBAL] 2.2 "Entities and
// Declared Types": an array's value includes its dimensions' bounds). So a routine returning
// `Array(lu, p, sign)` (an LU decomposition) keeps `p`'s 1 To 3, and `r(1)(3)` is its last
// item.
#[test]
fn an_array_inside_array_keeps_its_bounds() {
    let src = "Function Decompose() As Variant\n    Dim p() As Variant, sign As Variant\n\
               \x20   ReDim p(1 To 3)\n    p(1) = 10: p(2) = 20: p(3) = 30: sign = -1\n\
               \x20   Decompose = Array(0, p, sign)\nEnd Function\n\
               Sub Main()\n    Dim r As Variant\n    r = Decompose()\n\
               \x20   Debug.Print LBound(r(1)); UBound(r(1)); r(1)(3); r(2)\nEnd Sub\n";
    assert_eq!(printed(src), [" 1  3  30 -1 "]);
}

/// A macro run with the project's other standard modules (name, source).
fn printed_with_modules(main: &str, modules: &[(&str, &str)]) -> Vec<String> {
    let project = modules.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    let mut wb = Workbook::with_sheet();
    let options = RunOptions { project, ..RunOptions::default() };
    vba::run(&mut wb, main, "Module1.bas", &options).unwrap_or_else(|e| panic!("{e}")).printed
}

// [MS-VBAL] 5.6.10 "Simple Name Expressions": a simple name is looked up in the enclosing
// procedure first, then its module, then the project's other modules. So a local `Dim pinv`
// is the variable `pinv` in its procedure, assigned and read, although another module has a
// Function pinv (a matrix inverse's permutation, as a real module names both).
#[test]
fn a_local_variable_hides_a_procedure_of_another_module() {
    let main = "Option Explicit\nFunction Inverse() As Variant\n    Dim pinv As Variant\n\
                \x20   pinv = Array(2, 0, 1)\n    Inverse = pinv(0) + pinv(2)\nEnd Function\n\
                Sub Main()\n    Debug.Print Inverse(); pinv(5)\nEnd Sub\n";
    let perm = "Attribute VB_Name = \"Perm\"\nOption Explicit\nFunction pinv(n As Variant) As Variant\n\
                \x20   pinv = n * 10\nEnd Function\n";
    assert_eq!(printed_with_modules(main, &[("Perm", perm)]), [" 3  50 "]);
}

// [MS-VBAL] 5.6.16.8 "Argument Lists" and "Understanding named arguments and optional
// arguments": an argument may be given by its parameter's name, in any order after the
// positional ones. The names are those of the "InStr function" (Start, String1, String2,
// Compare) and "Replace function" (Expression, Find, Replace, Start, Count, Compare) pages:
// InStr(Start:=3, String1:="abcabc", String2:="B", Compare:=vbTextCompare) finds the second
// "b" at 5; InStr(String2:="c", String1:="abc") leaves Start out (3); Replace with Count:=1
// replaces the first match only.
#[test]
fn a_library_function_takes_arguments_by_vba_s_parameter_names() {
    let src = "Sub Main()\n\
               \x20   Debug.Print VBA.Strings.InStr(Start:=3, String1:=\"abcabc\", String2:=\"B\", Compare:=vbTextCompare); \
               InStr(String2:=\"c\", String1:=\"abc\"); Replace(\"a-a-a\", \"a\", Count:=1, Replace:=\"b\")\nEnd Sub\n";
    assert_eq!(printed(src), [" 5  3 b-a-a"]);
}
