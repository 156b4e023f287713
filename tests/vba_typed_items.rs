//! A value keeps its type wherever it goes, and becomes the String its type writes wherever
//! VBA wants a String ([MS-VBAL] 5.5.1.2.4, Let-coercion to String): an array's items
//! (Join, Filter), a comparison with a String, a ByVal String parameter. Expected values are
//! MS-VBAL's and the Office VBA language reference's (each test cites its sections), not our
//! own output.

mod common;

use common::vba::printed_after as printed;

// "Variant data type": numeric Variant data "is maintained in its original data type", so an
// item of a Variant array given CSng(1 / 3) holds a Single, #1/2/2024# a Date, CCur(1.23456)
// a Currency (1.2346, "Currency data type": four places) and 1234567890123456^ a LongLong
// ("VarType function": 4, 7, 6, 20). "Join function" joins the array's strings: each item is
// let-coerced to String ([MS-VBAL] 5.5.1.2.4), a Single to its seven significant digits as
// CStr writes it ("Single data type"; CStr(CSng(1 / 3)) is "0.3333333"), a Date to its date
// in the system's short date format (en-US m/d/yyyy, a time alone h:mm:ss AM/PM: "Type
// conversion functions", CStr), a LongLong to every digit; a Double keeps its fifteen
// ("Double data type"). "Filter function" searches the same strings. An item of a typed array
// let-coerced by CStr or `&` ([MS-VBAL] 5.6.9.4) is written as its type writes it too.
#[test]
fn array_items_are_joined_and_filtered_as_their_types_write_them() {
    let out = printed(
        "",
        "    Dim v(4), a(1) As Single, d(1) As Date\n\
         \x20   v(0) = CSng(1 / 3): v(1) = #1/2/2024#: v(2) = CCur(1.23456): v(3) = 1234567890123456^: v(4) = 1 / 3\n\
         \x20   a(0) = 1 / 3: a(1) = 0.1: d(0) = #1/2/2024#: d(1) = #12:30:00 PM#\n\
         \x20   Debug.Print VarType(v(0)); VarType(v(1)); VarType(v(2)); VarType(v(3))\n\
         \x20   Debug.Print Join(v, \",\")\n\
         \x20   Debug.Print Join(Filter(v, \"/\"), \"|\"); \"|\"; UBound(Filter(v, \"33333\")); \"|\"; Filter(v, \"456\")(0)\n\
         \x20   Debug.Print CStr(a(0)); \"|\"; a(1) & \"\"; \"|\"; CStr(d(1)); \"|\"; d(0) & \"\"",
    );
    assert_eq!(
        out,
        [
            " 4  7  6  20 ",
            "0.3333333,1/2/2024,1.2346,1234567890123456,0.333333333333333",
            "1/2/2024| 1 |1234567890123456",
            "0.3333333|0.1|12:30:00 PM|1/2/2024",
        ]
    );
}

// "Comparison operators" (Office VBA reference), the table of how expressions compare: "One
// expression is a String and the other is any Variant except a Null: perform a string
// comparison". The Variant's number is let-coerced to String ([MS-VBAL] 5.5.1.2.4) as its
// type writes it: a Single held in a Variant is "0.3333333", a Date "1/2/2024", so both equal
// the Strings with that text, where the Double's text "0.333333343267441" and the day count
// "45293" did not.
#[test]
fn a_string_compared_with_a_variant_single_or_date_compares_the_text_its_type_writes() {
    let out = printed(
        "",
        "    Dim s As String, t As String, v, w\n    s = \"0.3333333\": t = \"1/2/2024\"\n\
         \x20   v = CSng(1 / 3): w = #1/2/2024#\n\
         \x20   Debug.Print s = v; v = s; t = w; w <> t; s < v; \"0.4\" > v",
    );
    assert_eq!(out, ["TrueTrueTrueFalseFalseTrue"]);
}

// [MS-VBAL] 5.3.1.11: an argument passed ByVal is let-coerced to the parameter's declared
// type; 5.5.1.2.4, Let-coercion to String: a LongLong becomes its every digit ("LongLong data
// type": a signed 64-bit integer, 9007199254740993 is one, where no Double is), a Decimal
// its every digit ("Decimal data type": up to 28 places, CDec(1) / 3 is
// 0.3333333333333333333333333333 as CStr writes it).
#[test]
fn a_longlong_or_a_decimal_given_to_a_string_parameter_keeps_every_digit() {
    let out = printed(
        "Sub Show(ByVal t As String)\n    Debug.Print \"[\" & t & \"]\";\nEnd Sub\n",
        "    Dim k As LongLong, m As LongLong, x\n    k = 9007199254740993^: m = 1234567890123456^: x = CDec(1) / 3\n\
         \x20   Show k: Show m: Show x: Show CDec(2) / 3: Debug.Print",
    );
    assert_eq!(
        out,
        ["[9007199254740993][1234567890123456][0.3333333333333333333333333333][0.6666666666666666666666666667]"]
    );
}
