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

// [MS-VBAL] 5.4.3.8 "Let Statement": a Let whose target is an index expression on an object is
// a Let of the object's default member with those arguments; 5.6.13.1 "Index Expressions": an
// index expression on an object calls its default member. A Dictionary's and a Collection's
// default member is Item ("Dictionary object", "Collection object"), and the Dictionary's
// "Item property" adds a key it does not have. So `dicts(0)("x") = 5` (an array of
// Dictionaries), `c(1)("y") = 7` (a Collection of Dictionaries) and `d("inner")("z") = "q"`
// each change the Dictionary the item holds.
#[test]
fn a_let_through_an_items_default_member_changes_that_object() {
    let out = printed(
        "",
        "    Dim dicts(1) As Object\n\
         \x20   Set dicts(0) = CreateObject(\"Scripting.Dictionary\")\n\
         \x20   dicts(0)(\"x\") = 5\n\
         \x20   dicts(0)(\"x\") = dicts(0)(\"x\") + 1\n\
         \x20   Debug.Print dicts(0)(\"x\"); dicts(0).Count\n\
         \x20   Dim c As New Collection\n\
         \x20   c.Add CreateObject(\"Scripting.Dictionary\")\n\
         \x20   c(1)(\"y\") = 7\n\
         \x20   Debug.Print c(1)(\"y\"); c(1).Count\n\
         \x20   Dim d As Object: Set d = CreateObject(\"Scripting.Dictionary\")\n\
         \x20   Set d(\"inner\") = CreateObject(\"Scripting.Dictionary\")\n\
         \x20   d(\"inner\")(\"z\") = \"q\"\n\
         \x20   Set d(\"inner\")(\"w\") = New Collection\n\
         \x20   Debug.Print d(\"inner\")(\"z\"); d(\"inner\").Count; TypeName(d(\"inner\")(\"w\"))",
    );
    assert_eq!(out, [" 6  1 ", " 7  1 ", "q 2 Collection"]);
}

