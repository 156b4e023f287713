//! `Range.TextToColumns` (issue 31). Expected values are worked by hand from Microsoft's
//! "Range.TextToColumns method" page: DataType xlDelimited splits at the delimiters set True
//! (Tab, Semicolon, Comma, Space, Other with OtherChar), TextQualifier (xlDoubleQuote by
//! default) keeps a quoted field whole, ConsecutiveDelimiter "True to have Excel consider
//! consecutive delimiters as one delimiter", Destination is where the fields go (the range
//! itself when omitted), and each field is typed as General: `10.5` is a number.

mod common;

use common::sheet::{get, n, set};
use common::vba::{main_fails, run_main};
use ncsheet::eval::Value;
use ncsheet::workbook::Workbook;

fn text(s: &str) -> Value {
    Value::text(s)
}

// Spaces, several in a row taken as one: an NC block's words go one to a column.
#[test]
fn spaces_split_a_block_into_its_words() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "G01 X10.5  Y-3");
    set(&mut wb, "A2", "M30");
    run_main(&mut wb, "Range(\"A1:A2\").TextToColumns DataType:=xlDelimited, ConsecutiveDelimiter:=True, Space:=True");
    assert_eq!([get(&wb, "A1"), get(&wb, "B1"), get(&wb, "C1")], [text("G01"), text("X10.5"), text("Y-3")]);
    assert_eq!([get(&wb, "A2"), get(&wb, "B2")], [text("M30"), Value::Blank]);
}

// Commas with a quoted field, into Destination:=C1: the quotes group "M6, zinc" and go; 12
// is typed as a number; A1 itself stays as it was.
#[test]
fn a_quoted_field_keeps_its_commas_and_the_fields_go_to_the_destination() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "bolt,\"M6, zinc\",12");
    run_main(&mut wb, "Range(\"A1\").TextToColumns Destination:=Range(\"C1\"), Comma:=True");
    assert_eq!([get(&wb, "C1"), get(&wb, "D1"), get(&wb, "E1")], [text("bolt"), text("M6, zinc"), n(12.0)]);
    assert_eq!(get(&wb, "A1"), text("bolt,\"M6, zinc\",12"));
}

// "XlTextQualifier enumeration": xlTextQualifierSingleQuote is 2, so 'M6, zinc' is one
// field. (The text starts with "bolt": a leading apostrophe would be the cell's text prefix,
// not part of its value.)
#[test]
fn the_text_qualifier_constants_pick_the_quote() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "bolt,'M6, zinc',12");
    run_main(
        &mut wb,
        "Range(\"A1\").TextToColumns Destination:=Range(\"C1\"), DataType:=xlDelimited, \
         TextQualifier:=xlTextQualifierSingleQuote, Comma:=True",
    );
    assert_eq!([get(&wb, "C1"), get(&wb, "D1"), get(&wb, "E1")], [text("bolt"), text("M6, zinc"), n(12.0)]);
}

// What the macro recorder writes: Other:=True with OtherChar "-", FieldInfo giving each
// column xlGeneralFormat (1). A format it would change (xlTextFormat, 2) is refused by name,
// as is a range of two columns (Excel: one column at a time, run-time error 1004).
#[test]
fn a_recorded_split_runs_and_what_it_cannot_do_is_refused() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "M6-20");
    run_main(
        &mut wb,
        "Range(\"A1\").TextToColumns Destination:=Range(\"A1\"), DataType:=xlDelimited, \
         TextQualifier:=xlDoubleQuote, ConsecutiveDelimiter:=False, Tab:=False, Semicolon:=False, Comma:=False, \
         Space:=False, Other:=True, OtherChar:=\"-\", FieldInfo:=Array(Array(1, 1), Array(2, 1)), \
         TrailingMinusNumbers:=True",
    );
    assert_eq!([get(&wb, "A1"), get(&wb, "B1")], [text("M6"), n(20.0)]);
    let message =
        main_fails(&mut wb, "Range(\"A1\").TextToColumns Other:=True, OtherChar:=\"-\", FieldInfo:=Array(Array(1, 2))");
    assert!(message.contains("FieldInfo"), "{message}");
    let printed = run_main(
        &mut wb,
        "On Error Resume Next\nRange(\"A1:B1\").TextToColumns Comma:=True\nDebug.Print CStr(Err.Number)",
    );
    assert_eq!(printed, ["1004"]);
}
