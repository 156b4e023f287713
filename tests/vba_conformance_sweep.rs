//! VBA conformance found by a sweep of several hundred expressions run through ncsheet and
//! through LibreOffice Basic in VBA-compatibility mode (issue 31): where the two differed, the
//! value here is the one Microsoft's VBA language reference or [MS-VBAL] gives (cited at each
//! test), and LibreOffice's where it agrees (noted).

mod common;

use common::vba::printed_after;

/// What each line of `lines` (an expression) gives, or `Err <number>` for the run-time error
/// it raises, as `Sub Main` prints them with errors resumed.
fn each(lines: &[&str]) -> Vec<String> {
    let mut body = String::from("    Dim r\n    On Error Resume Next\n");
    for line in lines {
        body.push_str(&format!(
            "    Err.Clear\n    r = Empty\n    r = {line}\n    If Err.Number <> 0 Then Debug.Print \"Err \" & Err.Number Else Debug.Print TypeName(r) & \" \" & r\n"
        ));
    }
    printed_after("", &body)
}

// "Type conversion functions": "If the expression passed to the function is outside the range
// of the data type being converted to, an error occurs"; [MS-VBAL] 5.5.1.2.1.1 (Let-coercion
// from String to a numeric type): a String that is no number is run-time error 13, Type
// mismatch. The conversions returned an Excel error value (#VALUE!) into the variable instead.
// LibreOffice's VBA mode raises 13 on each as well, except CBool(""), which is False there.
#[test]
fn a_conversion_of_text_that_is_no_number_is_type_mismatch() {
    let got = each(&[
        "CDbl(\"abc\")",
        "CDbl(\"\")",
        "CInt(\"1x\")",
        "CLng(\"x\")",
        "CByte(\"a\")",
        "CSng(\"a\")",
        "CCur(\"a\")",
        "CDate(\"abc\")",
        "CDate(\"2/29/2021\")",
        "CBool(\"yes\")",
        "CBool(\"\")",
    ]);
    assert_eq!(got, vec!["Err 13"; 11]);
}

// [MS-VBAL] 5.5.1.2.2 (Let-coercion to Boolean): a String is converted to a number first when
// it is not "True" or "False", and the number is False when 0, True otherwise; so
// `CBool("1")` is True and `CBool("0")` False, in CBool and in a Boolean variable alike
// (both were refused or an error value). LibreOffice agrees.
#[test]
fn numeric_text_converts_to_boolean_by_its_number() {
    let got = each(&["CBool(\"1\")", "CBool(\"0\")", "CBool(\" -2.5 \")", "CBool(\"false\")"]);
    assert_eq!(got, ["Boolean True", "Boolean False", "Boolean True", "Boolean False"]);
    let printed = printed_after(
        "",
        "    Dim b As Boolean\n    b = \"0\"\n    Debug.Print b\n    b = \"12\"\n    Debug.Print b\n",
    );
    assert_eq!(printed, ["False", "True"]);
}

// "Filter function": Filter(sourcearray, match[, include[, compare]]) returns a zero-based
// array of the items that contain match (include True or left out) or that do not (False);
// compare as in the Comparison constants (vbTextCompare, 1, ignores case). The bare name
// reached Excel's worksheet FILTER, which failed ("a is not an array"). LibreOffice agrees.
#[test]
fn filter_keeps_the_items_that_contain_the_match() {
    let printed = printed_after(
        "",
        "    Dim a, b, c\n    a = Filter(Array(\"ab\", \"cd\", \"abc\"), \"b\")\n    Debug.Print LBound(a) & \" \" & UBound(a) & \" \" & Join(a, \"|\")\n    b = Filter(Array(\"ab\", \"cd\", \"abc\"), \"b\", False)\n    Debug.Print Join(b, \"|\")\n    c = Filter(Array(\"Ab\", \"ab\", \"x\"), \"A\", True, vbTextCompare)\n    Debug.Print Join(c, \"|\")\n    Debug.Print CStr(UBound(Filter(Array(\"x\"), \"y\")))\n",
    );
    assert_eq!(printed, ["0 1 ab|abc", "cd", "Ab|ab", "-1"]);
}

