//! The macro language, one statement form or built-in at a time. Expected values are VBA's
//! documented behaviour (Round(2.5) is 2, -7 Mod 3 is -1, …), not our own output.

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::{self, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run(src: &str) -> RunOutput {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "test.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The lines `Sub Main` prints.
fn printed(body: &str) -> Vec<String> {
    run(&format!("Sub Main()\n{body}\nEnd Sub\n")).printed
}

/// A macro expression's value, as written into a cell.
fn value(expr: &str) -> Value {
    let mut wb = Workbook::with_sheet();
    let src = format!("Sub Main()\n    [A1] = {expr}\nEnd Sub\n");
    vba::run(&mut wb, &src, "test.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{expr}: {e}"));
    wb.value(0, parse_cell("A1").unwrap())
}

fn n(x: f64) -> Value {
    Value::Number(x)
}

/// A text expression's value, as printed.
fn text(expr: &str) -> String {
    printed(&format!("Debug.Print {expr}")).remove(0)
}

#[test]
fn sub_and_function_with_parameters_return_by_name() {
    let out = run("Function Area(w, h)\n    Area = w * h\nEnd Function\n\n\
                   Private Function Twice(ByVal x As Double) As Double\n    Twice = 2 * x\nEnd Function\n\n\
                   Sub Main()\n    Debug.Print \"area \" & Area(3, 4) & \" twice \" & Twice(Area(1, 2))\nEnd Sub\n");
    assert_eq!(out.printed, ["area 12 twice 4"]);
}

#[test]
fn a_function_can_recurse_by_name_with_arguments() {
    let out = run("Function Fact(n)\n    If n <= 1 Then Fact = 1 Else Fact = n * Fact(n - 1)\nEnd Function\n\
                   Sub Main()\n    Debug.Print \"\" & Fact(10)\nEnd Sub\n");
    assert_eq!(out.printed, ["3628800"]);
}

#[test]
fn dim_with_types_converts_as_vba_does() {
    let lines = printed(
        "    Dim i As Integer, s As String, b As Boolean, d As Double, v\n\
         \x20   Debug.Print \"[\" & s & \"]\" & d & b & \"[\" & v & \"]\"\n\
         \x20   i = 2.5: d = \"1.5\": s = 7\n\
         \x20   Debug.Print i & \" \" & d & \" \" & s",
    );
    // Integer rounds halves to even; a String holds "7"; defaults are "", 0, False, Empty; a
    // Boolean joined with & is "False" as CStr spells it ("& operator").
    assert_eq!(lines, ["[]0False[]", "2 1.5 7"]);
}

#[test]
fn const_at_module_and_procedure_level() {
    let out = run("Const Pi As Double = 3.14159265358979\nPrivate Const Half = 0.5\n\
                   Sub Main()\n    Const Two = 2\n    Debug.Print \"\" & Round(Pi * Two * Half, 4)\nEnd Sub\n");
    assert_eq!(out.printed, ["3.1416"]);
}

#[test]
fn if_block_with_elseif_and_else() {
    let body = "    Dim x\n    For Each x In Array(-1, 0, 5, 50)\n\
                \x20       If x < 0 Then\n            Debug.Print \"negative\"\n\
                \x20       ElseIf x = 0 Then\n            Debug.Print \"zero\"\n\
                \x20       ElseIf x < 10 Then\n            Debug.Print \"small\"\n\
                \x20       Else\n            Debug.Print \"large\"\n        End If\n    Next";
    assert_eq!(printed(body), ["negative", "zero", "small", "large"]);
}

#[test]
fn one_line_if_with_else_and_several_statements() {
    let body = "    Dim a, b\n    If 1 < 2 Then a = 1: b = 2 Else a = 3\n    Debug.Print a & \",\" & b\n\
                \x20   If 1 > 2 Then a = 1: b = 2 Else a = 3: b = 4\n    Debug.Print a & \",\" & b\n\
                \x20   If a = 3 Then If b = 4 Then Debug.Print \"nested\"";
    assert_eq!(printed(body), ["1,2", "3,4", "nested"]);
}

#[test]
fn select_case_with_values_ranges_is_and_else() {
    let body = "    Dim x\n    For Each x In Array(1, 3, 7, 12, 20, \"b\")\n        Select Case x\n\
                \x20           Case 1, 2\n                Debug.Print \"one or two\"\n\
                \x20           Case 3 To 8\n                Debug.Print \"three to eight\"\n\
                \x20           Case \"a\", \"b\"\n                Debug.Print \"a letter\"\n\
                \x20           Case Is >= 20\n                Debug.Print \"twenty or more\"\n\
                \x20           Case Else\n                Debug.Print \"else\"\n        End Select\n    Next x";
    assert_eq!(printed(body), ["one or two", "three to eight", "three to eight", "else", "twenty or more", "a letter"]);
}

#[test]
fn for_next_with_step_counts_as_vba_does() {
    let body = "    Dim i, s\n    For i = 10 To 1 Step -3\n        s = s & i & \" \"\n    Next i\n\
                \x20   Debug.Print s & \"after \" & i\n\
                \x20   For i = 1 To 0\n        Debug.Print \"never\"\n    Next\n\
                \x20   For i = 0 To 1 Step 0.25: s = i: Next: Debug.Print \"\" & s";
    // The variable ends one step past the last value; an empty range runs no turn.
    assert_eq!(printed(body), ["10 7 4 1 after -2", "1"]);
}

#[test]
fn exit_for_and_exit_do_leave_the_innermost_loop() {
    let body = "    Dim i, j, n\n    For i = 1 To 3\n        For j = 1 To 10\n            If j > 2 Then Exit For\n\
                \x20           n = n + 1\n        Next j\n    Next i\n    Debug.Print \"\" & n\n\
                \x20   Do\n        n = n + 1\n        If n >= 10 Then Exit Do\n    Loop\n    Debug.Print \"\" & n";
    assert_eq!(printed(body), ["6", "10"]);
}

#[test]
fn do_loops_test_before_or_after_with_while_or_until() {
    let body = "    Dim n\n    n = 0: Do While n < 3: n = n + 1: Loop: Debug.Print \"\" & n\n\
                \x20   n = 0: Do Until n >= 4\n        n = n + 1\n    Loop\n    Debug.Print \"\" & n\n\
                \x20   n = 10: Do\n        n = n + 1\n    Loop While n < 5\n    Debug.Print \"\" & n\n\
                \x20   n = 10: Do\n        n = n - 1\n    Loop Until n < 8\n    Debug.Print \"\" & n";
    // A test after Loop runs the body once even when it is false at the start.
    assert_eq!(printed(body), ["3", "4", "11", "7"]);
}

#[test]
fn while_wend() {
    assert_eq!(printed("    Dim n\n    While n < 5\n        n = n + 2\n    Wend\n    Debug.Print \"\" & n"), ["6"]);
}

#[test]
fn exit_sub_and_exit_function() {
    let out = run("Function F(x)\n    F = 1\n    If x > 0 Then Exit Function\n    F = 2\nEnd Function\n\
                   Sub Main()\n    Debug.Print F(1) & \" \" & F(0)\n    Exit Sub\n    Debug.Print \"not here\"\nEnd Sub\n");
    assert_eq!(out.printed, ["1 2"]);
}

#[test]
fn goto_and_labels_as_the_papers_cycles_are_written() {
    // docs/domain.md §2: numbered blocks with IF … THEN GOTO Nn.
    let body = "    Dim x\n    x = 0\nN10:\n    x = x + 1\n    If x < 5 Then GoTo N10\n    Debug.Print \"\" & x\n\
                \x20   GoTo 100\n    Debug.Print \"skipped\"\n100 Debug.Print \"line 100\"\n\
                \x20   For x = 1 To 10\n        If x = 3 Then GoTo Done\n    Next\nDone:\n    Debug.Print \"left at \" & x";
    assert_eq!(printed(body), ["5", "line 100", "left at 3"]);
}

#[test]
fn comments_rem_continuation_and_colons() {
    let body = "    Dim total ' a comment after a statement\n    Rem a Rem line\n\
                \x20   ' a comment line\n    total = 1 + _\n        2 + _\n        3: total = total * 2 ' two statements\n\
                \x20   Debug.Print \"it's \" & total";
    assert_eq!(printed(body), ["it's 12"]);
}

#[test]
fn option_explicit_accepts_declared_names() {
    let out = run("Option Explicit\nDim counter As Long\n\nSub Main()\n    Dim i As Long\n\
                   \x20   For i = 1 To 4: counter = counter + i: Next\n    Debug.Print \"\" & counter\nEnd Sub\n");
    assert_eq!(out.printed, ["10"]);
}

#[test]
fn byref_changes_the_callers_variable_and_byval_does_not() {
    let out = run("Sub Bump(ByRef a, ByVal b)\n    a = a + 1\n    b = b + 1\nEnd Sub\n\
                   Sub Twice(x)\n    x = x * 2\nEnd Sub\n\
                   Sub Main()\n    Dim p, q\n    Const K = 5\n    p = 1: q = 1\n    Bump p, q\n    Call Twice(p)\n\
                   \x20   Twice q + 0\n    Twice K\n    Debug.Print p & \" \" & q & \" \" & K\nEnd Sub\n");
    // ByRef is VBA's default; an expression or a constant argument is a copy.
    assert_eq!(out.printed, ["4 1 5"]);
}

#[test]
fn optional_and_named_arguments() {
    let out = run("Function Pt(Optional x = 1, Optional z As Double = 2)\n    Pt = x & \"/\" & z\nEnd Function\n\
                   Sub Main()\n    Debug.Print Pt() & \" \" & Pt(5) & \" \" & Pt(z:=7) & \" \" & Pt(, 9)\nEnd Sub\n");
    assert_eq!(out.printed, ["1/2 5/2 1/7 1/9"]);
}

#[test]
fn vba_operators() {
    assert_eq!(value("7 Mod 3"), n(1.0));
    assert_eq!(value("-7 Mod 3"), n(-1.0));
    assert_eq!(value("5.5 Mod 2"), n(0.0)); // operands round half to even: 6 Mod 2
    assert_eq!(value("7 \\ 2"), n(3.0));
    assert_eq!(value("-7 \\ 2"), n(-3.0));
    assert_eq!(value("1 < 2 And 2 < 3"), Value::Bool(true));
    assert_eq!(value("1 > 2 Or 2 > 3"), Value::Bool(false));
    assert_eq!(value("Not 1 = 2 And 3 = 3"), Value::Bool(true)); // Not binds looser than =
    assert_eq!(value("True Xor True"), Value::Bool(false));
    assert_eq!(value("12 And 10"), n(8.0)); // bitwise on numbers
    assert_eq!(value("Not 0"), n(-1.0));
    assert_eq!(value("2 + 3 Mod 2"), n(3.0)); // Mod above +
    assert_eq!(value("2 ^ 3 ^ 2"), n(64.0)); // left-associative, as in the formula language
                                             // VBA's "Operator precedence": ^ above negation, so -2^2 is -4 (a cell's =-2^2 is 4).
    assert_eq!(value("-2 ^ 2"), n(-4.0));
    assert_eq!(text("\"G\" & 1 & \" X\" & 2.5"), "G1 X2.5");
}

#[test]
fn math_built_ins() {
    assert_eq!(value("Sqr(16)"), n(4.0));
    assert_eq!(value("Atn(1) * 4"), n(std::f64::consts::PI));
    assert_eq!(value("Round(Tan(Atn(1)), 12)"), n(1.0));
    assert_eq!(value("Sin(0) + Cos(0)"), n(1.0));
    assert_eq!(value("Round(Exp(2), 3)"), n(7.389));
    assert_eq!(value("Round(Log(100), 3)"), n(4.605)); // natural logarithm
    assert_eq!(value("Abs(-3) + Sgn(-2)"), n(2.0));
    assert_eq!(value("Int(-2.5)"), n(-3.0));
    assert_eq!(value("Fix(-2.5)"), n(-2.0));
    assert_eq!(value("Round(2.5)"), n(2.0)); // halves to even
    assert_eq!(value("Round(3.5)"), n(4.0));
    assert_eq!(value("Round(1.2345, 2)"), n(1.23));
    assert_eq!(value("CInt(2.5) + CInt(3.5)"), n(6.0));
    assert_eq!(value("CDbl(\"1.5\") * 2"), n(3.0));
    assert_eq!(value("Val(\" 1 2.5mm\")"), n(12.5));
    assert_eq!(value("IIf(2 > 1, 10, 20)"), n(10.0));
}

#[test]
fn text_built_ins() {
    assert_eq!(text("Format(44.2627417, \"0.000\")"), "44.263");
    assert_eq!(text("Format(1234.5, \"#,##0.00\")"), "1,234.50");
    assert_eq!(text("Format(-4.6, \"0.000\")"), "-4.600");
    assert_eq!(text("CStr(1 / 4) & CStr(True)"), "0.25True");
    assert_eq!(text("Len(\"abc\") & Left(\"abcdef\", 2) & Mid(\"abcdef\", 3, 2) & Right(\"abcdef\", 1)"), "3abcdf");
    assert_eq!(text("Mid(\"abcdef\", 4)"), "def");
    assert_eq!(text("UCase(\"g1x\") & LCase(\"M30\")"), "G1Xm30");
    assert_eq!(text("\"[\" & Trim(\"  a  b  \") & \"]\""), "[a  b]");
    assert_eq!(text("Left$(\"N0010\", 1) & InStr(\"G01 X5\", \"X\")"), "N5");
    assert_eq!(text("Replace(\"X1,5\", \",\", \".\")"), "X1.5");
}

#[test]
fn sheet_functions_are_callable_with_or_without_worksheetfunction() {
    assert_eq!(value("Application.WorksheetFunction.Sum(1, 2, 3)"), n(6.0));
    assert_eq!(value("WorksheetFunction.Max(4, 9, 2)"), n(9.0));
    assert_eq!(value("SUM(1, 2) + Atan2(1, 1) * 0"), n(3.0));
    // docs/domain.md §1, outer chamfer D=40 f=2 α=45 r=0.8 eA=eB=1: XA = 44.262742.
    assert_eq!(value("Round(CHAMFER_XA(\"outer\", 40, 2, 45, 0.8, 1, 1), 6)"), n(44.262742));
    // Excel's ROUND rounds halves away from zero, VBA's Round to even.
    assert_eq!(value("WorksheetFunction.Round(2.5, 0)"), n(3.0));
}

#[test]
fn arrays_with_bounds_redim_and_ubound() {
    let body = "    Dim a(1 To 3) As Double, b(2), i, s\n    For i = 1 To 3: a(i) = i * i: Next\n\
                \x20   Debug.Print LBound(a) & \"..\" & UBound(a) & \" \" & a(3) & \" \" & UBound(b)\n\
                \x20   ReDim Preserve a(1 To 4)\n    a(4) = 16\n    Debug.Print \"\" & Application.WorksheetFunction.Sum(a)\n\
                \x20   Dim m(1 To 2, 1 To 3)\n    m(2, 3) = 7\n    Debug.Print UBound(m, 1) & \"x\" & UBound(m, 2) & \" \" & m(2, 3)\n\
                \x20   s = Array(\"x\", \"z\")\n    Debug.Print s(0) & s(1) & UBound(s)";
    assert_eq!(printed(body), ["1..3 9 2", "30", "2x3 7", "xz1"]);
}

#[test]
fn with_block_and_end() {
    let mut wb = Workbook::with_sheet();
    let src =
        "Sub Main()\n    With Range(\"B2\")\n        .Value = 5\n        Debug.Print \"\" & .Value * 2 & .Address\n\
               \x20   End With\n    Stop2\n    Debug.Print \"not reached\"\nEnd Sub\n\
               Sub Stop2()\n    Debug.Print \"ending\"\n    End\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["10$B$2", "ending"]);
}

#[test]
fn debug_print_separators_and_msgbox() {
    let out = run("Sub Main()\n    Debug.Print \"a\"; \"b\", \"c\"\n    Debug.Print 5; -2\n    Debug.Print \"x\";\n\
                   \x20   Debug.Print \"y\"\n    Debug.Print\n    MsgBox \"done\"\nEnd Sub\n");
    // `;` joins, `,` moves to the next 14-column zone, a trailing `;` keeps the line open,
    // numbers get VBA's sign space before and a space after.
    assert_eq!(out.printed, ["ab            c", " 5 -2 ", "xy", ""]);
    assert_eq!(out.messages, ["done"]);
}

#[test]
fn the_sub_to_run_and_its_arguments_come_from_the_options() {
    let mut wb = Workbook::with_sheet();
    let src = "Sub Other()\n    Debug.Print \"other\"\nEnd Sub\nSub Cut(D As Double, Optional kind = \"outer\")\n\
               \x20   Debug.Print kind & \" \" & D * 2\nEnd Sub\n";
    let options = RunOptions {
        sub: Some("cut".into()),
        args: vec![("D".into(), "20.5".into()), ("kind".into(), "pipe".into())],
        ..RunOptions::default()
    };
    assert_eq!(vba::run(&mut wb, src, "t.bas", &options).unwrap().printed, ["pipe 41"]);
    // Without --sub: Main if there is one, else the first Sub that needs no arguments.
    assert_eq!(vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap().printed, ["other"]);
}

#[test]
fn attribute_lines_of_an_exported_module_are_ignored() {
    let out = run("Attribute VB_Name = \"Module1\"\nOption Explicit\nSub Main()\n    Debug.Print \"ok\"\nEnd Sub");
    assert_eq!(out.printed, ["ok"]);
}

#[test]
fn static_variables_keep_their_value_between_calls() {
    let out = run("Function Counter()\n    Static n As Long\n    Dim fresh\n    n = n + 1: fresh = fresh + 1\n\
                   \x20   Counter = n * 10 + fresh\nEnd Function\n\
                   Sub Main()\n    Debug.Print Counter() & \" \" & Counter() & \" \" & Counter()\nEnd Sub\n");
    assert_eq!(out.printed, ["11 21 31"]);
}

#[test]
fn option_base_one_moves_the_default_lower_bound() {
    let out = run("Option Base 1\nSub Main()\n    Dim a(3), b\n    b = Array(7, 8)\n\
                   \x20   Debug.Print LBound(a) & UBound(a) & LBound(b) & b(1)\nEnd Sub\n");
    assert_eq!(out.printed, ["1317"]);
}

#[test]
fn a_macro_runs_on_a_workbook_without_sheets() {
    let mut wb = Workbook::new();
    let src = "Sub Main()\n    [A1] = 2\n    Debug.Print \"\" & [A1] * 2\nEnd Sub\n";
    assert_eq!(vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap().printed, ["4"]);
}

#[test]
fn cells_keep_the_formula_language() {
    // The macro grammar shares the parser but adds nothing a cell can reach.
    let mut wb = Workbook::with_sheet();
    let at = |c: &str| parse_cell(c).unwrap();
    wb.set_input(0, at("A1"), "=1+\n2").unwrap();
    assert_eq!(wb.value(0, at("A1")), n(3.0), "a line break is a space in a formula");
    assert!(wb.set_input(0, at("A2"), "=7 Mod 2").is_err(), "Mod is not an Excel operator");
    wb.set_input(0, at("A3"), "=-2^2").unwrap();
    assert_eq!(wb.value(0, at("A3")), n(4.0));
    wb.set_input(0, at("A4"), "=VBA.SQR(16)+VBA.ROUND(2.5)").unwrap();
    assert_eq!(wb.value(0, at("A4")), n(6.0), "VBA's functions are rows of the one table");
}

/// A Date is days since 1899-12-30 with the time of day as the fraction ([MS-VBAL] 2.1, Date):
/// 6 PM is 0.75, 2 January 2026 is day 46024 (LibreOffice agrees: tests/vba_libreoffice.rs).
#[test]
fn date_literals_with_a_time_of_day() {
    assert_eq!(value("#1/2/2026 6:00:00 PM#"), n(46024.75));
    assert_eq!(value("#2026-01-02 18:00#"), n(46024.75));
    assert_eq!(value("#12:00 AM#"), n(0.0));
    assert_eq!(value("#12:00 PM#"), n(0.5));
    assert_eq!(value("#6:00:00 AM#"), n(0.25));
    // Two-digit years are 1930-2029.
    assert_eq!(value("#1/2/26#"), n(46024.0));
    assert_eq!(value("#1/1/30#"), n(10959.0));
}

/// Where LibreOffice's VBA mode is no oracle (it shares a Type value between variables, passes
/// `(y)` by reference, and rounds 2.5 up into an Integer), [MS-VBAL] decides: assigning a
/// Type value copies each field (5.4.3.8 Let of a UDT), an argument in parentheses is an
/// expression and so passed by value (5.3.1.11), and an Integer rounds halves to even (5.5.1.2.1).
#[test]
fn type_values_copy_and_parenthesised_arguments_pass_by_value() {
    let out = run("Type Pt\n    X As Double\n    N As Integer\nEnd Type\n\
                   Sub Times10(a)\n    a = a * 10\nEnd Sub\n\
                   Sub Main()\n    Dim p As Pt, q As Pt, y\n    p.X = 3\n    q = p\n    q.X = 10\n\
                   \x20   p.N = 2.5\n    y = 1\n    Times10 (y)\n\
                   \x20   Debug.Print p.X & \" \" & q.X & \" \" & p.N & \" \" & y\nEnd Sub\n");
    assert_eq!(out.printed, ["3 10 2 1"]);
}

#[test]
fn type_misuse_is_named() {
    let mut wb = Workbook::with_sheet();
    let src = "Type Pt\n    X As Double\nEnd Type\nSub Main()\n    Dim p As Pt\n    p.Z = 1\nEnd Sub\n";
    let e = vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("Type Pt has no field Z"), "{e}");
    let src = "Type Pt\n    X As Double\nEnd Type\nSub Main()\n    Dim p As Pt\n    Debug.Print p\nEnd Sub\n";
    let e = vba::run(&mut wb, src, "t.bas", &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("p is a Type value"), "{e}");
}

