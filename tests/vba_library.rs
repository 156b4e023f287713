//! VBA's library as real modules use it (issue 31, scope 3): built-ins beyond the first set
//! (`String`, `Hex`, `Oct`, `DateSerial`, `TimeSerial`, `CLngLng`, `StrReverse`, `Replace`'s
//! start/count/compare, the Mid statement, `Application.Run`), Null given to library
//! functions, and `TypeName` of a class module's object.
//!
//! Each expected value is the one Microsoft's VBA language reference (learn.microsoft.com,
//! "Office VBA language reference", the page named at each test, its examples' stated
//! results) or [MS-VBAL] section 6 (the VBA standard library's "Runtime Semantics") gives. The
//! cases LibreOffice Basic agrees on are run there too (tests/vba_libreoffice.rs, "library").

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run_src(src: &str) -> Result<RunOutput, MacroError> {
    vba::run(&mut Workbook::with_sheet(), src, "Module1.bas", &RunOptions::default())
}

/// What a Sub body prints with Debug.Print, line by line.
fn printed(body: &str) -> Vec<String> {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    run_src(&src).unwrap_or_else(|e| panic!("{e}")).printed
}

/// One expression as `CStr` shows it (Null: "Null").
fn shown(expr: &str) -> String {
    let out = printed(&format!(
        "    Dim v\n    v = {expr}\n    If IsNull(v) Then Debug.Print \"Null\" Else Debug.Print CStr(v)"
    ));
    out[0].clone()
}

// "String function", its example: String(5, "*") and String(5, 42) are "*****",
// String(10, "ABC") is "AAAAAAAAAA"; "If number contains Null, Null is returned" (and the
// same for character).
#[test]
fn string_repeats_a_character() {
    assert_eq!(shown("String(5, \"*\")"), "*****");
    assert_eq!(shown("String(5, 42)"), "*****");
    assert_eq!(shown("String(10, \"ABC\")"), "AAAAAAAAAA");
    assert_eq!(shown("String(0, \"x\")"), "");
    assert_eq!(shown("String(Null, \"x\")"), "Null");
    assert_eq!(shown("String(3, Null)"), "Null");
    // "If you specify a number for character greater than 255, String converts the number
    // to a valid character code by using this formula: character Mod 256."
    assert_eq!(shown("String(3, 42 + 256)"), "***");
}

// "Hex function": Hex(5) is "5", Hex(10) "A", Hex(459) "1CB", Hex(255) "FF"; [MS-VBAL]
// 6.1.2 Hex: Null gives Null (and Hex$ raises error 94), Empty "0", -32,767 to -1 the 16-bit
// two's complement, below it the 32-bit one; a fraction is rounded first.
#[test]
fn hex_and_oct_write_whole_numbers() {
    assert_eq!(printed("    Debug.Print Hex(5); Hex(10); Hex(459); Hex(255)"), ["5A1CBFF"]);
    assert_eq!(shown("Hex(-1)"), "FFFF");
    assert_eq!(shown("Hex(-32768)"), "FFFF8000");
    assert_eq!(shown("Hex(2.5)"), "2");
    assert_eq!(shown("Hex(Empty)"), "0");
    assert_eq!(shown("Hex(Null)"), "Null");
    assert_eq!(shown("Hex$(4096)"), "1000");
    // "Oct function": Oct(4) is "4", Oct(8) "10", Oct(459) "713".
    assert_eq!(printed("    Debug.Print Oct(4); \" \"; Oct(8); \" \"; Oct(459)"), ["4 10 713"]);
    assert_eq!(shown("Oct(-1)"), "177777");
    assert_eq!(shown("Oct$(64)"), "100");
}

