//! Recalculation behaviour of the workbook: dependencies, cycles, spills, names.

mod common;

use common::sheet::{get, n, set};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::{ProblemKind, Workbook};

#[test]
fn editing_a_cell_updates_its_dependents() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    set(&mut wb, "A2", "=A1*3");
    set(&mut wb, "A3", "=SUM(A1:A2)+1");
    assert_eq!(get(&wb, "A3"), n(9.0));
    set(&mut wb, "A1", "10");
    assert_eq!(get(&wb, "A2"), n(30.0));
    assert_eq!(get(&wb, "A3"), n(41.0));
}

#[test]
fn a_range_sees_cells_created_after_the_formula() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "B1", "=SUM(A1:A100)");
    assert_eq!(get(&wb, "B1"), n(0.0));
    set(&mut wb, "A50", "4");
    assert_eq!(get(&wb, "B1"), n(4.0));
    set(&mut wb, "C1", "=SUM(A:A)");
    set(&mut wb, "A5000", "1");
    assert_eq!(get(&wb, "C1"), n(5.0));
}

/// Excel without iterative calculation warns of a circular reference and "displays either a
/// zero or the last calculated value in the cell" (Microsoft support, "Remove or allow a
/// circular reference in Excel"): the cycle's cells keep what they held, what reads them
/// computes from that, and the cycle is named.
#[test]
fn cycles_are_named_and_keep_their_previous_values_while_the_rest_computes() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=B1+1");
    set(&mut wb, "B1", "=A1+1");
    set(&mut wb, "C1", "=A1*2");
    set(&mut wb, "D1", "5");
    set(&mut wb, "E1", "=D1+1");
    // A1 computed 1 before B1 closed the cycle; B1 never computed: 0.
    assert_eq!(get(&wb, "A1"), n(1.0));
    assert_eq!(get(&wb, "B1"), n(0.0));
    assert_eq!(get(&wb, "C1"), n(2.0));
    assert_eq!(get(&wb, "E1"), n(6.0));
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!A1".to_string(), "Sheet1!B1".to_string()]]);
    // Breaking the cycle recomputes all three.
    set(&mut wb, "B1", "1");
    assert_eq!(get(&wb, "A1"), n(2.0));
    assert_eq!(get(&wb, "C1"), n(4.0));
    assert!(wb.cycles().is_empty());
}

#[test]
fn a_cell_reading_a_range_that_holds_it_is_a_cycle() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A3", "=SUM(A1:A5)");
    // Never computed: Excel shows 0.
    assert_eq!(get(&wb, "A3"), n(0.0));
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!A3".to_string()]]);
}

#[test]
fn arrays_spill_and_report_spill_when_blocked() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "={1;2;3}");
    assert_eq!(get(&wb, "A3"), n(3.0));
    set(&mut wb, "B1", "=SUM(A1#)");
    assert_eq!(get(&wb, "B1"), n(6.0));
    set(&mut wb, "C1", "=A3*10");
    assert_eq!(get(&wb, "C1"), n(30.0));
    // A value in the way blocks the spill.
    set(&mut wb, "A2", "x");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Spill));
    assert_eq!(get(&wb, "A3"), Value::Blank);
    assert_eq!(get(&wb, "C1"), n(0.0));
    // Clearing it lets the array spill again.
    set(&mut wb, "A2", "");
    assert_eq!(get(&wb, "A1"), n(1.0));
    assert_eq!(get(&wb, "C1"), n(30.0));
}

#[test]
fn spilled_arithmetic_over_ranges() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "1");
    set(&mut wb, "A2", "2");
    set(&mut wb, "B1", "=A1:A2*10");
    assert_eq!(get(&wb, "B2"), n(20.0));
    set(&mut wb, "A2", "3");
    assert_eq!(get(&wb, "B2"), n(30.0));
}

