//! VBA's own semantics where ncsheet used to differ (issue 31, scope 1): a macro written for
//! Excel gives Excel's result, or is refused with the reason. Each test cites the page of
//! Microsoft's VBA reference or the section of [MS-VBAL] (the VBA language specification)
//! its expected value comes from.

mod common;

use common::vba::{main_fails, printed_after, run_main};
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::RunOptions;
use ncsheet::workbook::Workbook;

/// A workbook of one sheet whose VBA project is one standard module, Module1, holding
/// `source`, installed as the workbook's own functions; `cells` typed in after.
fn book_with_functions(source: &str, cells: &[(&str, &str)]) -> Workbook {
    let mut wb = Workbook::with_sheet();
    let project = common::vba::module1(source);
    assert!(ncsheet::vba::install_functions(&mut wb, &project, RunOptions::default()).is_empty());
    for (cell, text) in cells {
        wb.set_input(0, parse_cell(cell).unwrap(), text).unwrap();
    }
    wb
}

// ---- item 1: a function in a cell sees the number format the running macro set ----------

/// Excel VBA reference, "Range.Text property": the formatted text of the cell. A function
/// called from a cell reads the same cell's look the macro that is running gave it.
#[test]
fn a_cell_function_reading_text_sees_the_format_the_macro_set() {
    let mut wb = book_with_functions(
        "Public Function Shown(r As Range) As String\n    Shown = r.Text\nEnd Function\n",
        &[("B1", "=Shown(A1)")],
    );
    let printed = run_main(
        &mut wb,
        "    Range(\"A1\").NumberFormat = \"0.00\"\n    Range(\"A1\").Value = 1.5\n    Debug.Print Range(\"B1\").Value",
    );
    assert_eq!(printed, ["1.50"]);
}

// ---- item 5: For Each goes through an array only with a Variant -------------------------

/// VBA reference, "For Each control variable must be Variant or Object" (and "… on arrays
/// must be Variant"); [MS-VBAL] 5.4.2.4 lets each item be let-assigned, which into an Integer
/// would round 1.5 and 2.5 to 2 and 2. VBA refuses the procedure instead, and no handler
/// traps a compile error.
#[test]
fn for_each_with_an_integer_control_variable_is_refused() {
    let message = main_fails(
        &mut Workbook::with_sheet(),
        "    On Error Resume Next\n    Dim m As Integer\n    For Each m In Array(1.5, 2.5)\n        Debug.Print m\n    Next",
    );
    assert!(message.contains("For Each control variable must be Variant or Object"), "{message}");
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "    Dim m As Variant\n    For Each m In Array(1.5, 2.5)\n        Debug.Print CStr(m)\n    Next",
    );
    assert_eq!(printed, ["1.5", "2.5"]);
}

// ---- item 3: number text as VBA reads it ----------------------------------------------

/// "IsNumeric function": True when the whole expression is recognized as a number; VBA
/// recognizes the literals of [MS-VBAL] 3.3.2 in text: `&H10` (16), `&O17` (15) and a Double
/// with a D exponent (`1d2`, 100), as CDbl, CLng and a String assigned to a Double do
/// (LibreOffice's VBA mode agrees: tests/vba_libreoffice.rs number_text_as_vba_reads_it).
#[test]
fn hexadecimal_octal_and_d_exponent_text_are_numbers() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Debug.Print IsNumeric(\"&H10\"); IsNumeric(\"&O17\"); IsNumeric(\"1d2\"); IsNumeric(\"1D-2\")\n\
         \x20   Debug.Print IsNumeric(\"&H\"); IsNumeric(\"&HG1\"); IsNumeric(\"1d\"); IsNumeric(\"d2\")\n\
         \x20   Debug.Print CStr(CDbl(\"1d2\")); \"|\"; CStr(CLng(\"&H10\")); \"|\"; CStr(CInt(\" &O17 \"))\n\
         \x20   Dim d As Double\n    d = \"2.5D1\"\n    Debug.Print CStr(d)",
    );
    assert_eq!(printed, ["TrueTrueTrueTrue", "FalseFalseFalseFalse", "100|16|15", "25"]);
}

// ---- item 2: `^` without a real value is Invalid procedure call --------------------------

/// VBA reference, "^ operator": "A number can be negative only if exponent is an integer
/// value"; breaking it is run-time error 5, "Invalid procedure call or argument" ("Trappable
/// errors"), and so is 0 raised to a negative power, which has no value either. A result past
/// a Double's range stays Overflow (6); `(-8) ^ 3` is -512 by hand.
#[test]
fn a_power_without_a_real_value_is_invalid_procedure_call() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim x\n    On Error Resume Next\n\
         \x20   x = (-8) ^ (1 / 3)\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   x = 0 ^ -1\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   x = 10 ^ 400\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   x = (-8) ^ 3\n    Debug.Print Err.Number; CStr(x)",
    );
    assert_eq!(printed, [" 5 ", " 5 ", " 6 ", " 0 -512"]);
}

// ---- item 6: a Type's field keeps its declared type -------------------------------------

/// [MS-VBAL] 5.2.3.3 (a Type's elements are declared with their types) and "TypeName
/// function" / "VarType function": an Integer field answers "Integer" (2), a Single field
/// "Single" (4), a Currency field "Currency" (6); and Integer arithmetic on the field
/// overflows as an Integer's does ("Overflow (Error 6)": 300 * 200 is past 32,767).
#[test]
fn a_type_field_answers_its_declared_type() {
    let printed = printed_after(
        "Type Inner\n    l As Long\nEnd Type\n\
         Type Pt\n    n As Integer\n    s As Single\n    c As Currency\n    inner As Inner\nEnd Type",
        "    Dim p As Pt, a(1) As Pt\n    p.n = 300: p.s = 1.5: p.c = 2.5: p.inner.l = 7: a(1).n = 1\n\
         \x20   Debug.Print TypeName(p.n); \" \"; TypeName(p.s); \" \"; TypeName(p.c); \" \"; TypeName(p.inner.l); \" \"; TypeName(a(1).n)\n\
         \x20   Debug.Print VarType(p.n); VarType(p.s); VarType(p.c)\n\
         \x20   On Error Resume Next\n    Dim x\n    x = p.n * 200\n    Debug.Print Err.Number",
    );
    assert_eq!(printed, ["Integer Single Currency Long Integer", " 2  4  6 ", " 6 "]);
}

// ---- item 8: a block's closer with no such block open ------------------------------------

/// The VBA reference's compile errors "End If without block If" (an `End If` after a
/// one-line If, which has none), "Next without For", "Loop without Do", "Wend without While".
#[test]
fn a_closer_without_its_block_says_so_as_vba_does() {
    let cases = [
        ("    Dim i\n    For i = 1 To 2\n    If i = 0 Then i = 1\n    End If\n    Next", "End If without block If"),
        ("    Dim x\n    If x = 0 Then x = 1\n    End If", "End If without block If"),
        ("    Dim x\n    x = 1\n    Next", "Next without For"),
        ("    Dim x\n    x = 1\n    Loop", "Loop without Do"),
        ("    Dim x\n    x = 1\n    Wend", "Wend without While"),
    ];
    for (body, message) in cases {
        let got = main_fails(&mut Workbook::with_sheet(), body);
        assert!(got.contains(message), "{body}: {got}");
    }
}
