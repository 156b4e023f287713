//! .NET's `System.Collections.ArrayList` as a macro reaches it through
//! `CreateObject("System.Collections.ArrayList")`: ncsheet makes it itself (no .NET library is
//! loaded), a list of items by 0-based position kept in the same [`Store`] as a Collection.
//! Its members follow Microsoft's .NET reference ("ArrayList Class"): Add returns the new
//! item's index, Item is the default member, IndexOf gives -1 for an item not there, Sort
//! orders by the items' own comparison (`Comparer.Default`) and fails on items of different
//! types, Capacity grows as .NET's does. The exceptions reach VBA through COM as their
//! HRESULTs, which `Err.Number` reads as negative Longs.

use std::cmp::Ordering;

use crate::eval::{Array, Value};
use crate::formula::ast::Expr;

use super::ast::{Link, Span};
use super::collections::{Entry, Handle, Store};
use super::interp::{Fault, Interp, Run};
use super::objects::lower;
use super::typing::Declared;
use super::value::{Obj, Var};

/// ArgumentOutOfRangeException's HRESULT, COR_E_ARGUMENTOUTOFRANGE (0x80131502): an index
/// past the items, a Capacity below Count.
const OUT_OF_RANGE: i32 = 0x8013_1502_u32 as i32;
const OUT_OF_RANGE_TEXT: &str =
    "Index was out of range. Must be non-negative and less than the size of the collection.";
/// InvalidOperationException's HRESULT, COR_E_INVALIDOPERATION (0x80131509): Sort of items
/// of different types.
const CANNOT_COMPARE: i32 = 0x8013_1509_u32 as i32;
const CANNOT_COMPARE_TEXT: &str = "Failed to compare two elements in the array.";

/// The Capacity a new ArrayList's first item grows it to ("ArrayList.Capacity": the
/// capacity doubles as needed, from this default).
const DEFAULT_CAPACITY: usize = 4;

/// What an item is as .NET sees it after COM converted it: the type decides equality (an
/// Integer 1 is not a Long 1 nor a Double 1: `Object.Equals`) and whether two items compare.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Boxed<'a> {
    /// Empty: `null`, equal to itself and before everything in a sort.
    Null,
    Number(f64, Declared),
    Text(&'a str),
    Bool(bool),
    /// An object: equal only to itself, never compared.
    Object,
}

fn boxed<'a>(item: &'a Var, held: Declared) -> Boxed<'a> {
    match item {
        Var::Value(v) | Var::Obj(Obj::Value(v)) => match v {
            Value::Blank => Boxed::Null,
            // A Variant's number is a Double unless its type was followed.
            Value::Number(n) if held == Declared::Variant => Boxed::Number(*n, Declared::Double),
            Value::Number(n) => Boxed::Number(*n, held),
            Value::Text(t) => Boxed::Text(t),
            Value::Bool(b) => Boxed::Bool(*b),
            _ => Boxed::Object,
        },
        _ => Boxed::Object,
    }
}

/// `Object.Equals` of two items: the same type and value; objects only the same object.
fn equals(a: (&Var, Declared), b: (&Var, Declared)) -> bool {
    match (boxed(a.0, a.1), boxed(b.0, b.1)) {
        (Boxed::Object, Boxed::Object) => same_object(a.0, b.0),
        (x, y) => x == y,
    }
}

fn same_object(a: &Var, b: &Var) -> bool {
    match (a, b) {
        (Var::Obj(Obj::Store(x)), Var::Obj(Obj::Store(y))) => x == y,
        _ => false,
    }
}

/// The type a sort compares an item as, `None` for Empty, which compares with every type.
fn sort_type(item: &Boxed) -> Option<&'static str> {
    match item {
        Boxed::Null => None,
        Boxed::Number(..) => Some("number"),
        Boxed::Text(_) => Some("text"),
        Boxed::Bool(_) => Some("bool"),
        Boxed::Object => Some("object"),
    }
}

