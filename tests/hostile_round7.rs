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

/// MMULT of matrices the array limit allows but whose product is tens of billions of
/// multiply-adds (rows × inner size × columns): two 4,096 × 4,096 matrices took 13 s and a
/// cell of three such products ran past 30 s. Past 4·10^9 it is `#NUM!` before any work, the
/// limit in the cell's note: 4,000 × 251 by 251 × 4,000 is 4,016,000,000 (by hand).
#[test]
fn matrix_products_past_the_work_limit_are_num_with_a_note() {
    let formula = "=SUM(MMULT(SEQUENCE(4000,251,0,0),SEQUENCE(251,4000,0,0)))";
    let (value, notes, _) = common::sheet::eval_a1(formula);
    assert_eq!(value, Value::Error(XlError::Num), "{formula}");
    assert!(notes.iter().any(|n| n.contains("4016000000 multiply-adds") && n.contains("4e9")), "{notes:?}");
    // Inside the limit it computes: a row of 251 ones by a column of 251 twos is 502.
    assert_eq!(common::sheet::eval_a1("=MMULT(SEQUENCE(1,251,1,0),SEQUENCE(251,1,2,0))").0, Value::Number(502.0));
}

/// Operators and lifted functions over arrays of long texts make small items (TRUE, a
/// position) but read each pair of texts whole: 100 × 4,000 texts of 30,000 characters
/// compared took 53 s, FIND of them 119 s, SEARCH of 100,000 needles in one 32,000-character
/// text 77 s. The texts read for one array count against 512 MiB (2^29 bytes): 100 × 200
/// pairs of 30,001–30,003 characters read 1.2·10^9 bytes, 20,000 FINDs in a 32,000-character
/// text 6.4·10^8 (by hand) — `#NUM!` with the note; ten by ten texts of a thousand
/// characters compare as ever (the ten equal pairs, by hand).
#[test]
fn texts_read_for_one_array_count_against_their_limit() {
    for formula in [
        "=SUM(--(REPT(\"a\",30000)&SEQUENCE(100)>REPT(\"a\",30000)&SEQUENCE(1,200)))",
        "=ROWS(FIND(SEQUENCE(20000)&\"\",REPT(\"a\",32000)))",
    ] {
        let (value, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(value, Value::Error(XlError::Num), "{formula}");
        assert!(notes.iter().any(|n| n.contains("read more than 512 MiB of text")), "{formula}: {notes:?}");
    }
    let within = "=SUM(--(REPT(\"a\",1000)&SEQUENCE(10)=REPT(\"a\",1000)&SEQUENCE(1,10)))";
    assert_eq!(common::sheet::eval_a1(within).0, Value::Number(10.0));
}
