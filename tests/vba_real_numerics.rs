//! Constructs found by real public engineering modules (issue 31, session 20's sample: a
//! steel-section class with its errors class, a Brent root finder class, spline and channel-flow
//! UDFs), each in a small macro of our own with the result Microsoft's VBA language reference
//! or [MS-VBAL] (the page or section named at each test) gives.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

/// Runs `main` with the project's class modules (name, source).
fn run_with_classes(main: &str, classes: &[(&str, &str)]) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    vba::run(&mut wb, main, "Module1.bas", &RunOptions { classes, ..RunOptions::default() })
}

// [MS-VBAL] 5.3.1.4 "Property Declarations": a Property Get and a Property Let of one name are
// two procedures, the Let with one parameter more, its value. VBA compiles a procedure when it
// is first called here (ncsheet's rule, issue 31), so a Let whose body does not compile (an
// undeclared variable under Option Explicit, "Option Explicit statement": "an error occurs at
// compile time") fails with that error when `r.W = 4` calls it, naming the variable; its Get
// still runs (a Double's 0 printed " 0 ", "Print method").
#[test]
fn a_property_let_that_does_not_compile_fails_with_its_own_error() {
    let class = "Option Explicit\nPrivate mW As Double\nPublic Property Get W() As Double\n    W = mW\nEnd Property\n\
                 Public Property Let W(v As Double)\n    tmp = v\n    mW = tmp\nEnd Property\n";
    let main = "Sub Main()\n    Dim r As New Rect\n    Debug.Print r.W\n    r.W = 4\nEnd Sub\n";
    let error = match run_with_classes(main, &[("Rect", class)]) {
        Ok(out) => panic!("ran, printing {:?}", out.printed),
        Err(e) => e,
    };
    assert_eq!(error.output.printed, [" 0 "]);
    let message = error.to_string();
    assert!(message.contains("variable tmp is not declared"), "{message}");
}

/// A macro run alone, printing.
fn printed(main: &str) -> Vec<String> {
    run_with_classes(main, &[]).unwrap_or_else(|e| panic!("{e}")).printed
}

// [MS-VBAL] 5.6.13.1 "Index Expressions": an index applied to a Variant holding an array is an
// index into that array, and a Type's field declared Variant ("Type statement": any data type)
// is such a Variant. So `This.Arr(1)` and `.Arr(1)` inside `With This` read item 1 of
// Array(10, 20, 30) (20; UBound 2), `.Arr(2) = 5` replaces item 2, 5 + 10 = 15; numbers print
// with a leading and a trailing space ("Print method").
#[test]
fn a_variant_field_of_a_type_holding_an_array_is_indexed() {
    let main = "Private Type TBox\n    Arr As Variant\n    n As Long\nEnd Type\nPrivate This As TBox\n\
                Sub Main()\n    This.Arr = Array(10, 20, 30)\n    With This\n        Debug.Print .Arr(1); UBound(.Arr)\n\
                \x20       .Arr(2) = 5\n    End With\n    Debug.Print This.Arr(2) + This.Arr(0)\nEnd Sub\n";
    assert_eq!(printed(main), [" 20  2 ", " 15 "]);
}
