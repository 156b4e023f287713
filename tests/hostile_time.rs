//! Hostile input that costs time (issue 19): a formula reading its own spill range, LAMBDA
//! recursion without end or branching past ncsheet's limit, deep name chains, macros whose
//! statements are each expensive, and the workbook shapes whose work used to grow with the
//! square of their size (their timing is benches/scaling.rs; here, that the answers hold).
//! Expected values are Excel's documented behaviour and hand arithmetic.

mod common;

use common::sheet::{get, n, set};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::{self, ErrorKind, RunOptions};
use ncsheet::workbook::Workbook;

/// The messages listed for one cell (what the CLI prints after `Sheet1!A1: `).
fn problems_at(wb: &Workbook, cell: &str) -> Vec<String> {
    let pos = parse_cell(cell).unwrap();
    wb.problems().into_iter().filter(|p| p.sheet == 0 && p.pos == pos).map(|p| p.message()).collect()
}

fn mentions(problems: &[String], words: &[&str]) -> bool {
    problems.iter().any(|m| words.iter().all(|w| m.contains(w)))
}

// ---- a formula reading its own spill range ------------------------------------------------

#[test]
fn a_formula_reading_its_own_spill_range_is_a_circular_reference() {
    // Excel: "=SUM(A2:A3)+SEQUENCE(3)" in A1 is a circular reference (its spill would change
    // what it sums); before, the passes left 10737418236 in A1.
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=SUM(A2:A3)+SEQUENCE(3)");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Circ));
    assert_eq!(get(&wb, "A2"), Value::Blank, "nothing spills");
    assert_eq!(get(&wb, "A3"), Value::Blank);
    let problems = problems_at(&wb, "A1");
    assert!(mentions(&problems, &["circular reference", "A1"]), "{problems:?}");
    assert!(mentions(&problems, &["own spill range A1:A3"]), "{problems:?}");
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!A1".to_string()]]);

    // Through another cell, and through a range read as a range node (more than 16 cells).
    set(&mut wb, "B1", "=A3*2");
    set(&mut wb, "A1", "=B1+SEQUENCE(3)");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Circ));
    set(&mut wb, "A1", "=SUM(A2:A40)+SEQUENCE(3)");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Circ));

    // Reading beside the spill is no cycle: 0 + {1;2;3}, then 10 + {1;2;3}.
    set(&mut wb, "A1", "=SUM(C1:C40)+SEQUENCE(3)");
    assert_eq!((get(&wb, "A1"), get(&wb, "A2"), get(&wb, "A3")), (n(1.0), n(2.0), n(3.0)));
    assert!(wb.cycles().is_empty(), "{:?}", wb.cycles());
    assert!(problems_at(&wb, "A1").is_empty());
    set(&mut wb, "C7", "10");
    assert_eq!((get(&wb, "A1"), get(&wb, "A3")), (n(11.0), n(13.0)));
    // The anchor's own cell is no part of its spill: reading it is a plain cycle of A1.
    set(&mut wb, "B5", "=A1#");
    assert_eq!(get(&wb, "B7"), n(13.0));
}

#[test]
fn a_spill_that_would_reach_its_reader_later_becomes_a_cycle_then_recovers() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=SEQUENCE(3)*B1");
    set(&mut wb, "B1", "2");
    assert_eq!(get(&wb, "A3"), n(6.0));
    // B1 now reads A2, which A1 spills into: a cycle A1 → A2 → B1 → A1.
    set(&mut wb, "B1", "=A2+1");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Circ));
    assert_eq!(get(&wb, "A2"), Value::Blank);
    // B1 reads nothing of the spill again: A1 spills 5, 10, 15.
    set(&mut wb, "B1", "5");
    assert_eq!((get(&wb, "A1"), get(&wb, "A2"), get(&wb, "A3")), (n(5.0), n(10.0), n(15.0)));
    assert!(wb.cycles().is_empty());
}

// ---- LAMBDA recursion and name chains -----------------------------------------------------

#[test]
fn recursive_lambdas_compute_within_the_limits() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("FIB", "=LAMBDA(n, IF(n<2, n, FIB(n-1)+FIB(n-2)))", None).unwrap();
    wb.define_name("FACT", "=LAMBDA(n, IF(n<=1, 1, n*FACT(n-1)))", None).unwrap();
    // F(20) = 6765 (21,891 calls); 20! = 2432902008176640000; 150 levels deep.
    set(&mut wb, "A1", "=FIB(20)");
    set(&mut wb, "A2", "=FACT(20)");
    set(&mut wb, "A3", "=LET(f, LAMBDA(n, IF(n=0, 0, 1+f(n-1))), f(150))");
    assert_eq!(get(&wb, "A1"), n(6765.0));
    assert_eq!(get(&wb, "A2"), n(2432902008176640000.0));
    assert_eq!(get(&wb, "A3"), n(150.0));
    assert!(wb.problems().is_empty(), "{:?}", wb.problems());
}

#[test]
fn branching_recursion_past_the_call_limit_is_num_with_the_limit_named() {
    // fib(45) is 2.3 billion calls: hours. It stops at ncsheet's limit, in about a second.
    // The bound is the outcome: the limit's #NUM! and its note, not a time.
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=LET(fib, LAMBDA(n, IF(n<2, n, fib(n-1)+fib(n-2))), fib(45))");
    // Excel's error for a LAMBDA that calls itself without end is #NUM!.
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Num));
    let problems = problems_at(&wb, "A1");
    assert!(mentions(&problems, &["#NUM!", "LAMBDA calls in one formula", "ncsheet's limit", "fib"]), "{problems:?}");
    assert_eq!(problems.len(), 1, "one note, not one per failed call: {problems:?}");
}

