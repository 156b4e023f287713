//! What a macro variable holds (values, arrays, objects, `Type` records) and VBA's
//! conversions between them and the sheet's values.

use std::cell::Cell;
use std::rc::Rc;

use crate::eval::functions::vba::vba_number;
use crate::eval::functions::vba::vba_text;
use crate::eval::{Array, Value, XlError};
use crate::formula::address::Rect;
use crate::formula::ast::SheetId;

use super::ast::Ty;
use super::typing::{Declared, Typing};

/// What a variable holds.
#[derive(Clone, Debug)]
pub enum Var {
    Value(Value),
    Obj(Obj),
    Array(VArray),
    /// A variable of a `Type`: its fields in the Type's order (copied on assignment, as VBA does).
    Record(usize, Vec<Var>),
}

/// An array variable: its items (row-major) and the lower bound of each dimension.
#[derive(Clone, Debug)]
pub struct VArray {
    pub data: Rc<Array>,
    /// (first row, first column) indexes; a one-dimensional array uses only the column.
    pub lower: (i64, i64),
    pub dims: u8,
    /// The items that are objects (`Set a(i) = New Class1`), by their row-major position;
    /// `data` holds Empty there. Copying the array copies the references, as VBA does.
    pub objects: Option<Rc<std::collections::HashMap<usize, Obj>>>,
    /// The items of a Variant array that hold a number of a type other than Double, with
    /// that type, by row-major position: a Date (VarType 7), or the Integer 1 of `Array(1, 2)`
    /// and of `v(0) = 1` keeps its type in the array ([MS-VBAL] 2.1.1.1). An array of a
    /// declared type needs none: its type says it.
    pub(super) held_types: Option<Rc<std::collections::HashMap<usize, Declared>>>,
    /// The items of a Variant array that hold an array, by row-major position, each with its
    /// own bounds ([MS-VBAL] 2.2: an array value carries its bounds; `a(1) = b` with
    /// `Dim b(1 To 3)` keeps 1 To 3). `data` holds the same items there, as a plain array.
    pub arrays: Option<Rc<std::collections::HashMap<usize, VArray>>>,
    /// An array of a `Type` (`Dim pts(1 To 10) As TPoint`): each item's record, row-major
    /// (`data` holds Empty there). Copying the array copies the records: Types are values.
    pub records: Option<Rc<Vec<Var>>>,
    /// An array of three dimensions or more (`Dim a(1 To 3, 1 To 4, 0 To 2)`): the (lower
    /// bound, length) of every dimension, first to last. `data`'s rows are then every
    /// dimension but the last, row-major, and its columns the last dimension, so that
    /// `ReDim Preserve` of the last dimension keeps items as it does for two. `None` for one
    /// or two dimensions, which `lower` and `data` describe alone (the common case, kept
    /// as fast as before).
    pub shape: Option<Rc<[(i64, usize)]>>,
    /// The items of a LongLong or Variant array that hold a LongLong past 2^53, where their
    /// double is not exact: the integer, by row-major position (`longlong.rs`). Each is used
    /// only while it still stands for its item's double; `None` for almost every array.
    pub(super) exact: Option<Rc<std::collections::HashMap<usize, i64>>>,
    /// The type its items were declared with (`Dim o() As Double`, a Function `As Long()`),
    /// which the array keeps wherever it goes: a Variant given it, or a Function `As Variant`
    /// returning it, holds a `Double()` ("TypeName function", "VarType function": vbArray +
    /// vbDouble), not a `Variant()`. `Variant` for an array of Variants, objects or records.
    pub(super) item_type: Declared,
}

impl VArray {
    /// An array of `dims` dimensions over `data` from the bounds `lower`, holding plain
    /// values: none of the side tables (objects, held types, arrays, records, shape,
    /// LongLongs) that the few arrays needing them add.
    pub(super) fn plain(data: Rc<Array>, lower: (i64, i64), dims: u8) -> VArray {
        VArray {
            data,
            lower,
            dims,
            objects: None,
            held_types: None,
            arrays: None,
            records: None,
            shape: None,
            exact: None,
            item_type: Declared::Variant,
        }
    }

    /// Its items and what it holds beside them (arrays, objects, records) that it alone holds,
    /// to be let go one after another (`classes::let_go`).
    pub(super) fn into_parts(self) -> (Rc<Array>, Vec<Var>) {
        let mut parts = Vec::new();
        if let Some(arrays) = self.arrays.and_then(|a| Rc::try_unwrap(a).ok()) {
            parts.extend(arrays.into_values().map(Var::Array));
        }
        if let Some(objects) = self.objects.and_then(|o| Rc::try_unwrap(o).ok()) {
            parts.extend(objects.into_values().map(Var::Obj));
        }
        if let Some(records) = self.records.and_then(|r| Rc::try_unwrap(r).ok()) {
            parts.extend(records);
        }
        (self.data, parts)
    }

    /// A one-dimensional array of `data`'s one row, from `lower`, holding plain values.
    pub fn row(data: Rc<Array>, lower: i64) -> VArray {
        VArray::plain(data, (1, lower), 1)
    }

    /// A two-dimensional array of `data`'s rows and columns, from (1, 1), as VBA reads a
    /// Range's values, holding plain values.
    pub fn table(data: Rc<Array>) -> VArray {
        VArray::plain(data, (1, 1), 2)
    }

    /// The item at row-major position `k` as a variable holds it: its object, or its value.
    pub fn item(&self, k: usize) -> Var {
        if let Some(record) = self.records.as_ref().and_then(|r| r.get(k)) {
            return record.clone();
        }
        if let Some(array) = self.arrays.as_ref().and_then(|a| a.get(&k)) {
            return Var::Array(array.clone());
        }
        match self.objects.as_ref().and_then(|o| o.get(&k)) {
            Some(object) => Var::Obj(object.clone()),
            None => Var::Value(self.data.data[k].clone()),
        }
    }

    /// Whether the item at row-major position `k` holds a Date (in a Variant array).
    pub fn holds_date(&self, k: usize) -> bool {
        self.held(k) == Declared::Date
    }

