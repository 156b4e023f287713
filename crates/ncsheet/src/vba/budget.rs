//! The memory budget of a macro run (`run --max-memory`): all its strings and arrays
//! together, not only each one (`--max-string`, `--max-array-items` bound those), so that a
//! loop filling an array with long strings ends with a clear error instead of an abort.
//!
//! Stores charge the memory they bring (a new string's bytes, a new array's items); once the
//! charges pass a sixteenth of the budget (at most 64 MiB), every variable is measured, values
//! shared between variables once, and the run stops if they hold more than the budget. The
//! measurement costs what the variables hold, and comes at most once per sixteenth of the
//! budget stored, so the memory held stays under the budget plus one sixteenth plus one
//! statement's values.
//!
//! An array another variable (or item) already holds brings nothing when stored (`b = a`,
//! `c.Add a`): its items are shared, not copied, and were charged when they were made, so the
//! store costs the same whatever the array's size. The copy comes when one holder changes an
//! item (copy on write), and that is charged where it happens ([`copy_bytes`]).

use std::rc::Rc;

use crate::eval::{Array, Value};
use crate::workbook::FxMap;

use super::ast::Span;
use super::interp::{Interp, Run};
use super::value::{Obj, Slot, VArray, Var};
use super::ErrorKind;

/// What storing `var` may add: its text's bytes, its array's items, and those of its
/// records' fields, each shared text or array once; an array something else holds too
/// brings nothing (its items are shared).
pub(super) fn brought(var: &Var) -> u64 {
    let mut m = Measure::new_only();
    m.brought(var);
    m.bytes
}

/// What storing the value `v` may add: its text, or its array's items with the texts and
/// arrays they hold however deep (an array stored into each item of another is counted),
/// each once; an array something else holds too brings nothing (its items are shared).
pub(super) fn value_bytes(v: &Value) -> u64 {
    let mut m = Measure::new_only();
    m.value(v);
    m.bytes
}

/// What storing the array `a` may add ([`value_bytes`] of its items), taking the `Rc` as the
/// holder has it: a clone made to call [`value_bytes`] would make every array look shared.
pub(super) fn array_brought(a: &Rc<Array>) -> u64 {
    let mut m = Measure::new_only();
    if m.counts_array(a) {
        m.array(a);
    }
    m.bytes
}

/// What converting `given` to a declared type added to what its store charged: a
/// `String * n` pads a short text to its `n` characters (`a(i) = "x"` into an array of
/// `String * 65000` holds 65,000), measured before the conversion as the one character it
/// was: 100,000 such stores held 6.5 GB uncounted and aborted at a 4 GiB cap.
pub(super) fn padding_bytes(given: &Var, stored: &Var) -> u64 {
    let text = |var: &Var| match var {
        Var::Value(Value::Text(t)) => t.len() as u64,
        _ => 0,
    };
    text(stored).saturating_sub(text(given))
}

/// What making a shared array's items one's own copies (`b = a` then `b(1) = 0`): the items
/// themselves; the texts and arrays they hold stay shared. Costs nothing to work out.
pub(super) fn copy_bytes(a: &Array) -> u64 {
    array_bytes(a)
}

fn array_bytes(a: &Array) -> u64 {
    (a.data.len() * std::mem::size_of::<Value>()) as u64
}

/// Measures what variables hold, each shared text or array once.
#[derive(Default)]
struct Measure {
    /// The addresses met, hashed by Fx: SipHash of each text's address was 60 % of the time
    /// of `v = Split(s, ",")` storing a million items.
    seen: FxMap<usize, ()>,
    bytes: u64,
    /// Counting what a store brings: an array held elsewhere too is not new memory.
    new_only: bool,
}

impl Measure {
    fn new_only() -> Measure {
        Measure { new_only: true, ..Measure::default() }
    }

    fn first_time<T: ?Sized>(&mut self, rc: &Rc<T>) -> bool {
        // Shifted: every address is a multiple of 8, and Fx keeps low zero bits zero.
        self.seen.insert(Rc::as_ptr(rc) as *const u8 as usize >> 3, ()).is_none()
    }