#[test]
fn endless_lambda_recursion_is_num_with_the_depth_named() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("DOWN", "=LAMBDA(n, DOWN(n+1))", None).unwrap();
    set(&mut wb, "A1", "=DOWN(1)");
    set(&mut wb, "A2", "=LET(g, LAMBDA(x, g(x)+1), g(0))");
    for cell in ["A1", "A2"] {
        assert_eq!(get(&wb, cell), Value::Error(XlError::Num), "{cell}");
        let problems = problems_at(&wb, cell);
        assert!(mentions(&problems, &["#NUM!", "LAMBDA calls nest deeper than", "levels"]), "{cell}: {problems:?}");
    }
}

/// Sets `formula` in `cell` and checks it is #NUM! with the LAMBDA work limit's note; the
/// cell's notes.
fn past_the_work_limit(wb: &mut Workbook, cell: &str, formula: &str) -> Vec<String> {
    past_the_limit_of(wb, cell, formula, 268_435_456)
}

/// [`past_the_work_limit`] for a workbook whose LAMBDAs may do `limit` items of work.
fn past_the_limit_of(wb: &mut Workbook, cell: &str, formula: &str, limit: u64) -> Vec<String> {
    set(wb, cell, formula);
    assert_eq!(get(wb, cell), Value::Error(XlError::Num), "{formula}");
    let problems = problems_at(wb, cell);
    let more_than = format!("more than {limit} items of work");
    assert!(mentions(&problems, &["#NUM!", &more_than, "ncsheet's limit"]), "{formula}: {problems:?}");
    problems
}

/// The budget the tests of what is charged give the LAMBDAs (`Settings::lambda_work`): 2^20
/// items of work, so that a case passes it after a 256th of the work the real limit (2^28)
/// takes, through the same charges.
const SMALL_BUDGET: u64 = 1 << 20;

fn with_small_lambda_budget() -> Workbook {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().lambda_work = Some(SMALL_BUDGET);
    wb
}

/// A LAMBDA of BYROW, BYCOL, MAP or MAKEARRAY that returns an array gives `#CALC!` for that
/// item, as Excel does ("anything but a single value return from the LAMBDA function
/// returns a #CALC error", Microsoft's BYROW function page), and the note says so. Its arrays
/// are let go as each call ends: 1,000 rows each returning 100 items, against a limit of
/// 10,000 items held at once (`Settings::live_items`), were counted as held together, so the
/// note spoke of that limit's `#NUM!` while the cell showed `#CALC!`.
#[test]
fn a_lambda_returning_an_array_for_one_item_is_calc_and_says_why() {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().live_items = Some(10_000);
    for (cell, formula) in [
        ("A1", "=SUM(BYROW(SEQUENCE(1000),LAMBDA(r,SEQUENCE(1,100))))"),
        ("A2", "=SUM(BYCOL(SEQUENCE(1,1000),LAMBDA(c,SEQUENCE(100))))"),
        ("A3", "=SUM(MAP(SEQUENCE(1000),LAMBDA(x,SEQUENCE(100))))"),
        ("A4", "=SUM(MAKEARRAY(10,100,LAMBDA(r,c,SEQUENCE(100))))"),
    ] {
        set(&mut wb, cell, formula);
        assert_eq!(get(&wb, cell), Value::Error(XlError::Calc), "{formula}");
        let problems = problems_at(&wb, cell);
        // The function whose LAMBDA it is: the one SUM is given.
        let function = formula["=SUM(".len()..].split('(').next().unwrap();
        let returned = format!("the LAMBDA of {function} returned an array");
        assert!(mentions(&problems, &["#CALC!", &returned]), "{formula}: {problems:?}");
        assert!(!problems.iter().any(|p| p.contains("#NUM!")), "{formula}: {problems:?}");
    }
    // One value from each call is an ordinary result: 1,000 rows of SUM(SEQUENCE(1,100)).
    set(&mut wb, "B1", "=SUM(BYROW(SEQUENCE(1000),LAMBDA(r,SUM(SEQUENCE(1,100)))))");
    assert_eq!(get(&wb, "B1"), n(5_050_000.0));
}

/// The LAMBDAs of MAP, REDUCE, SCAN, BYROW, BYCOL and MAKEARRAY share one budget of work per
/// formula (`MAX_LAMBDA_WORK`, 2^28: each call, each array item made, each cell read): an
/// array grown by VSTACK at each step of a REDUCE (copied whole each time: n²/2 items), a
/// MAKEARRAY whose LAMBDA builds arrays, a MAP whose LAMBDA reads a range, ran past 30 s.
#[test]
fn lambdas_of_the_array_helpers_past_their_work_limit_are_num_naming_it() {
    let mut wb = Workbook::with_sheet();
    for r in 1..=1000 {
        set(&mut wb, &format!("B{r}"), "1");
    }
    let cases = [
        // 25,000 steps copy 312 million items.
        ("A1", "=ROWS(REDUCE(0,SEQUENCE(25000),LAMBDA(a,x,VSTACK(a,x))))"),
        // 4 million calls, each making 1,000 items.
        ("A2", "=SUM(MAKEARRAY(2000,2000,LAMBDA(r,c,SUM(SEQUENCE(1000)))))"),
        ("A3", "=SUM(BYROW(SEQUENCE(1000000),LAMBDA(row,SUM(SEQUENCE(1,1000)))))"),
        // A million calls, each reading 1,000 cells.
        ("A4", "=SUM(MAP(SEQUENCE(1000000),LAMBDA(x,SUM(B1:B1000))))"),
        ("A5", "=SUM(SCAN(0,SEQUENCE(1000000),LAMBDA(a,x,a+SUM(B1:B1000))))"),
    ];
    for (cell, formula) in cases {
        let problems = past_the_work_limit(&mut wb, cell, formula);
        assert_eq!(problems.len(), 1, "one note: {problems:?}");
    }
    // Within the limit they compute: 1,000 steps give 1,001 rows summing to 1 + … + 1,000;
    // MAKEARRAY's items are 10r + c; 1,000 reads of 1,000 ones.
    set(&mut wb, "C1", "=SUM(REDUCE(0,SEQUENCE(1000),LAMBDA(a,x,VSTACK(a,x))))");
    set(&mut wb, "C2", "=ROWS(REDUCE(0,SEQUENCE(1000),LAMBDA(a,x,VSTACK(a,x))))");
    set(&mut wb, "C3", "=SUM(MAKEARRAY(3,2,LAMBDA(r,c,10*r+c)))");
    set(&mut wb, "C4", "=SUM(MAP(SEQUENCE(1000),LAMBDA(x,SUM(B1:B1000))))");
    assert_eq!(get(&wb, "C1"), n(500_500.0));
    assert_eq!(get(&wb, "C2"), n(1_001.0));
    assert_eq!(get(&wb, "C3"), n((11 + 12 + 21 + 22 + 31 + 32) as f64));
    assert_eq!(get(&wb, "C4"), n(1_000_000.0));
    assert!(problems_at(&wb, "C1").is_empty());
}

