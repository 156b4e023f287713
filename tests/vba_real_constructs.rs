//! Constructs found by real public VBA modules (issue 31, session 15's sample: sorters,
//! a geodesy module, class-free enum sorters), each in a small macro of our own with the
//! result Microsoft's VBA language reference or [MS-VBAL] (the page or section named at each
//! test) gives.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run_with(src: &str, options: &RunOptions) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", options)
}

/// What the macro's `Debug.Print`s wrote, line by line.
fn printed(src: &str) -> Vec<String> {
    run_with(src, &RunOptions::default()).unwrap_or_else(|e| panic!("{e}")).printed
}

// [MS-VBAL] 5.2.3.3 "User Defined Type Declarations": `private-type-declaration` and
// `public-type-declaration` put Private or Public before Type ("Type statement": `[ Private |
// Public ] Type varname`).
#[test]
fn a_type_declared_private_or_public() {
    let src = "Private Type Params\n    s As Double\n    n As Long\nEnd Type\n\
               Public Type Pair\n    a As String\nEnd Type\n\
               Private Function Make() As Params\n    Dim p As Params\n    p.s = 2.5: p.n = 3\n    Make = p\nEnd Function\n\
               Sub Main()\n    Dim p As Params, q As Pair\n    p = Make()\n    q.a = \"x\"\n\
               \x20   Debug.Print p.s * p.n; q.a\nEnd Sub\n";
    assert_eq!(printed(src), [" 7.5 x"]);
}

// "XlCVError enumeration (Excel)": xlErrNA is 2042, a member of Excel's object library, so
// `Excel.xlErrNA` names it as `xlErrNA` does; VBA's own constants likewise through `VBA.`
// ("Miscellaneous constants": vbCrLf is Chr(13) & Chr(10)).
#[test]
fn constants_named_through_their_library() {
    let src = "Sub Main()\n    Debug.Print Excel.xlErrNA, Excel.xlErrDiv0\n\
               \x20   Debug.Print Len(VBA.vbCrLf), IsError(CVErr(Excel.xlErrNA))\nEnd Sub\n";
    assert_eq!(printed(src), [" 2042          2007 ", " 2            True"]);
}

// [MS-VBAL] 5.3.1.5 "Parameter Lists": a parameter declared with `()` is an array of its
// declared type; the caller passes a whole array (`S x` or `S x()`), by reference unless
// ByVal, so what the procedure writes into it, ReDim included, is the caller's.
#[test]
fn an_array_parameter_of_a_declared_type_takes_the_whole_array() {
    let src = "Sub AddTen(a() As Long)\n    a(1) = a(1) + 10\nEnd Sub\n\
               Sub Grow(a() As Double)\n    ReDim a(0 To 2)\n    a(2) = 0.5\nEnd Sub\n\
               Sub Main()\n    Dim x(1 To 2) As Long\n    x(1) = 1\n    AddTen x\n    AddTen x()\n\
               \x20   Dim y() As Double\n    Grow y\n    Debug.Print x(1); UBound(y); y(2); y(0)\nEnd Sub\n";
    assert_eq!(printed(src), [" 21  2  0.5  0 "]);
}

// "Enum statement" and [MS-VBAL] 5.2.3.4 "Enum Declarations": members are Long constants;
// a member without a value is one more than the member before it, the first 0; a variable
// of the Enum's type is a Long (starts at 0); a member is named alone or as `Enum.member`.
#[test]
fn enum_members_are_long_constants_counting_on_from_the_one_before() {
    let src = "Public Enum Tool\n    Drill\n    Mill = 5\n    Tap\nEnd Enum\n\
               Private Enum Flags\n    F1 = 1\n    F2 = F1 * 2\nEnd Enum\n\
               Sub Main()\n    Dim t As Tool\n    Debug.Print t; Drill; Mill; Tap; Tool.Tap; F2\n\
               \x20   t = Tool.Mill\n    Debug.Print VarType(t); t\nEnd Sub\n";
    assert_eq!(printed(src), [" 0  0  5  6  6  2 ", " 3  5 "]);
}

/// A macro run with the project's class modules (name, source).
fn printed_with_classes(main: &str, classes: &[(&str, &str)]) -> Vec<String> {
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    run_with(main, &RunOptions { classes, ..RunOptions::default() }).unwrap_or_else(|e| panic!("{e}")).printed
}

