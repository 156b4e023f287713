//! Issue 30: a macro's library functions that read a long text and answer little (a number,
//! a Boolean, a short text) count what they read against the statement limit, as the texts
//! functions make already did (tests/hostile_time.rs). Uncounted, `c = Mid(s, i, 1)` over a
//! text of millions of characters, or `Trim`, `CDbl`, `Val`, `IsNumeric`, `IsDate`, `Len`
//! and `LenB` of a long text in a loop, ran for minutes to hours within the default limit
//! of 30,000,000 statements, each turn counting one.
//!
//! The rate is docs/limits.md's: a statement per 64 characters read (`WORK_PER_STATEMENT`
//! units of 16 bytes). No test here reads a clock: each asserts that the run stops at the
//! statement limit, naming the text work, where its own statements stay far below it.

use ncsheet::vba::{self, ErrorKind, MacroError, RunOptions};
use ncsheet::workbook::Workbook;

/// Runs `Sub Main()` with `body` under a statement limit of `limit`; the error it stops with.
fn stops_within(body: &str, limit: u64) -> MacroError {
    let source = format!("Sub Main()\n{body}\nEnd Sub\n");
    let options = RunOptions { max_statements: limit, ..RunOptions::default() };
    let mut wb = Workbook::with_sheet();
    match vba::run(&mut wb, &source, "work.bas", &options) {
        Ok(out) => panic!("the macro ran to its end, printing {:?}:\n{body}", out.printed),
        Err(e) => e,
    }
}

fn stopped_by_text_work(e: &MacroError, what: &str) {
    assert_eq!(e.kind, ErrorKind::Limit, "{what}: {e}");
    assert!(e.message.contains("text and array work counts too"), "{what}: {e}");
}

/// A loop of 100 turns, each reading a text of 100,001 characters: 1,562 statements' worth a
/// read at 64 characters a statement, 156,000 in all, past a limit of 100,000 that the loop's
/// own 200 statements stay far below.
#[test]
fn functions_reading_a_long_text_count_what_they_read() {
    let setup = "    Dim u As String, v, n As Double, b As Boolean, t As String, i As Long\n    \
                 u = Space(100000) & \"5\": v = Array(u)\n";
    for work in [
        "t = Trim(u)",
        "t = LTrim(u)",
        "n = CDbl(u)",
        "n = Val(u)",
        "b = IsNumeric(u)",
        "b = IsDate(u)",
        "n = LenB(u)",
        // An array's item, not a variable whose length the macro keeps as it grows.
        "n = Len(v(0))",
    ] {
        let body = format!("{setup}    For i = 1 To 100\n        {work}\n    Next i");
        let e = stops_within(&body, 100_000);
        stopped_by_text_work(&e, work);
        assert!(e.span.is_some_and(|s| (4..=6).contains(&s.line)), "{work}: {:?}", e.span);
    }
}

/// `Mid(s, i, 1)` finds character i by stepping over the i − 1 before it (checking them for
/// ASCII a word at a time, a unit per 1,024 bytes): walking a text of 2,000,000 characters
/// checks 2·10^12 bytes, about 4.9·10^8 statements' worth, and stops within a limit of
/// 1,000,000 after about 90,000 characters; its loop's 4,000,000 statements alone would pass
/// the limit only at its 500,000th character. Stepping characters one by one (a text of
/// accented letters) is a unit per 16 bytes.
#[test]
fn mid_over_a_long_text_counts_the_characters_it_steps_over() {
    for (text, what) in [("String(2000000, \"a\")", "ASCII"), ("String(2000000, ChrW(233))", "accented")] {
        let body = format!(
            "    Dim s As String, c As String, i As Long\n    s = {text}\n    \
             For i = 1 To Len(s)\n        c = Mid(s, i, 1)\n    Next i"
        );
        let e = stops_within(&body, 1_000_000);
        stopped_by_text_work(&e, what);
        assert!(e.span.is_some_and(|s| (4..=5).contains(&s.line)), "{what}: {:?}", e.span);
    }
}

/// What reads a bounded part of a long text counts only that part: the same loops of
/// `Left`, `Right`, `Asc` and a short `Mid` near the start run to their end.
#[test]
fn functions_reading_a_part_of_a_long_text_count_only_the_part() {
    let source = "Sub Main()\n    Dim u As String, t As String, n As Long, i As Long\n    \
                  u = String(1000000, \"a\")\n    For i = 1 To 1000\n        \
                  t = Left(u, 1) & Right(u, 1) & Mid(u, 10, 2): n = Asc(u) + AscW(u)\n    \
                  Next i\n    Debug.Print t; n\nEnd Sub\n";
    let options = RunOptions { max_statements: 100_000, ..RunOptions::default() };
    let mut wb = Workbook::with_sheet();
    let out = vba::run(&mut wb, source, "part.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed.iter().map(|l| l.trim()).collect::<Vec<_>>(), ["aaaa 194"]);
}
