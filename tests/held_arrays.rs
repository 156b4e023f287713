//! The array items one formula holds at once (issue 30): each array passed the 2^24-item
//! limit alone, but a function's arguments, an operator's operands and LET's names were all
//! held together, so `=COLUMNS(HSTACK(SEQUENCE(1048576,16), …))` of twelve arguments aborted
//! at a 4 GiB cap. One count in the evaluator (`MAX_LIVE_ITEMS`, docs/limits.md) covers
//! every way of holding them. These tests shrink it (`Settings::live_items`) to 2^20 items,
//! so that a few arrays of 300,000 items show what is held without holding gigabytes; what
//! ncsheet computes within it is checked against sums worked out here.

mod common;

use common::sheet::{get, n, set};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

/// An array of 300,000 items: three of them are less than 2^20, four are more.
const PART: &str = "SEQUENCE(1000,300)";

fn small_budget() -> Workbook {
    let mut wb = Workbook::with_sheet();
    wb.settings_mut().live_items = Some(1 << 20);
    wb
}

fn notes_at(wb: &Workbook, cell: &str) -> Vec<String> {
    let at = parse_cell(cell).unwrap();
    wb.problems().into_iter().filter(|p| p.pos == at).map(|p| p.message()).collect()
}

fn assert_held_too_much(wb: &Workbook, cell: &str) {
    assert_eq!(get(wb, cell), Value::Error(XlError::Num), "{cell}");
    let notes = notes_at(wb, cell);
    assert!(notes.iter().any(|m| m.contains("holds at once") && m.contains("1048576 items")), "{cell}: {notes:?}");
}

fn parts(k: usize) -> String {
    vec![PART; k].join(",")
}

/// HSTACK and VSTACK hold all their arguments while they build their result: two parts of
/// 200,000 items and the result fit, three do not, whatever the result's own size (1000 × 600
/// is far below the 2^24 items one array may have).
#[test]
fn stacking_functions_count_every_argument_they_hold() {
    let mut wb = small_budget();
    let parts = |k: usize| vec!["SEQUENCE(1000,200)"; k].join(",");
    set(&mut wb, "A1", &format!("=COLUMNS(HSTACK({}))", parts(2)));
    set(&mut wb, "A2", &format!("=ROWS(VSTACK({}))", parts(2)));
    set(&mut wb, "A3", &format!("=COLUMNS(HSTACK({}))", parts(3)));
    set(&mut wb, "A4", &format!("=ROWS(VSTACK({}))", parts(3)));
    set(&mut wb, "A5", &format!("=COLUMNS(CHOOSECOLS(HSTACK({}),1,2))", parts(3)));
    assert_eq!(get(&wb, "A1"), n(400.0));
    assert_eq!(get(&wb, "A2"), n(2000.0));
    for cell in ["A3", "A4", "A5"] {
        assert_held_too_much(&wb, cell);
    }
}