    /// Whether an array's items are counted: the first time it is met, and, for what a store
    /// brings, only when nothing else holds it.
    fn counts_array(&mut self, a: &Rc<Array>) -> bool {
        !(self.new_only && Rc::strong_count(a) > 1) && self.first_time(a)
    }

    /// An array's own items, and the texts and arrays they hold (queued on `pending`).
    fn array_items<'v>(&mut self, a: &'v Array, pending: &mut Vec<&'v Value>) {
        super::count(&super::ITEMS_MEASURED, a.data.len() as u64);
        self.bytes = self.bytes.saturating_add(array_bytes(a));
        pending.extend(a.data.iter().filter(|i| matches!(i, Value::Text(_) | Value::Array(_))));
    }

    /// A value's texts and arrays, and those its arrays hold however deep (an explicit
    /// stack: arrays nested a million deep do not take the native stack with them).
    fn value(&mut self, v: &Value) {
        self.values(vec![v]);
    }

    /// The values `pending` holds and those they reach, each text and array once.
    fn values(&mut self, mut pending: Vec<&Value>) {
        while let Some(v) = pending.pop() {
            match v {
                Value::Text(t) if self.first_time(t) => self.bytes = self.bytes.saturating_add(t.len() as u64),
                Value::Array(a) if self.counts_array(a) => self.array_items(a, &mut pending),
                _ => {}
            }
        }
    }

    /// What storing `var` may add, objects aside (they are measured with every variable).
    /// One measure for all its records: `Dim t(1 To 100000) As T` whose T holds an array of
    /// 100,000 items shares that array among the records, and measuring each record on its
    /// own went over it 100,000 times.
    fn brought(&mut self, var: &Var) {
        let mut pending = vec![var];
        while let Some(var) = pending.pop() {
            match var {
                Var::Value(v) => self.value(v),
                Var::Array(a) => {
                    // Counted before anything clones the `Rc`, which would make it look shared.
                    if self.counts_array(&a.data) {
                        self.array(&a.data);
                    }
                    let records = a.records.as_ref().filter(|r| !(self.new_only && Rc::strong_count(r) > 1));
                    pending.extend(records.iter().flat_map(|r| r.iter()));
                }
                Var::Record(_, fields) => pending.extend(fields.iter()),
                Var::Obj(_) => {}
            }
        }
    }

    /// An array variable's items (the array itself already counted once).
    fn array(&mut self, a: &Array) {
        let mut pending = Vec::new();
        self.array_items(a, &mut pending);
        self.values(pending);
    }

    /// A variable's values, and those of the Collections and Dictionaries it reaches however
    /// deep (an explicit stack, as for arrays).
    fn var(&mut self, var: &Var) {
        let mut pending = vec![var.clone()];
        while let Some(var) = pending.pop() {
            match &var {
                Var::Value(v) => self.value(v),
                Var::Array(a) => {
                    if self.first_time(&a.data) {
                        self.array(&a.data);
                    }
                    self.side_tables(a, &mut pending);
                }
                Var::Obj(Obj::Store(h)) if self.first_time(&h.0) => {
                    self.bytes = self.bytes.saturating_add(h.own_bytes());
                    pending.extend(h.items());
                }
                Var::Obj(Obj::Instance(o)) if self.first_time(&o.0) => {
                    self.bytes = self.bytes.saturating_add(super::classes::object_bytes(&o.0));
                    pending.extend(o.field_vars());
                }
                // A MatchCollection, or a Match or SubMatches of one, holds all its matches.
                Var::Obj(Obj::Regex(r)) if r.hits().is_some_and(|h| self.first_time(h)) => {
                    self.bytes = self.bytes.saturating_add(r.hits().map_or(0, |h| super::regexp::hits_bytes(h)));
                }
                Var::Obj(_) => {}
                Var::Record(_, fields) => pending.extend(fields.iter().cloned()),
            }
        }
    }

    /// The tables an array keeps beside its items, each once by its `Rc` whoever shares it,
    /// and what they hold: its records, its objects (`Set kept(i) = New Node`), and the arrays
    /// its items hold with their own bounds and tables. Those tables are checked apart from
    /// the items: `a(i) = a` in a loop gives every nested array a table of its own that its
    /// items, already met, do not lead to (3,000 turns held 845 MB of them uncounted, and
    /// 10,000 aborted at a 4 GiB cap).
    fn side_tables(&mut self, a: &VArray, pending: &mut Vec<Var>) {
        if let Some(records) = a.records.as_ref().filter(|r| self.first_time(r)) {
            self.add(records.capacity() * std::mem::size_of::<Var>());
            pending.extend(records.iter().cloned());
        }
        if let Some(objects) = a.objects.as_ref().filter(|o| self.first_time(o)) {
            self.add(map_bytes(objects));
            pending.extend(objects.values().map(|o| Var::Obj(o.clone())));
        }
        if let Some(arrays) = a.arrays.as_ref().filter(|m| self.first_time(m)) {
            self.add(map_bytes(arrays));
            pending.extend(arrays.values().map(|inner| Var::Array(inner.clone())));
        }
        if let Some(held) = a.held_types.as_ref().filter(|h| self.first_time(h)) {
            self.add(map_bytes(held));
        }
        if let Some(exact) = a.exact.as_ref().filter(|e| self.first_time(e)) {
            self.add(map_bytes(exact));
        }
    }

    fn add(&mut self, bytes: usize) {
        self.bytes = self.bytes.saturating_add(bytes as u64);
    }

    /// Variables' values; a text growing in place (`append.rs`) by its buffer's capacity,
    /// without making its value.
    fn slots<'a>(&mut self, slots: impl IntoIterator<Item = &'a Slot>) {
        for s in slots {
            let (buffer, var) = s.held_parts();
            self.bytes = self.bytes.saturating_add(buffer as u64);
            if let Some(var) = var {
                self.var(&var);
            }
        }
    }
}

