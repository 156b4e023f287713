//! VBA's `Collection` (`New Collection`) and Scripting's `Dictionary`
//! (`CreateObject("Scripting.Dictionary")`, `New Dictionary`): reference objects a macro
//! keeps values in by position or key. Their members follow Microsoft's VBA reference
//! ("Collection object", "Dictionary object") and raise its run-time errors: 457 for a key
//! already there, 5 for a missing Collection key, 9 for an index past the items, 32811 for
//! a Dictionary's Remove of a missing key.

use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use crate::eval::functions::vba::{errors, vba_text};
use crate::eval::{Array, Ctx, Operand, Value};

use crate::formula::ast::{Expr, ExprKind};

use super::ast::{Arg, Class, Link, Node, Span};
use super::interp::{Fault, Interp, Run};
use super::objects::lower;
use super::typing::Declared;
use super::value::{Obj, VArray, Var};

/// Where a Collection's, a Dictionary's or an object's item goes, as a refusal names it.
pub(super) const STORE_ITEM: &str = "an item of a Collection, a Dictionary or an object";

/// "Trappable errors": the numbers and texts VBA raises for these objects.
const DUPLICATE_KEY: (u32, &str) = (457, errors::description(457));
const INVALID_CALL: (u32, &str) = (5, errors::description(5));
const OUT_OF_RANGE: (u32, &str) = (9, errors::description(9));
const NO_SUCH_KEY: (u32, &str) = (32811, "Method 'Remove' of object 'IDictionary' failed: the key is not there");
const NO_KEY_TO_CHANGE: (u32, &str) = (32811, "Method 'Key' of object 'IDictionary' failed: the key is not there");

/// What one entry costs the memory budget besides its key's text and its item.
const ENTRY_BYTES: u64 = 64;

/// A key as compared: text in lower case when the comparison ignores case; a number (a
/// Boolean's too, True being -1) as the Single nearest to it. Scripting compares numeric keys
/// of any type by value after converting both to Single (Wine's scrrun `numeric_key_eq`; its
/// `get_HashVal` hashes the key as a FLOAT, which Wine's tests check against Windows' DLL:
/// the Integer 0 and the Single 0 are one key, the Long 2175 is the Single 2175's key), so
/// Doubles closer than a Single tells apart are one key. A number past the Single's range
/// keeps its Double.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum KeyForm {
    Text(String),
    Single(u32),
    Wide(u64),
    Blank,
    Null,
}

/// The form of a number key (see [`KeyForm`]); -0 is 0.
fn number_form(n: f64) -> KeyForm {
    let single = n as f32;
    if single.is_finite() {
        KeyForm::Single((single + 0.0).to_bits())
    } else {
        KeyForm::Wide((n + 0.0).to_bits())
    }
}

/// The forms an Empty key matches besides its own, or that match an Empty key: Scripting's
/// Empty matches "the zero/default value of the other key's type: any numeric zero, the
/// empty string, or another Empty" (Wine's scrrun `empty_matches_key`; Windows hashes Empty,
/// 0 and "" alike, to 0, in Wine's `test_hash_value`).
fn empty_alike(form: &KeyForm) -> Vec<KeyForm> {
    match form {
        KeyForm::Blank => vec![KeyForm::Single(0), KeyForm::Text(String::new())],
        KeyForm::Single(0) => vec![KeyForm::Blank],
        KeyForm::Text(t) if t.is_empty() => vec![KeyForm::Blank],
        _ => Vec::new(),
    }
}

/// A key as the macro gave it: its value and the type its number has, which Scripting keeps
/// (the key is the VARIANT given: `Keys` gives an Integer key back as an Integer, a Date as
/// a Date; Wine's `test_Keys` checks VT_R4 and VT_I4 against Windows).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Key {
    pub value: Value,
    pub held: Declared,
}

impl Key {
    /// A key whose type says nothing past its value (a Collection's text, an index).
    pub(super) fn plain(value: Value) -> Key {
        Key { value, held: Declared::Variant }
    }
}

/// One entry: its key (a Collection's item may have none), its item, and the type the item's
/// number has, which a Variant item keeps ([MS-VBAL] 2.1.1.1: a Date, VarType 7; an Integer
/// 5, VarType 2); `Variant` for any other item.
pub(super) type Entry = (Option<Key>, Var, Declared);

/// The entries of a Collection or a Dictionary, in the order added.
#[derive(Debug)]
pub struct Store {
    pub class: Class,
    /// A Dictionary's CompareMode is vbTextCompare (a Collection's keys always ignore case).
    text_compare: bool,
    /// The entries in order; `None` is a removed entry's place, left until half the places
    /// are such (removing one entry at a time would otherwise move and re-index all the
    /// later ones each time: emptying a Collection with `Remove 1` would be quadratic).
    entries: Vec<Option<Entry>>,
    /// Removed places among `entries`.
    gone: usize,
    /// Each key's place in `entries`.
    index: HashMap<KeyForm, usize>,
    /// Which places hold an entry, counted so that a Collection's 1-based position and a
    /// place convert into each other in logarithmic time.
    live: LiveCounts,
    /// An ArrayList's Capacity: the items its .NET array has room for (`array_list.rs`).
    pub(super) capacity: usize,
}