// [MS-VBAL] 5.2.3.3 "User Defined Type Declarations": a field's declared type may be a
// class (Collection, "Type statement": `elementname As type`, any data type); the field
// holds an object reference that `Set` assigns and whose members the field reaches.
#[test]
fn a_type_field_holds_an_object_and_reaches_its_members() {
    let src = "Private Type TPrivate\n    Items As Collection\n    n As Long\nEnd Type\nPrivate this As TPrivate\n\
               Sub Main()\n    Set this.Items = New Collection\n    this.Items.Add \"a\"\n    this.Items.Add \"b\", before:=1\n\
               \x20   this.n = this.Items.Count\n    Debug.Print this.n; this.Items.Item(1); this.Items.Item(2)\nEnd Sub\n";
    assert_eq!(printed(src), [" 2 ba"]);
}

// "TypeName function", "IsObject function", "UBound function": members of VBA's library
// (the VBA project's "VBA" reference, Information and Conversion modules), so `VBA.TypeName(x)`
// is `TypeName(x)`.
#[test]
fn vba_library_functions_named_through_the_library() {
    let src = "Sub Main()\n    Dim c As New Collection, a(2 To 4)\n\
               \x20   Debug.Print VBA.TypeName(c); \" \"; VBA.IsObject(c); VBA.UBound(a); VBA.LBound(a); VBA.IsArray(a)\nEnd Sub\n";
    assert_eq!(printed(src), ["Collection True 4  2 True"]);
}

// [MS-VBAL] 5.3.1.5 and "Function statement": a Function's value is what its name holds when
// it returns, an array with its bounds, whether the Function is a standard module's or a
// class module's method (`a = s.Items(1)` with `ReDim arr(base To …)`).
#[test]
fn a_class_functions_array_keeps_its_bounds() {
    let class = "Option Explicit\nPublic Function Items(Optional ByVal base As Long) As Variant()\n\
                 \x20   Dim arr() As Variant: ReDim arr(base To base + 2)\n    arr(base) = \"x\"\n    Items = arr\nEnd Function\n";
    let main = "Sub Main()\n    Dim s As New Bag, a As Variant\n    a = s.Items(1)\n    Debug.Print LBound(a); UBound(a); a(1)\n\
                \x20   a = s.Items(5)\n    Debug.Print LBound(a); UBound(a); a(5)\nEnd Sub\n";
    assert_eq!(printed_with_classes(main, &[("Bag", class)]), [" 1  3 x", " 5  7 x"]);
}

// "Print # statement" (Debug.Print's "Print method" formats its items the same way): error
// data "is written as Error errorcode", so `Debug.Print CVErr(xlErrNA)` prints `Error 2042`,
// as VBA's Immediate window shows it, not the cell's `#N/A`.
#[test]
fn debug_print_writes_an_error_value_as_error_and_its_number() {
    let src = "Sub Main()\n    Debug.Print CVErr(xlErrNA)\n    Debug.Print CVErr(2007); \"|\"\nEnd Sub\n";
    assert_eq!(printed(src), ["Error 2042", "Error 2007|"]);
}

// "Range.Item property (Excel)": Item is the Range object's default member, so a Range
// variable (or parameter) followed by an index is the cell at that place counted from its
// top-left, `(i)` row by row, `(row, column)` otherwise; a member assigned through it writes
// that cell (`theRange(1&).Resize(n, 2).Value = ary`).
#[test]
fn a_range_variable_with_an_index_is_its_item_as_an_assignment_target() {
    let src = "Sub Fill(ByRef r As Range)\n    r(2).Value = 9\nEnd Sub\n\
               Sub Main()\n    Dim r As Range\n    Set r = Range(\"B2\")\n    r(1).Value = 5\n    r(2, 2).Value = 7\n\
               \x20   r(1&).Resize(1, 2).Value = 3\n    Fill Range(\"E1\")\n\
               \x20   Debug.Print Range(\"B2\").Value; Range(\"C3\").Value; Range(\"C2\").Value; Range(\"E2\").Value; r(2, 2).Value\nEnd Sub\n";
    assert_eq!(printed(src), [" 3  7  3  9  7 "]);
}