/// A function inside the LAMBDA that makes no array of its size still counts its work against
/// the same budget: an aggregate or SUMPRODUCT of an array bound outside the LAMBDA (read
/// whole at every call), a regression (rows × variables × the smaller), a matrix product
/// (its multiply-adds), a text function reading a long text. Each of these formulas ran for
/// minutes or hours at full size (a million sums of a million items); each is #NUM! with the
/// note. Shown with the small budget (the same charges; at 2^28 the text case alone reads
/// 4 GB of text before it stops), and the real limit once, for an aggregate.
#[test]
fn heavy_functions_inside_the_lambdas_count_against_their_work_limit() {
    let mut wb = Workbook::with_sheet();
    past_the_work_limit(&mut wb, "A1", "=LET(a,SEQUENCE(1000,1000),SUM(MAP(SEQUENCE(1000000),LAMBDA(x,SUM(a)))))");
    let mut wb = with_small_lambda_budget();
    let cases = [
        // 1,000 calls, each reading 10,000 items (or multiplying 30 × 30 by 30 × 30).
        ("A1", "=LET(a,SEQUENCE(100,100),SUM(MAP(SEQUENCE(1000),LAMBDA(x,SUM(a)))))"),
        ("A2", "=LET(a,SEQUENCE(100,100),SUM(MAP(SEQUENCE(1000),LAMBDA(x,SUMPRODUCT(a,a)))))"),
        ("A3", "=LET(m,SEQUENCE(30,30),SUM(MAP(SEQUENCE(1000),LAMBDA(x,INDEX(MMULT(m,m),1,1)))))"),
        // 100 regressions of 1,000 rows on 10 variables: 100,000 steps each.
        (
            "A4",
            "=LET(x,SEQUENCE(1000,10)^0.5,y,SEQUENCE(1000),\
             SUM(MAKEARRAY(100,1,LAMBDA(r,c,INDEX(LINEST(y,x),1,1)))))",
        ),
        // 600 lengths of a 32,767-byte text: 2,047 + 1 each, 1,228,800 in all.
        ("A5", "=LET(t,REPT(\"a\",32767),REDUCE(0,SEQUENCE(600),LAMBDA(a,x,a+LEN(t))))"),
    ];
    for (cell, formula) in cases {
        past_the_limit_of(&mut wb, cell, formula, SMALL_BUDGET);
    }
    // Within the budget they compute: 1,000 sums of 1 + … + 100, 1,000 lengths of 1,000, and
    // 500 lengths of 32,767 (1,024,000 items of work, just under 2^20).
    set(&mut wb, "B1", "=LET(a,SEQUENCE(10,10),SUM(MAP(SEQUENCE(1000),LAMBDA(x,SUM(a)))))");
    set(&mut wb, "B2", "=LET(t,REPT(\"a\",1000),REDUCE(0,SEQUENCE(1000),LAMBDA(a,x,a+LEN(t))))");
    set(&mut wb, "B3", "=LET(t,REPT(\"a\",32767),REDUCE(0,SEQUENCE(500),LAMBDA(a,x,a+LEN(t))))");
    assert_eq!(get(&wb, "B1"), n(5_050_000.0));
    assert_eq!(get(&wb, "B2"), n(1_000_000.0));
    assert_eq!(get(&wb, "B3"), n(500.0 * 32_767.0));
}

/// Lookups inside the LAMBDA count the items they look at (and the column VLOOKUP, HLOOKUP
/// and LOOKUP copy) against the same budget: a MAP whose LAMBDA looks each item up in a
/// million-item array bound outside it (`MAP(SEQUENCE(100000),LAMBDA(i,MATCH(i,big,0)))`)
/// scanned 5·10^10 items. A value not found is a scan of the whole array at every call; a
/// value found early, or a binary search, costs what it looked at, so those compute.
#[test]
fn lookups_inside_the_lambdas_count_the_items_they_look_at() {
    // Bound outside the LAMBDA: made once, not charged; read at every call.
    const BOUND: &str = "LET(big,SEQUENCE(100000),wide,SEQUENCE(1,16000),texts,\"\"&big,";
    let mut wb = with_small_lambda_budget();
    // 1,000 calls each scanning 100,000 items (HLOOKUP 16,000, a row being at most 16,384
    // columns): a hundred million, past 2^20 at the 11th call (the 66th).
    let scans = [
        "MATCH(-i,big,0)",
        "XMATCH(-i,big)",
        "XLOOKUP(-i,big,big,0)",
        "XLOOKUP(-i,big,big,0,-1,-1)",
        "VLOOKUP(-i,big,1,FALSE)",
        "HLOOKUP(-i,wide,1,FALSE)",
        // A sorted search copies both vectors; text items are stepped over one by one.
        "LOOKUP(i,big)",
        "MATCH(i,texts,1)",
    ];
    for (r, scan) in scans.iter().enumerate() {
        let formula = format!("={BOUND}SUM(MAP(SEQUENCE(1000),LAMBDA(i,IFERROR({scan},0)))))");
        past_the_limit_of(&mut wb, &format!("A{}", r + 1), &formula, SMALL_BUDGET);
    }
    // 1,000 values found at positions 1 … 1,000 (500,500 items looked at), 5 copies of the
    // column VLOOKUP searches, and 10,000 binary searches of about 17 steps each: within 2^20,
    // each the sum 1 + … + n.
    let within = [
        ("B1", "MATCH(i,big,0)", 1000),
        ("B2", "XLOOKUP(i,big,big)", 1000),
        ("B3", "VLOOKUP(i,big,1,FALSE)", 5),
        ("B4", "MATCH(i,big,1)", 10_000),
        ("B5", "XLOOKUP(i,big,big,,0,2)", 10_000),
    ];
    for (cell, lookup, calls) in within {
        let formula = format!("={BOUND}SUM(MAP(SEQUENCE({calls}),LAMBDA(i,{lookup}))))");
        set(&mut wb, cell, &formula);
        let sum = (calls * (calls + 1) / 2) as f64;
        assert_eq!(get(&wb, cell), n(sum), "{formula}: {:?}", problems_at(&wb, cell));
    }
}

