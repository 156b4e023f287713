//! Members of VBA's and Excel's object model that real modules use (issue 31): a class
//! module's default instance (`Attribute VB_PredeclaredId = True`), `CallByName`, the
//! `Parent` and `Application` of Excel's objects, `Intersect` and `Union`. Each expected
//! value is worked by hand from the page of Microsoft's reference named at the test, or from
//! [MS-VBAL] (the VBA language specification), never from our own earlier output.

mod common;

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

/// Runs `main` on a one-sheet workbook named Book1.xlsm with the project's class modules
/// (name, source as the VBA project stores it, `Attribute` lines included).
fn run_with_classes(main: &str, classes: &[(&str, &str)]) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    let options = RunOptions { classes, workbook_name: Some("Book1.xlsm".into()), ..RunOptions::default() };
    vba::run(&mut wb, main, "Module1.bas", &options)
}

fn printed(main: &str, classes: &[(&str, &str)]) -> Vec<String> {
    run_with_classes(main, classes).unwrap_or_else(|e| panic!("{e}")).printed
}

/// A class as the VBA editor stores it, `predeclared` its VB_PredeclaredId; each object it
/// makes counts itself in the standard module's `Made`.
fn point_class(predeclared: bool) -> String {
    let flag = if predeclared { "True" } else { "False" };
    format!(
        "Attribute VB_Name = \"Point\"\r\nAttribute VB_GlobalNameSpace = False\r\nAttribute VB_Creatable = False\r\n\
         Attribute VB_PredeclaredId = {flag}\r\nAttribute VB_Exposed = False\r\n\
         Public X As Double\r\nPublic Y As Double\r\n\
         Private Sub Class_Initialize()\r\n    Made = Made + 1\r\nEnd Sub\r\n\
         Public Function Create(a As Double, b As Double) As Point\r\n    Dim p As New Point\r\n    p.X = a\r\n    \
         p.Y = b\r\n    Set Create = p\r\nEnd Function\r\n"
    )
}

const FACTORY_MAIN: &str = "Public Made As Long\r\n\
    Sub Main()\r\n    Debug.Print CStr(Made)\r\n    Dim q As Point\r\n    Set q = Point.Create(1, 2)\r\n    \
    Debug.Print CStr(q.X + q.Y)\r\n    Point.X = 5\r\n    Remember\r\n    Debug.Print CStr(q Is Point) & \" \" & CStr(Made)\r\n\
    End Sub\r\nSub Remember()\r\n    Debug.Print CStr(Point.X)\r\nEnd Sub\r\n";

// [MS-VBAL] 5.2.4.1.2 "Default Instance Variables Static Semantics": a class module whose
// VB_PredeclaredId is "True" has a default instance variable named after the class, "with
// module extent as if declared in a <module-variable-declaration> containing an
// <as-autoobject>": made at its first use (5.2.3.1.4 auto-instantiation), one object for
// the whole run. So: no object before the first use (Made 0); `Point.Create` makes the
// default instance (1) and the new one inside (2); `Point.X = 5` is seen by another
// procedure; the object Create returned is not the default one.
#[test]
fn a_predeclared_class_has_one_default_instance_named_after_it() {
    let out = printed(FACTORY_MAIN, &[("Point", &point_class(true))]);
    assert_eq!(out, ["0", "3", "5", "False 2"]);
}

// Without the attribute (VB_PredeclaredId False, the default of a class module) `Point` names
// no object: VBA requires `New Point` ("Object required", error 424, at run time without
// Option Explicit). ncsheet refuses the module, naming the class and the attribute.
#[test]
fn a_class_without_the_attribute_has_no_default_instance() {
    let error = run_with_classes(FACTORY_MAIN, &[("Point", &point_class(false))]).expect_err("refused");
    assert!(error.message.contains("Point") && error.message.contains("VB_PredeclaredId"), "{error}");
}

