//! VBA's conversions where the macro language followed the formula language (issue 31,
//! scope 1): a number's text, a String read as a number by arithmetic, the type IIf's
//! Variant holds, the Overflow of Abs. Each test cites where its expected value comes from.

mod common;

use common::vba::{main_fails, run_main};
use ncsheet::workbook::Workbook;

// ---- a number's text ---------------------------------------------------------------------

/// OLE Automation's VarBstrFromR8 and VarBstrFromR4, which VBA's CStr, Str, `&`, Print and a
/// String variable use, write C's `%.15G` and `%.7G` (Wine's oleaut32 implements them so;
/// the values here are Python's `'%.15G' % x` and `'%.7G' % x`): positional from 1E-04 to
/// below 10^15 (10^7 for a Single), `1.5E-07` and `1E+15` outside. LibreOffice's Basic
/// differs (it writes 0.00000015 and 1000000000000000), so it is no oracle here.
#[test]
fn numbers_are_text_as_vba_writes_them() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        r#"    Debug.Print CStr(1.5E-7); "|"; CStr(-1.5E-7); "|"; CStr(1E-5); "|"; CStr(0.0001)
    Debug.Print CStr(1E15); "|"; CStr(1E16); "|"; CStr(123456789012345678#); "|"; CStr(1.5E+300)
    Debug.Print CStr(0.1 + 0.2); "|"; CStr(CSng(1 / 3)); "|"; CStr(CSng(12345678)); "|"; CStr(CSng(1E-5))
    Debug.Print "x" & 1.5E-7; "|"; Str(1.5E-7); "|"; Str(CSng(12345678)); "|"; CSng(12345678) & ""
    Dim s As String, f As Single
    s = 0.00001234
    f = 10000000
    Debug.Print s; "|"; Format(1.5E-7)
    Debug.Print 1.5E-7; f"#,
    );
    assert_eq!(
        printed,
        [
            "1.5E-07|-1.5E-07|1E-05|0.0001",
            "1E+15|1E+16|1.23456789012346E+17|1.5E+300",
            "0.3|0.3333333|1.234568E+07|1E-05",
            "x1.5E-07| 1.5E-07| 1.234568E+07|1.234568E+07",
            "1.234E-05|1.5E-07",
            " 1.5E-07  1E+07 ",
        ]
    );
}

// ---- a String in arithmetic --------------------------------------------------------------

/// [MS-VBAL] 5.6.9.3: an arithmetic operator let-coerces a String operand to a number, as
/// CDbl reads it (5.5.1.2.1; the literals of 3.3.2: `&H10`, a `D` exponent); LibreOffice's
/// VBA mode gives the same 100, 16, 12 and 99 (tests/vba_libreoffice.rs
/// text_in_arithmetic_as_vba_reads_it). A String that is no number stays a Type mismatch.
#[test]
fn a_string_in_arithmetic_is_read_as_cdbl_reads_it() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim v\n    v = \"1d2\"\n    Debug.Print CStr(v + 0); \"|\"; CStr(\"&H10\" * 1); \"|\"; CStr(\" 12 \" + 0); \"|\"; CStr(\"1d2\" - 1)",
    );
    assert_eq!(printed, ["100|16|12|99"]);
    let message = main_fails(&mut Workbook::with_sheet(), "    Debug.Print \"1d\" * 1");
    assert!(message.contains("Type mismatch (run-time error 13)"), "{message}");
}

// ---- IIf ----------------------------------------------------------------------------------

/// "IIf function" (VBA reference): it returns a Variant holding the chosen argument as it
/// was, so `IIf(True, 1, 2.5)` holds the Integer 1 and `IIf(False, 1, 2.5)` the Double 2.5
/// ("TypeName function"; LibreOffice's VBA mode also says Integer).
#[test]
fn iif_gives_the_chosen_argument_with_its_type() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim v\n    v = IIf(2 > 1, 1, 2.5)\n    Debug.Print TypeName(IIf(True, 1, 2.5)); \"|\"; TypeName(IIf(False, 1, 2.5)); \"|\"; TypeName(v)",
    );
    assert_eq!(printed, ["Integer|Double|Integer"]);
}