/// Work known before it is done is checked against the LAMBDAs' budget before it is done
/// (issue 30): criteria tested cell by cell (COUNTIF/SUMIFS with an array of patterns ran its
/// whole scan, up to 10^9 tests, and was charged after it, so a LAMBDA called once ended with a
/// number past the budget), and the copies of the lines BYROW and BYCOL hand their LAMBDA.
/// Each case is one call of the outer LAMBDA, whose work no later call's check would catch.
/// The counts are hand arithmetic: 2,000 patterns × 1,000 cells = 2·10^6 tests; 100 rows of
/// 16,000 items copied = 1.6·10^6; both past 2^20.
#[test]
fn work_known_before_it_is_done_is_checked_against_the_lambda_budget_first() {
    let mut wb = with_small_lambda_budget();
    for r in 1..=1000 {
        set(&mut wb, &format!("B{r}"), "x");
    }
    let patterns = "\"*\"&SEQUENCE(2000)&\"*\"";
    let cases = [
        format!("=SUM(MAP(1,LAMBDA(x,SUM(COUNTIF(B1:B1000,{patterns})))))"),
        format!("=SUM(MAP(1,LAMBDA(x,SUM(COUNTIFS(B1:B1000,{patterns})))))"),
        format!("=SUM(MAP(1,LAMBDA(x,SUM(SUMIFS(B1:B1000,B1:B1000,{patterns})))))"),
        // The arrays are bound outside the LAMBDA: made there, they are not charged.
        "=LET(a,SEQUENCE(100,16000),SUM(MAP(1,LAMBDA(x,ROWS(BYROW(a,LAMBDA(r,1)))))))".to_string(),
        "=LET(a,SEQUENCE(16000,100),SUM(MAP(1,LAMBDA(x,COLUMNS(BYCOL(a,LAMBDA(c,1)))))))".to_string(),
    ];
    for (i, formula) in cases.iter().enumerate() {
        past_the_limit_of(&mut wb, &format!("A{}", i + 1), formula, SMALL_BUDGET);
    }
    // Within the budget: 200 patterns × 1,000 cells, each matching no "x"; 10 rows of 16,000.
    set(&mut wb, "C1", "=SUM(MAP(1,LAMBDA(x,SUM(COUNTIF(B1:B1000,\"*\"&SEQUENCE(200)&\"*\")))))");
    set(&mut wb, "C2", "=LET(a,SEQUENCE(10,16000),SUM(MAP(1,LAMBDA(x,ROWS(BYROW(a,LAMBDA(r,1)))))))");
    assert_eq!(get(&wb, "C1"), n(0.0), "{:?}", problems_at(&wb, "C1"));
    assert_eq!(get(&wb, "C2"), n(10.0), "{:?}", problems_at(&wb, "C2"));
}

/// MAP broadcasts a column and a row to their product, and that product is held to the
/// array limit (2^24 items) before anything is made: a million rows by 16,000 columns asked
/// for 16·10^9 items up front and aborted the process (issue 30).
#[test]
fn a_map_broadcast_past_the_array_limit_is_num_before_it_is_made() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=ROWS(MAP(SEQUENCE(1000000),SEQUENCE(1,16000),LAMBDA(a,b,1)))");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Num));
    let problems = problems_at(&wb, "A1");
    assert!(mentions(&problems, &["#NUM!"]), "{problems:?}");
    // The same broadcast within the limit: 1,000 × 16 items, each a + b.
    set(&mut wb, "A2", "=SUM(MAP(SEQUENCE(1000),SEQUENCE(1,16),LAMBDA(a,b,a+b)))");
    assert_eq!(get(&wb, "A2"), n((16 * 500_500 + 1000 * 136) as f64));
}

/// Evaluates the surface `formula` (`=x+…`, the rest 0) at 300 points through one evaluation
/// context, as BALLPATH and `ballpath --surface` do, and checks each point's height is its x.
fn surface_heights_are_x_at_300_points(formula: &str) {
    use ncsheet::eval::functions::Registry;
    use ncsheet::eval::surface::FormulaSurface;
    use ncsheet::eval::Ctx;
    use ncsheet::formula::parse::ParseContext;
    use ncsheet::formula::Pos;
    let parsing = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
    let surface = FormulaSurface::parse(formula, &parsing).unwrap();
    let wb = Workbook::with_sheet();
    let mut eval = Ctx::new(&wb, 0, Pos::new(0, 0));
    let mut bound = surface.bind(&mut eval);
    for i in 0..300 {
        assert_eq!(bound.height_at(f64::from(i), 0.0), Ok(f64::from(i)), "point {i}");
    }
}

/// A macro's `Evaluate` has the workbook's LAMBDA budget (`Settings::lambda_work`), as its
/// cells do (issue 30): it had the default budget (2^28) whatever the settings said. The MAP
/// here is past the small budget of 2^20 items of work and within the default.
#[test]
fn a_macros_evaluate_has_the_workbooks_lambda_budget() {
    let mut wb = with_small_lambda_budget();
    // A million calls, each making 5 items: about 6 million items of work.
    let formula = "SUM(MAP(SEQUENCE(1000,1000),LAMBDA(x,SUM(SEQUENCE(1,5)))))";
    let source = format!("Sub Main()\n    Range(\"A1\").Value = Evaluate(\"{formula}\")\nEnd Sub\n");
    vba::run(&mut wb, &source, "evaluate.bas", &RunOptions::default()).unwrap();
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Num));
    let mut wb = Workbook::with_sheet();
    vba::run(&mut wb, &source, "evaluate.bas", &RunOptions::default()).unwrap();
    assert_eq!(get(&wb, "A1"), n(15_000_000.0), "within the default budget: 10^6 × (1 + … + 5)");
}