    /// The type of the number the item at row-major position `k` holds, where it is not a
    /// Double (in a Variant array), or the array's declared item type (a `Long()` a Variant
    /// holds gives a Long); `Variant` otherwise.
    pub(super) fn held(&self, k: usize) -> Declared {
        self.held_types.as_ref().and_then(|d| d.get(&k).copied()).unwrap_or(self.item_type)
    }

    /// Notes whether the item at `k` now holds a Date.
    pub fn mark_date(&mut self, k: usize, date: bool) {
        self.mark_held(k, if date { Declared::Date } else { Declared::Variant });
    }

    /// Notes the type of the number the item at `k` now holds (`Variant` or `Double`: none
    /// to note).
    pub(super) fn mark_held(&mut self, k: usize, ty: Declared) {
        match (&mut self.held_types, ty) {
            (Some(held), Declared::Variant | Declared::Double) if held.contains_key(&k) => {
                Rc::make_mut(held).remove(&k);
            }
            (_, Declared::Variant | Declared::Double) => {}
            (held, ty) => {
                Rc::make_mut(held.get_or_insert_with(Default::default)).insert(k, ty);
            }
        }
    }

    /// The LongLong the item at `k` holds past 2^53, if one is kept for it.
    pub(super) fn exact_item(&self, k: usize) -> Option<i64> {
        self.exact.as_ref().and_then(|e| e.get(&k).copied())
    }

    /// Keeps `k`'s LongLong (`Some`) or forgets it (`None`: the item changed to anything else).
    pub(super) fn keep_exact_item(&mut self, k: usize, long_long: Option<i64>) {
        match (&mut self.exact, long_long) {
            (Some(kept), None) if kept.contains_key(&k) => _ = Rc::make_mut(kept).remove(&k),
            (_, None) => {}
            (kept, Some(n)) => _ = Rc::make_mut(kept.get_or_insert_with(Default::default)).insert(k, n),
        }
    }

    /// The (lower bound, length) of each dimension, first to last; none before the first
    /// ReDim of a dynamic array.
    pub fn bounds(&self) -> Vec<(i64, usize)> {
        match (self.dims, &self.shape) {
            (0, _) => Vec::new(),
            (1, _) => vec![(self.lower.1, self.data.cols)],
            (2, _) => vec![(self.lower.0, self.data.rows), (self.lower.1, self.data.cols)],
            (_, Some(shape)) => shape.to_vec(),
            (_, None) => unreachable!("an array of three dimensions or more has its shape"),
        }
    }

    /// The row-major positions of the items in VBA's memory order, the first index varying
    /// fastest (`a(1, 1), a(2, 1), …, a(1, 2)`): the order For Each goes through an array in
    /// and a file holds it in (VBA's arrays are laid out column-major, which is why
    /// `ReDim Preserve` may change only the last dimension: "ReDim statement").
    pub fn memory_order(&self) -> Vec<usize> {
        let lengths: Vec<usize> = self.bounds().iter().map(|&(_, len)| len).collect();
        let items = self.data.data.len();
        // One dimension, or a range's values whose blank tail is no items (`whole`): as held.
        if lengths.len() < 2 || lengths.iter().product::<usize>() != items {
            return (0..items).collect();
        }
        if lengths.contains(&0) {
            return Vec::new();
        }
        // The step in `data` of each dimension's index: the last dimension's is 1.
        let mut steps = vec![1usize; lengths.len()];
        for d in (0..lengths.len() - 1).rev() {
            steps[d] = steps[d + 1] * lengths[d + 1];
        }
        let mut order = Vec::with_capacity(items);
        let mut index = vec![0usize; lengths.len()];
        let mut at = 0usize;
        loop {
            order.push(at);
            // Counts up like an odometer whose first wheel turns fastest.
            let mut d = 0;
            loop {
                if d == lengths.len() {
                    return order;
                }
                index[d] += 1;
                at += steps[d];
                if index[d] < lengths[d] {
                    break;
                }
                at -= steps[d] * lengths[d];
                index[d] = 0;
                d += 1;
            }
        }
    }

    /// Every item, in VBA's memory order (For Each, [`VArray::memory_order`]).
    pub fn items(&self) -> Vec<Var> {
        self.memory_order().into_iter().map(|k| self.item(k)).collect()
    }
}

/// The objects a macro reaches through member paths.
#[derive(Clone, Debug, PartialEq)]
pub enum Obj {
    Value(Value),
    Range(SheetId, Rect),
    /// A Range of two or more areas on one sheet (`Range("A1:B2,D4")`, `Union` of separate
    /// ranges), in the order given (`areas.rs`).
    Areas(SheetId, Rc<[Rect]>),
    /// `r.Areas`: the areas of a range, one for a range of one area ("Range.Areas property").
    AreaList(SheetId, Rc<[Rect]>),
    /// A Range, Rows or Columns, Font or Interior whose cells were all deleted (`Rows(5).Delete`
    /// with `r` set to B5): Excel's object is gone, and using it is run-time error 424.
    DeletedRange(SheetId),
    /// `r.Rows` / `r.Columns` without an index: for `.Count` and `(i)`.
    Lines(SheetId, Rect, bool),
    /// `r.Font` or `r.Interior` (`formats.rs`).
    Look(SheetId, Rect, super::formats::LookPart),
    /// A sheet's hyperlinks on the cells of a rectangle (the whole sheet for `ws.Hyperlinks`),
    /// and one hyperlink of a sheet by its id (`hyperlinks.rs`).
    Hyperlinks(SheetId, Rect),
    Hyperlink(SheetId, u32),
    Sheet(SheetId),
    /// `Sheets(Array("A", "B"))`: several sheets at once, in the order named.
    SheetGroup(Rc<[SheetId]>),
    Sheets,
    Workbook,
    App,
    /// Excel's WorksheetFunction object (`Set wf = Application.WorksheetFunction`): its
    /// members are the worksheet functions, called through a variable set to it by the names
    /// the parser resolves (`resolve.rs`, `sheet_function_aliases`).
    SheetFunctions,
    Nc,
    Debug,
    /// `Err`: the last trapped error.
    Err,
    /// A field of a `Type` variable, by the variable's name and the fields leading to it:
    /// reads and writes reach the variable itself (so `With p` … `.X = 1` changes `p`).
    Record(Rc<str>, Vec<usize>),
    /// A Collection or a Dictionary, shared by every variable set to it.
    Store(super::collections::Handle),
    /// Scripting's FileSystemObject or one of its TextStreams (`files.rs`).
    Files(super::files::FileObj),
    /// An object of a class module, shared by every variable set to it.
    Instance(super::classes::Instance),
    /// A worksheet's `Sort` object and its `SortFields` (`sort.rs`).
    SheetSort(SheetId),
    SortFields(SheetId),
    /// VBScript's RegExp, MatchCollection, Match or SubMatches (`regexp.rs`).
    Regex(super::regexp::RegexObj),
    /// A harmless object or member ncsheet keeps nothing of (`ActiveWindow`, `Borders`,
    /// `Interior.Pattern`), by the name a message gives it: set and called as no-ops
    /// (`unmodelled.rs`).
    Unkept(Rc<str>),
    /// A sheet's tables, a table, its columns or rows (`list_objects.rs`).
    Table(super::list_objects::TableObj),
}