// ---- Abs ---------------------------------------------------------------------------------

/// "Abs function": "The data type of the return value is the same as that of the number
/// argument", so the absolute value of the smallest Integer (-32,768), Long (-2,147,483,648)
/// or LongLong (-2^63) is past its type: Overflow, run-time error 6 ("Overflow (Error 6)"),
/// as `-x` of it is ([MS-VBAL] 5.6.9.3). One above the smallest is fine.
#[test]
fn abs_of_the_smallest_integer_overflows() {
    for body in [
        "    Dim i As Integer\n    i = -32768\n    Debug.Print Abs(i)",
        "    Dim l As Long\n    l = -2147483647 - 1\n    Debug.Print Abs(l)",
        "    Dim k As LongLong\n    k = -9223372036854775807^ - 1\n    Debug.Print Abs(k)",
    ] {
        let message = main_fails(&mut Workbook::with_sheet(), body);
        assert!(message.contains("Overflow (run-time error 6)"), "{body}: {message}");
    }
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim i As Integer, k As LongLong\n    i = -32767\n    k = -9223372036854775807^\n    Debug.Print CStr(Abs(i)); TypeName(Abs(i)); \"|\"; CStr(Abs(k))",
    );
    assert_eq!(printed, ["32767Integer|9223372036854775807"]);
}

// ---- Range.Formula of a text cell ----------------------------------------------------------

/// "Range.Formula property" (Excel VBA reference): "If the cell contains a constant, this
/// property returns the constant", the text 2022 for a cell given `'2022`; the `'` is the
/// cell's "Range.PrefixCharacter property", not part of its contents. So `.Formula = .Formula`
/// turns such a text into the number it spells, as in Excel.
#[test]
fn formula_of_a_text_typed_with_a_quote_is_the_text() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Range(\"A1\").Value = \"'2022\"\n    Debug.Print Range(\"A1\").Formula; \"|\"; TypeName(Range(\"A1\").Value)\n\
         \x20   Range(\"A1\").Formula = Range(\"A1\").Formula\n    Debug.Print TypeName(Range(\"A1\").Value)",
    );
    assert_eq!(printed, ["2022|String", "Double"]);
}

// ---- conversions and results past a Double --------------------------------------------------

/// "Exp function": "If the value of number exceeds 709.782712893384, an error occurs" — VBA's
/// Overflow, run-time error 6 ("Overflow (Error 6)": "the result of a calculation … is too large
/// for the data type"), not a value left in the variable.
#[test]
fn exp_past_a_doubles_range_is_overflow() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    On Error Resume Next\n    Dim d As Double\n    d = Exp(710)\n    Debug.Print Err.Number; d",
    );
    assert_eq!(printed, vec![" 6  0 "]);
}

/// "Type conversion functions": CVar returns a Variant of what it is given, so TypeName sees the
/// argument's own type (an Integer literal stays Integer, a Double Double), and CVar(Null) is
/// Null. CDec of a text written in the call keeps its every digit ("Decimal data type": up to
/// 28 places); of a text of more than 15 significant digits held elsewhere it is refused with
/// its reason, not rounded.
#[test]
fn cvar_keeps_the_type_and_cdec_of_too_many_digits_is_refused_by_name() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Debug.Print TypeName(CVar(5)); \" \"; TypeName(CVar(2.5)); \" \"; CVar(\"a\"); \" \"; IsNull(CVar(Null))",
    );
    assert_eq!(printed, vec!["Integer Double a True"]);
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim v As Variant\n    v = CDec(\"1.2345678901234567890\")\n    Debug.Print v",
    );
    assert_eq!(printed, vec![" 1.234567890123456789 "]);
    let message = main_fails(
        &mut Workbook::with_sheet(),
        "    Dim t As String, v As Variant\n    t = \"1.2345678901234567890\"\n    v = CDec(t)",
    );
    assert!(message.contains("CDec") && message.contains("15 significant digits"), "{message}");
}

