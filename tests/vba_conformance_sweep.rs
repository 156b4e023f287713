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