#[test]
fn defined_names_and_other_sheets() {
    let mut wb = Workbook::with_sheet();
    let data = wb.add_sheet("Chamfer data").unwrap();
    wb.set_input(data, parse_cell("B4").unwrap(), "40").unwrap();
    wb.define_name("Dv", "='Chamfer data'!$B$4", None).unwrap();
    set(&mut wb, "A1", "=Dv/2");
    set(&mut wb, "A2", "='Chamfer data'!B4+1");
    assert_eq!(get(&wb, "A1"), n(20.0));
    assert_eq!(get(&wb, "A2"), n(41.0));
    wb.set_input(data, parse_cell("B4").unwrap(), "50").unwrap();
    assert_eq!(get(&wb, "A1"), n(25.0));
    assert_eq!(get(&wb, "A2"), n(51.0));
    set(&mut wb, "A3", "=Nowhere!A1");
    assert_eq!(get(&wb, "A3"), Value::Error(XlError::Ref));
    set(&mut wb, "A4", "=undefined_name+1");
    assert_eq!(get(&wb, "A4"), Value::Error(XlError::Name));
}

/// Names defined in bulk (a file's defined names) recalculate nothing until the one
/// recalculation after them, which also links the cells that already read them.
#[test]
fn names_defined_in_bulk_are_linked_at_the_one_recalculation_after_them() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    set(&mut wb, "B1", "=Rate*Count");
    assert_eq!(get(&wb, "B1"), Value::Error(XlError::Name));
    wb.define_name_deferred("Rate", "=Sheet1!$A$1", None).unwrap();
    wb.define_name_deferred("Count", "=3", None).unwrap();
    assert_eq!(get(&wb, "B1"), Value::Error(XlError::Name), "nothing is recalculated yet");
    wb.recalculate();
    assert_eq!(get(&wb, "B1"), n(6.0));
    // B1 now reads A1 through Rate: an edit of A1 reaches it.
    set(&mut wb, "A1", "5");
    assert_eq!(get(&wb, "B1"), n(15.0));
}

#[test]
fn a_bad_formula_is_reported_with_a_caret_and_the_rest_computes() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "1");
    let err = wb.set_input_deferred(0, parse_cell("B2").unwrap(), "=1+*2").unwrap_err();
    set(&mut wb, "C1", "=A1+1");
    assert_eq!(get(&wb, "B2"), Value::Error(XlError::Name));
    assert_eq!(get(&wb, "C1"), n(2.0));
    let text = err.to_string();
    assert!(text.starts_with("Sheet1!B2: =1+*2\n   ^ column 4"), "{text}");
    assert_eq!(wb.problems().len(), 1);
    assert_eq!(wb.formula(0, parse_cell("B2").unwrap()).as_deref(), Some("=1+*2"));
}

#[test]
fn an_edit_that_does_not_parse_is_refused_and_leaves_the_cell_as_it_was() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "B2", "=2*3");
    let refused = wb.set_input(0, parse_cell("B2").unwrap(), "=1+*2").unwrap_err();
    assert_eq!(refused.kind, ProblemKind::Parse("expected a value".into()), "{refused}");
    // The caret stands under the `*`, the fourth character.
    assert_eq!(refused.span.map(|s| s.start), Some(3));
    assert_eq!(get(&wb, "B2"), n(6.0));
    assert_eq!(wb.formula(0, parse_cell("B2").unwrap()).as_deref(), Some("=2*3"));
    assert!(wb.problems().is_empty(), "{:?}", wb.problems());
    let refused = wb.set_input(0, parse_cell("D4").unwrap(), "=SUM(").unwrap_err();
    assert_eq!((refused.sheet, refused.pos), (0, parse_cell("D4").unwrap()));
    assert_eq!(wb.input(0, parse_cell("D4").unwrap()), None);
}