/// [MS-VBAL] 5.5.1.2.1 (Let-coercion between numeric types): a value the destination type holds
/// keeps its value, so CDec of a Decimal (or a Currency or a LongLong, scaled integers too) is
/// that number digit for digit; only a Double goes through VarDecFromR8's 15 digits. Gustav
/// Brock's RoundingMethodsTest (IsGoodRoundUpZero) asserts `RoundUp(CDec(10 ^ 13) + CDec(0.74),
/// 1, True)` is 10000000000000.8: RoundUp's `-Int(CDec(-Value) * Scaling) / Scaling` needs the
/// 16-digit 10000000000000.74, where 15 digits gave 10000000000000.7 (Python's decimal, apart:
/// Decimal(10**13) + Decimal("0.74") is 10000000000000.74, times 10 is 100000000000007.4, floor
/// of its negation -100000000000008). A LongLong of more digits than a Double gives back keeps
/// them: CDec(CLngLng("9007199254740993")) + 1 is 9007199254740994 (2^53 + 2).
#[test]
fn cdec_of_a_decimal_keeps_its_digits() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim v\n    v = CDec(10 ^ 13) + CDec(0.74)\n    Debug.Print CDec(v); CDec(v) * 10; -Int(CDec(-v) * 10) / 10\n\
         \x20   Debug.Print CDec(CCur(2.5) / 2); CDec(0.1 + 0.2)",
    );
    assert_eq!(printed, vec![" 10000000000000.74  100000000000007.4  10000000000000.8 ", " 1.25  0.3 "]);
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim d\n    d = CDec(CLngLng(\"9007199254740993\"))\n    Debug.Print d; d + 1; TypeName(d)",
    );
    assert_eq!(printed, vec![" 9007199254740993  9007199254740994 Decimal"]);
}

/// "Int, Fix functions" of a Decimal operation whose result has more digits than a double holds
/// but whose whole part a double does: VBA keeps a Decimal's 28 digits ("Decimal data type"),
/// so Gustav Brock's RoundMid, `Int(CDec(Value) * Scaling + Half) / Scaling` with Scaling
/// 10 ^ 20, gives 10.5 for 10.5 (his RoundingMethodsTest asserts `NiceDbl(RoundMid(10.5, 20))
/// = 10.5` and `NiceDbl(RoundMid(10.5, -20)) = 0`). Python's decimal, apart: Decimal("10.5") *
/// 10**20 + Decimal("0.5") floored is 1050000000000000000000, over 10**20 10.5; the negated sum
/// -1049999999999999999999.5 floors to -1050000000000000000000; 10.5E-20 + 0.5 truncated is 0.
/// The same sum kept in a variable keeps its digits too.
#[test]
fn int_of_a_decimal_no_double_holds_takes_its_digits() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim s, h\n    s = CDec(10 ^ 20): h = CDec(0.5)\n\
         \x20   Debug.Print Int(CDec(10.5) * s + h) / s; Fix(CDec(10.5) * CDec(1E-20) + h); Int(-CDec(10.5) * s + h)",
    );
    assert_eq!(printed, vec![" 10.5  0 -1050000000000000000000 "]);
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim x\n    x = CDec(10.5) * CDec(10 ^ 20) + CDec(0.5)\n    Debug.Print x; Int(x); Fix(-x); CDbl(x)",
    );
    assert_eq!(printed, vec![" 1050000000000000000000.5  1050000000000000000000 -1050000000000000000000  1.05E+21 "]);
}