// [MS-VBAL] 6.1.2 "Predefined Procedural Modules": VBA's functions are members of the
// library's modules (Conversion, DateTime, FileSystem, Financial, Information, Interaction,
// Math, Strings), so `Math.Sqr`, `Strings.UCase` and `VBA.Math.Abs` name the same functions
// as `Sqr`, `UCase` and `Abs`; a variable of such a name is still the variable.
#[test]
fn functions_named_through_a_module_of_the_vba_library() {
    let src = "Sub Main()\n    Debug.Print Math.Sqr(16); Strings.UCase(\"ab\"); VBA.Math.Abs(-2); Math.Atn(1) * 4 = 4 * Atn(1)\n\
               \x20   Debug.Print Conversion.CInt(2.6); Interaction.IIf(True, \"y\", \"n\")\nEnd Sub\n\
               Sub Shadowed()\n    Dim Strings As New Collection\n    Strings.Add \"x\"\n    Debug.Print Strings.Count\nEnd Sub\n";
    assert_eq!(printed(src), [" 4 AB 2 True", " 3 y"]);
    let shadowed = RunOptions { sub: Some("Shadowed".into()), ..RunOptions::default() };
    assert_eq!(run_with(src, &shadowed).unwrap().printed, [" 1 "]);
}

// [MS-VBAL] 5.3.1.11 "Procedure Invocation": a ByRef parameter is bound to the argument's
// variable itself, so what the callee writes into a caller's array is in the caller's array
// at once, also when the callee then fails and the caller goes on (On Error Resume Next);
// an array passed on from one call to the next (`HeapSort Arr` → `Swap Arr, 1, i`) is still
// the caller's one array.
#[test]
fn an_array_passed_by_reference_is_the_callers_array_even_when_the_call_fails() {
    let src = "Sub Fill(a() As Long, v)\n    a(1) = 7: v(2) = \"w\"\n    Err.Raise 5\nEnd Sub\n\
               Sub Swap(l() As Long, i As Long, j As Long)\n    Dim t As Long\n    t = l(i): l(i) = l(j): l(j) = t\nEnd Sub\n\
               Sub Pass(l() As Long)\n    Swap l, 1, 2\nEnd Sub\n\
               Sub Main()\n    Dim a(1 To 2) As Long, v(1 To 2)\n    On Error Resume Next\n    Fill a, v\n\
               \x20   Debug.Print a(1); v(2); Err.Number\n    On Error GoTo 0\n    a(2) = 3\n    Pass a\n    Debug.Print a(1); a(2)\nEnd Sub\n";
    assert_eq!(printed(src), [" 7 w 5 ", " 3  7 "]);
}

// "Understanding parameter arrays" and [MS-VBAL] 5.3.1.5: a last parameter `ParamArray
// args()` takes every argument from its position on as one Variant array; "Option Base
// statement": "The base of an array created with the ParamArray keyword is zero; Option Base
// does not affect ParamArray", so a call giving none has LBound 0 and UBound -1. Each item is
// what the argument is: the literal 2 an Integer, 2.5 a Double ("TypeName function"), a Range
// object a Range. A Function never assigned returns Empty, which Debug.Print writes as
// nothing ("Print # statement").
#[test]
fn a_param_array_takes_the_rest_of_the_arguments_from_zero() {
    let src = "Option Base 1\n\
               Function Shape(first, ParamArray rest() As Variant) As String\n\
               \x20   Dim x\n\
               \x20   Shape = first & \":\" & LBound(rest) & \":\" & UBound(rest)\n\
               \x20   For Each x In rest\n        Shape = Shape & \":\" & TypeName(x)\n    Next\n\
               End Function\n\
               Function Total(ParamArray values())\n\
               \x20   Dim i As Integer\n\
               \x20   For i = LBound(values) To UBound(values)\n        Total = Total + values(i)\n    Next i\n\
               End Function\n\
               Sub Main()\n\
               \x20   Debug.Print Shape(\"a\"); \" \"; Shape(\"b\", 2, 2.5, \"t\", Range(\"A1:B2\"))\n\
               \x20   Debug.Print Total(); Total(1, 2, 3.5); Total(10)\n\
               End Sub\n";
    assert_eq!(printed(src), ["a:0:-1 b:0:3:Integer:Double:String:Range", " 6.5  10 "]);
}

// [MS-VBAL] 5.3.1.5: `param-array` comes last in a parameter list that has no `optional`
// parameter, and its type is Variant; anything else does not compile.
#[test]
fn a_param_array_is_last_of_a_list_without_optional_parameters() {
    for (params, why) in [
        ("ParamArray a(), b", "must be the last parameter"),
        ("Optional b = 1, ParamArray a()", "cannot have Optional parameters"),
        ("ParamArray a() As Long", "declare it As Variant"),
    ] {
        let src = format!("Function F({params})\nEnd Function\nSub Main()\n    Debug.Print F(1, 2)\nEnd Sub\n");
        let e = run_with(&src, &RunOptions::default()).unwrap_err();
        assert!(e.to_string().contains(why), "{params}: {e}");
    }
}