/// [MS-VBAL] 3.3.2: `&H` hex and `&O` (or bare `&`) octal literals are Integers when the
/// digits fit 16 bits, two's complement (`&HFFFF` = -1, `&H8000` = -32768), else Longs
/// (`&H10000` = 65536, `&HFFFFFFFF` = -1); a `&` suffix makes a Long (`&HFFFF&` = 65535).
#[test]
fn hex_and_octal_literals_are_typed_as_vba_types_them() {
    let cases = [
        ("&H1F", 31.0),
        ("&hff", 255.0),
        ("&HFFFF", -1.0),
        ("&H8000", -32768.0),
        ("&HFFFF&", 65535.0),
        ("&H10000", 65536.0),
        ("&HFFFFFFFF", -1.0),
        ("&O17", 15.0),
        ("&17", 15.0),
        ("&H10 + 1", 17.0),
    ];
    for (expr, want) in cases {
        assert_eq!(value(expr), n(want), "{expr}");
    }
}

// ---- issue 31: VBA's semantics for New, Const, negation and Date ----------------------

/// A macro run with the project's class modules (name, source), failing or not.
fn with_classes(main: &str, classes: &[(&str, &str)]) -> Result<RunOutput, vba::MacroError> {
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, main, "test.bas", &RunOptions { classes, ..RunOptions::default() })
}

