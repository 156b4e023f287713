//! Hostile input (issue 30), a sixth round of variants (session 19): each test is a class the
//! round reached that the earlier fixes did not cover. Values come from outside our code:
//! Microsoft's VBA reference for the errors a macro meets, arithmetic worked by hand.

mod common;

use std::path::Path;

/// Writes `text` to `name` in `dir` and gives its path as text.
fn file(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// A recursive Function whose every level runs its call nested in 120 calls of Abs (inside
/// the 255 brackets a line may nest): each level takes far more native stack than the
/// 64 KiB `--max-depth` gives it, and 5,000 such levels overflowed the thread's stack (a
/// crash, exit 134) before the depth limit of 10,000 was reached. VBA stops recursion that
/// runs out of stack with error 28 (VBA reference, "Out of stack space (Error 28)"), which
/// an error handler can trap: the call that finds too little stack left is refused so.
#[test]
fn recursion_whose_levels_outgrow_their_share_of_the_stack_is_error_28() {
    let dir = tempfile::tempdir().unwrap();
    let sheet = file(dir.path(), "one.csv", "1\n");
    let nested = format!("{}F(n + 1){}", "Abs(".repeat(120), ")".repeat(120));
    let src = format!("Sub Main()\n    Debug.Print F(0)\nEnd Sub\nFunction F(n)\n    F = {nested}\nEnd Function\n");
    let bas = file(dir.path(), "deep.bas", &src);
    let run = common::cli::ncsheet(&["run", "--max-depth", "10000", &sheet, &bas]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(run.stderr.contains("Out of stack space (run-time error 28)"), "{}", run.stderr);

    // Trapped, as VBA's error 28 is: the outermost handler reads its number.
    let trapped = format!(
        "Sub Main()\n    On Error Resume Next\n    Debug.Print F(0)\n    Debug.Print \"error\"; Err.Number\nEnd Sub\n\
         Function F(n)\n    F = {nested}\nEnd Function\n"
    );
    let bas = file(dir.path(), "trapped.bas", &trapped);
    let run = common::cli::ncsheet(&["run", "--max-depth", "10000", &sheet, &bas]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("error 28"), "{}", run.stderr);
}
