//! Class modules as VBA compiles them (issue 31, scope 2): a class's default member and its
//! enumerator, named by the `Attribute <Member>.VB_UserMemId` lines the VBA editor keeps in
//! the module's source (0: the default member, -4: NewEnum); the project's own classes before
//! the libraries' of the same name; a Let into an object variable. Each expected value is
//! worked by hand from [MS-VBAL] (the VBA language specification) or the page of Microsoft's
//! VBA reference named at the test, never from our own earlier output.

mod common;

use common::vba::run_with_classes;

fn printed(main: &str, classes: &[(&str, &str)]) -> Vec<String> {
    run_with_classes(main, classes).unwrap_or_else(|e| panic!("{e}")).printed
}

/// A Collection wrapped in a class, as the editor stores it: `Item` is its default member
/// (read with an index, written by a Property Let), `NewEnum` its enumerator.
const BAG: &str = "Attribute VB_Name = \"Bag\"\r\n\
    Private mItems As Collection\r\n\
    Private Sub Class_Initialize()\r\n    Set mItems = New Collection\r\nEnd Sub\r\n\
    Public Property Get Item(ByVal i As Long) As Variant\r\n\
    Attribute Item.VB_UserMemId = 0\r\n    Item = mItems(i)\r\nEnd Property\r\n\
    Public Property Let Item(ByVal i As Long, ByVal v As Variant)\r\n\
    \x20   mItems.Add v, After:=i\r\n    mItems.Remove i\r\nEnd Property\r\n\
    Public Sub Add(ByVal v As Variant)\r\n    mItems.Add v\r\nEnd Sub\r\n\
    Public Property Get NewEnum() As IUnknown\r\n\
    Attribute NewEnum.VB_UserMemId = -4\r\n    Set NewEnum = mItems.[_NewEnum]\r\nEnd Property\r\n";

/// A value behind a default Property Get/Let without parameters.
const GAUGE: &str = "Attribute VB_Name = \"Gauge\"\r\n\
    Private mValue As Double\r\n\
    Public Property Get Value() As Double\r\n\
    Attribute Value.VB_UserMemId = 0\r\n    Value = mValue\r\nEnd Property\r\n\
    Public Property Let Value(ByVal v As Double)\r\n    mValue = v\r\nEnd Property\r\n";

// [MS-VBAL] 5.6.13.1 (index expressions): an index applied to an object without a member
// named is the object's default member called with those arguments; 5.4.3.8 (Let statement):
// `b(2) = v` assigns through the default member's Property Let. 5.4.2.4 (For Each): an object
// is enumerated through its NewEnum member (DISPID -4), here the Collection's own enumerator.
#[test]
fn a_default_member_takes_the_index_and_new_enum_drives_for_each() {
    let main = "Sub Main()\n    Dim b As New Bag\n    b.Add 10: b.Add 20: b.Add 30\n\
                \x20   Debug.Print \"b(2)=\" & b(2)\n    b(2) = 25\n    Debug.Print \"item=\" & b.Item(2)\n\
                \x20   Debug.Print \"sum=\" & (b(1) + b(3))\n    Dim x, s As String\n\
                \x20   For Each x In b\n        s = s & x & \";\"\n    Next\n    Debug.Print \"each=\" & s\nEnd Sub\n";
    assert_eq!(printed(main, &[("Bag", BAG)]), ["b(2)=20", "item=25", "sum=40", "each=10;25;30;"]);
}

// [MS-VBAL] 5.5.1.2 (Let-coercion): an object where a value is wanted is its default member's
// value, so `x = g` gives x the Double and `g + 1` adds to it; 5.4.3.8: `g = 2.5` without Set
// goes to the default Property Let and g keeps its object; `Set` (5.4.3.9) keeps the object.
#[test]
fn an_object_where_a_value_is_wanted_is_its_default_member() {
    let main = "Sub Main()\n    Dim g As Gauge, x As Variant, y As Object\n    Set g = New Gauge\n    g = 2.5\n\
                \x20   x = g\n    Debug.Print \"x=\" & x & \" \" & TypeName(x)\n    Debug.Print \"sum=\" & (g + 1)\n\
                \x20   Set y = g\n    Debug.Print \"same=\" & (y Is g) & \" \" & TypeName(y)\nEnd Sub\n";
    assert_eq!(printed(main, &[("Gauge", GAUGE)]), ["x=2.5 Double", "sum=3.5", "same=True Gauge"]);
}