/// A macro's failure.
fn failure(src: &str) -> vba::MacroError {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "test.bas", &RunOptions::default()).expect_err("the macro fails")
}

/// A class that says when an object of it is made and let go, and counts its objects.
const PROBE: &str = "Public Field As Long\nPrivate Sub Class_Initialize()\n    Debug.Print \"init\"\nEnd Sub\n\
    Private Sub Class_Terminate()\n    Debug.Print \"term\"; Field\nEnd Sub\n";

// [MS-VBAL] 5.2.3.1.4 "Variable Declarations" (auto-instantiation): a variable declared
// `As New` holds Nothing until it is used; using it then makes a new object, so the object
// is made at the first use, not at the Dim; `Set x = Nothing` lets the object go and the
// next use makes another; `x Is Nothing` uses x, so it is never True. ("Dim statement": New
// "enables implicit creation of an object".)
#[test]
fn dim_as_new_makes_the_object_at_its_first_use() {
    let main = "Sub Main()\n    Dim x As New Probe\n    Debug.Print \"declared\"\n    x.Field = 1\n\
                \x20   Set x = Nothing\n    Debug.Print \"let go\"\n    Debug.Print x.Field\n    Debug.Print x Is Nothing\n\
                \x20   Set x = Nothing\n    Debug.Print x Is Nothing\n    Set x = Nothing\n    Debug.Print TypeName(x)\nEnd Sub\n";
    let out = with_classes(main, &[("Probe", PROBE)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        out.printed,
        [
            "declared", "init", "term 1 ", "let go", "init", " 0 ", "False", "term 0 ", "init", "False", "term 0 ",
            "init", "Probe", "term 0 "
        ]
    );
}

// [MS-VBAL] 5.2.3.2 "Const Declarations": a constant with an `As` clause has the declared
// type, its value let-coerced to it (5.5.1.2.1: to Integer by banker's rounding, so 2.5 is
// 2 and 3.5 is 4); a value past the type's range is "Overflow (Error 6)".
#[test]
fn a_typed_constant_is_converted_to_its_type() {
    let out =
        printed("    Const C As Integer = 2.5, D As Long = 3.5, S As String = 12\n    Debug.Print C; D; S & \"!\"");
    assert_eq!(out, [" 2  4 12!"]);
    let e = failure("Sub Main()\n    Const X As Integer = 40000\n    Debug.Print X\nEnd Sub\n");
    assert!(e.message.contains("run-time error 6"), "{e}");
    assert_eq!(e.span.unwrap().line, 2, "{e}");
    // A constant's declared type is its expressions': Integer * Integer overflows (5.6.9.3).
    let e = failure("Const K As Integer = 200\nSub Main()\n    x = K * K\nEnd Sub\n");
    assert!(e.message.contains("run-time error 6"), "{e}");
}

// [MS-VBAL] 5.6.9.3.1 "Unary - Operator": the result has the operand's declared type, and
// "if the result overflows the range of the declared type, runtime error 6 (Overflow) is
// raised": the Integer -32,768 and the Long -2,147,483,648 have no positive of their type.
#[test]
fn negating_the_most_negative_integer_or_long_overflows() {
    for (ty, min) in [("Integer", "-32768"), ("Long", "-2147483648")] {
        let e = failure(&format!("Sub Main()\n    Dim x As {ty}\n    x = {min}\n    y = -x\nEnd Sub\n"));
        assert!(e.message.contains("run-time error 6"), "{ty}: {e}");
        assert_eq!(e.span.unwrap().line, 4, "{e}");
    }
    // A Variant widens, and an Integer's other values negate.
    assert_eq!(
        printed("    Dim x As Integer, v\n    x = -32767: v = -32768\n    Debug.Print -x; -v"),
        [" 32767  32768 "]
    );
    let out = printed(
        "    Dim x As Integer\n    x = -32768\n    On Error Resume Next\n    y = -x\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 6 "]);
}