impl Obj {
    pub fn describe(&self) -> &'static str {
        match self {
            Obj::Value(_) => "a value",
            Obj::Range(..) => "a Range",
            Obj::Areas(..) => "a Range of several areas",
            Obj::AreaList(..) => "an Areas collection",
            Obj::DeletedRange(..) => "a Range whose cells were deleted",
            Obj::Lines(..) => "a Rows or Columns collection",
            Obj::Look(_, _, super::formats::LookPart::Font) => "a Font",
            Obj::Look(_, _, super::formats::LookPart::Interior) => "an Interior",
            Obj::Hyperlinks(..) => "a Hyperlinks collection",
            Obj::Hyperlink(..) => "a Hyperlink",
            Obj::Sheet(_) => "a Worksheet",
            Obj::SheetGroup(_) => "a group of sheets",
            Obj::Sheets => "the Worksheets collection",
            Obj::Workbook => "the Workbook",
            Obj::App => "Application",
            Obj::Nc => "Nc",
            Obj::Debug => "Debug",
            Obj::Err => "Err",
            Obj::SheetFunctions => "WorksheetFunction",
            Obj::Record(..) => "a Type value",
            Obj::Files(super::files::FileObj::System) => "a FileSystemObject",
            Obj::Files(super::files::FileObj::Stream(_)) => "a TextStream",
            Obj::Store(h) => match h.class() {
                super::ast::Class::Collection => "a Collection",
                super::ast::Class::Dictionary => "a Dictionary",
                super::ast::Class::ArrayList => "an ArrayList",
            },
            Obj::Instance(_) => "an object of a class module",
            Obj::SheetSort(_) => "a Sort",
            Obj::SortFields(_) => "a SortFields collection",
            Obj::Regex(r) => r.describe(),
            Obj::Unkept(_) => "a setting ncsheet does not keep",
            Obj::Table(_) => "a table (ListObject) or its rows or columns",
        }
    }
}

#[derive(Clone, Debug)]
pub struct Slot {
    pub name: Rc<str>,
    /// What it holds, read through [`Slot::var`]: a text that `s = s & …` grows is kept as a
    /// buffer with room to grow.
    held: Held,
    pub ty: Option<Ty>,
    pub constant: bool,
    /// `Dim x As New Class1`: the class an auto-instantiated variable makes an object of when
    /// it is used holding Nothing ([MS-VBAL] 5.2.3.1.4), and the declaration's place.
    pub new: Option<(super::ast::Made, super::ast::Span)>,
    /// The type a Variant holds its number with ("Variant data type": "numeric Variant data
    /// is maintained in its original data type"): an Integer for `x = 5`, a Date assigned
    /// from a Date, which it shows and answers as until assigned anything else. `Variant`
    /// when it holds no number or the variable is not a Variant.
    pub(super) holds: Declared,
    /// A fixed-size array: `Dim a(1 To 3)` gave its bounds, not ReDim (Put writes no
    /// descriptor before it in a Random file, "Put statement").
    pub fixed: bool,
    /// A number given at each change of what it holds, never given twice ([`next_write`]):
    /// `s = s & f(x)` appends in place when it is the same after `f(x)` ran (`append.rs`).
    written: u64,
    /// The LongLong the variable holds, where its double is not exact (past 2^53,
    /// `longlong.rs`); forgotten at any other change of what it holds.
    exact: Option<i64>,
    /// The Decimal the variable holds, where its double does not give its digits back
    /// (`typing/decimal.rs`); forgotten at any other change of what it holds.
    decimal: Option<Box<super::typing::Dec>>,
}

/// A number no earlier change of a variable was given.
fn next_write() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static WRITES: AtomicU64 = AtomicU64::new(0);
    WRITES.fetch_add(1, Ordering::Relaxed)
}

/// What a variable holds: a value, or a text growing in place.
#[derive(Clone, Debug)]
enum Held {
    Var(Var),
    Growing(Growing),
    GrowingItem(GrowingItem),
}

/// What a variable held is let go through `classes::let_go` when the variable dies or is
/// given another value: arrays within arrays (`a = Array(a)` a million times), and objects or
/// Collections holding arrays that hold the next, are let go one link after another. Dropped
/// each inside the one holding it, such a chain overflowed the native stack.
impl Drop for Held {
    fn drop(&mut self) {
        let var = match self {
            Held::Var(var) => std::mem::replace(var, Var::Value(Value::Blank)),
            Held::Growing(_) => return,
            Held::GrowingItem(item) => match item.array.get_mut().take() {
                Some(array) => Var::Array(array),
                None => match item.text.shown.take() {
                    Some(var) => var,
                    None => return,
                },
            },
        };
        if !matches!(var, Var::Value(Value::Number(_) | Value::Blank | Value::Bool(_) | Value::Text(_))) {
            super::classes::let_go(vec![var]);
        }
    }
}