/// Objects held in items are let go one after another, not each inside the one holding it:
/// a chain of a million Collections each holding the next does not take the native stack.
impl Drop for Store {
    fn drop(&mut self) {
        let items = self.entries.drain(..).flatten().map(|(_, item, _)| item).collect();
        super::classes::let_go(items);
    }
}

/// A Fenwick tree over the places of `Store::entries`, 1 where an entry is: how many entries
/// lie before a place, and the place of the n-th entry, each in O(log n).
#[derive(Debug, Default)]
struct LiveCounts {
    /// `tree[i]` (1-based) counts the entries among places `i - lowbit(i) .. i`; `tree[0]` is unused.
    tree: Vec<u32>,
}

fn lowbit(i: usize) -> usize {
    i & i.wrapping_neg()
}

impl LiveCounts {
    /// The counts for places that all hold an entry, built in O(n).
    fn full(places: usize) -> LiveCounts {
        let mut tree = vec![1u32; places + 1];
        tree[0] = 0;
        for i in 1..=places {
            let parent = i + lowbit(i);
            if parent <= places {
                tree[parent] += tree[i];
            }
        }
        LiveCounts { tree }
    }

    fn places(&self) -> usize {
        self.tree.len().saturating_sub(1)
    }

    /// A new place at the end holding an entry.
    fn push(&mut self) {
        if self.tree.is_empty() {
            self.tree.push(0);
        }
        let i = self.tree.len();
        // The new node covers places i - lowbit(i) + 1 ..= i: the one added and those before it.
        let covered = self.before(i - 1) - self.before(i - lowbit(i));
        self.tree.push(1 + covered as u32);
    }

    /// The place `at` (0-based) no longer holds an entry.
    fn take(&mut self, at: usize) {
        let mut i = at + 1;
        while i <= self.places() {
            self.tree[i] -= 1;
            i += lowbit(i);
        }
    }

    /// How many entries lie in the first `places` places.
    fn before(&self, places: usize) -> usize {
        let mut i = places;
        let mut n = 0;
        while i > 0 {
            n += self.tree[i] as usize;
            i -= lowbit(i);
        }
        n
    }

    /// The place (0-based) of the entry at 0-based position `n` (there must be more than n).
    fn nth(&self, n: usize) -> usize {
        let places = self.places();
        let mut at = 0;
        let mut left = n + 1;
        let mut step = if places == 0 { 0 } else { 1 << places.ilog2() };
        while step > 0 {
            if at + step <= places && (self.tree[at + step] as usize) < left {
                at += step;
                left -= self.tree[at] as usize;
            }
            step >>= 1;
        }
        at
    }
}

/// A shared Collection or Dictionary: `Set d2 = d` makes two names for one object.
#[derive(Clone, Debug)]
pub struct Handle(pub Rc<RefCell<Store>>);

impl PartialEq for Handle {
    fn eq(&self, other: &Handle) -> bool {
        Rc::ptr_eq(&self.0, &other.0)
    }
}

impl Handle {
    pub fn new(class: Class) -> Handle {
        let store = Store {
            class,
            text_compare: false,
            entries: Vec::new(),
            gone: 0,
            index: HashMap::new(),
            live: LiveCounts::default(),
            capacity: 0,
        };
        Handle(Rc::new(RefCell::new(store)))
    }

    pub fn class(&self) -> Class {
        self.0.borrow().class
    }

    /// What For Each goes through: a Collection's items, a Dictionary's keys.
    pub fn each(&self) -> Vec<Var> {
        let store = self.0.borrow();
        match store.class {
            Class::Collection | Class::ArrayList => store.live().map(|(_, item, _)| item.clone()).collect(),
            Class::Dictionary => store.live().map(|(k, _, _)| Var::Value(key_value(k))).collect(),
        }
    }

    /// The type of the number each of [`Handle::each`]'s items holds (a Date, the Integer of
    /// `c.Add 5`, a Dictionary's Integer key).
    pub(super) fn each_held(&self) -> Vec<Declared> {
        let store = self.0.borrow();
        match store.class {
            Class::Collection | Class::ArrayList => store.live().map(|e| e.2).collect(),
            Class::Dictionary => {
                store.live().map(|(k, _, _)| k.as_ref().map_or(Declared::Variant, |k| k.held)).collect()
            }
        }
    }

    /// A Dictionary's `Keys` (or `Items`) as a macro's variable receives it: zero-based, each
    /// item keeping the type its number has ("Keys method": "returns an array").
    pub(super) fn listing(&self, keys: bool) -> VArray {
        let store = self.0.borrow();
        let (values, held): (Vec<Value>, Vec<Declared>) = store
            .live()
            .map(|(k, item, held)| match keys {
                true => (key_value(k), k.as_ref().map_or(Declared::Variant, |k| k.held)),
                false => (var_value(item), *held),
            })
            .unzip();
        let mut array = VArray::row(Rc::new(Array::row(values)), 0);
        for (k, held) in held.into_iter().enumerate() {
            array.mark_held(k, held);
        }
        array
    }