// "Terminate event": it "occurs when all references to an instance of an object are removed
// from memory": an object whose last reference was a Collection's or a Dictionary's entry is
// terminated when the entry is removed (Remove, RemoveAll), replaced, or when the Collection
// itself goes; one still held by a variable is not.
#[test]
fn objects_only_a_collection_held_are_terminated_when_it_lets_them_go() {
    let main = "Function Made(n)\n    Dim p As Probe\n    Set p = New Probe\n    p.Field = n\n    Set Made = p\nEnd Function\n\
                Sub Main()\n    Dim c As Collection, d As Object, kept As Probe\n    Set c = New Collection\n\
                \x20   c.Add Made(1)\n    c.Add Made(2)\n    Set kept = c(2)\n    c.Remove 1\n    c.Remove 1\n\
                \x20   Debug.Print \"removed\"\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    d.Add \"a\", Made(3)\n\
                \x20   d.Add \"b\", Made(4)\n    Set d(\"b\") = Made(5)\n    d.RemoveAll\n    Debug.Print \"cleared\"\n\
                \x20   c.Add Made(6)\n    Set c = Nothing\n    Debug.Print \"end\"\nEnd Sub\n";
    let out = with_classes(main, &[("Probe", PROBE)]).unwrap_or_else(|e| panic!("{e}"));
    let mut lines: Vec<&str> = out.printed.iter().map(String::as_str).filter(|l| *l != "init").collect();
    // RemoveAll lets both go; the reference names no order between them.
    lines[3..5].sort_unstable();
    assert_eq!(lines, ["term 1 ", "removed", "term 4 ", "term 3 ", "term 5 ", "cleared", "term 6 ", "end", "term 2 "]);
}

