//! Variables used without a declaration in a module with `Def…` directives (issue 31). The
//! oracles: [MS-VBAL] 5.2.2 "Implicit Definition Directives" (a variable implicitly declared
//! by its first use takes the declared type the directive gives its first letter) and
//! Microsoft's VBA reference, "Deftype statements" (the directive sets "the default data type
//! for variables … whose names start with the specified characters", its example making the
//! undeclared `Message` of `DefStr A-Q` a String), "Integer data type" (-32,768 to 32,767)
//! and "Overflow (Error 6)".

use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

fn printed(src: &str) -> Vec<String> {
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, src, "Module1.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}")).printed
}

// An undeclared For counter under `DefInt I-N` is an Integer: 4 after `For i = 1 To 3`, and
// 40000, past 32,767, is error 6; `k`, never assigned, is an Integer's 0, not an Empty "".
#[test]
fn an_undeclared_for_counter_takes_the_def_type() {
    let src = "DefInt I-N\nSub Main()\n    For i = 1 To 3\n    Next\n    Debug.Print i; TypeName(i); k\n\
               \x20   On Error Resume Next\n    i = 40000\n    Debug.Print Err.Number; i\nEnd Sub\n";
    assert_eq!(printed(src), [" 4 Integer 0 ", " 6  4 "]);
}

// An undeclared variable first passed ByRef: `j` is an Integer, so it may be given to a
// `ByRef x As Integer` ("ByRef argument type mismatch" only when the types differ), and the
// 1.7 assigned through x is rounded to 2 as an Integer ("Type conversion functions": CInt).
// `ReDim` of an undeclared name declares an array of the directive's type ("ReDim
// statement"; TypeName gives the element type and "()").
#[test]
fn an_undeclared_byref_argument_and_redim_take_the_def_type() {
    let src = "DefInt J-N\nSub Main()\n    Bump j\n    ReDim nums(2)\n    nums(1) = 2.6\n\
               \x20   Debug.Print j; TypeName(j); nums(1); TypeName(nums)\nEnd Sub\n\
               Sub Bump(ByRef x As Integer)\n    x = x + 1.7\nEnd Sub\n";
    assert_eq!(printed(src), [" 2 Integer 3 Integer()"]);
}

// "Deftype statements": `DefStr A-Q` makes `Message`, assigned without a declaration, a
// String, so the number 12 assigned to it is the text "12" (TypeName "String").
#[test]
fn an_undeclared_assigned_variable_takes_the_def_type() {
    let src =
        "DefStr A-Q\nSub Main()\n    Message = 12\n    Debug.Print TypeName(Message); \"|\"; Message; \"|\"\nEnd Sub\n";
    assert_eq!(printed(src), ["String|12|"]);
}