/// A surface evaluates its formula once per point through one evaluation context: each point
/// has the LAMBDA work budget to itself, as each cell does. 300 points of a million items
/// each are past one budget, not past one point's.
#[test]
fn a_surface_has_the_lambda_work_budget_at_each_point() {
    surface_heights_are_x_at_300_points("=x+0*SUM(MAP(SEQUENCE(10),LAMBDA(v,SUM(SEQUENCE(100000)))))");
}

/// The same holds for the calls of named LAMBDAs (`MAX_LAMBDA_CALLS`, 2,000,000 per
/// evaluation): 300 points of 10,000 calls of a LET-bound LAMBDA each are 3,000,000 calls in
/// all, past one evaluation's limit, and within each point's.
#[test]
fn a_surface_has_the_named_lambda_calls_at_each_point() {
    // 0 * (1 + … + 10,000): each point calls g 10,000 times by name.
    surface_heights_are_x_at_300_points("=x+0*LET(g,LAMBDA(v,v),SUM(MAP(SEQUENCE(10000),LAMBDA(v,g(v)))))");
}

#[test]
fn names_that_refer_to_themselves_or_chain_too_deep_say_so() {
    let mut wb = Workbook::with_sheet();
    // N1 = N2 + 1, …, N300 = 1: 300 levels of names, past ncsheet's 200.
    for i in 1..300 {
        wb.define_name(&format!("N{i}x"), &format!("=N{}x+1", i + 1), None).unwrap();
    }
    wb.define_name("N300x", "=1", None).unwrap();
    wb.define_name("LOOPY", "=LOOPY+1", None).unwrap();
    set(&mut wb, "A1", "=N1x");
    set(&mut wb, "A2", "=LOOPY");
    // A chain within the limit computes: N150 = 151 - 1 + … = 151.
    set(&mut wb, "A3", "=N150x");
    assert_eq!(get(&wb, "A3"), n(151.0));
    for cell in ["A1", "A2"] {
        assert_eq!(get(&wb, cell), Value::Error(XlError::Circ), "{cell}");
        let problems = problems_at(&wb, cell);
        assert!(
            mentions(&problems, &["#CIRC!", "defined names nest deeper than", "refers to itself"]),
            "{cell}: {problems:?}"
        );
    }
}

// ---- macros whose statements are each expensive --------------------------------------------

#[test]
fn a_macro_of_expensive_statements_stops_at_its_time_limit() {
    let source = "Sub Main()\n    Dim i, s\n    For i = 1 To 100000\n        s = Evaluate(\"SUM(SEQUENCE(100000))\")\n    Next\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    let options = RunOptions { deadline: Some(vba::Deadline::after(0.5)), ..RunOptions::default() };
    // The bound is the outcome: the Limit error naming the --timeout, not a time measured here.
    let err = vba::run(&mut wb, source, "loop.bas", &options).expect_err("stopped by the time limit");
    assert_eq!(err.kind, ErrorKind::Limit);
    assert!(err.message.contains("--timeout of 0.5 s"), "{}", err.message);
    // The statement it stopped at is named.
    assert!(err.span.is_some_and(|s| (3..=5).contains(&s.line)), "{:?}", err.span);
}

/// Runs `Sub Main()` with `body` under a statement limit of `limit`; the error it stops with.
fn stops_within(body: &str, limit: u64) -> vba::MacroError {
    let source = format!("Sub Main()\n{body}\nEnd Sub\n");
    let options = RunOptions { max_statements: limit, ..RunOptions::default() };
    let mut wb = Workbook::with_sheet();
    match vba::run(&mut wb, &source, "work.bas", &options) {
        Ok(out) => panic!("the macro ran to its end, printing {:?}:\n{body}", out.printed),
        Err(e) => e,
    }
}

/// Text and array work counts against the statement limit (issue 30): a loop of a hundred
/// statements, each reading or making a 100,000-character text or a 50,000-item array, ran
/// to its end within a limit of 100,000 statements (a loop of `Replace` over 16 million
/// characters took 0.5 s a statement, so the default limit let it run for hours). At the
/// documented rate, each 64 characters or 4 items read or made a statement
/// (docs/limits.md), every loop here is worth over 300,000 statements: it stops, naming the
/// work, at a statement of its loop.
#[test]
fn text_and_array_work_counts_against_the_statement_limit() {
    let setup = "    Dim s As String, t As String, c As String, v, w, n As Long, i As Long\n    \
                 s = String(100000, \"a\"): t = s: c = Replace(String(50000, \"a\"), \"a\", \"a,\")\n    \
                 v = Split(c, \",\"): Range(\"A1:A50000\").Value = 1\n";
    // Each statement reads or makes at least 6,250 units of 16 characters or an item: the
    // 100,000 characters of `s`, the 50,001 items of `v` or the 50,000 cells summed.
    for work in [
        "t = Replace(s, \"b\", \"c\")",
        "n = InStr(s, \"b\")",
        "If s = t Then n = n + 1",
        "v = Split(c, \",\")",
        "t = Join(v, \",\")",
        "w = Filter(v, \"b\")",
        "t = StrConv(s, vbUpperCase)",
        "w = StrConv(s, vbFromUnicode)",
        "t = Format(s, \"!\")",
        "t = Space(100000)",
        "n = Application.WorksheetFunction.Sum(Range(\"A1:A50000\"))",
    ] {
        let body = format!("{setup}    For i = 1 To 100\n        {work}\n    Next i");
        let e = stops_within(&body, 100_000);
        assert_eq!(e.kind, ErrorKind::Limit, "{work}: {e}");
        assert!(e.message.contains("text and array work counts too"), "{work}: {e}");
        assert!(e.span.is_some_and(|s| (5..=8).contains(&s.line)), "{work}: {:?}", e.span);
    }
}