// "WorksheetFunction.Match method" and Excel's run-time error 1004 "Unable to get the Match
// property of the WorksheetFunction class" (Microsoft TechNet wiki 3145): a worksheet
// function called through WorksheetFunction raises its error result as error 1004, which On
// Error traps, and the assignment does not happen; through Application (`Application.Match`)
// the error comes back as a value (Error 2042, xlErrNA).
#[test]
fn a_worksheet_function_error_is_raised_through_worksheet_function_returned_through_application() {
    let src = "Sub Main()\n\
               \x20   Dim r\n\
               \x20   r = Application.Match(\"z\", Array(\"a\", \"b\"), 0)\n\
               \x20   Debug.Print IsError(r); CStr(r)\n\
               \x20   On Error Resume Next\n\
               \x20   r = 7\n\
               \x20   r = WorksheetFunction.Match(\"z\", Array(\"a\", \"b\"), 0)\n\
               \x20   Debug.Print Err.Number; r\n\
               \x20   Err.Clear\n\
               \x20   r = Application.WorksheetFunction.Match(\"b\", Array(\"a\", \"b\"), 0)\n\
               \x20   Debug.Print Err.Number; r\n\
               End Sub\n";
    assert_eq!(printed(src), ["TrueError 2042", " 1004  7 ", " 0  2 "]);
}

// "With statement": `.Member` inside `With object` is object.Member, so in `With
// Application.WorksheetFunction` `.Max(…)` is WorksheetFunction.Max(…), raising as it does,
// and in `With Application` `.Max(…)` is Application.Max(…) ("Application object": the
// worksheet functions are its members too).
#[test]
fn worksheet_functions_as_members_of_a_with_block() {
    let src = "Sub Main()\n\
               \x20   Dim r\n\
               \x20   With Application.WorksheetFunction\n\
               \x20       Debug.Print .Max(3, 9, 4); .Sum(1, 2)\n\
               \x20       On Error GoTo Failed\n\
               \x20       r = .Match(\"z\", Array(\"a\"), 0)\n\
               \x20   End With\n\
               \x20   Exit Sub\n\
               Failed:\n\
               \x20   Debug.Print Err.Number\n\
               \x20   With Application\n\
               \x20       Debug.Print .Min(3, 9, 4); IsError(.Match(\"z\", Array(\"a\"), 0))\n\
               \x20   End With\n\
               End Sub\n";
    assert_eq!(printed(src), [" 9  3 ", " 1004 ", " 3 True"]);
}

/// A macro run with the project's other standard modules (name, source).
fn printed_with_modules(main: &str, modules: &[(&str, &str)]) -> Vec<String> {
    let project = modules.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    run_with(main, &RunOptions { project, ..RunOptions::default() }).unwrap_or_else(|e| panic!("{e}")).printed
}

// "Understanding scope and visibility": a Public constant or variable of a standard module is
// visible throughout the project, whichever module comes first, and may be qualified by its
// module's name ([MS-VBAL] 5.6.10 "Simple Name Expressions" and 5.6.12 "Member Access
// Expressions": `Module2.Rate` names the module's member). Under Option Explicit it is
// declared, not an undeclared variable.
#[test]
fn a_public_constant_or_variable_of_a_later_module_by_name_and_qualified() {
    let main = "Option Explicit\nSub Main()\n    Counter = Counter + 2\n\
                \x20   Debug.Print PI * 2; Geom.PI; Geom.Counter; Twice()\nEnd Sub\n";
    let geom = "Attribute VB_Name = \"Geom\"\nOption Explicit\nPublic Const PI As Double = 3.5\n\
                Public Counter As Long\nFunction Twice()\n    Twice = Geom.PI + PI\nEnd Function\n";
    assert_eq!(printed_with_modules(main, &[("Geom", geom)]), [" 7  3.5  2  7 "]);
}