/// `Comparer.Default.Compare` of two items of one type (checked before): null first, numbers
/// by value, texts in the culture's order (case ignored, then lowercase first: the order
/// Excel's sort with MatchCase uses), False before True.
fn compare(a: &Boxed, b: &Boxed) -> Ordering {
    match (a, b) {
        (Boxed::Null, Boxed::Null) => Ordering::Equal,
        (Boxed::Null, _) => Ordering::Less,
        (_, Boxed::Null) => Ordering::Greater,
        (Boxed::Number(x, _), Boxed::Number(y, _)) => x.total_cmp(y),
        (Boxed::Text(x), Boxed::Text(y)) => {
            super::sort::ascending(&Value::Text((*x).into()), &Value::Text((*y).into()), true)
        }
        (Boxed::Bool(x), Boxed::Bool(y)) => x.cmp(y),
        _ => Ordering::Equal,
    }
}

/// Whether Sort can compare every pair of the items: one type among those not Empty, and a
/// number's type the same throughout (`Int16.CompareTo` refuses a Double), no objects.
fn comparable(items: &[Entry]) -> bool {
    let kinds: Vec<Boxed> = items.iter().map(|(_, item, held)| boxed(item, *held)).collect();
    let mut typed = kinds.iter().filter(|b| sort_type(b).is_some());
    let Some(first) = typed.next() else { return true };
    let same = |b: &Boxed| match (first, b) {
        (Boxed::Number(_, t), Boxed::Number(_, u)) => t == u,
        (Boxed::Object, _) => false,
        (x, y) => sort_type(x) == sort_type(y),
    };
    !matches!(first, Boxed::Object) && typed.all(same)
}

/// The Capacity after growing to hold `needed` items (.NET's EnsureCapacity: double, from 4).
fn grown(capacity: usize, needed: usize) -> usize {
    if needed <= capacity {
        return capacity;
    }
    let doubled = if capacity == 0 { DEFAULT_CAPACITY } else { capacity * 2 };
    doubled.max(needed)
}

impl Store {
    /// The items in order with their types, and each one's place.
    fn typed_items(&self) -> impl Iterator<Item = (&Var, Declared)> {
        self.live().map(|(_, item, held)| (item, *held))
    }

    /// The 0-based position of the first item from `start` (at most `count` items) equal to
    /// `wanted`, as IndexOf and Contains look.
    fn position_of_item(&self, wanted: (&Var, Declared), start: usize, count: usize) -> Option<usize> {
        self.typed_items().enumerate().skip(start).take(count).find(|(_, item)| equals(*item, wanted)).map(|(n, _)| n)
    }
}

impl Interp<'_, '_> {
    /// A .NET exception as VBA reports it: its HRESULT for `Err.Number`, and its message.
    fn dotnet_fault(&self, span: Span, hresult: i32, text: &str, what: &str) -> Fault {
        let mut fault =
            self.fault_at(span, format!("{what}: {text} (run-time error {hresult} ({:08X}))", hresult as u32));
        fault.code = hresult as u32;
        fault
    }

    fn out_of_range(&self, span: Span, what: &str) -> Fault {
        self.dotnet_fault(span, OUT_OF_RANGE, OUT_OF_RANGE_TEXT, what)
    }

    /// An index argument as .NET's Int32 receives it from COM: rounded to even.
    fn list_index(&self, e: &Expr, what: &str) -> Run<i64> {
        let v = self.eval(e)?;
        let n = self.number_of(&v, what).map_err(|m| self.fault_at(self.expr_span(e), m))?;
        Ok(n.round_ties_even() as i64)
    }

    /// The place in the store of the item at 0-based `index` (an index past the items is
    /// ArgumentOutOfRangeException).
    pub(super) fn array_list_place(&self, h: &Handle, index: &Value, span: Span) -> Run<usize> {
        let n = self.number_of(index, "the index").map_err(|m| self.fault_at(span, m))?.round_ties_even();
        let count = h.0.borrow().len();
        if n < 0.0 || n >= count as f64 {
            return Err(self.out_of_range(span, &format!("index {n} of an ArrayList of {count}")));
        }
        Ok(h.0.borrow().place_of(n as usize))
    }

    /// An item argument with the type its number has.
    fn typed_item(&self, e: &Expr) -> Run<(Var, Declared)> {
        let item = self.item_var(e)?;
        let held = self.item_held(e, &item);
        Ok((item, held))
    }

