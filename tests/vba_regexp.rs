//! VBScript's RegExp ("Microsoft VBScript Regular Expressions 5.5") as macros create it
//! (issue 31). Expected values come from Microsoft's VBScript reference, the page named at
//! each test (its own examples where it has one), or from Python's `re` worked apart where
//! ECMAScript and Python agree (noted), never from ncsheet's own output. Before this the
//! RegExp was refused by name, so each test failed. `Debug.Print a; b` writes a number with a
//! space before (its sign's place) and after it, a Boolean or a String bare ("Print #
//! Statement").

mod common;

use common::vba::{main_fails, run_main};
use ncsheet::workbook::Workbook;

fn printed(body: &str) -> Vec<String> {
    run_main(&mut Workbook::with_sheet(), body)
}

fn fails(body: &str) -> String {
    main_fails(&mut Workbook::with_sheet(), body)
}

/// "Execute Method" (VBScript), its example: `RegExpTest("is.", "IS1 is2 IS3 is4")` with
/// IgnoreCase and Global finds IS1 at 0, is2 at 4, IS3 at 8, is4 at 12.
#[test]
fn execute_finds_every_match_with_its_zero_based_first_index() {
    let body = r#"
    Dim regEx, Matches, Match, RetStr
    Set regEx = CreateObject("VBScript.RegExp")
    regEx.Pattern = "is."
    regEx.IgnoreCase = True
    regEx.Global = True
    Set Matches = regEx.Execute("IS1 is2 IS3 is4")
    Debug.Print Matches.Count
    For Each Match In Matches
        Debug.Print Match.FirstIndex & " " & Match.Value & " " & Match.Length
    Next
    Debug.Print Matches(1) & Matches.Item(3).Value"#;
    assert_eq!(printed(body), [" 4 ", "0 IS1 3", "4 is2 3", "8 IS3 3", "12 is4 3", "is2is4"]);
}

/// "Global Property": False (the default) searches for the first match only; IgnoreCase
/// False (the default) is case-sensitive, so "is." then finds is2 at 4 first.
#[test]
fn global_false_finds_only_the_first_match() {
    let body = r#"
    Dim re As Object
    Set re = CreateObject("vbscript.regexp")
    re.Pattern = "is."
    Debug.Print re.Global; re.IgnoreCase; re.MultiLine
    Debug.Print re.Execute("IS1 is2 IS3 is4").Count; re.Execute("IS1 is2 IS3 is4")(0).FirstIndex
    Debug.Print re.Replace("IS1 is2 IS3 is4", "*")"#;
    assert_eq!(printed(body), ["FalseFalseFalse", " 1  4 ", "IS1 * IS3 is4"]);
}

/// "SubMatches Collection", its example: "(\w+)@(\w+)\.(\w+)" in "Please send mail to
/// dragon@xyzzy.com. Thanks!" is dragon@xyzzy.com, with dragon, xyzzy and com; the Match
/// reads as its Value (its default property, "Match Object"), early bound as
/// `Dim oRe As New RegExp`.
#[test]
fn submatches_of_the_reference_example_early_bound() {
    let body = r#"
    Dim oRe As New RegExp
    Dim oMatches As MatchCollection, oMatch As Match
    oRe.Pattern = "(\w+)@(\w+)\.(\w+)"
    Set oMatches = oRe.Execute("Please send mail to dragon@xyzzy.com. Thanks!")
    Set oMatch = oMatches(0)
    Debug.Print "Email address is: " & oMatch
    Debug.Print oMatch.SubMatches(0) & "|" & oMatch.SubMatches.Item(1) & "|" & oMatch.SubMatches(2)
    Debug.Print oMatch.SubMatches.Count; TypeName(oRe); TypeName(oMatch)
    Dim s
    For Each s In oMatch.SubMatches
        Debug.Print s
    Next"#;
    assert_eq!(
        printed(body),
        ["Email address is: dragon@xyzzy.com", "dragon|xyzzy|com", " 3 IRegExp2IMatch2", "dragon", "xyzzy", "com"]
    );
}

/// A group that took no part is Empty in SubMatches; Python: re.match("(a)|(b)", "b").groups()
/// is (None, 'b').
#[test]
fn an_unmatched_group_is_empty() {
    let body = r#"
    Dim re As New VBScript_RegExp_55.RegExp, m
    re.Pattern = "(a)|(b)"
    Set m = re.Execute("b")(0)
    Debug.Print IsEmpty(m.SubMatches(0)); m.SubMatches(1)"#;
    assert_eq!(printed(body), ["Trueb"]);
}