// "DateSerial function", its example: DateSerial(1969, 2, 12) is February 12, 1969, and
// DateSerial(1990 - 10, 8 - 2, 1 - 1) is May 31, 1980 (a day of 0 is the last of the month
// before); a two-digit year 0-29 is 2000-2029, 30-99 1930-1999. The day count is VBA's Date:
// days from 1899-12-30 (2020-01-31 is 43861, Excel's serial of that day too).
#[test]
fn date_serial_builds_a_date() {
    let f = |e: &str| shown(&format!("Format({e}, \"yyyy-mm-dd\")"));
    assert_eq!(f("DateSerial(1969, 2, 12)"), "1969-02-12");
    assert_eq!(f("DateSerial(1990 - 10, 8 - 2, 1 - 1)"), "1980-05-31");
    assert_eq!(f("DateSerial(2020, 13, 1)"), "2021-01-01");
    assert_eq!(f("DateSerial(2021, 3, 0)"), "2021-02-28");
    assert_eq!(f("DateSerial(20, 1, 1)"), "2020-01-01");
    assert_eq!(f("DateSerial(75, 1, 1)"), "1975-01-01");
    assert_eq!(shown("CDbl(DateSerial(2020, 1, 31))"), "43861");
    assert_eq!(shown("CDbl(DateSerial(1899, 12, 30))"), "0");
    assert_eq!(shown("CDbl(DateSerial(1899, 12, 29))"), "-1");
}

// "TimeSerial function", its example: TimeSerial(16, 35, 17) is 4:35:17 PM, and
// TimeSerial(12 - 6, -15, 0) is 5:45:00 AM (a negative minute borrows from the hour).
#[test]
fn time_serial_builds_a_time() {
    assert_eq!(shown("Format(TimeSerial(16, 35, 17), \"hh:mm:ss\")"), "16:35:17");
    assert_eq!(shown("Format(TimeSerial(12 - 6, -15, 0), \"hh:mm:ss\")"), "05:45:00");
    assert_eq!(shown("CDbl(TimeSerial(6, 0, 0))"), "0.25");
}

// "Type conversion functions": CLngLng rounds halves to the even number (0.5 to 0, 1.5 to 2),
// as CInt and CLng do; its range is LongLong's.
#[test]
fn clnglng_rounds_halves_to_even() {
    assert_eq!(printed("    Debug.Print CLngLng(0.5); CLngLng(1.5); CLngLng(2.5); CLngLng(-2.5)"), [" 0  2  2 -2 "]);
    assert_eq!(shown("CLngLng(\"3000000000\")"), "3000000000");
}

// "StrReverse function": the characters in reverse order; [MS-VBAL] declares its expression
// a String, so Null is error 94.
#[test]
fn str_reverse_reverses() {
    assert_eq!(shown("StrReverse(\"abc\")"), "cba");
    assert_eq!(shown("StrReverse(\"\")"), "");
}

// "Replace function": the return value "begins at the position specified by start"; count
// limits the replacements; vbTextCompare ignores case. The page's table: find "" gives a
// copy of expression, start past the length gives "".
#[test]
fn replace_takes_start_count_and_compare() {
    assert_eq!(shown("Replace(\"XXpXXPXXp\", \"p\", \"Y\")"), "XXYXXPXXY");
    assert_eq!(shown("Replace(\"XXpXXPXXp\", \"p\", \"Y\", 3)"), "YXXPXXY");
    assert_eq!(shown("Replace(\"XXpXXPXXp\", \"p\", \"Y\", 1, 1)"), "XXYXXPXXp");
    assert_eq!(shown("Replace(\"XXpXXPXXp\", \"p\", \"Y\", 1, -1, vbTextCompare)"), "XXYXXYXXY");
    assert_eq!(shown("Replace(\"XXpXXPXXp\", \"p\", \"Y\", 1, 0)"), "XXpXXPXXp");
    assert_eq!(shown("Replace(\"abc\", \"\", \"Y\", 2)"), "bc");
    assert_eq!(shown("Replace(\"abc\", \"b\", \"Y\", 9)"), "");
}

// "Mid statement", its example, line for line.
#[test]
fn mid_statement_replaces_characters_in_place() {
    let out = printed(
        "    Dim MyString
    MyString = \"The dog jumps\"
    Mid(MyString, 5, 3) = \"fox\"
    Debug.Print MyString
    Mid(MyString, 5) = \"cow\"
    Debug.Print MyString
    Mid(MyString, 5) = \"cow jumped over\"
    Debug.Print MyString
    Mid(MyString, 5, 3) = \"duck\"
    Debug.Print MyString",
    );
    assert_eq!(out, ["The fox jumps", "The cow jumps", "The cow jumpe", "The duc jumpe"]);
    // A typed String, and Mid$: the same statement.
    let out = printed("    Dim s As String\n    s = \"G01 X0\"\n    Mid$(s, 2, 2) = \"00\"\n    Debug.Print s");
    assert_eq!(out, ["G00 X0"]);
    // A start past the text is run-time error 5, "Invalid procedure call or argument".
    let out = printed(
        "    Dim s As String\n    s = \"abc\"\n    On Error Resume Next\n    Mid(s, 9) = \"x\"\n    Debug.Print Err.Number; s",
    );
    assert_eq!(out, [" 5 abc"]);
}

