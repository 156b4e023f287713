//! The indexes a lookup builds once per call when it looks up many keys
//! (`MATCH(SEQUENCE(100000), items, 0)`): a hash of the items for exact matches, and the
//! items in order for XLOOKUP's next smaller or next larger item. One key by itself is
//! still searched item by item: building an index costs more than one scan.

use std::cmp::Ordering;
use std::collections::HashMap;

use crate::eval::coerce::compare;
use crate::eval::functions::arrays::reshape::{item_key, ItemKey};
use crate::eval::value::Value;

/// From this many keys in one call, a lookup indexes its items. Below it, each key's scan
/// (which stops at the first match) is cheaper than hashing every item.
const MANY_KEYS: usize = 8;

/// Whether `keys`, a lookup's first argument, holds enough keys to index the items for.
pub fn worth_indexing(keys: &Value) -> bool {
    match keys {
        Value::Array(a) => {
            let (rows, cols) = a.whole_size();
            rows.saturating_mul(cols) >= MANY_KEYS
        }
        _ => false,
    }
}

/// The first and last position of each distinct item, equal as an exact lookup finds them
/// equal: text without regard to case, numbers by value (0 and -0 alike), booleans; blanks
/// are kept for XLOOKUP's search for an empty cell.
pub struct ExactIndex {
    positions: HashMap<ItemKey, (usize, usize)>,
}

impl ExactIndex {
    pub fn new(items: &[Value]) -> ExactIndex {
        let mut positions: HashMap<ItemKey, (usize, usize)> = HashMap::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            if let Some(key) = item_key(item) {
                positions.entry(key).or_insert((i, i)).1 = i;
            }
        }
        ExactIndex { positions }
    }

    /// The first (last when `reverse`) item equal to `key`, a number, text or boolean (any
    /// other key matches nothing, as a scan finds: errors and blanks are no lookup keys).
    pub fn find(&self, key: &Value, reverse: bool) -> Option<usize> {
        if !matches!(key, Value::Number(_) | Value::Text(_) | Value::Bool(_)) {
            return None;
        }
        self.at(&item_key(key)?, reverse)
    }

    /// The first (last when `reverse`) empty item.
    pub fn find_blank(&self, reverse: bool) -> Option<usize> {
        self.at(&ItemKey::Blank, reverse)
    }

    fn at(&self, key: &ItemKey, reverse: bool) -> Option<usize> {
        self.positions.get(key).map(|&(first, last)| if reverse { last } else { first })
    }
}

/// The positions of the items XLOOKUP's next-smaller and next-larger modes weigh (numbers,
/// text and booleans; blanks and errors take no part), sorted as they compare across kinds
/// (numbers < text < booleans), equal items by position.
pub struct OrderIndex<'a> {
    items: &'a [Value],
    sorted: Vec<usize>,
}

