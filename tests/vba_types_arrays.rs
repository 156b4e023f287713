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

/// A run with class modules (name, source) beside the module `src`.
fn run_with_classes(src: &str, classes: &[(&str, &str)]) -> RunOutput {
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", &RunOptions { classes, ..RunOptions::default() })
        .unwrap_or_else(|e| panic!("{e}"))
}

// [MS-VBAL] 5.6.12 "Member Access Expressions" (`l-expression "." name`) and 5.6.13 "Index
// Expressions" (`l-expression "(" argument-list ")"`): each applies to any l-expression,
// itself an index or a member access, so a chain of them has any length. `A(2)(0)` is the
// Collection the inner array holds: `.Count` is its items, `.Add` adds to that very
// Collection (objects are references, "Set statement"), and `outer(1)(0)` and `d("k")(0)`
// reach the same one through a Collection's and a Dictionary's item.
#[test]
fn members_of_an_indexed_item_are_read_and_called() {
    let out = printed(
        "Sub Main()\n    Dim A(1 To 2) As Variant, c As New Collection, inner(0)\n    c.Add 10\n\
         \x20   Set inner(0) = c\n    A(2) = inner\n    Debug.Print A(2)(0).Count\n\
         \x20   A(2)(0).Add 20\n    Debug.Print c.Count; A(2)(0)(2)\n\
         \x20   Dim outer As New Collection\n    outer.Add inner\n    outer(1)(0).Add 30\n\
         \x20   Debug.Print c.Count; outer(1)(0).Item(3)\n\
         \x20   Dim d As Object, o As Object\n    Set d = CreateObject(\"Scripting.Dictionary\")\n\
         \x20   d.Add \"k\", inner\n    Debug.Print d(\"k\")(0).Count\n\
         \x20   Set o = d(\"k\")(0)\n    o.Add 40\n    Debug.Print c.Count\nEnd Sub\n",
    );
    assert_eq!(out, [" 1", " 2  20", " 3  30", " 3", " 4"]);
}

const PIECE_CLS: &str = "Public Items As Collection\nPublic Name As String\nPublic Parts As Variant\n\
    Private Sub Class_Initialize()\n    Set Items = New Collection\nEnd Sub\n\
    Public Function FirstName() As String\n    FirstName = Me.Items(1).Name\nEnd Function\n";

// [MS-VBAL] 5.6.12 and 5.6.13 as above, on objects of a class module: `this.Items(1)` is the
// Collection field indexed by its default member, Item ("Collection object"), so
// `this.Items(1).Name` is the Name of the object added; `Me.Items(1).Name` the same inside
// the class; `coll(1).Name = x` and `A(1)(0).Name = x` assign the member of the very object.
#[test]
fn members_of_items_of_class_objects() {
    let main = "Sub Main()\n    Dim this As New Piece, other As New Piece, coll As New Collection\n\
                \x20   other.Name = \"inner\"\n    this.Items.Add other\n\
                \x20   Debug.Print this.Items(1).Name; \" \"; this.FirstName()\n\
                \x20   coll.Add other\n    coll(1).Name = \"renamed\"\n    Debug.Print other.Name\n\
                \x20   Dim A(1 To 2), inner(0)\n    Set inner(0) = other\n    A(1) = inner\n\
                \x20   A(1)(0).Name = \"again\"\n    Debug.Print this.Items(1).Name\n\
                \x20   this.Parts = inner\n    Debug.Print this.Parts(0).Name\nEnd Sub\n";
    let out: Vec<String> = run_with_classes(main, &[("Piece", PIECE_CLS)]).printed;
    assert_eq!(out, ["inner inner", "renamed", "again", "again"]);
}

const NESTED_TYPES: &str = "Type TInner\n    v() As Double\n    w() As Variant\n    f(1 To 3) As Long\nEnd Type\n\
    Type TOuter\n    inner As TInner\n    n As Long\n    xs() As Long\nEnd Type\n";

