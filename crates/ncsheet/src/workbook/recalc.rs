//! Recalculation: from the changed cells, collect what depends on them (cells and range
//! nodes), order it topologically (Kahn), evaluate each formula once. Cells left over have
//! a cycle upstream: strongly connected components name the cycle's cells, which keep
//! their previous values (as Excel does), and everything downstream computes from those.
//!
//! Dynamic arrays spill into the cells below/right of their formula. Cells whose value
//! changed by a spill are recalculated in a following pass.

use crate::eval::{too_many_items, Array, Ctx, Locale, Value, XlError};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};

use super::graph::{FxHasher, FxMap};

type FxSet<T> = std::collections::HashSet<T, std::hash::BuildHasherDefault<FxHasher>>;
use super::{Workbook, NO_FORMULA};

/// Node ids with this bit set are range nodes, others are cells.
const RANGE_BIT: u32 = 1 << 31;
const NO_SLOT: u32 = u32::MAX;
/// Spills feeding spills feeding spills… deeper than this is reported as `#SPILL!`-free but
/// possibly stale; real sheets need one or two passes.
const MAX_PASSES: usize = 32;

/// Where dynamic arrays spilled, and which are blocked.
#[derive(Default)]
pub struct SpillState {
    /// Anchor cell → the rectangle it fills (anchor included).
    areas: FxMap<u32, Rect>,
    /// Spilled cell → its anchor.
    owners: FxMap<u32, u32>,
    /// Anchor showing `#SPILL!` → the rectangle it wants.
    blocked: FxMap<u32, Rect>,
    /// Anchors and freed cells to recompute at the next recalculation.
    pending: Vec<u32>,
    /// Anchor → the part of its spill that is one value and stored only in the cells that
    /// exist there (a whole row or column spilled: `=1:1*2`).
    tails: FxMap<u32, SpillTail>,
}

/// A spill's cells beyond its stored items: `rect` less `stored`, each holding `fill`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpillTail {
    pub sheet: u16,
    pub rect: Rect,
    pub stored: Rect,
    pub fill: Value,
}

impl SpillTail {
    fn holds(&self, sheet: u16, pos: Pos) -> bool {
        self.sheet == sheet && self.rect.contains(pos) && !self.stored.contains(pos)
    }
}

/// Whether two rectangles share a cell.
pub(super) fn meets(a: Rect, b: Rect) -> bool {
    a.first.row <= b.last.row && b.first.row <= a.last.row && a.first.col <= b.last.col && b.first.col <= a.last.col
}

impl SpillState {
    /// No anchor spills or is blocked: a result needs no spill bookkeeping.
    fn is_empty(&self) -> bool {
        self.areas.is_empty() && self.blocked.is_empty()
    }

    /// The anchors showing `#SPILL!`.
    pub(super) fn blocked_anchors(&self) -> impl Iterator<Item = u32> + '_ {
        self.blocked.keys().copied()
    }

    pub fn owner(&self, id: u32) -> Option<u32> {
        self.owners.get(&id).copied()
    }

    pub fn rect(&self, anchor: u32) -> Option<Rect> {
        self.areas.get(&anchor).copied()
    }

    /// The rectangle the anchor spills over, or wants where its spill was refused.
    pub fn wanted(&self, anchor: u32) -> Option<Rect> {
        self.rect(anchor).or_else(|| self.blocked.get(&anchor).copied())
    }

    /// The value of a position no cell is stored at: a spill tail's fill, or blank.
    #[inline]
    pub fn tail_value(&self, sheet: u16, pos: Pos) -> Value {
        if self.tails.is_empty() {
            return Value::Blank;
        }
        self.tail_at(sheet, pos).map_or(Value::Blank, |(_, t)| t.fill.clone())
    }

    /// Notes a cell made inside a spill as the anchor's.
    pub(super) fn own(&mut self, cell: u32, anchor: u32) {
        self.owners.insert(cell, anchor);
    }

    /// The anchor and tail holding `pos`, if any.
    pub fn tail_at(&self, sheet: u16, pos: Pos) -> Option<(u32, &SpillTail)> {
        self.tails.iter().find(|(_, t)| t.holds(sheet, pos)).map(|(&a, t)| (a, t))
    }

    /// The tails on `sheet` meeting `rect`.
    pub fn tails_meeting(&self, sheet: u16, rect: Rect) -> impl Iterator<Item = &SpillTail> + '_ {
        self.tails.values().filter(move |t| t.sheet == sheet && meets(t.rect, rect))
    }

    /// Anchors that spilled and anchors blocked.
    pub fn anchors(&self) -> impl Iterator<Item = u32> + '_ {
        self.areas.keys().chain(self.blocked.keys()).copied()
    }
}

/// The circular references the recalculations found, each a list of cells, with the cycle
/// each cell is in: an edit forgets the cycles through the cells it recomputes in work
/// proportional to those cells, not to all cycles (80,000 self-references written one by
/// one, as a macro fills a column, were quadratic).
#[derive(Default)]
pub struct Cycles {
    /// By the cycle's first cell.
    lists: FxMap<u32, Vec<u32>>,
    /// Cell → the first cell of its cycle.
    member: FxMap<u32, u32>,
    /// The first cells of the cycles recorded, and the cycles forgotten, since the
    /// recalculation began: what an edit reports as new without copying every cycle.
    recorded: Vec<u32>,
    forgotten: Vec<Vec<u32>>,
    /// Cell evaluations the iterating cycles have spent in this recalculation, with the work
    /// inside them (`cycles::round_cost`), against `cycles::MAX_ITERATION_EVALUATIONS` for
    /// all of them together.
    pub(super) iteration_spent: u64,
}

