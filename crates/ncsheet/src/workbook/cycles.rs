//! What a cycle of the dependency graph computes. The graph links a formula to every cell
//! it names, but Excel finds circular references from what evaluation reads:
//! `=INDEX(2:2,1,2)` in A2 names row 2 and reads only B2, `=IF(B3=0,0,B10+1)` in B10 reads
//! B10 only while B3 is not 0. So the cells of a strongly connected component are
//! evaluated on demand: a cell whose evaluation reads no cell still waiting is computed,
//! which may free others; those left waiting read each other and are circular: they keep
//! their previous values, 0 if they had none, as Excel does without iterative calculation.
//!
//! With iterative calculation on (`<calcPr iterate="1">`, [`Iteration`]) a cycle is not an
//! error: its cells are recalculated in sheet, row, column order, each reading the others'
//! latest values, until no value moves by more than the maximum change or the count runs
//! out, as Excel does. Excel starts from the values the cells show; so does a file reader
//! here (`set_starting_value_deferred`), and a first round that moves nothing by more than
//! the maximum change keeps them.

use std::cell::Cell;
use std::rc::Rc;

use crate::eval::{Ctx, Env, Note, UserCall, Value, WorkDone};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{Expr, SheetId};

use super::graph::FxMap;
use super::Workbook;

/// Excel's iterative calculation: at most `count` rounds, stopping once no value of the
/// cycle changes by more than `max_change`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iteration {
    pub count: u32,
    pub max_change: f64,
}

impl Default for Iteration {
    /// Excel's defaults (File > Options > Formulas).
    fn default() -> Iteration {
        Iteration { count: 100, max_change: 0.001 }
    }
}

/// Cell evaluations the iterating cycles of one recalculation may spend together, rounds ×
/// cells summed over the cycles, with the work inside each evaluation ([`round_cost`]):
/// Excel's largest count, 32,767 rounds, of a 5,000-cell cycle is 164 million evaluations,
/// which ran for minutes with INDEX or INDIRECT in each cell, and so did 10,000 two-cell
/// cycles (each within a budget of its own), and two cells, one of them summing a
/// SEQUENCE of a million items. A cycle of up to 305 plain cells alone has all 32,767
/// rounds; a larger one, one doing more work, or one met after others spent the budget,
/// stops earlier, its first cell saying so ([`IterationCut`]).
pub const MAX_ITERATION_EVALUATIONS: u64 = 10_000_000;

/// Units of work ([`WorkDone::items`]: array items made or read, cells read, 16 bytes of
/// text) an evaluation of the budget stands for: a plain cell's evaluation costs about as
/// much as making or reading 10 to 20 items (`SUM(SEQUENCE(1000000))` about 11 ms). A
/// LAMBDA call ([`WorkDone::calls`]) counts as an evaluation of its own.
pub const ITEMS_PER_EVALUATION: u64 = 16;

/// What a round of a cycle of `cells` cells cost against [`MAX_ITERATION_EVALUATIONS`]: an
/// evaluation per cell, and the work `done` inside them.
fn round_cost(cells: usize, done: WorkDone) -> u64 {
    (cells as u64).saturating_add(done.calls).saturating_add(done.items / ITEMS_PER_EVALUATION)
}

/// A cycle whose iteration the budget ([`MAX_ITERATION_EVALUATIONS`], or the workbook's
/// smaller `limit`) stopped before it settled or ran the rounds the workbook asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationCut {
    pub cells: usize,
    pub rounds: u32,
    pub asked: u32,
    pub limit: u64,
}

/// A component larger than this is not probed cell by cell (each probe of a range looks
/// through the waiting cells): all its cells are circular, as the graph says.
const PROBED_COMPONENT: usize = 4096;

/// Evaluations spent resolving one component on demand before the rest is called circular
/// (each round evaluates every waiting cell; a chain computes one cell per round at worst).
const DEMAND_BUDGET: usize = 1 << 20;

