//! Constructs that stopped real public engineering modules (issue 31, session 19's sample:
//! steam tables, friction factors, matrix routines, interpolation UDFs), each in a small macro
//! of our own with the result Microsoft's VBA language reference or [MS-VBAL] (the page or
//! section named at each test) gives.

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::project::{ModuleKind, ProjectModule, VbaProject};
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

/// Magnus Holmgren's XSteam 2.6 (IAPWS IF-97 steam tables for Excel, www.x-eng.com; "free to
/// use, modify and distribute the code as long as authorship is properly acknowledged"): its
/// saturation functions as the module has them, called from cells as its users call them.
const XSTEAM_SATURATION: &str = "Option Explicit\r\n\
Function Tsat_p(ByVal P As Double) As Double\r\n\
 P = toSIunit_p(P)\r\n\
 If P >= 0.000611657 And P <= 22.06395 + 0.001 Then '0.001 Added to enable the tripple point.\r\n\
   Tsat_p = fromSIunit_T(T4_p(P))\r\n\
 Else\r\n\
   Tsat_p = CVErr(xlErrValue)\r\n\
 End If\r\n\
End Function\r\n\
Function psat_T(ByVal T As Double) As Double\r\n\
 T = toSIunit_T(T)\r\n\
 If T <= 647.096 And T > 273.15 Then\r\n\
   psat_T = fromSIunit_p(p4_T(T))\r\n\
 Else\r\n\
   psat_T = CVErr(xlErrValue)\r\n\
 End If\r\n\
End Function\r\n\
Function p4_T(ByVal T As Double) As Double\r\n\
  'Release on the IAPWS Industrial Formulation 1997 for the Thermodynamic Properties of Water and Steam, September 1997\r\n\
  'Section 8.1 The Saturation-Pressure Equation\r\n\
  'Eq 30, Page 33\r\n\
  Dim teta, a, b, c As Double\r\n\
  teta = T - 0.23855557567849 / (T - 650.17534844798)\r\n\
  a = teta ^ 2 + 1167.0521452767 * teta - 724213.16703206\r\n\
  b = -17.073846940092 * teta ^ 2 + 12020.82470247 * teta - 3232555.0322333\r\n\
  c = 14.91510861353 * teta ^ 2 - 4823.2657361591 * teta + 405113.40542057\r\n\
  p4_T = (2 * c / (-b + (b ^ 2 - 4 * a * c) ^ 0.5)) ^ 4\r\n\
End Function\r\n\
Function T4_p(ByVal P As Double) As Double\r\n\
  'Release on the IAPWS Industrial Formulation 1997 for the Thermodynamic Properties of Water and Steam, September 1997\r\n\
  'Section 8.2 The Saturation-Temperature Equation\r\n\
  'Eq 31, Page 34\r\n\
  Dim beta, E, f, g, D As Double\r\n\
  beta = P ^ 0.25\r\n\
  E = beta ^ 2 - 17.073846940092 * beta + 14.91510861353\r\n\
  f = 1167.0521452767 * beta ^ 2 + 12020.82470247 * beta - 4823.2657361591\r\n\
  g = -724213.16703206 * beta ^ 2 - 3232555.0322333 * beta + 405113.40542057\r\n\
  D = 2 * g / (-f - (f ^ 2 - 4 * E * g) ^ 0.5)\r\n\
  T4_p = (650.17534844798 + D - ((650.17534844798 + D) ^ 2 - 4 * (-0.23855557567849 + 650.17534844798 * D)) ^ 0.5) / 2\r\n\
End Function\r\n\
Function toSIunit_p(ByVal Ins As Double) As Double\r\n\
'Translate bar to MPa\r\n\
  toSIunit_p = Ins / 10\r\n\
End Function\r\n\
Function fromSIunit_p(ByVal Ins As Double) As Double\r\n\
'Translate bar to MPa\r\n\
  fromSIunit_p = Ins * 10\r\n\
End Function\r\n\
Function toSIunit_T(ByVal Ins As Double) As Double\r\n\
'Translate degC to Kelvon\r\n\
  toSIunit_T = Ins + 273.15\r\n\
End Function\r\n\
Function fromSIunit_T(ByVal Ins As Double) As Double\r\n\
'Translate Kelvin to degC\r\n\
  fromSIunit_T = Ins - 273.15\r\n\
End Function\r\n";

// The values are pyXSteam 0.4.10's (PyPI, a Python port of the same XSteam, computed apart):
// tsat_p(1) = 99.60591861133764 °C, psat_t(100) = 1.0141797792131013 bar. Out of range, XSteam
// assigns `CVErr(xlErrValue)` to a Function `As Double`: "Type mismatch (Error 13)" in the
// Function ("CVErr function": the Error subtype converts to no number), which a cell shows as
// #VALUE!. The whole 156,341-character module agreed with pyXSteam at 195 points over regions
// 1-5 and the saturation line to 4e-15 (session 29, issue 31), with pyXSteam's region-3
// bisection stopped at XSteam's 1e-6 K instead of its own 1e-5 K.
#[test]
fn xsteam_saturation_functions_compute_in_cells_as_pyxsteam_does() {
    let mut wb = Workbook::with_sheet();
    for (cell, text) in [("A1", "=Tsat_p(1)"), ("A2", "=psat_T(100)"), ("A3", "=Tsat_p(300)")] {
        wb.set_input(0, parse_cell(cell).unwrap(), text).unwrap();
    }
    let module = ProjectModule {
        name: "zXSteam".into(),
        stream: "zXSteam".into(),
        kind: ModuleKind::Standard,
        source: XSTEAM_SATURATION.into(),
    };
    let project = VbaProject { code_page: 1252, modules: vec![module], protection: None };
    let errors = vba::install_functions(&mut wb, &project, RunOptions::default());
    assert!(errors.is_empty(), "{errors:?}");
    for (cell, expected) in [("A1", 99.60591861133764), ("A2", 1.0141797792131013)] {
        match wb.value(0, parse_cell(cell).unwrap()) {
            Value::Number(n) => assert!((n - expected).abs() <= 1e-13 * expected, "{cell}: {n}"),
            other => panic!("{cell}: {other:?}"),
        }
    }
    assert_eq!(wb.value(0, parse_cell("A3").unwrap()), Value::Error(XlError::Value));
}