    /// Adds `item` at 0-based `at` (the end when `at` is the count), growing the Capacity.
    fn list_insert(&self, h: &Handle, at: usize, (item, held): (Var, Declared), span: Span) -> Run<()> {
        self.charge(64 + super::budget::brought(&item), span)?;
        let mut store = h.0.borrow_mut();
        let count = store.len();
        store.capacity = grown(store.capacity, count + 1);
        let moved = store.insert(at, None, item);
        let place = store.place_of(at);
        store.set_held(place, held);
        drop(store);
        self.count_moved(moved);
        Ok(())
    }

    /// A member of an ArrayList ("ArrayList Class": its methods and properties).
    pub(super) fn array_list_member(&self, h: &Handle, link: &Link) -> Run<Obj> {
        let blank = Ok(Obj::Value(Value::Blank));
        let count = h.0.borrow().len();
        match lower(link).as_str() {
            "count" => Ok(Obj::Value(Value::Number(count as f64))),
            "capacity" => Ok(Obj::Value(Value::Number(h.0.borrow().capacity as f64))),
            "add" => {
                let args = self.member_args(link, &["value"])?;
                let item = self.typed_item(self.required(args[0], link, "value")?)?;
                self.list_insert(h, count, item, link.span)?;
                Ok(Obj::Value(Value::Number(count as f64)))
            }
            "item" => {
                let args = self.member_args(link, &["index"])?;
                let index = self.eval(self.required(args[0], link, "index")?)?;
                self.store_item(h, &super::collections::Key::plain(index), link.span).map(super::collections::var_obj)
            }
            "insert" => {
                let args = self.member_args(link, &["index", "value"])?;
                let at = self.list_index(self.required(args[0], link, "index")?, "Insert's index")?;
                let item = self.typed_item(self.required(args[1], link, "value")?)?;
                if at < 0 || at > count as i64 {
                    return Err(self.out_of_range(link.span, &format!("Insert at {at} in an ArrayList of {count}")));
                }
                self.list_insert(h, at as usize, item, link.span)?;
                blank
            }
            "contains" => {
                let args = self.member_args(link, &["item"])?;
                let (item, held) = self.typed_item(self.required(args[0], link, "item")?)?;
                let found = h.0.borrow().position_of_item((&item, held), 0, count).is_some();
                Ok(Obj::Value(Value::Bool(found)))
            }
            "indexof" => self.index_of(h, link, count),
            "remove" => {
                let args = self.member_args(link, &["obj"])?;
                let (item, held) = self.typed_item(self.required(args[0], link, "obj")?)?;
                let at = h.0.borrow().position_of_item((&item, held), 0, count);
                // "ArrayList.Remove": an item not there leaves the list as it is, no error.
                if let Some(n) = at {
                    self.remove_at(h, n)?;
                }
                blank
            }
            "removeat" => {
                let args = self.member_args(link, &["index"])?;
                let at = self.list_index(self.required(args[0], link, "index")?, "RemoveAt's index")?;
                if at < 0 || at >= count as i64 {
                    return Err(self.out_of_range(link.span, &format!("RemoveAt {at} of an ArrayList of {count}")));
                }
                self.remove_at(h, at as usize)?;
                blank
            }
            "clear" => {
                self.member_args(link, &[])?;
                // "ArrayList.Clear": Count becomes 0, Capacity stays.
                let removed = h.0.borrow_mut().take_items();
                self.release_all(removed)?;
                blank
            }
            "reverse" => {
                self.member_args(link, &[])?;
                self.reorder(h, |entries| entries.reverse());
                blank
            }
            "sort" => {
                self.member_args(link, &[])?;
                if !comparable(&h.0.borrow().live().cloned().collect::<Vec<_>>()) {
                    return Err(self.dotnet_fault(link.span, CANNOT_COMPARE, CANNOT_COMPARE_TEXT, "Sort"));
                }
                self.reorder(h, |entries| {
                    entries.sort_by(|a, b| compare(&boxed(&a.1, a.2), &boxed(&b.1, b.2)));
                });
                blank
            }
            "toarray" => self.list_to_array(h, link),
            "trimtosize" => {
                self.member_args(link, &[])?;
                h.0.borrow_mut().capacity = count;
                blank
            }
            _ => Err(self.no_member(&Obj::Store(h.clone()), link)),
        }
    }