/// "Replace Method", its examples on "The quick brown fox jumped over the lazy dog.":
/// "fox" → "cat", and "(\S+)(\s+)(\S+)" with "$3$2$1" swaps the first pair of words.
#[test]
fn replace_examples_of_the_reference() {
    let body = r#"
    Dim regEx, str1
    str1 = "The quick brown fox jumped over the lazy dog."
    Set regEx = New RegExp
    regEx.IgnoreCase = True
    regEx.Pattern = "fox"
    Debug.Print regEx.Replace(str1, "cat")
    regEx.Pattern = "(\S+)(\s+)(\S+)"
    Debug.Print regEx.Replace(str1, "$3$2$1")"#;
    assert_eq!(
        printed(body),
        ["The quick brown cat jumped over the lazy dog.", "quick The brown fox jumped over the lazy dog."]
    );
}

/// The replacement's `$&`, `` $` ``, `$'`, `$$` and `$nn` (ECMA-262 3rd ed. 15.5.4.11, Table 22,
/// which JScript's replace and VBScript's Replace method follow). Worked by hand: in "xaby"
/// the match of "a(b)" is "ab", with "x" before and "y" after; `$2` names no group and stays.
#[test]
fn replacement_patterns_follow_jscript() {
    let body = r#"
    Dim re: Set re = CreateObject("VBScript.RegExp")
    re.Pattern = "a(b)"
    Debug.Print re.Replace("xaby", "[$&|$`|$'|$$|$1|$2|$01]")"#;
    assert_eq!(printed(body), ["x[ab|x|y|$|b|$2|b]y"]);
}

/// "Test Method": True when the pattern is found. "\d" is [0-9] only ("Pattern Property"),
/// so an Arabic-Indic digit is no digit; "\bcat\b" needs ASCII word boundaries.
#[test]
fn test_with_ascii_classes() {
    let body = r#"
    Dim re: Set re = New RegExp
    re.Pattern = "^\d+$"
    Debug.Print re.Test("2026"); re.Test("20a6"); re.Test(ChrW(1634))
    re.Pattern = "\bcat\b"
    Debug.Print re.Test("a cat."); re.Test("concat")"#;
    assert_eq!(printed(body), ["TrueFalseFalse", "TrueFalse"]);
}

/// "Pattern Property": `.` matches any character but "\n"; `^` and `$` are the text's
/// start and end, and with MultiLine also a line's. Python agrees: re.findall("^\w+$",
/// "ab\ncd", re.M) is ['ab', 'cd'], and without re.M there is no match.
#[test]
fn multiline_anchors_and_the_dot() {
    let body = r#"
    Dim re: Set re = New RegExp
    re.Global = True
    re.Pattern = "^\w+$"
    Debug.Print re.Execute("ab" & vbLf & "cd").Count
    re.MultiLine = True
    Debug.Print re.Execute("ab" & vbLf & "cd").Count; re.Execute("ab" & vbLf & "cd")(1).FirstIndex
    re.Pattern = "a.b"
    Debug.Print re.Test("a" & vbLf & "b"); re.Test("a" & vbTab & "b")"#;
    assert_eq!(printed(body), [" 0 ", " 2  3 ", "FalseTrue"]);
}

/// FirstIndex and Length count a String's UTF-16 units, as a VBA String is made of them: "😀"
/// is two (Python: len("é😀a".encode("utf-16-le")) // 2 is 4, where the "bb" starts).
#[test]
fn positions_are_counted_in_utf16_units() {
    let body = r#"
    Dim re: Set re = New RegExp
    re.Pattern = "b+"
    Dim t: t = "é😀abb"
    Debug.Print re.Execute(t)(0).FirstIndex; re.Execute(t)(0).Length"#;
    assert_eq!(printed(body), [" 4  2 "]);
}

/// "VBScript Run-time Errors": a bad pattern raises 5017-5021, trapped like any error.
#[test]
fn bad_patterns_raise_vbscripts_errors() {
    let body = r#"
    Dim re: Set re = New RegExp
    Dim p, found
    On Error Resume Next
    For Each p In Array("a(b", "[ab", "*a", "[z-a]", "a)")
        Err.Clear
        re.Pattern = p
        found = re.Test("ab")
        Debug.Print Err.Number
    Next"#;
    assert_eq!(printed(body), [" 5020 ", " 5019 ", " 5018 ", " 5021 ", " 5017 "]);
}

/// Lookahead and backreferences are refused by name, never matched otherwise.
#[test]
fn lookahead_and_backreferences_are_refused_by_name() {
    for (pattern, named) in [("Windows (?=95|98)", "lookahead"), ("(a)\\1", "backreference \\1")] {
        let body = format!("Dim re: Set re = New RegExp\n re.Pattern = \"{pattern}\"\n Debug.Print re.Test(\"aa\")");
        let message = fails(&body);
        assert!(message.contains(named) && message.contains(pattern), "{message}");
    }
}

