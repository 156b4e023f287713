//! The dependency graph's storage: per-cell dependent lists and range nodes.
//!
//! A formula that reads a range depends on one range node, not on each cell of it. When a
//! cell changes, a spatial index finds the range nodes that contain it.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;

/// A small, fast hasher for the graph's integer keys (std's SipHash is built for untrusted keys).
#[derive(Default, Clone, Copy)]
pub struct FxHasher(u64);

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        // Eight bytes at a time: formula keys are strings of a few dozen bytes.
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.add(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut last = [0u8; 8];
            last[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(last) ^ ((rest.len() as u64) << 59));
        }
    }

    fn write_u8(&mut self, i: u8) {
        self.add(i as u64)
    }

    fn write_u16(&mut self, i: u16) {
        self.add(i as u64)
    }

    fn write_u32(&mut self, i: u32) {
        self.add(i as u64)
    }

    fn write_u64(&mut self, i: u64) {
        self.add(i)
    }

    fn write_usize(&mut self, i: usize) {
        self.add(i as u64)
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

impl FxHasher {
    #[inline]
    fn add(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

pub type FxMap<K, V> = HashMap<K, V, BuildHasherDefault<FxHasher>>;

/// The formula cells that read a cell or a range. Most cells have one to three, so those
/// are stored inline (in the 16 bytes the boxed case needs anyway), as arrays so that every
/// case reads as a slice.
#[derive(Clone, Debug, Default)]
pub enum Deps {
    #[default]
    None,
    One([u32; 1]),
    Two([u32; 2]),
    Three([u32; 3]),
    // Boxed so that the enum stays 16 bytes: most cells never need the vector.
    #[allow(clippy::box_collection)]
    Many(Box<Vec<u32>>),
}

impl Deps {
    pub fn push(&mut self, id: u32) {
        *self = match std::mem::take(self) {
            Deps::None => Deps::One([id]),
            Deps::One([a]) => Deps::Two([a, id]),
            Deps::Two([a, b]) => Deps::Three([a, b, id]),
            Deps::Three([a, b, c]) => Deps::Many(Box::new(vec![a, b, c, id])),
            Deps::Many(mut v) => {
                v.push(id);
                Deps::Many(v)
            }
        }
    }

    /// Removes one occurrence of `id`.
    pub fn remove(&mut self, id: u32) {
        *self = match std::mem::take(self) {
            Deps::One([a]) if a == id => Deps::None,
            Deps::Two([a, b]) if a == id => Deps::One([b]),
            Deps::Two([a, b]) if b == id => Deps::One([a]),
            Deps::Three([a, b, c]) if a == id => Deps::Two([b, c]),
            Deps::Three([a, b, c]) if b == id => Deps::Two([a, c]),
            Deps::Three([a, b, c]) if c == id => Deps::Two([a, b]),
            Deps::Many(mut v) => {
                if let Some(i) = v.iter().position(|&x| x == id) {
                    v.swap_remove(i);
                }
                match v.as_slice() {
                    [a, b, c] => Deps::Three([*a, *b, *c]),
                    _ => Deps::Many(v),
                }
            }
            other => other,
        }
    }

    /// The dependents, in no particular order. A slice rather than a callback, so that the
    /// recalculation's search loops over it inline.
    #[inline]
    pub fn as_slice(&self) -> &[u32] {
        match self {
            Deps::None => &[],
            Deps::One(ids) => ids,
            Deps::Two(ids) => ids,
            Deps::Three(ids) => ids,
            Deps::Many(ids) => ids,
        }
    }

    pub fn is_empty(&self) -> bool {
        matches!(self, Deps::None)
    }
}

pub struct RangeNode {
    pub sheet: SheetId,
    pub rect: Rect,
    pub dependents: Deps,
}

/// Rows per bucket of the spatial index.
const BLOCK: u32 = 16;
/// Ranges spanning more buckets than this are kept in a list checked on every lookup
/// (whole columns and rows are few in real sheets).
const MAX_BUCKETS: u64 = 4096;

#[derive(Default)]
pub struct RangeIndex {
    pub nodes: Vec<RangeNode>,
    by_rect: FxMap<(SheetId, Rect), u32>,
    buckets: FxMap<(SheetId, u32, u32), Vec<u32>>,
    big: Vec<u32>,
}

impl RangeIndex {
    /// The node for a range, created on first use.
    pub fn intern(&mut self, sheet: SheetId, rect: Rect) -> u32 {
        if let Some(&id) = self.by_rect.get(&(sheet, rect)) {
            return id;
        }
        let id = self.nodes.len() as u32;
        self.nodes.push(RangeNode { sheet, rect, dependents: Deps::None });
        self.by_rect.insert((sheet, rect), id);
        let blocks = (rect.last.row / BLOCK - rect.first.row / BLOCK + 1) as u64 * rect.cols() as u64;
        if blocks > MAX_BUCKETS {
            self.big.push(id);
        } else {
            for col in rect.first.col..=rect.last.col {
                for block in rect.first.row / BLOCK..=rect.last.row / BLOCK {
                    self.buckets.entry((sheet, col, block)).or_default().push(id);
                }
            }
        }
        id
    }

    pub fn find(&self, sheet: SheetId, rect: Rect) -> Option<u32> {
        self.by_rect.get(&(sheet, rect)).copied()
    }

    /// Calls `f` with every range node that contains the cell.
    #[inline]
    pub fn containing(&self, sheet: SheetId, pos: Pos, mut f: impl FnMut(u32)) {
        if let Some(ids) = self.buckets.get(&(sheet, pos.col, pos.row / BLOCK)) {
            for &id in ids {
                let n = &self.nodes[id as usize];
                if n.rect.contains(pos) && !n.dependents.is_empty() {
                    f(id);
                }
            }
        }
        for &id in &self.big {
            let n = &self.nodes[id as usize];
            if n.sheet == sheet && n.rect.contains(pos) && !n.dependents.is_empty() {
                f(id);
            }
        }
    }

    /// Calls `f` with every range node with dependents that shares a cell with `rect` (a
    /// node may come more than once). Reads one bucket per column and 16 rows of `rect`.
    pub fn meeting(&self, sheet: SheetId, rect: Rect, mut f: impl FnMut(u32)) {
        let meets = |n: &RangeNode| {
            n.sheet == sheet
                && n.rect.first.row <= rect.last.row
                && rect.first.row <= n.rect.last.row
                && n.rect.first.col <= rect.last.col
                && rect.first.col <= n.rect.last.col
                && !n.dependents.is_empty()
        };
        if !self.buckets.is_empty() {
            for col in rect.first.col..=rect.last.col {
                for block in rect.first.row / BLOCK..=rect.last.row / BLOCK {
                    for &id in self.buckets.get(&(sheet, col, block)).map_or(&[][..], |v| v.as_slice()) {
                        if meets(&self.nodes[id as usize]) {
                            f(id);
                        }
                    }
                }
            }
        }
        for &id in &self.big {
            if meets(&self.nodes[id as usize]) {
                f(id);
            }
        }
    }

    pub fn clear(&mut self) {
        *self = RangeIndex::default();
    }

    /// Drops the nodes no formula reads any more, once they outnumber those read: each
    /// column inserted before `=SUM(A:A)` leaves the node of the range it read, and every
    /// changed cell is looked up among the whole-column nodes. Nodes are numbered afresh
    /// (only a recalculation's marks, made and dropped within it, name them).
    pub fn drop_unused(&mut self) {
        let used = self.nodes.iter().filter(|n| !n.dependents.is_empty()).count();
        if self.nodes.len() - used <= used.max(64) {
            return;
        }
        let kept: Vec<RangeNode> =
            std::mem::take(&mut self.nodes).into_iter().filter(|n| !n.dependents.is_empty()).collect();
        self.clear();
        for node in kept {
            let id = self.intern(node.sheet, node.rect);
            self.nodes[id as usize].dependents = node.dependents;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deps_keep_every_entry_through_pushes_and_removes() {
        let mut d = Deps::None;
        for i in 0..5 {
            d.push(i);
        }
        d.remove(2);
        d.remove(0);
        let mut seen = d.as_slice().to_vec();
        seen.sort();
        assert_eq!(seen, vec![1, 3, 4]);
        for n in 0..6u32 {
            for gone in 0..n {
                let mut d = Deps::None;
                (0..n).for_each(|i| d.push(i));
                d.remove(gone);
                let mut seen = d.as_slice().to_vec();
                seen.sort();
                assert_eq!(seen, (0..n).filter(|&i| i != gone).collect::<Vec<_>>());
            }
        }
        assert_eq!(std::mem::size_of::<Deps>(), 16);
    }

    #[test]
    fn ranges_are_found_from_any_cell_inside_them() {
        let mut idx = RangeIndex::default();
        let r = idx.intern(0, Rect::new(Pos::new(10, 1), Pos::new(40, 2)));
        let col = idx.intern(0, Rect::new(Pos::new(0, 0), Pos::new(1_048_575, 0)));
        idx.nodes[r as usize].dependents.push(99);
        idx.nodes[col as usize].dependents.push(98);
        let found = |p: Pos| {
            let mut v = Vec::new();
            idx.containing(0, p, |id| v.push(id));
            v
        };
        assert_eq!(found(Pos::new(40, 2)), vec![r]);
        assert_eq!(found(Pos::new(41, 2)), Vec::<u32>::new());
        assert_eq!(found(Pos::new(500_000, 0)), vec![col]);
        assert_eq!(idx.intern(0, Rect::new(Pos::new(10, 1), Pos::new(40, 2))), r);
    }
}
