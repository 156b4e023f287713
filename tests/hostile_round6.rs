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

fn number(formula: &str) -> f64 {
    match common::sheet::eval_a1(&format!("={formula}")).0 {
        ncsheet::eval::Value::Number(n) => n,
        other => panic!("{formula}: {other:?}"),
    }
}

fn close(formula: &str, want: f64) {
    let got = number(formula);
    assert!((got - want).abs() <= 1e-13 * want.abs(), "{formula}: {got}, not {want}");
}

/// With one degree of freedom Student's t is Cauchy's distribution, whose two tails beyond t
/// hold 1 - 2·atan(t)/π, so T.INV.2T(p, 1) = cot(πp/2) (mpmath, 30 digits:
/// 6.36619772367581343E+299 for p = 1E-300; 12.7062047361747 for 0.05, the tables' 12.706).
/// Past 1.34E+154, where t² overflows, the tail read 0 and the search stopped at that edge:
/// T.INV.2T(1E-300, 1) and T.INV(1E-200, 1) were ±1.34078079299426E+154.
#[test]
fn t_quantiles_past_where_t_squared_overflows_are_cauchys() {
    close("T.INV.2T(1E-300,1)", 6.366_197_723_675_813e299);
    close("T.INV(1E-200,1)", -3.183_098_861_837_907e199);
    close("T.INV.2T(0.05,1)", 12.706_204_736_174_705);
}

/// A sum of binomial terms that cannot be computed (ln Γ of a count past 1E+307 is infinite,
/// the term NaN) was turned into 1 by `f64::min`: BINOM.DIST.RANGE(1E308,0.5,0,0), whose
/// value 0.5^1E308 is 0, was 1. It is #NUM!, as BINOM.DIST of such a count is.
#[test]
fn binomial_sums_that_cannot_be_computed_are_num_not_one() {
    for formula in ["=BINOM.DIST.RANGE(1E308,0.5,0,0)", "=BINOM.DIST.RANGE(1E307,0.5,0)"] {
        let value = common::sheet::eval_a1(formula).0;
        assert_eq!(value, ncsheet::eval::Value::Error(ncsheet::eval::XlError::Num), "{formula}");
    }
}

/// GAMMA.INV(0.999999, 1E-300, 1E+300): for a shape a near 0, P(X ≤ x) ≈ (x/β)^a, so the
/// quantile is β·0.999999^(1/a) = β·exp(-1E+294), below every double: 0. Searching x itself,
/// x/β underflowed first and the search settled at β × the smallest double, 2.47E-24.
#[test]
fn a_gamma_quantile_below_every_double_is_zero_whatever_the_scale() {
    assert_eq!(number("GAMMA.INV(0.999999,1E-300,1E+300)"), 0.0);
    // An ordinary one keeps its value: GAMMA.INV(0.5, 1, 2) is the exponential's median 2·ln 2.
    close("GAMMA.INV(0.5,1,2)", 2.0 * std::f64::consts::LN_2);
}

/// A chain A1 = A5000 + 1, Ai = A(i-1) + 1: each round of the iteration adds 1 to every cell
/// in order, so after r rounds A5000 holds 5000·r (worked by hand). Excel's largest count,
/// 32,767 rounds, is 164 million evaluations (minutes with INDEX or INDIRECT in the cells):
/// the budget of 10,000,000 evaluations a cycle gives this one 2,000 rounds, A5000 = 10,000,000,
/// and its first cell says where it stopped. A two-cell cycle keeps all 32,767 rounds.
#[test]
fn iteration_of_a_large_cycle_stops_at_the_work_budget_and_says_so() {
    use ncsheet::workbook::{Iteration, ProblemKind, Workbook};
    let mut wb = Workbook::with_sheet();
    wb.set_iteration(Some(Iteration { count: 32_767, max_change: 0.0 }));
    common::sheet::set(&mut wb, "A1", "=A5000+1");
    for row in 2..=5000 {
        common::sheet::set(&mut wb, &format!("A{row}"), &format!("=A{}+1", row - 1));
    }
    assert_eq!(common::sheet::get(&wb, "A5000"), common::sheet::n(10_000_000.0));
    let cut = wb.problems().into_iter().find(|p| matches!(p.kind, ProblemKind::IterationCut { .. }));
    let cut = cut.expect("the cut is reported");
    assert_eq!(cut.kind, ProblemKind::IterationCut { cells: 5000, rounds: 2000, asked: 32_767, limit: 10_000_000 });
    assert!(cut.message().contains("stopped after 2000 of its 32767 rounds"), "{}", cut.message());

    let mut small = Workbook::with_sheet();
    small.set_iteration(Some(Iteration { count: 32_767, max_change: 0.0 }));
    common::sheet::set(&mut small, "A1", "=B1+1");
    common::sheet::set(&mut small, "B1", "=A1+1");
    assert_eq!(common::sheet::get(&small, "B1"), common::sheet::n(65_534.0));
    assert!(small.problems().is_empty());
}