    /// Entry `n` (0-based) of a Dictionary's `Keys` (or `Items`) as [`Handle::listing`] lists
    /// it, with the type its number holds; found in O(log n) through the counts of live places,
    /// not by walking the entries before it.
    pub(super) fn listed_one(&self, keys: bool, n: usize) -> Option<(Value, Declared)> {
        let store = self.0.borrow();
        if n >= store.len() {
            return None;
        }
        let (k, item, held) = store.entries[store.place_of(n)].as_ref()?;
        Some(match keys {
            true => (key_value(k), k.as_ref().map_or(Declared::Variant, |k| k.held)),
            false => (var_value(item), *held),
        })
    }

    /// The memory the entries hold besides their items: keys' texts and each entry's share.
    pub fn own_bytes(&self) -> u64 {
        let store = self.0.borrow();
        store.live().map(|(k, _, _)| ENTRY_BYTES + key_bytes(k.as_ref().map(|k| &k.value))).sum()
    }

    pub fn items(&self) -> Vec<Var> {
        self.0.borrow().live().map(|(_, item, _)| item.clone()).collect()
    }
}

/// The value of an entry's key (Empty for a Collection's item added without one).
fn key_value(key: &Option<Key>) -> Value {
    key.as_ref().map_or(Value::Blank, |k| k.value.clone())
}

fn key_bytes(key: Option<&Value>) -> u64 {
    match key {
        Some(Value::Text(t)) => t.len() as u64,
        _ => 0,
    }
}

impl Store {
    /// The items, to change in place (a macro's Range objects following an insert or delete).
    pub(super) fn items_mut(&mut self) -> impl Iterator<Item = &mut Var> {
        self.entries.iter_mut().flatten().map(|(_, item, _)| item)
    }

    fn form(&self, key: &Value) -> Result<KeyForm, String> {
        let ignore_case = self.text_compare || self.class == Class::Collection;
        Ok(match key {
            Value::Text(t) if ignore_case => KeyForm::Text(t.to_lowercase()),
            Value::Text(t) => KeyForm::Text(t.to_string()),
            Value::Number(n) => number_form(*n),
            Value::Bool(b) => number_form(if *b { -1.0 } else { 0.0 }),
            Value::Blank => KeyForm::Blank,
            Value::Null => KeyForm::Null,
            other => return Err(format!("{other} cannot be a key")),
        })
    }

    /// The entries there are, in order.
    pub(super) fn live(&self) -> impl Iterator<Item = &Entry> {
        self.entries.iter().flatten()
    }

    /// How many entries there are (`Count`).
    pub(super) fn len(&self) -> usize {
        self.entries.len() - self.gone
    }

    fn clear(&mut self) {
        self.entries.clear();
        self.index.clear();
        self.gone = 0;
        self.live = LiveCounts::default();
    }

    /// The place of the entry with `key`.
    /// A Dictionary's Empty key and a zero or empty-text key match each other: the first
    /// added of those it matches.
    fn position(&self, key: &Value) -> Result<Option<usize>, String> {
        let form = self.form(key)?;
        let own = self.index.get(&form).copied();
        if self.class != Class::Dictionary {
            return Ok(own);
        }
        Ok(empty_alike(&form).iter().filter_map(|f| self.index.get(f).copied()).chain(own).min())
    }

    /// The place of the entry at 0-based position `n` (`n < len()`).
    pub(super) fn place_of(&self, n: usize) -> usize {
        self.live.nth(n)
    }

    /// The 0-based position of the entry at place `at`.
    fn position_of(&self, at: usize) -> usize {
        self.live.before(at)
    }

    pub(super) fn item(&self, at: usize) -> &Var {
        &self.entries[at].as_ref().expect("a place holding an entry").1
    }

    /// The type of the number the item at place `at` holds.
    pub(super) fn held(&self, at: usize) -> Declared {
        self.entries[at].as_ref().map_or(Declared::Variant, |e| e.2)
    }

    pub(super) fn set_held(&mut self, at: usize, held: Declared) {
        if let Some(entry) = self.entries[at].as_mut() {
            entry.2 = held;
        }
    }

    pub(super) fn item_mut(&mut self, at: usize) -> &mut Var {
        &mut self.entries[at].as_mut().expect("a place holding an entry").1
    }

    /// Closes up the removed places, once: positions and places are the same again.
    fn close_up(&mut self) {
        super::count(&super::PLACES_CLOSED_UP, self.entries.len() as u64);
        self.entries.retain(Option::is_some);
        self.gone = 0;
        let forms: Vec<(KeyForm, usize)> = (self.live().enumerate())
            .filter_map(|(i, (k, _, _))| k.as_ref().and_then(|k| self.form(&k.value).ok()).map(|f| (f, i)))
            .collect();
        self.index = forms.into_iter().collect();
        self.live = LiveCounts::full(self.entries.len());
    }

    /// Adds an entry after the last.
    pub(super) fn push(&mut self, key: Option<Key>, item: Var) {
        if let Some(form) = key.as_ref().and_then(|k| self.form(&k.value).ok()) {
            self.index.insert(form, self.entries.len());
        }
        self.entries.push(Some((key, item, Declared::Variant)));
        self.live.push();
    }