impl<'a> OrderIndex<'a> {
    pub fn new(items: &'a [Value]) -> OrderIndex<'a> {
        let weighed = |v: &Value| match v {
            Value::Number(x) => !x.is_nan(),
            Value::Text(_) | Value::Bool(_) => true,
            _ => false,
        };
        let mut sorted: Vec<usize> = (0..items.len()).filter(|&i| weighed(&items[i])).collect();
        // Stable: equal items keep their order of position.
        sorted.sort_by(|&a, &b| order(&items[a], &items[b]));
        OrderIndex { items, sorted }
    }

    /// The work a query does: two binary searches.
    pub fn query_work(&self) -> usize {
        2 * (usize::BITS - self.sorted.len().leading_zeros()) as usize
    }

    /// The work of sorting: a query's for each item.
    pub fn sort_work(&self) -> usize {
        self.sorted.len().saturating_mul(self.query_work())
    }

    /// How many weighed items of `key`'s kind (numbers, text or booleans) sort before
    /// `key`, level with it and after it: four binary searches (twice a query's work).
    pub fn sides(&self, key: &Value) -> [usize; 3] {
        let [kind_start, before, through, kind_end] = self.bounds(key);
        [before - kind_start, through - before, kind_end - through]
    }

    /// Where in the sorted order `key`'s kind starts, the items equal to `key` start and
    /// end, and its kind ends.
    pub fn bounds(&self, key: &Value) -> [usize; 4] {
        [
            self.count_where(|item| kind(item) < kind(key)),
            self.count_where(|item| order(item, key) == Ordering::Less),
            self.count_where(|item| order(item, key) != Ordering::Greater),
            self.count_where(|item| kind(item) <= kind(key)),
        ]
    }

    /// The weighed items' positions in sorted order.
    pub fn sorted(&self) -> &[usize] {
        &self.sorted
    }

    /// The largest item below `key`; among equal ones the first met searching from the
    /// front (from the back when `reverse`).
    pub fn next_smaller(&self, key: &Value, reverse: bool) -> Option<usize> {
        let below = self.count_where(|item| order(item, key) == Ordering::Less);
        let largest = &self.items[*self.sorted.get(below.checked_sub(1)?)?];
        let class_start = self.count_where(|item| order(item, largest) == Ordering::Less);
        Some(if reverse { self.sorted[below - 1] } else { self.sorted[class_start] })
    }

    /// The smallest item above `key`; among equal ones the first met searching from the
    /// front (from the back when `reverse`).
    pub fn next_larger(&self, key: &Value, reverse: bool) -> Option<usize> {
        let not_above = self.count_where(|item| order(item, key) != Ordering::Greater);
        let smallest = &self.items[*self.sorted.get(not_above)?];
        let class_end = self.count_where(|item| order(item, smallest) != Ordering::Greater);
        Some(if reverse { self.sorted[class_end - 1] } else { self.sorted[not_above] })
    }

    /// How many sorted items from the front hold `test` (which holds for a prefix).
    fn count_where(&self, test: impl Fn(&Value) -> bool) -> usize {
        self.sorted.partition_point(|&i| test(&self.items[i]))
    }
}

/// The order of two weighed items, or of an item and a number, text or boolean key.
fn order(a: &Value, b: &Value) -> Ordering {
    compare(a, b).unwrap_or(Ordering::Equal)
}

/// Where a weighed item's kind sorts: numbers, then text, then booleans.
fn kind(v: &Value) -> u8 {
    match v {
        Value::Number(_) => 0,
        Value::Text(_) => 1,
        _ => 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(s: &str) -> Value {
        Value::text(s)
    }

    #[test]
    fn exact_index_finds_first_and_last_equal_items() {
        let items = [
            Value::Number(-0.0),
            t("Straße"),
            Value::Bool(true),
            t("STRASSE"),
            Value::Blank,
            Value::Number(0.0),
            t("straße"),
        ];
        let index = ExactIndex::new(&items);
        assert_eq!(index.find(&Value::Number(0.0), false), Some(0));
        assert_eq!(index.find(&Value::Number(0.0), true), Some(5));
        // "ß" folds to itself, not to "ss": STRASSE is another text.
        assert_eq!(index.find(&t("STRAẞE"), false), Some(1));
        assert_eq!(index.find(&t("STRAẞE"), true), Some(6));
        assert_eq!(index.find(&t("strasse"), false), Some(3));
        assert_eq!(index.find(&Value::Bool(true), false), Some(2));
        assert_eq!(index.find(&Value::Number(1.0), false), None);
        assert_eq!(index.find(&Value::Blank, false), None);
        assert_eq!(index.find_blank(false), Some(4));
    }

    #[test]
    fn order_index_finds_the_closest_item_on_each_side() {
        // Numbers < text < booleans; the blank and the error take no part.
        let items = [
            Value::Number(5.0),
            t("b"),
            Value::Number(3.0),
            Value::Blank,
            Value::Number(5.0),
            Value::Bool(false),
            t("B"),
        ];
        let index = OrderIndex::new(&items);
        assert_eq!(index.next_smaller(&Value::Number(6.0), false), Some(0));
        assert_eq!(index.next_smaller(&Value::Number(6.0), true), Some(4));
        assert_eq!(index.next_smaller(&Value::Number(3.0), false), None);
        assert_eq!(index.next_larger(&Value::Number(4.0), false), Some(0));
        assert_eq!(index.next_larger(&Value::Number(5.0), false), Some(1));
        assert_eq!(index.next_larger(&t("a"), true), Some(6));
        assert_eq!(index.next_larger(&t("c"), false), Some(5));
        assert_eq!(index.next_larger(&Value::Bool(false), false), None);
        assert_eq!(index.next_smaller(&Value::Bool(false), false), Some(1));
        // Within a kind only: 3 < 5 = 5 among the numbers; "b" = "B"; FALSE alone.
        assert_eq!(index.sides(&Value::Number(5.0)), [1, 2, 0]);
        assert_eq!(index.sides(&Value::Number(4.0)), [1, 0, 2]);
        assert_eq!(index.sides(&t("a")), [0, 0, 2]);
        assert_eq!(index.sides(&t("B")), [0, 2, 0]);
        assert_eq!(index.sides(&Value::Bool(true)), [1, 0, 0]);
    }
}