/// A text variable that `s = s & …` appends to (`append.rs`): a value's text is an `Rc<str>`,
/// which cannot grow, so each append copied the whole text and a loop of them was quadratic.
/// The buffer doubles its capacity as it grows; the value is made from it when the variable
/// is read, and kept until the next append.
#[derive(Clone, Debug)]
struct Growing {
    /// Shared only while an append evaluates its right side ([`Slot::growing_text`]).
    text: Rc<String>,
    /// The text's length in UTF-16 units, the unit of the macro string limit.
    units: usize,
    /// Its length in characters, which `Len` answers without making the value: a loop that
    /// reads `Len(s)` between appends would copy the text at every turn.
    chars: usize,
    /// Whether every character is ASCII (one byte each): the Mid statement then replaces
    /// characters in place by their byte positions.
    ascii: bool,
    shown: std::cell::OnceCell<Var>,
}

impl Growing {
    fn shown(&self) -> &Var {
        self.shown.get_or_init(|| Var::Value(Value::Text(Rc::from(self.text.as_str()))))
    }

    /// The text of `units` UTF-16 units, made ready to grow.
    fn of(text: &str, units: usize) -> Growing {
        super::count(&super::TEXT_COPIED, text.len() as u64);
        let (chars, ascii) = (text.chars().count(), text.is_ascii());
        Growing { text: Rc::new(String::from(text)), units, chars, ascii, shown: std::cell::OnceCell::new() }
    }
}

/// An array whose item `k` `a(i) = a(i) & …` appends to (`append.rs`): an item's text is an
/// `Rc<str>` as a variable's is, so each append copied the whole item and a loop of them was
/// quadratic. The item's text grows in a buffer apart from the array, whose item `k` is stale
/// meanwhile. Reading the variable moves the array into `text.shown` with the text put back
/// (the array is moved, not copied: one copy of the item's text); the next append moves it
/// out again. Reading one item (`a(j)`) reads the array apart, without making either.
#[derive(Clone, Debug)]
struct GrowingItem {
    /// The array while its item grows apart; `None` while `text.shown` holds it.
    array: std::cell::RefCell<Option<VArray>>,
    /// The row-major position of the item.
    k: usize,
    /// The item's text; its `shown` is the whole array, once read.
    text: Growing,
}

impl GrowingItem {
    fn shown(&self) -> &Var {
        self.text.shown.get_or_init(|| {
            let mut array = self.array.borrow_mut().take().expect("the array is apart until read");
            Rc::make_mut(&mut array.data).data[self.k] = Value::Text(Rc::from(self.text.text.as_str()));
            Var::Array(array)
        })
    }

    /// The array apart from its item, moved back out of `shown` when it was read.
    fn take_back(&mut self) {
        if let Some(Var::Array(array)) = self.text.shown.take() {
            *self.array.get_mut() = Some(array);
        }
    }
}

impl Slot {
    /// A variable holding `var`: not a constant, not `As New`, no Date.
    pub fn new(name: Rc<str>, var: Var, ty: Option<Ty>) -> Slot {
        let holds = Declared::Variant;
        let written = next_write();
        Slot {
            name,
            held: Held::Var(var),
            ty,
            constant: false,
            new: None,
            holds,
            fixed: false,
            written,
            exact: None,
            decimal: None,
        }
    }

    /// What the variable holds.
    pub fn var(&self) -> &Var {
        match &self.held {
            Held::Var(var) => var,
            Held::Growing(g) => g.shown(),
            Held::GrowingItem(g) => g.shown(),
        }
    }

    /// What the variable holds, to change in place (a growing text becomes a value first).
    pub fn var_mut(&mut self) -> &mut Var {
        self.written = next_write();
        self.exact = None;
        self.decimal = None;
        match &mut self.held {
            Held::Growing(g) => {
                let var = g.shown.take().unwrap_or_else(|| Var::Value(Value::Text(Rc::from(g.text.as_str()))));
                self.held = Held::Var(var);
            }
            Held::GrowingItem(g) => {
                g.shown();
                self.held = Held::Var(g.text.shown.take().expect("made just above"));
            }
            Held::Var(_) => {}
        }
        match &mut self.held {
            Held::Var(var) => var,
            _ => unreachable!("made a value above"),
        }
    }

    /// Gives the variable `var`; returns what it held.
    pub fn replace(&mut self, var: Var) -> Var {
        std::mem::replace(self.var_mut(), var)
    }

    /// The length in UTF-16 units of the text the variable holds, ready to be appended to
    /// with [`Slot::append`]; `None` when it holds no text.
    pub(super) fn text_units(&mut self) -> Option<usize> {
        if let Held::Var(Var::Value(Value::Text(t))) = &self.held {
            self.held = Held::Growing(Growing::of(t, t.encode_utf16().count()));
        }
        match &self.held {
            Held::Growing(g) => Some(g.units),
            _ => None,
        }
    }

    /// The length in UTF-16 units of the text the array's item at row-major position `k`
    /// holds, ready to be appended to with [`Slot::append`] (another item growing goes back
    /// into the array first); `None` when the variable holds no array or the item no text.
    pub(super) fn item_units(&mut self, k: usize) -> Option<usize> {
        if let Held::GrowingItem(g) = &self.held {
            if g.k == k {
                return Some(g.text.units);
            }
        }
        let Var::Array(a) = self.var_mut() else { return None };
        let Some(Value::Text(_)) = a.data.data.get(k) else { return None };
        // Only this array holds its items now (a copy made of them when shared, as
        // `a(i) = v` makes one): the item's text is taken out, not shared.
        let item = std::mem::replace(&mut Rc::make_mut(&mut a.data).data[k], Value::Blank);
        let Value::Text(t) = item else { unreachable!("a text, checked above") };
        let text = Growing::of(&t, t.encode_utf16().count());
        let units = text.units;
        let mut taken = std::mem::replace(&mut self.held, Held::Var(Var::Value(Value::Blank)));
        let Held::Var(var) = &mut taken else { unreachable!("an array, checked above") };
        let Var::Array(array) = std::mem::replace(var, Var::Value(Value::Blank)) else {
            unreachable!("an array, checked above")
        };
        self.held = Held::GrowingItem(GrowingItem { array: std::cell::RefCell::new(Some(array)), k, text });
        Some(units)
    }