// "FormatPercent function", "FormatCurrency function" and "FormatDateTime function" take
// FormatNumber's arguments (the last its NamedFormat), with the regional settings of English
// (United States); they were no functions at all ("no Function, Sub or sheet function named
// FormatPercent": the procedure did not compile). FormatCurrency(.20,,0) is "$.20" and
// FormatCurrency(20000,5) "$20,000.00000" as the VBScript reference's examples show them.
// FormatDateTime: vbGeneralDate shows a date part as a short date and a time part as a long
// time, vbShortTime "by using the 24-hour format (hh:mm)".
#[test]
fn format_percent_currency_and_date_time_as_the_reference_describes() {
    let got = each(&[
        "FormatPercent(0.256)",
        "FormatPercent(12.345, 1)",
        "FormatPercent(-0.5, 0, , vbTrue)",
        "FormatCurrency(1234.5)",
        "FormatCurrency(.20, , 0)",
        "FormatCurrency(20000, 5)",
        "FormatCurrency(-5, , , vbFalse)",
        "FormatCurrency(-5, , , vbTrue)",
        "FormatDateTime(#1/2/2020 13:05:09#)",
        "FormatDateTime(#1/2/2020#)",
        "FormatDateTime(#1/2/2020 13:05:09#, vbLongDate)",
        "FormatDateTime(#1/2/2020 13:05:09#, vbShortDate)",
        "FormatDateTime(#1/2/2020 13:05:09#, vbLongTime)",
        "FormatDateTime(#1/2/2020 13:05:09#, vbShortTime)",
        "FormatDateTime(#1/2/2020#, 7)",
    ]);
    let want = [
        "String 25.60%",
        "String 1,234.5%",
        "String (50%)",
        "String $1,234.50",
        "String $.20",
        "String $20,000.00000",
        "String -$5.00",
        "String ($5.00)",
        "String 1/2/2020 1:05:09 PM",
        "String 1/2/2020",
        "String Thursday, January 2, 2020",
        "String 1/2/2020",
        "String 1:05:09 PM",
        "String 13:05",
        "Err 5",
    ];
    assert_eq!(got, want);
}

// [MS-VBAL] 3.3.2 (number tokens): a hex or octal literal without a type character whose
// digits fit 16 bits is an Integer read as two's complement (so `&HFFFF` is -1), one that
// needs more bits a Long; `&` makes it a Long read from 32 bits. `&H8000` had the Integer's
// value, -32768, but was typed Long.
#[test]
fn hex_literals_of_sixteen_bits_are_integers() {
    let got = each(&["&H8000", "&HFFFF", "&H7FFF", "&O177777", "&H10000", "&H8000&", "&HFFFFFFFF"]);
    let want = ["Integer -32768", "Integer -1", "Integer 32767", "Integer -1", "Long 65536", "Long 32768", "Long -1"];
    assert_eq!(got, want);
}

// [MS-VBAL] 5.6.9.8.1 (Not Operator): the result's type is the operand's for a Byte, Boolean,
// Integer, Long or LongLong; any other operand (a Double, a String) is let-coerced to a Long
// first (5.5.1.2.1: 5.5 rounds half to even to 6, `Not 6` is -7). A Byte's Not flips its eight
// bits: 255 - 5 = 250. The "Not operator" page's example: `Not A` of A = 10 "Returns -11".
// Every Not was a Double, and `Not CByte(5)` -6. (LibreOffice types `Not CByte(5)` a Long -6:
// it disagrees with the specification.)
#[test]
fn not_keeps_its_operands_integral_type() {
    let got = each(&["Not CByte(5)", "Not CByte(0)", "Not 10", "Not CLng(5)", "Not True", "Not 5.5", "Not \"3\""]);
    let want = ["Byte 250", "Byte 255", "Integer -11", "Long -6", "Boolean False", "Long -7", "Long -4"];
    assert_eq!(got, want);
}

// Each function's page: Weekday, Year, Month, Day, Hour, Minute and Second each "Returns a
// Variant (Integer)"; "Asc function": AscW returns the Unicode code as Asc its Integer (so
// U+9C40, 40000, is 40000 - 65536 = -25536); "Len function": "Returns a Long"; "InStr
// function": "Variant (Long)". They were Doubles. A Variant's Integer past its range is
// promoted to a Long ("Variant data type"), so `Year(d) * 100` is the Long 202000, no
// Overflow. LibreOffice agrees on Weekday and Year (Integer).
#[test]
fn date_parts_and_character_codes_are_integers() {
    let got = each(&[
        "Weekday(#1/2/2020#)",
        "Year(#1/2/2020#)",
        "Month(#1/2/2020#)",
        "Day(#1/2/2020#)",
        "Hour(#1/2/2020 13:05:09#)",
        "Minute(#1/2/2020 13:05:09#)",
        "Second(#1/2/2020 13:05:09#)",
        "AscW(\"A\")",
        "AscW(ChrW(40000))",
        "Len(\"abc\")",
        "InStr(\"abc\", \"b\")",
        "Year(#1/2/2020#) * 100",
    ]);
    let want = [
        "Integer 5",
        "Integer 2020",
        "Integer 1",
        "Integer 2",
        "Integer 13",
        "Integer 5",
        "Integer 9",
        "Integer 65",
        "Integer -25536",
        "Long 3",
        "Long 2",
        "Long 202000",
    ];
    assert_eq!(got, want);
}