impl Cycles {
    pub fn clear(&mut self) {
        self.lists.clear();
        self.member.clear();
        self.begin();
    }

    /// Starts a recalculation: what it records is new from here.
    fn begin(&mut self) {
        self.recorded.clear();
        self.forgotten.clear();
        self.iteration_spent = 0;
    }

    /// The cycles the recalculation recorded that were not there before it.
    pub fn new_since_begin(&self) -> Vec<&Vec<u32>> {
        let mut firsts = self.recorded.clone();
        firsts.sort_unstable();
        firsts.dedup();
        firsts.iter().filter_map(|f| self.lists.get(f)).filter(|c| !self.forgotten.contains(c)).collect()
    }

    pub fn is_empty(&self) -> bool {
        self.lists.is_empty()
    }

    /// Records a cycle; its cells are in no recorded cycle (the pass that finds it forgot
    /// those through its affected cells).
    fn push(&mut self, cells: Vec<u32>) {
        let Some(&first) = cells.first() else { return };
        for &c in &cells {
            self.member.insert(c, first);
        }
        self.lists.insert(first, cells);
        self.recorded.push(first);
    }

    /// Forgets the cycle through `node`, if any (range nodes are in none).
    fn forget(&mut self, node: u32) {
        if node & RANGE_BIT != 0 {
            return;
        }
        if let Some(first) = self.member.remove(&node) {
            let cells = self.lists.remove(&first).unwrap_or_default();
            for c in &cells {
                self.member.remove(c);
            }
            self.forgotten.push(cells);
        }
    }

    /// The cycles in no particular order.
    pub fn iter(&self) -> impl Iterator<Item = &Vec<u32>> {
        self.lists.values()
    }
}

/// The formula cells recomputed at every edit (they call a volatile function), in the order
/// they were stored. Removing one leaves a gap, closed up when half are gaps, so rewriting a
/// column of 200,000 INDIRECT formulas costs each removal O(1), not a scan of the list.
#[derive(Default)]
pub struct VolatileCells {
    cells: Vec<u32>,
    /// Cell → its index in `cells`.
    at: FxMap<u32, u32>,
    gaps: usize,
}

const GAP: u32 = u32::MAX;

impl VolatileCells {
    pub fn insert(&mut self, id: u32) {
        if let std::collections::hash_map::Entry::Vacant(e) = self.at.entry(id) {
            e.insert(self.cells.len() as u32);
            self.cells.push(id);
        }
    }

    pub fn remove(&mut self, id: u32) {
        let Some(i) = self.at.remove(&id) else { return };
        self.cells[i as usize] = GAP;
        self.gaps += 1;
        if self.gaps * 2 > self.cells.len() {
            self.cells.retain(|&c| c != GAP);
            self.gaps = 0;
            for (i, &c) in self.cells.iter().enumerate() {
                self.at.insert(c, i as u32);
            }
        }
    }

    fn append_to(&self, out: &mut Vec<u32>) {
        out.extend(self.cells.iter().copied().filter(|&c| c != GAP));
    }
}

/// Reusable per-node slots, so a recalculation allocates nothing proportional to the book.
#[derive(Default)]
pub struct Scratch {
    cell_slot: Vec<u32>,
    range_slot: Vec<u32>,
    /// Depth-first search state per node (`UNSEEN`, `OPEN`, `DONE`).
    cell_mark: Vec<u8>,
    range_mark: Vec<u8>,
    /// The search's stack of nodes and the order in which they finished.
    stack: Vec<u32>,
    order: Vec<u32>,
    /// The values cells held before this recalculation evaluated them and found new
    /// references made at run time (OFFSET, INDEX, INDIRECT): one of them that turns out
    /// circular keeps that value, as a cell whose formula names its cycle does. With
    /// iterative calculation on, every evaluated cell's: a cycle those references reveal
    /// only in a later pass iterates from the values it had before, not from the first
    /// pass's, which read cells not yet computed (`Workbook::iteration_start`).
    pub(super) before_relink: FxMap<u32, Value>,
    /// The locale in force for this recalculation, found once at its start: with a fixed
    /// clock it holds the clock's year, a date conversion too many to make for every cell.
    locale: Locale,
    /// Formulas evaluated since the workbook was made ([`Workbook::formulas_evaluated`]).
    evaluations: u64,
    /// The work inside those evaluations, summed as the formulas tell it
    /// ([`crate::eval::Env::work_done`]; an iterating cycle is charged it, `cycles.rs`).
    pub(super) work: std::cell::Cell<crate::eval::WorkDone>,
}

impl Scratch {
    /// Adds `done` to the work the workbook's formulas did ([`Scratch::work`]).
    pub(super) fn add_work(&self, done: crate::eval::WorkDone) {
        let sum = self.work.get();
        self.work.set(crate::eval::WorkDone {
            items: sum.items.saturating_add(done.items),
            calls: sum.calls.saturating_add(done.calls),
        });
    }
}

/// Entries of the search's buffers kept between recalculations.
const KEEP_SCRATCH: usize = 1 << 16;
const UNSEEN: u8 = 0;
const OPEN: u8 = 1;
const DONE: u8 = 2;

/// The affected part of the graph, in compressed adjacency form over slot numbers.
struct Affected {
    nodes: Vec<u32>,
    adj_start: Vec<u32>,
    adj: Vec<u32>,
}

impl Affected {
    fn successors(&self, slot: usize) -> &[u32] {
        &self.adj[self.adj_start[slot] as usize..self.adj_start[slot + 1] as usize]
    }
}

impl Workbook {
    /// How many formulas recalculation has evaluated since the workbook was made: the work an
    /// edit costs, counted (tests bound it, so they hold on a loaded machine where a wall-clock
    /// bound would not).
    pub fn formulas_evaluated(&self) -> u64 {
        self.scratch.evaluations
    }

