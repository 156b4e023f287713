//! Constructs of the real public modules run in session 18 (issue 31), each cut down to a
//! macro of our own: `DefLng A-Z` (a Russian "sum in words" module and an Office 2000 string
//! library both begin `Option Base 1` / `DefLng A-Z`), CStr of an error value (a geodesy
//! module's functions return `CVErr(xlErrNA)`). Expected values from Microsoft's VBA reference
//! and [MS-VBAL], the page or section named at each test.

use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

fn run(src: &str) -> Result<Vec<String>, String> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).map(|out| out.printed).map_err(|e| e.message)
}

// "Deftype statements": the directive sets "the default data type for variables, arguments
// passed to procedures, and the return type for Function … procedures whose names start with
// the specified characters"; an `As` clause or a type character overrides it. A Long takes
// 2.5 and 3.5 to the even whole number ("Type conversion functions": CLng rounds halves to
// the nearest even number), so Half(5) = 2 and Half(7) = 4.
#[test]
fn def_statements_type_variables_parameters_and_results_by_first_letter() {
    let src = "DefLng A-Z\nDefStr S\nFunction Half(x)\n    Half = x / 2\nEnd Function\n\
               Sub Main()\n    Dim n, s, v As Variant, d#\n    n = 2.5: s = 7: v = 2.5: d = 2.5\n\
               \x20   Debug.Print TypeName(n) & \" \" & n & \" \" & TypeName(s) & \" \" & s & \" \" & v & \" \" & d\n\
               \x20   Debug.Print TypeName(Half(5)) & \" \" & Half(5) & \" \" & Half(7)\nEnd Sub\n";
    assert_eq!(run(src).unwrap(), ["Long 2 String 7 2.5 2.5", "Long 2 4"]);
}

// [MS-VBAL] 5.2.2: a letter range covers its letters whatever their case ("The case of letters
// in letterrange isn't significant"); names outside every range stay Variants.
#[test]
fn a_letter_range_covers_its_letters_in_either_case_and_no_other() {
    let src = "DefDbl c-E\nSub Main()\n    Dim count, Delta, zeta\n    count = 1: Delta = 1: zeta = 1\n\
               \x20   Debug.Print TypeName(count) & \" \" & TypeName(Delta) & \" \" & TypeName(zeta)\nEnd Sub\n";
    assert_eq!(run(src).unwrap(), ["Double Double Integer"]);
}

// [MS-VBAL] CStr's runtime semantics (the Conversion module of VBA's library): an Error value
// gives "Error", a space and its error code ("Type conversion functions", CStr's table: "A
// String containing the word Error followed by the error number"); CVErr's numbers are
// Excel's ("XlCVError enumeration": xlErrNA 2042, xlErrDiv0 2007).
#[test]
fn cstr_of_an_error_value_is_the_word_error_and_its_number() {
    let src = "Sub Main()\n    Dim v\n    v = CStr(CVErr(2042))\n\
               \x20   Debug.Print TypeName(v) & \"|\" & v & \"|\" & CStr(CVErr(xlErrDiv0))\nEnd Sub\n";
    assert_eq!(run(src).unwrap(), ["String|Error 2042|Error 2007"]);
}

// "StrConv function": vbFromUnicode (128) converts "from Unicode to the default code page of the
// system", Windows-1252 for a Western Excel (é is byte 233 there, as Python's
// 'é'.encode('cp1252') gives; € is 128), into a Byte array from 0; vbUnicode (64) converts such
// bytes back. A module's StrToBytes reads a text's digits byte by byte through it.
#[test]
fn strconv_from_unicode_gives_the_ansi_bytes_from_zero_and_unicode_reads_them_back() {
    let src = "Option Base 1\nSub Main()\n    Dim b() As Byte\n    b = StrConv(\"Aé€\", vbFromUnicode)\n\
               \x20   Debug.Print LBound(b); UBound(b); b(0); b(1); b(2)\n\
               \x20   Debug.Print StrConv(b, vbUnicode) = \"Aé€\"\nEnd Sub\n";
    assert_eq!(run(src).unwrap(), [" 0  2  65  233  128 ", "True"]);
}
