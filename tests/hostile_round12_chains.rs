//! Hostile input (issue 30), session 26, the macro half of tests/hostile_round12.rs:
//! variants of the classes that no earlier round named, found by a reviewer's run of
//! its own (helper h3's table of about 1,200 attacks). What each test expects comes from
//! outside our code: the MS-VBAL specification, quoted where it is used.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run(src: &str) -> Result<RunOutput, MacroError> {
    vba::run(&mut Workbook::with_sheet(), src, "round12.bas", &RunOptions::default())
}

fn printed(src: &str) -> Vec<String> {
    run(src).unwrap_or_else(|e| panic!("{e}")).printed
}

/// Runs `f` on a thread with the 2 MiB stack Rust gives a test thread, so that a value let go
/// through nested drops shows as an overflow here as it did in the CLI's macro thread.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new().stack_size(2 << 20).spawn(f).unwrap().join().unwrap()
}

/// [MS-VBAL] 2.2: a Variant holds an array, and an array of Variants holds Variants, so an
/// array may hold an array to any depth (`a = Array(a)`). Such a chain, a Collection holding
/// an array holding the next Collection, and an object whose field holds an array holding the
/// next object are let go one link after another: each was dropped inside the one holding it,
/// and 200,000 links overflowed the native stack after the macro had finished ("fatal runtime
/// error: stack overflow", exit 134; a 2,000,000-link chain in `ncsheet run` did the same).
#[test]
fn chains_of_arrays_within_arrays_are_let_go_without_the_native_stack() {
    let chains = [
        ("Dim a, i\na = Array(1)\nFor i = 1 To 200000\n    a = Array(a)\nNext\nDebug.Print IsArray(a(0)(0))", "True"),
        (
            "Dim c As Collection, n As Collection, i\nSet c = New Collection\nFor i = 1 To 200000\n\
             \x20   Set n = New Collection\n    n.Add Array(c)\n    Set c = n\nNext\nDebug.Print c.Count",
            " 1 ",
        ),
        ("Dim a(0 To 0), b, i\nFor i = 1 To 200000\n    b = a\n    a(0) = b\nNext\nDebug.Print UBound(a(0)(0))", " 0 "),
    ];
    for (body, expected) in chains {
        let src = format!("Sub Main()\n{body}\nEnd Sub\n");
        let out = on_small_stack(move || printed(&src));
        assert_eq!(out, [expected], "{body}");
    }
}

/// [MS-VBAL] 5.2.3.4: an Enum member without a value is "one greater than the value of the
/// preceding enum member", the first 0. Each such member was built as the expression of the
/// one before plus 1, so the k-th was k deep: 100,000 members took 5 billion expression nodes
/// and aborted at a 4 GiB cap (20,000 take 200 million). Now each is the last given value plus
/// a count: a number, or that member by name plus the count.
#[test]
fn an_enum_of_many_members_is_declared_in_linear_size() {
    let members: String = (0..20_000).map(|i| format!("    M{i}\n")).collect();
    let src = format!(
        "Enum Big\n{members}End Enum\nEnum Given\n    G0 = 7\n    G1\n    G2 = Big.M3 * 2\n    G3\n    G4\nEnd Enum\n\
         Sub Main()\nDebug.Print M19999; G1; G2; G4\nEnd Sub\n"
    );
    assert_eq!(printed(&src), [" 19999  8  6  8 "]);
}

/// "Array function" and [MS-VBAL] 5.6.13.1: an index is a Long. One far past any bounds
/// (`a(-9.2E+18)`, near a 64-bit integer's end) is run-time error 9, "Subscript out of range",
/// as `a(3000000000#)` already was, trappable by On Error: it panicked on an overflow in the
/// subtraction of the lower bound ("attempt to subtract with overflow").
#[test]
fn an_index_near_the_ends_of_a_64_bit_integer_is_out_of_range() {
    let src = "Sub Main()\nDim a(1 To 2), b(1 To 2, 1 To 2)\nOn Error Resume Next\n\
               Debug.Print a(-9223372036854775807#)\nDebug.Print Err.Number\nErr.Clear\n\
               Debug.Print b(1, 9.2E+18)\nDebug.Print Err.Number\nErr.Clear\n\
               Debug.Print a(3000000000#)\nDebug.Print Err.Number\nEnd Sub\n";
    let out = printed(src);
    let numbers: Vec<&str> = out.iter().map(|l| l.trim()).filter(|l| !l.is_empty()).collect();
    assert_eq!(numbers, ["9", "9", "9"], "{out:?}");
}