// [MS-VBAL] 2.1.1.1 "Date" and 3.3.3 "Date Tokens": `Dim d As Date` is a Date (TypeName
// "Date", VarType 7, vbDate, "VarType function"), `#1/2/2024#` and `#12:30:00 PM#` are Date
// literals; 5.6.9.3.3 and 5.6.9.3.4: a Date plus or minus a number is a Date (the next day
// for + 1), a Date minus a Date the Double of the days between; dates compare as points in
// time. A Date made a String ("Print # statement": "the standard short date format", and
// only the part, date or time, that is there) shows as the en-US locale writes it; Debug.Print,
// MsgBox and `&` show that text, not the day count. "Type conversion functions": CDate gives
// a Date; "Now function": "Returns a Variant (Date)"; a Variant assigned a Date holds a Date
// (VarType 7) until assigned something else; a String assigned a Date holds its text.
#[test]
fn date_is_a_type_with_literals_arithmetic_and_text() {
    let out = printed(
        "    Dim d As Date, e As Date, t As Date\n    d = #1/2/2024#\n    e = d + 1\n    t = #12:30:00 PM#\n\
         \x20   Debug.Print TypeName(d); VarType(d); TypeName(#1/2/2024#)\n    Debug.Print d\n    Debug.Print e\n\
         \x20   Debug.Print t\n    Debug.Print d + t\n    Debug.Print e - d; e > d; d = #2024-01-02#\n\
         \x20   Debug.Print \"on \" & e\n    Debug.Print CDate(\"1/2/2024\") + 1\n    Debug.Print TypeName(CDate(45000)); TypeName(Now)\n\
         \x20   v = d: w = v + 1\n    Debug.Print v; \" \"; w; \" \"; TypeName(v); VarType(w)\n    v = \"x\"\n    Debug.Print v; TypeName(v)\n    Dim s As String\n    s = d\n    Debug.Print s",
    );
    assert_eq!(
        out,
        [
            "Date 7 Date",
            "1/2/2024",
            "1/3/2024",
            "12:30:00 PM",
            "1/2/2024 12:30:00 PM",
            " 1 TrueTrue",
            "on 1/3/2024",
            "1/3/2024",
            "DateDate",
            "1/2/2024 1/3/2024 Date 7 ",
            "xString",
            "1/2/2024",
        ]
    );
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n    Dim d As Date\n    d = #1/2/2024#\n    MsgBox d - 1\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "test.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.messages, ["1/1/2024"]);
}