    /// Recomputes every formula (after loading a file or redefining names).
    pub fn recalculate(&mut self) {
        if std::mem::take(&mut self.names_unlinked) {
            self.rebuild_graph();
        }
        self.reclaim_unlinked_blanks();
        self.cycles.clear();
        self.iteration_cuts.clear();
        let sources: Vec<u32> =
            (0..self.cells.len() as u32).filter(|&id| self.cells[id as usize].formula != NO_FORMULA).collect();
        self.run_passes(sources);
    }

    /// Recomputes what depends on `changed` (cells whose input was just set), and the volatile
    /// cells, which Excel recalculates at every edit.
    pub(super) fn recalculate_from(&mut self, mut changed: Vec<u32>) {
        self.reclaim_unlinked_blanks();
        // A blocked spill may be freed by an edited cell; a volatile cell is still a formula
        // where it was, blocking what it blocked, so only the edited cells are looked up.
        if !self.spill.blocked.is_empty() {
            for &id in &changed.clone() {
                let c = &self.cells[id as usize];
                let (sheet, pos) = (c.sheet, c.pos);
                let blocked: Vec<u32> =
                    self.spill.blocked.iter().filter(|(_, r)| r.contains(pos)).map(|(&a, _)| a).collect();
                changed.extend(blocked.into_iter().filter(|&a| self.cells[a as usize].sheet == sheet));
            }
        }
        self.volatile.append_to(&mut changed);
        self.run_passes(changed);
    }

    fn run_passes(&mut self, mut sources: Vec<u32>) {
        self.fresh_notes.clear();
        self.scratch.before_relink.clear();
        self.scratch.locale = self.settings().locale_in_force(self.date_system());
        if let Some(functions) = &self.user_functions {
            functions.begin_recalculation();
        }
        self.cycles.begin();
        for _ in 0..MAX_PASSES {
            sources.append(&mut self.spill.pending);
            if sources.is_empty() {
                return;
            }
            sources = self.pass(&sources);
        }
    }

    /// One topological pass; returns cells that spills changed and whose dependents still
    /// need recomputing.
    fn pass(&mut self, sources: &[u32]) -> Vec<u32> {
        self.acyclic_pass(sources).unwrap_or_else(|| self.kahn_pass(sources))
    }

    /// The pass without a cycle among the affected nodes, the usual case: a depth-first
    /// search orders them (reverse finishing order) without building the affected graph.
    /// `None`, having computed nothing, when the search meets a cycle.
    fn acyclic_pass(&mut self, sources: &[u32]) -> Option<Vec<u32>> {
        self.scratch.cell_mark.resize(self.cells.len(), UNSEEN);
        self.scratch.range_mark.resize(self.ranges.nodes.len(), UNSEEN);
        let mut stack = std::mem::take(&mut self.scratch.stack);
        let mut order = std::mem::take(&mut self.scratch.order);
        stack.clear();
        order.clear();
        let cycle = self.search(sources, &mut stack, &mut order);
        let mut late = Vec::new();
        if cycle {
            for &node in &stack {
                set_mark(&mut self.scratch.cell_mark, &mut self.scratch.range_mark, node, UNSEEN);
            }
            for &node in &order {
                set_mark(&mut self.scratch.cell_mark, &mut self.scratch.range_mark, node, UNSEEN);
            }
        } else {
            // Cycles through affected cells are gone (they would have been met).
            if !self.cycles.is_empty() {
                order.iter().for_each(|&node| self.cycles.forget(node));
            }
            for &node in order.iter().rev() {
                set_mark(&mut self.scratch.cell_mark, &mut self.scratch.range_mark, node, UNSEEN);
                if node & RANGE_BIT == 0 && self.cells[node as usize].formula != NO_FORMULA {
                    self.evaluate(node, &mut late);
                }
            }
        }
        // Keep the buffers for the next edit (allocating them anew costs page faults) unless
        // they outgrew the workbook.
        let keep = KEEP_SCRATCH.max(self.cells.len() + self.ranges.nodes.len());
        order.clear();
        order.shrink_to(keep);
        stack.clear();
        stack.shrink_to(keep);
        self.scratch.stack = stack;
        self.scratch.order = order;
        (!cycle).then_some(late)
    }

