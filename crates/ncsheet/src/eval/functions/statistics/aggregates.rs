//! Statistical aggregates: MIN, MAX, AVERAGE, MEDIAN, the COUNT family and the
//! conditional forms (COUNTIF, SUMIF, AVERAGEIF, COUNTIFS, SUMIFS, AVERAGEIFS, MINIFS, MAXIFS).

use crate::eval::coerce::parse_number;
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{
    for_each_number, for_each_value, given, lift_values, number_result, numbers, ArgSet, Ctx, FnSpec, Source, MANY,
};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::criteria::{matching_cells, CellBlock, CriteriaMatcher, Criterion, Summary};
use crate::eval::functions::statistics::Total;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "AVERAGE",
        1,
        MANY,
        average,
        "AVERAGE(number1, [number2], ...)",
        "Arithmetic mean; #DIV/0! when there are no numbers",
    )
    .biff(5)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "AVERAGEIF",
        2,
        3,
        averageif,
        "AVERAGEIF(range, criteria, [average_range])",
        "Mean of the cells whose range cell meets the criteria",
    )
    .biff(483)
    .range_args(ArgSet::except(1)),
    FnSpec::value(
        "AVERAGEIFS",
        3,
        MANY,
        averageifs,
        "AVERAGEIFS(average_range, criteria_range1, criteria1, ...)",
        "Mean of the cells where every criteria range meets its criteria",
    )
    .biff(484)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "COUNT",
        1,
        MANY,
        count,
        "COUNT(value1, [value2], ...)",
        "How many numbers (typed numeric text and booleans count too)",
    )
    .biff(0)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "COUNTA",
        1,
        MANY,
        counta,
        "COUNTA(value1, [value2], ...)",
        "How many values are not empty (errors and \"\" count)",
    )
    .biff(169)
    .range_args(ArgSet::ALL),
    FnSpec::value("COUNTBLANK", 1, 1, countblank, "COUNTBLANK(range)", "How many cells are empty or hold \"\"")
        .biff(347)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "COUNTIF",
        2,
        2,
        countif,
        "COUNTIF(range, criteria)",
        "How many cells meet the criteria (\"<5\", \"<>x\", \"ab*\", 3, …)",
    )
    .biff(346)
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "COUNTIFS",
        2,
        MANY,
        countifs,
        "COUNTIFS(criteria_range1, criteria1, ...)",
        "How many positions meet every criteria",
    )
    .biff(481)
    .range_args(ArgSet::ALL),
    FnSpec::value("MAX", 1, MANY, max, "MAX(number1, [number2], ...)", "Largest number; 0 when there is none")
        .biff(7)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "MAXIFS",
        3,
        MANY,
        maxifs,
        "MAXIFS(max_range, criteria_range1, criteria1, ...)",
        "Largest number where every criteria range meets its criteria; 0 when none",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "MEDIAN",
        1,
        MANY,
        median,
        "MEDIAN(number1, [number2], ...)",
        "Middle number (mean of the two middle ones for an even count)",
    )
    .biff(227)
    .range_args(ArgSet::ALL),
    FnSpec::value("MIN", 1, MANY, min, "MIN(number1, [number2], ...)", "Smallest number; 0 when there is none")
        .biff(6)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "MINIFS",
        3,
        MANY,
        minifs,
        "MINIFS(min_range, criteria_range1, criteria1, ...)",
        "Smallest number where every criteria range meets its criteria; 0 when none",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "SUMIF",
        2,
        3,
        sumif,
        "SUMIF(range, criteria, [sum_range])",
        "Sum of the cells whose range cell meets the criteria",
    )
    .biff(345)
    .range_args(ArgSet::except(1)),
    FnSpec::value(
        "SUMIFS",
        3,
        MANY,
        sumifs,
        "SUMIFS(sum_range, criteria_range1, criteria1, ...)",
        "Sum of the cells where every criteria range meets its criteria",
    )
    .biff(482)
    .range_args(ArgSet::ALL),
];

// ---- plain aggregates ---------------------------------------------------------------------

fn max(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut best: Option<f64> = None;
    for_each_number(ctx, args, &mut |n| best = Some(best.map_or(n, |b| b.max(n))))?;
    Ok(Value::Number(best.unwrap_or(0.0)))
}

