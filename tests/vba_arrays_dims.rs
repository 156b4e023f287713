//! Issue 31: arrays of three dimensions and more, up to VBA's 60, and the array syntax VBA
//! allows around them. Each expected value is worked by hand from Microsoft's VBA language
//! reference (learn.microsoft.com, "Office VBA language reference", the page named at each
//! test) or the language specification [MS-VBAL], never from our own earlier output; where
//! LibreOffice Basic in VBA mode (`Option VBASupport 1`) was run on the same macro, it gave
//! the same lines.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run_result(src: &str) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", &RunOptions::default())
}

/// What `Debug.Print` printed, one line each, without the spaces around a number.
fn printed(src: &str) -> Vec<String> {
    let out = run_result(src).unwrap_or_else(|e| panic!("{e}"));
    out.printed.iter().map(|l| l.trim().to_string()).collect()
}

// "Dim statement": subscripts declare "the dimensions of an array variable; up to 60 multiple
// dimensions may be declared", each `lower To upper`; "LBound function" / "UBound function":
// the bound of the dimension the second argument names, 1 for the first. Each item is set to
// i*100 + j*10 + k, so a(2, 3, 1) = 231, a(3, 4, 2) = 342, a(1, 1, 0) = 110. TypeName of an
// array of Long is "Long()" ("TypeName function": "a string followed by empty parentheses").
#[test]
fn a_three_dimensional_array_holds_its_items_and_answers_each_dimensions_bounds() {
    let out = printed(
        "Sub Main()\n    Dim a(1 To 3, 1 To 4, 0 To 2) As Long, i, j, k\n\
         \x20   For i = 1 To 3: For j = 1 To 4: For k = 0 To 2\n\
         \x20       a(i, j, k) = i * 100 + j * 10 + k\n    Next: Next: Next\n\
         \x20   Debug.Print a(2, 3, 1) & \",\" & a(3, 4, 2) & \",\" & a(1, 1, 0)\n\
         \x20   Debug.Print LBound(a, 1) & \",\" & UBound(a, 1) & \",\" & LBound(a, 2) & \",\" & UBound(a, 2) & \",\" & LBound(a, 3) & \",\" & UBound(a, 3)\n\
         \x20   Debug.Print TypeName(a) & \",\" & IsArray(a) & \",\" & UBound(a)\nEnd Sub\n",
    );
    assert_eq!(out, ["231,342,110", "1,3,1,4,0,2", "Long(),True,3"]);
}

// "Subscript out of range (Error 9)": "You referenced a nonexistent array element" — an index
// past its dimension's bounds, or a dimension past the array's rank given to LBound/UBound.
#[test]
fn an_index_or_a_dimension_outside_a_three_dimensional_array_is_error_9() {
    let out = printed(
        "Sub Main()\n    Dim a(1 To 2, 1 To 2, 1 To 2), x\n    On Error Resume Next\n\
         \x20   x = a(1, 3, 1)\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   x = UBound(a, 4)\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   Dim b(1 To 5)\n    x = LBound(b, 2)\n    Debug.Print Err.Number\nEnd Sub\n",
    );
    assert_eq!(out, ["9", "9", "9"]);
}

// For Each goes through an array in VBA's memory order, the first index varying fastest
// (VBA lays arrays out column-major; "ReDim statement": that is why only the last dimension
// can be resized with Preserve). LibreOffice in VBA mode gives the same two lines. With
// a(i, j) = 10i + j over 1 To 2 × 1 To 3: 11, 21, 12, 22, 13, 23; with b(i, j, k) = 100i +
// 10j + k over 1 To 2 × 0 To 1 × 1 To 2: 101, 201, 111, 211, 102, 202, 112, 212.
#[test]
fn for_each_goes_through_an_array_first_index_fastest() {
    let out = printed(
        "Sub Main()\n    Dim a(1 To 2, 1 To 3), b(1 To 2, 0 To 1, 1 To 2), i, j, k, x, s\n\
         \x20   For i = 1 To 2: For j = 1 To 3: a(i, j) = i * 10 + j: Next: Next\n\
         \x20   For Each x In a: s = s & x & \",\": Next\n    Debug.Print s\n    s = \"\"\n\
         \x20   For i = 1 To 2: For j = 0 To 1: For k = 1 To 2: b(i, j, k) = i * 100 + j * 10 + k: Next: Next: Next\n\
         \x20   For Each x In b: s = s & x & \",\": Next\n    Debug.Print s\nEnd Sub\n",
    );
    assert_eq!(out, ["11,21,12,22,13,23,", "101,201,111,211,102,202,112,212,"]);
}