    /// Depth-first search along dependent edges from `sources`, leaving the nodes in
    /// `order` as they finish (dependents before what they read); stops at the first cycle
    /// and says so.
    fn search(&mut self, sources: &[u32], stack: &mut Vec<u32>, order: &mut Vec<u32>) -> bool {
        let (cells, ranges) = (&self.cells, &self.ranges);
        let Scratch { cell_mark, range_mark, .. } = &mut self.scratch;
        let with_ranges = !ranges.nodes.is_empty();
        let mut cycle = false;
        'search: for &source in sources {
            if mark_of(cell_mark, range_mark, source) != UNSEEN {
                continue;
            }
            stack.push(source);
            // A node stays on the stack while its dependents are searched; met again on
            // top (OPEN), it is finished.
            while let Some(&node) = stack.last() {
                match mark_of(cell_mark, range_mark, node) {
                    OPEN => {
                        stack.pop();
                        set_mark(cell_mark, range_mark, node, DONE);
                        order.push(node);
                        continue;
                    }
                    DONE => {
                        stack.pop();
                        continue;
                    }
                    _ => {}
                }
                set_mark(cell_mark, range_mark, node, OPEN);
                let (cm, rm): (&[u8], &[u8]) = (cell_mark, range_mark);
                let mut push = |next: u32| match mark_of(cm, rm, next) {
                    UNSEEN => stack.push(next),
                    DONE => {}
                    // `next` is on the search path: a cycle.
                    _ => cycle = true,
                };
                if node & RANGE_BIT != 0 {
                    for &next in ranges.nodes[(node & !RANGE_BIT) as usize].dependents.as_slice() {
                        push(next);
                    }
                } else {
                    let cell = &cells[node as usize];
                    for &next in cell.dependents.as_slice() {
                        push(next);
                    }
                    if with_ranges {
                        ranges.containing(cell.sheet, cell.pos, |r| push(r | RANGE_BIT));
                    }
                }
                if cycle {
                    break 'search;
                }
            }
        }
        cycle
    }

    /// The pass by Kahn's algorithm over the affected graph, which also finds cycles.
    fn kahn_pass(&mut self, sources: &[u32]) -> Vec<u32> {
        let affected = self.collect_affected(sources);
        let n = affected.nodes.len();
        let mut indegree = vec![0u32; n];
        for &t in &affected.adj {
            indegree[t as usize] += 1;
        }
        // Cycles through affected cells are found again below if they still exist.
        if !self.cycles.is_empty() {
            affected.nodes.iter().for_each(|&node| self.cycles.forget(node));
        }
        let mut late = Vec::new();
        let mut done = vec![false; n];
        let mut queue: Vec<u32> = (0..n as u32).filter(|&s| indegree[s as usize] == 0).collect();
        self.drain(&affected, &mut indegree, &mut done, &mut queue, &mut late);
        if done.iter().any(|d| !d) {
            self.break_cycles(&affected, &mut indegree, &mut done, &mut late);
        }
        self.release_slots(&affected.nodes);
        late
    }

    /// Kahn's algorithm: evaluate each node whose inputs are all computed.
    fn drain(
        &mut self,
        a: &Affected,
        indegree: &mut [u32],
        done: &mut [bool],
        queue: &mut Vec<u32>,
        late: &mut Vec<u32>,
    ) {
        let mut head = 0;
        while head < queue.len() {
            let slot = queue[head] as usize;
            head += 1;
            if done[slot] {
                continue;
            }
            done[slot] = true;
            let node = a.nodes[slot];
            if node & RANGE_BIT == 0 && self.cells[node as usize].formula != NO_FORMULA {
                self.evaluate(node, late);
            }
            for &t in a.successors(slot) {
                indegree[t as usize] -= 1;
                if indegree[t as usize] == 0 {
                    queue.push(t);
                }
            }
        }
    }

    /// Settles every cycle among the leftover nodes (`cycles.rs`), in dependency order so
    /// that a cycle reads what feeds it computed: the cells that truly read each other keep
    /// their previous values, as Excel does, and are recorded (a problem names each cycle).
    /// Then finishes the nodes downstream.
    fn break_cycles(&mut self, a: &Affected, indegree: &mut [u32], done: &mut [bool], late: &mut Vec<u32>) {
        let components = strongly_connected(a, done);
        let mut queue = Vec::new();
        // Tarjan finishes a component after those that read it: reversed, feeders come first.
        for comp in components.into_iter().rev() {
            let self_loop = comp.len() == 1 && a.successors(comp[0] as usize).contains(&comp[0]);
            if comp.len() == 1 && !self_loop {
                let node = a.nodes[comp[0] as usize];
                if node & RANGE_BIT == 0 && self.cells[node as usize].formula != NO_FORMULA {
                    self.evaluate(node, late);
                }
                done[comp[0] as usize] = true;
                continue;
            }
            let mut cells: Vec<u32> = comp
                .iter()
                .map(|&s| a.nodes[s as usize])
                .filter(|&n| n & RANGE_BIT == 0 && self.cells[n as usize].formula != NO_FORMULA)
                .collect();
            cells.sort_by_key(|&id| (self.cells[id as usize].sheet, self.cells[id as usize].pos));
            let circular = self.settle_component(&cells, late);
            for &id in &circular {
                self.keep_previous_value(id, late);
            }
            // No recorded cycle holds these cells: `kahn_pass` dropped those through
            // affected cells, and components are disjoint (searching the list per cycle
            // made 80,000 self-references quadratic). Only the cells that truly read each
            // other are circular (`settle_component`).
            if !circular.is_empty() {
                self.cycles.push(circular);
            }
            for &s in &comp {
                done[s as usize] = true;
            }
            for &s in &comp {
                for &t in a.successors(s as usize) {
                    indegree[t as usize] -= 1;
                    if indegree[t as usize] == 0 {
                        queue.push(t);
                    }
                }
            }
        }
        self.drain(a, indegree, done, &mut queue, late);
    }

    /// Everything reachable from `sources` along dependent edges, with those edges.
    fn collect_affected(&mut self, sources: &[u32]) -> Affected {
        self.scratch.cell_slot.resize(self.cells.len(), NO_SLOT);
        self.scratch.range_slot.resize(self.ranges.nodes.len(), NO_SLOT);
        let mut nodes = Vec::with_capacity(sources.len());
        for &s in sources {
            self.claim_slot(s, &mut nodes);
        }
        let mut adj_start = Vec::with_capacity(nodes.len() + 1);
        let mut adj = Vec::with_capacity(nodes.len());
        let mut successors = Vec::new();
        let mut i = 0;
        while i < nodes.len() {
            adj_start.push(adj.len() as u32);
            successors.clear();
            self.successors(nodes[i], &mut successors);
            for &t in &successors {
                adj.push(self.claim_slot(t, &mut nodes));
            }
            i += 1;
        }
        adj_start.push(adj.len() as u32);
        Affected { nodes, adj_start, adj }
    }

    /// The slot of a node, assigning the next one on first sight.
    fn claim_slot(&mut self, node: u32, nodes: &mut Vec<u32>) -> u32 {
        let slot = if node & RANGE_BIT == 0 {
            &mut self.scratch.cell_slot[node as usize]
        } else {
            &mut self.scratch.range_slot[(node & !RANGE_BIT) as usize]
        };
        if *slot == NO_SLOT {
            *slot = nodes.len() as u32;
            nodes.push(node);
        }
        *slot
    }

    fn release_slots(&mut self, nodes: &[u32]) {
        for &node in nodes {
            if node & RANGE_BIT == 0 {
                self.scratch.cell_slot[node as usize] = NO_SLOT;
            } else {
                self.scratch.range_slot[(node & !RANGE_BIT) as usize] = NO_SLOT;
            }
        }
    }

    /// Nodes that read this one: a cell's dependents and the ranges containing it, or a
    /// range's dependents.
    fn successors(&self, node: u32, out: &mut Vec<u32>) {
        if node & RANGE_BIT != 0 {
            out.extend_from_slice(self.ranges.nodes[(node & !RANGE_BIT) as usize].dependents.as_slice());
            return;
        }
        let cell = &self.cells[node as usize];
        out.extend_from_slice(cell.dependents.as_slice());
        self.ranges.containing(cell.sheet, cell.pos, |r| out.push(r | RANGE_BIT));
    }

    pub(super) fn evaluate(&mut self, id: u32, late: &mut Vec<u32>) {
        self.scratch.evaluations += 1;
        let cell = &self.cells[id as usize];
        let formula = self.formulas.get(cell.formula);
        let mut ctx = Ctx::for_cell_of(self, (self.date_system(), self.scratch.locale), cell.sheet, cell.pos);
        ctx.numbers = &formula.numbers;
        let value = ctx.eval_formula(&formula.expr);
        let (notes, dynamic_refs) = ctx.into_findings();
        // The usual cell: no notes now or before, no references made at run time anywhere,
        // and two lists that never allocated (so nothing to free): only its value to store.
        if notes.capacity() == 0
            && dynamic_refs.capacity() == 0
            && self.notes.is_empty()
            && self.dynamic_refs.is_empty()
            && self.iteration.is_none()
        {
            std::mem::forget(notes);
            std::mem::forget(dynamic_refs);
            self.set_result(id, value, late);
            return;
        }
        self.record_findings(id, value, notes, dynamic_refs, late);
    }

    /// The rest of [`Workbook::evaluate`] for a cell with notes or references made at run
    /// time (or in a workbook that has some): kept out of line, so that the usual cell's path
    /// saves no registers for it.
    #[inline(never)]
    fn record_findings(
        &mut self,
        id: u32,
        value: Value,
        notes: Vec<crate::eval::Note>,
        dynamic_refs: Vec<(crate::formula::ast::SheetId, Rect)>,
        late: &mut Vec<u32>,
    ) {
        if notes.is_empty() {
            if !self.notes.is_empty() {
                self.notes.remove(&id);
            }
        } else if self.notes.get(&id) != Some(&notes) {
            self.notes.insert(id, notes);
            self.fresh_notes.push(id);
        }
        // Only a cell making references at run time may find itself in a cycle after the fact;
        // an iterating cycle found so starts from every one of its cells' earlier values.
        let iterating = self.iteration.is_some();
        let before = (!dynamic_refs.is_empty() || iterating).then(|| self.cells[id as usize].value.clone());
        if iterating {
            if let Some(before) = &before {
                self.scratch.before_relink.entry(id).or_insert_with(|| before.clone());
            }
        }
        self.set_result(id, value, late);
        if (!dynamic_refs.is_empty() || !self.dynamic_refs.is_empty()) && self.relink_dynamic(id, dynamic_refs) {
            if let Some(before) = before {
                self.scratch.before_relink.entry(id).or_insert(before);
            }
            // Now in the graph, the cells it reached are ordered before it in the next pass.
            late.push(id);
        }
    }

    /// Stores a formula's result: blank reads as 0, an array spills or reports `#SPILL!`.
    /// A cell of a circular reference without iterative calculation keeps the value it held
    /// before this recalculation, 0 when it never had one: Excel's behaviour ("Excel can't
    /// automatically calculate" a circular reference and shows "the last calculated value"
    /// or zero, support.microsoft.com, "Remove or allow a circular reference"). Its
    /// dependents compute from that value; the cycle is a problem of the workbook.
    /// A cell whose cycle only its evaluation revealed (`=OFFSET(C2,-1,0)+1` in C1) keeps the
    /// value from before that evaluation too, not what it computed reading itself.
    fn keep_previous_value(&mut self, id: u32, late: &mut Vec<u32>) {
        let before = self.scratch.before_relink.remove(&id);
        let value = match before.as_ref().unwrap_or(&self.cells[id as usize].value) {
            Value::Blank | Value::Error(XlError::Circ) => Value::Number(0.0),
            other => other.clone(),
        };
        self.set_result(id, value, late);
    }

    pub(super) fn set_result(&mut self, id: u32, value: Value, late: &mut Vec<u32>) {
        // The usual result, a number in a workbook without spills or array formulas, stored
        // here; the rest is kept out of line, so that this path saves no registers for it.
        match value {
            Value::Number(n) if self.fixed_arrays.is_empty() && self.spill.is_empty() => self.store_number(id, n),
            value => self.set_any_result(id, value, late),
        }
    }

    fn store_number(&mut self, id: u32, n: f64) {
        let c = &mut self.cells[id as usize];
        if let Some(log) = &mut self.changes {
            // `c.value != Value::Number(n)` without building a `Value` for the derived
            // comparison, which is out of line: this runs for every cell an edit recomputes.
            if !matches!(c.value, Value::Number(old) if old == n) {
                log.values.insert(id);
            }
        }
        c.value = Value::Number(n);
        self.sheets[c.sheet as usize].grow_extent(c.pos);
    }

    #[inline(never)]
    fn set_any_result(&mut self, id: u32, value: Value, late: &mut Vec<u32>) {
        let fixed = if self.fixed_arrays.is_empty() { None } else { self.fixed_arrays.get(&id).copied() };
        let value = match fixed {
            Some((rows, cols)) => fit_to_area(value, rows as usize, cols as usize),
            None => value,
        };
        if let Value::Number(n) = value {
            if self.spill.is_empty() {
                return self.store_number(id, n);
            }
        }
        let value = match value {
            Value::Array(a) if a.rows == 1 && a.cols == 1 => a.data[0].clone(),
            // An array of no items (VBA's `Array()`) spills nowhere: Excel's #CALC!, its
            // error for an empty array ("How to correct a #CALC! error").
            Value::Array(a) if a.whole_size().0 == 0 || a.whole_size().1 == 0 => Value::Error(XlError::Calc),
            Value::Array(a) => return self.spill_array(id, &a, late),
            v => v,
        };
        let spilled = |m: &FxMap<u32, Rect>| !m.is_empty() && m.contains_key(&id);
        if spilled(&self.spill.areas) || spilled(&self.spill.blocked) {
            self.spill.blocked.remove(&id);
            self.release_spill(id, late);
        }
        self.store_value(id, value.blank_as_zero());
    }

    fn spill_array(&mut self, id: u32, a: &crate::eval::Array, late: &mut Vec<u32>) {
        let (sheet, anchor) = (self.cells[id as usize].sheet, self.cells[id as usize].pos);
        let (rows, cols) = a.whole_size();
        let last = Pos::new(anchor.row.saturating_add(rows as u32 - 1), anchor.col.saturating_add(cols as u32 - 1));
        let fits = last.row < MAX_ROWS && last.col < MAX_COLS;
        let rect = Rect::new(anchor, Pos::new(last.row.min(MAX_ROWS - 1), last.col.min(MAX_COLS - 1)));
        if !fits || self.spill_blocked(id, sheet, rect) {
            self.release_spill(id, late);
            self.spill.blocked.insert(id, rect);
            self.store_value(id, Value::Error(XlError::Spill));
            return;
        }
        if self.reads_own_spill(id, sheet, rect) {
            return self.refuse_own_spill(id, rect, late);
        }
        if let Some(made) = self.spill_past_cell_limit(sheet, anchor, a) {
            return self.refuse_large_spill(id, rect, made, late);
        }
        self.spill.blocked.remove(&id);
        if let Some(old) = self.spill.areas.get(&id).copied() {
            self.clear_cells_outside(id, old, rect, late);
        }
        for r in 0..a.rows {
            for c in 0..a.cols {
                let pos = Pos::new(anchor.row + r as u32, anchor.col + c as u32);
                let v = a.get(r, c).clone().blank_as_zero();
                if pos == anchor {
                    self.store_value(id, v);
                    continue;
                }
                let target = self.cell_at(sheet, pos);
                self.spill.owners.insert(target, id);
                if self.cells[target as usize].value != v {
                    self.store_value(target, v);
                    late.push(target);
                }
            }
        }
        self.spill.areas.insert(id, rect);
        let tail = a.tail.as_ref().map(|t| SpillTail {
            sheet,
            rect,
            stored: Rect::new(anchor, Pos::new(anchor.row + a.rows as u32 - 1, anchor.col + a.cols as u32 - 1)),
            fill: t.fill.clone().blank_as_zero(),
        });
        self.set_tail(id, tail, late);
    }

    /// Records an anchor's spill tail (or its absence): the cells that exist there take its
    /// value, and the ranges meeting the old or new tail are read again, since the cells
    /// that do not exist changed with them.
    fn set_tail(&mut self, anchor: u32, tail: Option<SpillTail>, late: &mut Vec<u32>) {
        let old = if self.spill.tails.is_empty() { None } else { self.spill.tails.remove(&anchor) };
        if old == tail {
            if let Some(t) = old {
                self.spill.tails.insert(anchor, t);
            }
            return;
        }
        for t in old.iter().chain(tail.iter()) {
            self.ranges.meeting(t.sheet, t.rect, |r| late.push(r | RANGE_BIT));
        }
        let Some(t) = tail else { return };
        let mut existing = Vec::new();
        self.sheets[t.sheet as usize].for_each_in(t.rect, &mut |p, cid| {
            if !t.stored.contains(p) {
                existing.push(cid);
            }
        });
        for cid in existing {
            self.spill.owners.insert(cid, anchor);
            if self.cells[cid as usize].value != t.fill {
                self.store_value(cid, t.fill.clone());
                late.push(cid);
            }
        }
        self.spill.tails.insert(anchor, t);
    }

    /// Whether the anchor reads, directly or through other formulas, a cell of `rect` other
    /// than itself: spilling there would change what it reads, a circular reference (Excel
    /// says so; iterating would print whatever the last of many passes left). Decided on the
    /// graph before anything spills, so the answer is the same at every recalculation.
    fn reads_own_spill(&self, anchor: u32, sheet: u16, rect: Rect) -> bool {
        let mut stack: Vec<u32> = Vec::new();
        self.sheets[sheet as usize].for_each_in(rect, &mut |_, cid| {
            if cid != anchor {
                stack.extend_from_slice(self.cells[cid as usize].dependents.as_slice());
            }
        });
        let anchor_pos = self.cells[anchor as usize].pos;
        self.ranges.meeting(sheet, rect, |r| {
            // A range meeting the spill only at the anchor reads no spilled cell.
            if self.ranges.nodes[r as usize].rect != Rect::cell(anchor_pos) {
                stack.extend_from_slice(self.ranges.nodes[r as usize].dependents.as_slice());
            }
        });
        let mut seen: FxSet<u32> = FxSet::default();
        while let Some(node) = stack.pop() {
            if node == anchor {
                return true;
            }
            if !seen.insert(node) {
                continue;
            }
            if node & RANGE_BIT != 0 {
                stack.extend_from_slice(self.ranges.nodes[(node & !RANGE_BIT) as usize].dependents.as_slice());
            } else {
                let cell = &self.cells[node as usize];
                stack.extend_from_slice(cell.dependents.as_slice());
                self.ranges.containing(cell.sheet, cell.pos, |r| stack.push(r | RANGE_BIT));
            }
        }
        false
    }

    /// The anchor reads its own spill range: `#CIRC!`, nothing spilled, the reason noted.
    fn refuse_own_spill(&mut self, id: u32, rect: Rect, late: &mut Vec<u32>) {
        self.release_spill(id, late);
        // Kept as a blocked spill is, so that a cell typed into the range computes the anchor
        // again: the range may now be blocked (`#SPILL!`), as a fresh recalculation finds.
        self.spill.blocked.insert(id, rect);
        let message = format!("the formula reads its own spill range {rect} (a circular reference)");
        self.notes.entry(id).or_default().push(crate::eval::Note { error: XlError::Circ, message });
        self.cycles.push(vec![id]);
        self.store_value(id, Value::Error(XlError::Circ));
    }

    /// The cells spilling `a` at `anchor` would make, when they would take the workbook past
    /// [`super::MAX_CELLS`] (`SEQUENCE(1048576,16)` in a few cells: each spill is within the
    /// array limit, all of them together are not). The tail of one value makes no cells.
    fn spill_past_cell_limit(&self, sheet: crate::formula::ast::SheetId, anchor: Pos, a: &Array) -> Option<usize> {
        let stored = a.rows * a.cols;
        if self.cell_count() + stored <= super::MAX_CELLS {
            return None;
        }
        let last = Pos::new(anchor.row + a.rows as u32 - 1, anchor.col + a.cols as u32 - 1);
        let mut existing = 0;
        self.sheets[sheet as usize].for_each_in(Rect::new(anchor, last), &mut |_, _| existing += 1);
        let made = stored - existing;
        (self.cell_count() + made > super::MAX_CELLS).then_some(made)
    }

    /// Excel's `#SPILL!` for a spill it has no memory for ("Out of memory", How to correct a
    /// #SPILL! error): kept as a blocked spill, so that a later recalculation tries again.
    fn refuse_large_spill(&mut self, id: u32, rect: Rect, made: usize, late: &mut Vec<u32>) {
        self.release_spill(id, late);
        self.spill.blocked.insert(id, rect);
        let message = format!("spilling into {rect} would make {made} more cells: {}", super::too_many_cells());
        self.notes.entry(id).or_default().push(crate::eval::Note { error: XlError::Spill, message });
        self.store_value(id, Value::Error(XlError::Spill));
    }

    /// Whether any cell of `rect` other than the anchor holds something of its own.
    fn spill_blocked(&self, anchor: u32, sheet: u16, rect: Rect) -> bool {
        let mut blocked = false;
        self.sheets[sheet as usize].for_each_in(rect, &mut |_, cid| {
            if cid == anchor || blocked {
                return;
            }
            let c = &self.cells[cid as usize];
            let owned_elsewhere = self.spill.owners.get(&cid).is_some_and(|&o| o != anchor);
            let own_content = !self.spill.owners.contains_key(&cid) && !c.value.is_blank();
            blocked = c.formula != NO_FORMULA || owned_elsewhere || own_content || self.bad_inputs.contains_key(&cid);
        });
        // Another spill's tail holds cells that do not exist.
        blocked || self.spill.tails.iter().any(|(&a, t)| a != anchor && t.sheet == sheet && meets(t.rect, rect))
    }

    fn clear_cells_outside(&mut self, anchor: u32, old: Rect, new: Rect, late: &mut Vec<u32>) {
        let sheet = self.cells[anchor as usize].sheet;
        let mut freed = Vec::new();
        let owners = &self.spill.owners;
        self.sheets[sheet as usize].for_each_in(old, &mut |p, cid| {
            // A cell typed into the spill is no longer the anchor's: it keeps its value.
            if cid != anchor && !new.contains(p) && owners.get(&cid) == Some(&anchor) {
                freed.push(cid);
            }
        });
        for cid in freed {
            self.spill.owners.remove(&cid);
            if let Some(log) = &mut self.changes {
                log.values.insert(cid);
            }
            self.cells[cid as usize].value = Value::Blank;
            late.push(cid);
        }
    }

    /// Empties the cells an anchor spilled into.
    fn release_spill(&mut self, anchor: u32, late: &mut Vec<u32>) {
        if !self.spill.tails.is_empty() {
            self.set_tail(anchor, None, late);
        }
        if let Some(old) = self.spill.areas.remove(&anchor) {
            let empty = Rect::cell(self.cells[anchor as usize].pos);
            self.clear_cells_outside(anchor, old, empty, late);
        }
    }

    /// Called when a formula leaves a cell: its spill goes, and the freed cells recompute.
    pub(super) fn clear_spill(&mut self, anchor: u32) {
        let mut freed = Vec::new();
        self.release_spill(anchor, &mut freed);
        self.spill.blocked.remove(&anchor);
        self.spill.pending.extend(freed);
    }

    /// A user typed into a spilled cell: the anchor must recompute (and will show `#SPILL!`).
    pub(super) fn take_spilled_cell(&mut self, id: u32) {
        if self.spill.owners.is_empty() {
            return;
        }
        if let Some(anchor) = self.spill.owners.remove(&id) {
            if self.fixed_arrays.contains_key(&anchor) {
                self.break_fixed_array(anchor);
            }
            self.spill.pending.push(anchor);
        }
    }

    /// An edit inside a legacy array formula's area (which Excel refuses: "You can't change
    /// part of an array"; a save names it as a loss): the formula is left filling its own
    /// cell, and the other cells of the area keep their values as constants, rather than
    /// the array filling the area again over the edit.
    fn break_fixed_array(&mut self, anchor: u32) {
        self.fixed_arrays.insert(anchor, (1, 1));
        self.spill.tails.remove(&anchor);
        if self.spill.areas.remove(&anchor).is_some() {
            self.spill.owners.retain(|_, owner| *owner != anchor);
        }
    }
}