/// The rounds a cycle's iteration ran before the budget stopped it, from its first cell's
/// note (`None`: it was not stopped).
fn iteration_cut(wb: &ncsheet::workbook::Workbook) -> Option<(u32, u64)> {
    use ncsheet::workbook::ProblemKind;
    wb.problems().into_iter().find_map(|p| match p.kind {
        ProblemKind::IterationCut { rounds, limit, .. } => Some((rounds, limit)),
        _ => None,
    })
}

/// An iterating cycle is charged the work inside its cells, not only their count: A1 =
/// B1+0*SUM(SEQUENCE(10000)), B1 = A1+1 makes at least 10,000 items in each evaluation of
/// A1, at least 625 evaluations' worth (16 items an evaluation), so a budget of 100,000 allows
/// at most 161 rounds, where a count of evaluations allowed 32,767 (two cells, 65,534
/// evaluations, each of 10^6 items took minutes). After r rounds from 0, A1 is r − 1 and
/// B1 is r (worked by hand). A LAMBDA's calls count as evaluations: A1 = A1 + SUM of a
/// 30 × 30 MAKEARRAY of its row number (900 calls, 30 × 465 = 13,950 a round) stops within
/// 112 rounds at 13,950 × rounds.
#[test]
fn iterating_cells_are_charged_the_work_they_do() {
    use ncsheet::workbook::{Iteration, Workbook};
    let iterating = |cells: &[(&str, &str)]| {
        let mut wb = Workbook::with_sheet();
        wb.settings_mut().iteration_work = Some(100_000);
        wb.set_iteration(Some(Iteration { count: 32_767, max_change: 0.0 }));
        for (cell, formula) in cells {
            common::sheet::set(&mut wb, cell, formula);
        }
        wb
    };
    let wb = iterating(&[("A1", "=B1+0*SUM(SEQUENCE(10000))"), ("B1", "=A1+1")]);
    let (rounds, limit) = iteration_cut(&wb).expect("the cut is reported");
    assert_eq!(limit, 100_000);
    assert!((1..=161).contains(&rounds), "{rounds} rounds");
    assert_eq!(common::sheet::get(&wb, "A1"), common::sheet::n(f64::from(rounds) - 1.0));
    assert_eq!(common::sheet::get(&wb, "B1"), common::sheet::n(f64::from(rounds)));
    assert!(wb.formulas_evaluated() <= 2 * 161 + 10, "{} evaluations", wb.formulas_evaluated());

    let wb = iterating(&[("A1", "=A1+SUM(MAKEARRAY(30,30,LAMBDA(r,c,r)))")]);
    let (rounds, _) = iteration_cut(&wb).expect("the cut is reported");
    assert!((1..=112).contains(&rounds), "{rounds} rounds");
    assert_eq!(common::sheet::get(&wb, "A1"), common::sheet::n(13_950.0 * f64::from(rounds)));
    let note = wb.problems().into_iter().map(|p| p.message()).find(|m| m.contains("stopped after"));
    assert!(
        note.as_deref().is_some_and(|m| m.starts_with("the iteration of this cycle of 1 cell stopped")),
        "{note:?}"
    );
}

/// The budget is the recalculation's, not each cycle's: 400 two-cell cycles (Ak = Bk+1,
/// Bk = Ak+1, each 65,534 evaluations for Excel's 32,767 rounds) are 26 million evaluations,
/// where 5,000 such cycles took 23 s with a budget for each. After r rounds from 0, Ak is
/// 2r − 1 (worked by hand): 152 cycles have all their rounds (152 × 65,534 is within 10,000,000), the
/// rest what is left, then one round each, every cut one saying so.
#[test]
fn many_iterating_cycles_share_one_work_budget() {
    use ncsheet::workbook::{Iteration, ProblemKind, Workbook};
    let mut wb = Workbook::with_sheet();
    wb.set_iteration(Some(Iteration { count: 32_767, max_change: 0.0 }));
    for k in 1..=400 {
        let at = |cell: String| ncsheet::formula::address::parse_cell(&cell).unwrap();
        let (a, b) = (at(format!("A{k}")), at(format!("B{k}")));
        wb.set_input_deferred(0, a, &format!("=B{k}+1")).unwrap();
        wb.set_input_deferred(0, b, &format!("=A{k}+1")).unwrap();
    }
    let before = wb.formulas_evaluated();
    wb.recalculate();
    let evaluated = wb.formulas_evaluated() - before;
    assert!(evaluated <= 10_000_000 + 2 * 400 * 2, "{evaluated} evaluations");
    let settled = (1..=400).filter(|k| common::sheet::get(&wb, &format!("A{k}")) == common::sheet::n(65_533.0)).count();
    assert_eq!(settled, 152);
    let cuts = wb.problems().into_iter().filter(|p| matches!(p.kind, ProblemKind::IterationCut { .. })).count();
    assert_eq!(cuts, 400 - 152);
}
