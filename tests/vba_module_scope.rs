//! Module-level names in a project of several standard modules (issue 31, "the project as VBA
//! compiles it"): each module has its own variables and constants, whatever names the others
//! use. The oracles are Microsoft's VBA reference, "Understanding scope and visibility"
//! (module-level variables declared with Dim or Private are "available only to procedures in
//! that module", Public ones "to all procedures in all modules"), "Ambiguous name detected", and
//! [MS-VBAL] 5.6.10 "Simple Name Expressions": a simple name is matched against tiers in order —
//! the procedure's names, then its own module's, then the Public names of the project's other
//! modules — the first tier with a match is chosen, and "if there are 2 or more matches
//! remaining in the selected tier, the simple name expression is invalid". [MS-VBAL] 5.6.12
//! "Member Access Expressions": `Module2.Rate` is the member Rate of the module Module2.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

/// Runs `main` (Module1) with the project's other standard modules (name, source).
fn run_project(main: &str, modules: &[(&str, &str)]) -> Result<RunOutput, MacroError> {
    let mut wb = Workbook::with_sheet();
    let project = modules.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    vba::run(&mut wb, main, "Module1.bas", &RunOptions { project, ..RunOptions::default() })
}

/// What the macro's `Debug.Print`s wrote, line by line.
fn printed(main: &str, modules: &[(&str, &str)]) -> Vec<String> {
    run_project(main, modules).unwrap_or_else(|e| panic!("{e}")).printed
}

/// The error the run stops with.
fn refused(main: &str, modules: &[(&str, &str)]) -> String {
    match run_project(main, modules) {
        Ok(out) => panic!("ran, printing {:?}", out.printed),
        Err(e) => e.to_string(),
    }
}

/// A standard module's source with its name.
fn module(name: &str, body: &str) -> String {
    format!("Attribute VB_Name = \"{name}\"\n{body}")
}

// "Understanding scope and visibility": a Private Const is its module's own, so Module1's
// procedures read "Module1" and Other's read "Other" (Debug.Print joins strings after `;`
// with nothing between).
#[test]
fn a_private_const_of_one_name_in_two_modules_is_each_modules_own() {
    let main =
        "Private Const MODULE_NAME = \"Module1\"\nSub Main()\n    Debug.Print MODULE_NAME; Other.Named\nEnd Sub\n";
    let other = module(
        "Other",
        "Private Const MODULE_NAME = \"Other\"\nFunction Named()\n    Named = MODULE_NAME\nEnd Function\n",
    );
    assert_eq!(printed(main, &[("Other", &other)]), ["Module1Other"]);
}

// "Understanding scope and visibility": a module-level Dim is private to its module: Other's
// procedures count in Other's `counter`, Module1's 10 stays 10 (10 + 0 and 0 + 2 by hand).
#[test]
fn a_dim_of_one_name_in_two_modules_is_two_variables() {
    let main = "Dim counter As Long\nSub Main()\n    counter = 10\n    Other.Bump\n    Bump\n\
                \x20   Debug.Print counter; Other.Count()\nEnd Sub\n";
    let other = module(
        "Other",
        "Dim counter As Long\nSub Bump()\n    counter = counter + 1\nEnd Sub\n\
         Function Count()\n    Count = counter\nEnd Function\n",
    );
    assert_eq!(printed(main, &[("Other", &other)]), [" 10  2 "]);
}

// [MS-VBAL] 5.6.12: `A.Rate` and `B.Rate` are two Public variables, one per module, read and
// assigned through their module's name; each module's own procedures read their own by the
// simple name (5.6.10: the module's tier comes before the other modules').
#[test]
fn a_public_variable_of_one_name_in_two_modules_qualified_by_its_module() {
    let body = "Public Rate As Double\nFunction OwnRate()\n    OwnRate = Rate\nEnd Function\n\
                Sub SetOwn(x)\n    Rate = x\nEnd Sub\n";
    let (a, b) = (module("A", body), module("B", body));
    let main = "Sub Main()\n    A.Rate = 1: B.Rate = 2\n    Debug.Print A.Rate; B.Rate; A.OwnRate(); B.OwnRate()\n\
                \x20   B.SetOwn 5\n    Debug.Print A.Rate; B.Rate\nEnd Sub\n";
    assert_eq!(printed(main, &[("A", &a), ("B", &b)]), [" 1  2  1  2 ", " 1  5 "]);
}