// [MS-VBAL] 3.3.5.3: a FOREIGN-NAME, text in brackets, is a name whatever its text, so an
// Enum's `[_First]` is the member `_First`, named `CURVE.[_First]` ("Enum statement": its
// members count on from the one before).
#[test]
fn an_enum_member_named_in_brackets() {
    let src = "Public Enum Curve\n    [_First] = -2\n    Ccw = -1\n    Straight\n    Cw\n    [_Last]\nEnd Enum\n\
               Sub Main()\n    Dim i As Integer, names As String\n\
               \x20   For i = Curve.[_First] + 1 To Curve.[_Last] - 1\n        names = names & i & \",\"\n    Next i\n\
               \x20   Debug.Print names; Curve.[_Last]; Cw\nEnd Sub\n";
    assert_eq!(printed(src), ["-1,0,1, 2  1 "]);
}

// "Raise method": `Err.Raise number, source, description` sets Err.Source to `source`; a
// source not given is "the programmatic ID of the current Visual Basic project" (Excel's
// VBAProject), as it is for the errors VBA raises itself ("Source property"); Err.Clear
// empties it ("Clear method": all of Err's properties are reset). A description not given is
// the one of VBA's error of that number ("Trappable errors": 9 "Subscript out of range"), else
// "Application-defined or object-defined error".
#[test]
fn err_source_is_the_raise_source_or_the_project() {
    let src = "Sub Main()\n    On Error Resume Next\n\
               \x20   Err.Raise 5, \"Geom.Atn2\", \"no angle\"\n\
               \x20   Debug.Print Err.Number; Err.Source; \"|\"; Err.Description\n\
               \x20   Err.Clear\n    Debug.Print \"[\"; Err.Source; \"]\"\n\
               \x20   Err.Raise 1000\n    Debug.Print Err.Source; \"|\"; Err.Description\n\
               \x20   Err.Clear\n    Err.Raise 9\n    Debug.Print Err.Description\n\
               \x20   Err.Clear\n    Dim z\n    z = 1 / 0\n    Debug.Print Err.Number; Err.Source\nEnd Sub\n";
    assert_eq!(
        printed(src),
        [
            " 5 Geom.Atn2|no angle",
            "[]",
            "VBAProject|Application-defined or object-defined error",
            "Subscript out of range",
            " 11 VBAProject",
        ]
    );
}

// "On Error statement": `On Error GoTo line` enables the routine starting at the line, which
// is any line of the procedure, here one inside the loop; "Resume statement": `Resume line`
// goes on at the line, and a Resume where no error is being handled is run-time error 20
// ("Resume without error"), trapped like any other: at i = 2 the handler is reached by falling
// into it (Err.Number 0), its Resume raises 20, which the handler takes. A failing Match
// leaves r as it was.
#[test]
fn an_error_handler_inside_a_loop_and_resume_without_error() {
    let src = "Sub Main()\n    Dim i As Integer, r, found As String\n    r = 0\n\
               \x20   For i = 1 To 3\n\
               \x20       On Error GoTo NextOne\n\
               \x20       r = WorksheetFunction.Match(\"b\", Array(Choose(i, \"a\", \"b\", \"c\")), 0)\n\
               \x20       found = found & i & \",\"\n\
               NextOne:\n\
               \x20       found = found & Err.Number & \";\"\n\
               \x20       Resume Continue\n\
               Continue:\n\
               \x20   Next i\n\
               \x20   Debug.Print found; r\nEnd Sub\n";
    assert_eq!(printed(src), ["1004;2,0;20;1004; 1 "]);
}

/// The error a macro run with the project's other standard modules stops with.
fn refused_with_modules(main: &str, modules: &[(&str, &str)]) -> String {
    let project = modules.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    match run_with(main, &RunOptions { project, ..RunOptions::default() }) {
        Ok(out) => panic!("ran, printing {:?}", out.printed),
        Err(e) => e.to_string(),
    }
}

// "Understanding scope and visibility": "private variables are available only to procedures in
// that module", and a module-level Dim is private by default; under Option Explicit another
// module's use of one is VBA's compile error "Variable not defined".
#[test]
fn another_modules_private_or_dim_variable_is_not_declared_here() {
    let other = "Attribute VB_Name = \"Other\"\nPrivate Hidden As Long\nDim Kept As Long\n";
    for name in ["Hidden", "Kept"] {
        let main = format!("Option Explicit\nSub Main()\n    {name} = 1\nEnd Sub\n");
        let error = refused_with_modules(&main, &[("Other", other)]);
        assert!(error.contains(&format!("variable {name} is not declared")), "{error}");
    }
}