    /// Adds an entry at 0-based position `n`: at the end in constant time, elsewhere moving
    /// the later entries and their keys' places one on (a Collection's Add with Before or
    /// After). Gives back the entries moved, which the caller counts as work
    /// ([`Interp::count_moved`]). The keys are not worked out again: that was 35 % of a
    /// loop of `c.Add x, Before:=1`.
    pub(super) fn insert(&mut self, n: usize, key: Option<Key>, item: Var) -> usize {
        if n >= self.len() {
            self.push(key, item);
            return 0;
        }
        if self.gone > 0 {
            self.close_up();
        }
        // Places and positions are the same now.
        for place in self.index.values_mut().filter(|place| **place >= n) {
            *place += 1;
        }
        if let Some(form) = key.as_ref().and_then(|k| self.form(&k.value).ok()) {
            self.index.insert(form, n);
        }
        self.entries.insert(n, Some((key, item, Declared::Variant)));
        self.live = LiveCounts::full(self.entries.len());
        self.entries.len() - n
    }

    /// Removes the entry at place `at`: its place is kept (no later entry moves) until half
    /// the places are such, then all are closed up at once, so that a removal costs the same
    /// on average however many entries there are.
    pub(super) fn remove(&mut self, at: usize) -> Option<Var> {
        let (key, item, _) = self.entries[at].take()?;
        if let Some(form) = key.as_ref().and_then(|k| self.form(&k.value).ok()) {
            self.index.remove(&form);
        }
        self.gone += 1;
        self.live.take(at);
        if self.gone * 2 > self.entries.len() {
            self.close_up();
        }
        Some(item)
    }

    /// Empties it, giving back the items it held (for their objects' Class_Terminate).
    pub(super) fn take_items(&mut self) -> Vec<Var> {
        self.take_entries().into_iter().map(|(_, item, _)| item).collect()
    }

    /// Empties it, giving back its entries in order.
    pub(super) fn take_entries(&mut self) -> Vec<Entry> {
        let entries = self.entries.drain(..).flatten().collect();
        self.clear();
        entries
    }

    /// `d.Key(old) = new`: the entry at place `at` takes the key `new` and keeps its place.
    fn rename(&mut self, at: usize, new: Key) -> Result<(), String> {
        let form = self.form(&new.value)?;
        let entry = self.entries[at].as_mut().expect("a place holding an entry");
        let old = entry.0.replace(new);
        if let Some(old) = old.and_then(|k| self.form(&k.value).ok()) {
            self.index.remove(&old);
        }
        self.index.insert(form, at);
        Ok(())
    }
}

/// The array Keys and Items give: zero-based, one dimension (the reference's examples).
fn zero_based(values: Vec<Value>) -> Value {
    Value::from(Array::row(values))
}

fn var_value(var: &Var) -> Value {
    match var {
        Var::Value(v) | Var::Obj(Obj::Value(v)) => v.clone(),
        Var::Array(a) => Value::Array(a.data.clone()),
        _ => Value::Blank,
    }
}

pub(super) fn var_obj(var: Var) -> Obj {
    match var {
        Var::Obj(o) => o,
        Var::Array(a) => Obj::Value(Value::Array(a.data)),
        other => Obj::Value(var_value(&other)),
    }
}

impl Interp<'_, '_> {
    pub(super) fn vba_error(&self, span: Span, (code, text): (u32, &str), what: &str) -> Fault {
        let mut fault = self.fault_at(span, format!("{what}: {text} (run-time error {code})"));
        fault.code = code;
        fault
    }