// [MS-VBAL] 5.6.10: Rate, Public in both A and B and declared neither in Main nor in Module1,
// matches twice in the selected tier: the name is invalid — VBA's compile error "Ambiguous name
// detected" ("the identifier conflicts with another identifier or requires qualification"),
// raised where the name is used, so the same project runs when Rate is only used qualified.
#[test]
fn a_public_name_of_two_other_modules_used_unqualified_is_ambiguous() {
    let public = |m: &str| module(m, "Public Rate As Double\n");
    let (a, b) = (public("A"), public("B"));
    let main = "Sub Main()\n    Debug.Print Rate\nEnd Sub\n";
    let error = refused(main, &[("A", &a), ("B", &b)]);
    assert!(error.contains("Ambiguous name detected") && error.contains("Rate"), "{error}");
    assert!(error.contains("A and B"), "{error}");
    let assigned = refused("Sub Main()\n    Rate = 3\nEnd Sub\n", &[("A", &a), ("B", &b)]);
    assert!(assigned.contains("Ambiguous name detected"), "{assigned}");
    let qualified = "Sub Main()\n    A.Rate = 3\n    Debug.Print A.Rate + B.Rate\nEnd Sub\n";
    assert_eq!(printed(qualified, &[("A", &a), ("B", &b)]), [" 3 "]);
}

// [MS-VBAL] 5.6.10: the current module's tier comes before the Public names of the others, so
// Module1's Private Rate shadows Lib's Public Rate in Module1's procedures, while Lib's own
// procedures and a third module that declares no Rate (Other) see Lib's.
#[test]
fn a_private_variable_shadows_another_modules_public_one_of_its_name() {
    let lib = module(
        "Lib",
        "Public Rate As Double\nSub SetRate(x)\n    Rate = x\nEnd Sub\nFunction ReadRate()\n    ReadRate = Rate\nEnd Function\n",
    );
    let other = module("Other", "Function ReadLib()\n    ReadLib = Rate * 10\nEnd Function\n");
    let main = "Private Rate As Double\nSub Main()\n    Rate = 1\n    Lib.SetRate 7\n\
                \x20   Debug.Print Rate; Lib.Rate; Lib.ReadRate(); Other.ReadLib()\nEnd Sub\n";
    assert_eq!(printed(main, &[("Lib", &lib), ("Other", &other)]), [" 1  7  7  70 "]);
}

// "Understanding scope and visibility": a Private module-level variable is not visible to
// another module, so Module1's undeclared `Hidden` (no Option Explicit) is a new, Empty local
// variable of Main ("Dim statement": a variable not declared is a Variant, Empty until
// assigned), not Other's 9.
#[test]
fn another_modules_private_variable_is_not_read_by_its_name() {
    let other = module("Other", "Private Hidden As Long\nSub SetHidden()\n    Hidden = 9\nEnd Sub\n");
    let main = "Sub Main()\n    Other.SetHidden\n    Debug.Print \"[\" & Hidden & \"]\"; IsEmpty(Hidden)\nEnd Sub\n";
    assert_eq!(printed(main, &[("Other", &other)]), ["[]True"]);
}