fn min(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut best: Option<f64> = None;
    for_each_number(ctx, args, &mut |n| best = Some(best.map_or(n, |b| b.min(n))))?;
    Ok(Value::Number(best.unwrap_or(0.0)))
}

fn average(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (mut total, mut count) = (Total::default(), 0usize);
    for_each_number(ctx, args, &mut |n| {
        total.add(n);
        count += 1;
    })?;
    mean(total, count).map(number_result)
}

fn mean(total: Total, count: usize) -> XlResult<f64> {
    if count == 0 {
        Err(XlError::Div0)
    } else {
        Ok(total.over(count as f64))
    }
}

fn median(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut xs = numbers(ctx, args)?;
    if xs.is_empty() {
        return Err(XlError::Num);
    }
    xs.sort_by(f64::total_cmp);
    let mid = xs.len() / 2;
    // Halved before adding: the sum of two numbers near 1E+308 would overflow.
    let m = if xs.len() % 2 == 1 { xs[mid] } else { xs[mid - 1] / 2.0 + xs[mid] / 2.0 };
    Ok(Value::Number(m))
}

/// COUNT: numbers anywhere; typed booleans and numeric text too. Errors are not counted and,
/// unlike in SUM, do not stop the count.
fn count(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let mut n = 0usize;
    for_each_value(ctx, args, &mut |v, source| {
        let counted = match (v, source) {
            (Value::Number(_), _) => true,
            (Value::Bool(_), Source::Direct) => true,
            (Value::Text(t), Source::Direct) => parse_number(t, dates).is_some(),
            _ => false,
        };
        n += usize::from(counted);
        Ok(())
    })?;
    Ok(Value::Number(n as f64))
}

/// COUNTA: everything but empty cells, errors and empty text included.
fn counta(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut n = 0usize;
    for_each_value(ctx, args, &mut |v, _| {
        n += usize::from(!v.is_blank());
        Ok(())
    })?;
    Ok(Value::Number(n as f64))
}

fn countblank(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let range = CellBlock::read(ctx, &args[0])?;
    // The criterion "" is exactly COUNTBLANK's test: empty cells and empty text.
    let m = matching_cells(&[range], &[Criterion::new(&Value::text(""), DateSystem::From1900)])?;
    Ok(Value::Number((m.cells.len() + m.blanks_beyond) as f64))
}

// ---- conditional aggregates ---------------------------------------------------------------

/// The arguments of a conditional aggregate: the cells aggregated (none for COUNTIF(S)) and
/// the (range, criteria) pairs. Criteria are kept as values: an array of criteria gives an
/// array of results, one per criterion (`SUMIF(A:A, {"x";"y"}, B:B)` spills).
struct Conditions {
    target: Option<CellBlock>,
    ranges: Vec<CellBlock>,
    criteria: Vec<Value>,
    /// The workbook's date system, in which the criteria read date text.
    dates: DateSystem,
}

/// How the aggregated numbers become the result.
type Aggregate = fn(&[f64]) -> XlResult<f64>;

/// The same result made from the numbers' [`Summary`] (their sum, or their extreme) and
/// their count, where an index summarizes them.
type OfSummary = fn(f64, usize) -> XlResult<f64>;