    /// The arguments of a member by position or by name (`Key:="a"`), `None` when left out.
    pub(super) fn member_args<'e>(&self, link: &'e Link, names: &[&str]) -> Run<Vec<Option<&'e Expr>>> {
        let mut out = vec![None; names.len()];
        for (i, Arg { name, value }) in link.args.as_deref().unwrap_or(&[]).iter().enumerate() {
            let at = match name {
                Some(n) => names.iter().position(|p| p.eq_ignore_ascii_case(n)),
                None => (i < names.len()).then_some(i),
            };
            let Some(at) = at else {
                return Err(self.fault_at(
                    link.span,
                    format!("{} takes no argument {}", link.name, name.as_deref().unwrap_or("more")),
                ));
            };
            if value.kind != crate::formula::ast::ExprKind::Missing {
                out[at] = Some(value);
            }
        }
        Ok(out)
    }

    /// What an item argument holds: a value, an array or an object (a Range stays a Range);
    /// a LongLong no double holds refused ([`Interp::refuse_long_long_past_double`]).
    pub(super) fn item_var(&self, e: &Expr) -> Run<Var> {
        let nothing = matches!(e.kind, ExprKind::Host(id) if matches!(self.module.nodes[id as usize], Node::Nothing));
        let var = match self.var_of(e, true)? {
            Var::Obj(Obj::Value(v)) if !nothing => Var::Value(v),
            other => other,
        };
        self.refuse_long_long_past_double(e, &var, STORE_ITEM)?;
        Ok(var)
    }

    pub(super) fn required<'e>(&self, arg: Option<&'e Expr>, link: &Link, what: &str) -> Run<&'e Expr> {
        arg.ok_or_else(|| self.fault_at(link.span, format!("{}: argument {what} is not optional", link.name)))
    }

    /// A member of a Collection or a Dictionary.
    pub(super) fn store_member(&self, _ctx: &mut Ctx, h: Handle, link: &Link) -> Run<Obj> {
        let name = lower(link);
        let class = h.class();
        let blank = Ok(Obj::Value(Value::Blank));
        match (class, name.as_str()) {
            (Class::ArrayList, _) => self.array_list_member(&h, link),
            (_, "count") => Ok(Obj::Value(Value::Number(h.0.borrow().len() as f64))),
            // The hidden enumerator a class's own NewEnum hands on (`Set NewEnum =
            // mItems.[_NewEnum]`): For Each through it goes through the Collection's items (a
            // Dictionary's keys), as For Each through the object itself does.
            (_, "[_newenum]" | "_newenum") => Ok(Obj::Store(h.clone())),
            (Class::Collection, "add") => {
                let args = self.member_args(link, &["Item", "Key", "Before", "After"])?;
                self.collection_add(&h, &args, link)?;
                blank
            }
            (Class::Dictionary, "add") => {
                let args = self.member_args(link, &["Key", "Item"])?;
                let key = self.store_key_value(self.required(args[0], link, "Key")?)?;
                let item_expr = self.required(args[1], link, "Item")?;
                let item = self.item_var(item_expr)?;
                if self.find(&h, &key.value, link.span)?.is_some() {
                    return Err(self.vba_error(link.span, DUPLICATE_KEY, "Add"));
                }
                let held = self.item_held(item_expr, &item);
                let value = key.value.clone();
                self.put(&h, key, item, link.span)?;
                self.mark_store_held(&h, Some(&value), held, link.span)?;
                blank
            }
            (_, "item") => {
                let args = self.member_args(link, &["Index"])?;
                let key = self.store_key_value(self.required(args[0], link, "Index")?)?;
                self.store_item(&h, &key, link.span).map(var_obj)
            }
            (_, "remove") => {
                let args = self.member_args(link, &["Key"])?;
                let key = self.store_key_value(self.required(args[0], link, "Key")?)?.value;
                let at = match class {
                    Class::Collection | Class::ArrayList => self.collection_place(&h, &key, link.span)?,
                    Class::Dictionary => self
                        .find(&h, &key, link.span)?
                        .ok_or_else(|| self.vba_error(link.span, NO_SUCH_KEY, "Remove"))?,
                };
                let removed = h.0.borrow_mut().remove(at);
                // An object only the entry held is let go: its Class_Terminate runs.
                self.release_all(removed.into_iter().collect())?;
                blank
            }
            (Class::Dictionary, "exists") => {
                let args = self.member_args(link, &["Key"])?;
                let key = self.store_key_value(self.required(args[0], link, "Key")?)?;
                Ok(Obj::Value(Value::Bool(self.find(&h, &key.value, link.span)?.is_some())))
            }
            (Class::Dictionary, "keys") => self.listed_or_one(&h, true, link),
            (Class::Dictionary, "items") => self.listed_or_one(&h, false, link),
            (Class::Dictionary, "removeall") => {
                let removed = h.0.borrow_mut().take_items();
                self.release_all(removed)?;
                blank
            }
            (Class::Dictionary, "comparemode") => {
                Ok(Obj::Value(Value::Number(if h.0.borrow().text_compare { 1.0 } else { 0.0 })))
            }
            _ => Err(self.no_member(&Obj::Store(h), link)),
        }
    }

    /// `d.Keys` (or `d.Items`) is the array of them counted from 0; `d.Keys(i)` is its item i:
    /// the method takes no argument, so VBA reads the parentheses as an index into the array it
    /// returns (Microsoft's "Keys method": "returns an array"; `For i = 0 To d.Count - 1:
    /// d.Keys(i)`), an index outside it run-time error 9.
    /// The whole array is counted as work by its items, as a function making an array is
    /// (`k = d.Keys` over 100,000 keys in a loop made 10^10 items counting a statement a turn);
    /// one item picked is read alone, as [`Interp::listed_item`] reads it.
    fn listed_or_one(&self, h: &Handle, keys: bool, link: &Link) -> Run<Obj> {
        let args = self.member_args(link, &["Index"])?;
        let Some(index) = args[0] else {
            self.add_work(h.0.borrow().len() as u64);
            let listed: Vec<Value> = match keys {
                true => h.each().iter().map(var_value).collect(),
                false => h.items().iter().map(var_value).collect(),
            };
            return Ok(Obj::Value(zero_based(listed)));
        };
        self.listed_item(h, keys, index, link.span).map(var_obj)
    }

    /// Item `index` of a Dictionary's zero-based `Keys` (or `Items`), read alone: found in
    /// O(log n) among the entries, where copying the whole list to pick one made
    /// `n = n + d.Items()(i)` over a Dictionary of 100,000 run 15 s before the statement limit
    /// stopped it. An index outside the list is run-time error 9 ("Subscript out of range").
    #[inline(never)]
    pub(super) fn listed_item(&self, h: &Handle, keys: bool, index: &Expr, span: Span) -> Run<Var> {
        let i = self.index(index, "the index")?;
        let Some((one, held)) = usize::try_from(i).ok().and_then(|n| h.listed_one(keys, n)) else {
            let what = if keys { "Keys" } else { "Items" };
            let count = h.0.borrow().len();
            return Err(self.vba_error(span, OUT_OF_RANGE, &format!("{what}()({i}) of a Dictionary of {count}")));
        };
        self.gave.set(held);
        Ok(Var::Value(one))
    }

    /// `k = d.Keys`: the array whose items keep their types (an Integer key reads back as an
    /// Integer), counted as work by its items as [`Interp::listed_or_one`] counts; another
    /// object's `Keys` member as that object gives it.
    pub(super) fn keys_var(&self, path: &super::ast::Path) -> Run<Var> {
        Ok(self.keys_or_item(path, None)?.unwrap_or_else(|whole| whole))
    }

    /// `d.Keys()(i)` (or `d.Items()(i)`) with `pick` the index: a Dictionary's one item
    /// ([`Interp::listed_item`], `Ok`); without `pick`, or for another object's `Keys` member,
    /// the whole array as [`Interp::keys_var`] gives it, for the caller to index (`Err`). The
    /// owner is worked out once either way.
    #[inline(never)]
    pub(super) fn keys_or_item(&self, path: &super::ast::Path, pick: Option<(&Expr, Span)>) -> Run<Result<Var, Var>> {
        let mut ctx = self.ctx();
        let owner = self.path_until(&mut ctx, path, path.links.len() - 1);
        self.take_pending()?;
        let link = path.links.last().expect("a Keys member");
        let keys = link.name.eq_ignore_ascii_case("keys");
        let obj = match owner? {
            Obj::Store(h) if h.class() == Class::Dictionary => {
                if let Some((index, span)) = pick {
                    return self.listed_item(&h, keys, index, span).map(Ok);
                }
                self.add_work(h.0.borrow().len() as u64);
                return Ok(Err(Var::Array(h.listing(keys))));
            }
            other => self.member(&mut ctx, other, link),
        };
        self.take_pending()?;
        Ok(Err(match obj? {
            Obj::Value(Value::Array(a)) => Var::Array(VArray::row(a, 0)),
            Obj::Value(v) => super::value::array_var(v, self.option_base()),
            other => Var::Obj(other),
        }))
    }

    fn find(&self, h: &Handle, key: &Value, span: Span) -> Run<Option<usize>> {
        h.0.borrow().position(key).map_err(|m| self.fault_at(span, m))
    }

    /// Adds an entry at the end, counted against the memory budget.
    fn put(&self, h: &Handle, key: Key, item: Var, span: Span) -> Run<()> {
        self.charge(ENTRY_BYTES + key_bytes(Some(&key.value)) + super::budget::brought(&item), span)?;
        h.0.borrow_mut().push(Some(key), item);
        Ok(())
    }

    /// `c.Add item[, key][, before][, after]` ("Add method (Visual Basic for Applications)").
    fn collection_add(&self, h: &Handle, args: &[Option<&Expr>], link: &Link) -> Run<()> {
        let item_expr = self.required(args[0], link, "Item")?;
        let item = self.item_var(item_expr)?;
        let held = self.item_held(item_expr, &item);
        let key = match args[1] {
            Some(e) => {
                let v = self.eval(e)?;
                let text = vba_text(&v).map_err(|e| self.fault_at(link.span, format!("Add: the key is {e}")))?;
                Some(Key::plain(Value::Text(text)))
            }
            None => None,
        };
        if let Some(k) = &key {
            if self.find(h, &k.value, link.span)?.is_some() {
                return Err(self.vba_error(link.span, DUPLICATE_KEY, "Add"));
            }
        }
        let at = match (args[2], args[3]) {
            (Some(_), Some(_)) => {
                return Err(self.vba_error(link.span, INVALID_CALL, "Add with both Before and After"))
            }
            (Some(e), None) => self.collection_index(h, &self.eval(e)?, link.span)?,
            (None, Some(e)) => self.collection_index(h, &self.eval(e)?, link.span)? + 1,
            (None, None) => h.0.borrow().len(),
        };
        self.charge(
            ENTRY_BYTES + key_bytes(key.as_ref().map(|k| &k.value)) + super::budget::brought(&item),
            link.span,
        )?;
        let mut store = h.0.borrow_mut();
        let last = at >= store.len();
        let moved = store.insert(at, key, item);
        // Added last, it is at the last place; else the places were closed up first.
        let place = if last { store.entries.len() - 1 } else { at };
        store.set_held(place, held);
        self.count_moved(moved);
        Ok(())
    }

    /// Counts the entries an insertion into a Collection or an ArrayList moved against the
    /// statement limit, as an array copy counts its items ([`super::interp::ITEMS_PER_STATEMENT`]
    /// a statement): `c.Add x, Before:=1` moves every entry, and 300,000 of them ran for
    /// minutes counting a statement each.
    pub(super) fn count_moved(&self, entries: usize) {
        let per_unit = super::interp::ITEMS_PER_STATEMENT / super::interp::WORK_PER_STATEMENT;
        self.add_work(entries as u64 / per_unit);
    }

    /// The place of a Collection's entry by 1-based index (error 9 past the items) or by key
    /// (error 5 when no item has it).
    fn collection_place(&self, h: &Handle, key: &Value, span: Span) -> Run<usize> {
        match key {
            Value::Text(_) => {
                self.find(h, key, span)?.ok_or_else(|| self.vba_error(span, INVALID_CALL, "no item has the key"))
            }
            _ => {
                let n = self.collection_number(h, key, span)?;
                Ok(h.0.borrow().place_of(n))
            }
        }
    }

    /// The 0-based position of a Collection's entry by 1-based index or by key.
    fn collection_index(&self, h: &Handle, key: &Value, span: Span) -> Run<usize> {
        match key {
            Value::Text(_) => {
                let at = self.collection_place(h, key, span)?;
                Ok(h.0.borrow().position_of(at))
            }
            _ => self.collection_number(h, key, span),
        }
    }

    /// A 1-based index as a 0-based position among the entries (error 9 past them).
    fn collection_number(&self, h: &Handle, key: &Value, span: Span) -> Run<usize> {
        let n = self.number_of(key, "the index").map_err(|m| self.fault_at(span, m))?.round_ties_even();
        let count = h.0.borrow().len();
        if n < 1.0 || n > count as f64 {
            return Err(self.vba_error(span, OUT_OF_RANGE, &format!("index {n} of a Collection of {count}")));
        }
        Ok(n as usize - 1)
    }

    /// `c(i)`, `c("k")`, `d(k)`: the item; a Dictionary adds a key it does not have, with
    /// Empty ("Item property": "If key is not found when attempting to return an existing
    /// item, a new key is created and its corresponding item is left empty").
    pub(super) fn store_item(&self, h: &Handle, key: &Key, span: Span) -> Run<Var> {
        let at = match h.class() {
            Class::Collection => self.collection_place(h, &key.value, span)?,
            Class::ArrayList => self.array_list_place(h, &key.value, span)?,
            Class::Dictionary => match self.find(h, &key.value, span)? {
                Some(at) => at,
                None => {
                    self.put(h, key.clone(), Var::Value(Value::Blank), span)?;
                    h.0.borrow().entries.len() - 1
                }
            },
        };
        let item = h.0.borrow().item(at).clone();
        self.gave.set(h.0.borrow().held(at));
        Ok(item)
    }

    /// Notes the type of the number the item under `key` (a Collection's last item without
    /// one) holds.
    pub(super) fn mark_store_held(&self, h: &Handle, key: Option<&Value>, held: Declared, span: Span) -> Run<()> {
        let at = match key {
            Some(key) => self.find(h, key, span)?,
            None => h.0.borrow().entries.len().checked_sub(1),
        };
        if let Some(at) = at {
            h.0.borrow_mut().set_held(at, held);
        }
        Ok(())
    }

    /// The type of the number the item expression `e`, which gave `item`, holds (a Date, an
    /// Integer …); `Variant` for an item that is no number.
    pub(super) fn item_held(&self, e: &Expr, item: &Var) -> Declared {
        match item {
            Var::Value(v @ Value::Number(_)) if self.as_date(e, v).is_some() => Declared::Date,
            Var::Value(v @ Value::Number(_)) => self.value_type(e, v),
            _ => Declared::Variant,
        }
    }

    /// `d(k) = v`, `d.Item(k) = v`: replaces the item, or adds the key ("Item property").
    pub(super) fn set_store_item(&self, h: &Handle, key: &Key, item: Var, span: Span) -> Run<()> {
        if h.class() == Class::Collection {
            return Err(self.fault_at(span, "a Collection's items cannot be assigned: Remove and Add the item"));
        }
        if h.class() == Class::ArrayList {
            let at = self.array_list_place(h, &key.value, span)?;
            return self.replace_item(h, at, item, span);
        }
        match self.find(h, &key.value, span)? {
            Some(at) => self.replace_item(h, at, item, span),
            None => self.put(h, key.clone(), item, span),
        }
    }

    /// The item at place `at` becomes `item`; the one it was is let go.
    fn replace_item(&self, h: &Handle, at: usize, item: Var, span: Span) -> Run<()> {
        self.charge(super::budget::brought(&item), span)?;
        let old = std::mem::replace(h.0.borrow_mut().item_mut(at), item);
        self.release(&old)
    }

    /// `d.Key(old) = new` ("Key property"): the entry keeps its place and its item under the
    /// new key; a run-time error when `old` is not there, 457 when `new` already is.
    fn change_key(&self, h: &Handle, old: &Value, new: Key, span: Span) -> Run<()> {
        let at = self.find(h, old, span)?.ok_or_else(|| self.vba_error(span, NO_KEY_TO_CHANGE, "Key"))?;
        if self.find(h, &new.value, span)?.is_some() {
            return Err(self.vba_error(span, DUPLICATE_KEY, "Key"));
        }
        self.charge(key_bytes(Some(&new.value)), span)?;
        h.0.borrow_mut().rename(at, new).map_err(|m| self.fault_at(span, m))
    }

    /// A Dictionary's key from its expression: a value. An object (a Collection, a
    /// Dictionary, a Range) is refused by name: ncsheet's keys are values, and `Keys` gives
    /// them as an array of values, which cannot hold objects.
    pub(super) fn store_key_value(&self, e: &Expr) -> Run<Key> {
        let object = match &e.kind {
            ExprKind::Name(name) => match self.lookup(name) {
                Some(Var::Obj(obj @ (Obj::Store(_) | Obj::Range(..) | Obj::Sheet(_)))) => Some(obj.describe()),
                _ => None,
            },
            ExprKind::Host(id) => match self.module.nodes[*id as usize] {
                super::ast::Node::New { .. } => Some("a new object"),
                _ => None,
            },
            _ => None,
        };
        if let Some(what) = object {
            return Err(self.unsupported(
                self.expr_span(e),
                format!(
                    "{what} cannot be a Dictionary key here: ncsheet's Dictionary keys are values (text, \
                     numbers, dates, booleans), not objects; key it by a value that names the object"
                ),
            ));
        }
        let value = self.eval(e)?;
        self.typed_key(e, value)
    }

    /// The key `e` gave as `value`, with the type of its number. A LongLong is refused as
    /// Scripting refuses it (its `get_HashVal` fails VT_I8 with "Invalid procedure call or
    /// argument", checked against Windows in Wine's `test_hash_value`).
    #[inline(never)]
    fn typed_key(&self, e: &Expr, value: Value) -> Run<Key> {
        let held = self.item_held(e, &Var::Value(value.clone()));
        if held == Declared::LongLong {
            return Err(self.vba_error(self.expr_span(e), INVALID_CALL, "a LongLong as a Dictionary key"));
        }
        Ok(Key { value, held })
    }

    /// The index arguments of `c(i)` as one key.
    pub(super) fn store_key(&self, ctx: &mut Ctx, index: &[Expr], span: Span) -> Run<Key> {
        let [e] = index else {
            return Err(self.vba_error(span, INVALID_CALL, "an item is picked by one index or key"));
        };
        if let ExprKind::Name(_) | ExprKind::Host(_) = e.kind {
            return self.store_key_value(e);
        }
        let v = ctx.eval(e).unwrap_single();
        self.take_pending()?;
        self.typed_key(e, v)
    }

    /// `c(i)` in an expression.
    pub(super) fn store_operand(&self, ctx: &mut Ctx, h: &Handle, index: &[Expr], span: Span) -> Run<Operand> {
        let key = self.store_key(ctx, index, span)?;
        match self.store_item(h, &key, span)? {
            Var::Obj(Obj::Range(sheet, rect)) => Ok(Operand::Ref(sheet, rect)),
            Var::Obj(Obj::Value(v)) | Var::Value(v) => Ok(Operand::Value(v)),
            Var::Array(a) => Ok(Operand::Value(Value::Array(a.data))),
            Var::Obj(o) => self.operand_of(o, span),
            Var::Record(..) => Err(self.fault_at(span, "the item is a Type value")),
        }
    }

    /// `d.Item(k) = v`, `d.CompareMode = vbTextCompare`.
    pub(super) fn set_store_member(&self, h: &Handle, link: &Link, value: &Expr) -> Run<()> {
        match lower(link).as_str() {
            "item" => {
                let args = self.member_args(link, &["Key"])?;
                let key = self.store_key_value(self.required(args[0], link, "Key")?)?;
                let item = self.item_var(value)?;
                self.set_store_item(h, &key, item, link.span)
            }
            "key" if h.class() == Class::Dictionary => {
                let args = self.member_args(link, &["Key"])?;
                let old = self.store_key_value(self.required(args[0], link, "Key")?)?;
                let new = self.store_key_value(value)?;
                self.change_key(h, &old.value, new, link.span)
            }
            "comparemode" if h.class() == Class::Dictionary => {
                let mode = self.number(value, "CompareMode")?;
                if h.0.borrow().len() > 0 || !(0.0..=2.0).contains(&mode) {
                    // "CompareMode property": an error occurs when the Dictionary already holds data.
                    return Err(self.vba_error(link.span, INVALID_CALL, "CompareMode"));
                }
                h.0.borrow_mut().text_compare = mode >= 1.0;
                Ok(())
            }
            "capacity" if h.class() == Class::ArrayList => self.set_capacity(h, link, value),
            _ => Err(self.no_member(&Obj::Store(h.clone()), link)),
        }
    }
}