impl Workbook {
    /// Computes the formula cells of one strongly connected component (in sheet, row,
    /// column order) and returns those that are circular, which the caller marks.
    pub(super) fn settle_component(&mut self, cells: &[u32], late: &mut Vec<u32>) -> Vec<u32> {
        if let Some(iteration) = self.iteration {
            self.iterate_component(cells, iteration, late);
            return Vec::new();
        }
        if cells.len() > PROBED_COMPONENT {
            return cells.to_vec();
        }
        self.settle_on_demand(cells, late)
    }

    /// Evaluates, round after round, each waiting cell whose evaluation reads no waiting
    /// cell; the cells still waiting when a round frees none are circular.
    fn settle_on_demand(&mut self, cells: &[u32], late: &mut Vec<u32>) -> Vec<u32> {
        let mut waiting: Vec<u32> = cells.to_vec();
        let mut places: FxMap<(SheetId, Pos), ()> = FxMap::default();
        for &id in cells {
            places.insert(self.place(id), ());
        }
        let mut budget = DEMAND_BUDGET;
        loop {
            let before = waiting.len();
            let mut i = 0;
            while i < waiting.len() && budget > 0 {
                budget -= 1;
                let id = waiting[i];
                if self.reads_any(id, &places) {
                    i += 1;
                } else {
                    waiting.remove(i);
                    places.remove(&self.place(id));
                    self.evaluate(id, late);
                }
            }
            if waiting.len() == before || waiting.is_empty() || budget == 0 {
                return waiting;
            }
        }
    }

    fn place(&self, id: u32) -> (SheetId, Pos) {
        let c = &self.cells[id as usize];
        (c.sheet, c.pos)
    }

    /// Whether evaluating formula cell `id` reads the value of a cell at one of `waiting`
    /// (its own included). The result is thrown away.
    fn reads_any(&self, id: u32, waiting: &FxMap<(SheetId, Pos), ()>) -> bool {
        let probe = Probe { wb: self, waiting, hit: Cell::new(false) };
        let cell = &self.cells[id as usize];
        let formula = self.formulas.get(cell.formula);
        let mut ctx = Ctx::new(&probe, cell.sheet, cell.pos);
        ctx.numbers = &formula.numbers;
        let _ = ctx.eval(&formula.expr);
        probe.hit.get()
    }

    /// Excel's iteration over a cycle: rounds in cell order, each cell reading the latest
    /// values, until the largest change of a round is within the limit.
    /// Values that a first round moves by no more than the maximum change had converged
    /// already and stay as they were: a workbook Excel saved shows its iterated values.
    ///
    /// Each round is charged what it cost ([`round_cost`]) against the recalculation's
    /// budget; the next round runs only while one more like the last one fits (the first
    /// always runs), so a cycle of plain cells gets budget ÷ cells rounds.
    fn iterate_component(&mut self, cells: &[u32], iteration: Iteration, late: &mut Vec<u32>) {
        let start = self.iteration_start(cells, late);
        let asked = iteration.count.max(1);
        let limit = self.settings.iteration_work.unwrap_or(MAX_ITERATION_EVALUATIONS);
        self.iteration_cuts.remove(&cells[0]);
        let mut last_cost = 0;
        for round in 0..asked {
            if round > 0 && self.cycles.iteration_spent.saturating_add(last_cost) > limit {
                let cut = IterationCut { cells: cells.len(), rounds: round, asked, limit };
                self.iteration_cuts.insert(cells[0], cut);
                return;
            }
            let work_before = self.scratch.work.get();
            let largest = self.iteration_round(cells, late);
            let work_after = self.scratch.work.get();
            let done =
                WorkDone { items: work_after.items - work_before.items, calls: work_after.calls - work_before.calls };
            last_cost = round_cost(cells.len(), done);
            self.cycles.iteration_spent = self.cycles.iteration_spent.saturating_add(last_cost);
            if largest <= iteration.max_change {
                if round == 0 {
                    for (&id, value) in cells.iter().zip(start) {
                        self.set_result(id, value, late);
                    }
                }
                return;
            }
        }
    }