#[inline]
/// A legacy array formula's result as its fixed area shows it: a scalar, a single row or
/// a single column repeats; items beyond the result are `#N/A`; the rest is cut off.
fn fit_to_area(value: Value, rows: usize, cols: usize) -> Value {
    if too_many_items(rows, cols) {
        return fit_to_large_area(value, rows, cols);
    }
    if rows == 1 && cols == 1 {
        return match value {
            Value::Array(a) => a.data.first().cloned().unwrap_or(Value::Blank),
            v => v,
        };
    }
    let item = |r: usize, c: usize| match &value {
        Value::Array(a) => {
            let (whole_rows, whole_cols) = a.whole_size();
            let r = if whole_rows == 1 { 0 } else { r };
            let c = if whole_cols == 1 { 0 } else { c };
            a.whole_get(r, c).cloned().unwrap_or(Value::Error(XlError::NA))
        }
        v => v.clone(),
    };
    let data = (0..rows).flat_map(|r| (0..cols).map(move |c| (r, c))).map(|(r, c)| item(r, c)).collect();
    Value::Array(std::rc::Rc::new(crate::eval::Array::new(rows, cols, data)))
}

/// [`fit_to_area`] for an area past the array limit (a file's array formula over a whole
/// sheet): the items the result has, and beyond them one value kept once (the spill's tail,
/// held only by the cells that exist). A scalar fills the area; a result broadcast along a
/// dimension would need every item stored, and is `#NUM!` as an array past the limit is.
fn fit_to_large_area(value: Value, rows: usize, cols: usize) -> Value {
    let tailed = |a: Array, fill: Value| Value::Array(std::rc::Rc::new(a.with_tail(rows, cols, fill)));
    let a = match value {
        Value::Array(a) => a,
        v => return tailed(Array::new(1, 1, vec![v.clone()]), v),
    };
    let (whole_rows, whole_cols) = a.whole_size();
    if whole_rows == 1 && whole_cols == 1 {
        let v = a.whole_get(0, 0).cloned().unwrap_or(Value::Blank);
        return tailed(Array::new(1, 1, vec![v.clone()]), v);
    }
    let (r, c) = (whole_rows.min(rows), whole_cols.min(cols));
    if whole_rows == 1 || whole_cols == 1 || too_many_items(r, c) {
        return Value::Error(XlError::Num);
    }
    let data = (0..r)
        .flat_map(|i| (0..c).map(move |j| (i, j)))
        .map(|(i, j)| a.whole_get(i, j).cloned().unwrap_or(Value::Blank));
    tailed(Array::new(r, c, data.collect()), Value::Error(XlError::NA))
}

