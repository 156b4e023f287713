//! Hostile input (issue 30), session 26: variants of the classes that no earlier
//! round named, found by a reviewer's run of its own (helper h3's table of about 1,200
//! attacks). What each test expects comes from outside our code: the MS-VBAL specification
//! and Microsoft's VBA reference, quoted where they are used.

mod common;

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run(src: &str) -> Result<RunOutput, MacroError> {
    vba::run(&mut Workbook::with_sheet(), src, "round12.bas", &RunOptions::default())
}

fn printed(src: &str) -> Vec<String> {
    run(src).unwrap_or_else(|e| panic!("{e}")).printed
}

/// "InStr function", "InStrRev function", "Split function", "Filter function" and "Replace
/// function": the first (last) position where one text is found in another, and each place
/// Replace puts its text. They compared the text sought at every position, so a
/// 2,000,000-character text and a 1,000,000-character one that almost matches everywhere were
/// 10^12 comparisons (`InStr(s, String(5000000, "a") & "b")` of 10 million characters ran past
/// 30 s); now one linear search each. The answers below are worked by hand from the
/// functions' definitions (Replace with a start gives the text from that start on).
#[test]
fn text_searches_in_macros_take_time_linear_in_the_texts() {
    let src = "Sub Main()\nDim s, t, u\ns = String(2000000, \"a\")\nt = String(1000000, \"a\") & \"b\"\n\
               u = s & \"b\"\n\
               Debug.Print InStr(s, t); InStr(u, t); InStrRev(s, t); InStrRev(u, t)\n\
               Debug.Print UBound(Split(s, t)); UBound(Split(u, t)); UBound(Filter(Array(s, u), t))\n\
               Debug.Print Len(Replace(s, t, \"x\")); Len(Replace(u, t, \"x\"))\n\
               Debug.Print InStr(\"abababc\", \"ababc\"); InStrRev(\"abcabcab\", \"cab\"); InStrRev(\"abcabcab\", \"cab\", 5)\n\
               Debug.Print Join(Split(\"aXbxc\", \"x\", -1, vbTextCompare), \"|\"); \" \"; Replace(\"AaAa\", \"aa\", \"-\", 1, -1, vbTextCompare)\n\
               Debug.Print InStr(3, \"aaa\", \"\"); InStrRev(\"aaa\", \"a\", 2); Replace(\"abcabc\", \"bc\", \"Y\", 3)\n\
               End Sub\n";
    let out = printed(src);
    assert_eq!(
        out,
        [" 0  1000001  0  1000001 ", " 0  1  0 ", " 2000000  1000001 ", " 3  6  3 ", "a|b|c --", " 3  2 caY",]
    );
}