#[test]
fn an_edit_returns_the_problems_it_brought_as_data() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=B1");
    let at = |cell: &str| parse_cell(cell).unwrap();
    let news = wb.set_input(0, at("B1"), "=A1+NOSUCH(1)+nothing+Gone!A1").unwrap();
    let kinds: Vec<&ProblemKind> = news.iter().map(|p| &p.kind).collect();
    assert!(kinds.contains(&&ProblemKind::UnknownFunction("NOSUCH".into())), "{news:?}");
    assert!(kinds.contains(&&ProblemKind::UnknownName("nothing".into())), "{news:?}");
    assert!(kinds.contains(&&ProblemKind::MissingSheet("Gone".into())), "{news:?}");
    assert!(kinds.iter().any(|k| matches!(k, ProblemKind::Cycle(_))), "{news:?}");
    // Each unknown points at its own words in the formula as printed.
    for p in news.iter().filter(|p| p.span.is_some_and(|s| s.end > s.start)) {
        let word = &p.text[p.span.unwrap().start as usize..p.span.unwrap().end as usize];
        let expected = match &p.kind {
            ProblemKind::UnknownFunction(_) => "NOSUCH(1)",
            ProblemKind::UnknownName(_) => "nothing",
            ProblemKind::MissingSheet(_) => "Gone!A1",
            other => panic!("{other:?}"),
        };
        assert_eq!(word, expected, "{}", p.text);
    }
    // Nothing new: an edit that brings no problem returns none, even with old ones around.
    assert_eq!(wb.set_input(0, at("C1"), "=1+1").unwrap(), vec![]);
}

/// Where `word` is in `text` (for sorting problems by their place in one formula).
fn p_start(text: &str, word: &str) -> usize {
    text.find(word).unwrap_or(usize::MAX)
}

#[test]
fn an_unknown_name_of_a_sheet_is_reported_with_its_place() {
    let mut wb = Workbook::with_sheet();
    let data = wb.add_sheet("Tool data").unwrap();
    wb.set_input(data, parse_cell("A1").unwrap(), "4").unwrap();
    wb.define_name("Known", "='Tool data'!$A$1", Some(data)).unwrap();
    let at = parse_cell("B2").unwrap();
    let news = wb.set_input(0, at, "='Tool data'!Known+'Tool data'!Nothing+Gone!Thing").unwrap();
    let mut found: Vec<(&ProblemKind, &str)> =
        news.iter().map(|p| (&p.kind, &p.text[p.span.unwrap().start as usize..p.span.unwrap().end as usize])).collect();
    found.sort_by_key(|(_, word)| p_start(&news[0].text, word));
    assert_eq!(
        found,
        [
            (&ProblemKind::UnknownName("'Tool data'!Nothing".into()), "'Tool data'!Nothing"),
            (&ProblemKind::MissingSheet("Gone".into()), "Gone!Thing"),
        ],
        "{news:?}"
    );
    assert!(news.iter().all(|p| (p.sheet, p.pos) == (0, at)));
    assert_eq!(wb.problems().len(), 2, "{:?}", wb.problems());
}

#[test]
fn copied_formulas_share_one_parsed_form() {
    let mut wb = Workbook::with_sheet();
    for r in 1..=100 {
        set(&mut wb, &format!("A{r}"), &r.to_string());
        set(&mut wb, &format!("B{r}"), &format!("=A{r}*2+SUM($A$1:A{r})"));
    }
    assert_eq!(wb.formula_counts(), (100, 1));
    assert_eq!(get(&wb, "B100"), n(200.0 + 5050.0));
    assert_eq!(wb.formula(0, parse_cell("B7").unwrap()).as_deref(), Some("=A7*2+SUM($A$1:A7)"));
}

#[test]
fn a_long_chain_recalculates_without_deep_recursion() {
    let mut wb = Workbook::with_sheet();
    wb.set_input_deferred(0, parse_cell("A1").unwrap(), "1").unwrap();
    for r in 2..=200_000u32 {
        wb.set_input_deferred(0, ncsheet::formula::Pos::new(r - 1, 0), &format!("=A{}+1", r - 1)).unwrap();
    }
    wb.recalculate();
    assert_eq!(get(&wb, "A200000"), n(200_000.0));
    set(&mut wb, "A1", "2");
    assert_eq!(get(&wb, "A200000"), n(200_001.0));
}