// "Enum statement": an Enum is Public unless declared Private, so a module uses the members of
// an Enum that a module after it declares, Option Explicit or not; the members count on from the
// one given (Cw = 2, Ccw 3).
#[test]
fn enum_members_of_a_later_module_are_declared_under_option_explicit() {
    let main = "Option Explicit\nSub Main()\n    Dim x As Long\n    x = Cw\n    Debug.Print x; Ccw\nEnd Sub\n";
    let dirs = "Attribute VB_Name = \"Dirs\"\nPublic Enum Turn\n    Cw = 2\n    Ccw\nEnd Enum\n";
    assert_eq!(printed_with_modules(main, &[("Dirs", dirs)]), [" 2  3 "]);
}

// [MS-VBAL] 5.6.12 "Member Access Expressions": `Geom.Rate` names a member of the module Geom;
// a Rate that only another module declares is none of Geom's (VBA: "Method or data member not
// found"), and it is not the other module's Rate.
#[test]
fn a_qualified_name_must_be_declared_in_the_module_named() {
    let main = "Option Explicit\nSub Main()\n    Debug.Print Geom.Rate\nEnd Sub\n";
    let geom = "Attribute VB_Name = \"Geom\"\nPublic Const PI As Double = 3.5\n";
    let lib = "Attribute VB_Name = \"Lib\"\nPublic Rate As Double\n";
    let error = refused_with_modules(main, &[("Geom", geom), ("Lib", lib)]);
    assert!(error.contains("Geom"), "{error}");
}

// The pattern of real modules (`Private Const ACCURACY = 0.000000001` in each of three flow
// modules): constants declared alike in two modules have the one value VBA gives each, so the
// project runs ("Understanding scope and visibility": each reads its own).
#[test]
fn a_constant_declared_alike_in_two_modules_runs() {
    let main = "Private Const ACCURACY = 0.001\nSub Main()\n    Debug.Print ACCURACY; Other.Tolerance\nEnd Sub\n";
    let other = "Attribute VB_Name = \"Other\"\nPrivate Const ACCURACY = 0.001\n\
                 Function Tolerance()\n    Tolerance = ACCURACY * 2\nEnd Function\n";
    assert_eq!(printed_with_modules(main, &[("Other", other)]), [" 0.001  0.002 "]);
}

// [MS-VBAL] 5.3.1.11: an argument that is not a plain variable is evaluated and Let-coerced to
// the parameter's declared type, and Let-coercing an object reads its default member, which
// for a Range is Value (Microsoft's "Range.Value property": "the default member"). A
// collection helper passes `KeyRange.Cells(i)` to `KeyName As String` so.
#[test]
fn a_cell_given_to_a_typed_parameter_is_its_value() {
    let src = "Function Tag(KeyName As String) As String\n    Tag = \"<\" & KeyName & \">\"\nEnd Function\n\
               Function Twice(ByVal n As Long) As Long\n    Twice = 2 * n\nEnd Function\n\
               Sub Main()\n    Range(\"A1\").Value = \"x1\": Range(\"A2\").Value = 7\n\
               Dim r As Range: Set r = Range(\"A1:A2\")\n\
               Debug.Print Tag(r.Cells(1))\n    Debug.Print Tag(KeyName:=r.Cells(2))\n\
               Debug.Print CStr(Twice(Range(\"A2\")))\nEnd Sub\n";
    assert_eq!(printed(src), ["<x1>", "<7>", "14"]);
}

// [MS-VBAL] 5.3.1.11: each argument bound to a ParamArray is a Variant holding what the argument
// gave, and a function returning a Collection gives an object reference ("Array function": "a
// Variant containing an array" of such Variants). A `zip(col(1, 2), col(3))` helper relies on it.
#[test]
fn a_function_returning_an_object_given_to_a_param_array() {
    let src = "Function Mk(n) As Collection\n    Set Mk = New Collection\n    Dim i\n\
               For i = 1 To n: Mk.Add i: Next\nEnd Function\n\
               Function Total(ParamArray Args() As Variant) As Long\n    Dim i As Long\n\
               For i = LBound(Args) To UBound(Args): Total = Total + Args(i).Count: Next\nEnd Function\n\
               Sub Main()\n    Debug.Print CStr(Total(Mk(2), Mk(3)))\n\
               Dim v: v = Array(Mk(1), 7)\n    Debug.Print TypeName(v(0)) & \" \" & TypeName(v(1))\nEnd Sub\n";
    assert_eq!(printed(src), ["5", "Collection Integer"]);
}