/// MatchCollection.Item past the matches: "Invalid procedure call or argument" (5).
#[test]
fn an_item_past_the_matches_is_error_5() {
    let body = r#"
    Dim re: Set re = New RegExp
    re.Pattern = "x"
    On Error Resume Next
    Dim m: Set m = re.Execute("abc")(0)
    Debug.Print Err.Number"#;
    assert_eq!(printed(body), [" 5 "]);
}

/// A pattern that backtracking engines take exponential time over ("(a+)+b" on a run of
/// "a"s with no "b": 2^n ways to split the run) answers at once here: the text has no "b", so
/// False (Python's `re` needs minutes at this length, so it is worked by hand).
#[test]
fn a_catastrophic_pattern_for_backtracking_answers_at_once() {
    let body = r#"
    Dim re: Set re = New RegExp
    re.Pattern = "(a+)+b"
    Dim t: t = String(20000, "a")
    Debug.Print re.Test(t); re.Execute(t & "b")(0).Length"#;
    assert_eq!(printed(body), ["False 20001 "]);
}

/// docs/limits.md: a pattern past 10,000 characters, or one that compiles past 8 MiB, is
/// refused naming the limit, never built.
#[test]
fn patterns_past_the_limits_are_refused() {
    let long = fails("Dim re: Set re = New RegExp\n re.Pattern = String(10001, \"a\")\n Debug.Print re.Test(\"a\")");
    assert!(long.contains("10001 characters") && long.contains("10000"), "{long}");
    let big = fails("Dim re: Set re = New RegExp\n re.Pattern = \"(a{1000}){1000}\"\n Debug.Print re.Test(\"a\")");
    assert!(big.contains("8 MiB"), "{big}");
}

/// `v = m` without Set assigns the Match's Value, its default property ("Match Object";
/// [MS-VBAL]'s object Let-coercion: "the simple data value of the object"): a String.
#[test]
fn let_assigning_a_match_gives_its_value() {
    let body = r#"
    Dim re: Set re = New RegExp
    re.Pattern = "\d+"
    re.Global = True
    Dim mc: Set mc = re.Execute("a12b345")
    Dim v, w
    v = mc(1)
    w = mc.Item(0)
    Debug.Print TypeName(v); v; TypeName(w); w"#;
    assert_eq!(printed(body), ["String345String12"]);
}

/// The message of the error that stops `body` run under a memory limit of `max_memory` bytes.
fn fails_within(body: &str, max_memory: u64) -> String {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    let options = ncsheet::vba::RunOptions { max_memory, ..ncsheet::vba::RunOptions::default() };
    match ncsheet::vba::run(&mut Workbook::with_sheet(), &src, "main.bas", &options) {
        Ok(out) => panic!("the macro ran to its end, printing {:?}", out.printed),
        Err(e) => e.message,
    }
}

/// docs/limits.md: Replace stops at the longest string a macro may make (16,777,216
/// characters by default) instead of building more: "$'" after each of 100,000 empty matches
/// would make about 5·10^9 characters (the sum of the suffixes, n(n+1)/2).
#[test]
fn a_replacement_past_the_longest_string_is_refused() {
    let message = fails(
        "Dim re: Set re = New RegExp\n re.Global = True\n Debug.Print Len(re.Replace(String(100000, \"a\"), \"$'\"))",
    );
    assert!(message.contains("Replace") && message.contains("16777216 characters"), "{message}");
}

/// Execute's matches count against the macro's memory limit as they are found, and the
/// MatchCollections a macro keeps are measured with its variables: 100,000 one-character
/// matches, or 200 collections of 1,000 kept in a Collection, pass a 4 MiB limit.
#[test]
fn matches_count_against_the_memory_limit() {
    let many = fails_within(
        "Dim re: Set re = New RegExp\n re.Global = True\n re.Pattern = \"a\"\n Debug.Print re.Execute(String(100000, \"a\")).Count",
        4 << 20,
    );
    assert!(many.contains("Execute") && many.contains("--max-memory"), "{many}");
    let kept = fails_within(
        "Dim re: Set re = New RegExp\n re.Global = True\n re.Pattern = \"a\"\n Dim c As New Collection, i\n \
         For i = 1 To 2000\n c.Add re.Execute(String(1000, \"a\"))\n Next\n Debug.Print c.Count",
        4 << 20,
    );
    assert!(kept.contains("--max-memory"), "{kept}");
}

