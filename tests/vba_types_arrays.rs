//! VBA's data types and arrays, issue 31: each construct with the result Microsoft's VBA
//! language reference (learn.microsoft.com, "Office VBA language reference", page named at
//! each test) or the language specification [MS-VBAL] gives, never our own earlier output.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run_result(src: &str) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", &RunOptions::default())
}

fn run(src: &str) -> RunOutput {
    run_result(src).unwrap_or_else(|e| panic!("{e}"))
}

/// What `Debug.Print` printed, one line each, trailing spaces dropped.
fn printed(src: &str) -> Vec<String> {
    run(src).printed.iter().map(|l| l.trim_end().to_string()).collect()
}

// "Variant data type": "numeric Variant data is maintained in its original data type within
// the Variant. For example, if you assign an Integer to a Variant, subsequent operations
// treat the Variant as an Integer" (and a Long and a Single likewise). An item of a Variant
// array is a Variant ([MS-VBAL] 2.2, an array of Variants), and For Each let-assigns each
// item to its element variable ([MS-VBAL] 5.4.2.4), keeping its subtype: the literal 1 is an
// Integer, 2.5 a Double, 40000 a Long ([MS-VBAL] 3.3.2, a decimal literal's type is the
// smallest of Integer and Long that holds it).
#[test]
fn for_each_over_an_array_keeps_each_items_type() {
    let out = printed(
        "Sub Main()\n    Dim x\n    For Each x In Array(1, 2.5, \"a\", 40000)\n\
         \x20       Debug.Print TypeName(x); VarType(x)\n    Next\nEnd Sub\n",
    );
    assert_eq!(out, ["Integer 2", "Double 5", "String 8", "Long 3"]);
}

// "Variant data type", as above: `v(0) = 5` gives the Variant item the Integer 5 (VarType
// 2, "VarType function": vbInteger), `5.5` a Double, `40000` a Long, `CLng(3)` a Long
// ("Type conversion functions": CLng returns a Long), a Date literal a Date.
#[test]
fn an_item_of_a_variant_array_keeps_the_type_it_is_given() {
    let out = printed(
        "Sub Main()\n    Dim v As Variant\n    v = Array(1.5, 2.5)\n    v(0) = 5\n\
         \x20   Debug.Print TypeName(v(0)); VarType(v(0))\n\
         \x20   v(0) = 5.5\n    Debug.Print TypeName(v(0))\n\
         \x20   v(0) = 40000\n    Debug.Print TypeName(v(0))\n\
         \x20   v(1) = CLng(3)\n    Debug.Print TypeName(v(1))\n\
         \x20   Dim w(2)\n    w(0) = 7: w(1) = #1/2/2024#\n\
         \x20   Debug.Print TypeName(w(0)); \" \"; TypeName(w(1)); \" \"; TypeName(w(2))\n\
         \x20   w(0) = \"s\"\n    Debug.Print TypeName(w(0))\nEnd Sub\n",
    );
    assert_eq!(out, ["Integer 2", "Double", "Long", "Long", "Integer Date Empty", "String"]);
}

// "Variant data type": an Integer held in a Variant whose arithmetic passes the Integer's
// range "is promoted within the Variant to the next larger data type" (Integer to Long):
// the item holding the Integer 5 times the Integer 10000 is the Long 50000, no Overflow.
#[test]
fn an_integer_item_widens_as_a_variant_does() {
    let out = printed(
        "Sub Main()\n    Dim v(1)\n    v(0) = 5\n    v(1) = v(0) * 10000\n\
         \x20   Debug.Print v(1); TypeName(v(1))\nEnd Sub\n",
    );
    assert_eq!(out, [" 50000 Long"], "a positive number prints with a space before it");
}

// "For Each...Next statement": the element goes through a Collection's items; each keeps the
// type it was added with ("Variant data type"), and an array of a declared type gives items
// of that type ("Dim statement": `Dim a(1 To 2) As Long`).
#[test]
fn for_each_over_a_collection_and_a_typed_array_keeps_the_types() {
    let out = printed(
        "Sub Main()\n    Dim c As New Collection, x\n    c.Add 5: c.Add 2.5: c.Add CLng(7)\n\
         \x20   For Each x In c\n        Debug.Print TypeName(x)\n    Next\n\
         \x20   Dim a(1 To 2) As Long\n    For Each x In a\n        Debug.Print TypeName(x)\n    Next\nEnd Sub\n",
    );
    assert_eq!(out, ["Integer", "Double", "Long", "Long", "Long"]);
}