/// The ProgIDs `CreateObject` may name: Scripting's Dictionary and .NET's ArrayList, which
/// ncsheet makes itself; nothing else.
pub fn created_class(prog_id: &str) -> Option<Class> {
    match prog_id.to_ascii_lowercase().as_str() {
        "scripting.dictionary" => Some(Class::Dictionary),
        "system.collections.arraylist" => Some(Class::ArrayList),
        _ => None,
    }
}

/// The class `New` names: `Collection`, `Dictionary`, `Scripting.Dictionary`.
pub fn new_class(name: &str) -> Option<Class> {
    match name.to_ascii_lowercase().as_str() {
        "collection" | "vba.collection" => Some(Class::Collection),
        "dictionary" | "scripting.dictionary" => Some(Class::Dictionary),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::LiveCounts;

    /// The counts agree with counting the places one by one, through pushes and removals in
    /// an order that is neither the first nor the last place each time.
    #[test]
    fn live_counts_find_positions_and_places() {
        let mut counts = LiveCounts::default();
        let mut live = Vec::new();
        for i in 0..300usize {
            counts.push();
            live.push(true);
            if i % 3 == 1 {
                let at = (i * 7) % live.len();
                if live[at] {
                    counts.take(at);
                    live[at] = false;
                }
            }
        }
        let places: Vec<usize> = (0..live.len()).filter(|&p| live[p]).collect();
        for (n, &place) in places.iter().enumerate() {
            assert_eq!(counts.nth(n), place, "position {n}");
            assert_eq!(counts.before(place), n, "place {place}");
        }
        let rebuilt = LiveCounts::full(places.len());
        assert_eq!(
            (0..places.len()).map(|n| rebuilt.nth(n)).collect::<Vec<_>>(),
            (0..places.len()).collect::<Vec<_>>()
        );
    }
}