    /// `IndexOf(value[, startIndex[, count]])`: the 0-based index of the first equal item from
    /// startIndex, -1 when none; a start or count past the items is ArgumentOutOfRangeException.
    fn index_of(&self, h: &Handle, link: &Link, count: usize) -> Run<Obj> {
        let args = self.member_args(link, &["value", "startIndex", "count"])?;
        let (item, held) = self.typed_item(self.required(args[0], link, "value")?)?;
        let start = match args[1] {
            Some(e) => self.list_index(e, "IndexOf's startIndex")?,
            None => 0,
        };
        let span = match args[2] {
            Some(e) => self.list_index(e, "IndexOf's count")?,
            None => count as i64 - start,
        };
        if start < 0 || start > count as i64 || span < 0 || start + span > count as i64 {
            return Err(self.out_of_range(link.span, &format!("IndexOf from {start} in an ArrayList of {count}")));
        }
        let found = h.0.borrow().position_of_item((&item, held), start as usize, span as usize);
        Ok(Obj::Value(Value::Number(found.map_or(-1.0, |n| n as f64))))
    }

    fn remove_at(&self, h: &Handle, n: usize) -> Run<()> {
        let removed = {
            let mut store = h.0.borrow_mut();
            let place = store.place_of(n);
            store.remove(place)
        };
        self.release_all(removed.into_iter().collect())
    }

    /// The entries put back in the order `change` leaves them in.
    fn reorder(&self, h: &Handle, change: impl FnOnce(&mut Vec<Entry>)) {
        let mut store = h.0.borrow_mut();
        let capacity = store.capacity;
        let mut entries = store.take_entries();
        change(&mut entries);
        for (key, item, held) in entries {
            store.push(key, item);
            let place = store.len() - 1;
            store.set_held(place, held);
        }
        store.capacity = capacity;
    }

    /// `ToArray()`: the items as a zero-based Variant array ("ArrayList.ToArray": an Object
    /// array, which COM hands VBA as a Variant()). An object item is refused by name: a
    /// ncsheet array holds values.
    fn list_to_array(&self, h: &Handle, link: &Link) -> Run<Obj> {
        self.member_args(link, &[])?;
        let store = h.0.borrow();
        let mut values = Vec::with_capacity(store.len());
        for (item, _) in store.typed_items() {
            match item {
                Var::Value(v) | Var::Obj(Obj::Value(v)) => values.push(v.clone()),
                Var::Array(a) => values.push(Value::Array(a.data.clone())),
                other => {
                    return Err(self.unsupported(
                        link.span,
                        format!(
                            "ToArray: the ArrayList holds {}, which a ncsheet array cannot hold (its items are \
                             values); read the objects by index instead",
                            describe(other)
                        ),
                    ))
                }
            }
        }
        Ok(Obj::Value(Value::from(Array::row(values))))
    }

    /// `list.Capacity = n` ("ArrayList.Capacity": below Count is ArgumentOutOfRangeException;
    /// 0 gives the default capacity).
    pub(super) fn set_capacity(&self, h: &Handle, link: &Link, value: &Expr) -> Run<()> {
        let n = self.list_index(value, "Capacity")?;
        let count = h.0.borrow().len();
        if n < count as i64 {
            return Err(self.out_of_range(link.span, &format!("Capacity {n} below the Count {count}")));
        }
        let mut store = h.0.borrow_mut();
        if n as usize != store.capacity {
            store.capacity = if n == 0 { DEFAULT_CAPACITY } else { n as usize };
        }
        Ok(())
    }
}

fn describe(var: &Var) -> &'static str {
    match var {
        Var::Obj(o) => o.describe(),
        _ => "a Type value",
    }
}

#[cfg(test)]
mod tests {
    use super::grown;

    /// .NET's growth: 0, then 4, then doubling (ArrayList.EnsureCapacity).
    #[test]
    fn capacity_grows_from_four_by_doubling() {
        let mut capacity = 0;
        let seen: Vec<usize> = (1..=9)
            .map(|n| {
                capacity = grown(capacity, n);
                capacity
            })
            .collect();
        assert_eq!(seen, [4, 4, 4, 4, 8, 8, 8, 8, 16]);
    }
}