// "Ambiguous name detected": `MyModule.MyID` names the module-level variable even inside a
// procedure whose local has that name (the page's own example, in Module1), and the local is
// what the simple name reads.
#[test]
fn a_module_qualified_name_reaches_the_module_variable_past_a_local() {
    let main = "Dim MyID As String\nSub Main()\n    Module1.MyID = \"module\"\n    Dim MyID As String\n\
                \x20   MyID = \"local\"\n    Debug.Print MyID; \" \"; Module1.MyID; \" \"; Other.Peek()\nEnd Sub\n";
    let other = module("Other", "Function Peek()\n    Peek = \"-\"\nEnd Function\n");
    assert_eq!(printed(main, &[("Other", &other)]), ["local module -"]);
}

// "Dim statement": `String * length` declares a fixed-length String, whose length may be a
// constant's name; that name is found as any simple name ([MS-VBAL] 5.6.10): Third declares no W, so its `String * W` is Module1's Public W (3),
// not Second's Private W (5), which only Second's procedure reads. Len of a fixed-length
// String is its declared length ("Len function").
#[test]
fn a_fixed_length_reads_the_constant_of_the_module_that_sees_it() {
    let main = "Public Const W = 3\nSub Main()\n    Debug.Print Third.Width(); Second.Own()\nEnd Sub\n";
    let second = module(
        "Second",
        "Private Const W = 5\nFunction Own()\n    Dim t As String * W\n    Own = Len(t)\nEnd Function\n",
    );
    let third = module("Third", "Function Width()\n    Dim t As String * W\n    Width = Len(t)\nEnd Function\n");
    assert_eq!(printed(main, &[("Second", &second), ("Third", &third)]), [" 3  5 "]);
}

// A module-level name is found in a bounded number of hash probes however many modules the
// project has (the macro hot path): 40 modules declare a Private Rate of their own and Lib
// the Public one Module1's loop reads ([MS-VBAL] 5.6.10: none of the 40 is in Module1's
// tiers), so 100,000 reads cost probes in proportion to the reads, not to the modules.
#[test]
fn another_modules_public_name_is_found_without_a_look_at_every_module() {
    let lib = module("Lib", "Public Rate As Double\nSub Init()\n    Rate = 0.5\nEnd Sub\n");
    let privates: Vec<(String, String)> =
        (0..40).map(|i| (format!("M{i}"), module(&format!("M{i}"), "Private Rate As Double\n"))).collect();
    let mut modules: Vec<(&str, &str)> = privates.iter().map(|(n, s)| (n.as_str(), s.as_str())).collect();
    modules.push(("Lib", &lib));
    let main = "Sub Main()\n    Dim i As Long, s As Double\n    Lib.Init\n\
                \x20   For i = 1 To 100000\n        s = s + Rate\n    Next i\n    Debug.Print s\nEnd Sub\n";
    let before = vba::work_done();
    let printed = printed(main, &modules);
    let probes = vba::work_done().name_probes - before.name_probes;
    assert_eq!(printed, [" 50000 "]);
    // About 21 a pass of the loop (i, s and Rate, read and written); a look at each of the 40
    // modules for Rate would add 40 or more.
    assert!(probes < 30 * 100_000, "{probes} probes for 100,000 reads");
}

// [MS-VBAL] 5.2.1.2 "Option Base Directive" and 5.2.1.4 "Option Compare Directive" are module
// directives: each applies to the module it is in. So a module with `Option Base 1` and
// `Option Compare Text` dimensions `Dim b(3)` from 1, makes `Array(1, 2)` from 1 ("Array
// function": the lower bound is set by Option Base of the module where Array is called) and
// compares "a" = "A" True, while Module1, which has neither, keeps 0-based arrays and the
// Binary compare ("a" = "A" False).
#[test]
fn option_base_and_option_compare_apply_to_their_own_module() {
    let main = "Sub Main()\n    Dim a(3)\n    Debug.Print LBound(a); LBound(Array(1, 2)); UBound(Array(1, 2)); (\"a\" = \"A\")\n\
                \x20   Show\n    Debug.Print LBound(a); (\"a\" = \"A\")\nEnd Sub\n";
    let other = module(
        "Other",
        "Option Base 1\nOption Compare Text\nPublic Sub Show()\n    Dim b(3)\n\
         \x20   Debug.Print LBound(b); LBound(Array(1, 2)); UBound(Array(1, 2)); (\"a\" = \"A\")\nEnd Sub\n",
    );
    let out = printed(main, &[("Other", &other)]);
    assert_eq!(out, [" 0  0  1 False", " 1  1  2 True", " 0 False"]);
}

