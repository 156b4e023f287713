//! Hostile input, numbers at the edges (issue 30): values that came out silently wrong where a
//! cycle, a criterion or a number near the limits of a double met the engine's shortcuts.

mod common;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::{Iteration, Workbook};

// ---------------------------------------------------------------------------------------
// Iterative calculation: a cycle made by INDEX, OFFSET or INDIRECT

/// A column A1:A`n` where A1 = A`n`+1 and each later cell is the one above plus 1, the link
/// written by `above(row)`, iterated `count` rounds as one recalculation of a loaded file.
fn iterated_chain(n: u32, count: u32, above: impl Fn(u32) -> String) -> Workbook {
    let mut wb = Workbook::with_sheet();
    wb.set_iteration(Some(Iteration { count, max_change: 0.0 }));
    let a = |row: u32| parse_cell(&format!("A{row}")).unwrap();
    wb.set_input_deferred(0, a(1), &format!("=A{n}+1")).unwrap();
    for row in 2..=n {
        wb.set_input_deferred(0, a(row), &format!("={}+1", above(row))).unwrap();
    }
    wb.recalculate();
    wb
}

#[test]
fn a_cycle_through_index_offset_or_indirect_iterates_as_the_plain_chain() {
    // Each round computes A1..A50 in order from 0: round r leaves A1 = 50(r-1)+1 and
    // A50 = 50r, so 10 rounds end at A1 = 451, A50 = 500 (exact arithmetic). LibreOffice
    // (iteration on, 10 steps) gives the INDEX form the values of the plain one too.
    // The cycle of the last three forms is found only once their evaluation links it; the
    // iteration started from what that first evaluation left and ended 2 above.
    type CellAbove = fn(u32) -> String;
    let forms: [(&str, CellAbove); 4] = [
        ("plain", |row| format!("A{}", row - 1)),
        ("by INDEX", |row| format!("INDEX(A:A,{})", row - 1)),
        ("by OFFSET", |row| format!("OFFSET(A{row},-1,0)")),
        ("by INDIRECT", |row| format!("INDIRECT(\"A{}\")", row - 1)),
    ];
    for (name, above) in forms {
        let wb = iterated_chain(50, 10, above);
        let at = |cell: &str| wb.value(0, parse_cell(cell).unwrap());
        assert_eq!((at("A1"), at("A50")), (Value::Number(451.0), Value::Number(500.0)), "{name}");
    }
}

// ---------------------------------------------------------------------------------------
// Every function at the edges of doubles

/// Arguments at the edges of doubles: the largest and smallest, the smallest normal and
/// subnormals of both signs, zero and a negative zero made by arithmetic (`-0*1`: a formula
/// cannot type one), the last whole numbers a double counts one by one (2^53) and 2^63 (past
/// any 64-bit integer a function might count with), 1E+15 (Excel's 15 digits) and 2^32 (a huge
/// count, past any 32-bit one), arrays of the largest (two of one sign, and of both signs), an
/// array of no items (VBA's `Array()`, the one function that makes one), a missing argument,
/// and texts, empty and not a number.
const EDGES: [&str; 19] = [
    "1E+308",
    "-1E+308",
    "2.2250738585072014E-308",
    "5E-324",
    "1E-320",
    "-1E-320",
    "0",
    "-0*1",
    "9007199254740992",
    "-9007199254740993",
    "9223372036854775808",
    "1E+15",
    "4294967296",
    "{1E+308,1E+308,1E+308}",
    "{1E+308,-1E+308}",
    "VBA.ARRAY()",
    "",
    "\"\"",
    "\"x\"",
];

/// The calls of `name` taking `arity` arguments with an edge value in each place in turn
/// (the others 1), and in every place at once.
fn edge_calls(name: &str, arity: usize) -> Vec<String> {
    let call = |args: Vec<&str>| format!("={name}({})", args.join(","));
    let mut calls = Vec::new();
    for edge in EDGES {
        calls.push(call(vec![edge; arity]));
        for place in 0..arity {
            let mut args = vec!["1"; arity];
            args[place] = edge;
            calls.push(call(args));
        }
    }
    calls
}

/// What is wrong with the values `formula` leaves in A1:D4 (its spill included), if anything.
fn edge_fault(formula: &str) -> Option<String> {
    let run = std::panic::catch_unwind(|| {
        let mut wb = Workbook::with_sheet();
        let _ = wb.set_input_deferred(0, parse_cell("A1").unwrap(), formula);
        wb.recalculate();
        let mut shown = Vec::new();
        for row in 0..4 {
            for col in 0..4 {
                shown.push(wb.value(0, ncsheet::formula::Pos::new(row, col)));
            }
        }
        shown
    });
    let Ok(values) = run else { return Some(format!("{formula}: panicked")) };
    values.iter().find_map(|v| match v {
        Value::Number(n) if !n.is_finite() => Some(format!("{formula}: {n}")),
        Value::Number(n) if *n != 0.0 && n.abs() < f64::MIN_POSITIVE => Some(format!("{formula}: subnormal {n:e}")),
        Value::Number(n) if v.to_string() == "-0" => Some(format!("{formula}: shown as -0 ({n})")),
        _ => None,
    })
}

