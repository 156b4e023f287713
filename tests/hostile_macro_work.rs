//! Issue 30: what a macro's sheet statements do to many cells counts against the statement
//! limit by the cells they go over, as text and array work does (tests/hostile_text_work.rs).
//! Counted a statement a turn, `Cells(1, 1).End(xlDown)` over 100,000 filled cells ×
//! 100,000, `Columns(1).Find` over 100,000 cells × 2,000, `Rows(1).Insert` × 20,000 over
//! 20,000 cells and `Rows(i).Delete` × 25,000 over 100,000 ran for minutes within the default
//! limit of 30,000,000 statements.
//!
//! The rates are docs/limits.md's ("macro statements"): an item of work a cell `End` reads, a
//! statement a filled cell `Find` or `Replace` searches, an item a cell and a statement a
//! formula of the workbook an insert or delete goes over. No test here reads a clock: each
//! asserts that the run stops at the statement limit, naming the work, where its own
//! statements stay far below it, and that the same statements over a few cells run to their end.

use ncsheet::vba::{self, ErrorKind, MacroError, RunOptions};
use ncsheet::workbook::Workbook;

/// The limit every run here has: the macros' own statements stay below 10,000.
const LIMIT: u64 = 100_000;

/// `Sub Main()` with `fill` then `work`, run under [`LIMIT`].
fn run(fill: &str, work: &str) -> Result<Vec<String>, MacroError> {
    let source = format!("Sub Main()\n    Dim i As Long, r As Long\n{fill}\n{work}\nEnd Sub\n");
    let options = RunOptions { max_statements: LIMIT, ..RunOptions::default() };
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, &source, "work.bas", &options).map(|out| out.printed)
}

fn stopped_by_work(result: Result<Vec<String>, MacroError>, what: &str) {
    match result {
        Ok(printed) => panic!("{what}: ran to its end within {LIMIT} statements, printing {printed:?}"),
        Err(e) => {
            assert_eq!(e.kind, ErrorKind::Limit, "{what}: {e}");
            assert!(e.message.contains("work counts too"), "{what}: {e}");
        }
    }
}

/// Column A filled with 1..=n (and column B with formulas reading it, when `formulas`).
fn filled(n: u32, formulas: bool) -> String {
    let formula = if formulas { "\n        Cells(i, 2).Formula = \"=A\" & i & \"*2\"" } else { "" };
    format!("    For i = 1 To {n}\n        Cells(i, 1).Value = i{formula}\n    Next i")
}

/// 300 turns of `End(xlDown)` down a run of 3,000 filled cells read 900,000 cells, 225,000
/// statements' worth at four a statement; the same turns down 30 cells read 9,000.
#[test]
fn end_counts_the_cells_it_reads() {
    let work = "    For i = 1 To 300\n        r = Cells(1, 1).End(xlDown).Row\n    Next i";
    stopped_by_work(run(&filled(3000, false), work), "End(xlDown) over 3,000 cells");
    assert!(run(&filled(30, false), work).is_ok(), "End(xlDown) over 30 cells");
}

/// 100 `Find`s of the last of 3,000 filled cells search 300,000 cells, a statement each;
/// 100 `Replace`s over them as many. Over 30 cells, 3,000 of each.
#[test]
fn find_and_replace_count_the_cells_they_search() {
    let find = "    For i = 1 To 100\n        r = Columns(1).Find(What:=\"2999\").Row\n    Next i";
    let replace = "    For i = 1 To 100\n        Columns(1).Replace What:=\"zz\", Replacement:=\"y\"\n    Next i";
    for (work, what) in [(find, "Find"), (replace, "Replace")] {
        stopped_by_work(run(&filled(3000, false), work), what);
        let few = work.replace("2999", "29");
        assert!(run(&filled(30, false), &few).is_ok(), "{what} over 30 cells");
    }
}

/// 200 inserts over 3,000 cells go over 600,000 cells, 150,000 statements' worth; 200 deletes
/// over 3,000 values and 3,000 formulas go over 3,000 formulas each, 600,000 statements. Over
/// 30 cells (and 30 formulas) the same edits count 1,500 (6,000).
#[test]
fn inserts_and_deletes_count_the_cells_of_the_workbook() {
    let insert = "    For i = 1 To 200\n        Rows(1).Insert\n    Next i";
    let delete = "    For i = 1 To 200\n        Rows(1).Delete\n    Next i";
    stopped_by_work(run(&filled(3000, false), insert), "Rows(1).Insert over 3,000 cells");
    stopped_by_work(run(&filled(3000, true), delete), "Rows(1).Delete over 3,000 formulas");
    assert!(run(&filled(30, false), insert).is_ok(), "Rows(1).Insert over 30 cells");
    assert!(run(&filled(30, true), delete).is_ok(), "Rows(1).Delete over 30 formulas");
}