    /// `f` of the array the variable holds, without putting a growing item's text back in
    /// (its item is stale there: [`Slot::growing_item`] tells which); `None` when it holds
    /// no array.
    pub(super) fn with_array<T>(&self, f: impl FnOnce(&VArray) -> T) -> Option<T> {
        if let Held::GrowingItem(g) = &self.held {
            if let Some(array) = g.array.borrow().as_ref() {
                return Some(f(array));
            }
        }
        match self.var() {
            Var::Array(a) => Some(f(a)),
            _ => None,
        }
    }

    /// The row-major position of the array's item growing in place, and its text (shared,
    /// not copied, as [`Slot::growing_text`]).
    pub(super) fn growing_item(&self) -> Option<(usize, Rc<String>)> {
        match &self.held {
            Held::GrowingItem(g) => Some((g.k, Rc::clone(&g.text.text))),
            _ => None,
        }
    }

    /// Appends `piece` of `units` UTF-16 units to the text [`Slot::text_units`] made ready.
    pub(super) fn append(&mut self, piece: &str, units: usize) {
        self.written = next_write();
        let g = match &mut self.held {
            Held::Growing(g) => {
                g.shown.take();
                g
            }
            Held::GrowingItem(item) => {
                item.take_back();
                &mut item.text
            }
            Held::Var(_) => unreachable!("text_units or item_units made the text ready"),
        };
        if Rc::strong_count(&g.text) > 1 {
            // Shared (a copy of the variable holds it too): made the variable's own first.
            super::count(&super::TEXT_COPIED, g.text.len() as u64);
        }
        Rc::make_mut(&mut g.text).push_str(piece);
        g.units += units;
        g.chars += piece.chars().count();
        g.ascii &= piece.is_ascii();
    }

    /// `Mid(s, from + 1, length) = with` (the Mid statement) on an ASCII text growing in place,
    /// `with` ASCII too: the characters replaced where they are, the text's length kept.
    /// `false` (nothing done) for any other text, or a start past its end (run-time error 5,
    /// which the statement raises).
    pub(super) fn replace_ascii(&mut self, from: usize, length: Option<usize>, with: &str) -> bool {
        let Held::Growing(g) = &mut self.held else { return false };
        if !g.ascii || !with.is_ascii() || from >= g.chars {
            return false;
        }
        let n = with.len().min(g.chars - from).min(length.unwrap_or(usize::MAX));
        g.shown.take();
        Rc::make_mut(&mut g.text).replace_range(from..from + n, &with[..n]);
        self.written = next_write();
        true
    }

    /// The LongLong the variable holds exactly, where its double is not exact.
    pub(super) fn exact(&self) -> Option<i64> {
        self.exact
    }

    /// Notes the LongLong `k` the variable now holds as its nearest double.
    pub(super) fn set_exact(&mut self, k: i64) {
        self.exact = Some(k);
    }

    /// The Decimal the variable holds, where its double does not give its digits back.
    pub(super) fn decimal(&self) -> Option<super::typing::Dec> {
        self.decimal.as_deref().copied()
    }

    /// Notes the Decimal `d` the variable now holds as its nearest double.
    pub(super) fn set_decimal(&mut self, d: super::typing::Dec) {
        self.decimal = Some(Box::new(d));
    }

    /// The number of the last change of what the variable holds (see `written`).
    pub(super) fn written(&self) -> u64 {
        self.written
    }

    /// The text the variable grows in place, shared (not copied): what it held before an
    /// append's right side ran, should that change it.
    pub(super) fn growing_text(&self) -> Option<Rc<String>> {
        match &self.held {
            Held::Growing(g) => Some(Rc::clone(&g.text)),
            _ => None,
        }
    }

    /// The length in characters of the text the variable grows in place; `None` when it
    /// holds anything else.
    pub(super) fn growing_chars(&self) -> Option<usize> {
        match &self.held {
            Held::Growing(g) => Some(g.chars),
            _ => None,
        }
    }

    /// The bytes of a growing text's buffer, and what else the variable holds to be measured
    /// (the value made from the buffer, when it was read): for the memory budget.
    pub(super) fn held_parts(&self) -> (usize, Option<std::borrow::Cow<'_, Var>>) {
        use std::borrow::Cow;
        match &self.held {
            Held::Var(var) => (0, Some(Cow::Borrowed(var))),
            Held::Growing(g) => (g.text.capacity(), g.shown.get().map(Cow::Borrowed)),
            // The array apart is shared for the measure, not copied (its items are `Rc`s).
            Held::GrowingItem(g) => match g.text.shown.get() {
                Some(array) => (g.text.text.capacity(), Some(Cow::Borrowed(array))),
                None => {
                    let array = g.array.borrow().clone().map(|a| Cow::Owned(Var::Array(a)));
                    (g.text.text.capacity(), array)
                }
            },
        }
    }

    /// The type its value answers to: the declared one, or for a Variant holding a number
    /// the number's type.
    pub fn held_ty(&self) -> Option<Ty> {
        match (self.holds, self.var()) {
            (Declared::Variant, _) | (_, Var::Value(Value::Blank)) => self.ty.clone(),
            (holds, Var::Value(Value::Number(_))) => holds.ty(),
            _ => self.ty.clone(),
        }
    }

    /// Notes the type of the number the variable now holds, which only a Variant keeps.
    pub(super) fn set_holds(&mut self, ty: Declared) {
        let variant = matches!(self.ty, None | Some(Ty::Variant));
        let number = matches!(self.var(), Var::Value(Value::Number(_)));
        self.holds = if variant && number { ty } else { Declared::Variant };
    }

