//! VBA's LongLong as a 64-bit integer, exact past 2^53 where a double is not ("LongLong data
//! type": a signed 64-bit integer, -9,223,372,036,854,775,808 to 9,223,372,036,854,775,807).
//! Expected values are worked in Python's unbounded integers (shown beside each), and the
//! rules are MS-VBAL's (each test cites its section), not our own output.

mod common;

use common::vba::{printed_after as printed, run_module as run};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

// [MS-VBAL] 5.6.9.3: `+`, `-` and `*` of LongLong operands (or a LongLong beside a Long or
// an Integer) are LongLong operations; 5.5.1.2.4, CStr of a number is its decimal text. Past
// 2^53 a double skips odd numbers: 9007199254740993 + 2 is 9007199254740995 exactly as a
// 64-bit integer, where doubles give 9007199254740994. Python:
// 9007199254740993 + 2 == 9007199254740995; 3037000499 * 3037000499 == 9223372030926249001;
// (2**62 - 1) * 2 + 1 == 2**63 - 1 == 9223372036854775807; 4503599627370497 * 2 + 1 ==
// 9007199254740995; 9007199254740993 - 9007199254740992 == 1.
#[test]
fn long_long_arithmetic_is_exact_past_2_to_the_53() {
    let out = printed(
        "",
        "    Dim x As LongLong, y As LongLong, z As LongLong\n    x = 9007199254740993^\n\
         \x20   Debug.Print CStr(x + 2); \" \"; CStr(x - 9007199254740992^); \" \"; TypeName(x + 2&)\n\
         \x20   y = 3037000499^\n    y = y * y\n    Debug.Print CStr(y)\n\
         \x20   z = 4611686018427387903^\n    z = z * 2 + 1\n    Debug.Print CStr(z); \" \"; CStr(z - 1 - 9223372036854775806^)\n\
         \x20   Debug.Print x + 2; Str(x + 2); \" \"; Format(x + 2); \" \"; \"n=\" & (x + 2)",
    );
    assert_eq!(
        out,
        [
            "9007199254740995 1 LongLong",
            "9223372030926249001",
            "9223372036854775807 0",
            " 9007199254740995  9007199254740995 9007199254740995 n=9007199254740995",
        ]
    );
}

// [MS-VBAL] 5.6.9.3.6 and 5.6.9.3.7 (`\` and `Mod`): the quotient truncated toward zero, and
// the remainder with the dividend's sign (Office VBA reference, "Mod operator": -7 Mod 3
// is -1), on the 64-bit integers. Python (truncating): -9007199254740993 \ 2 ==
// -4503599627370496 (-4503599627370496.5 truncated); -9007199254740993 Mod 2 == -1;
// 9007199254740993 Mod 10 == 3; 9007199254740993 \ -10 == -900719925474099;
// -9007199254740993 Mod -10 == -3.
#[test]
fn integer_division_and_mod_of_long_longs_truncate_on_the_integers() {
    let out = printed(
        "",
        "    Dim x As LongLong\n    x = -9007199254740993^\n\
         \x20   Debug.Print CStr(x \\ 2); \" \"; x Mod 2; CStr(-x Mod 10); \" \"; CStr(-x \\ -10); \" \"; x Mod -10",
    );
    assert_eq!(out, ["-4503599627370496 -1 3 -900719925474099 -3 "]);
}

// [MS-VBAL] 5.6.9.5 (relational operators): two integral operands compare as the wider
// integral type, here LongLong, so 9007199254740993 and 9007199254740992, one apart, are
// not equal (their doubles are).
#[test]
fn comparisons_of_long_longs_are_on_the_integers() {
    let out = printed(
        "",
        "    Dim a As LongLong, b As LongLong\n    a = 9007199254740993^\n    b = 9007199254740992^\n\
         \x20   Debug.Print a = b; a > b; a <> b; b < a; a - 1 = b",
    );
    assert_eq!(out, ["FalseTrueTrueTrueTrue"]);
}