// "Application.Run method (Excel)": runs a macro by its name with arguments, and returns
// what a Function returns; a name the project lacks is run-time error 1004.
#[test]
fn application_run_calls_a_procedure_by_name() {
    let out = run_src(
        "Sub Main()\n    Application.Run \"Greet\", \"N10\"\n    Debug.Print Application.Run(\"Twice\", 21)\n\
         \x20   Dim name As String\n    name = \"Tw\" & \"ice\"\n    Debug.Print Application.Run(name, 4)\n\
         \x20   On Error Resume Next\n    Application.Run \"NoSuchMacro\"\n    Debug.Print Err.Number\nEnd Sub\n\
         Sub Greet(block)\n    Debug.Print \"hello \" & block\nEnd Sub\n\
         Function Twice(x)\n    Twice = x * 2\nEnd Function\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["hello N10", " 42 ", " 8 ", " 1004 "]);
}

// "Application.Run method (Excel)": each argument "should be passed to the function" as its
// value; an item of an array (`v(1)`, a Type member's `.Arr(0)` in a With block) is the item,
// so a Function with `ByVal a As Double` gets 4 and returns 5 * 4 = 20 (it stopped with "a is
// declared with a type and cannot hold an object or an array").
#[test]
fn application_run_passes_an_array_item_as_its_value() {
    let out = run_src(
        "Private Type Saved\n    Arr As Variant\nEnd Type\nPrivate This As Saved\n\
         Function Times(ByVal x As Double, ByVal a As Double) As Double\n    Times = x * a\nEnd Function\n\
         Sub Main()\n    Dim r As Double\n    This.Arr = Array(4, 7)\n    r = Application.Run(\"Times\", 5, This.Arr(0))\n\
         \x20   Debug.Print r\n    With This\n        r = Application.Run(\"Times\", 2, .Arr(1))\n    End With\n\
         \x20   Debug.Print r\nEnd Sub\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 20 ", " 14 "]);
}

// Null given to library functions: "If string contains Null, Null is returned" (Left,
// Right, Mid, Len, LTrim/RTrim/Trim, UCase/LCase); "If number contains Null, Null is
// returned" (Abs, Int, Fix); [MS-VBAL] section 6: Left$ and the other `$` forms return a String
// and raise error 94, "Invalid use of Null", as does a Null for a parameter that is not a
// Variant (Chr's code, Sqr's number, Left's length, CStr, CDbl).
#[test]
fn null_passes_through_string_and_number_functions() {
    for f in [
        "Left(Null, 1)",
        "Right(Null, 1)",
        "Mid(Null, 2)",
        "Len(Null)",
        "Trim(Null)",
        "LTrim(Null)",
        "RTrim(Null)",
        "UCase(Null)",
        "LCase(Null)",
        "Abs(Null)",
        "Int(Null)",
        "Fix(Null)",
    ] {
        assert_eq!(shown(f), "Null", "{f}");
    }
}