    /// One round of an iteration: each cell of the cycle evaluated in order; returns how far
    /// the value that moved most moved.
    fn iteration_round(&mut self, cells: &[u32], late: &mut Vec<u32>) -> f64 {
        let mut largest = 0.0f64;
        for &id in cells {
            let before = self.cells[id as usize].value.clone();
            self.evaluate(id, late);
            largest = largest.max(change(&before, &self.cells[id as usize].value));
        }
        largest
    }

    /// The values a cycle's iteration starts from, each cell set back to it: those the cells
    /// held before this recalculation. A cycle that INDEX, OFFSET or INDIRECT made is found
    /// only in the pass after the one that evaluated its cells through links not yet made;
    /// starting from that pass's values ran the iteration ahead of the same cycle written
    /// with plain references (a 5,000-cell chain ended 2 above it after 10 rounds).
    fn iteration_start(&mut self, cells: &[u32], late: &mut Vec<u32>) -> Vec<Value> {
        let mut start = Vec::with_capacity(cells.len());
        for &id in cells {
            match self.scratch.before_relink.remove(&id) {
                Some(before) => {
                    self.set_result(id, before.clone(), late);
                    start.push(before);
                }
                None => start.push(self.cells[id as usize].value.clone()),
            }
        }
        start
    }

    /// The value a formula cell holds before the next recalculation: where an iterating
    /// cycle starts from (a file reader gives it the value the file cached, as Excel
    /// continues from the values it shows). No effect on other cells.
    pub fn set_starting_value_deferred(&mut self, sheet: SheetId, pos: Pos, value: Value) {
        let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) else { return };
        // An array formula's anchor starts from the values of its whole area.
        let fits = !matches!(value, Value::Array(_)) || self.fixed_arrays.contains_key(&id);
        if self.cells[id as usize].formula != super::NO_FORMULA && fits {
            self.cells[id as usize].value = value;
        }
    }

    /// The cells of the circular references the recalculations found: a file reader starts
    /// them from the values the file cached (see [`Workbook::set_starting_value_deferred`]),
    /// which they then keep, as in Excel.
    pub fn cycle_cells(&self) -> Vec<(SheetId, Pos)> {
        self.cycles.iter().flatten().map(|&id| self.place(id)).collect()
    }

    /// Turns iterative calculation on (with its limits) or off, and recalculates.
    pub fn set_iteration(&mut self, iteration: Option<Iteration>) {
        if self.iteration != iteration {
            self.iteration = iteration;
            self.recalculate();
        }
    }

    /// The iterative-calculation setting (`None`: a cycle is an error).
    pub fn iteration(&self) -> Option<Iteration> {
        self.iteration
    }
}

/// How far a value moved in one round: numbers by their difference, anything else by
/// whether it changed.
fn change(before: &Value, after: &Value) -> f64 {
    let number = |v: &Value| match v {
        Value::Number(n) => Some(*n),
        Value::Blank => Some(0.0),
        _ => None,
    };
    match (number(before), number(after)) {
        (Some(a), Some(b)) => (a - b).abs(),
        _ if before == after => 0.0,
        _ => f64::INFINITY,
    }
}

/// The workbook as a formula reads it, noting whether it reads a cell still waiting.
struct Probe<'a> {
    wb: &'a Workbook,
    waiting: &'a FxMap<(SheetId, Pos), ()>,
    hit: Cell<bool>,
}

impl Probe<'_> {
    fn note(&self, sheet: SheetId, rect: Rect) {
        if self.hit.get() {
            return;
        }
        let found = if rect.is_cell() {
            self.waiting.contains_key(&(sheet, rect.first))
        } else {
            self.waiting.keys().any(|&(s, p)| s == sheet && rect.contains(p))
        };
        self.hit.set(found);
    }
}