// "ReDim statement": "If you use the Preserve keyword, you can resize only the last array
// dimension and you can't change the number of dimensions at all"; "when you use Preserve,
// you can change the size of the array only by changing the upper bound; changing the lower
// bound causes an error" (Subscript out of range, error 9). The items kept keep their values,
// the new ones are the type's default (0 for Double).
#[test]
fn redim_preserve_resizes_only_the_last_dimensions_upper_bound() {
    let out = printed(
        "Sub Main()\n    Dim c() As Double\n    ReDim c(1 To 2, 1 To 2, 1 To 2)\n\
         \x20   c(2, 1, 2) = 5: c(1, 2, 1) = 7\n    ReDim Preserve c(1 To 2, 1 To 2, 1 To 4)\n\
         \x20   Debug.Print c(2, 1, 2) & \",\" & c(1, 2, 1) & \",\" & c(2, 2, 4) & \",\" & UBound(c, 3) & \",\" & TypeName(c)\n\
         \x20   On Error Resume Next\n\
         \x20   ReDim Preserve c(1 To 3, 1 To 2, 1 To 4)\n    Debug.Print Err.Number & \",\" & UBound(c, 1)\n    Err.Clear\n\
         \x20   ReDim Preserve c(1 To 2, 1 To 2, 0 To 4)\n    Debug.Print Err.Number & \",\" & LBound(c, 3)\n    Err.Clear\n\
         \x20   ReDim Preserve c(1 To 2, 1 To 8)\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   Dim m()\n    ReDim m(1 To 2, 1 To 2)\n    ReDim Preserve m(1 To 3, 1 To 2)\n    Debug.Print Err.Number & \",\" & UBound(m, 1)\n\
         \x20   Err.Clear\n    ReDim c(0 To 1, 0 To 1, 0 To 1)\n    Debug.Print Err.Number & \",\" & UBound(c, 1) & c(1, 1, 1)\nEnd Sub\n",
    );
    assert_eq!(out, ["5,7,0,4,Double()", "9,2", "9,1", "9", "9,2", "0,10"]);
}

// [MS-VBAL] 5.3.1.5: a Function's result is the value of its name's variable, an array with
// its bounds; a parameter declared `x() As Long` takes the caller's array whole, ByRef by
// default ("Sub statement": "ByRef … the default in VBA"), so Bump's change is the caller's.
// Items 1..8 sum to 36; a(1, 1, 1) = 1 becomes 2; Fill3(3) is 1 To 3, 1 To 2, 0 To 1.
#[test]
fn a_three_dimensional_array_goes_to_and_comes_back_from_procedures() {
    let out = printed(
        "Function Fill3(n As Long) As Variant\n    Dim t()\n    ReDim t(1 To n, 1 To 2, 0 To 1)\n\
         \x20   t(n, 2, 1) = \"last\"\n    Fill3 = t\nEnd Function\n\
         Function Total(x() As Long) As Long\n    Dim v\n    For Each v In x: Total = Total + v: Next\nEnd Function\n\
         Sub Bump(x() As Long)\n    x(1, 1, 1) = x(1, 1, 1) + 1\nEnd Sub\n\
         Sub Main()\n    Dim a(1 To 2, 1 To 2, 1 To 2) As Long, i, j, k, n, w\n\
         \x20   For i = 1 To 2: For j = 1 To 2: For k = 1 To 2: n = n + 1: a(i, j, k) = n: Next: Next: Next\n\
         \x20   Debug.Print Total(a)\n    Bump a\n    Debug.Print a(1, 1, 1)\n\
         \x20   w = Fill3(3)\n    Debug.Print UBound(w, 1) & \",\" & LBound(w, 3) & \",\" & UBound(w, 3) & \",\" & w(3, 2, 1)\n\
         \x20   Dim b\n    b = a\n    b(2, 2, 2) = 0\n    Debug.Print a(2, 2, 2) & \",\" & b(2, 2, 2) & \",\" & UBound(b, 3)\nEnd Sub\n",
    );
    assert_eq!(out, ["36", "2", "3,0,1,last", "8,0,2"]);
}

