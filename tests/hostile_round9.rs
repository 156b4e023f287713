//! Hostile input (issue 30), session 23: limits a function reached with no note, or reached
//! where Excel computes a number. Values come from outside our code: exact arithmetic worked
//! in Python's fractions, mpmath at 40 digits, or bounds worked by hand.

mod common;

use common::sheet::eval_a1;
use ncsheet::eval::{Value, XlError};

/// The value of `formula`, which must be a number.
fn number(formula: &str) -> f64 {
    match eval_a1(formula).0 {
        Value::Number(n) => n,
        other => panic!("{formula}: {other:?}"),
    }
}

/// Whether `formula` is within `relative` of `want`.
fn near(formula: &str, want: f64, relative: f64) {
    let got = number(formula);
    assert!((got - want).abs() <= want.abs() * relative, "{formula}: {got}, want {want}");
}

#[test]
fn geomean_of_equal_numbers_is_that_number_at_the_edges_of_doubles() {
    // The geometric mean of n copies of x is x (exact arithmetic); Excel shows
    // GEOMEAN(1E308,1E308) as 1E+308. Through logarithms it was 1.00000000000001E+308.
    for (formula, want) in [
        ("=GEOMEAN(1E308,1E308)", 1e308),
        ("=GEOMEAN(1E300,1E300,1E300)", 1e300),
        ("=GEOMEAN(1E-300,1E-300)", 1e-300),
        ("=GEOMEAN(2,8)", 4.0),
    ] {
        assert_eq!(number(formula), want, "{formula}");
    }
}

#[test]
fn a_wrap_count_no_array_holds_is_named_as_given() {
    // docs/limits.md: an array past 2^24 items is #NUM! with a note. The count 1E+300 read
    // as a usize saturated, and the note spoke of "1 × 18446744073709551615" items.
    let (value, notes, _) = eval_a1("=WRAPROWS(SEQUENCE(10),1E300,0)");
    assert_eq!(value, Value::Error(XlError::Num));
    assert!(notes.iter().any(|n| n.contains("1E+300") && n.contains("16777216")), "{notes:?}");
    assert!(!notes.iter().any(|n| n.contains("18446744073709551615")), "{notes:?}");
}

#[test]
fn depreciation_of_a_long_life_computes_the_periods_asked() {
    // VDB over the first 10 periods of a 1E7-period life, double declining: the rate is
    // 2/1E7 and the sum is 1000·(1 − (1 − 2E-7)^10) = 0.00199999820000096 (Python's
    // fractions; straight line never wins so early). It was #NUM! for the life.
    near("=VDB(1000,0,1E7,0,10)", 0.001_999_998_200_000_96, 1e-12);
    // Salvage 0: DB's rate is 1 − 0^(1/life) = 1, the first period takes all 1000, and
    // every later one 0 (by hand). Past a million periods it was #NUM!.
    assert_eq!(number("=DB(1000,0,2E6,1500000)"), 0.0);
    // Stepping to a far end remains past the limit, and says so.
    let (value, notes, _) = eval_a1("=VDB(1000,0,1E7,0,1E7)");
    assert_eq!(value, Value::Error(XlError::Num));
    assert!(notes.iter().any(|n| n.contains("VDB") && n.contains("1000000")), "{notes:?}");
}

#[test]
fn cumulative_interest_and_principal_over_millions_of_periods() {
    // mpmath at 40 digits, the annuity's sums as geometric series: rate 1E-4, 3E6 periods,
    // 1000 borrowed, payments 1 to 2E6 in advance. Past 1E6 periods both were #NUM!.
    near("=CUMIPMT(1E-4,3E6,1000,1,2E6,1)", -199_979.902_009_799, 1e-9);
    near("=CUMPRINC(1E-4,3E6,1000,1,2E6,1)", -0.099_990_000_999_900_02, 1e-9);
    near("=CUMIPMT(1E-4,3E6,1000,1,2E6,0)", -200_000.0, 1e-9);
}

#[test]
fn poisson_and_gamma_of_large_shapes_are_computed() {
    // Q(x + 1, mean) and P(a, x) by mpmath at 40 digits; the series behind them gave up past
    // a shape of about 1E8 (#NUM!) and lost digits before that.
    near("=POISSON.DIST(1E9,1E9,TRUE)", 0.500_008_410_441_739, 1e-13);
    near("=POISSON.DIST(999000000,1E9,TRUE)", 7.603_874_886_270_09e-220, 1e-11);
    near("=GAMMA.DIST(1E6,1E6,1,TRUE)", 0.500_132_980_760_872_6, 1e-13);
}

#[test]
fn negative_binomial_of_large_counts_is_computed() {
    // I_½(a, a + 1) = ½ + 2^(−2a)/(a·B(a, a)) (the recurrence I_x(a, b+1) = I_x(a, b) +
    // x^a (1−x)^b/(b·B(a, b)) and I_½(a, a) = ½), a = 1E8: 0.50002820947914212597 by mpmath.
    // It was #NUM!.
    near("=NEGBINOM.DIST(1E8,1E8,0.5,TRUE)", 0.500_028_209_479_142_1, 1e-12);
}

