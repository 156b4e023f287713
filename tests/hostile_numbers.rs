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
/// subnormal, zero, an array of the largest, and an array of no items (VBA's `Array()`, the
/// one function that makes one).
const EDGES: [&str; 7] =
    ["1E+308", "-1E+308", "2.2250738585072014E-308", "5E-324", "0", "{1E+308,1E+308,1E+308}", "VBA.ARRAY()"];

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
    assert!(formulas.len() > 10_000, "{} calls: the registry was not read", formulas.len());
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