/// The local date as the system's `date` command prints it: (year, month, day).
fn system_date() -> Option<(f64, f64, f64)> {
    let out = std::process::Command::new("date").arg("+%Y %m %d").output().ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    let parts: Vec<f64> = text.split_whitespace().filter_map(|p| p.parse().ok()).collect();
    (parts.len() == 3).then(|| (parts[0], parts[1], parts[2]))
}

#[test]
fn today_is_the_system_clocks_local_date() {
    let Some(before) = system_date() else {
        println!("SKIPPED: no `date` command to compare TODAY() with");
        return;
    };
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=TODAY()");
    set(&mut wb, "A2", "=YEAR(A1)");
    set(&mut wb, "A3", "=MONTH(A1)");
    set(&mut wb, "A4", "=DAY(A1)");
    set(&mut wb, "A5", "=INT(NOW())=A1");
    let after = system_date().expect("date ran a moment ago");
    let ours = [get(&wb, "A2"), get(&wb, "A3"), get(&wb, "A4")];
    // Midnight may pass between the two readings of the clock: either date will do.
    let matches = |(y, m, d): (f64, f64, f64)| ours == [n(y), n(m), n(d)];
    assert!(matches(before) || matches(after), "TODAY() is {ours:?}, date says {before:?}");
    if before == after {
        assert_eq!(get(&wb, "A5"), Value::Bool(true));
    }
}

#[test]
fn volatile_cells_recalculate_at_every_edit() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=NOW()");
    set(&mut wb, "A2", "=A1*86400");
    let first = get(&wb, "A2");
    std::thread::sleep(std::time::Duration::from_millis(20));
    // An edit that NOW() does not read still moves the clock forward.
    set(&mut wb, "B1", "1");
    let Value::Number(later) = get(&wb, "A2") else { panic!("NOW() is a number") };
    let Value::Number(earlier) = first else { panic!("NOW() is a number") };
    assert!(later - earlier >= 0.015, "NOW() moved {} s", later - earlier);
    // A cell that no longer calls NOW() stops moving.
    set(&mut wb, "A1", "5");
    set(&mut wb, "B1", "2");
    assert_eq!(get(&wb, "A2"), n(432_000.0));
}

/// Operators and one- or two-number functions read number operands without building values;
/// every other kind of operand must still follow Excel's coercions.
#[test]
fn operands_of_every_kind_in_arithmetic_and_number_functions() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    set(&mut wb, "A2", "'3");
    set(&mut wb, "A3", "TRUE");
    // A4 stays empty.
    set(&mut wb, "A5", "x");
    set(&mut wb, "A6", "=1/0");
    set(&mut wb, "A7", "1E+308");
    let cases: &[(&str, Value)] = &[
        ("=A1+1", n(3.0)),
        ("=A2+1", n(4.0)),
        ("=A3+1", n(2.0)),
        ("=A4+1", n(1.0)),
        ("=A5+1", Value::Error(XlError::Value)),
        ("=A6+1", Value::Error(XlError::Div0)),
        ("=A7*10", Value::Error(XlError::Num)),
        ("=A1/A4", Value::Error(XlError::Div0)),
        ("=A1&A1", Value::text("22")),
        ("=A1>A4", Value::Bool(true)),
        ("=A1=2", Value::Bool(true)),
        ("=ZZ1048576+A1", n(2.0)),
        ("=SQRT(A1+2)", n(2.0)),
        ("=SIN(A4)", n(0.0)),
        ("=ABS(A5)", Value::Error(XlError::Value)),
        ("=ABS(A6)", Value::Error(XlError::Div0)),
        ("=ROUND(A1/3,A4)", n(1.0)),
        ("=ROUND(2.5,)", n(3.0)),
        ("=ROUND(A1/3,2)", n(0.67)),
        ("=ROUND(A5,1)", Value::Error(XlError::Value)),
        ("=ROUND(A1,A6)", Value::Error(XlError::Div0)),
    ];
    for (i, (formula, want)) in cases.iter().enumerate() {
        let cell = format!("C{}", i + 1);
        set(&mut wb, &cell, formula);
        assert_eq!(&get(&wb, &cell), want, "{formula}");
    }
}