#[test]
fn no_function_at_the_edges_of_doubles_panics_or_leaks_inf_nan_or_minus_zero() {
    // Excel keeps no infinity, NaN, subnormal or negative zero in a cell: a result past the
    // doubles is #NUM! (MS-XLSX stores only finite numbers; Excel's "Floating-point
    // arithmetic may give inaccurate results" names 1E+308 its largest number).
    let mut formulas = std::collections::BTreeSet::new();
    for spec in ncsheet::eval::functions::REGISTRY.iter() {
        // Functions that read the clock, chance or the host are swept like the rest.
        for arity in spec.min_args..=spec.max_args.min(spec.min_args + 1).min(4) {
            formulas.extend(edge_calls(spec.name, arity));
        }
    }
    assert!(formulas.len() > 25_000, "{} calls: the registry was not read", formulas.len());
    let faults: Vec<String> = formulas.iter().filter_map(|f| edge_fault(f)).collect();
    assert!(faults.is_empty(), "{} faults:\n{}", faults.len(), faults.join("\n"));
}

// ---------------------------------------------------------------------------------------
// Dispersion near the largest double

fn a1(formula: &str) -> Value {
    common::sheet::eval_a1(formula).0
}

/// Whether `v` is a number within 1E-14 of `want`, relatively.
fn near(v: &Value, want: f64) -> bool {
    matches!(v, Value::Number(n) if (n - want).abs() <= want.abs() * 1e-14)
}