/// Format reads its format whole however short the text it makes: 100,000 `#` format 1 as
/// "1" ("Format function": `#` shows a digit or nothing), 1,562 statements' worth of text
/// work each time at 64 characters a statement (docs/limits.md), so a hundred turns (156,250)
/// pass a limit of 100,000 that the loop's own 200 statements stay far below.
#[test]
fn a_long_format_with_a_short_result_counts_what_it_reads() {
    let body = "    Dim p As String, t As String, i As Long\n    p = String(100000, \"#\")\n    \
                For i = 1 To 100\n        t = Format(1, p)\n    Next i";
    let e = stops_within(body, 100_000);
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    assert!(e.message.contains("text and array work counts too"), "{e}");
}

/// `ReDim Preserve` of a two-dimensional array copies every item each time (issue 30): a
/// loop of them passed 30 s within the default limit while each 64 items copied counted as
/// one statement, about four times too few for their cost (60 ns an item against a
/// statement's 1 µs, measured in release: docs/limits.md). Each 16 items copied now count:
/// growing a(1 To 10, 1 To i) for i up to 300 copies 10 · (1 + … + 299) = 448,500 items,
/// 28,031 statements' worth (7,007 at 64 a statement), past a limit of 20,000 that the
/// loop's 600 statements stay far below.
#[test]
fn redim_preserve_copies_count_a_statement_per_16_items() {
    let body = "    Dim a() As Double, i As Long\n    ReDim a(1 To 10, 1 To 1)\n    For i = 2 To 300\n        \
                ReDim Preserve a(1 To 10, 1 To i)\n    Next i";
    let e = stops_within(body, 20_000);
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    assert!(e.message.contains("each 16 items copied count as a statement"), "{e}");
}

// ---- shapes that were quadratic: the answers (benches/scaling.rs times them) ---------------

#[test]
fn every_self_reference_of_a_filled_column_is_its_own_cycle() {
    let mut wb = Workbook::with_sheet();
    for k in 1..=2000u32 {
        wb.set_input_deferred(0, parse_cell(&format!("A{k}")).unwrap(), &format!("=A{k}+1")).unwrap();
    }
    wb.recalculate();
    assert_eq!(wb.cycles().len(), 2000);
    // Never calculated: 0, as Excel shows a circular reference.
    assert_eq!(get(&wb, "A1777"), n(0.0));
    // Breaking one cycle leaves the others.
    set(&mut wb, "A5", "7");
    assert_eq!(wb.cycles().len(), 1999);
    assert_eq!(get(&wb, "A5"), n(7.0));
    assert_eq!(get(&wb, "A6"), n(0.0));
}

#[test]
fn sheets_are_found_by_name_in_any_ascii_case_among_many() {
    let mut wb = Workbook::new();
    for k in 1..=3000u32 {
        let id = wb.add_sheet(&format!("Part {k}")).unwrap();
        wb.set_input_deferred(id, parse_cell("A1").unwrap(), &k.to_string()).unwrap();
    }
    assert!(wb.add_sheet("PART 17").is_err(), "names differ from others beyond ASCII case");
    assert_eq!(wb.sheet_id("pArT 2999"), Some(2998));
    assert_eq!(wb.sheet_id("Part 3001"), None);
    wb.set_input(0, parse_cell("B1").unwrap(), "='part 3000'!A1+INDIRECT(\"'PART 2500'!A1\")").unwrap();
    assert_eq!(wb.value(0, parse_cell("B1").unwrap()), n(5500.0));
}

#[test]
fn offset_chains_settle_in_order() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "1");
    for k in 2..=3000u32 {
        wb.set_input_deferred(0, parse_cell(&format!("A{k}")).unwrap(), &format!("=OFFSET(A{},0,0)+1", k - 1)).unwrap();
    }
    wb.recalculate();
    assert_eq!(get(&wb, "A3000"), n(3000.0));
    set(&mut wb, "A1", "101");
    assert_eq!(get(&wb, "A3000"), n(3100.0));
}

// ---- OFFSET chains filled one edit at a time (issue 19's "200k OFFSET chains") -------------

#[test]
fn an_offset_chain_filled_one_edit_at_a_time_is_linear_and_right() {
    // Ak = OFFSET(A(k-1),0,0)+1 with A1 = 1: Ak is k. 20,000 edits, each recalculating: when
    // every edit recomputed every OFFSET (Excel's volatility) this took minutes.
    let size = 20_000;
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "1");
    for k in 2..=size {
        set(&mut wb, &format!("A{k}"), &format!("=OFFSET(A{},0,0)+1", k - 1));
    }
    // Each edit evaluates the new formula and what reads it, none yet: the work is counted,
    // not timed (recomputing every OFFSET at every edit was size²/2 = 2·10^8 evaluations).
    let evaluated = wb.formulas_evaluated();
    assert!(evaluated <= 2 * size as u64, "{evaluated} evaluations for {size} edits");
    assert_eq!(get(&wb, &format!("A{size}")), n(size as f64));
    // Still recomputed when what it reads changes: through the chain, and where a moved
    // reference lands (B1 reads A(1+C1)).
    set(&mut wb, "A1", "5");
    assert_eq!(get(&wb, &format!("A{size}")), n(size as f64 + 4.0));
    set(&mut wb, "B1", "=OFFSET(A1,C1,0)");
    assert_eq!(get(&wb, "B1"), n(5.0));
    set(&mut wb, "C1", "2");
    assert_eq!(get(&wb, "B1"), n(7.0));
    set(&mut wb, "A2", "100");
    assert_eq!(get(&wb, "B1"), n(101.0));
}