/// Formulas that differ only in their numbers share one tree, each reading its own numbers.
#[test]
fn formulas_differing_in_numbers_read_their_own() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    set(&mut wb, "B1", "=$A$1*7+1");
    set(&mut wb, "B2", "=$A$1*8+1");
    set(&mut wb, "C1", "=ROUND($A$1/3,2)");
    set(&mut wb, "C2", "=ROUND($A$1/3,3)");
    set(&mut wb, "D1", "=SQRT($A$1*8)");
    set(&mut wb, "D2", "=SQRT($A$1*18)");
    assert_eq!(get(&wb, "B1"), n(15.0));
    assert_eq!(get(&wb, "B2"), n(17.0));
    assert_eq!(get(&wb, "C1"), n(0.67));
    assert_eq!(get(&wb, "C2"), n(0.667));
    assert_eq!(get(&wb, "D1"), n(4.0));
    assert_eq!(get(&wb, "D2"), n(6.0));
    set(&mut wb, "A1", "4.5");
    assert_eq!(get(&wb, "B2"), n(37.0));
    assert_eq!(get(&wb, "C2"), n(1.5));
    assert_eq!(get(&wb, "D2"), n(9.0));
}

/// INDIRECT and OFFSET reach cells their text does not name; an edit there still
/// recomputes them, in order, as in Excel.
#[test]
fn run_time_references_follow_the_cells_they_reach() {
    let mut wb = Workbook::with_sheet();
    // C1 is set first, so a pass that ordered it by its text alone would run it before A2.
    set(&mut wb, "C1", "=INDIRECT(B1)*10");
    set(&mut wb, "C2", "=SUM(OFFSET(A1,1,0,2,1))");
    set(&mut wb, "B1", "A2");
    set(&mut wb, "A1", "1");
    set(&mut wb, "A2", "=A1*2");
    set(&mut wb, "A3", "=A2+1");
    assert_eq!(get(&wb, "C1"), n(20.0));
    assert_eq!(get(&wb, "C2"), n(5.0));
    set(&mut wb, "A1", "5");
    assert_eq!(get(&wb, "C1"), n(100.0));
    assert_eq!(get(&wb, "C2"), n(21.0));
    // Pointed elsewhere, it follows the new cell and no longer the old one.
    set(&mut wb, "B1", "A3");
    assert_eq!(get(&wb, "C1"), n(110.0));
    set(&mut wb, "A3", "7");
    assert_eq!(get(&wb, "C1"), n(70.0));
    // A cell that reaches itself is a cycle.
    set(&mut wb, "D1", "=INDIRECT(\"D1\")+1");
    // It shows 0, as Excel shows a circular formula it meets at entry and as `=D1+1` shows;
    // not 1, its first computation reading itself as blank before the reference was known.
    assert_eq!(get(&wb, "D1"), n(0.0));
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!D1".to_string()]]);
    // INDIRECT is volatile: every edit computes it again, and it keeps its 0.
    set(&mut wb, "E5", "1");
    assert_eq!(get(&wb, "D1"), n(0.0));
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!D1".to_string()]]);
    // Where a reference is, unlike what it holds, is no dependency (Excel: no cycle).
    set(&mut wb, "D2", "=ROW(INDIRECT(\"D2\"))+ISREF(OFFSET(A1,1,3))");
    assert_eq!(get(&wb, "D2"), n(3.0));
}