/// Microsoft's "Decimal data type": a 96-bit integer scaled by a power of ten, 0 to 28 places.
/// A result with more digits than that is rounded half to even to the most places whose
/// integer fits 96 bits, and the Decimal goes on whole through a Variant, a Function's result,
/// a second operation, CStr, `&`, Int, Abs, Round and the comparisons ([MS-VBAL] 5.6.9.5),
/// where a Double variable takes its nearest double. Expected values computed apart by Python's
/// decimal at 200 digits, then fitted by that rule (/tmp/h1/s32/oracle.py, session 32):
/// 1/3 = 0.3333333333333333333333333333, (1/3)·3 = 0.9999999999999999999999999999,
/// (1/3)+10 = 10.333333333333333333333333333, (1/3)² = 0.1111111111111111111111111111,
/// 10/3 = 3.3333333333333333333333333333 (29 digits: 33333333333333333333333333333 < 2^96),
/// (1/7)·7 = 1.0000000000000000000000000003, (2/3) rounded half to even to 27 places
/// 0.666666666666666666666666667, 2^96 − 1 − 1 = 79228162514264337593543950334.
#[test]
fn a_decimal_keeps_its_28_places_through_variables_and_functions() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim t, u\n    t = CDec(1) / 3\n    u = Third()\n\
         \x20   Debug.Print t; t * 3; CStr(t + 10); t * t\n\
         \x20   Debug.Print u = t; u > CDec(\"0.3333333333333333333333333332\"); t = 0.333333333333333\n\
         \x20   Debug.Print CDec(10) / 3; CDec(1) / 7 * 7; Abs(-t); Round(CDec(2) / 3, 27)\n\
         \x20   Debug.Print CDec(\"79228162514264337593543950335\") - 1; \"[\" & u * 3 & \"]\"\n\
         \x20   Dim d As Double\n    d = t\n    Debug.Print d\n\
         End Sub\n\
         Function Third()\n    Third = CDec(1) / 3\nEnd Function\nSub Unused()",
    );
    assert_eq!(
        printed,
        vec![
            " 0.3333333333333333333333333333  0.9999999999999999999999999999 10.333333333333333333333333333 \
             0.1111111111111111111111111111 ",
            "TrueTrueFalse",
            " 3.3333333333333333333333333333  1.0000000000000000000000000003  0.3333333333333333333333333333  \
             0.666666666666666666666666667 ",
            " 79228162514264337593543950334 [0.9999999999999999999999999999]",
            " 0.333333333333333 ",
        ]
    );
}

/// A Decimal whose digits no double holds is refused by name where ncsheet would keep its
/// nearest double instead (an array item); On Error does not trap the refusal.
#[test]
fn a_decimal_no_double_holds_is_refused_where_it_would_lose_digits() {
    let message = main_fails(
        &mut Workbook::with_sheet(),
        "    Dim t, a(2)\n    On Error Resume Next\n    t = CDec(1) / 3\n    a(1) = t\n    Debug.Print \"went on\"\n\
         End Sub\nFunction Twice(x)\n    Twice = x * 2\nEnd Function\nSub Unused()",
    );
    assert!(message.contains("whose digits no Double holds"), "{message}");
}

/// A Decimal argument is bound to a Variant parameter with its value type ([MS-VBAL]
/// 5.3.1.11), its 28 places with it, and given back through a ByRef one; a Double parameter
/// takes its nearest double. Expected values by Python's decimal, exact, then fitted to 96 bits
/// and at most 28 places halving to even ("Decimal data type"; /tmp/h1/s32/oracle.py):
/// (1/3)·2 = 0.6666666666666666666666666666, (1/3)+1 = 1.3333333333333333333333333333.
#[test]
fn a_decimal_argument_keeps_its_digits_in_a_variant_parameter() {
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim t\n    t = CDec(1) / 3\n    Debug.Print Twice(t); TypeName(Echo(t)); Near(t)\n    Bump t\n    Debug.Print t\n\
         End Sub\nFunction Twice(x)\n    Twice = x * 2\nEnd Function\nFunction Echo(ByVal x)\n    Echo = x\nEnd Function\n\
         Function Near(ByVal x As Double)\n    Near = x\nEnd Function\nSub Bump(x)\n    x = x + 1\nEnd Sub\nSub Unused()",
    );
    assert_eq!(
        printed,
        vec![" 0.6666666666666666666666666666 Decimal 0.333333333333333 ", " 1.3333333333333333333333333333 "]
    );
}