#[test]
fn deviations_near_the_largest_double_are_finite_where_the_result_is() {
    // Exact arithmetic: 1E+308 and -1E+308 have mean 0 and squared deviations 2E+616, past
    // the doubles; the sample deviation is √2·1E+308 and the population one 1E+308. The
    // sums of squares overflowed and each was #NUM!.
    let root2 = std::f64::consts::SQRT_2 * 1e308;
    assert!(near(&a1("=STDEV(1E+308,-1E+308)"), root2), "{:?}", a1("=STDEV(1E+308,-1E+308)"));
    assert!(near(&a1("=STDEV.S(1E+308,-1E+308)"), root2));
    assert!(near(&a1("=STDEVA(1E+308,-1E+308)"), root2));
    assert!(near(&a1("=STDEV.P(1E+308,-1E+308)"), 1e308));
    // Equal values deviate by nothing: 0, however large they are.
    for f in ["=STDEV(1E+308,1E+308)", "=VAR(1E+308,1E+308)", "=VAR.P(-1E+308,-1E+308)", "=DEVSQ(1E+308,1E+308,1E+308)"]
    {
        assert_eq!(a1(f), Value::Number(0.0), "{f}");
    }
    // The variance itself past the doubles stays #NUM! (2E+616).
    assert_eq!(a1("=VAR(1E+308,-1E+308)"), Value::Error(ncsheet::eval::XlError::Num));
    // The database functions compute it the same way.
    let mut wb = Workbook::with_sheet();
    for (cell, input) in
        [("A1", "x"), ("A2", "1E+308"), ("A3", "-1E+308"), ("C1", "x"), ("E1", "=DSTDEV(A1:A3,1,C1:C2)")]
    {
        wb.set_input(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    let dstdev = wb.value(0, parse_cell("E1").unwrap());
    assert!(near(&dstdev, root2), "{dstdev:?}");
}

// ---------------------------------------------------------------------------------------
// Limits reached say so

#[test]
fn munit_past_the_array_limit_names_it() {
    // docs/limits.md: an array past 2^24 items is #NUM! with a note naming its size and the
    // limit; MUNIT(5000) (25,000,000 items) was #NUM! without one.
    let (value, notes, _) = common::sheet::eval_a1("=MUNIT(5000)");
    assert_eq!(value, Value::Error(ncsheet::eval::XlError::Num));
    assert!(notes.iter().any(|n| n.contains("5000") && n.contains("16777216")), "{notes:?}");
}

// ---------------------------------------------------------------------------------------
// Rates of cash flows near the largest double

#[test]
fn irr_and_xirr_of_flows_near_the_largest_double_find_the_rate() {
    // -F + F/(1+r) + F/(1+r)^2 = 0 for any F: with x = 1/(1+r), x^2 + x - 1 = 0, so
    // x = (sqrt(5) - 1)/2 and r = (1 + sqrt(5))/2 - 1 = 0.6180339887498949 (worked by hand;
    // the rate of {-1,1,1} is the same). At F = 1E308 the slope at the guess overflows to
    // -inf, and IRR and XIRR gave the guess 0.1 back as their answer (issue 30).
    let want = (1.0 + 5f64.sqrt()) / 2.0 - 1.0;
    for f in [
        "=IRR({-1E+308,1E+308,1E+308})",
        "=IRR({-1E+308,1E+308,1E+308},0.5)",
        // Whole years of 365 days apart: the same equation (XIRR's exponent is days/365).
        "=XIRR({-1E+308,1E+308,1E+308},{1,366,731})",
    ] {
        let (value, _, _) = common::sheet::eval_a1(f);
        match value {
            Value::Number(r) => assert!((r - want).abs() <= 1e-12, "{f}: {r}, want {want}"),
            other => panic!("{f}: {other:?}"),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Annuities whose growth (1 + rate)^nper passes the doubles

#[test]
fn payments_past_an_overflowing_growth_are_the_numbers_they_are() {
    // (1 + rate)^nper past 1.8E+308 made ∞/∞ in PMT and PV: #NUM! where the payment is an
    // ordinary number. Values by mpmath at 60 digits from the annuity formula of Excel's PMT
    // and PV pages, −(fv + pv·g)·rate / ((1 + rate·type)(g − 1)) and
    // −(fv + pmt(1 + rate·type)(g − 1)/rate)/g with g = (1 + rate)^nper; LibreOffice gives
    // PV(1000,1000,1) = −0.001 too (its PMT and CUMIPMT are #NUM!).
    let cases = [
        ("=PMT(1,2000,1000)", -1000.0),
        ("=PMT(1E+10,1E+10,1000)", -1e13),
        ("=PMT(1,2000,1000,0,1)", -500.0),
        ("=PMT(1000,1000,1000)", -1e6),
        ("=PV(1000,1000,1)", -0.001),
        ("=PV(1,2000,1,1E+300)", -1.0),
        // The interest of the first two payments: −1000 each (each period's interest is
        // rate × the balance, and a payment of about −1000 leaves the balance at 1000).
        ("=CUMIPMT(1,2000,1000,1,2,0)", -2000.0),
        ("=CUMIPMT(1000,1000,1000,1,2,0)", -2e6),
        ("=IPMT(1,2,2000,1000)", -1000.0),
    ];
    for (formula, want) in cases {
        let v = a1(formula);
        assert!(near(&v, want), "{formula}: {v:?}, want {want}");
    }
    // FV itself past the doubles stays #NUM! (2^2000 · 1).
    assert_eq!(a1("=FV(1,2000,0,-1)"), Value::Error(ncsheet::eval::XlError::Num));
}

#[test]
fn nominal_of_many_periods_is_excels_formula_in_doubles() {
    // Excel computes NOMINAL as ((1 + effect)^(1/npery) − 1)·npery in doubles: the values it
    // stored in the IronCalc corpus (calc_tests/FINANCIAL/NOMINAL_EFFECT.xlsx: 0.5 over 10
    // periods is 0.41379743992410623, 8 over 7 is 2.5811667464954122) are that formula's to
    // the last bit, where ln_1p and exp_m1 differ in the last digits. At 1E+15 periods the power
    // is 1 + 3111 units of its last place, so the formula gives 3111·2^-52·1E+15 =
    // 690.7807659217724 (Python's float arithmetic; the exact value is 690.77552789845, by
    // mpmath): a rounding of the power that Excel's own arithmetic makes, kept as Excel keeps it.
    let v = a1("=NOMINAL(1E+300,1E+15)");
    assert!(near(&v, 3111.0 * f64::EPSILON * 1e15), "{v:?}");
    // Excel's own example (NOMINAL function page): NOMINAL(5.3543%, 4) = 0.05250032.
    let v = a1("=NOMINAL(0.053543,4)");
    assert!(matches!(v, Value::Number(n) if (n - 0.052_500_32).abs() < 5e-9), "{v:?}");
}

#[test]
fn declining_balance_over_a_long_life_is_exact_to_its_digits() {
    // VDB(1000,0,1E7,0,10): ten periods of double-declining balance at 2/1E+7 a period,
    // 1000·(1 − (1 − 2E-7)^10) = 0.00199999820000095999966… (mpmath at 40 digits); it steps
    // the ten periods, not the life.
    let v = a1("=VDB(1000,0,1E+7,0,10)");
    assert!(near(&v, 0.001_999_998_200_000_96), "{v:?}");
}