// Round's result has its argument's type ("VB & VBA in a Nutshell", Round: "Return Value:
// The same data type as expression"; Microsoft's "Round function" page names none, and Abs,
// Int and Fix, whose pages say so, behave alike): the Round of a Currency is a Currency, of a
// Single a Single, of an Integer an Integer; a String is read as a Double. Every Round was a
// Double. (LibreOffice gives a Double for the Currency and the Single.)
#[test]
fn round_keeps_its_arguments_type() {
    let got = each(&[
        "Round(CCur(2.3456), 2)",
        "Round(CSng(2.5))",
        "Round(CInt(7))",
        "Round(CLng(3))",
        "Round(2.5)",
        "Round(\"2.5\")",
    ]);
    let want = ["Currency 2.35", "Single 2", "Integer 7", "Long 3", "Double 2", "Double 2"];
    assert_eq!(got, want);
}

// "IsNumeric function": "IsNumeric returns False if expression is a date expression", True
// when "the entire expression is recognized as a number" (its examples: "53" and "459.95"
// True, "45 Help" False). A Date was True. LibreOffice agrees on the texts and Empty.
#[test]
fn is_numeric_is_false_for_a_date() {
    let got = each(&[
        "IsNumeric(#1/2/2020#)",
        "IsNumeric(CDate(\"1/2/2020\"))",
        "IsNumeric(DateSerial(2020, 1, 2))",
        "IsNumeric(\"1/2/2020\")",
        "IsNumeric(\"53\")",
        "IsNumeric(\"459.95\")",
        "IsNumeric(\"45 Help\")",
        "IsNumeric(\" 1 \")",
        "IsNumeric(\"\")",
        "IsNumeric(Empty)",
    ]);
    let want = [
        "Boolean False",
        "Boolean False",
        "Boolean False",
        "Boolean False",
        "Boolean True",
        "Boolean True",
        "Boolean False",
        "Boolean True",
        "Boolean False",
        "Boolean True",
    ];
    assert_eq!(got, want);
}

// "Returning strings from functions": the Variant forms "allow Null to be propagated through
// an expression", the `$` forms (Format$ among them) return a String, so Format$(Null) is
// "Invalid use of Null" (error 94); FormatNumber of a String that is no number cannot
// let-coerce it to a Double ([MS-VBAL] 5.5.1.2.1.1): Type mismatch, error 13. Both Format
// calls gave the error value Error 2015 into the variable, and FormatNumber too.
// LibreOffice agrees on FormatNumber.
#[test]
fn format_passes_null_and_format_number_refuses_text() {
    let got = each(&[
        "Format(Null)",
        "Format(Null, \"0.00\")",
        "Format$(Null)",
        "FormatNumber(\"abc\")",
        "FormatNumber(\"1.5\")",
    ]);
    assert_eq!(got, ["Null ", "Null ", "Err 94", "Err 13", "String 1.50"]);
}

// "^ operator": VBA computes `0 ^ 0` as IEEE 754's pow does, 1 (the page names no exception
// for it, and LibreOffice's VBA mode gives 1), where the sheet's `^` is #NUM!; it raised
// Overflow (error 6).
#[test]
fn zero_to_the_zero_is_one() {
    let got = each(&["0 ^ 0", "0# ^ 0", "CInt(0) ^ CLng(0)"]);
    assert_eq!(got, ["Double 1", "Double 1", "Double 1"]);
}

// `0 / 0` has no value, where `1 / 0` has an infinite one: Microsoft's Knowledge Base article
// Q42473, "'Overflow' Error Might Be the Result of 0/0", says its BASIC raises Overflow there
// (`(b# - c#) / (b# - c#)`), and VBA raises error 6 for it as well (help-vba.com's "0で除算
// しました" page: a zero numerator over a zero denominator is オーバーフロー, Overflow). Any
// other number over zero, and `\` and `Mod` by zero, are Division by zero (error 11, "Division
// by zero (Error 11)"). It was 11.
#[test]
fn zero_over_zero_is_overflow() {
    let got = each(&["0 / 0", "0# / 0", "CLng(0) / CLng(0)", "Empty / 0", "1 / 0", "0 \\ 0", "0 Mod 0"]);
    assert_eq!(got, ["Err 6", "Err 6", "Err 6", "Err 6", "Err 11", "Err 11", "Err 11"]);
}

