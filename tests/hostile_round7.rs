//! Hostile input (issue 30), a seventh round of variants (session 20): each test is a class
//! the round reached that the earlier fixes did not cover. Values come from outside our code:
//! arithmetic worked by hand.

mod common;

use ncsheet::eval::{Value, XlError};

/// MINVERSE and MDETERM of a matrix the array limit allows but whose LU decomposition is
/// billions of steps (n³): `MINVERSE(RANDARRAY(3000,3000))` ran past 30 s and 4,096 × 4,096
/// would take minutes. Past 10^9 steps (n > 1000) they are `#NUM!` before any work, with the
/// limit in the cell's note; at the limit they still compute: the identity matrix is its own
/// inverse and its determinant is 1, whatever its size (by hand).
#[test]
fn matrix_inverses_past_the_work_limit_are_num_with_a_note() {
    for formula in ["=SUM(MINVERSE(MUNIT(1001)))", "=MDETERM(MUNIT(1001))"] {
        let (value, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(value, Value::Error(XlError::Num), "{formula}");
        assert!(notes.iter().any(|n| n.contains("1001 × 1001 matrix") && n.contains("1e9")), "{formula}: {notes:?}");
    }
    assert_eq!(common::sheet::eval_a1("=SUM(MINVERSE(MUNIT(1000)))").0, Value::Number(1000.0));
    assert_eq!(common::sheet::eval_a1("=MDETERM(MUNIT(1000))").0, Value::Number(1.0));
}