    /// The variable's type as `typing.rs` follows it: for the declared type, a Variant is a
    /// Variant unless it holds a Date (which `+` and `&` treat as a Date); for the held type,
    /// a Variant is the type of what it holds, Empty an Integer ([MS-VBAL] 5.6.9.3: Empty's
    /// effective value type in arithmetic).
    pub(super) fn typed(&self, typing: Typing) -> Declared {
        match (typing, self.holds) {
            (_, Declared::Date) => Declared::Date,
            (Typing::Held, Declared::Variant) => match (Declared::of_ty(self.ty.as_ref()), self.var()) {
                (Declared::Variant, Var::Value(Value::Text(_))) => Declared::String,
                (Declared::Variant, Var::Value(Value::Bool(_))) => Declared::Boolean,
                (Declared::Variant, Var::Value(Value::Blank)) => Declared::Integer,
                (Declared::Variant, Var::Value(Value::Number(_))) => Declared::Double,
                (declared, _) => declared,
            },
            (Typing::Held, holds) => holds,
            (Typing::Declared, _) => Declared::of_ty(self.ty.as_ref()),
        }
    }
}

/// The variables of a procedure's call or of the module, in the order declared, each found
/// by name in one step: 50,000 `Dim`s in one Sub declare in time proportional to their number.
///
/// A loop names the same few variables over and over (`a(j) > a(j + 1)` in a sort's inner
/// loop): a small table of the names found lately, placed by their first and last letters and
/// length, answers those without hashing the whole name with the map's keyed hash (that hash
/// and its fallback to lower case were a third of a sort's time). A hit is checked against
/// the slot's own name, so the table can only speed a lookup, never change its answer.
///
/// A call's few parameters and locals (a `Swap(l, i, j)` with one `Dim t`, called millions
/// of times from a sort) are searched one by one: the map is built only once a table holds
/// more than [`SCANNED_SLOTS`], so a call does not allocate and hash a lower-case key for
/// each of its variables (a tenth of a bubble sort's time).
#[derive(Clone, Debug, Default)]
pub struct Slots {
    slots: Vec<Slot>,
    /// Each slot's index by its name in ASCII lower case, once there are more than
    /// [`SCANNED_SLOTS`] (empty before).
    index: std::collections::HashMap<Box<str>, usize>,
    /// The slot index of a name found lately, at the name's [`recent_place`].
    recent: [Cell<usize>; RECENT_NAMES],
}

/// The names [`Slots`] remembers: a procedure's inner loop names a handful.
const RECENT_NAMES: usize = 16;

/// The slots [`Slots`] searches by comparing names, without its map.
const SCANNED_SLOTS: usize = 8;

/// Where [`Slots`] remembers `name`: from its first and last letters in lower case and its
/// length, which tell a loop's few names apart (`i`, `j`, `a`, `t`, `total`) in a few steps.
fn recent_place(name: &str) -> usize {
    let bytes = name.as_bytes();
    let letter = |b: Option<&u8>| b.map_or(0, |b| b.to_ascii_lowercase() as usize);
    (letter(bytes.first()) * 5 + letter(bytes.last()) * 2 + bytes.len()) % RECENT_NAMES
}

impl Slots {
    /// The bytes the slots take as allocated, their names' and values' own memory aside (an
    /// object's fields: the memory budget counts them, `classes::object_bytes`).
    pub(super) fn own_bytes(&self) -> u64 {
        let slots = self.slots.capacity() * std::mem::size_of::<Slot>();
        (std::mem::size_of::<Slots>() + slots) as u64
    }

    /// Lets go of the room the slots have beyond the ones they hold.
    pub(super) fn shrink_to_fit(&mut self) {
        self.slots.shrink_to_fit();
    }

    pub fn get(&self, name: &str) -> Option<&Slot> {
        self.position(name).map(|i| &self.slots[i])
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut Slot> {
        self.position(name).map(|i| &mut self.slots[i])
    }

    fn position(&self, name: &str) -> Option<usize> {
        let remembered = &self.recent[recent_place(name)];
        let i = remembered.get();
        if self.slots.get(i).is_some_and(|s| s.name.eq_ignore_ascii_case(name)) {
            return Some(i);
        }
        let i = self.hashed_position(name)?;
        remembered.set(i);
        Some(i)
    }

    fn hashed_position(&self, name: &str) -> Option<usize> {
        if self.index.is_empty() {
            let found = self.slots.iter().position(|s| s.name.eq_ignore_ascii_case(name));
            // Each slot looked at counts as a probe ([`super::Work::name_probes`]).
            super::count(&super::NAME_PROBES, found.map_or(self.slots.len(), |i| i + 1) as u64);
            return found;
        }
        super::count(&super::NAME_PROBES, 1);
        if let Some(&i) = self.index.get(name) {
            return Some(i);
        }
        if !name.bytes().any(|b| b.is_ascii_uppercase()) {
            return None;
        }
        super::count(&super::NAME_PROBES, 1);
        self.index.get(name.to_ascii_lowercase().as_str()).copied()
    }

    /// Adds a variable; one already of that name keeps its place and takes the new slot.
    pub fn push(&mut self, slot: Slot) {
        match self.position(&slot.name) {
            Some(i) => self.slots[i] = slot,
            None => {
                self.slots.push(slot);
                if self.slots.len() > SCANNED_SLOTS {
                    self.index_new_slots();
                }
            }
        }
    }

    /// Puts in the map the slots it does not hold yet: all of them when the table first
    /// passes [`SCANNED_SLOTS`], then the one just pushed.
    fn index_new_slots(&mut self) {
        for at in self.index.len()..self.slots.len() {
            self.index.insert(self.slots[at].name.to_ascii_lowercase().into(), at);
        }
    }

    pub fn iter(&self) -> std::slice::Iter<'_, Slot> {
        self.slots.iter()
    }

    /// The variables held.
    pub(super) fn len(&self) -> usize {
        self.slots.len()
    }

    /// Where variable `name` is held, for [`Slots::at`] and [`Slots::put_at`].
    pub(super) fn position_of(&self, name: &str) -> Option<usize> {
        self.position(name)
    }

    pub(super) fn at(&self, at: usize) -> &Slot {
        &self.slots[at]
    }

    /// Puts `slot` back at `at`, where the variable of its name is held.
    pub(super) fn put_at(&mut self, at: usize, slot: Slot) {
        self.slots[at] = slot;
    }

    pub fn iter_mut(&mut self) -> std::slice::IterMut<'_, Slot> {
        self.slots.iter_mut()
    }
}