#[test]
fn run_time_references_computed_in_a_full_recalculation() {
    let mut wb = Workbook::with_sheet();
    for (cell, input) in [("E1", "=INDIRECT(\"A\"&B1)"), ("A1", "3"), ("A2", "=A1^2"), ("B1", "2")] {
        wb.set_input_deferred(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    wb.recalculate();
    assert_eq!(get(&wb, "E1"), n(9.0));
}

#[test]
fn a_reference_only_located_is_no_cycle() {
    // Excel finds cycles from what evaluation reads: INDEX in row 2 reads only B2, a
    // condition that stays false never reads its own cell.
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "B2", "7");
    set(&mut wb, "A2", "=INDEX(2:2,1,2)");
    set(&mut wb, "C3", "0");
    set(&mut wb, "C4", "=IF(C3=0,0,C4+1)");
    set(&mut wb, "D1", "=ROWS(D:D)+COLUMNS(1:1)");
    assert_eq!(get(&wb, "A2"), n(7.0));
    assert_eq!(get(&wb, "C4"), n(0.0));
    assert_eq!(get(&wb, "D1"), n(1_048_576.0 + 16_384.0));
    assert!(wb.cycles().is_empty());
    set(&mut wb, "B2", "8");
    assert_eq!(get(&wb, "A2"), n(8.0));
    // Once the condition holds, the cell reads itself: a cycle, the last calculated value kept.
    set(&mut wb, "C3", "1");
    assert_eq!(get(&wb, "C4"), n(0.0));
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!C4".to_string()]]);
    // A range built from INDEX results names the row it sits in, reads what it sums.
    set(&mut wb, "E5", "=SUM(INDEX(5:5,1,1):INDEX(5:5,1,3))");
    set(&mut wb, "A5", "1");
    set(&mut wb, "C5", "2");
    assert_eq!(get(&wb, "E5"), n(3.0));
}

#[test]
fn iterative_calculation_runs_a_cycle_to_its_limits() {
    use ncsheet::workbook::Iteration;
    // Excel's own illustration: A1 = 1+A2, A2 = 1+A1 with 10 iterations shows 19 and 20
    // (each cell reads the other's latest value, in cell order).
    let mut wb = Workbook::with_sheet();
    wb.set_iteration(Some(Iteration { count: 10, max_change: 0.001 }));
    set(&mut wb, "A1", "=1+A2");
    set(&mut wb, "A2", "=1+A1");
    assert_eq!(get(&wb, "A1"), n(19.0));
    assert_eq!(get(&wb, "A2"), n(20.0));
    assert!(wb.cycles().is_empty());
    // A converging cycle stops once no value moves by more than the maximum change.
    set(&mut wb, "B1", "=B2/2+1");
    set(&mut wb, "B2", "=B1");
    let b1 = match get(&wb, "B1") {
        Value::Number(x) => x,
        v => panic!("{v:?}"),
    };
    assert!((b1 - 2.0).abs() < 0.002, "{b1}");
    // Without iteration the cycle keeps its last calculated values, and is named.
    wb.set_iteration(None);
    assert_eq!(get(&wb, "A1"), n(19.0));
    assert_eq!(get(&wb, "A2"), n(20.0));
    assert!(!wb.cycles().is_empty());
}

// Excel 365 spills a whole row or column over the whole row or column, blanks read as 0,
// and refuses (#SPILL!) one that would pass the sheet's edge ("Spill range extends beyond
// the worksheet's edge", Microsoft's #SPILL! page). The cells beyond the used area are
// not stored: reading them, and editing into them, still sees the spill.
#[test]
fn a_whole_row_from_another_sheet_spills_to_the_last_column_blanks_as_zero() {
    let mut wb = Workbook::with_sheet();
    let first = wb.add_sheet("First").unwrap();
    wb.set_input(first, parse_cell("A1").unwrap(), "1").unwrap();
    wb.set_input(first, parse_cell("C1").unwrap(), "x").unwrap();
    set(&mut wb, "A3", "=XFD1+5");
    set(&mut wb, "A4", "=COUNT(1:1)");
    set(&mut wb, "A5", "=SUM(B1:XFD1)+COUNTA(D1:XFD1)");
    set(&mut wb, "A1", "=First!1:1");
    assert_eq!(get(&wb, "A1"), n(1.0));
    assert_eq!(get(&wb, "B1"), n(0.0));
    assert_eq!(get(&wb, "C1"), Value::text("x"));
    assert_eq!(get(&wb, "XFD1"), n(0.0));
    assert_eq!(get(&wb, "A3"), n(5.0));
    // Every cell of row 1 but the text is a number.
    assert_eq!(get(&wb, "A4"), n(16383.0));
    assert_eq!(get(&wb, "A5"), n(16381.0));
    wb.set_input(first, parse_cell("XFD1").unwrap(), "7").unwrap();
    assert_eq!(get(&wb, "XFD1"), n(7.0));
    assert_eq!(get(&wb, "A3"), n(12.0));
    wb.set_input(first, parse_cell("XFD1").unwrap(), "").unwrap();
    assert_eq!(get(&wb, "A3"), n(5.0));
    // A value typed into the tail blocks the spill; taking it away lets it spill again.
    set(&mut wb, "Z1", "y");
    assert_eq!(get(&wb, "A1"), Value::Error(XlError::Spill));
    assert_eq!(get(&wb, "XFD1"), Value::Blank);
    assert_eq!(get(&wb, "A3"), n(5.0));
    assert_eq!(get(&wb, "A4"), n(0.0));
    set(&mut wb, "Z1", "");
    assert_eq!(get(&wb, "A4"), n(16383.0));
    assert_eq!(get(&wb, "Z1"), n(0.0));
}

#[test]
fn arithmetic_on_whole_rows_and_columns_spills_over_them() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    set(&mut wb, "B1", "3");
    set(&mut wb, "A2", "=1:1*2");
    assert_eq!(get(&wb, "B2"), n(6.0));
    assert_eq!(get(&wb, "XFD2"), n(0.0));
    // A blank compared is a blank compared, in every one of the 16,384 columns.
    set(&mut wb, "A3", "=IF(1:1=\"\",\"-\",1:1)");
    assert_eq!(get(&wb, "B3"), n(3.0));
    assert_eq!(get(&wb, "XFD3"), Value::text("-"));
    set(&mut wb, "A4", "=COUNTIF(3:3,\"-\")");
    assert_eq!(get(&wb, "A4"), n(16382.0));
}