// Items of three-dimensional arrays of a Type, of objects and of Variants: "Type statement"
// (an array of a user-defined type, each item its own record), "Set statement" (an item of
// an array of Object holds a reference; an item never set is Nothing), [MS-VBAL] 2.2 (a
// Variant item holds an array, indexed again with a second list: `v(1, 2, 1)(1)` is the
// second item of Array(4, 5), 5).
#[test]
fn three_dimensional_arrays_of_types_objects_and_variants() {
    let out = printed(
        "Type TPt\n    x As Double\n    tag As String\nEnd Type\n\
         Sub Main()\n    Dim p(0 To 1, 0 To 1, 0 To 1) As TPt\n\
         \x20   p(1, 0, 1).x = 2.5\n    p(1, 0, 1).tag = \"q\"\n\
         \x20   Debug.Print p(1, 0, 1).x & p(1, 0, 1).tag & \",\" & p(0, 0, 0).x & \",\" & p(1, 1, 1).tag & \"|\"\n\
         \x20   Dim o(1 To 2, 1 To 2, 1 To 2) As Object\n    Set o(2, 1, 2) = New Collection\n\
         \x20   o(2, 1, 2).Add 5\n    Debug.Print o(2, 1, 2).Count & \",\" & (o(1, 1, 1) Is Nothing)\n\
         \x20   Dim v(1 To 2, 1 To 2, 1 To 2)\n    v(1, 2, 1) = Array(4, 5)\n    v(2, 2, 2) = \"s\"\n\
         \x20   Debug.Print v(1, 2, 1)(1) & \",\" & v(2, 2, 2) & \",\" & IsEmpty(v(1, 1, 1)) & \",\" & TypeName(v)\nEnd Sub\n",
    );
    assert_eq!(out, ["2.5q,0,|", "1,True", "5,s,True,Variant()"]);
}

// "Erase statement": for a fixed-size array, Erase sets each item of a numeric array to zero
// and of a Variant array to Empty; the array keeps its dimensions.
#[test]
fn erase_empties_a_three_dimensional_array_and_keeps_its_bounds() {
    let out = printed(
        "Sub Main()\n    Dim a(1 To 2, 1 To 3, 0 To 1) As Long, v(1 To 2, 1 To 2, 1 To 2)\n\
         \x20   a(2, 3, 1) = 7: v(2, 2, 2) = \"x\"\n    Erase a, v\n\
         \x20   Debug.Print a(2, 3, 1) & \",\" & UBound(a, 2) & \",\" & UBound(a, 3) & \",\" & IsEmpty(v(2, 2, 2))\nEnd Sub\n",
    );
    assert_eq!(out, ["0,3,1,True"]);
}