// [MS-VBAL] 5.6.9.5 (relational operators): a comparison's value is a Boolean; [MS-VBAL]
// 5.6.9.3 (arithmetic operators' declared types): a Boolean with an Integer adds as an
// Integer, True being -1 ("Boolean data type"). `(1 = 1) + 1` was a Double.
#[test]
fn a_comparison_is_a_boolean_in_arithmetic() {
    let got = each(&["(1 = 1) + 1", "(2 > 1) * 3", "(1 <> 1) - CLng(1)"]);
    assert_eq!(got, ["Integer 0", "Integer -3", "Long -1"]);
}

// "Boolean data type": "When Boolean values are converted to other data types, False becomes
// 0 and True becomes -1" ([MS-VBAL] 5.5.1.2.1 alike); Boolean with Boolean or Integer adds as
// an Integer (5.6.9.3). Arithmetic and the conversions took the sheet's TRUE, 1: `True + True`
// was 2, `CInt(True)` 1, `-True` -1. LibreOffice agrees on the values.
#[test]
fn true_is_minus_one_in_arithmetic() {
    let got = each(&[
        "True + True",
        "True * 3",
        "-True",
        "True + 1",
        "False - 1",
        "CInt(True)",
        "CDbl(True)",
        "True + \"1\"",
        "Abs(True)",
    ]);
    let want = [
        "Integer -2",
        "Integer -3",
        "Integer 1",
        "Integer 0",
        "Integer -1",
        "Integer -1",
        "Double -1",
        "Double 0",
        "Double 1",
    ];
    assert_eq!(got, want);
    let printed =
        printed_after("", "    Dim b As Boolean, n As Long\n    b = True\n    n = b + 10\n    Debug.Print CStr(n)\n");
    assert_eq!(printed, ["9"]);
}

// "+ operator": "One expression is an Empty Variant: Return the remaining expression unchanged
// as result", so an Empty plus a String is that String; it was read as a number (`Empty + "1"`
// the Double 1, `Empty + "a"` a Type mismatch). LibreOffice agrees.
#[test]
fn empty_plus_a_string_is_the_string() {
    let got = each(&["Empty + \"1\"", "\"a\" + Empty", "Empty + \"a\"", "Empty + 1"]);
    assert_eq!(got, ["String 1", "String a", "String a", "Integer 1"]);
    let printed = printed_after("", "    Dim v, w\n    w = \"7\"\n    Debug.Print TypeName(v + w) & \" \" & (v + w)\n");
    assert_eq!(printed, ["String 7"]);
}

// "Hex function" / "Oct function": a negative number's digits are its two's complement, "up to
// eight hexadecimal characters"; Microsoft's pages do not say in how many bits, and
// LibreOffice's VBA mode (the oracle where Microsoft is silent) writes a Long's in 32 bits and
// an Integer's in 16, whatever the value: `Hex(CLng(-1))` is "FFFFFFFF", `Hex(CInt(-32768))`
// "8000". The width came from the value alone (a Long -1 was "FFFF", an Integer -32768
// "FFFF8000").
#[test]
fn hex_and_oct_write_a_negative_in_its_types_bits() {
    let got = each(&["Hex(CLng(-1))", "Oct(CLng(-1))", "Hex(CInt(-32768))", "Oct(CInt(-32768))", "Hex(-1)"]);
    assert_eq!(got, ["String FFFFFFFF", "String 37777777777", "String 8000", "String 100000", "String FFFF"]);
    let printed = printed_after(
        "",
        "    Dim x As Long, v\n    x = -1\n    v = CLng(-256)\n    Debug.Print Hex(x) & \" \" & Hex(v)\n",
    );
    assert_eq!(printed, ["FFFFFFFF FFFFFF00"]);
}

// "LSet statement": "If string is shorter than stringvar, LSet left-aligns string in stringvar.
// LSet replaces any leftover characters in stringvar with spaces. If string is longer than
// stringvar, LSet places only the leftmost characters, up to the length of the stringvar";
// "RSet statement": right-aligns, "replaces any leftover characters in stringvar with spaces,
// back to its beginning". Both were no statements at all ("no Function, Sub or sheet function
// named LSet": the procedure did not compile). LibreOffice agrees on each.
#[test]
fn lset_and_rset_align_in_the_variables_length() {
    let body = "    Dim s As String, t As String, u As String, w As String * 4\n\
                \x20   s = \"abcde\": LSet s = \"xy\"\n\
                \x20   t = \"abcde\": RSet t = \"xy\"\n\
                \x20   u = \"ab\": RSet u = \"xyz\"\n\
                \x20   RSet w = 12\n\
                \x20   Debug.Print \"[\" & s & \"][\" & t & \"][\" & u & \"][\" & w & \"]\"\n";
    assert_eq!(printed_after("", body), ["[xy   ][   xy][xy][  12]"]);
}