// The same class exported by the VBA editor as Point.cls (its VERSION 1.0 CLASS header and
// BEGIN … END block, then the Attribute lines) and given with `run --module`.
#[test]
fn an_exported_cls_file_keeps_its_default_instance() {
    let dir = tempfile::tempdir().unwrap();
    let cls = format!("VERSION 1.0 CLASS\r\nBEGIN\r\n  MultiUse = -1  'True\r\nEND\r\n{}", point_class(true));
    std::fs::write(dir.path().join("Point.cls"), cls).unwrap();
    std::fs::write(dir.path().join("Module1.bas"), FACTORY_MAIN).unwrap();
    std::fs::write(dir.path().join("book.csv"), "1\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .current_dir(dir.path())
        .args(["run", "book.csv", "Module1.bas", "--module", "Point.cls"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Debug.Print goes to standard error, before the note that no program was written.
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.starts_with("ncsheet:")).map(str::trim).collect();
    assert_eq!(lines, ["0", "3", "5", "False 2"]);
}

const RECT: &str = "Attribute VB_Name = \"Rect\"\r\nPrivate mW As Double\r\n\
    Public Property Get W() As Double\r\n    W = mW\r\nEnd Property\r\n\
    Public Property Let W(v As Double)\r\n    mW = v\r\nEnd Property\r\n\
    Public Function Area(h As Double) As Double\r\n    Area = mW * h\r\nEnd Function\r\n";

// "CallByName function" (Office VBA reference): `CallByName(object, procname, calltype,
// [args()])` "executes a method of an object, or sets or returns a property"; calltype is
// vbMethod 1, vbGet 2, vbLet 4, vbSet 8 ("VbCallType" constants). Rect.W set to 4 through
// vbLet reads back 4 through vbGet; Area(3) is 4 * 3 = 12; a Collection's Add and Count,
// and a Range's Value, are members as well.
#[test]
fn call_by_name_runs_the_member_its_text_names() {
    let main = "Sub Main()\r\n    Dim r As New Rect\r\n    CallByName r, \"W\", VbLet, 4\r\n\
        Debug.Print CStr(CallByName(r, \"W\", VbGet))\r\n    Debug.Print CStr(CallByName(r, \"Area\", VbMethod, 3))\r\n\
        Dim c As New Collection\r\n    c.Add \"a\"\r\n    CallByName c, \"Add\", vbMethod, \"b\"\r\n\
        Debug.Print CStr(CallByName(c, \"Count\", VbGet)) & c(2)\r\n\
        CallByName Range(\"A1\"), \"Value\", VbLet, 7\r\n    Debug.Print CStr(Range(\"A1\").Value + 1)\r\n\
        Debug.Print CStr(CallByName(Range(\"A1\"), \"Value\", 2))\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[("Rect", RECT)]), ["4", "12", "2b", "8", "7"]);
}

// A member the object has not is VBA's run-time error 438, "Object doesn't support this
// property or method" ("Trappable errors"), which On Error traps as Err.Number.
#[test]
fn call_by_name_of_a_member_the_class_has_not_is_error_438() {
    let main = "Sub Main()\r\n    Dim r As New Rect\r\n    On Error Resume Next\r\n\
        Debug.Print CallByName(r, \"Height\", VbGet)\r\n    Debug.Print CStr(Err.Number)\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[("Rect", RECT)]), ["438"]);
}

// "Range.Parent property": a Range's parent is its Worksheet; "Worksheet.Parent property"
// the Workbook; every object's `Application` property is the Application, whose ActiveSheet
// and Worksheets are the workbook's. The sheet is Sheet1 and the workbook Book1.xlsm.
#[test]
fn parent_and_application_chains_reach_the_sheet_and_the_workbook() {
    let main = "Sub Main()\r\n    Debug.Print Range(\"B2\").Parent.Name\r\n    Debug.Print ActiveSheet.Parent.Name\r\n\
        Debug.Print Range(\"B2\").Parent.Parent.Name\r\n    Debug.Print ThisWorkbook.Application.ActiveSheet.Name\r\n\
        Debug.Print CStr(Range(\"A1\").Application.Worksheets.Count)\r\n\
        Debug.Print ActiveSheet.Application.ActiveSheet.Range(\"C3\").Address\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[]), ["Sheet1", "Book1.xlsm", "Book1.xlsm", "Sheet1", "1", "$C$3"]);
}

// "Application.Intersect method": "Returns a Range object that represents the rectangular
// intersection of two or more ranges" — A1:C3 and B2:D4 share B2:C3; ranges that share no
// cell give Nothing (the page's example tests `If isect Is Nothing`). "Application.Union
// method": "the union of two or more ranges" — A1:A2 and A3:A5 are A1:A5. Both are members
// of Application and are called unqualified too.
#[test]
fn intersect_and_union_of_ranges() {
    let main = "Sub Main()\r\n    Debug.Print Intersect(Range(\"A1:C3\"), Range(\"B2:D4\")).Address\r\n\
        Debug.Print CStr(Application.Intersect(Range(\"A1\"), Range(\"C3\")) Is Nothing)\r\n\
        Dim isect As Range\r\n    Set isect = Application.Intersect(Range(\"A1:B9\"), Range(\"B5:Z5\"), Range(\"A5:B5\"))\r\n\
        Debug.Print isect.Address\r\n    Debug.Print Union(Range(\"A1:A2\"), Range(\"A3:A5\")).Address\r\n\
        Debug.Print Application.Union(Range(\"B2\"), Range(\"A1:C3\")).Address\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[]), ["$B$2:$C$3", "True", "$B$5", "$A$1:$A$5", "$A$1:$C$3"]);
}

// A union of two areas (A1 and C3) is one Range of two areas in Excel ("Range.Areas
// property"): its Address lists both (tests/vba_areas.rs goes further).
#[test]
fn a_union_of_separate_areas_is_two_areas() {
    let main = "Sub Main()\r\n    Debug.Print Union(Range(\"A1\"), Range(\"C3\")).Address\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[]), ["$A$1,$C$3"]);
}

// Excel's selection is a reference to cells and moves with them as every Range does
// ("Range.Insert method": the cells "shift"; d1b5432 moved the macro's Range variables the
// same way): B1 selected, a column inserted at A, C1 is selected and active. B2:C3 with C3
// active ("Range.Activate": a cell inside the selection becomes active, the selection
// stays), row 1 deleted: B1:C2 with C2 active.
#[test]
fn selection_and_active_cell_move_with_inserted_and_deleted_cells() {
    let main = "Sub Main()\r\n    Range(\"B1\").Select\r\n    Columns(\"A\").Insert\r\n\
        Debug.Print Selection.Address & \" \" & ActiveCell.Address\r\n\
        Range(\"B2:C3\").Select\r\n    Range(\"C3\").Activate\r\n    Rows(1).Delete\r\n\
        Debug.Print Selection.Address & \" \" & ActiveCell.Address\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[]), ["$C$1 $C$1", "$B$1:$C$2 $C$2"]);
}

/// `New ArrayList` through CreateObject, as sorting and array-rebasing macros use it.
const MAKE_LIST: &str = "    Dim a As Object\r\n    Set a = CreateObject(\"System.Collections.ArrayList\")\r\n";

fn printed_with_list(body: &str) -> Vec<String> {
    printed(&format!("Sub Main()\r\n{MAKE_LIST}{body}End Sub\r\n"), &[])
}

/// The words of Microsoft's ArrayList examples ("ArrayList.Sort Method", "ArrayList.Reverse
/// Method"), added in order.
const QUICK_FOX: &str = "    Dim w As Variant, s As String, x As Variant\r\n    For Each w In Split(\"The quick brown fox jumps over the lazy dog\")\r\n\
    a.Add w\r\n    Next\r\n";

fn joined_items() -> &'static str {
    "    s = \"\"\r\n    For Each x In a\r\n        s = s & \" \" & x\r\n    Next\r\n    \
     Debug.Print Mid(s, 2)\r\n"
}

// .NET's System.Collections.ArrayList reached through COM ("ArrayList Class", Microsoft's .NET
// reference): Add returns the index the item got (0-based), Item is the default member,
// Count and Capacity as the class example prints them after three Adds (Count 3, Capacity 4),
// Contains and IndexOf by the items' Equals (-1 for none), Insert, Remove (the first equal
// item; an item not there is no error), RemoveAt, Clear (Capacity stays), ToArray a zero-based
// array, For Each over the items. It was refused by name before.
#[test]
fn a_dotnet_array_list_keeps_items_by_zero_based_index() {
    let body = "    Debug.Print a.Capacity & \" \" & a.Add(\"Hello\") & a.Add(\"World\") & a.Add(\"!\")\r\n\
        Debug.Print a.Count & \" \" & a.Capacity & \" \" & a(1) & \" \" & a.Item(0)\r\n\
        Debug.Print a.Contains(\"World\") & \" \" & a.Contains(\"world\") & \" \" & a.IndexOf(\"!\", 0) & \" \" & a.IndexOf(\"?\", 0)\r\n\
        a.Insert 1, \"big\"\r\n    a(0) = \"Hi\"\r\n    a.Remove \"nothing\"\r\n    a.Remove \"!\"\r\n\
        Dim v As Variant\r\n    v = a.ToArray()\r\n    Debug.Print LBound(v) & \" \" & UBound(v) & \" \" & Join(v, \"-\")\r\n\
        a.RemoveAt 0\r\n    a.Add 5\r\n    a.Add 6\r\n    a.Add 7\r\n\
        Debug.Print a.Count & \" \" & a.Capacity\r\n    a.Clear\r\n    Debug.Print a.Count & \" \" & a.Capacity & \" \" & TypeName(a)\r\n";
    assert_eq!(
        printed_with_list(body),
        ["0 012", "3 4 World Hello", "True False 2 -1", "0 2 Hi-big-World", "5 8", "0 8 ArrayList"]
    );
}

// "ArrayList.Sort Method" and "ArrayList.Reverse Method": Microsoft's examples sort "The quick
// brown fox jumps over the lazy dog" into "brown dog fox jumps lazy over quick the The" (the
// culture's order: case ignored, then lowercase first) and reverse it into "dog lazy the over
// jumps fox brown quick The". Numbers sort by value.
#[test]
fn a_dotnet_array_list_sorts_and_reverses_as_the_reference_shows() {
    let body = format!(
        "{QUICK_FOX}    a.Reverse\r\n{joined}    a.Sort\r\n{joined}    a.Clear\r\n\
        a.Add 10#\r\n    a.Add 2.5\r\n    a.Add -1#\r\n    a.Sort\r\n{joined}",
        joined = joined_items()
    );
    assert_eq!(
        printed_with_list(&body),
        ["dog lazy the over jumps fox brown quick The", "brown dog fox jumps lazy over quick the The", "-1 2.5 10"]
    );
}

// Through COM the .NET exceptions reach VBA as their HRESULTs, which Err.Number reads as a
// Long: ArgumentOutOfRangeException 0x80131502 (-2146233086) for an index past the items
// ("ArrayList.Item[Int32]": "index is equal to or greater than Count"), InvalidOperationException
// 0x80131509 (-2146233079) for Sort of items that cannot be compared ("ArrayList.Sort":
// "InvalidOperationException: An error occurred while comparing two elements"; a String's
// CompareTo refuses a number).
#[test]
fn a_dotnet_array_list_raises_dotnet_errors() {
    let body =
        "    a.Add \"x\"\r\n    On Error Resume Next\r\n    Debug.Print a(1)\r\n    Debug.Print CStr(Err.Number)\r\n\
        Err.Clear\r\n    a.RemoveAt -1\r\n    Debug.Print CStr(Err.Number)\r\n    Err.Clear\r\n\
        a.Add 1#\r\n    a.Sort\r\n    Debug.Print Err.Number & \" \" & a(0)\r\n";
    assert_eq!(printed_with_list(body), ["-2146233086", "-2146233086", "-2146233079 x"]);
}

/// A class module's Public Enum is a type of the project: its members are seen from every
/// module, plainly or through the Enum's name ("Enum statement": Public, the default, makes the
/// Enum "visible to all procedures in all modules"; [MS-VBAL] 5.2.3.4). They read as Empty from
/// a standard module before: `BadDim` gave "" where VBA gives vbObjectError + 200.
#[test]
fn a_class_modules_public_enum_is_seen_from_every_module() {
    let class = "Attribute VB_Name = \"Shape\"\r\nAttribute VB_PredeclaredId = False\r\nOption Explicit\r\n\
                 Public Enum ShapeError\r\n    BadDim = vbObjectError + 200\r\n    Other = 7\r\nEnd Enum\r\n\
                 Private Enum Hidden\r\n    Secret = 3\r\nEnd Enum\r\n\
                 Public Function Code() As Long\r\n    Code = BadDim + Secret\r\nEnd Function\r\n";
    let main = "Sub Main()\r\n    Dim s As New Shape\r\n    Debug.Print BadDim; ShapeError.Other; s.Code; IsEmpty(Secret)\r\nEnd Sub\r\n";
    // vbObjectError is -2147221504 ("Raise method"); the Private Enum stays inside its class.
    assert_eq!(printed(main, &[("Shape", class)]), vec!["-2147221304  7 -2147221301 True"]);
}

// Library objects ncsheet does not make are refused by their own name, with what to use
// instead, not as a program a macro may not start ("cannot touch files or run programs"
// was the message for VBScript.RegExp, which ncsheet now makes: tests/vba_regexp.rs).
#[test]
fn library_objects_not_made_are_refused_by_name() {
    let (prog_id, names) = ("System.Collections.SortedList", [".NET's collections", "Scripting.Dictionary"]);
    let main = format!("Sub Main()\r\n    Dim o\r\n    Set o = CreateObject(\"{prog_id}\")\r\nEnd Sub\r\n");
    let error = run_with_classes(&main, &[]).expect_err("refused");
    assert!(error.message.contains(prog_id), "{error}");
    assert!(names.iter().all(|n| error.message.contains(n)), "{error}");
    assert!(!error.message.contains("run programs"), "{error}");
}

// [MS-VBAL] 5.2.3.1.3: a declared type may be a library's qualified name, so `As VBA.Collection`
// is VBA's Collection class (an object variable: `Is Nothing`, `Set … = New VBA.Collection`)
// and `As Excel.XlDirection` Excel's enum (a Long, 0 to start); a class module of the project
// is an object whatever its name begins with (`XlsRow` is no `Xl…` enum of Excel's).
#[test]
fn qualified_and_class_type_names_declare_what_they_name() {
    let main =
        "Function Grow(c As VBA.Collection) As Long\r\n    If c Is Nothing Then Set c = New VBA.Collection\r\n    \
        c.Add 1\r\n    Grow = c.Count\r\nEnd Function\r\n\
        Sub Main()\r\n    Dim c As Collection, r As XlsRow, d As Excel.XlDirection\r\n    \
        Debug.Print CStr(Grow(c)) & CStr(Grow(c))\r\n    Set r = New XlsRow\r\n    r.N = 7\r\n    \
        Debug.Print CStr(r.N) & TypeName(r) & CStr(d)\r\nEnd Sub\r\n";
    let class = "Attribute VB_Name = \"XlsRow\"\r\nPublic N As Long\r\n";
    assert_eq!(printed(main, &[("XlsRow", class)]), ["12", "7XlsRow0"]);
}

// "Keys method" and "Items method" (Scripting.Dictionary): each "returns an array" of the keys
// (items), counted from 0. Neither takes an argument, so `d.Keys(i)` indexes the array it returns
// ([MS-VBAL] 5.6.13.1, an argument list after a function without parameters), the loop `For i = 0
// To d.Count - 1: d.Keys(i)` common in real modules; an index outside it is run-time error 9
// ("Subscript out of range").
#[test]
fn dictionary_keys_and_items_index_the_array_they_return() {
    let main = "Sub Main()\r\n    Dim d As New Scripting.Dictionary, i As Long\r\n    d.Add \"a\", 10: d.Add \"b\", 20\r\n    \
        For i = 0 To d.Count - 1\r\n        Debug.Print d.Keys(i) & \"=\" & d.Items(i)\r\n    Next\r\n    \
        Debug.Print UBound(d.Keys) & d.Keys()(1)\r\n    On Error Resume Next\r\n    Debug.Print d.Keys(2)\r\n    \
        Debug.Print CStr(Err.Number)\r\nEnd Sub\r\n";
    assert_eq!(printed(main, &[]), ["a=10", "b=20", "1b", "9"]);
}

/// Runs `body` as Sub Main on a workbook of `sheets` (the first active), printing what it prints.
fn printed_on(sheets: &[&str], body: &str) -> Vec<String> {
    let mut wb = Workbook::with_sheet();
    wb.rename_sheet(0, sheets[0]).unwrap();
    for name in &sheets[1..] {
        wb.add_sheet(name).unwrap();
    }
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    vba::run(&mut wb, &src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}")).printed
}

// [MS-VBAL] 5.6.13.1: an index expression on an object is a call of its default member. The
// default member of Excel's Sheets and Worksheets collections is Item ("Sheets.Item property",
// "Worksheets object": `Worksheets(1)`), of a Rows or Columns collection too ("Range.Item
// property"). So a variable set to the collection is indexed as the collection is, by number
// or by name, and `Set` takes the sheet (a real module, ListWorksheets: `Set sl =
// ActiveWorkbook.Worksheets` … `Set ws = sl(j)`).
#[test]
fn a_variable_set_to_a_collection_is_indexed_by_its_item() {
    let out = printed_on(
        &["Parts", "Offsets", "Notes"],
        "    Dim sl As Object, ws As Worksheet, rw As Object\n    Set sl = ActiveWorkbook.Worksheets\n\
         \x20   Set ws = sl(2)\n    Debug.Print ws.Name; \",\"; sl(\"Notes\").Index; \",\"; sl(3).Name\n\
         \x20   Set rw = Range(\"A1:B3\").Rows\n    Debug.Print rw(2).Address",
    );
    assert_eq!(out, ["Offsets, 3 ,Notes", "$A$2:$B$2"]);
}

// "Range.Item property": `expression.Item(RowIndex, ColumnIndex)`, the default member, counted
// from the range's first cell and allowed past it (`Range("B2")(2)` is B3, `(1, 2)` is C2), on
// a Range any expression gives: `Range("A65536").End(xlUp)(2)`, the cell under the last used
// one, as ExtendOffice's "Combine" macro pastes each sheet's rows there.
#[test]
fn a_range_an_expression_gives_is_indexed_by_its_item() {
    let out = printed_on(
        &["Data"],
        "    Range(\"A1:A3\").Value = 7\n    Debug.Print Range(\"B2\")(2).Address; Range(\"B2\")(1, 2).Address; \
         Range(\"B2:C3\")(3).Address\n    Debug.Print Range(\"A65536\").End(xlUp)(2).Address\n\
         \x20   Range(\"A65536\").End(xlUp)(2).Value = \"next\"\n    Debug.Print Range(\"A4\").Value",
    );
    assert_eq!(out, ["$B$3$C$2$B$3", "$A$4", "next"]);
}

// "Application.Selection property": "Returns the currently selected object on the active
// worksheet"; "Application.ActiveCell property": the active cell, one cell of that selection.
// A workbook saved with A4:C9 selected and A4 active (`<selection activeCell="A4"
// sqref="A4:C9"/>`) starts a macro with that range as Selection, so a real module working on
// the user's selection (jmarcellusc's DeleteBlankRows: `Set SourceRange =
// Application.Selection`) sees its 6 rows. A saved range that does not hold the active cell is
// not Excel's, and the active cell alone is the selection then.
#[test]
fn selection_starts_as_the_range_the_file_saved() {
    let run = |selection: &str| {
        let mut wb = Workbook::with_sheet();
        let sheet = wb.sheet_names()[0].clone();
        let active = ncsheet::formula::address::parse_cell("A4").unwrap();
        let rect = ncsheet::formula::address::parse_rect(selection).unwrap();
        let options = RunOptions {
            active_cells: vec![(sheet.clone(), active)],
            selections: vec![(sheet, vec![rect])],
            ..RunOptions::default()
        };
        let src =
            "Sub Main()\nDebug.Print Selection.Address; \" \"; ActiveCell.Address; Selection.Rows.Count\nEnd Sub\n";
        vba::run(&mut wb, src, "Module1.bas", &options).unwrap_or_else(|e| panic!("{e}")).printed
    };
    assert_eq!(run("A4:C9"), ["$A$4:$C$9 $A$4 6 "]);
    assert_eq!(run("B5:C9"), ["$A$4 $A$4 1 "]);
}

/// A macro on LibreOffice's tables.xlsx (tests/data/libreoffice), whose table part says
/// `Parts`, `ref="A1:F6"`, one header row, one totals row, six columns "Part No", "Qty",
/// "Unit Price", "Col'#", "[x]", "Line Total".
fn printed_on_tables(body: &str) -> (Vec<String>, Workbook) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/libreoffice/tables.xlsx");
    let mut wb = ncsheet::io::xlsx::load(&path).unwrap_or_else(|e| panic!("{e}")).workbook;
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    let out = vba::run(&mut wb, &src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    (out.printed, wb)
}

/// "Worksheet.ListObjects property", "ListObjects.Item property" (an index or the table's
/// name), "ListObject.Range / DataBodyRange / HeaderRowRange / TotalsRowRange property" (the
/// whole table; the rows between header and totals; the header row; the totals row),
/// "ListColumn.Index / DataBodyRange property", "ListRows.Count": the table part's rectangle
/// cut as those pages say. The sum of the Qty column's data is the file's own cached total
/// in B6 (=SUBTOTAL(109,Parts[Qty]) saved by LibreOffice: 17). A name the sheet has no table
/// of is "Subscript out of range" (error 9).
#[test]
fn list_objects_give_a_tables_parts_as_ranges() {
    let (out, _) = printed_on_tables(
        "    Dim lo As ListObject, lc As ListColumn\n    Set lo = Worksheets(\"Parts Data\").ListObjects(\"parts\")\n    \
         Debug.Print Worksheets(\"Parts Data\").ListObjects.Count; Worksheets(\"Use\").ListObjects.Count; lo.Name; \
         TypeName(lo); Worksheets(1).ListObjects(1).Name\n    \
         Debug.Print lo.Range.Address; \" \"; lo.DataBodyRange.Address; \" \"; lo.HeaderRowRange.Address; \" \"; \
         lo.TotalsRowRange.Address\n    \
         Debug.Print lo.ListColumns.Count; lo.ListRows.Count; lo.ListColumns(\"Unit Price\").Index; lo.ListColumns(5).Name; \
         lo.ListColumns(\"Qty\").DataBodyRange.Address; Application.Sum(lo.ListColumns(\"Qty\").DataBodyRange); \
         lo.ListColumns(2).Range.Cells(RowIndex:=6)\n    \
         For Each lc In lo.ListColumns: Debug.Print lc.Index;: Next\n    \
         Debug.Print lo.ListRows(3).Range(1); lo.DataBodyRange(4, 2)\n    \
         On Error Resume Next\n    Set lo = ActiveSheet.ListObjects(\"Nope\")\n    Debug.Print Err.Number",
    );
    assert_eq!(
        out,
        vec![
            " 1  0 PartsListObjectParts",
            "$A$1:$F$6 $A$2:$F$5 $A$1:$F$1 $A$6:$F$6",
            " 6  4  3 [x]$B$2:$B$5 17  17 ",
            " 1  2  3  4  5  6 c 7 ",
            " 9 ",
        ]
    );
}

/// "ListRows.Add method": a row added without a Position goes at the end of the data, and the
/// totals row below it moves down ("AlwaysInsert … the cells below the table will be shifted
/// down one row"); with `Position:=1` it goes before the first data row, the rest moving down.
/// The ListRow it returns is the new row ("ListRow.Range property").
#[test]
fn list_rows_add_inserts_a_row_of_the_table() {
    let (out, wb) = printed_on_tables(
        "    Dim lo As ListObject, lr As ListRow\n    Set lo = Worksheets(\"Parts Data\").ListObjects(1)\n    \
         Set lr = lo.ListRows.Add\n    lr.Range(1) = \"e\": lr.Range(2) = 1\n    \
         Set lr = lo.ListRows.Add(Position:=1)\n    lr.Range.Cells(1, 1).Value = \"first\"\n    \
         Debug.Print lo.ListRows.Count; lr.Index; lo.Range.Address; \" \"; lo.TotalsRowRange.Address",
    );
    assert_eq!(out, vec![" 6  1 $A$1:$F$8 $A$8:$F$8"]);
    let text = |cell: &str| wb.value(0, ncsheet::formula::address::parse_cell(cell).unwrap());
    let t = |s: &str| ncsheet::eval::Value::text(s);
    assert_eq!(
        [text("A2"), text("A3"), text("A7"), text("B7"), text("A8")],
        [t("first"), t("a"), t("e"), ncsheet::eval::Value::Number(1.0), t("Total")]
    );
}

/// A table follows the rows and columns a macro inserts and deletes as Excel's does
/// (Microsoft's "Resize a table by adding or removing rows and columns": a row or column
/// inserted inside a table is the table's; Excel names a new column `Column1`): a row inserted
/// inside grows it, one above moves it, a column inserted inside is a new column of that name
/// written in its header cell, deleting all its rows deletes it. Shifting the cells of some of
/// its columns is refused as Excel refuses it ("This operation is not allowed. The operation is
/// attempting to shift cells in a table on your worksheet."), run-time error 1004.
#[test]
fn tables_follow_inserted_and_deleted_rows_and_columns() {
    let (out, _) = printed_on_tables(
        "    Dim lo As ListObject\n    Set lo = Worksheets(\"Parts Data\").ListObjects(1)\n    \
         Rows(3).Insert: Debug.Print lo.Range.Address; lo.ListRows.Count\n    Rows(3).Delete\n    \
         Columns(\"C\").Insert: Debug.Print lo.Range.Address; \" \"; lo.ListColumns(3).Name; \" \"; Range(\"C1\").Value\n    \
         Columns(\"C\").Delete: Debug.Print lo.ListColumns(3).Name\n    \
         Rows(1).Insert: Debug.Print lo.Range.Address\n    \
         On Error Resume Next\n    Range(\"A3:B3\").Insert Shift:=xlDown: Debug.Print Err.Number; lo.Range.Address\n    \
         On Error GoTo 0\n    Rows(\"2:7\").Delete: Debug.Print Worksheets(\"Parts Data\").ListObjects.Count",
    );
    assert_eq!(
        out,
        vec!["$A$1:$F$7 5 ", "$A$1:$G$6 Column1 Column1", "Unit Price", "$A$2:$F$7", " 1004 $A$2:$F$7", " 0 ",]
    );
}

/// What a macro run with `--save` writes of a table whose size it changed.
fn saved_table_part(book: &std::path::Path, body: &str) -> (String, std::path::PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let macro_file = dir.path().join("m.bas");
    std::fs::write(&macro_file, format!("Sub Main()\n{body}\nEnd Sub\n")).unwrap();
    let saved = dir.path().join("saved.xlsx");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["run".as_ref(), book.as_os_str(), macro_file.as_os_str(), "--save".as_ref(), saved.as_os_str()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let file = std::fs::File::open(&saved).unwrap();
    let mut zip = zip::ZipArchive::new(file).unwrap();
    let mut part = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("xl/tables/table1.xml").unwrap(), &mut part).unwrap();
    (part, saved, dir)
}

/// A table a macro grew is saved with its new range, as a table part: a package written anew
/// (rows were inserted) adds the part, and LibreOffice reads it as the same table (its own
/// save of our file names `Parts` over A1:F7); a package patched (ListRows.Add took the empty
/// row below POI's ExcelTables.xlsx table G1:I4, "ListRows.Add method": "the table will
/// expand to occupy that row without shifting cells") keeps the part, its `ref` and its
/// `<autoFilter>`'s moved to G1:I5, the calculated column's formula kept.
#[test]
fn a_table_a_macro_grew_is_saved_with_its_new_range() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let (part, saved, dir) =
        saved_table_part(&data.join("libreoffice/tables.xlsx"), "    Worksheets(\"Parts Data\").Rows(3).Insert");
    assert!(part.contains(r#"displayName="Parts" ref="A1:F7""#) && part.contains("totalsRowCount=\"1\""), "{part}");
    assert!(part.contains(r#"<tableColumn id="2" name="Qty" totalsRowFunction="sum"/>"#), "{part}");
    if let Some(lo) = common::xlsx::libreoffice_recalculated(&saved, dir.path()) {
        let mut zip = zip::ZipArchive::new(std::fs::File::open(lo).unwrap()).unwrap();
        let mut part = String::new();
        std::io::Read::read_to_string(&mut zip.by_name("xl/tables/table1.xml").unwrap(), &mut part).unwrap();
        assert!(part.contains(r#"name="Parts""#) && part.contains(r#"ref="A1:F7""#), "{part}");
    }
    let poi = data.join("excel-corpus/public/poi/test-data_spreadsheet_ExcelTables.xlsx");
    let (part, _, _) = saved_table_part(&poi, "    ActiveSheet.ListObjects(1).ListRows.Add.Range(1) = \"Zed\"");
    assert!(part.contains(r#"ref="G1:I5""#) && part.contains(r#"<autoFilter ref="G1:I5"/>"#), "{part}");
    assert!(part.contains("<calculatedColumnFormula>INT(H2/10)</calculatedColumnFormula>"), "{part}");
}

/// The text of part `name` of the package `file`.
fn package_part(file: &std::path::Path, name: &str) -> String {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(file).unwrap()).unwrap();
    let mut part = String::new();
    std::io::Read::read_to_string(&mut zip.by_name(name).unwrap(), &mut part).unwrap();
    part
}

/// "The names in structured references adjust whenever you add or remove data from the
/// table" (Microsoft's "Using structured references with Excel tables"): a row of Qty 7 added
/// by ListRows.Add makes the totals row's SUBTOTAL(109,Parts[Qty]) 17 + 7 = 24 (moved to B7
/// with the totals row) and Use!A1's SUM(Parts[Qty]) 24, where reading the references as the
/// ranges they named at load left 17. The saved package keeps the structured spelling, as
/// Excel stores it (`[@Qty]` as `Parts[[#This Row],[Qty]]`), with the table part's totals row
/// label and functions, and LibreOffice reading it back computes 24 too.
#[test]
fn structured_references_follow_a_table_a_macro_grew() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let body = "    Dim lr As ListRow\n    Set lr = Worksheets(\"Parts Data\").ListObjects(1).ListRows.Add\n    \
                lr.Range(1) = \"e\": lr.Range(2) = 7: lr.Range(3) = 2\n    \
                Debug.Print Range(\"B7\").Value; Worksheets(\"Use\").Range(\"A1\").Value; Range(\"B7\").Formula";
    let (out, _) = printed_on_tables(body);
    assert_eq!(out, vec![" 24  24 =SUBTOTAL(109,Parts[Qty])"]);
    let (part, saved, dir) = saved_table_part(&data.join("libreoffice/tables.xlsx"), body);
    // The totals row's label and functions of the file's table part are kept.
    assert!(part.contains(r#"name="Part No" totalsRowLabel="Total""#), "{part}");
    assert!(part.contains(r#"name="Qty" totalsRowFunction="sum""#), "{part}");
    let sheet = package_part(&saved, "xl/worksheets/sheet1.xml");
    assert!(sheet.contains("<f>SUBTOTAL(109,Parts[Qty])</f>"), "{sheet}");
    assert!(sheet.contains("<f>Parts[[#This Row],[Qty]]*Parts[[#This Row],[Unit Price]]</f>"), "{sheet}");
    if let Some(lo) = common::xlsx::libreoffice_recalculated(&saved, dir.path()) {
        let sheet = package_part(&lo, "xl/worksheets/sheet1.xml");
        let b7 = sheet.split("<c r=\"B7\"").nth(1).and_then(|c| c.split("</c>").next()).unwrap_or_default();
        assert!(b7.contains("<v>24</v>"), "LibreOffice's B7: {b7}");
    }
}

/// The value LibreOffice cached in cell `cell` of part `sheet` of package `file`.
fn cached_in(file: &std::path::Path, sheet: &str, cell: &str) -> String {
    let xml = package_part(file, sheet);
    let c = xml.split(&format!("<c r=\"{cell}\"")).nth(1).and_then(|c| c.split("</c>").next()).unwrap_or_default();
    c.split("<v>").nth(1).and_then(|v| v.split("</v>").next()).unwrap_or_default().to_string()
}

/// A header typed over renames its column, and a table renamed keeps its formulas: "When a
/// header is changed, all formula references to that column are automatically adjusted";
/// "When you enter a header value that is the same as another header in the same Table,
/// Excel appends a number" (Barresse and Jones, *Excel Tables*, ch. 2, "The Header Row");
/// an emptied header is `Column1`, as Excel fills it in; "ListObject.Name property",
/// "ListColumn.Name property" (read/write). Use!A1's SUM(Parts[Qty]) stays 17 (the value in
/// LibreOffice's own save, tables.lo.xlsx) as SUM(Items[Quantity]), F2's
/// `[@Qty]*[@[Unit Price]]` stays 2 × 1.5 = 3, and LibreOffice reading the saved package,
/// whose table part names the new columns, computes both again.
#[test]
fn a_header_typed_over_and_a_table_renamed_carry_the_formulas_naming_them() {
    let body = "    Dim lo As ListObject\n    Set lo = Worksheets(\"Parts Data\").ListObjects(1)\n    \
                Range(\"B1\").Value = \"Quantity\"\n    lo.Name = \"Items\"\n    \
                Range(\"C1\").Value = \"quantity\"\n    lo.ListColumns(6).Name = \"Amount\"\n    \
                Range(\"E1\").ClearContents\n    Range(\"D3\").Formula = \"=[@Quantity]*2\"\n    \
                Debug.Print Worksheets(\"Use\").Range(\"A1\").Formula; Worksheets(\"Use\").Range(\"A1\").Value; \
                Range(\"C1\").Value; \" \"; Range(\"F2\").Formula; Range(\"F2\").Value; Range(\"E1\").Value\n    \
                Debug.Print Range(\"H5\").Formula; \" \"; Range(\"F6\").Formula; \" \"; \
                Worksheets(\"Use\").Range(\"A7\").Formula; lo.ListColumns(2).Name; Range(\"D3\").Value";
    let (out, _) = printed_on_tables(body);
    assert_eq!(
        out,
        vec![
            "=SUM(Items[Quantity]) 17 quantity2 =Items[@Quantity]*Items[@quantity2] 3 Column1",
            "=Items[@Column1] =SUBTOTAL(109,Items[Amount]) =ROWS(Items)Quantity 6 ",
        ]
    );
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let (part, saved, dir) = saved_table_part(&data.join("libreoffice/tables.xlsx"), body);
    for name in [r#"displayName="Items""#, r#"name="Quantity""#, r#"name="quantity2""#, r#"name="Amount""#] {
        assert!(part.contains(name), "{name}: {part}");
    }
    let sheet = package_part(&saved, "xl/worksheets/sheet2.xml");
    assert!(sheet.contains("<f>SUM(Items[Quantity])</f>"), "{sheet}");
    // `[@Quantity]` typed in D3, a cell of the table, is stored as Excel stores it.
    let parts = package_part(&saved, "xl/worksheets/sheet1.xml");
    assert!(parts.contains("<f>Items[[#This Row],[Quantity]]*2</f>"), "{parts}");
    if let Some(lo) = common::xlsx::libreoffice_recalculated(&saved, dir.path()) {
        assert_eq!(cached_in(&lo, "xl/worksheets/sheet2.xml", "A1"), "17");
        assert_eq!(cached_in(&lo, "xl/worksheets/sheet1.xml", "F2"), "3");
        assert_eq!(cached_in(&lo, "xl/worksheets/sheet1.xml", "D3"), "6");
    }
}

/// A structured reference without its table's name (`[@Qty]`) is read against the table
/// holding its cell ("Using structured references with Excel tables": inside a table Excel
/// writes `[@[Sales Amount]]`); typed in a cell of no table it names nothing, and the macro
/// is told which cell.
#[test]
fn a_structured_reference_without_its_tables_name_is_refused_outside_a_table() {
    let (out, _) = printed_on_tables(
        "    On Error Resume Next\n    Range(\"J2\").Formula = \"=[@Qty]*2\"\n    \
         Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(out.len(), 1, "{out:?}");
    assert!(out[0].contains("J2") && out[0].contains("in none"), "{out:?}");
}

/// "ListObject.ShowTotals property" (read/write) as Excel's Total Row: hidden, the totals
/// row's cells go and the cells under the table move up (A8 to A7), `Parts[[#Totals],[Qty]]`
/// names nothing (#REF!, error 2023) while Parts[Qty] still sums 17; shown again, the cells
/// under the table move down and the row holds what the file's table part says of it
/// (`totalsRowLabel="Total"`, `totalsRowFunction="sum"`: SUBTOTAL(109,Parts[Qty]), 17 as
/// LibreOffice cached it in tables.lo.xlsx).
#[test]
fn show_totals_hides_and_shows_a_tables_totals_row_moving_the_cells_under_it() {
    let (out, _) = printed_on_tables(
        "    Dim lo As ListObject\n    Set lo = Worksheets(\"Parts Data\").ListObjects(1)\n    \
         Range(\"A8\").Value = \"below\"\n    lo.ShowTotals = False\n    \
         Debug.Print lo.ShowTotals; lo.Range.Address; Range(\"A7\").Value; \
         Worksheets(\"Use\").Range(\"A4\").Value; Worksheets(\"Use\").Range(\"A1\").Value\n    \
         lo.ShowTotals = True\n    \
         Debug.Print lo.ShowTotals; lo.Range.Address; Range(\"A8\").Value; Range(\"A6\").Value; \
         Range(\"B6\").Formula; Range(\"B6\").Value; Worksheets(\"Use\").Range(\"A4\").Value",
    );
    assert_eq!(
        out,
        vec!["False$A$1:$F$5belowError 2023 17 ", "True$A$1:$F$6belowTotal=SUBTOTAL(109,Parts[Qty]) 17  17 ",]
    );
}

/// A package written anew keeps a calculated column's formula (`calculatedColumnFormula`):
/// POI's ExcelTables.xlsx table G1:I4 has AgeGroup `INT(H2/10)`; a row inserted above it
/// moves it to G2:I5, and the part written anew still names the formula, read at its first
/// data row (`INT(H3/10)`), as Excel would store it.
#[test]
fn a_table_written_anew_keeps_its_calculated_columns_formula() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/excel-corpus/public/poi/test-data_spreadsheet_ExcelTables.xlsx");
    let (part, _saved, _dir) = saved_table_part(&path, "    Rows(1).Insert");
    assert!(part.contains(r#"ref="G2:I5""#), "{part}");
    assert!(part.contains("<calculatedColumnFormula>INT(H3/10)</calculatedColumnFormula>"), "{part}");
}

/// "Use calculated columns in an Excel table" (Microsoft: a calculated column's formula "is
/// automatically extended" to the rows added): POI's ExcelTables.xlsx table G1:I4 has the
/// calculated column AgeGroup, `INT(H2/10)` (its `calculatedColumnFormula`); the row
/// ListRows.Add makes (row 5) gets `=INT(H5/10)`, which for an Age of 123 is 12.
#[test]
fn a_row_added_to_a_table_gets_its_calculated_columns_formula() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/excel-corpus/public/poi/test-data_spreadsheet_ExcelTables.xlsx");
    let mut wb = ncsheet::io::xlsx::load(&path).unwrap_or_else(|e| panic!("{e}")).workbook;
    let src = "Sub Main()\n    Dim lr As ListRow\n    Set lr = ActiveSheet.ListObjects(1).ListRows.Add\n    \
               lr.Range(2) = 123\n    Debug.Print lr.Range(3).Formula; lr.Range(3).Value\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, vec!["=INT(H5/10) 12 "]);
}

/// "ListRow.Delete method" (the row's cells go, the rows below move up), "ListObject.Resize
/// method" ("No cells are inserted or moved"; "The header must remain in the same row"),
/// "ListObjects.Add method" over a range with headers (xlYes = 1: the first row's cells are
/// the column names; the table is named Table1, the first name unused), "ListObject.Name
/// property" (a variable holding the table still reaches it renamed), "ListObject.Unlist
/// method" (the cells stay).
#[test]
fn list_rows_delete_resize_and_list_objects_add_change_the_tables() {
    let (out, wb) = printed_on_tables(
        "    Dim lo As ListObject, nt As ListObject\n    Set lo = Worksheets(\"Parts Data\").ListObjects(1)\n    \
         lo.ListRows(2).Delete\n    Debug.Print lo.Range.Address; lo.ListRows.Count; \" \"; lo.ListRows(2).Range(1)\n    \
         lo.Resize Range(\"A1:G7\")\n    Debug.Print lo.Range.Address; \" \"; lo.ListColumns(7).Name; lo.ListRows.Count\n    \
         On Error Resume Next\n    lo.Resize Range(\"A2:F7\")\n    Debug.Print Err.Number\n    On Error GoTo 0\n    \
         With Worksheets(\"Use\")\n        .Range(\"F1:G1\").Value = Array(\"X\", \"X\"): .Range(\"F2:G3\").Value = 1\n        \
         Set nt = .ListObjects.Add(xlSrcRange, .Range(\"F1:G3\"), , xlYes)\n    End With\n    \
         Debug.Print nt.Name; \" \"; nt.Range.Address; \" \"; nt.ListColumns(2).Name; \" \"; Worksheets(\"Use\").Range(\"G1\")\n    \
         nt.Name = \"Extra\"\n    Debug.Print nt.Name; Worksheets(\"Use\").ListObjects(\"extra\").ListRows.Count\n    \
         nt.Unlist\n    Debug.Print Worksheets(\"Use\").ListObjects.Count; Worksheets(\"Use\").Range(\"G1\")",
    );
    assert_eq!(
        out,
        vec!["$A$1:$F$5 3  c", "$A$1:$G$7 Column1 5 ", " 1004 ", "Table1 $F$1:$G$3 X2 X2", "Extra 2 ", " 0 X2",]
    );
    let tables = wb.table_shapes();
    assert_eq!(tables.len(), 1);
}
