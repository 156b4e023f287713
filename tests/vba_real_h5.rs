//! Constructs that real automation modules (issue 31, session 26's sample: /tmp/realvba26/h5)
//! needed, each in a small macro of our own with the result Microsoft's VBA or Excel
//! reference, or [MS-VBAL], gives (the page or section named at each test).

mod common;

use common::vba::printed_after as printed;

// [MS-VBAL] 3.3.5.3 "Type characters": a type character is no part of the name it follows, so
// `s$` and `s` name one variable, a String ("$" String). healde/Excel-VBA's LastNumIndex.bas
// writes `indexGot$ = getOnlyIndex(element)` and then tests `If Not indexGot = ""`; a
// `Dim q$` is read back as `q` and as `q$`. VarType 8 is vbString ("VarType function").
#[test]
fn a_string_type_character_names_the_same_variable() {
    let out = printed(
        "",
        "    a$ = \"x\"\n\
         \x20   Debug.Print a; TypeName(a); VarType(a$)\n\
         \x20   Dim q$\n\
         \x20   q = \"z\"\n\
         \x20   Debug.Print q$; Len(q$); TypeName(q$)\n\
         \x20   b$ = 5\n\
         \x20   Debug.Print TypeName(b); b & \"|\"",
    );
    assert_eq!(out, ["xString 8 ", "z 1 String", "String5|"]);
}