// ---- an array as an operand --------------------------------------------------------------

/// [MS-VBAL] 5.6.9.3-5.6.9.8 define VBA's arithmetic, comparison, concatenation and logical
/// operators on single values (numbers, dates, strings, Booleans, Empty, Null), and "Type
/// mismatch (Error 13)" (Office VBA reference) names the cause "An object was passed to a
/// procedure that is expecting a single property or value": a several-cell Range's value and
/// a Variant holding an array are operands of no operator, where a formula's operators work
/// item by item. PsychroLib's `If (TDryBulb < -100 Or TDryBulb > 200)` on a cell's `=
/// GetSatVapPres(A1:A2)` gave a number instead of Excel's #N/A from its error handler.
#[test]
fn an_array_is_no_operand() {
    let mut wb = Workbook::with_sheet();
    for (row, text) in ["1", "2"].iter().enumerate() {
        wb.set_input(0, ncsheet::formula::address::Pos::new(row as u32, 0), text).unwrap();
    }
    let printed = run_main(
        &mut wb,
        "    Dim v As Variant, a As Variant\n    a = Array(1, 2)\n    On Error Resume Next\n\
         \x20   v = Range(\"A1:A2\") + 1: Debug.Print Err.Number;: Err.Clear\n\
         \x20   v = Range(\"A1:A2\") < 5: Debug.Print Err.Number;: Err.Clear\n\
         \x20   v = a * 2: Debug.Print Err.Number;: Err.Clear\n\
         \x20   v = a & \"x\": Debug.Print Err.Number;: Err.Clear\n\
         \x20   v = -a: Debug.Print Err.Number;: Err.Clear\n\
         \x20   v = Range(\"A1:A1\") + 1: Debug.Print Err.Number; v",
    );
    assert_eq!(printed, [" 13  13  13  13  13  0  2 "]);
}

/// VBA's library functions of single values take no array: `Abs`, `Int`, `Sqr`, `CDbl`,
/// `Len`, `Trim`, `Round`, `Format` of a several-cell Range (its value is an array) or of a
/// Variant holding an array is a Type mismatch, run-time error 13 ("Type mismatch (Error 13)":
/// "An object was passed to a procedure that is expecting a single property or value"; "Abs
/// function": "The required number argument can be any valid numeric expression"), where a
/// cell's formula works item by item; a one-cell Range is its value.
#[test]
fn a_library_function_of_one_value_takes_no_array() {
    let mut wb = Workbook::with_sheet();
    for (row, text) in ["-2.5", "3.7"].iter().enumerate() {
        wb.set_input(0, ncsheet::formula::address::Pos::new(row as u32, 0), text).unwrap();
    }
    let calls =
        ["Abs(r)", "Int(r.Value)", "Sqr(a)", "Sgn(r)", "CDbl(r)", "Len(r)", "Trim(a)", "Round(r, 1)", "Format(a)"];
    let mut body = String::from(
        "    Dim v As Variant, a As Variant, r As Range\n    a = Array(4, 9)\n    Set r = Range(\"A1:A2\")\n    \
         On Error Resume Next\n",
    );
    for call in calls {
        body.push_str(&format!("    v = {call}: Debug.Print Err.Number; TypeName(v);: Err.Clear\n"));
    }
    body.push_str("    Debug.Print Abs(Range(\"A1\")); Int(Range(\"A2:A2\"))");
    let printed = run_main(&mut wb, &body);
    assert_eq!(printed, [" 13 Empty".repeat(calls.len()) + " 2.5  3 "]);
}
