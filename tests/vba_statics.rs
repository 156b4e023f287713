//! Static variables as VBA keeps them (issue 31, scope 1): "Static statement" (VBA
//! reference): "In class modules, variables declared with the Static statement retain their
//! value in each class instance until that instance is destroyed", where a standard
//! module's keep theirs for the procedure as long as the code runs.

use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

/// `main` run with the class modules `classes` (name, source), printing what it printed.
fn printed_with_class(main: &str, classes: &[(&str, &str)]) -> Vec<String> {
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    let mut wb = Workbook::with_sheet();
    let options = RunOptions { classes, ..RunOptions::default() };
    vba::run(&mut wb, main, "test.bas", &options).unwrap_or_else(|e| panic!("{e}")).printed
}

/// A class whose method counts its calls in a Static variable, in a `Static Function` (all
/// its locals static) and in a Private module-level variable of the instance.
const COUNTER: &str = "Private n As Long\n\
    Public Function Bump() As Long\n    Static calls As Long\n    calls = calls + 1\n    n = n + 1\n    Bump = n * 100 + calls\nEnd Function\n\
    Public Static Function Tally() As Long\n    Dim t As Long\n    t = t + 1\n    Tally = t\nEnd Function\n";

/// Each object keeps its own Static variables: `b`'s first call sees its own count, 1, not
/// the 3 the other object's calls made; an object made later starts again from 0 even when
/// an earlier one is gone.
#[test]
fn a_class_methods_static_variable_is_kept_per_object() {
    let main = "Sub Main()\n    Dim a As New Counter, b As New Counter, c As Counter\n\
        \x20   Debug.Print a.Bump(); a.Bump(); b.Bump(); a.Tally(); a.Tally(); b.Tally()\n\
        \x20   Set a = Nothing\n    Set c = New Counter\n    Debug.Print c.Bump(); c.Tally()\nEnd Sub\n";
    let printed = printed_with_class(main, &[("Counter", COUNTER)]);
    assert_eq!(printed, [" 101  202  101  1  2  1 ", " 101  1 "]);
}