// [MS-VBAL] 3.3.2: a decimal literal with the `^` type character is a LongLong, up to
// 9223372036854775807; a hex or octal one with `^` is its 64 bits, the top one the sign
// (Python: int('7FFFFFFFFFFFFFFF', 16) == 2**63 - 1; 0xFFFFFFFFFFFFFFFF - 2**64 == -1;
// 0x8000000000000000 - 2**64 == -2**63). The `^` right after the digits is the type
// character, so `5^ + 1` is the LongLong 5 plus 1 (6), where `5 ^ 1` and `2^2` stay powers.
#[test]
fn long_long_literals_reach_the_type_s_top_and_bind_their_suffix() {
    let out = printed(
        "",
        "    Debug.Print CStr(9223372036854775807^); \" \"; 9223372036854775807^ = &H7FFFFFFFFFFFFFFF^\n\
         \x20   Debug.Print &HFFFFFFFFFFFFFFFF^; CStr(&H8000000000000000^); \" \"; TypeName(&H10^)\n\
         \x20   Debug.Print 5^ + 1; TypeName(5^ + 1); 5^ - 1; 2^2; 5 ^ 1",
    );
    assert_eq!(out, ["9223372036854775807 True", "-1 -9223372036854775808 LongLong", " 6 LongLong 4  4  5 ",]);
    // One past the top is no LongLong: a compile error naming its place.
    let e = run("Sub Main()\n    x = 9223372036854775808^\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("LongLong"), "{e}");
    assert_eq!(e.span.unwrap().line, 2, "{e}");
}

// [MS-VBAL] 5.6.9.3 and Office VBA reference "Overflow (Error 6)": a LongLong operation
// whose result is past -2^63 .. 2^63 - 1 is Overflow, Err.Number 6, one past the top
// (2**63 - 1 + 1) as well as a product (2**62 * 2 == 2**63); 5.6.9.3.1, the negation of
// -2^63 too. Doubles cannot tell 2^63 - 1 + 1 from 2^63 - 1.
#[test]
fn long_long_overflow_is_error_6() {
    let out = printed(
        "",
        "    Dim x As LongLong, y As LongLong\n    x = 9223372036854775807^\n    On Error Resume Next\n\
         \x20   y = x + 1\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   y = 4611686018427387904^ * 2\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   y = -x - 1\n    Debug.Print Err.Number; CStr(y)\n    Err.Clear\n\
         \x20   y = -y\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   y = x - 1 + 1\n    Debug.Print Err.Number; CStr(y)",
    );
    assert_eq!(out, [" 6 ", " 6 ", " 0 -9223372036854775808", " 6 ", " 0 9223372036854775807"]);
}

// [MS-VBAL] 5.6.9.3: a Double beside a LongLong makes the operation a Double's, and `/`
// and `^` give Doubles (5.6.9.3.5, 5.6.9.3.8); a Long beside a LongLong a LongLong.
// "VarType function": vbLongLong is 20; a Variant keeps its LongLong (2.1.1.1) and its
// value. CLngLng of a String of digits is that integer ("Type conversion functions").
#[test]
fn long_long_types_mix_as_vba_types_them() {
    let out = printed(
        "",
        "    Dim x As LongLong, v\n    x = 9007199254740993^\n    v = x\n\
         \x20   Debug.Print TypeName(x + 0.5); TypeName(x / 1); TypeName(x ^ 1); TypeName(x * 2&); VarType(v)\n\
         \x20   Debug.Print CStr(v + 2); \" \"; CStr(CLngLng(\"9223372036854775807\")); \" \"; CStr(CLngLng(v) + 2)",
    );
    assert_eq!(out, ["DoubleDoubleDoubleLongLong 20 ", "9007199254740995 9223372036854775807 9007199254740995"]);
}

// [MS-VBAL] 5.3.1.11: a ByVal parameter is bound to the argument's value, and a ByRef one
// gives back what the procedure made of it; 5.3.1.2, a Function's result is what its name
// was assigned. Each carries the LongLong whole (Python: 4503599627370497 * 2 + 1 ==
// 9007199254740995; 9007199254740995 + 2 == 9007199254740997).
#[test]
fn long_longs_pass_through_parameters_and_function_results() {
    let module = "Function Twice(ByVal k As LongLong) As LongLong\n    Twice = k * 2 + 1\nEnd Function\n\
                  Sub Bump(ByRef k As LongLong)\n    k = k + 2\nEnd Sub\n";
    let out = printed(
        module,
        "    Dim x As LongLong\n    x = Twice(4503599627370497^)\n    Debug.Print CStr(x); \" \"; CStr(Twice(4503599627370497^) + 0&)\n\
         \x20   Bump x\n    Debug.Print CStr(x)",
    );
    assert_eq!(out, ["9007199254740995 9007199254740995", "9007199254740997"]);
}

// Excel's cells hold doubles (IEEE 754, "Excel specifications and limits": 15 digits of
// precision); a LongLong written to a cell is its nearest double: 9007199254740995 lies
// between the doubles 9007199254740994 and 9007199254740996 and rounds to the even one,
// 9007199254740996 (Python: float(9007199254740995) == 9007199254740996.0).
#[test]
fn a_long_long_written_to_a_cell_is_its_nearest_double() {
    let mut wb = Workbook::with_sheet();
    let src =
        "Sub Main()\n    Dim x As LongLong\n    x = 9007199254740993^\n    Range(\"A1\").Value = x + 2\nEnd Sub\n";
    vba::run(&mut wb, src, "test.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(wb.value(0, parse_cell("A1").unwrap()), Value::Number(9007199254740996.0));
}

// [MS-VBAL] 5.2.3.2 (constant declarations): a constant's value is its expression's, here
// a LongLong, kept whole as a variable keeps it (Python: 9007199254740993 + 2 ==
// 9007199254740995; 9223372036854774001 - 1 == 9223372036854774000, whose nearest double
// is 9223372036854773760), at module level and in a procedure.
#[test]
fn a_long_long_constant_keeps_its_integer() {
    let out = printed(
        "Const TOP As LongLong = 9223372036854774001^",
        "    Const BIG As LongLong = 9007199254740993^\n    Debug.Print CStr(BIG + 2); \" \"; CStr(TOP - 1)",
    );
    assert_eq!(out, ["9007199254740995 9223372036854774000"]);
}

// [MS-VBAL] 5.4.2.10 (Select Case): each Case compares the subject as `=`, `<=`, `>=` and
// the relational operator of `Case Is` do, here on two LongLongs' integers (5.6.9.5).
// 9007199254740993 and 9007199254740992 are one double (Python:
// float(9007199254740993) == 9007199254740992.0) but different LongLongs
// (9007199254740993 > 9007199254740992), so only the Cases naming ...993 hold.
#[test]
fn select_case_compares_long_longs_on_their_integers() {
    let out = printed(
        "",
        "    Dim x As LongLong\n    x = 9007199254740993^\n\
         \x20   Select Case x\n        Case 9007199254740992^: Debug.Print \"992\"\n\
         \x20       Case 9007199254740993^: Debug.Print \"993\"\n    End Select\n\
         \x20   Select Case x\n        Case Is <= 9007199254740992^: Debug.Print \"<=992\"\n\
         \x20       Case Is > 9007199254740992^: Debug.Print \">992\"\n    End Select\n\
         \x20   Select Case x\n        Case 9007199254740990^ To 9007199254740992^: Debug.Print \"to 992\"\n\
         \x20       Case 9007199254740993^ To 9007199254740995^: Debug.Print \"from 993\"\n    End Select",
    );
    assert_eq!(out, ["993", ">992", "from 993"]);
}

// [MS-VBAL] 5.4.2.3 (For statement): the counter is assigned the start, then its value plus
// the step each time round, until it passes the end; for a LongLong counter that addition is
// a LongLong's (5.6.9.3), so past 2^53 it moves by exactly the step where a double's + 1
// would leave 9007199254740992 where it is. Python:
// list(range(9007199254740993, 9007199254740998, 2)) == [..993, ..995, ..997], the counter
// then 9007199254740999; list(range(9007199254740995, 9007199254740992, -1)) == [..995,
// ..994, ..993].
#[test]
fn a_long_long_for_counter_steps_on_its_integer_past_2_to_the_53() {
    let out = printed(
        "",
        "    Dim i As LongLong, n As Long, v\n\
         \x20   For i = 9007199254740993^ To 9007199254740997^ Step 2\n        n = n + 1: Debug.Print CStr(i)\n    Next\n\
         \x20   Debug.Print CStr(n); \" \"; CStr(i)\n\
         \x20   For v = 9007199254740995^ To 9007199254740993^ Step -1\n        Debug.Print CStr(v)\n    Next",
    );
    assert_eq!(
        out,
        [
            "9007199254740993",
            "9007199254740995",
            "9007199254740997",
            "3 9007199254740999",
            "9007199254740995",
            "9007199254740994",
            "9007199254740993",
        ]
    );
}

// "LongLong data type": a signed 64-bit integer, every whole number to 9,223,372,036,854,775,807
// exact, as an item of an array of LongLong ("Dim statement": an array's items are of its
// type) and of a Variant array (a Variant holds a LongLong as itself, "Variant data type").
// 9007199254740993 = 2^53 + 1 has no double; the sums are worked with Python's int:
// 9007199254740993 + 2 = 9007199254740995, 2^53 + 1 - 1 = 9007199254740992. An item given
// another value afterwards is that value: a(1) = 9007199254740992^ (2^53, the double that
// 2^53 + 1 rounds to) shows 9007199254740992, not the integer kept before.
#[test]
fn an_array_item_keeps_its_long_long_past_two_to_the_53() {
    let out = printed(
        "",
        "    Dim a(3) As LongLong, v(1 To 2)\n\
         \x20   a(1) = 9007199254740993^: v(2) = 9007199254740993^\n\
         \x20   Debug.Print CStr(a(1) + 2)\n    Debug.Print CStr(v(2) - 1)\n    Debug.Print a(1) = v(2) + 0\n\
         \x20   a(1) = 9007199254740992^\n    Debug.Print CStr(a(1)); \" \"; a(1) = v(2)",
    );
    assert_eq!(out, ["9007199254740995", "9007199254740992", "True", "9007199254740992 False"]);
}

// "Abs function": the absolute value, "of the same type as that passed to it"; "Int, Fix
// functions": the integer portion, a whole number being its own, of the argument's type;
// "Sgn function": -1 below zero. On LongLongs that no double holds (Python:
// abs(-9223372036854775807) == 9223372036854775807; -9007199254740993 // 1 ==
// -9007199254740993; abs(-9007199254740993) + 2 == 9007199254740995; float(9007199254740993)
// == 9007199254740992.0, one off).
#[test]
fn abs_int_fix_and_sgn_keep_a_long_long_s_integer() {
    let out = printed(
        "",
        "    Dim x As LongLong\n    x = -9007199254740993^\n\
         \x20   Debug.Print CStr(Abs(-9223372036854775807^)); \" \"; TypeName(Abs(x))\n\
         \x20   Debug.Print CStr(Int(x)); \" \"; CStr(Fix(x)); \" \"; CStr(Abs(x) + 2); Sgn(x)",
    );
    assert_eq!(out, ["9223372036854775807 LongLong", "-9007199254740993 -9007199254740993 9007199254740995-1 "]);
}

// "IIf function": it returns one of two parts, a Variant holding that part's value (both are
// evaluated). 9007199254740993 and 9007199254740992 are one double (Python:
// float(9007199254740993) == float(9007199254740992)), so only the branch chosen tells which
// LongLong it gave; 9007199254740993 + 2 == 9007199254740995.
#[test]
fn iif_gives_the_long_long_of_the_branch_it_chose() {
    let out = printed(
        "",
        "    Dim big As LongLong, c As Boolean\n    big = 9007199254740993^\n\
         \x20   Debug.Print CStr(IIf(True, big, 0)); \" \"; TypeName(IIf(True, big, 0)); \" \"; CStr(IIf(False, 0, big) + 2)\n\
         \x20   c = False\n    Debug.Print CStr(IIf(c, big, 9007199254740992^)); \" \"; CStr(IIf(Not c, big, 9007199254740992^))",
    );
    assert_eq!(out, ["9007199254740993 LongLong 9007199254740995", "9007199254740992 9007199254740993"]);
}

// "Format function", user-defined number formats: `0` is a digit or a zero, `#` a digit or
// nothing, `,` between digit placeholders separates the thousands. The LongLong's every digit
// is laid out (Python: f"{9007199254740993:,}" == "9,007,199,254,740,993";
// "-" + str(9007199254740993).zfill(20) == "-00009007199254740993").
#[test]
fn format_with_a_code_lays_out_every_digit_of_a_long_long() {
    let out = printed(
        "",
        "    Dim x As LongLong\n    x = 9007199254740993^\n\
         \x20   Debug.Print Format(x, \"0\"); \" \"; Format(x, \"#,##0\"); \" \"; Format(-x, \"00000000000000000000\")",
    );
    assert_eq!(out, ["9007199254740993 9,007,199,254,740,993 -00009007199254740993"]);
    // A code that would lay out the nearest double's digits instead is refused.
    let e = run("Sub Main()\n    Debug.Print Format(9007199254740993^, \"0.00\")\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("run-time error 6"), "{}", e.message);
}

// "LongLong data type": every whole number to 9,223,372,036,854,775,807 is a LongLong, and a
// LongLong argument binds to a LongLong parameter as it is ([MS-VBAL] 5.3.1.11). The top 512
// of them share the double 2^63 (Python: float(2**63 - 512) == float(2**63 - 1) == 2.0**63),
// one past the type, yet are in it: 9223372036854775807 - 1 == 9223372036854775806,
// 2**63 - 512 == 9223372036854775296, minus 1 == 9223372036854775295.
#[test]
fn long_long_arguments_reach_the_top_of_the_type() {
    let module = "Function Less(ByVal k As LongLong) As LongLong\n    Less = k - 1\nEnd Function\n";
    let out =
        printed(module, "    Debug.Print CStr(Less(9223372036854775807^)); \" \"; CStr(Less(9223372036854775296^))");
    assert_eq!(out, ["9223372036854775806 9223372036854775295"]);
}

// [MS-VBAL] 5.3.1.11: each call binds its own arguments. An argument that calls a Function
// binds that Function's parameters in between, whose LongLong must not reach the outer call:
// Bump(Less(9007199254740993^)) is (9007199254740993 - 1) + 2 == 9007199254740994 (Python),
// where the inner argument, 9007199254740993, shares the double of 9007199254740992.
#[test]
fn a_call_in_an_argument_binds_its_own_long_longs() {
    let module = "Function Less(ByVal k As LongLong) As LongLong\n    Less = k - 1\nEnd Function\n\
                  Function Bump(ByVal k As LongLong) As LongLong\n    Bump = k + 2\nEnd Function\n";
    let out = printed(module, "    Debug.Print CStr(Bump(Less(9007199254740993^)))");
    assert_eq!(out, ["9007199254740994"]);
}

// A Type's field, a Collection's or a Dictionary's item and an item reached through another
// item keep a double alone in ncsheet (docs/limits.md); 9007199254740993 has none (Python:
// int(float(9007199254740993)) == 9007199254740992), so it is refused there, Overflow
// (run-time error 6), never kept as the other number.
#[test]
fn a_long_long_no_double_holds_is_refused_where_only_a_double_is_kept() {
    let types = "Type T\n    n As LongLong\n    arr(3) As LongLong\nEnd Type\n";
    for body in [
        "    Dim t As T\n    t.n = 9007199254740993^",
        "    Dim t As T\n    t.arr(2) = 9007199254740993^",
        "    Dim a(2) As T\n    a(1).n = 9007199254740993^",
        "    Dim c As New Collection\n    c.Add 9007199254740993^",
        "    Dim d\n    Set d = CreateObject(\"Scripting.Dictionary\")\n    d(\"k\") = 9007199254740993^",
        "    Dim v(1), w(1)\n    v(1) = w\n    v(1)(0) = 9007199254740993^",
    ] {
        let e = run(&format!("{types}Sub Main()\n{body}\nEnd Sub\n")).unwrap_err();
        assert!(
            e.message.contains("run-time error 6") && e.message.contains("9007199254740993"),
            "{body}: {}",
            e.message
        );
    }
    // A LongLong whose double is exact is kept there as any number (Python: float(2**53) == 2**53).
    let out = printed(
        types,
        "    Dim c As New Collection\n    c.Add 9007199254740992^\n    Debug.Print c(1) = 9007199254740992^",
    );
    assert_eq!(out, ["True"]);
}

// "ReDim statement": Preserve keeps the items of the array, of two dimensions too (only the
// last one's upper bound changes). An item that holds a LongLong keeps it whole, in an array
// of LongLong and of Variant (Python: 9007199254740993 + 2 == 9007199254740995).
#[test]
fn redim_preserve_keeps_a_long_long_item() {
    let out = printed(
        "",
        "    Dim a() As LongLong, v()\n    ReDim a(1, 1): ReDim v(1 To 2, 1 To 2)\n\
         \x20   a(1, 1) = 9007199254740993^: v(2, 2) = 9007199254740993^\n\
         \x20   ReDim Preserve a(1, 3): ReDim Preserve v(1 To 2, 1 To 5)\n\
         \x20   Debug.Print CStr(a(1, 1) + 2); \" \"; CStr(v(2, 2) + 2)",
    );
    assert_eq!(out, ["9007199254740995 9007199254740995"]);
}