// "Print # statement": dates are written in the short date format, only the part there;
// "Write # statement": "Date data is written to the file by using the universal date
// format" (#yyyy-mm-dd hh:mm:ss#, hours 0 to 23; its example: "#1994-07-13#").
#[test]
fn print_and_write_to_a_file_write_dates_as_vba_does() {
    use ncsheet::vba::FileAccess;
    let src = "Sub Main()\n    Dim d As Date\n    d = #7/13/1994#\n    Open \"OUT.TXT\" For Output As #1\n\
               \x20   Print #1, d; \"|\"; d + #1:05:09 PM#\n    Write #1, d, d + #1:05:09 PM#, #13:05:09#, 1\n    Close #1\nEnd Sub\n";
    let files = FileAccess {
        out_dir: Some("out".into()),
        inputs: Vec::new(),
        read_out_dir: std::rc::Rc::new(|_| Ok(None)),
        list_out_dir: std::rc::Rc::new(|| Ok(Vec::new())),
        modified_out_dir: std::rc::Rc::new(|_| Ok(None)),
    };
    let options = RunOptions { files: Some(files), ..RunOptions::default() };
    let out = vba::run(&mut Workbook::with_sheet(), src, "test.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    let text = String::from_utf8(out.files[0].1.clone()).unwrap();
    assert_eq!(text, "7/13/1994|7/13/1994 1:05:09 PM\r\n#1994-07-13#,#1994-07-13 13:05:09#,#13:05:09#,1\r\n");
}

// [MS-VBAL] 5.4.3.9 "Set Statement" with an index expression as its target, and "Using
// arrays" / "Dim statement" (`Dim a(3) As Class1`: an array whose items hold objects, each
// Nothing until set): `Set a(i) = New Class1` puts a reference in the item, `a(i).Field`
// reaches the object's member, two items may share one object, an item is passed to a
// procedure as the object, `ReDim Preserve` keeps the items, For Each goes through them,
// and an object only an item held is terminated when the item is set to another, or when
// the array goes at the end of its procedure.
#[test]
fn arrays_hold_objects() {
    let main = "Sub Bump(p As Probe)\n    p.Field = p.Field + 100\nEnd Sub\n\
                Sub Main()\n    Dim a(3) As Probe, total As Long\n    Set a(0) = New Probe\n    a(0).Field = 1\n\
                \x20   Set a(1) = a(0)\n    a(1).Field = a(1).Field + 1\n    Debug.Print a(0).Field; a(2) Is Nothing; a(0) Is a(1)\n\
                \x20   Bump a(1)\n    ReDim Preserve a(5)\n    Set a(5) = New Probe\n    a(5).Field = 10\n\
                \x20   For Each p In a\n        If Not p Is Nothing Then total = total + p.Field\n    Next\n\
                \x20   Set p = Nothing\n    Debug.Print total; UBound(a)\n    Set a(0) = Nothing\n    Debug.Print \"one left\"\n\
                \x20   Set a(1) = New Probe\n    Debug.Print \"end\"\nEnd Sub\n";
    let out = with_classes(main, &[("Probe", PROBE)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        out.printed,
        ["init", " 2 TrueTrue", "init", " 214  5 ", "one left", "init", "term 102 ", "end", "term 0 ", "term 10 "],
    );
    // An array of values cannot hold an object: "Type mismatch".
    let e = with_classes("Sub Main()\n    Dim a(3) As Long\n    Set a(0) = New Probe\nEnd Sub\n", &[("Probe", PROBE)])
        .unwrap_err();
    assert!(e.message.contains("type mismatch"), "{e}");
    assert_eq!(e.span.unwrap().line, 3, "{e}");
}

// "Implements statement" ([MS-VBAL] 5.2.4.2, implements directive): a class module that
// `Implements IShape` provides IShape's members as its procedures `IShape_Member`, usually
// Private, and an object of it used as an IShape runs them: `shape.Area` of a Circle runs
// Circle's `IShape_Area`; one procedure takes objects of every class implementing IShape.
#[test]
fn a_class_implements_an_interface_with_its_interface_procedures() {
    let shape = "Public Function Area() As Double\nEnd Function\nPublic Property Get Name() As String\nEnd Property\n";
    let circle = "Implements IShape\nPublic R As Double\n\
                  Private Function IShape_Area() As Double\n    IShape_Area = 3 * R * R\nEnd Function\n\
                  Private Property Get IShape_Name() As String\n    IShape_Name = \"circle\"\nEnd Property\n";
    let square = "Option Explicit\nImplements IShape\nPublic Side As Double\n\
                  Private Function IShape_Area() As Double\n    IShape_Area = Side * Side\nEnd Function\n\
                  Private Property Get IShape_Name() As String\n    IShape_Name = \"square\"\nEnd Property\n";
    let main = "Sub Show(s As IShape)\n    Debug.Print s.Name; s.Area\nEnd Sub\n\
                Sub Main()\n    Dim c As New Circle, q As New Square, s As IShape\n    c.R = 2\n    q.Side = 3\n\
                \x20   Show c\n    Set s = q\n    Show s\nEnd Sub\n";
    let classes = [("IShape", shape), ("Circle", circle), ("Square", square)];
    let out = with_classes(main, &classes).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["circle 12 ", "square 9 "]);
}

// [MS-VBAL] 5.6.7 "TypeOf…Is Expressions": True when the object's type is the type named,
// when its class implements the interface named, and for `Object` with any object; `Not`
// applies to the whole test. Nothing is of no type: False, as the "If...Then...Else
// statement" reference page says of `TypeOf objectname Is objecttype` ("True if objectname
// is of the object type specified by objecttype; otherwise it is False").
#[test]
fn typeof_is_tests_an_objects_type() {
    let shape = "Public Function Area() As Double\nEnd Function\n";
    let circle = "Implements IShape\nPrivate Function IShape_Area() As Double\nEnd Function\n";
    let main = "Sub Main()\n    Dim c As New Collection, k As Circle, r As Range, o As Object, v\n\
                \x20   Set k = New Circle\n    Set r = Range(\"A1:B2\")\n    Set v = ActiveSheet\n\
                \x20   Debug.Print TypeOf c Is Collection, TypeOf c Is VBA.Collection, TypeOf c Is Range, TypeOf c Is Object\n\
                \x20   Debug.Print TypeOf k Is Circle, TypeOf k Is IShape, TypeOf k Is Collection\n\
                \x20   Debug.Print TypeOf r Is Range, TypeOf r Is Excel.Range, TypeOf v Is Worksheet, TypeOf v Is Range\n\
                \x20   Debug.Print TypeOf o Is Object, Not TypeOf o Is Collection, Not TypeOf c Is Collection\n\
                \x20   If TypeOf c Is Collection And Not TypeOf r Is Worksheet Then Debug.Print \"both\"\nEnd Sub\n";
    let out = with_classes(main, &[("IShape", shape), ("Circle", circle)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        out.printed,
        [
            "True          True          False         True",
            "True          True          False",
            "True          True          True          False",
            "False         True          False",
            "both"
        ]
    );
}

// An object variable not yet Set holds Nothing ([MS-VBAL] 5.2.3.1.3, the default value of a
// variable of an object type is Nothing): "TypeName function" gives "Nothing", "VarType
// function" vbObject (9), "IsObject function" True ("IsObject returns True if identifier is
// a variable declared with Object type or any valid class type"), `Is Nothing` True; a
// Variant not yet assigned is Empty (0, False).
#[test]
fn an_unset_object_variable_holds_nothing() {
    let probe = "Public Field As Long\n";
    let main = "Function Maker() As Object\nEnd Function\n\
                Sub Main()\n    Dim o As Object, c As Collection, p As Probe, w As Worksheet, v\n\
                \x20   Debug.Print TypeName(o); \" \"; TypeName(c); \" \"; TypeName(p); \" \"; TypeName(w); \" \"; TypeName(v)\n\
                \x20   Debug.Print VarType(o); VarType(c); VarType(p); VarType(v)\n\
                \x20   Debug.Print IsObject(o); IsObject(p); IsObject(v); o Is Nothing; p Is Nothing\n\
                \x20   Debug.Print TypeName(Maker()); Maker() Is Nothing\nEnd Sub\n";
    let out = with_classes(main, &[("Probe", probe)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        out.printed,
        ["Nothing Nothing Nothing Nothing Empty", " 9  9  9  0 ", "TrueTrueFalseTrueTrue", "NothingTrue"]
    );
}

// "Initialize, Terminate events": Terminate runs when the last reference to an object goes.
// The end of a run is the end of its program, so the objects module-level and Static
// variables still hold go then, their Class_Terminate run (module variables in the order
// declared); a run ended by `End` removes them without it (the same page: "if your
// application invokes the End statement … the Terminate event isn't triggered").
#[test]
fn module_and_static_objects_are_terminated_at_the_runs_end() {
    let main = "Private first As Probe, second As Object\n\
                Sub Keep()\n    Static kept As Probe\n    If kept Is Nothing Then Set kept = New Probe: kept.Field = 3\nEnd Sub\n\
                Sub Main()\n    Set second = New Probe\n    second.Field = 2\n    Set first = New Probe\n    first.Field = 1\n\
                \x20   Keep\n    Keep\n    Debug.Print \"end of Main\"\nEnd Sub\n";
    let out = with_classes(main, &[("Probe", PROBE)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["init", "init", "init", "end of Main", "term 1 ", "term 2 ", "term 3 "]);
    let ended = main.replace("Debug.Print \"end of Main\"", "Debug.Print \"end of Main\"\n    End");
    let out = with_classes(&ended, &[("Probe", PROBE)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["init", "init", "init", "end of Main"]);
}

// "+ operator" (Office VBA language reference): two String expressions, or two Variants
// holding Strings, are concatenated; a String and a number are added ("1" + 2 is 3).
#[test]
fn plus_joins_two_strings_and_adds_a_string_to_a_number() {
    let out = printed(
        "    Dim s As String, v\n    s = \"36\"\n    v = \"1\"\n\
         \x20   Debug.Print s + Chr(34); \" \"; v + \"2\"; \" \"; v + 2; \" \"; \"a\" + \"b\" + \"c\"",
    );
    assert_eq!(out, ["36\" 12  3  abc"]);
}

// An array variable followed by empty parentheses is the whole array: the way a call passes
// an array ("Call statement" and "Function statement": an array argument `a()` for an array
// parameter), here to a ByRef parameter that sorts it in place.
#[test]
fn an_array_passed_with_empty_parentheses_is_the_whole_array() {
    let out = run("Sub SortUp(ByRef xs() As Variant)\n    Dim i As Integer, j As Integer, t\n\
                   \x20   For i = LBound(xs) To UBound(xs)\n        For j = i + 1 To UBound(xs)\n\
                   \x20           If xs(j) < xs(i) Then t = xs(i): xs(i) = xs(j): xs(j) = t\n\
                   \x20       Next j\n    Next i\nEnd Sub\n\
                   Function Total(xs()) As Double\n    Dim x\n    For Each x In xs\n        Total = Total + x\n    Next\nEnd Function\n\
                   Sub Main()\n    Dim a() As Variant\n    a = Array(3, 1, 2)\n    Call SortUp(a())\n\
                   \x20   Debug.Print a(0); a(1); a(2); Total(a())\nEnd Sub\n");
    assert_eq!(out.printed, [" 1  2  3  6 "]);
}

/// [MS-VBAL] 3.3.5.3 (type characters): a name may be used with the type character it was
/// declared with, and names the same variable (`Dim living%` … `living% = True`, `Loop While
/// living%`), as line-numbered and older modules write it. `a&b` still joins and `x^2` is still a
/// power ([MS-VBAL] 5.6.9.5, 5.6.9.3.7): a type character is read only where no operand follows.
#[test]
fn a_name_used_with_its_type_character_is_the_same_variable() {
    let out = printed(
        "    Dim living%, n&, total#, a, b, x\n    living% = True\n    n& = 0\n    Do\n        n& = n& + 1\n        If n >= 3 Then living% = False\n    Loop While living%\n    total# = n& / 2\n    a = \"p\": b = \"q\": x = 3\n    Debug.Print n; living; total; a&b; x^2",
    );
    // An Integer holds True as -1 and False as 0 ("Boolean data type": "When other numeric types
    // are converted to Boolean values, 0 becomes False … True is stored as -1").
    assert_eq!(out, vec![" 3  0  1.5 pq 9 "]);
}

/// `Erl`: the line number of the line the error was raised on, 0 where the procedure has none
/// (Microsoft's "Erl Property (Err Object)": `10 On Error Resume Next` / `20 Err.Raise(60000)`
/// "Returns 20"; "If Visual Basic encounters no line numbers, it returns 0"). Line-numbered
/// modules print it in their error handlers; it was an undeclared Empty.
#[test]
fn erl_is_the_line_number_the_error_was_raised_on() {
    let src = "Sub Main()\n10  On Error Resume Next\n20  Err.Raise 60000\n30  Debug.Print Erl\n    Handled\n    Plain\nEnd Sub\n\
               Sub Handled()\n10  On Error GoTo bad\n20  Dim x\n30  x = 1 / 0\n40  Exit Sub\nbad:\n50  Debug.Print Err.Number; Erl\nEnd Sub\n\
               Sub Plain()\n    On Error Resume Next\n    Err.Raise 5\n    Debug.Print Erl\nEnd Sub\n";
    assert_eq!(run(src).printed, vec![" 20 ", " 11  30 ", " 0 "]);
}

/// "IsDate function": "Returns True if the expression is a date or is recognizable as a valid
/// date or time; otherwise, it returns False" — a Date literal or variable, `Now`, and text
/// such as "2024-01-15", "12:30" or "January 5, 2020"; not a number, nor number text, nor Empty.
#[test]
fn is_date_answers_dates_and_text_that_reads_as_one() {
    let out = printed(
        "    Dim d As Date\n    d = #1/2/2020#\n    Debug.Print IsDate(\"2024-01-15\"); IsDate(\"abc\"); IsDate(#1/2/2020#); IsDate(5); \
         IsDate(\"5\"); IsDate(d); IsDate(Now); IsDate(\"12:30\"); IsDate(\"January 5, 2020\"); IsDate(Empty)",
    );
    assert_eq!(out, vec!["TrueFalseTrueFalseFalseTrueTrueTrueTrueFalse"]);
}

/// "Workbook.Application property": the Application object, so
/// `ThisWorkbook.Application.WorksheetFunction.Max(…)` is Application's own worksheet function.
#[test]
fn a_workbooks_application_reaches_the_worksheet_functions() {
    let out = printed(
        "    Debug.Print ThisWorkbook.Application.WorksheetFunction.Max(3, 7, 5); ThisWorkbook.Application.Min(4, 2)",
    );
    assert_eq!(out, vec![" 7  2 "]);
}

/// "Windows.Application property", "Worksheet.Application property": each "Returns an
/// Application object that represents the Microsoft Excel application", so a worksheet function
/// reached through the windows or the active sheet is Application's own. A real module
/// (TrimSpacesFx, session 26's h5/r13) writes `Windows.Application.WorksheetFunction.Trim(…)`;
/// "Trim" (Excel's TRIM) keeps one space between words.
#[test]
fn the_windows_and_sheets_application_reaches_the_worksheet_functions() {
    let out = printed(
        "    Debug.Print Windows.Application.WorksheetFunction.Trim(\"  a   b \") & \"|\"; ActiveSheet.Application.Max(4, 9)",
    );
    assert_eq!(out, vec!["a b| 9 "]);
}

/// "Application.WorksheetFunction property": "Returns the WorksheetFunction object", which a
/// module keeps in a variable (`Dim wsf As Object: Set wsf = Application.WorksheetFunction`,
/// then `wsf.Trim(wsf.Clean(wsf.Substitute(v, Chr(160), "")))` in a real module, the-mad-statter's
/// I2DB_TRIM); each member is the worksheet function, raising run-time error 1004 for an error
/// result as WorksheetFunction's members do ("WorksheetFunction object"). TypeName is
/// "WorksheetFunction". A variable also Set to something else is refused by name when it calls
/// one, not run as some other object.
#[test]
fn a_variable_set_to_worksheetfunction_calls_the_worksheet_functions() {
    let out = printed(
        "    Dim wsf As Object, wf As WorksheetFunction\n    Set wsf = Application.WorksheetFunction\n    Set wf = WorksheetFunction\n\
         \x20   Debug.Print wsf.Max(3, 7, 5); wf.Min(4, 2); TypeName(wsf); \" [\" & wsf.Trim(wsf.Clean(\"  a \" & Chr(7) & \"  b \")) & \"]\"\n\
         \x20   On Error Resume Next\n    Debug.Print wf.Match(9, Array(1, 2), 0)\n    Debug.Print Err.Number",
    );
    assert_eq!(out, vec![" 7  2 WorksheetFunction [a b]", " 1004 "]);
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n    Dim o As Object\n    Set o = WorksheetFunction\n    Set o = Sheets(1)\n    x = o.Max(1, 2)\nEnd Sub\n";
    let e = vba::run(&mut wb, src, "test.bas", &RunOptions::default()).unwrap_err();
    assert!(e.message.contains("WorksheetFunction.Max") || e.message.contains("Max"), "{e}");
}

/// "Worksheet.Application property", "Range.Application property": each "Returns an
/// Application object that represents the Microsoft Excel application", so a worksheet function
/// reached through a sheet or a range the macro names or holds in a variable is Application's
/// own; the object is still looked up first, and a sheet the workbook lacks is "Subscript out
/// of range (Error 9)" as `Sheets("Nope")` alone is.
#[test]
fn any_objects_application_reaches_the_worksheet_functions() {
    let out = printed(
        "    Dim ws As Worksheet, x As Variant\n    Set ws = Worksheets(1)\n    [A1] = 3: [A2] = 7\n    \
         Debug.Print Worksheets(1).Application.WorksheetFunction.Max(1, 5); ws.Application.Max(ws.Range(\"A1:A2\")); \
         ws.Range(\"A1\").Application.Sum(2, 3)\n    On Error Resume Next\n    \
         x = Sheets(\"Nope\").Application.WorksheetFunction.Max(1, 5)\n    Debug.Print Err.Number; IsEmpty(x)",
    );
    assert_eq!(out, vec![" 5  7  5 ", " 9 True"]);
}