#[test]
fn hypergeometric_tails_past_the_step_limit_are_computed() {
    // A sample of 1E8 from 1E9 holding 1E8 marked: the mean is 1E7. Hoeffding's bound
    // (sampling without replacement) gives P(X ≥ 2E7) ≤ e^(−2·0.1²·1E8) = e^(−2E6) and
    // P(X ≤ 1E6) ≤ e^(−2·0.09²·1E8): the cumulative probabilities are 1 and 0 to every digit
    // a double holds (by hand). Both sides of k held more than 10,000,000 terms: #NUM!.
    assert_eq!(number("=HYPGEOM.DIST(2E7,1E8,1E8,1E9,TRUE)"), 1.0);
    assert_eq!(number("=HYPGEOM.DIST(1E6,1E8,1E8,1E9,TRUE)"), 0.0);
}

#[test]
fn a_number_too_large_is_quoted_by_its_start_and_length() {
    // A literal past the largest double (1.797…E+308) is refused; its message quoted it
    // whole: a macro's literal of 1,000,000 digits made a 1 MB line.
    let digits = "9".repeat(400);
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let at = ncsheet::formula::address::parse_cell("A1").unwrap();
    let e = wb.set_input(0, at, &format!("={digits}")).unwrap_err().to_string();
    assert!(e.contains("is too large") && e.contains("400 characters"), "{e}");
    assert!(e.len() < 300, "{} bytes: {e}", e.len());
}

#[test]
fn a_cells_control_characters_do_not_reach_the_terminal() {
    // ECMA-48: ESC starts a control sequence (OSC `ESC ] 0 ; title BEL` sets a terminal's
    // title, CSI `ESC [ 31 m` colours what follows) and a carriage return moves to the line's
    // start, over what was shown. A csv cell's text printed raw by `eval` and `show`, and a
    // formula quoted raw in a message, drove the terminal; they are shown as pictures.
    let dir = std::env::temp_dir().join(format!("ncsheet-h4-escapes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("escapes.csv");
    std::fs::write(&file, "\"\u{1b}]0;title\u{7}x\",\u{1b}[31mred\r\n\"=SUM(\u{1b}[2J\"\n").unwrap();
    let path = file.to_str().unwrap();
    for args in [vec!["eval", path], vec!["show", path, "A1:B2"]] {
        let run = common::cli::ncsheet(&args);
        let out = format!("{}{}", run.stdout, run.stderr);
        assert!(!out.contains(['\u{1b}', '\u{7}']), "{args:?}: {out:?}");
        assert!(out.contains("\u{241b}]0;title\u{2407}x") && out.contains("\u{241b}[31mred"), "{args:?}: {out}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_nc_word_with_a_number_past_the_doubles_says_so_briefly() {
    // 400 nines are a number (past the largest double, 1.797…E+308), not "no number"; the
    // message quoted the whole word however long it was.
    let dir = std::env::temp_dir().join(format!("ncsheet-h4-ncword-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("huge.nc");
    std::fs::write(&file, format!("G90 G21\nG01 X{} F100\n", "9".repeat(400))).unwrap();
    let run = common::cli::ncsheet(&["nc", "check", file.to_str().unwrap()]);
    assert_ne!(run.code, 0);
    let said = run.stderr.lines().find(|l| l.contains("line 2")).unwrap_or_else(|| panic!("{}", run.stderr));
    assert!(said.contains("too large") && said.contains("400 characters"), "{said}");
    assert!(said.len() < 300, "{} bytes: {said}", said.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn interest_of_a_long_loan_keeps_its_digits() {
    // mpmath at 120 digits: the interest of payment 1E6 of 3E6 at 1E-4 on 1000 is -0.1 (the
    // balance is still about 1000), and payments 1 to 10 pay -1.0 in all; payments 1 to 1E6
    // pay 1E6 times the payment, -0.1·gⁿ/(gⁿ − 1) with gⁿ = e^300: -100000. FV's form of the
    // balance cancelled numbers near 1E+46: IPMT was 0 and the CUMIPMT of 1E6 periods 1.5E+29.
    near("=IPMT(1E-4,1E6,3E6,1000)", -0.1, 1e-9);
    near("=CUMIPMT(1E-4,3E6,1000,1,10,0)", -1.0, 1e-12);
    near("=CUMIPMT(1E-4,3E6,1000,1,1E6,0)", -100_000.0, 1e-9);
}

#[test]
fn principal_of_a_long_loan_keeps_its_digits() {
    // mpmath at 4,000 digits, PPMT as its definition (PMT − IPMT, each from FV's balance,
    // Microsoft's PPMT/IPMT reference) in exact arithmetic: the digits cancel past 1E+130,
    // where PMT − IPMT in doubles was 0 for the first two and −219902325.66 for the third.
    // Beside them the neighbours: in advance (type 1), a future value, a negative rate, a
    // tiny one, and CUMPRINC of a payment where (1 + rate)^nper overflows (it was #NUM!).
    for (formula, want) in [
        ("=PPMT(1E-4,1E6,3E6,1000)", -1.397_664_219_835_894_5e-88),
        ("=PPMT(1E-4,1E6,3E6,1000,0,1)", -1.397_524_467_389_155_6e-88),
        ("=PPMT(1E-4,3E6,3E6,1000)", -0.099_990_000_999_900_02),
        ("=PPMT(1E-4,3E6,3E6,1000,500,1)", -0.149_970_004_499_400_07),
        ("=PPMT(-0.01,10,3000,1000)", -9.135_172_474_837_145),
        ("=PPMT(-0.01,2,3000,1000,0,1)", -10.000_000_000_000_805),
        ("=PPMT(1E-300,5,10,1000)", -100.0),
        ("=CUMPRINC(0.001,2E6,1000,2E6,2E6,0)", -0.999_000_999_000_999),
    ] {
        near(formula, want, 1e-12);
    }
}