// "Erase statement": "Erase frees the memory used by dynamic arrays. Before your program can
// refer to the dynamic array again, it must redeclare the array variable's dimensions by using
// a ReDim statement." A freed array has no bounds, so UBound and an item of it are "Subscript
// out of range (Error 9)" until ReDim gives new ones; a fixed-size array beside it keeps its
// bounds. Holds for a typed (Long), a Variant and a Type dynamic array alike.
#[test]
fn erase_frees_a_dynamic_array_until_redim_gives_it_bounds_again() {
    let out = printed(
        "Type TPoint\n    x As Double\nEnd Type\n\
         Sub Main()\n    Dim a() As Long, v(), p() As TPoint, f(1 To 4) As Long\n\
         \x20   ReDim a(5): ReDim v(1 To 3): ReDim p(2)\n    a(2) = 7: v(2) = \"x\": p(1).x = 1.5: f(4) = 3\n\
         \x20   Erase a, v, p, f\n    On Error Resume Next\n\
         \x20   Debug.Print UBound(a): Debug.Print Err.Number: Err.Clear\n\
         \x20   Debug.Print a(2): Debug.Print Err.Number: Err.Clear\n\
         \x20   Debug.Print UBound(v): Debug.Print Err.Number: Err.Clear\n\
         \x20   Debug.Print UBound(p): Debug.Print Err.Number: Err.Clear\n\
         \x20   On Error GoTo 0\n\
         \x20   Debug.Print UBound(f) & \",\" & f(4)\n\
         \x20   ReDim a(2): ReDim v(0): ReDim p(1)\n\
         \x20   Debug.Print a(2) & \",\" & UBound(a) & \",\" & IsEmpty(v(0)) & \",\" & p(1).x\nEnd Sub\n",
    );
    // With Resume Next, a failing Debug.Print prints nothing: only Err.Number shows.
    assert_eq!(out, ["9", "9", "9", "9", "4,0", "0,2,True,0"]);
}

// A worksheet's range holds rows and columns: Excel's "Range.Value property" takes a value or
// a two-dimensional array. A three-dimensional array has no such layout, so writing one is a
// type mismatch (error 13, "Type mismatch (Error 13)": "the variable or property isn't of the
// correct type"), never its items written flattened.
#[test]
fn writing_a_three_dimensional_array_to_a_range_is_a_type_mismatch() {
    let mut wb = Workbook::with_sheet();
    let src = "Sub Main()\n    Dim a(1 To 2, 1 To 2, 1 To 2)\n    a(1, 1, 1) = 1\n    On Error Resume Next\n\
               \x20   Range(\"A1:B2\").Value = a\n    Debug.Print Err.Number\n    Err.Clear\n\
               \x20   Range(\"A1:B2\") = a\n    Debug.Print Err.Number\nEnd Sub\n";
    let out = vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let printed: Vec<&str> = out.printed.iter().map(|l| l.trim()).collect();
    assert_eq!(printed, ["13", "13"]);
    let sheet = wb.active_sheet();
    assert!(wb.value(sheet, ncsheet::formula::address::Pos::new(0, 0)).is_blank(), "nothing written to A1");
}

// "Dim statement": "up to 60 multiple dimensions may be declared". Sixty dimensions of one
// item each hold one item; sixty-one are refused with VBA's own message (a compile error in
// VBA, "Too many dimensions"), naming the line (`Module1.bas:2:…`).
#[test]
fn sixty_dimensions_are_allowed_and_sixty_one_are_refused() {
    let dims = |n: usize| vec!["1 To 1"; n].join(", ");
    let ones = vec!["1"; 60].join(", ");
    let src = format!(
        "Sub Main()\n    Dim z({})\n    z({ones}) = 42\n    Debug.Print z({ones}) & \",\" & UBound(z, 60)\nEnd Sub\n",
        dims(60)
    );
    assert_eq!(printed(&src), ["42,1"]);
    let src = format!("Sub Main()\n    Dim y({})\nEnd Sub\n", dims(61));
    let err = run_result(&src).expect_err("61 dimensions").to_string();
    assert!(err.contains("Module1.bas:2:") && err.contains("Too many dimensions: 61"), "{err}");
}

// "Array function": Array returns "a Variant containing an array"; an item of a Variant holds
// an object as a reference ([MS-VBAL] 2.2, 5.4.3.9 "Set Statement"), so `Array(c)` holds the
// Collection itself: adding to `a(0)` adds to `c` (Count 2), and `a(0) Is c` is True. The
// plain item 7 keeps its Integer type ("Variant data type").
#[test]
fn array_of_an_object_holds_the_object_reference() {
    let out = printed(
        "Sub Main()\n    Dim c As New Collection, a\n    c.Add 1\n    a = Array(c, 7)\n\
         \x20   a(0).Add 2\n    Debug.Print c.Count & \",\" & (a(0) Is c) & \",\" & TypeName(a(1)) & \",\" & UBound(a)\n\
         \x20   Dim x\n    For Each x In Array(c)\n        Debug.Print x.Count\n    Next\nEnd Sub\n",
    );
    assert_eq!(out, ["2,True,Integer,1", "2"]);
}