fn mark_of(cell_mark: &[u8], range_mark: &[u8], node: u32) -> u8 {
    if node & RANGE_BIT == 0 {
        cell_mark[node as usize]
    } else {
        range_mark[(node & !RANGE_BIT) as usize]
    }
}

#[inline]
fn set_mark(cell_mark: &mut [u8], range_mark: &mut [u8], node: u32, mark: u8) {
    if node & RANGE_BIT == 0 {
        cell_mark[node as usize] = mark;
    } else {
        range_mark[(node & !RANGE_BIT) as usize] = mark;
    }
}

/// Tarjan's strongly connected components over the nodes not yet `done`, iteratively
/// (a chain of a million formulas must not overflow the stack).
fn strongly_connected(a: &Affected, done: &[bool]) -> Vec<Vec<u32>> {
    const UNSEEN: u32 = u32::MAX;
    let n = a.nodes.len();
    let mut index = vec![UNSEEN; n];
    let mut low = vec![0u32; n];
    let mut on_stack = vec![false; n];
    let mut stack = Vec::new();
    let mut components = Vec::new();
    let mut next = 0u32;
    let mut call: Vec<(u32, usize)> = Vec::new();
    for root in 0..n as u32 {
        if done[root as usize] || index[root as usize] != UNSEEN {
            continue;
        }
        call.push((root, 0));
        while let Some(&(v, edge)) = call.last() {
            let vi = v as usize;
            if edge == 0 && index[vi] == UNSEEN {
                index[vi] = next;
                low[vi] = next;
                next += 1;
                stack.push(v);
                on_stack[vi] = true;
            }
            if let Some(&w) = a.successors(vi).get(edge) {
                call.last_mut().expect("frame").1 += 1;
                let wi = w as usize;
                if done[wi] {
                    continue;
                }
                if index[wi] == UNSEEN {
                    call.push((w, 0));
                } else if on_stack[wi] {
                    low[vi] = low[vi].min(index[wi]);
                }
                continue;
            }
            call.pop();
            if let Some(&(parent, _)) = call.last() {
                low[parent as usize] = low[parent as usize].min(low[vi]);
            }
            if low[vi] == index[vi] {
                let mut comp = Vec::new();
                while let Some(w) = stack.pop() {
                    on_stack[w as usize] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                components.push(comp);
            }
        }
    }
    components
}