impl Conditions {
    /// `COUNTIF(range, criteria)`, `SUMIF(range, criteria, [sum_range])`: the sum range
    /// takes the criteria range's shape from its own top-left cell.
    fn single(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Conditions> {
        let range = CellBlock::read(ctx, &args[0])?;
        let criteria = vec![ctx.eval(&args[1])];
        let target = match given(args, 2) {
            Some(e) => CellBlock::read_sized(ctx, e, range.rows, range.cols)?,
            None => range.clone(),
        };
        Ok(Conditions { target: Some(target), ranges: vec![range], criteria, dates: ctx.dates() })
    }

    /// `COUNTIFS(range1, criteria1, …)` and, with a target, `SUMIFS(sum_range, range1,
    /// criteria1, …)`.
    fn pairs(ctx: &mut Ctx, args: &[Expr], with_target: bool) -> XlResult<Conditions> {
        let (target, pairs) =
            if with_target { (Some(CellBlock::read(ctx, &args[0])?), &args[1..]) } else { (None, args) };
        if pairs.len() % 2 != 0 {
            return Err(XlError::Value);
        }
        let mut ranges = Vec::new();
        let mut criteria = Vec::new();
        for pair in pairs.chunks(2) {
            ranges.push(CellBlock::read(ctx, &pair[0])?);
            criteria.push(ctx.eval(&pair[1]));
        }
        Ok(Conditions { target, ranges, criteria, dates: ctx.dates() })
    }

    /// How many positions meet every criterion, per criteria item.
    fn count(&self, ctx: &mut Ctx) -> XlResult<Value> {
        let matcher = CriteriaMatcher::new(&self.ranges, &self.criteria, self.dates);
        matcher.within_scan_limit(ctx, &self.criteria, true)?;
        let counts = lift_values(&self.criteria, &|items| {
            let criteria: Vec<Criterion> = items.iter().map(|v| Criterion::new(v, self.dates)).collect();
            Ok(Value::Number(matcher.count(&criteria)? as f64))
        });
        ctx.charge(matcher.work.get());
        counts
    }

    /// `aggregate` of the target's numbers at the matching positions, per criteria item.
    /// Text, booleans and blanks there are skipped; an error there is the result.
    /// `of_summary` makes the same result from their `summary` and count, where the
    /// matcher's index answers (many comparison or `<>` criteria) without testing cells.
    fn aggregate(
        &self,
        ctx: &mut Ctx,
        aggregate: Aggregate,
        summary: Summary,
        of_summary: OfSummary,
    ) -> XlResult<Value> {
        let target = self.target.as_ref().expect("an aggregate has a target range");
        if !target.same_shape(&self.ranges[0]) {
            return Err(XlError::Value);
        }
        let ranges: Vec<CellBlock> = self.ranges.iter().map(|r| r.read_as_far_as(target)).collect();
        let matcher = CriteriaMatcher::new(&ranges, &self.criteria, self.dates).summarizing(target, summary);
        matcher.within_scan_limit(ctx, &self.criteria, false)?;
        let results = lift_values(&self.criteria, &|items| {
            let criteria: Vec<Criterion> = items.iter().map(|v| Criterion::new(v, self.dates)).collect();
            if let Some(summarized) = matcher.indexed_summary(&criteria) {
                let (summary, count) = summarized?;
                return of_summary(summary, count).map(number_result);
            }
            let m = matcher.matches(&criteria)?;
            let mut xs = Vec::with_capacity(m.cells.len());
            for &(r, c) in &m.cells {
                match target.get(r, c) {
                    Value::Number(n) => xs.push(*n),
                    Value::Error(e) => return Err(*e),
                    _ => {}
                }
            }
            aggregate(&xs).map(number_result)
        });
        ctx.charge(matcher.work.get());
        results
    }
}

fn total(xs: &[f64]) -> XlResult<f64> {
    // From 0, not Rust's `sum()`, whose sum of no numbers is -0: SUMIF matching nothing is 0.
    Ok(xs.iter().fold(0.0, |a, x| a + x))
}

fn sum_of(total: f64, _count: usize) -> XlResult<f64> {
    Ok(total)
}

/// MINIFS and MAXIFS of no number are 0.
fn extreme_or_zero(extreme: f64, count: usize) -> XlResult<f64> {
    Ok(if count == 0 { 0.0 } else { extreme })
}

/// The mean from a criteria index's plain sum (many criteria over one range; the summary is
/// kept as a plain sum there).
fn mean_of_sum(sum: f64, count: usize) -> XlResult<f64> {
    if count == 0 {
        Err(XlError::Div0)
    } else {
        Ok(sum / count as f64)
    }
}

fn arithmetic_mean(xs: &[f64]) -> XlResult<f64> {
    let mut total = Total::default();
    xs.iter().for_each(|&x| total.add(x));
    mean(total, xs.len())
}

fn smallest(xs: &[f64]) -> XlResult<f64> {
    Ok(xs.iter().copied().reduce(f64::min).unwrap_or(0.0))
}

fn largest(xs: &[f64]) -> XlResult<f64> {
    Ok(xs.iter().copied().reduce(f64::max).unwrap_or(0.0))
}

fn countif(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::single(ctx, args)?.count(ctx)
}

fn countifs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::pairs(ctx, args, false)?.count(ctx)
}