// [MS-VBAL] 5.6.12 "Member Access Expressions": a member access applies to the value of the
// expression before the dot, a function's call too, so `Pick(d, "b").Name` reads the Name of
// the object the function returned (a dictionary helper returns the item it finds).
#[test]
fn a_member_of_what_a_function_returns() {
    let src = "Function Pick(d As Object, k) As Variant\n    Set Pick = d(k)\nEnd Function\n\
               Function Made() As Collection\n    Set Made = New Collection\n    Made.Add 4\nEnd Function\n\
               Sub Main()\n    Dim d As Object: Set d = CreateObject(\"Scripting.Dictionary\")\n\
               Set d(\"b\") = ActiveSheet\n    Debug.Print Pick(d, \"b\").Name\n\
               Debug.Print CStr(Made.Count + Made().Item(1))\nEnd Sub\n";
    assert_eq!(printed(src), ["Sheet1", "5"]);
}

// [MS-VBAL] 5.3.1.11: an argument that is an object passes the reference; the Worksheets
// collection is an object ("Workbook.Worksheets property": "a Sheets collection"), so a helper
// given it reads its Count and its items (`hasKey(Worksheets, name)` in a key-probing module).
#[test]
fn the_worksheets_collection_given_as_an_argument() {
    let src = "Function CountOf(Container As Variant) As Long\n    CountOf = Container.Count\nEnd Function\n\
               Function FirstName(Container As Variant) As String\n    FirstName = Container(1).Name\nEnd Function\n\
               Sub Main()\n    Worksheets.Add\n\
               Debug.Print CStr(CountOf(Worksheets)) & \" \" & CStr(CountOf(ThisWorkbook.Worksheets))\n\
               Debug.Print FirstName(Worksheets) = Worksheets(1).Name\nEnd Sub\n";
    assert_eq!(printed(src), ["2 2", "True"]);
}

// Microsoft's "Raise method": `object.Raise number, source, description, helpfile,
// helpcontext`, whose arguments may be named; `Err.Raise Number:=91, Description:="…"` gives
// Err the description named, in whatever order the names come.
#[test]
fn err_raise_takes_its_arguments_by_name() {
    let src = "Sub Main()\n    On Error Resume Next\n\
               Err.Raise Number:=91, Description:=\"input can't be empty\"\n\
               Debug.Print CStr(Err.Number) & \" \" & Err.Description\n    Err.Clear\n\
               Err.Raise Description:=\"late\", Number:=vbObjectError + 7, Source:=\"Mod\"\n\
               Debug.Print CStr(Err.Number - vbObjectError) & \" \" & Err.Source & \" \" & Err.Description\nEnd Sub\n";
    assert_eq!(printed(src), ["91 input can't be empty", "7 Mod late"]);
}

// [MS-VBAL] 5.3.1.11: an argument that is an object passes the reference, an item of a
// Collection that holds a Collection too ("Item method": the item itself), so `J(z(1))` with
// `J(c As Collection)` reads the inner Collection.
#[test]
fn a_collections_item_that_is_an_object_given_as_an_argument() {
    let src = "Function J(c As Collection) As String\n    Dim v\n    For Each v In c: J = J & v & \",\": Next\nEnd Function\n\
               Sub Main()\n    Dim z As New Collection, a As New Collection\n    a.Add 1: a.Add \"x\"\n    z.Add a\n\
               Debug.Print J(z(1)) & \" \" & J(z.Item(1))\nEnd Sub\n";
    assert_eq!(printed(src), ["1,x, 1,x,"]);
}

// Microsoft's "CompareMode property" (Scripting.Dictionary): the compare method's values are
// 0 binary, 1 text and 2 database, which the Scripting library names BinaryCompare,
// TextCompare and DatabaseCompare, so `d.CompareMode = TextCompare` compiles under Option
// Explicit and makes the keys ignore case.
#[test]
fn the_scripting_compare_method_constants() {
    let src = "Option Explicit\nSub Main()\n    Dim d As New Dictionary\n    d.CompareMode = TextCompare\n\
               d.Add \"a\", 1\n    Debug.Print d.Exists(\"A\")\n\
               Debug.Print CStr(BinaryCompare) & CStr(TextCompare) & CStr(DatabaseCompare)\nEnd Sub\n";
    assert_eq!(printed(src), ["True", "012"]);
}