// The default member may be a public variable (its attribute follows the declaration); a
// member holding an object with a default member takes the index after it:
// `Host.Arguments(1)` is `Host.Arguments.Item(1)` (Windows Script Host's WScript.Arguments).
#[test]
fn a_public_variable_and_a_member_holding_an_object_index_through_defaults() {
    let args = "Attribute VB_Name = \"Args\"\r\nPrivate mItems As Variant\r\n\
                Public Sub Init(v As Variant)\r\n    mItems = v\r\nEnd Sub\r\n\
                Public Property Get Item(ByVal i As Long) As Variant\r\n\
                Attribute Item.VB_UserMemId = 0\r\n    Item = mItems(i)\r\nEnd Property\r\n";
    let host = "Attribute VB_Name = \"Host\"\r\nPublic Arguments As Args\r\n\
                Public Name As String\r\nAttribute Name.VB_UserMemId = 0\r\n";
    let main = "Sub Main()\n    Dim h As New Host, a As New Args\n    a.Init Array(\"in.drl\", \"F120\")\n\
                \x20   Set h.Arguments = a\n    Debug.Print \"arg=\" & h.Arguments(1)\n\
                \x20   h = \"wsh\"\n    Debug.Print \"name=\" & h & \" \" & h.Name\nEnd Sub\n";
    assert_eq!(printed(main, &[("Args", args), ("Host", host)]), ["arg=F120", "name=wsh wsh"]);
}

// "Object doesn't support this property or method (Error 438)": an index on an object whose
// class has no default member. "Object variable or With block variable not set (Error 91)":
// a Let into an object variable holding Nothing, which has no default member to take the
// value. A library's enum type (VbCompareMethod, XlDirection) declares a Long ("Enum
// statement": its members are Longs), whose Let replaces the value.
#[test]
fn an_index_without_a_default_member_is_438_and_a_let_into_nothing_is_91() {
    let plain = "Attribute VB_Name = \"Plain\"\r\nPublic N As Long\r\n";
    let main = "Sub Main()\n    Dim p As New Plain, v As Variant\n    On Error Resume Next\n\
                \x20   v = p(1)\n    Debug.Print \"index=\" & Err.Number\n    Err.Clear\n\
                \x20   Dim r As Range\n    r = 5\n    Debug.Print \"range=\" & Err.Number & \" \" & TypeName(r)\n    Err.Clear\n\
                \x20   Dim c As Collection\n    c = 1\n    Debug.Print \"collection=\" & Err.Number\n    Err.Clear\n\
                \x20   On Error GoTo 0\n    Dim m As VbCompareMethod, d As XlDirection\n    m = 1: d = -4121\n\
                \x20   Debug.Print \"enums=\" & TypeName(m) & m & \" \" & TypeName(d) & d\nEnd Sub\n";
    assert_eq!(
        printed(main, &[("Plain", plain)]),
        ["index=438", "range=91 Nothing", "collection=91", "enums=Long1 Long-4121"]
    );
}

// [MS-VBAL] 5.6.10 (simple name expressions) and 4.1 (projects): a name binds in the enclosing
// project before its references, so the project's class `Dictionary` is what `New Dictionary`
// makes; the library's stays reachable qualified, `New Scripting.Dictionary`.
#[test]
fn the_projects_own_class_comes_before_a_librarys_of_the_same_name() {
    let probe = "Attribute VB_Name = \"Dictionary\"\r\n\
                 Public Property Get Count() As Long\r\n    Count = 42\r\nEnd Property\r\n";
    let main = "Sub Main()\n    Dim d As New Dictionary, s As Object\n    Debug.Print \"own=\" & d.Count\n\
                \x20   Set s = New Scripting.Dictionary\n    s.Add \"k\", 1\n    Debug.Print \"library=\" & s.Count\nEnd Sub\n";
    assert_eq!(printed(main, &[("Dictionary", probe)]), ["own=42", "library=1"]);
}

// "Erase statement": Erase "frees the memory used by dynamic arrays"; an array declared
// without bounds (`Private a() As Variant`) is a dynamic array before its first ReDim too
// ([MS-VBAL] 5.2.3.1.3), so erasing it is no error, and IsArray finds an array ("IsArray
// function"). Tim Hall's VBA-Dictionary erases its arrays so in Class_Initialize.
#[test]
fn erase_of_a_variant_array_declared_without_bounds_frees_it() {
    let main = "Sub Main()\n    Dim a() As Variant\n    Erase a\n    Debug.Print \"array=\" & IsArray(a)\n\
                \x20   ReDim a(0 To 1)\n    a(1) = \"x\"\n    Debug.Print \"item=\" & a(1) & UBound(a)\nEnd Sub\n";
    assert_eq!(printed(main, &[]), ["array=True", "item=x1"]);
}

// [MS-VBAL] 5.3.1.11 (argument binding): an argument for a ByVal parameter of a declared type
// is let-coerced to that type, so an object goes as its default member's value; a Variant
// parameter takes the object itself (TypeName "Gauge").
#[test]
fn an_object_given_to_a_typed_parameter_is_its_default_members_value() {
    let main = "Function Twice(ByVal x As Double) As Double\n    Twice = 2 * x\nEnd Function\n\
                Function Kind(v As Variant) As String\n    Kind = TypeName(v)\nEnd Function\n\
                Sub Main()\n    Dim g As New Gauge\n    g = 4\n    Debug.Print \"twice=\" & Twice(g) & \" \" & Kind(g)\nEnd Sub\n";
    assert_eq!(printed(main, &[("Gauge", GAUGE)]), ["twice=8 Gauge"]);
}