fn sumif(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::single(ctx, args)?.aggregate(ctx, total, Summary::Total, sum_of)
}

fn averageif(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::single(ctx, args)?.aggregate(ctx, arithmetic_mean, Summary::Total, mean_of_sum)
}

fn sumifs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::pairs(ctx, args, true)?.aggregate(ctx, total, Summary::Total, sum_of)
}

fn averageifs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::pairs(ctx, args, true)?.aggregate(ctx, arithmetic_mean, Summary::Total, mean_of_sum)
}

fn minifs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::pairs(ctx, args, true)?.aggregate(ctx, smallest, Summary::Smallest, extreme_or_zero)
}

fn maxifs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Conditions::pairs(ctx, args, true)?.aggregate(ctx, largest, Summary::Largest, extreme_or_zero)
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::testing::{err, n};
    use crate::eval::value::{Value, XlError};

    /// A1:A6 = 1, "2", TRUE, 4, "x", (blank); B1:B6 = 10..60; C1:C3 = "apple", "Banana", "".
    fn env() -> MapEnv {
        MapEnv::with(&[
            ("A1", n(1.0)),
            ("A2", Value::text("2")),
            ("A3", Value::Bool(true)),
            ("A4", n(4.0)),
            ("A5", Value::text("x")),
            ("B1", n(10.0)),
            ("B2", n(20.0)),
            ("B3", n(30.0)),
            ("B4", n(40.0)),
            ("B5", n(50.0)),
            ("B6", n(60.0)),
            ("C1", Value::text("apple")),
            ("C2", Value::text("Banana")),
            ("C3", Value::text("")),
            ("D1", err(XlError::Div0)),
        ])
    }

    /// Excel has no negative zero: a conditional sum that matches nothing is 0, whose sign a
    /// later ATAN2 or 1/x would otherwise see.
    #[test]
    fn a_conditional_sum_of_nothing_is_positive_zero() {
        let env = env();
        for f in ["=SUMIF(B1:B6,\">100\")", "=SUMIFS(B1:B6,B1:B6,\">100\")", "=SUMIF(C1:C3,\"zzz\",B1:B3)"] {
            match env.eval(f) {
                Value::Number(x) => assert!(x == 0.0 && x.is_sign_positive(), "{f}: {x:?}"),
                other => panic!("{f}: {other:?}"),
            }
        }
    }

    #[test]
    fn aggregates_skip_text_in_ranges_but_coerce_typed_arguments() {
        let env = env();
        assert_eq!(env.eval("=MAX(A1:A6)"), n(4.0));
        assert_eq!(env.eval("=MIN(A1:A6)"), n(1.0));
        assert_eq!(env.eval("=MIN(A1:A6,\"-1\")"), n(-1.0));
        assert_eq!(env.eval("=MAX(C1:C3)"), n(0.0));
        assert_eq!(env.eval("=AVERAGE(A1:A6)"), n(2.5));
        assert_eq!(env.eval("=AVERAGE(A1:A6,TRUE)"), n(2.0));
        assert_eq!(env.eval("=AVERAGE(C1:C3)"), err(XlError::Div0));
        assert_eq!(env.eval("=AVERAGE(A1,D1)"), err(XlError::Div0));
        assert_eq!(env.eval("=MIN(\"x\")"), err(XlError::Value));
        assert_eq!(env.eval("=MEDIAN(B1:B6)"), n(35.0));
        assert_eq!(env.eval("=MEDIAN(3,1,2)"), n(2.0));
        assert_eq!(env.eval("=MEDIAN(C1:C3)"), err(XlError::Num));
    }

    #[test]
    fn counts_follow_excel() {
        let env = env();
        assert_eq!(env.eval("=COUNT(A1:A6)"), n(2.0));
        assert_eq!(env.eval("=COUNT(1,\"2\",TRUE,\"x\",#N/A)"), n(3.0));
        assert_eq!(env.eval("=COUNT(A1:D6)"), n(8.0));
        assert_eq!(env.eval("=COUNTA(A1:A6)"), n(5.0));
        assert_eq!(env.eval("=COUNTA(C1:D3)"), n(4.0));
        assert_eq!(env.eval("=COUNTBLANK(A1:A6)"), n(1.0));
        assert_eq!(env.eval("=COUNTBLANK(C1:C4)"), n(2.0));
    }

    #[test]
    fn countif_reads_criteria_as_excel_does() {
        let env = env();
        assert_eq!(env.eval("=COUNTIF(B1:B6,\">25\")"), n(4.0));
        assert_eq!(env.eval("=COUNTIF(B1:B6,\"<=20\")"), n(2.0));
        assert_eq!(env.eval("=COUNTIF(A1:A6,2)"), n(1.0));
        assert_eq!(env.eval("=COUNTIF(A1:A6,\"<>x\")"), n(5.0));
        assert_eq!(env.eval("=COUNTIF(C1:C3,\"?a*\")"), n(1.0));
        assert_eq!(env.eval("=COUNTIF(C1:C3,\"A*\")"), n(1.0));
        assert_eq!(env.eval("=COUNTIF(C1:C4,\"\")"), n(2.0));
        assert_eq!(env.eval("=COUNTIF(A1:D1,D1)"), n(1.0));
        assert_eq!(env.eval("=COUNTIF(A:A,\"\")"), n(1_048_576.0 - 5.0));
        assert_eq!(env.eval("=SUM(COUNTIF(B1:B6,{\">10\",\">50\"}))"), n(6.0));
    }

    #[test]
    fn sumif_and_averageif_follow_excel() {
        let env = env();
        assert_eq!(env.eval("=SUMIF(B1:B6,\">25\")"), n(180.0));
        assert_eq!(env.eval("=SUMIF(C1:C3,\"*an*\",B1:B3)"), n(20.0));
        // The sum range takes the criteria range's shape from its top-left cell.
        assert_eq!(env.eval("=SUMIF(C1:C3,\"<>x\",B1)"), n(60.0));
        assert_eq!(env.eval("=AVERAGEIF(B1:B6,\">25\")"), n(45.0));
        assert_eq!(env.eval("=AVERAGEIF(B1:B6,\">100\")"), err(XlError::Div0));
        assert_eq!(env.eval("=SUMIF(A1:A4,1,D1:D4)"), err(XlError::Div0));
    }

    #[test]
    fn multi_criteria_functions_follow_excel() {
        let env = env();
        assert_eq!(env.eval("=COUNTIFS(B1:B6,\">15\",B1:B6,\"<45\")"), n(3.0));
        assert_eq!(env.eval("=SUMIFS(B1:B6,A1:A6,\">0\",B1:B6,\">15\")"), n(40.0));
        assert_eq!(env.eval("=AVERAGEIFS(B1:B6,B1:B6,\">15\")"), n(40.0));
        assert_eq!(env.eval("=MINIFS(B1:B6,B1:B6,\">15\")"), n(20.0));
        assert_eq!(env.eval("=MAXIFS(B1:B6,A1:A6,\"<>x\")"), n(60.0));
        assert_eq!(env.eval("=MAXIFS(B1:B6,B1:B6,\">100\")"), n(0.0));
        assert_eq!(env.eval("=SUMIFS(B1:B6,A1:A5,\">0\")"), err(XlError::Value));
    }

    /// A small linear congruential sequence: the same inputs on every run.
    struct Lcg(u64);

    impl Lcg {
        fn pick<'p>(&mut self, pool: &'p [Value]) -> &'p Value {
            self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            &pool[(self.0 >> 33) as usize % pool.len()]
        }
    }

    /// The values criteria ranges hold and criteria name: numbers, the same as text, text
    /// in other cases, booleans, empty cells and empty text, errors.
    fn keys_pool() -> Vec<Value> {
        let mut pool: Vec<Value> = (1..=6).map(|i| n(i as f64)).collect();
        pool.extend(["3", "Apple", "APPLE", "apple", "banana", "", "b"].map(Value::text));
        pool.extend([Value::Bool(true), Value::Bool(false), Value::Blank, Value::Blank, err(XlError::NA), n(2.5)]);
        pool
    }

    /// What is aggregated: integers mostly, with text, booleans and blanks that are skipped;
    /// `hard` adds what an index must not reorder (fractions, -0) and errors.
    fn targets_pool(hard: bool) -> Vec<Value> {
        let mut pool: Vec<Value> = (-20..=20).map(|i| n(f64::from(i))).collect();
        pool.extend([Value::text("7"), Value::Bool(true), Value::Blank]);
        if hard {
            pool.extend([n(0.1), n(-0.0), n(1e300), err(XlError::Div0), err(XlError::NA)]);
        }
        pool
    }

    /// Rows 1 … `rows` of columns A, C, D drawn from the keys, B from the targets; criteria
    /// items E1:G40 from the keys.
    fn generated(seed: u64, rows: u32, hard: bool) -> MapEnv {
        let (keys, targets) = (keys_pool(), targets_pool(hard));
        let mut rng = Lcg(seed);
        let mut env = MapEnv::default();
        for row in 0..rows {
            for (col, pool) in [(0, &keys), (1, &targets), (2, &keys), (3, &keys)] {
                env.cells.insert((row, col), rng.pick(pool).clone());
            }
        }
        for row in 0..40 {
            for col in 4..7 {
                env.cells.insert((row, col), rng.pick(&keys).clone());
            }
        }
        env
    }

    /// `formula` with `#` standing for E1:E40 (and `$`, `%` for F1:F40, G1:G40): a call
    /// given 40 criteria at once, which indexes its range, against the same call given one
    /// criterion at a time, which tests every cell (Excel's rules as the unit tests above
    /// check them).
    fn assert_indexed_as_scanned(env: &MapEnv, formula: &str) {
        let spelled = |e: &str, f: &str, g: &str| formula.replace('#', e).replace('$', f).replace('%', g);
        let Value::Array(all) = env.eval(&spelled("E1:E40", "F1:F40", "G1:G40")) else {
            panic!("{formula}: no array");
        };
        for row in 1..=40 {
            let one = spelled(&format!("E{row}"), &format!("F{row}"), &format!("G{row}"));
            assert_eq!(all.data[row - 1], env.eval(&one), "{one}");
        }
    }

    #[test]
    fn criteria_arrays_answered_by_an_index_equal_one_criterion_at_a_time() {
        let mut formulas = Vec::new();
        for op in ["", "=", "<>", "<", "<=", ">", ">="] {
            formulas.push(format!("=SUMIF(A1:A150,\"{op}\"&#,B1:B150)"));
            formulas.push(format!("=AVERAGEIF(A1:A150,\"{op}\"&#,B1:B150)"));
            formulas.push(format!("=MINIFS(B1:B150,A1:A150,\"{op}\"&#)"));
            formulas.push(format!("=MAXIFS(B1:B150,A1:A150,\"{op}\"&#)"));
            formulas.push(format!("=MAXIFS(B1:B150,C1:C150,\"<>b\",A1:A150,\"{op}\"&#)"));
            formulas.push(format!("=SUMIFS(B1:B150,A1:A150,\"{op}\"&#,D1:D150,\">2\")"));
        }
        // Three and four criteria arrays paired item by item, with and without a fixed one.
        formulas.push("=COUNTIFS(A1:A150,#,C1:C150,$,D1:D150,%)".to_string());
        formulas.push("=COUNTIFS(A1:A150,#,C1:C150,$,D1:D150,%,B1:B150,\">0\")".to_string());
        formulas.push("=SUMIFS(B1:B150,A1:A150,#,C1:C150,$,D1:D150,%)".to_string());
        formulas.push("=MINIFS(B1:B150,A1:A150,#,C1:C150,$,D1:D150,%,A1:A150,#)".to_string());
        // Long columns, where most values recur; short ones, where one value's cells often
        // hold the only largest or smallest number (a `<>` of it takes the runner-up).
        for (seed, rows) in (0..12).zip([150, 150, 150, 150, 150, 150, 12, 12, 12, 12, 12, 12]) {
            let env = generated(seed, rows, seed % 2 == 1);
            for formula in &formulas {
                assert_indexed_as_scanned(&env, formula);
            }
        }
    }
}