/// The statement limit `body` runs under, and the error that stops it.
fn stops_within(body: &str, max_statements: u64) -> ncsheet::vba::MacroError {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    let options = ncsheet::vba::RunOptions { max_statements, ..ncsheet::vba::RunOptions::default() };
    match ncsheet::vba::run(&mut Workbook::with_sheet(), &src, "main.bas", &options) {
        Ok(out) => panic!("the macro ran to its end, printing {:?}", out.printed),
        Err(e) => e,
    }
}

/// docs/limits.md, "a regular expression": a search's work is the states the pattern can
/// have active × (its slots + 100) per byte, refused past 3·10^9 before it runs. A chain of
/// 1,000 `(?:a?)` then 1,000 `a` keeps about 2,000 states active at every byte (each `a?`
/// may or may not have taken its `a`): 2,000 × 102 × 30,001 bytes is 6·10^9, past the limit
/// (it ran for seconds); over 1,000 characters it is 2·10^8, and it matches (each `a?` may
/// take nothing, the 1,000 `a` take the text; Python: re.search('(?:a?)'*1000+'a'*1000,
/// 'a'*1000) matches).
#[test]
fn a_search_past_the_work_limit_is_refused_before_it_runs() {
    let setup = "Dim re: Set re = New RegExp\n Dim p, i\n For i = 1 To 1000: p = p & \"(?:a?)\": Next\n \
                 re.Pattern = p & String(1000, \"a\")\n";
    assert_eq!(printed(&format!("{setup} Debug.Print re.Test(String(1000, \"a\"))")), ["True"]);
    for call in ["re.Test(t)", "re.Execute(t).Count", "re.Replace(t, \"\")"] {
        let e = stops_within(&format!("{setup} Dim t: t = String(30000, \"a\")\n Debug.Print {call}"), 30_000_000);
        assert_eq!(e.kind, ncsheet::vba::ErrorKind::Limit, "{call}: {e}");
        assert!(e.message.contains("30000 bytes") && e.message.contains("limit of 3e9"), "{call}: {e}");
    }
}

/// A loop of searches each within the limit counts their work against the statement limit,
/// a unit of text work per 400 steps: 100 `(?:a?)` and "b" keep about 200 states active, so a
/// search of 10,000 "a" is about 200 × 102 × 10,001 = 2·10^8 steps, 500,000 units, 125,000
/// statements; twenty turns pass a limit of 1,000,000 that the loop's own 60 statements stay
/// far below.
#[test]
fn a_loop_of_searches_counts_their_work_as_statements() {
    let body = "Dim re: Set re = New RegExp\n Dim p, i\n For i = 1 To 100: p = p & \"(?:a?)\": Next\n \
                re.Pattern = p & \"b\"\n Dim t: t = String(10000, \"a\")\n For i = 1 To 20: Debug.Print re.Test(t): Next";
    let e = stops_within(body, 1_000_000);
    assert_eq!(e.kind, ncsheet::vba::ErrorKind::Limit, "{e}");
    assert!(e.message.contains("text and array work counts too"), "{e}");
}

/// A global search searches again from each match's end, and a search reads on while a
/// branch of higher priority could still match: `.*[^A-Z]` stays alive to the end of a text
/// of letters, so each one-letter match of `[A-Z]` reads the rest (10,000 letters took
/// seconds). The bytes each search reads are added up against the one limit of 3·10^9, for
/// Execute and Replace alike; without Global one search is made, and over 1,000 letters the
/// global search answers (JavaScript: "A".repeat(1000).replace(/.*[^A-Z]|[A-Z]/g, "x") is
/// 1,000 "x").
#[test]
fn a_global_search_counts_the_bytes_each_search_reads() {
    let setup = "Dim re: Set re = New RegExp\n re.Pattern = \".*[^A-Z]|[A-Z]\"\n re.Global = True\n";
    let short = format!("{setup} Debug.Print re.Replace(String(1000, \"A\"), \"x\") = String(1000, \"x\")");
    assert_eq!(printed(&short), ["True"]);
    for call in ["re.Execute(t).Count", "re.Replace(t, \"x\")"] {
        let e = stops_within(&format!("{setup} Dim t: t = String(10000, \"A\")\n Debug.Print {call}"), 30_000_000);
        assert_eq!(e.kind, ncsheet::vba::ErrorKind::Limit, "{call}: {e}");
        assert!(e.message.contains("finding every match") && e.message.contains("limit of 3e9"), "{call}: {e}");
    }
    let once = format!("{setup} re.Global = False\n Debug.Print re.Execute(String(10000, \"A\")).Count");
    assert_eq!(printed(&once), [" 1 "]);
}