#[test]
fn a_whole_column_spills_down_to_the_last_row_and_not_past_it() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "2");
    set(&mut wb, "A2", "3");
    set(&mut wb, "C1", "=A:A+1");
    assert_eq!(get(&wb, "C2"), n(4.0));
    assert_eq!(get(&wb, "C1048576"), n(1.0));
    set(&mut wb, "D2", "=A:A");
    assert_eq!(get(&wb, "D2"), Value::Error(XlError::Spill));
    // Beyond a shorter operand the items are #N/A, to the sheet's edge.
    set(&mut wb, "E1", "=A:A+A1:A3");
    assert_eq!(get(&wb, "E2"), n(6.0));
    assert_eq!(get(&wb, "E3"), n(0.0));
    assert_eq!(get(&wb, "E4"), Value::Error(XlError::NA));
    assert_eq!(get(&wb, "E1048576"), Value::Error(XlError::NA));
    set(&mut wb, "H1", "=ROWS(A:A+1)*10+COLUMNS(5:5*2)");
    assert_eq!(get(&wb, "H1"), n(1_048_576.0 * 10.0 + 16_384.0));
    set(&mut wb, "F1", "=SUM(C:C)+COUNT(C:C)");
    assert_eq!(get(&wb, "F1"), n(3.0 + 4.0 + 1_048_574.0 + 1_048_576.0));
    // An edit above the tail moves it; a cell read inside the tail follows.
    set(&mut wb, "G1", "=C900000*10");
    assert_eq!(get(&wb, "G1"), n(10.0));
    set(&mut wb, "A900000", "4");
    assert_eq!(get(&wb, "G1"), n(50.0));
}
