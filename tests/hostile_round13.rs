//! Hostile input (issue 30), session 34: variants found by helper h5's round of about 450
//! attacks of its own (/tmp/h5/s34/round.md) that no earlier round named. Each test bounds
//! the work by a counted budget (the memory budget, the statement limit, a parse limit),
//! never by time; what a value must be comes from the MS-VBAL specification and Microsoft's
//! VBA reference, cited where used.

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run_with(src: &str, options: &RunOptions) -> Result<RunOutput, MacroError> {
    vba::run(&mut Workbook::with_sheet(), src, "round13.bas", options)
}

fn refused(src: &str, options: &RunOptions) -> String {
    match run_with(src, options) {
        Ok(out) => panic!("ran to its end, printing {:?}", out.printed),
        Err(e) => e.to_string(),
    }
}

/// A memory budget of 16 MiB, small enough that a test stays small.
fn small_memory() -> RunOptions {
    RunOptions { max_memory: 16 << 20, ..RunOptions::default() }
}

/// [MS-VBAL] 5.5.1.2 (Let-coercion to String * length): a fixed-length string holds exactly
/// its length, a shorter text padded with spaces, so `a(i) = "x"` into a `String * 65000`
/// holds 65,000 characters. The store was charged as the one character given: 100,000 such
/// stores held 6.5 GB uncounted and aborted at a 4 GiB cap, in an array's items, a Type's
/// field and a class's field alike. 1,000 stores of 65,000 characters are 62 MiB, past a
/// budget of 16 MiB.
#[test]
fn fixed_length_strings_are_charged_the_length_they_hold() {
    let padded =
        "Sub Main()\nDim a(1 To 2) As String * 65000\na(1) = \"x\"\nDebug.Print Len(a(1)); Len(a(2))\nEnd Sub\n";
    assert_eq!(run_with(padded, &RunOptions::default()).unwrap().printed, [" 65000  65000 "]);
    let items = "Sub Main()\nDim a(1 To 1000) As String * 65000, i As Long\n\
                 For i = 1 To 1000\na(i) = \"x\"\nNext\nEnd Sub\n";
    let fields = "Type T\ns As String * 65000\nEnd Type\nSub Main()\nDim a(1 To 1000) As T, i As Long\n\
                  For i = 1 To 1000\na(i).s = \"x\"\nNext\nEnd Sub\n";
    let field_items = "Type T\ns(1 To 1000) As String * 65000\nEnd Type\nSub Main()\nDim r As T, i As Long\n\
                       For i = 1 To 1000\nr.s(i) = \"x\"\nNext\nEnd Sub\n";
    for src in [items, fields, field_items] {
        let message = refused(src, &small_memory());
        assert!(message.contains("more than the 16.0 MiB allowed"), "{message}");
    }
}

/// "For Each...Next statement": the loop goes through the group's elements, and `Exit For`
/// leaves it. The elements were all gathered before the first turn and counted nowhere, so
/// `For Each x In a: Exit For: Next` over 9 million items in a loop ran past 30 s within the
/// statement limit. Gathering now counts a statement per 16 items, as an array's copy does:
/// 1,000 turns over 100,000 items are 6.25 million statements, past a limit of one million.
#[test]
fn for_each_counts_the_items_it_gathers() {
    let options = RunOptions { max_statements: 1_000_000, ..RunOptions::default() };
    let array = "Sub Main()\nDim a, i As Long, x\nReDim a(1 To 100000)\n\
                 For i = 1 To 1000\nFor Each x In a\nExit For\nNext\nNext\nEnd Sub\n";
    let collection = "Sub Main()\nDim c As New Collection, i As Long, x\n\
                      For i = 1 To 100000\nc.Add i\nNext\n\
                      For i = 1 To 1000\nFor Each x In c\nExit For\nNext\nNext\nEnd Sub\n";
    for src in [array, collection] {
        let message = refused(src, &options);
        assert!(message.contains("statement limit (1000000)"), "{message}");
    }
    // A loop through every item is counted as before, and gives each item in order.
    let whole = "Sub Main()\nDim x, s\nFor Each x In Array(1, 2, 3)\ns = s & x\nNext\nDebug.Print s\nEnd Sub\n";
    assert_eq!(run_with(whole, &RunOptions::default()).unwrap().printed, ["123"]);
}

/// Index lists applied one after another (`o(1)(1)(1)…`, "Property Get" default members,
/// arrays held in arrays) nest the expression one level each when it runs, though no two of
/// their brackets are open at once: 5,000 of them overflowed the stack and aborted the
/// process. Past 255, the brackets' nesting limit (docs/limits.md), the line is refused.
#[test]
fn index_lists_chained_past_the_nesting_limit_are_refused() {
    let chain = |n: usize| format!("Sub Main()\nDim a\nx = a{}\nEnd Sub\n", "(0)".repeat(n));
    let message = refused(&chain(5000), &RunOptions::default());
    assert!(message.contains("5000 index lists applied one after another, more than 255"), "{message}");
    // Members between the lists (`a(0)(0).b(0)(0)…`) nest it as well; a path of members each
    // given its arguments (`a(0).b(0).b(0)…`) is read link after link, so it is no chain.
    let members = format!("Sub Main()\nDim a\nx = a(0)(0){}\nEnd Sub\n", ".b(0)(0)".repeat(150));
    let message = refused(&members, &RunOptions::default());
    assert!(message.contains("more than 255"), "{message}");
    // Arrays in arrays read through a short chain as VBA reads them ([MS-VBAL] 5.6.13.1).
    let nested = "Sub Main()\nDim a\na = Array(Array(1, Array(7, 8)))\nDebug.Print a(0)(1)(1)\nEnd Sub\n";
    assert_eq!(run_with(nested, &RunOptions::default()).unwrap().printed, [" 8 "]);
}

/// A module whose lines the grammar refuses in many procedures (VBA compiles each procedure
/// when it is called, so each fails alone and the others run): each such procedure made the
/// whole module be read again, 40 of them in a module of 20,000 procedures 40 readings (32 s).
/// Now each procedure is read alone once: the source read is at most three times the module's
/// (the whole, its procedures from the first that fails, the whole with theirs set aside), and
/// Main still runs; calling a refused one is its own syntax error.
#[test]
fn procedures_that_do_not_parse_cost_one_more_reading_of_the_module() {
    let mut src = String::new();
    for i in 0..20_000 {
        src += &format!("Function F{i}(x)\n    F{i} = x * {i} + Sqr(x)\nEnd Function\n");
        if i % 500 == 0 {
            src += &format!("Function Bad{i}()\n    Bad{i} = 1 +\nEnd Function\n");
        }
    }
    src += "Sub Main()\n    Debug.Print F3(4)\nEnd Sub\nSub CallsBad()\n    x = Bad1000()\nEnd Sub\n";
    let before = ncsheet::vba::work_done();
    let out = run_with(&src, &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let parsed = (ncsheet::vba::work_done() - before).source_parsed;
    assert_eq!(out.printed, [" 14 "]);
    assert!(parsed <= 3 * src.len() as u64, "{parsed} bytes parsed for a module of {}", src.len());
    let calls = RunOptions { sub: Some("CallsBad".into()), ..RunOptions::default() };
    let e = run_with(&src, &calls).unwrap_err();
    let line = src.lines().position(|l| l == "    Bad1000 = 1 +").unwrap() as u32 + 1;
    assert_eq!((e.kind, e.span.unwrap().line), (ncsheet::vba::ErrorKind::Syntax, line), "{e}");
}