/// A value as a variable holds it: arrays become array variables (one row: one dimension
/// from Option Base; more rows: two dimensions from 1, as VBA reads a Range's values).
pub fn array_var(v: Value, base: i64) -> Var {
    match v {
        Value::Array(a) if a.rows == 1 && a.cols == 1 => Var::Value(a.data[0].clone()),
        Value::Array(a) if a.rows == 1 => Var::Array(VArray::row(a, base)),
        Value::Array(a) => Var::Array(VArray::table(a)),
        other => Var::Value(other),
    }
}

/// A range's values as a variable holds them (`v = Range("B5:D5").Value`): one cell is its
/// value, any other range a two-dimensional array from (1, 1), a single row too (Excel's
/// "Range.Value property": 1 × 3 for B5:D5). A whole column or row is all of it
/// (1,048,576 rows), not the used part the evaluator stores with its blank tail, up to
/// ncsheet's limit on an array's items.
pub fn range_var(v: Value) -> Var {
    match v {
        Value::Array(a) if a.rows == 1 && a.cols == 1 && a.tail.is_none() => Var::Value(a.data[0].clone()),
        Value::Array(a) => Var::Array(VArray::table(whole(a))),
        other => Var::Value(other),
    }
}

/// A range's values with the blank tail the evaluator keeps out of memory made items.
pub fn whole_array(v: Value) -> Value {
    match v {
        Value::Array(a) => Value::Array(whole(a)),
        other => other,
    }
}

/// An array with its tail made items, when the whole fits [`crate::eval::value::MAX_ARRAY_ITEMS`].
fn whole(a: Rc<Array>) -> Rc<Array> {
    let (rows, cols) = a.whole_size();
    if (rows, cols) == (a.rows, a.cols) || crate::eval::value::too_many_items(rows, cols) {
        return a;
    }
    let mut data = Vec::with_capacity(rows * cols);
    for r in 0..rows {
        for c in 0..cols {
            data.push(a.whole_get(r, c).cloned().unwrap_or(Value::Blank));
        }
    }
    Rc::new(Array::new(rows, cols, data))
}

pub(super) fn default_value(ty: Option<&Ty>) -> Value {
    match ty {
        Some(Ty::Whole(_) | Ty::Number(_)) => Value::Number(0.0),
        Some(Ty::String) => Value::text(""),
        // A fixed-length String starts as its length of Chr(0).
        Some(Ty::FixedString(n)) => Value::text("\0".repeat(*n as usize)),
        Some(Ty::Boolean) => Value::Bool(false),
        _ => Value::Blank,
    }
}

/// VBA's run-time error 94, for Null where a value is needed ("Invalid use of Null (Error 94)").
pub const INVALID_USE_OF_NULL: &str = "Invalid use of Null (run-time error 94)";

/// What a typed variable makes of an assigned value (VBA's implicit conversions).
pub(super) fn convert(var: Var, ty: Option<&Ty>, name: &str) -> Result<Var, String> {
    let Some(ty) = ty.filter(|t| !matches!(t, Ty::Variant | Ty::Object)) else { return Ok(var) };
    if let Ty::Record(i) = ty {
        return match var {
            Var::Record(j, fields) if j == *i => Ok(Var::Record(j, fields)),
            _ => Err(format!("{name} holds a Type value; only a value of the same Type can be assigned to it")),
        };
    }
    if let Var::Record(..) = var {
        return Err(format!("{name} cannot hold a Type value (type mismatch)"));
    }
    let Var::Value(v) = var else {
        return Err(format!("{name} is declared with a type and cannot hold an object or an array"));
    };
    if let Value::Null = v {
        return Err(format!("{name} cannot hold Null: {INVALID_USE_OF_NULL}"));
    }
    let mismatch = |e: XlError| format!("{name} cannot hold {e} (type mismatch)");
    let text_mismatch = |v: &Value| format!("{name} cannot hold \"{}\" (type mismatch)", print_text(v));
    Ok(Var::Value(match ty {
        // A VBA Date counts days as the 1900 system does, whatever the workbook's.
        // A String read as VBA reads it (`"&H10"` is 16, `"1d2"` 100).
        Ty::Whole(code) => match (&v, vba_number(&v)) {
            (_, Ok(n)) => Value::Number(in_range(n.round_ties_even(), *code, name)?),
            (Value::Text(_), Err(_)) => return Err(text_mismatch(&v)),
            (_, Err(e)) => return Err(mismatch(e)),
        },
        Ty::Number(code) => match (&v, vba_number(&v)) {
            (_, Ok(n)) => Value::Number(in_number_type(n, *code, name)?),
            (Value::Text(_), Err(_)) => return Err(text_mismatch(&v)),
            (_, Err(e)) => return Err(mismatch(e)),
        },
        Ty::String => Value::Text(vba_text(&v).map_err(mismatch)?),
        Ty::FixedString(n) => Value::text(fixed_length(&vba_text(&v).map_err(mismatch)?, *n as usize)),
        Ty::Boolean => match (&v, crate::eval::functions::vba::vba_bool(&v)) {
            (_, Ok(b)) => Value::Bool(b),
            (Value::Text(_), Err(_)) => return Err(text_mismatch(&v)),
            (_, Err(e)) => return Err(mismatch(e)),
        },
        Ty::Variant | Ty::Object | Ty::Record(_) => v,
    }))
}

/// A text as a `String * n` holds it ([MS-VBAL] 5.5.1.2, Let-coercion to String * length):
/// its first `n` characters, or it padded on the right with spaces to `n`.
fn fixed_length(text: &str, n: usize) -> String {
    let mut fixed: String = text.chars().take(n).collect();
    let short = n - fixed.chars().count();
    fixed.extend(std::iter::repeat_n(' ', short));
    fixed
}