#[test]
fn null_where_a_value_is_needed_is_error_94() {
    for f in [
        "Left$(Null, 1)",
        "UCase$(Null)",
        "Chr(Null)",
        "Sqr(Null)",
        "Left(\"abc\", Null)",
        "CStr(Null)",
        "CDbl(Null)",
        "Space(Null)",
        "Hex$(Null)",
    ] {
        let out = printed(&format!(
            "    Dim v\n    On Error Resume Next\n    v = {f}\n    Debug.Print Err.Number; Err.Description"
        ));
        assert_eq!(out, [" 94 Invalid use of Null"], "{f}");
    }
    // Not trapped, the macro stops with the error's number and name.
    let e = run_src("Sub Main()\n    x = Chr(Null)\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("Invalid use of Null") && e.message.contains("94"), "{e}");
}

// "TypeName function": an object's class; for an object of a class module, its name.
#[test]
fn type_name_of_a_class_object_is_its_class() {
    let main = "Sub Main()\n    Dim t As Tool\n    Set t = New Tool\n\
                \x20   Debug.Print TypeName(t)\n    Dim v As Variant\n    Set v = t\n    Debug.Print TypeName(v)\nEnd Sub\n";
    let options =
        RunOptions { classes: vec![("Tool".into(), "Public Diameter As Double\n".into())], ..RunOptions::default() };
    let out = vba::run(&mut Workbook::with_sheet(), main, "Module1.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["Tool", "Tool"]);
}

// "Format function", its predefined formats with English (United States) system settings:
// Currency (thousands separator, two decimals, a negative number in parentheses), Yes/No,
// True/False, On/Off (0 is No, False, Off); General Date (the date, the time, or both as
// the value has them), Long Date, Medium Date, Short Date, Long Time, Medium Time (12-hour,
// AM/PM), Short Time (24-hour).
#[test]
fn format_takes_the_predefined_formats() {
    let out = printed(
        "    d = DateSerial(2026, 11, 28) + TimeSerial(14, 5, 9)
    Debug.Print Format(1234.5, \"Currency\"); \"|\"; Format(-1234.5, \"Currency\")
    Debug.Print Format(0, \"Yes/No\"); Format(3, \"Yes/No\"); Format(0, \"True/False\"); Format(-1, \"On/Off\")
    Debug.Print Format(d, \"General Date\"); \"|\"; Format(Int(d), \"General Date\"); \"|\"; Format(d - Int(d), \"General Date\")
    Debug.Print Format(d, \"Long Date\"); \"|\"; Format(d, \"Medium Date\"); \"|\"; Format(d, \"Short Date\")
    Debug.Print Format(d, \"Long Time\"); \"|\"; Format(d, \"Medium Time\"); \"|\"; Format(d, \"Short Time\")",
    );
    assert_eq!(
        out,
        [
            "$1,234.50|($1,234.50)",
            "NoYesFalseOn",
            "11/28/2026 2:05:09 PM|11/28/2026|2:05:09 PM",
            "Saturday, November 28, 2026|28-Nov-26|11/28/2026",
            "2:05:09 PM|02:05 PM|14:05",
        ]
    );
}

// "Format function" (Office VBA language reference), its example (MyTime = #17:04:23#,
// MyDate = #January 27, 1993#, English/U.S. assumed) and its tables of user-defined
// date/time and string formats. The date/time codes on December 7, 1958, 8:50:35 PM (a
// Sunday), the date of Microsoft's "User-Defined Date/Time Formats Example" (VBA 6
// reference: "hh:mm AM/PM" 08:50 PM, "h:mm:ss a/p" 8:50:35 p, "m/d/yy h:mm" 12/7/58 20:50);
// the rest worked by hand from the tables: `y` the day of the year (334 days in January to
// November + 7 = 341), `q` the quarter (4), `w` the day of the week (Sunday 1), `ww` the week
// of the year from the week of January 1 (a Wednesday in 1958: week 2 starts January 5, and
// December 7 is 48 weeks later, week 50), `n`/`nn` the minute, `ttttt` the system's long
// time, `ddddd`/`dddddd` its short and long date and `c` both (English/U.S.: m/d/yyyy,
// "dddd, mmmm d, yyyy", h:mm:ss AM/PM, as the Short Date, Long Date and Long Time of
// tests above), `AMPM` the system's designator. LibreOffice's VBA mode agrees on `y`, `w`,
// `ww`, `ttttt` and `dddddd`, and differs where its Format lacks the code (`n`, `q` as "Q4",
// `AMPM`, `am/pm` in capitals, `@` padding), so it is not the oracle for those.
#[test]
fn format_reads_vba_date_and_time_codes() {
    let out = printed(
        "    t = TimeSerial(17, 4, 23)
    Debug.Print Format(t, \"h:m:s\"); \"|\"; Format(t, \"hh:mm:ss am/pm\"); \"|\"; Format(t, \"hh:mm:ss AM/PM\")
    Debug.Print Format(DateSerial(1993, 1, 27), \"dddd, mmm d yyyy\")
    d = DateSerial(1958, 12, 7) + TimeSerial(20, 50, 35)
    Debug.Print Format(d, \"hh:mm AM/PM\"); \"|\"; Format(d, \"h:mm:ss a/p\"); \"|\"; Format(d, \"m/d/yy h:mm\")
    Debug.Print Format(d, \"y\"); \"|\"; Format(d, \"q\"); \"|\"; Format(d, \"w\"); \"|\"; Format(d, \"ww\")
    Debug.Print Format(d, \"h:n:s\"); \"|\"; Format(d, \"hh:nn\"); \"|\"; Format(d, \"ttttt\"); \"|\"; Format(d, \"h:mm AMPM\")
    Debug.Print Format(d, \"c\"); \"|\"; Format(Int(d), \"c\"); \"|\"; Format(d - Int(d), \"c\")
    Debug.Print Format(d, \"ddddd\"); \"|\"; Format(d, \"dddddd\"); \"|\"; Format(DateSerial(2024, 3, 1), \"y\")",
    );
    assert_eq!(
        out,
        [
            "17:4:23|05:04:23 pm|05:04:23 PM",
            "Wednesday, Jan 27 1993",
            "08:50 PM|8:50:35 p|12/7/58 20:50",
            "341|4|1|50",
            "20:50:35|20:50|8:50:35 PM|8:50 PM",
            "12/7/1958 8:50:35 PM|12/7/1958|8:50:35 PM",
            "12/7/1958|Sunday, December 7, 1958|61",
        ]
    );
}

// A date letter after a number's digit placeholder is written as it is: VBA reads the
// section as a number format from its first placeholder (LibreOffice's VBA mode:
// Format(5, "0 w") is "5 w"); it was read as a date code and the number refused.
#[test]
fn a_date_letter_after_a_digit_placeholder_is_text() {
    assert_eq!(shown("Format(5, \"0 w\")"), "5 w");
    assert_eq!(shown("Format(2.5, \"0.0 h\")"), "2.5 h");
}

// "Format function", "User-defined string formats": `@` a character or a space, `&` a
// character or nothing, filled from right to left unless `!`; `<` small letters, `>`
// capitals (its example: Format("HELLO", "<") is "hello", Format("This is it", ">") "THIS
// IS IT"); a second section is for zero-length strings.
#[test]
fn format_applies_vba_string_formats() {
    assert_eq!(shown("Format(\"HELLO\", \"<\")"), "hello");
    assert_eq!(shown("Format(\"This is it\", \">\")"), "THIS IS IT");
    assert_eq!(shown("\"[\" & Format(\"abc\", \"@@@@@\") & \"]\""), "[  abc]");
    assert_eq!(shown("\"[\" & Format(\"abc\", \"&&&&&\") & \"]\""), "[abc]");
    assert_eq!(shown("\"[\" & Format(\"abc\", \"!@@@@@\") & \"]\""), "[abc  ]");
    assert_eq!(shown("Format(\"5551234567\", \"(@@@) @@@-@@@@\")"), "(555) 123-4567");
    assert_eq!(shown("Format(\"abc\", \">@@@\")"), "ABC");
    assert_eq!(shown("\"[\" & Format(5, \"@@@\") & \"]\""), "[  5]");
    assert_eq!(shown("Format(\"\", \"@;\"\"none\"\"\")"), "none");
    assert_eq!(shown("Format(\"x\", \"@;\"\"none\"\"\")"), "x");
}

// "InStr function": "If string1 is Null / string2 is Null: Null"; "StrComp function": "If
// string1 or string2 is Null: Null"; "Len function" covers LenB. A Null start is error 94.
#[test]
fn instr_and_strcomp_pass_null() {
    for f in
        ["InStr(Null, \"a\")", "InStr(1, \"abc\", Null)", "InStrRev(Null, \"a\")", "StrComp(\"a\", Null)", "LenB(Null)"]
    {
        assert_eq!(shown(f), "Null", "{f}");
    }
    let out = printed("    On Error Resume Next\n    x = InStr(Null, \"abc\", \"b\")\n    Debug.Print Err.Number");
    assert_eq!(out, [" 94 "]);
}

// Arguments out of range are VBA's run-time errors, raised and trappable, not values:
// [MS-VBAL] section 6: Hex and Oct Let-coerce to Long ("Overflow", error 6, past it); String's
// number and Replace's start below 1 are "Invalid procedure call or argument" (5); "DateSerial
// function": "If the date specified by the three arguments falls outside the acceptable
// range of dates, an error occurs".
#[test]
fn arguments_out_of_range_raise_vba_errors() {
    for (f, number) in [
        ("Hex(3000000000#)", 6),
        ("Oct(-3000000000#)", 6),
        ("String(-1, \"a\")", 5),
        ("String(2, \"\")", 5),
        ("Replace(\"abc\", \"b\", \"x\", 0)", 5),
        ("DateSerial(10000, 1, 1)", 5),
    ] {
        let out = printed(&format!("    Dim v\n    On Error Resume Next\n    v = {f}\n    Debug.Print Err.Number"));
        assert_eq!(out, [format!(" {number} ")], "{f}");
    }
}

// "Date function" and "Time function": `Date$` is a 10-character string, mm-dd-yyyy, and
// `Time$` an 8-character one, hh:mm:ss, of the same clock as Date and Time.
#[test]
fn date_and_time_dollar_are_strings() {
    let out = printed(
        "    Debug.Print TypeName(Date$); Len(Date$); Date$ Like \"##-##-####\"; Date$ = Format(Date, \"mm-dd-yyyy\")
    Debug.Print TypeName(Time$); Len(Time$); Time$ Like \"##:##:##\"",
    );
    assert_eq!(out, ["String 10 TrueTrue", "String 8 True"]);
}

// An argument outside a function's domain is run-time error 5, "Invalid procedure call or
// argument", raised (On Error traps it), not a value: "Mid function" (start below 1, a
// negative length), "Left function" and "Right function" (a negative length), "Space
// function", "String function" (a negative number), "Chr function" (a negative code),
// "Asc function" ("If the string contains no characters, a run-time error occurs"), "InStr
// function" (start below 1), "InStrRev function", "Split function" (limit below -1), "Sqr
// function" (a number below zero), "Log function" (a number not above zero), "Round
// function" (negative decimal places; and more than 22, where the reference and MS-VBAL's
// Round, "Function Round(Number As Variant, Optional NumDigitsAfterDecimal As Long)", name no
// result and 10^22 is the last power of ten a Double scales by exactly: ncsheet raises the
// same error 5 there, a refusal, rather than print a guessed value). CInt and CLng past their
// type are error 6, Overflow ("Type conversion functions").
#[test]
fn an_argument_outside_the_domain_raises_error_5() {
    for f in [
        "Mid(\"abc\", 0)",
        "Mid(\"abc\", 1, -1)",
        "Left(\"abc\", -1)",
        "Right$(\"abc\", -1)",
        "Space(-1)",
        "String(-1, \"a\")",
        "Chr(-1)",
        "Asc(\"\")",
        "InStr(0, \"abc\", \"b\")",
        "InStrRev(\"abc\", \"b\", 0)",
        "Split(\"a b\", \" \", -2)",
        "Sqr(-1)",
        "Log(0)",
        "Round(2.5, -1)",
        "Round(2.5, 23)",
        // Past 99 decimals ncsheet refuses as VBA refuses an argument out of range (the
        // "FormatNumber function" page names no largest count); it was an Error value.
        "FormatNumber(1, 100)",
        "FormatPercent(1, 32767)",
        "FormatCurrency(1, 1000000000)",
    ] {
        let out = printed(&format!(
            "    Dim v\n    v = \"kept\"\n    On Error Resume Next\n    v = {f}\n    Debug.Print Err.Number; Err.Description; \" \"; v"
        ));
        assert_eq!(out, [" 5 Invalid procedure call or argument kept"], "{f}");
    }
    for f in ["CInt(40000)", "CLng(3E+9)"] {
        let out = printed(&format!("    Dim v\n    On Error Resume Next\n    v = {f}\n    Debug.Print Err.Number"));
        assert_eq!(out, [" 6 "], "{f}");
    }
    // Not trapped, the macro stops there, naming the error.
    let e = run_src("Sub Main()\n    Dim s As String\n    s = Mid(\"abc\", 0, 1)\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("Invalid procedure call or argument") && e.message.contains("Mid"), "{e}");
}

// "Err object": its default property is Number, so `Err = 10` sets Err.Number, and "Number
// property" is a Long that can be set (`Err.Number = 5`) without raising the error; a value
// set is rounded as a Long takes it (`Err = 0.3` is 0). Description can be set too.
#[test]
fn err_number_can_be_assigned_and_err_is_its_number() {
    let out = printed(
        "    Err = 10\n    Debug.Print Err; Err.Number; Err > 5\n    Err.Number = 5\n    Err.Description = \"mine\"\n\
         \x20   Debug.Print Err.Number; Err.Description\n    Err = 0.3\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 10  10 True", " 5 mine", " 0 "]);
}