#[test]
fn a_macro_filling_an_offset_chain_cell_by_cell_is_linear() {
    let size = 20_000;
    let source = format!(
        "Sub Main()\n    Dim i\n    Range(\"A1\").Value = 1\n    For i = 2 To {size}\n        Cells(i, 1).Formula = \"=OFFSET(A\" & (i - 1) & \",0,0)+1\"\n    Next\n    Debug.Print Cells({size}, 1).Value\nEnd Sub\n"
    );
    let mut wb = Workbook::with_sheet();
    let out = vba::run(&mut wb, &source, "fill.bas", &RunOptions::default()).unwrap();
    assert_eq!(out.printed, vec![format!(" {size} ")]);
    // Counted, not timed: each Formula set evaluates its cell, not the chain before it.
    let evaluated = wb.formulas_evaluated();
    assert!(evaluated <= 2 * size as u64, "{evaluated} evaluations for {size} edits");
}

// ---- INDIRECT columns: volatile, recomputed at every edit, in work proportional to them ----

#[test]
fn an_indirect_column_rewritten_and_edited_is_linear_and_right() {
    // Ak = INDIRECT("A"&(ROW()-1))+1 with A1 = 1: Ak is k. Rewriting the column (each
    // volatile formula replaced) scanned the list of volatile cells once per cell.
    let size = 20_000u32;
    let at = |cell: &str| parse_cell(cell).unwrap();
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "1");
    let before = wb.formulas_evaluated();
    for k in 2..=size {
        wb.set_input_deferred(0, at(&format!("A{k}")), "=INDIRECT(\"A\"&(ROW()-1))+1").unwrap();
    }
    wb.recalculate();
    assert_eq!(get(&wb, &format!("A{size}")), n(size as f64));
    for k in 2..=size {
        wb.set_input_deferred(0, at(&format!("A{k}")), "=INDIRECT(\"R[-1]C\",FALSE)+2").unwrap();
    }
    wb.recalculate();
    // Two recalculations of the column, counted (not timed): each evaluates every cell at most
    // twice (again when the references it made at run time are new to the graph).
    let evaluated = wb.formulas_evaluated() - before;
    assert!(evaluated <= 4 * size as u64, "{evaluated} evaluations for two passes over {size} cells");
    assert_eq!(get(&wb, &format!("A{size}")), n(2.0 * size as f64 - 1.0));
    // Still volatile: recomputed through the chain, and where the text now points.
    set(&mut wb, "A1", "11");
    assert_eq!(get(&wb, &format!("A{size}")), n(2.0 * size as f64 + 9.0));
    set(&mut wb, "C1", "=INDIRECT(\"'Sheet1'!$A$\"&D1)");
    assert_eq!(get(&wb, "C1"), Value::Error(XlError::Ref), "row 0 is no row");
    set(&mut wb, "D1", "3");
    assert_eq!(get(&wb, "C1"), n(15.0));
    set(&mut wb, "C2", "=SUM(INDIRECT(\"a3:$A$1\"))");
    assert_eq!(get(&wb, "C2"), n(11.0 + 13.0 + 15.0));
    // Replaced by constants, the cells are no longer recomputed at every edit.
    for k in 2..=size {
        wb.set_input_deferred(0, at(&format!("A{k}")), "0").unwrap();
    }
    wb.recalculate();
    assert!(!wb.calls_volatile(0, at("A7")));
    set(&mut wb, "A1", "0");
    assert_eq!(get(&wb, "C2"), n(0.0));
}

/// Unclosed calls (in-place LAMBDA calls too) and references spaced before a parenthesis,
/// 60 levels deep: the parser once tried each level both as a call and as an intersection
/// with a parenthesis, 2^60 attempts. Each gives its error (or value) at once.
#[test]
fn nested_unclosed_calls_and_spaced_parentheses_parse_in_linear_time() {
    let mut wb = Workbook::with_sheet();
    let deep = [
        format!("={}1", "ABS(".repeat(60)),
        format!("={}1", "(A1 ".repeat(60)),
        format!("={}B2{}", "(A1 ".repeat(60), ")".repeat(60)),
        format!("={}1", "IF(A1,".repeat(60)),
        format!("={}1", "LAMBDA(x,x)(".repeat(60)),
        format!("={}1", "LAMBDA(x,x)(1)(".repeat(60)),
    ];
    for (row, text) in deep.iter().enumerate() {
        let _ = wb.set_input(0, parse_cell(&format!("D{}", 10 + row)).unwrap(), text);
    }
}

// ---- regular expressions ---------------------------------------------------------------------