/// A number as a variable of VarType `code` holds it: a Single (4) rounded to a 32-bit
/// float ("Single data type"), a Currency (6) to four places, halves to even ("Currency data
/// type": a 64-bit integer of ten-thousandths), or VBA's run-time error 6, Overflow, past
/// the type's range; any other as it is.
fn in_number_type(n: f64, code: u8, name: &str) -> Result<f64, String> {
    // 2^63 / 10^4, the first ten-thousandth past a Currency.
    const CURRENCY_END: f64 = 9_223_372_036_854_775_808.0 / 10_000.0;
    let (fitted, ty) = match code {
        4 => (f64::from(n as f32), "a Single (-3.402823E38 to 3.402823E38)"),
        6 => (
            (n * 10_000.0).round_ties_even() / 10_000.0,
            "a Currency (-922,337,203,685,477.5808 to 922,337,203,685,477.5807)",
        ),
        _ => return Ok(n),
    };
    let fits = if code == 4 { fitted.is_finite() } else { (-CURRENCY_END..CURRENCY_END).contains(&fitted) };
    if fits || !n.is_finite() {
        return Ok(fitted);
    }
    Err(format!("{name}: {} does not fit in {ty}: overflow (run-time error 6)", print_text(&Value::Number(n))))
}

/// A whole number as a variable of VarType `code` holds it, or VBA's run-time error 6,
/// Overflow, past the type's range ("Data type summary": Integer -32,768 to 32,767, Long
/// -2,147,483,648 to 2,147,483,647, Byte 0 to 255).
fn in_range(n: f64, code: u8, name: &str) -> Result<f64, String> {
    let (low, high, ty) = match code {
        2 => (-32768.0, 32767.0, "Integer"),
        3 => (-2147483648.0, 2147483647.0, "Long"),
        17 => (0.0, 255.0, "Byte"),
        _ => (-super::ast::LONG_LONG_END, super::ast::LONG_LONG_END, "LongLong"),
    };
    if (low..=high).contains(&n) && n != super::ast::LONG_LONG_END {
        return Ok(n);
    }
    Err(format!(
        "{name}: {} does not fit in {ty} ({low} to {high}): overflow (run-time error 6)",
        print_text(&Value::Number(n))
    ))
}

/// How `Debug.Print` shows a value: as a cell shows it, booleans in VBA's spelling.
pub fn print_text(v: &Value) -> String {
    match v {
        Value::Bool(b) => if *b { "True" } else { "False" }.to_string(),
        Value::Number(n) => crate::eval::functions::vba::vba_number_shown(*n, false),
        other => other.to_string(),
    }
}

/// A Date's calendar day (`None` for day 0, 1899-12-30: a time alone) and its second of
/// the day (`None` at midnight). VBA counts days from 1899-12-30 on both sides of 1900 (no
/// 1900-02-29), and a negative date's time runs forward from its day ([MS-VBAL] 2.1.1.1
/// "Date": the fractional part's absolute value is the time of day).
/// A serial's day and its seconds past midnight; no day outside the days a Date holds.
fn date_parts(serial: f64) -> (Option<chrono::NaiveDate>, Option<u32>) {
    let mut days = serial.trunc();
    let mut seconds = ((serial - days).abs() * 86400.0).round() as u32;
    if seconds == 86400 {
        seconds = 0;
        days += serial.signum();
    }
    let base = chrono::NaiveDate::from_ymd_opt(1899, 12, 30).expect("VBA's day 0");
    let in_range = days != 0.0 && crate::eval::dates::VBA_DATE_RANGE.contains(&days);
    let date = in_range.then(|| base.checked_add_signed(chrono::Duration::days(days as i64))).flatten();
    (date, (seconds != 0).then_some(seconds))
}

/// A Date as VBA makes it a String in the en-US locale ("Print # statement": the short date
/// format, the time in the long time format; "when either the date or the time component is
/// missing or zero, only the part provided" is there): `1/2/2024`, `12:30:00 PM`,
/// `1/2/2024 12:30:00 PM`; midnight of day 0 is `12:00:00 AM`.
pub fn date_text(serial: f64) -> String {
    use chrono::Datelike;
    // Only arithmetic past a Date's range makes one (CDate refuses it): shown as its number,
    // where chrono panicked on a day past its own range (`CDate(1E+308)`).
    if !crate::eval::dates::VBA_DATE_RANGE.contains(&serial) {
        return crate::eval::format::number_format::general(serial);
    }
    let time = |s: u32| {
        let (h, m, sec) = (s / 3600, s / 60 % 60, s % 60);
        let twelve = if h % 12 == 0 { 12 } else { h % 12 };
        format!("{twelve}:{m:02}:{sec:02} {}", if h < 12 { "AM" } else { "PM" })
    };
    match date_parts(serial) {
        (Some(d), None) => format!("{}/{}/{}", d.month(), d.day(), d.year()),
        (Some(d), Some(s)) => format!("{}/{}/{} {}", d.month(), d.day(), d.year(), time(s)),
        (None, Some(s)) => time(s),
        (None, None) => time(0),
    }
}

/// A Date as `Write #` writes it ("Write # statement": the universal format
/// `#yyyy-mm-dd hh:mm:ss#`, hours 0 to 23, only the part that is there).
pub fn universal_date_text(serial: f64) -> String {
    if !crate::eval::dates::VBA_DATE_RANGE.contains(&serial) {
        return format!("#{}#", crate::eval::format::number_format::general(serial));
    }
    let time = |s: u32| format!("{:02}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
    match date_parts(serial) {
        (Some(d), None) => format!("#{}#", d.format("%Y-%m-%d")),
        (Some(d), Some(s)) => format!("#{} {}#", d.format("%Y-%m-%d"), time(s)),
        (None, Some(s)) => format!("#{}#", time(s)),
        (None, None) => format!("#{}#", time(0)),
    }
}

/// What to type into a cell for a value (VBA's Range.Value = v).
pub fn input_text(v: &Value) -> String {
    match v {
        Value::Blank => String::new(),
        Value::Number(n) => crate::formula::print::number_literal(*n),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.to_string(),
        Value::Text(t) => t.to_string(),
        Value::Error(e) => e.as_str().to_string(),
        Value::Lambda(_) => XlError::Calc.as_str().to_string(),
        // A cell holds no Null: the cell is left empty.
        Value::Null => String::new(),
        Value::Array(a) => a.data.first().map(input_text).unwrap_or_default(),
    }
}