/// LET's names are held while its body runs, an operator's left operand while the right is
/// made, and a LAMBDA keeps the names it captured alive after the LET that bound them. An
/// array held twice (a captured name a call returns) is counted once.
#[test]
fn let_names_operands_and_captured_names_are_held() {
    let mut wb = small_budget();
    let names = |k: usize| (0..k).map(|i| format!("part_{i},{PART}")).collect::<Vec<_>>().join(",");
    let rows = |k: usize| (0..k).map(|i| format!("ROWS(part_{i})")).collect::<Vec<_>>().join("+");
    set(&mut wb, "A1", &format!("=LET({},{})", names(3), rows(3)));
    set(&mut wb, "A2", &format!("=LET({},{})", names(4), rows(4)));
    // (a + b) × (c + d): a + b is held while c + d is made, at most three arrays at once;
    // (a + b) × (c + (d + e)) holds four.
    set(&mut wb, "A3", &format!("=MAX(({PART}+{PART})*({PART}+{PART}))"));
    set(&mut wb, "A6", &format!("=MAX(({PART}+{PART})*({PART}+({PART}+{PART})))"));
    let kept = "LET(q,SEQUENCE(1000,300),LAMBDA(q))";
    let held = |k: usize| (0..k).map(|i| format!("f_{i},{kept}")).collect::<Vec<_>>().join(",");
    let called = |k: usize| (0..k).map(|i| format!("ROWS(f_{i}())")).collect::<Vec<_>>().join("+");
    set(&mut wb, "A4", &format!("=LET({},{})", held(3), called(3)));
    set(&mut wb, "A5", &format!("=LET({},{})", held(4), called(4)));
    assert_eq!(get(&wb, "A1"), n(3000.0));
    assert_held_too_much(&wb, "A2");
    // The largest item, 300,000 doubled and squared.
    assert_eq!(get(&wb, "A3"), n(600_000.0 * 600_000.0));
    assert_held_too_much(&wb, "A6");
    assert_eq!(get(&wb, "A4"), n(3000.0));
    assert_held_too_much(&wb, "A5");
}

/// What is let go is not counted: SUM reads each argument and drops it, REDUCE keeps one
/// accumulator, MAP's calls keep only their items; a call holds only its result.
#[test]
fn what_is_let_go_is_not_counted() {
    let mut wb = small_budget();
    // 1 + … + 300,000, five times over: 5 × 300000 × 300001 / 2.
    set(&mut wb, "A1", &format!("=SUM({})", parts(5)));
    // A growing accumulator: 2,000 steps of up to 2,001 items each, 2 million in all, never
    // more than two at once.
    set(&mut wb, "A2", "=ROWS(REDUCE(0,SEQUENCE(2000),LAMBDA(a,x,VSTACK(a,x))))");
    set(&mut wb, "A3", "=SUM(SCAN(0,SEQUENCE(2000),LAMBDA(a,x,IF(x>1,VSTACK(a,x),a))))");
    // Each call makes 300,000 items and returns one number: six calls, 1.8 million made.
    set(&mut wb, "A4", "=SUM(MAP(SEQUENCE(6),LAMBDA(k,SUM(SEQUENCE(1000,300)*0+k))))");
    // Ten calls in one formula, each holding 300,000 items only while it runs.
    let calls = (0..10).map(|_| format!("ROWS({PART})")).collect::<Vec<_>>().join("+");
    set(&mut wb, "A5", &format!("={calls}"));
    assert_eq!(get(&wb, "A1"), n(5.0 * 300_000.0 * 300_001.0 / 2.0));
    assert_eq!(get(&wb, "A2"), n(2001.0));
    // SCAN's items are its accumulators: 0 then, from the second step, arrays (#CALC! as items).
    assert_eq!(get(&wb, "A3"), Value::Error(XlError::Calc));
    assert_eq!(get(&wb, "A4"), n(300_000.0 * 21.0));
    assert_eq!(get(&wb, "A5"), n(10_000.0));
}

/// A range read as an array counts its cells before they are read: `B1:XFC1048575` (the
/// edges not reached, so nothing clipped to the used area) asked for 17 billion items, 412 GB,
/// and aborted; under ncsheet's own limit it is `#NUM!` with the note.
#[test]
fn a_range_read_whole_counts_its_cells_before_it_is_read() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=SUM(B1:XFC1048575*1)");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Num));
    let notes = notes_at(&wb, "A1");
    assert!(notes.iter().any(|m| m.contains("holds at once") && m.contains("67108864 items")), "{notes:?}");
    // A range of 2^20 + 2 cells under the small budget; one of 2^19 reads.
    let mut wb = small_budget();
    set(&mut wb, "A1", "=SUM(B1:C524289*1)");
    set(&mut wb, "A2", "=ROWS(B1:C262144*1)");
    assert_held_too_much(&wb, "A1");
    assert_eq!(get(&wb, "A2"), n(262_144.0));
}