/// What a hash table of an array's side holds: a slot of key and value, and a control byte,
/// for every item it has room for.
fn map_bytes<V>(map: &std::collections::HashMap<usize, V>) -> usize {
    map.capacity() * (std::mem::size_of::<(usize, V)>() + 1)
}

/// Charges between measurements: a sixteenth of the budget, at most 64 MiB.
fn measure_every(budget: u64) -> u64 {
    (budget / 16).clamp(1, 64 << 20)
}

impl Interp<'_, '_> {
    /// Counts the copy of a shared array's items made where the budget cannot be checked
    /// (while a variable is borrowed to change it); the next [`Interp::charge`] checks it.
    pub(super) fn owe(&self, bytes: u64) {
        self.charged.set(self.charged.get().saturating_add(bytes));
    }

    /// Counts what a store at `span` brought; past the charges allowed between measurements,
    /// measures every variable and stops the run when they hold more than the budget.
    pub(super) fn charge(&self, bytes: u64, span: Span) -> Run<()> {
        let charged = self.charged.get().saturating_add(bytes);
        let budget = self.options.max_memory;
        if charged < measure_every(budget) {
            self.charged.set(charged);
            return Ok(());
        }
        self.charged.set(0);
        let held = self.held_bytes();
        if held <= budget {
            return Ok(());
        }
        let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
        let mut f = self.fault_at(
            span,
            format!(
                "the macro's strings and arrays hold {:.1} MiB, more than the {:.1} MiB allowed \
                 (ncsheet's memory limit for a macro run; {})",
                mib(held),
                mib(budget),
                self.options.raise_hint("raise it with --max-memory")
            ),
        );
        f.kind = ErrorKind::Limit;
        Err(f)
    }

    /// The bytes the variables of every running procedure, the module and the Static
    /// variables hold.
    fn held_bytes(&self) -> u64 {
        let mut m = Measure::default();
        m.slots(self.globals.borrow().iter().flat_map(|g| g.iter()));
        for frame in self.frames.borrow().iter() {
            m.slots(frame.vars.iter());
        }
        m.slots(self.kept.borrow().values().flatten());
        // What the macro's files hold (`files.rs`): written text and text being read.
        m.bytes.saturating_add(self.files.borrow().held_bytes())
    }
}