// "Array function": "The lower bound of an array created by using the Array function is
// determined by the lower bound specified with the Option Base statement, unless Array is
// qualified with the name of the type library (for example VBA.Array). If qualified with the
// type-library name, Array is unaffected by Option Base." Under Option Base 1, Array(5, 6) is
// 1 To 2 and VBA.Array(5, 6) is 0 To 1, its item 0 the 5.
#[test]
fn vba_array_is_zero_based_whatever_option_base_says() {
    let out = printed(
        "Option Base 1\nSub Main()\n    Dim a, b\n    a = Array(5, 6)\n    b = VBA.Array(5, 6)\n\
         \x20   Debug.Print LBound(a) & \",\" & UBound(a) & \",\" & LBound(b) & \",\" & UBound(b) & \",\" & b(0) & \",\" & TypeName(b(1))\nEnd Sub\n",
    );
    assert_eq!(out, ["1,2,0,1,5,Integer"]);
}

// "ReDim statement": ReDim "reallocate[s] storage space for dynamic array variables", which
// includes a dynamic array field of a user-defined type, here of an item of an array of the
// Type ("Type statement"). Item i gets v(1 To i) with v(i) = 1.5i: UBound(pts(1).v) = 1,
// UBound(pts(3).v) = 3, pts(3).v(3) = 4.5; ReDim Preserve keeps pts(2).v(2) = 3 at 1 To 4.
#[test]
fn redim_sizes_the_array_field_of_an_item_of_an_array_of_a_type() {
    let out = printed(
        "Type TPath\n    n As Long\n    v() As Double\nEnd Type\n\
         Sub Main()\n    Dim pts(1 To 3) As TPath, i\n    For i = 1 To 3\n\
         \x20       ReDim pts(i).v(1 To i)\n        pts(i).v(i) = i * 1.5\n    Next\n\
         \x20   ReDim Preserve pts(2).v(1 To 4)\n\
         \x20   Debug.Print UBound(pts(1).v) & \",\" & UBound(pts(3).v) & \",\" & pts(3).v(3) & \",\" & UBound(pts(2).v) & \",\" & pts(2).v(2)\nEnd Sub\n",
    );
    assert_eq!(out, ["1,3,4.5,4,3"]);
}

// [MS-VBAL] 5.6.13.1 "Index Expressions": an index expression on a variable's array names the
// element as a variable, and on a Variant item holding an array names that array's element;
// 5.6.12 "Member Access Expressions": a member of a UDT variable names its field. So
// `A(1).Arr(2)(3) = 99` changes item 3 of the array held by item 2 of A(1)'s field Arr:
// Array(10, 20, 30, 40) is 0 To 3 ("Array function", Option Base 0), its item 3 becomes 99,
// item 2 stays 30. The same through a Type variable: p.Arr(1)(0) = "x" over Array(1, 2).
#[test]
fn an_item_is_assigned_through_a_chain_of_indexes_and_type_fields() {
    let out = printed(
        "Type TBox\n    Arr() As Variant\nEnd Type\n\
         Sub Main()\n    Dim A(1 To 2) As TBox, inner\n    ReDim A(1).Arr(1 To 3)\n\
         \x20   inner = Array(10, 20, 30, 40)\n    A(1).Arr(2) = inner\n    A(1).Arr(2)(3) = 99\n\
         \x20   Debug.Print A(1).Arr(2)(3) & \",\" & A(1).Arr(2)(2) & \",\" & UBound(A(1).Arr(2)) & \",\" & inner(3)\n\
         \x20   Dim p As TBox\n    ReDim p.Arr(0 To 1)\n    p.Arr(1) = Array(1, 2)\n    p.Arr(1)(0) = \"x\"\n\
         \x20   Debug.Print p.Arr(1)(0) & p.Arr(1)(1)\nEnd Sub\n",
    );
    assert_eq!(out, ["99,30,3,40", "x2"]);
}