// "Constants, fixed-length strings, arrays, user-defined types, and Declare statements not
// allowed as Public members of an object module" (VBA's compile error): a class module's
// `Public Items() As Double` does not compile ("To simulate a Public array in a class module,
// use a set of Property procedures that accept and return a Variant containing an array"), so
// `ReDim b.Items(3)` and `UBound(b.Items)` never run; a Public Variant holding an array does.
#[test]
fn a_class_cannot_declare_a_public_array_or_constant() {
    let main = "Sub Main()\n    Dim b As New Bag\n    ReDim b.Items(3)\n    Debug.Print UBound(b.Items)\nEnd Sub\n";
    for class in ["Public Items() As Double\n", "Public Items(1 To 3) As Double\n", "Public Const Size = 3\n"] {
        let e = common::vba::run_with_classes(main, &[("Bag", class)]).expect_err(class);
        assert!(e.message.contains("not allowed as Public members of object modules"), "{class}: {e}");
    }
    let fine = "Public Items As Variant\nPrivate Own(1 To 3) As Double\nPrivate Const Size = 3\n";
    let main =
        "Sub Main()\n    Dim b As New Bag\n    b.Items = Array(1, 2)\n    Debug.Print UBound(b.Items)\nEnd Sub\n";
    let out = common::vba::run_with_classes(main, &[("Bag", fine)]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 1 "]);
}

// "Create custom functions in Excel" (Microsoft Support): a Function in a standard module of
// the workbook's project is called from a cell as a built-in is. A macro writing
// `=COALESCE(A1,B1,C1)` into a cell (cdet405/excel-vba's COALESCE.vba, its usage line) reads
// the Function's result back; a ParamArray's Variant items go through `"" & v <> ""`
// (an empty cell is Empty, "" as text). The Functions of a second module of the run count too.
#[test]
fn a_cell_calls_the_running_projects_public_function() {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let module = "Public Function COALESCE(ParamArray Fields() As Variant) As Variant\n\
         \x20   Dim v As Variant\n\
         \x20   For Each v In Fields\n\
         \x20       If \"\" & v <> \"\" Then\n\
         \x20           Coalesce = v\n\
         \x20           Exit Function\n\
         \x20       End If\n\
         \x20   Next\n\
         \x20   Coalesce = \"\"\n\
         End Function\n\
         Private Function Hidden() As Long\n\
         \x20   Hidden = 1\n\
         End Function\n\
         Sub Main()\n\
         \x20   Range(\"B1\").Value = \"b\": Range(\"C2\").Value = 7\n\
         \x20   Range(\"D1\").Formula = \"=COALESCE(A1,B1,C1)\"\n\
         \x20   Range(\"D2\").Formula = \"=coalesce(A2,B2,C2)*2\"\n\
         \x20   Range(\"D3\").Formula = \"=COALESCE(A3)\"\n\
         \x20   Range(\"D4\").Formula = \"=Twice(21)\"\n\
         \x20   Range(\"D5\").Formula = \"=Hidden()\"\n\
         \x20   Debug.Print Range(\"D1\").Value; Range(\"D2\").Value; \"[\" & Range(\"D3\").Value & \"]\"; Range(\"D4\").Value\n\
         \x20   Debug.Print IsError(Range(\"D5\").Value)\n\
         End Sub\n";
    let other = "Public Function Twice(x As Double) As Double\n    Twice = 2 * x\nEnd Function\n";
    let options = ncsheet::vba::RunOptions {
        project: vec![("Helpers".into(), other.into())],
        ..ncsheet::vba::RunOptions::default()
    };
    let out = ncsheet::vba::run(&mut wb, module, "Module1.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    // A Private Function is not callable from a cell: #NAME? ("Function statement": Private
    // procedures are accessible only to the module they are declared in).
    assert_eq!(out.printed, ["b 14 [] 42 ", "True"]);
}

// "StrConv function": vbUnicode (64) "converts the string to Unicode using the default code
// page of the system". A String's bytes are its UTF-16 little-endian units, so each ASCII
// character comes out followed by a NUL: t-goulart's MASCARAS.vb turns "123" into
// "1" & vbNullChar & "2" & vbNullChar & "3" & vbNullChar and splits it at vbNullChar to get
// the digits one by one. A Byte array converts as before.
#[test]
fn strconv_vbunicode_of_a_string_reads_its_bytes_as_ansi() {
    let out = printed(
        "",
        "    Dim d As Variant\n\
         \x20   d = StrConv(\"123\", vbUnicode)\n\
         \x20   Debug.Print Len(d); Asc(Mid(d, 2, 1)); Mid(d, 3, 1)\n\
         \x20   d = Split(Left(d, Len(d) - 1), vbNullChar)\n\
         \x20   Debug.Print UBound(d); d(0) & d(1) & d(2)\n\
         \x20   Dim b() As Byte: b = StrConv(\"Az\", vbFromUnicode)\n\
         \x20   Debug.Print StrConv(b, vbUnicode)",
    );
    assert_eq!(out, [" 6  0 2", " 2 123", "Az"]);
}

// "Range.Value property": "The only difference between this property and the Value property is
// that the Value2 property doesn't use the Currency and Date data types" (Range.Value2): a cell
// formatted as a date gives Value a Date (VarType 7), one formatted as currency a Currency
// (VarType 6), a General one a Double (5); Value2 gives a Double for each. ZiggyLux's
// CellValueType.excelMacro.bas prints `VarType(v)` of cells by name.
#[test]
fn range_value_gives_dates_and_currency_as_their_types() {
    let out = printed(
        "",
        "    Range(\"A1\").Value = 45366: Range(\"A1\").NumberFormat = \"yyyy-mm-dd\"\n\
         \x20   Range(\"A2\").Value = 12.5: Range(\"A2\").NumberFormat = \"\"\"$\"\"#,##0.00\"\n\
         \x20   Range(\"A3\").Value = 7\n\
         \x20   Debug.Print VarType(Range(\"A1\").Value); TypeName(Range(\"A1\").Value); VarType(Range(\"A1\").Value2)\n\
         \x20   Debug.Print VarType(Range(\"A2\").Value); TypeName(Cells(2, 1).Value); VarType(Range(\"A2\").Value2)\n\
         \x20   Debug.Print VarType(Range(\"A3\").Value); Year(Range(\"A1\").Value); Range(\"A2\").Value * 2",
    );
    assert_eq!(out, [" 7 Date 5 ", " 6 Currency 5 ", " 5  2024  25 "]);
}

// The same cells passed on: [MS-VBAL] 5.3.1.11 binds an argument's value to a Variant
// parameter as it is, its value type with it, so `VT(Range("A1").Value)` sees a Date; and
// "VarType function": "If an object is passed and has a default property, VarType(object)
// returns the type of the object's default property", so a Range given to `v As Variant` (from
// a macro or from a cell's formula, `=VT(A1)`) and `VarType(Cells(1, 1))` answer Value's
// type: 7 for the date cell, 6 for the currency cell. ZiggyLux's CellValueType.excelMacro.bas
// is such a Function, called both ways.
#[test]
fn a_date_or_currency_cell_keeps_its_type_through_a_variant_parameter() {
    let out = printed(
        "Function VT(v As Variant) As Integer
    VT = VarType(v)
End Function
         Function VT2(ByVal v As Variant) As Integer
    VT2 = VarType(v)
End Function
",
        "    Range(\"A1\").Value = 45366: Range(\"A1\").NumberFormat = \"yyyy-mm-dd\"\n\
         \x20   Range(\"A2\").Value = 12.5: Range(\"A2\").NumberFormat = \"\"\"$\"\"#,##0.00\"\n\
         \x20   Range(\"A3\").Value = 7\n\
         \x20   Debug.Print VT(Range(\"A1\").Value); VT2(Cells(1, 1).Value); VT(Range(\"A1\")); VT(Range(\"A1\").Value2)\n\
         \x20   Debug.Print VT(Range(\"A2\").Value); VT2(Range(\"A2\")); VT(Range(\"A3\").Value); VT(Range(\"A3\"))\n\
         \x20   Debug.Print VarType(Cells(1, 1)); VarType(Range(\"A2\")); VarType(Range(\"A3\")); VarType(Cells(1, 1).Value2)\n\
         \x20   Range(\"B1\").Formula = \"=VT(A1)\": Range(\"B2\").Formula = \"=VT(A2)\": Range(\"B3\").Formula = \"=VT(A3)\"\n\
         \x20   Debug.Print Range(\"B1\").Value; Range(\"B2\").Value; Range(\"B3\").Value",
    );
    assert_eq!(out, [" 7  7  7  5 ", " 6  6  5  5 ", " 7  6  5  5 ", " 7  6  5 "]);
}
