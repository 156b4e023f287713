//! NC dialects: how one control writes a [`Program`]. A dialect is a value implementing
//! [`Dialect`]; [`by_name`] is the one list the CLI's `--dialect` reads.
//!
//! Word-address controls (ISO/Fanuc, LinuxCNC, Sinumerik, NC31) share one writer configured
//! by a [`WordAddress`] table; Heidenhain's plain language has a writer of its own.

use std::fmt;

use super::format::NumberStyle;
use super::program::{Block, Machine, Program, Target};

mod heidenhain;
mod word_address;

pub use heidenhain::Heidenhain;
pub use word_address::{WordAddress, ISO, LINUXCNC, NC31, SINUMERIK};

/// Something a dialect cannot write.
#[derive(Clone, Debug, PartialEq)]
pub struct NcError {
    pub dialect: &'static str,
    /// 1-based index of the block in the program model, when one block is at fault.
    pub block: Option<usize>,
    pub message: String,
}

impl fmt::Display for NcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.block {
            Some(b) => write!(f, "{} dialect, block {b}: {}", self.dialect, self.message),
            None => write!(f, "{} dialect: {}", self.dialect, self.message),
        }
    }
}

impl std::error::Error for NcError {}

pub trait Dialect {
    /// The name `--dialect` takes.
    fn name(&self) -> &'static str;

    /// The smallest step the control's numbers resolve (mm).
    fn resolution(&self) -> f64;

    /// The program as the control reads it, one block per line, ending in a newline.
    fn render(&self, program: &Program) -> Result<String, NcError>;
}

/// Every dialect, by the name the CLI uses.
pub fn all() -> [&'static dyn Dialect; 5] {
    [&ISO, &LINUXCNC, &SINUMERIK, &Heidenhain, &NC31]
}

pub fn by_name(name: &str) -> Option<&'static dyn Dialect> {
    all().into_iter().find(|d| d.name().eq_ignore_ascii_case(name))
}

pub fn names() -> Vec<&'static str> {
    all().iter().map(|d| d.name()).collect()
}

/// Where the tool is while a program is written: arcs need their start point.
#[derive(Clone, Copy, Debug, Default)]
struct Position {
    axes: [Option<f64>; 6],
}

impl Position {
    fn apply(&mut self, t: &Target) {
        for (i, v) in [t.x, t.y, t.z, t.a, t.b, t.c].into_iter().enumerate() {
            if v.is_some() {
                self.axes[i] = v;
            }
        }
    }

    fn x(&self) -> Option<f64> {
        self.axes[0]
    }

    fn y(&self) -> Option<f64> {
        self.axes[1]
    }

    fn z(&self) -> Option<f64> {
        self.axes[2]
    }
}

/// Arc centre offsets from the start point, as (address, value) in the machine's plane:
/// I/J on a mill; I (radius, though X is a diameter) and K on a lathe.
fn centre_offsets(machine: Machine, start: &Position, centre: &Target) -> Option<[(char, f64); 2]> {
    match machine {
        Machine::Mill => Some([('I', centre.x? - start.x()?), ('J', centre.y? - start.y()?)]),
        Machine::Lathe => Some([('I', (centre.x? - start.x()?) / 2.0), ('K', centre.z? - start.z()?)]),
    }
}

/// Checks that every number of a block is finite (NaN would be written as text).
fn finite_block(block: &Block) -> bool {
    let target_ok = |t: &Target| t.axes().all(|(_, v)| v.is_finite());
    match block {
        Block::Rapid(t) => target_ok(t),
        Block::Line { to, feed } => target_ok(to) && feed.is_none_or(f64::is_finite),
        Block::Arc { to, centre, feed, .. } => target_ok(to) && target_ok(centre) && feed.is_none_or(f64::is_finite),
        Block::Dwell(s) => s.is_finite(),
        Block::Comment(_) => true,
        Block::Words(w) => w.iter().all(|w| w.value.is_finite()),
    }
}

/// The number style a dialect writes feed rates in (they are not lengths; two decimals do).
fn feed_style(base: NumberStyle) -> NumberStyle {
    NumberStyle { decimals: base.decimals.min(3), ..base }
}