// "ReDim statement": ReDim sizes a dynamic array, `Preserve` keeping its items; a Type's
// field that is a dynamic array is such an array, in a Type nested in another too
// ([MS-VBAL] 5.4.3.3: the ReDim target is a member access of any depth naming a resizable
// array). Assigning a Type copies it ("Type statement": a UDT is a value), so resizing the
// copy's field leaves the original's.
#[test]
fn redim_sizes_an_array_field_of_a_nested_type() {
    let src = format!(
        "{NESTED_TYPES}Sub Main()\n    Dim o As TOuter, p As TOuter\n    ReDim o.xs(1 To 3)\n    o.xs(2) = 5\n\
         \x20   ReDim Preserve o.xs(1 To 4)\n    Debug.Print o.xs(2); UBound(o.xs)\n\
         \x20   ReDim o.inner.v(2)\n    o.inner.v(1) = 2.5\n    ReDim Preserve o.inner.v(5)\n\
         \x20   Debug.Print o.inner.v(1); LBound(o.inner.v); UBound(o.inner.v)\n\
         \x20   ReDim o.inner.v(1 To 2)\n    Debug.Print o.inner.v(1); UBound(o.inner.v)\n\
         \x20   p = o\n    ReDim Preserve p.inner.v(1 To 3)\n    p.inner.v(3) = 7\n\
         \x20   Debug.Print UBound(o.inner.v); UBound(p.inner.v); p.inner.v(3)\nEnd Sub\n"
    );
    assert_eq!(printed(&src), [" 5  4", " 2.5  0  5", " 0  2", " 2  3  7"]);
}

// "ReDim statement": a fixed-size array (`f(1 To 3) As Long`) cannot be resized, and only
// an array can: each refusal names the field, and nothing is resized.
#[test]
fn redim_of_a_nested_field_that_is_no_dynamic_array_is_refused() {
    for (target, why) in
        [("o.inner.f(5)", "no dynamic array field"), ("o.n.v(5)", "no Type value"), ("o.inner.zz(5)", "no field zz")]
    {
        let src = format!("{NESTED_TYPES}Sub Main()\n    Dim o As TOuter\n    ReDim {target}\nEnd Sub\n");
        let e = run_result(&src).unwrap_err();
        assert!(e.message.contains(why), "{target}: {e}");
    }
}

// "TypeName function": "If varname is an array, the returned string can be any one of the
// possible returned strings (or Variant) with empty parentheses appended"; a Type's array
// field is an array of its declared type: `v() As Double` is "Double()", `w() As Variant`
// "Variant()", `f(1 To 3) As Long` "Long()".
#[test]
fn typename_of_a_types_array_field_names_its_item_type() {
    let src = format!(
        "{NESTED_TYPES}Sub Main()\n    Dim o As TOuter\n    ReDim o.inner.v(2)\n\
         \x20   Debug.Print TypeName(o.xs); \" \"; TypeName(o.inner.v); \" \"; TypeName(o.inner.w); \" \"; \
         TypeName(o.inner.f)\nEnd Sub\n"
    );
    assert_eq!(printed(&src), ["Long() Double() Variant() Long()"]);
}

// [MS-VBAL] 3.3.2 "Number Tokens": `integer-type-suffix = "%" / "&" / "^"`, `^` making the
// literal a LongLong ("LongLong data type": its type-declaration character is the caret);
// the token ends at the suffix, so `17^ Mod 5` is the LongLong 17 Mod 5 (2, a LongLong as
// [MS-VBAL] 5.6.9.3.7 makes `Mod` of two LongLongs) and `1^ To 3^ Step 2^` bounds a loop.
// "Type conversion functions": CLngLng rounds a half to the even number (2.5 to 2, 3.5 to 4).
#[test]
fn a_longlong_literal_before_an_operator_word() {
    let out = printed(
        "Sub Main()\n    Dim i\n    Debug.Print 17^ Mod 5; TypeName(17^ Mod 5)\n\
         \x20   For i = 1^ To 3^ Step 2^\n        Debug.Print i; TypeName(i)\n    Next\n\
         \x20   Debug.Print CLngLng(2.5); CLngLng(3.5); TypeName(CLngLng(1)); VarType(5^)\nEnd Sub\n",
    );
    assert_eq!(out, [" 2 LongLong", " 1 LongLong", " 3 LongLong", " 2  4 LongLong 20"]);
}

// [MS-VBAL] 5.6.9.8 "Logical Operators": a binary logical operator's declared type by its
// operands' (two Bytes a Byte, Bytes, Booleans and Integers an Integer, a LongLong beside a
// LongLong, any other number a Long); a Variant holds the result with that type ("Variant
// data type"): `5 And 4` is the Integer 4, `CLng(5) Or 2` the Long 7, `2.5 Xor 1` a Long.
#[test]
fn logical_operators_on_numbers_give_their_declared_type() {
    let out = printed(
        "Sub Main()\n    Dim v\n    v = 5 And 4\n    Debug.Print v; TypeName(v)\n\
         \x20   Debug.Print TypeName(CLng(5) Or 2); \" \"; TypeName(2.5 Xor 1); \" \"; \
         TypeName(CByte(3) And CByte(1)); \" \"; TypeName(5^ And 1); \" \"; TypeName(True And False)\nEnd Sub\n",
    );
    assert_eq!(out, [" 4 Integer", "Long Long Byte LongLong Boolean"]);
}