/// docs/limits.md, "a regular expression": a search's work is the states the pattern can
/// have active × (its capture slots + 100) per byte of the text, refused past 3·10^9 before it
/// runs; the matcher's table of slots (states × slots) past 4,194,304. `(?:a?)` 1,000 times
/// then 1,000 `a` keeps about 2,000 states active at each byte: over 30,000 bytes that is
/// 2,000 × 102 × 30,001 = 6·10^9 (REGEXTEST ran 9.6 s with the groups capturing); with the
/// groups capturing, 5,000 states × 2,002 slots pass the table's limit. Over 1,000 characters
/// the same chain is 2·10^8 and matches (each `a?` may take nothing; Python:
/// re.search('(?:a?)'*1000+'a'*1000, 'a'*1000) matches).
#[test]
fn regular_expressions_past_the_work_limit_are_num_naming_it() {
    let mut wb = Workbook::with_sheet();
    let chain = r#"REPT("(?:a?)",1000)&REPT("a",1000)"#;
    set(&mut wb, "A1", &format!(r#"=REGEXTEST(REPT("a",1000),{chain})"#));
    assert_eq!(get(&wb, "A1"), Value::Bool(true));
    for (cell, formula) in [
        ("A2", format!(r#"=REGEXTEST(REPT("a",30000),{chain})"#)),
        ("A3", format!(r#"=REGEXEXTRACT(REPT("a",30000),{chain},1)"#)),
        ("A4", format!(r#"=REGEXREPLACE(REPT("a",30000),{chain},"")"#)),
    ] {
        set(&mut wb, cell, &formula);
        assert_eq!(get(&wb, cell), Value::Error(XlError::Num), "{formula}");
        let problems = problems_at(&wb, cell);
        assert!(mentions(&problems, &["30000 bytes", "limit of 3e9"]), "{formula}: {problems:?}");
    }
    set(&mut wb, "A5", r#"=REGEXTEST(REPT("a",30000),REPT("(a?)",1000)&REPT("a",1000))"#);
    assert_eq!(get(&wb, "A5"), Value::Error(XlError::Num));
    assert!(mentions(&problems_at(&wb, "A5"), &["1000 capture groups", "64 MiB"]), "{:?}", problems_at(&wb, "A5"));
    // XLOOKUP's and XMATCH's match mode 3 search with the same limits, their searches' work
    // added up: the chain over one 30,000-byte item is past it, over a 1,000-byte item it
    // matches the item.
    set(&mut wb, "B1", &format!(r#"=XMATCH({chain},{{"b";"x"}}&REPT("a",30000),3)"#));
    assert_eq!(get(&wb, "B1"), Value::Error(XlError::Num));
    set(&mut wb, "B2", &format!(r#"=XMATCH({chain},{{"b";"x"}}&REPT("a",1000),3)"#));
    assert_eq!(get(&wb, "B2"), n(1.0));
    set(&mut wb, "B3", &format!(r#"=XLOOKUP({chain},REPT("a",30000),1,,3)"#));
    assert_eq!(get(&wb, "B3"), Value::Error(XlError::Num));
    // Each says why, as REGEXTEST does (before, #NUM! with no note).
    assert!(
        mentions(&problems_at(&wb, "B1"), &["XMATCH: searching 1 item (30001 bytes)", "limit of 3e9"]),
        "{:?}",
        problems_at(&wb, "B1")
    );
    assert!(
        mentions(&problems_at(&wb, "B3"), &["XLOOKUP: searching 1 item (30000 bytes)"]),
        "{:?}",
        problems_at(&wb, "B3")
    );
    set(&mut wb, "B4", r#"=XMATCH(REPT("(a?)",1000)&REPT("a",1000),{"b";"x"},3)"#);
    assert_eq!(get(&wb, "B4"), Value::Error(XlError::Num));
    assert!(
        mentions(&problems_at(&wb, "B4"), &["XMATCH: the pattern's 1000 capture groups"]),
        "{:?}",
        problems_at(&wb, "B4")
    );
}

/// Finding every match searches again from each match's end, and a search reads on while a
/// branch of higher priority could still match: `.*[^A-Z]` stays alive to the end of a text
/// of letters, so each one-letter match of `[A-Z]` reads the rest of the text (the `regex`
/// crate's documented O(m·n²) for its iterators; 10,000 letters took 4 s, 32,767 about 40 s).
/// The bytes each search reads are added up against the same 3·10^9: a few dozen searches of
/// 10,000 letters pass it. Over 1,000 letters the same pattern answers (Python:
/// re.sub('.*[^A-Z]|[A-Z]', 'x', 'A'*1000) is 'x'*1000).
#[test]
fn finding_every_match_counts_the_bytes_each_search_reads() {
    let mut wb = Workbook::with_sheet();
    let pattern = r#"".*[^A-Z]|[A-Z]""#;
    set(&mut wb, "A1", &format!(r#"=REGEXREPLACE(REPT("A",1000),{pattern},"x")=REPT("x",1000)"#));
    assert_eq!(get(&wb, "A1"), Value::Bool(true));
    for (cell, formula) in [
        ("A2", format!(r#"=REGEXREPLACE(REPT("A",10000),{pattern},"x")"#)),
        ("A3", format!(r#"=REGEXEXTRACT(REPT("A",10000),{pattern},1)"#)),
    ] {
        set(&mut wb, cell, &formula);
        assert_eq!(get(&wb, cell), Value::Error(XlError::Num), "{formula}");
        let problems = problems_at(&wb, cell);
        assert!(
            mentions(&problems, &["finding every match", "10000 bytes", "limit of 3e9"]),
            "{formula}: {problems:?}"
        );
    }
}

/// Ordinary patterns on the longest texts a cell holds still answer: a Unicode class counts
/// the few states a thread can be in, not the hundreds it compiles to. Python:
/// re.sub(r'\s+', ' ', 'ab  cd '*4000) has 24,000 characters; the address after 10,000 "ab "
/// is dragon@xyzzy.com (the reference example of VBScript's SubMatches).
#[test]
fn ordinary_patterns_on_long_texts_still_answer() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", r#"=LEN(REGEXREPLACE(REPT("ab  cd ",4000),"\s+"," "))"#);
    assert_eq!(get(&wb, "A1"), n(24000.0));
    set(&mut wb, "A2", r#"=TEXTJOIN(",",,REGEXEXTRACT(REPT("ab ",10000)&"dragon@xyzzy.com","(\w+)@(\w+)\.(\w+)",2))"#);
    assert_eq!(get(&wb, "A2"), Value::text("dragon,xyzzy,com"));
    set(&mut wb, "A3", r#"=REGEXTEST(REPT("語",32000)&"1","^\w+\d$")"#);
    assert_eq!(get(&wb, "A3"), Value::Bool(true));
    // Every match of 32,767-character texts, each search reading a few bytes: Python's
    // re.sub('[A-Z]', '', 'A'*32767) is '', len(re.findall(r'\w+', 'word '*6553)) 6553,
    // len(re.sub(r'\d', '', 'ab1 '*8191)) 24573.
    set(&mut wb, "A4", r#"=LEN(REGEXREPLACE(REPT("A",32767),"[A-Z]",""))"#);
    assert_eq!(get(&wb, "A4"), n(0.0));
    set(&mut wb, "A5", r#"=COLUMNS(REGEXEXTRACT(REPT("word ",6553),"\w+",1))"#);
    assert_eq!(get(&wb, "A5"), n(6553.0));
    set(&mut wb, "A6", r#"=LEN(REGEXREPLACE(REPT("ab1 ",8191),"\d",""))"#);
    assert_eq!(get(&wb, "A6"), n(24573.0));
}
