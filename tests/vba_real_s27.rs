//! VBA's results where real modules measured in sessions 26 and 27 (issue 31) met ncsheet's
//! doubles standing in for VBA's other number types and array types. Each test is a small
//! macro of our own; the expected values come from Microsoft's VBA reference (the page named
//! at each test), [MS-VBAL] (the section named), and Python's `decimal` module computed apart
//! from ncsheet.

mod common;

use common::vba::printed_after as printed;

// "Currency data type": a Currency is "stored as 64-bit (8-byte) numbers in an integer format,
// scaled by 10,000", so CCur(1.015) is exactly 10150 ten-thousandths and Round(…, 2) meets a
// tie that "Round function" breaks to even; the result has the expression's type ("Round
// function": Currency in, Currency out). Python, apart: Decimal("1.015").quantize(
// Decimal("0.01"), ROUND_HALF_EVEN) is 1.02, Decimal("2.345") 2.34, Decimal("-0.125") -0.12,
// Decimal("123456.785") 123456.78; float 1.015 * 100 is 101.49999999999999, which a Double's
// Round gives as 1.01 (the last value: the Double keeps its own result). (Wine's VarCyRound
// multiplies the Currency's double instead, which gives 1.01 for the first: Wine is no oracle
// here, the Currency's scaled integer is.)
#[test]
fn round_of_a_currency_rounds_its_scaled_integer_to_even() {
    let out = printed(
        "",
        "    Dim c As Currency\n\
         \x20   c = 1.015\n\
         \x20   Debug.Print Round(CCur(1.015), 2); Round(CCur(2.345), 2); Round(c, 2); TypeName(Round(c, 2))\n\
         \x20   Debug.Print Round(CCur(-0.125), 2); Round(CCur(123456.785), 2); Round(CCur(2.5)); Round(1.015, 2)",
    );
    assert_eq!(out, [" 1.02  2.34  1.02 Currency", "-0.12  123456.78  2  1.01 "]);
}

// "Currency data type": "a fixed-point number with 15 digits to the left of the decimal point
// and 4 digits to the right", so CStr and `&` of the Currency 123456789012345.5 show its 16
// digits, where a Double's text keeps 15 ("Str function", [MS-VBAL] 5.5.1.2.4) and would
// show 123456789012346.
#[test]
fn a_currency_shows_every_digit() {
    let out = printed(
        "",
        "    Dim c As Currency\n\
         \x20   c = 123456789012345.5\n\
         \x20   Debug.Print CStr(c); \"|\" & c & \"|\"; CStr(CCur(-0.0001)); CStr(CDbl(c))",
    );
    assert_eq!(out, ["123456789012345.5|123456789012345.5|-0.0001123456789012346"]);
}

// YujiFukami/VBA-Approximate-formula ModMatrix.bas (session 26's r10): `TypeName(F_Minverse(B))`
// of a Function `As Variant` that fills a `Dim Output#()` and returns it. "TypeName function":
// "if varname is an array of integers, TypeName returns "Integer()""; "VarType function": "the
// value returned for an array of integers is calculated as vbInteger + vbArray, or 8194".
// An array keeps its items' type wherever it goes, so a Variant given a `Long()` holds a
// Long() (8195, vbLong 3 + vbArray 8192), a Function `As Variant` returning a `Double()` gives
// a Double() (8197), one `As String()` a String(); `Array(…)` makes a Variant() ("Array
// function": "a Variant containing an array").
#[test]
fn an_array_keeps_its_item_type_in_a_variant() {
    let out = printed(
        "Function F() As Variant\n    Dim o#()\n    ReDim o(1 To 2)\n    F = o\nEnd Function\n\
         Function G() As String()\n    Dim s(1) As String\n    G = s\nEnd Function\n",
        "    Dim a() As Long, v As Variant, w\n\
         \x20   ReDim a(2)\n\
         \x20   v = a\n\
         \x20   w = G()\n\
         \x20   Debug.Print TypeName(v); VarType(v); TypeName(F()); VarType(F()); TypeName(w); TypeName(Array(1))",
    );
    assert_eq!(out, ["Long() 8195 Double() 8197 String()Variant()"]);
}