impl Env for Probe<'_> {
    fn value(&self, sheet: SheetId, pos: Pos) -> Value {
        self.note(sheet, Rect::cell(pos));
        self.wb.value(sheet, pos)
    }

    fn number(&self, sheet: SheetId, pos: Pos) -> Option<f64> {
        self.note(sheet, Rect::cell(pos));
        Env::number(self.wb, sheet, pos)
    }

    fn for_each_value(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(Pos, &Value)) {
        self.note(sheet, rect);
        self.wb.for_each_value(sheet, rect, f)
    }

    fn used_rect(&self, sheet: SheetId) -> Option<Rect> {
        Env::used_rect(self.wb, sheet)
    }

    /// A whole row or column is read whole, beyond the used area too: a waiting cell there
    /// (blank until computed) is read.
    fn used_rect_for(&self, sheet: SheetId, rect: Rect) -> Option<Rect> {
        self.note(sheet, rect);
        Env::used_rect_for(self.wb, sheet, rect)
    }

    fn defined_name(&self, name: &str, sheet: SheetId) -> Option<(Rc<Expr>, SheetId)> {
        self.wb.defined_name(name, sheet)
    }

    fn table_part(
        &self,
        r: &crate::formula::ast::TableRef,
        sheet: SheetId,
        pos: Pos,
    ) -> Result<(SheetId, Rect), crate::formula::ast::XlError> {
        self.wb.table_part(r, sheet, pos)
    }

    fn pivot_data(
        &self,
        sheet: SheetId,
        at: Pos,
        data_field: &str,
        pairs: &[(String, Value)],
    ) -> Result<Value, String> {
        self.wb.pivot_data(sheet, at, data_field, pairs)
    }

    /// A waiting anchor's spill area is not known yet: asking for it is reading it.
    fn spill_rect(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
        self.note(sheet, Rect::cell(pos));
        self.wb.spill_rect(sheet, pos)
    }

    fn sheet_count(&self) -> usize {
        self.wb.sheet_count()
    }

    fn sheet_name(&self, sheet: SheetId) -> Option<String> {
        self.wb.sheet_name(sheet)
    }

    fn tab_position(&self, sheet: SheetId) -> usize {
        Env::tab_position(self.wb, sheet)
    }

    fn sheets_spanned(&self, first: SheetId, last: SheetId) -> Vec<SheetId> {
        Env::sheets_spanned(self.wb, first, last)
    }

    fn formula_text(&self, sheet: SheetId, pos: Pos) -> Option<String> {
        self.wb.formula_text(sheet, pos)
    }

    fn is_subtotal(&self, sheet: SheetId, pos: Pos) -> bool {
        self.wb.is_subtotal(sheet, pos)
    }

    fn date_system(&self) -> crate::eval::dates::DateSystem {
        self.wb.date_system()
    }

    fn now(&self) -> f64 {
        self.wb.settings.now(self.wb.date_system())
    }

    fn next_random(&self) -> f64 {
        self.wb.settings.next_random()
    }

    fn vba_rnd(&self, n: f64) -> f64 {
        self.wb.settings.vba_rnd.draw(n)
    }

    fn lambda_work_limit(&self) -> u64 {
        self.wb.settings.lambda_work_limit()
    }

    fn live_items_limit(&self) -> usize {
        self.wb.settings.live_items_limit()
    }

    fn locale(&self) -> crate::eval::Locale {
        self.wb.settings.locale_in_force(self.wb.date_system())
    }

    fn excel_language(&self) -> Option<&'static str> {
        Env::excel_language(self.wb)
    }

    fn column_width(&self, sheet: SheetId, col: u32) -> Option<f64> {
        Env::column_width(self.wb, sheet, col)
    }

    /// The function reads cells through the probe: what it reads is what the cell reads.
    fn call_user_function(&self, cells: &dyn Env, call: &UserCall) -> Option<Result<Value, Note>> {
        self.wb.call_user_function(cells, call)
    }
}