// [MS-VBAL] 5.2.3.2 "Const Declarations": a module constant's value is a constant expression
// whose names are found as any simple name (5.6.10), so Module1's `2 * PI` reads Module2's
// Public PI whatever the order of the modules; a module variable's bounds and `String * W`
// are constant expressions too ("Dim statement"). VBA compiles the declarations by what they
// read, not by their place: 2 × 3.14159 = 6.28318 by hand, UBound 4 for `1 To N` and `(N)`,
// Len 7 for a String * 7 ("Len function": a fixed-length String's declared length).
#[test]
fn module_declarations_read_the_constants_of_a_later_module() {
    let main = "Private Const TWO_PI = 2 * PI\nDim arr(1 To N) As Double\nPrivate buf(N) As Double\n\
                Dim s As String * W\nSub Main()\n    Debug.Print TWO_PI; UBound(arr); UBound(buf); Len(s)\nEnd Sub\n";
    let later = module("Module2", "Public Const PI = 3.14159\nPublic Const N = 4\nPublic Const W = 7\n");
    assert_eq!(printed(main, &[("Module2", &later)]), [" 6.28318  4  4  7 "]);
}

// "Circular dependencies between modules" (VBA's compile error; [MS-VBAL] 5.2.4's static
// semantics: no circular reference through Const declarations): A reads B, which reads A, is
// refused naming both constants and their modules, where it computed a number before.
#[test]
fn constants_computed_from_each_other_are_refused_naming_them() {
    let main = "Public Const A = B + 1\nSub Main()\n    Debug.Print A\nEnd Sub\n";
    let other = module("Module2", "Public Const B = A + 1\n");
    let error = refused(main, &[("Module2", &other)]);
    assert!(error.contains("Circular dependencies"), "{error}");
    assert!(error.contains("A (Module1)") && error.contains("B (Module2)"), "{error}");
    let itself = refused("Const C = 2 * C\nSub Main()\n    Debug.Print C\nEnd Sub\n", &[]);
    assert!(itself.contains("the constant C needs itself"), "{itself}");
}

// [MS-VBAL] 5.2.1.3 "Option Explicit Directive": it sets "the variable declaration mode" of
// "the containing module"; a module without it is in implicit-mode ("Option Explicit
// statement": "used at the module level to force explicit declaration of all variables in that
// module"). So Module1's Option Explicit does not stop Other's undeclared `n` (3 * 2 = 6,
// printed as " 6 ": "Print method", a number has a leading and a trailing space), and Other's Option Explicit does not stop Module1's undeclared
// `k`, while Other's own undeclared `m` is still a compile error that names it.
#[test]
fn option_explicit_applies_to_its_own_module() {
    let main = "Option Explicit\nSub Main()\n    Show\nEnd Sub\n";
    let other = module("Other", "Public Sub Show()\n    n = 3\n    Debug.Print n * 2\nEnd Sub\n");
    assert_eq!(printed(main, &[("Other", &other)]), [" 6 "]);

    let main = "Sub Main()\n    k = 4\n    Debug.Print k + Twice(1)\nEnd Sub\n";
    let other = module(
        "Other",
        "Option Explicit\nPublic Function Twice(x)\n    Twice = 2 * x\nEnd Function\n\
         Public Sub Careless()\n    m = 1\nEnd Sub\n",
    );
    assert_eq!(printed(main, &[("Other", &other)]), [" 6 "]);
    let main = "Sub Main()\n    Careless\nEnd Sub\n";
    let error = refused(main, &[("Other", &other)]);
    assert!(error.contains("variable m is not declared"), "{error}");
}
