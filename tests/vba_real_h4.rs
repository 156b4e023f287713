//! Constructs that stopped real public engineering modules measured in session 26 (issue 31):
//! Gustav Brock's VBA.Round (RoundingMethods.bas), which rounds in Decimal "to prevent bit
//! errors of reals". Each test is a small macro of our own; the expected values come from
//! Microsoft's VBA reference (the page named at each test) and Python's `decimal` module,
//! computed apart from ncsheet.

mod common;

use common::vba::run_main;
use ncsheet::workbook::Workbook;

// "Decimal data type" and "/ operator" ("Division involves a Decimal and any other data type:
// A Decimal data type"): CDec(32.675) * 100 is the decimal 3267.5, so RoundMid's
// `Int(CDec(Value) * Scaling + Half) / Scaling` is 32.68, where the Doubles give
// Int(3267.4999999999995 + 0.5) / 100 = 32.67 (Python: int(32.675 * 100 + 0.5) / 100 is 32.67;
// Decimal("32.675") * 100 + Decimal("0.5") floored, / 100 is 32.68). CDec of a Double keeps
// its 15 significant digits (OLE Automation's VarDecFromR8): CDec(0.1 + 0.2) is 0.3. "VarType
// function": vbDecimal is 14; "TypeName function": "Decimal".
#[test]
fn decimal_operations_are_exact_decimals() {
    let body = "    Dim s As Variant, h As Variant\n\
                \x20   s = CDec(10 ^ 2): h = CDec(0.5)\n\
                \x20   Debug.Print Int(CDec(32.675) * s + h) / s; Int(32.675 * 100 + 0.5) / 100\n\
                \x20   Debug.Print TypeName(s); VarType(CDec(1) / 4); CDec(0.1 + 0.2) = 0.3; \"[\" & CDec(2.5) / 2 & \"]\"\n\
                \x20   Debug.Print CDec(-9999999999999.25) * 10";
    assert_eq!(
        run_main(&mut Workbook::with_sheet(), body),
        [" 32.68  32.67 ", "Decimal 14 True[1.25]", "-99999999999992.5 "]
    );
}

// "Round function" rounds halves to even; a Decimal's digits are exact, so the Decimal 2.345 is
// a tie and rounds to 2.34, 2.355 to 2.36 (Python: Decimal("2.345").quantize(Decimal("0.01"),
// ROUND_HALF_EVEN) is 2.34, Decimal("2.355") 2.36).
#[test]
fn round_of_a_decimal_rounds_its_digits_to_even() {
    let body =
        "    Debug.Print Round(CDec(2.345), 2); Round(CDec(2.355), 2); Round(CDec(-2.345), 2); Round(CDec(2.3), 2)";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), [" 2.34  2.36 -2.34  2.3 "]);
}

// "Decimal data type": a Decimal holds up to 28 places, so CDec(1) / 3 is
// 0.3333333333333333333333333333 (Python's decimal: Decimal(1) / Decimal(3) at 28 digits).
#[test]
fn a_decimal_of_more_digits_than_a_double_keeps_them() {
    let body = "    Dim q As Variant\n    q = CDec(1) / 3\n    Debug.Print q";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), [" 0.3333333333333333333333333333 "]);
}

// "Decimal data type": the range is +/-79,228,162,514,264,337,593,543,950,335; past it an
// operation is run-time error 6, Overflow, which On Error traps as VBA's.
#[test]
fn a_decimal_past_its_range_is_a_trappable_overflow() {
    let body = "    Dim q As Variant\n    On Error Resume Next\n    q = CDec(7E+28) * 10\n    Debug.Print Err.Number";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), [" 6 "]);
}