/// 3,000 `c.Add i, Before:=1` move 4.5 million entries, 281,000 statements' worth at sixteen
/// a statement (as an array copy counts its items); `ArrayList.Insert 0` as many. 300 of them
/// move 45,000.
#[test]
fn adding_before_the_first_entry_counts_the_entries_moved() {
    let collection =
        "    Dim c As New Collection\n    c.Add 0\n    For i = 1 To N\n        c.Add i, Before:=1\n    Next i";
    let list = "    Dim c As Object\n    Set c = CreateObject(\"System.Collections.ArrayList\")\n    \
                For i = 1 To N\n        c.Insert 0, i\n    Next i";
    for (work, what) in [(collection, "Collection.Add Before:=1"), (list, "ArrayList.Insert 0")] {
        stopped_by_work(run("", &work.replace(" N\n", " 3000\n")), what);
        assert!(run("", &work.replace(" N\n", " 300\n")).is_ok(), "{what} × 300");
    }
}

/// Moving the later entries keeps every key with its item ("Add method (Visual Basic for
/// Applications)": Before names the item the new one goes before).
#[test]
fn adding_before_keeps_the_keys_with_their_items() {
    let work = "    Dim c As New Collection\n    c.Add \"a\", \"ka\"\n    c.Add \"b\", \"kb\", Before:=1\n    \
                c.Add \"c\", \"kc\", Before:=\"ka\"\n    \
                Debug.Print c(1) & c(2) & c(3) & c(\"ka\") & c(\"kb\") & c(\"kc\")";
    assert_eq!(run("", work).expect("runs"), ["bcaabc"]);
}

/// `k = d.Keys` makes the whole array of keys (Microsoft's "Keys method": "Returns an array
/// containing all existing keys"): over 1,000 keys, 1,000 calls make a million items, 250,000
/// statements' worth; over 30 keys, 30 calls make 900. `d.Keys()(i)`, `d.Items()(i)` and
/// `d.Keys(i)` read the one entry they pick: a loop of them over 10,000 entries counts its
/// 40,000 statements (copying the list at each call, it made 100 million items, 2,500
/// statements' worth a call) and adds up what the entries hold, 1 + 2 + … + 10,000.
#[test]
fn keys_and_items_count_the_array_made_and_read_one_entry_picked() {
    let fill = "    Dim d As Object, n As Double, k
    Set d = CreateObject(\"Scripting.Dictionary\")
    \
                For i = 1 To KEYS
        d(i) = i
    Next i";
    for member in ["Keys", "Items"] {
        let whole = format!(
            "    For i = 0 To KEYS - 1
        k = d.{member}
        n = n + k(i)
    Next i"
        );
        stopped_by_work(run(&fill.replace("KEYS", "1000"), &whole.replace("KEYS", "1000")), member);
        assert!(run(&fill.replace("KEYS", "30"), &whole.replace("KEYS", "30")).is_ok(), "{member} of 30");
        for picked in [format!("d.{member}()(i)"), format!("d.{member}(i)")] {
            let work = format!(
                "    For i = 0 To 9999
        n = n + {picked}
    Next i
    Debug.Print n"
            );
            let printed = run(&fill.replace("KEYS", "10000"), &work).unwrap_or_else(|e| panic!("{picked}: {e}"));
            assert_eq!(printed, [" 50005000 "], "{picked}");
        }
    }
}

/// Arguments reach their parameters whatever order they are written in ([MS-VBAL] 5.3.1.11:
/// a named argument binds to the parameter of that name), now that they are ordered by
/// parameter before binding: a call of 60,000 arguments found each one among all of them.
/// The wide call's values check each place; its work is not counted here.
#[test]
fn arguments_bind_to_their_parameters_in_any_order() {
    let source = "Sub F(a, Optional b = 20, Optional c, Optional ByVal d As Integer = 40)\n    \
                  Debug.Print a; b; IsMissing(c); d\nEnd Sub\n\
                  Sub Main()\n    F d:=4, a:=1\n    F 1, c:=3, b:=2\n    F c:=3, a:=1, d:=4, b:=2\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    let out = vba::run(&mut wb, source, "bind.bas", &RunOptions::default()).expect("runs");
    assert_eq!(out.printed, [" 1  20 True 4 ", " 1  2 False 40 ", " 1  2 False 4 "]);

    let n = 60_000;
    let params: Vec<String> = (0..n).map(|i| format!("p{i}")).collect();
    let args: Vec<String> = (0..n).map(|i| i.to_string()).collect();
    let wide = format!(
        "Sub F({})\n    Debug.Print p0; p1; p30000; p59999\nEnd Sub\nSub Main()\n    F {}\nEnd Sub\n",
        params.join(", "),
        args.join(", ")
    );
    let out = vba::run(&mut wb, &wide, "wide.bas", &RunOptions::default()).expect("runs");
    assert_eq!(out.printed, [" 0  1  30000  59999 "]);
}
