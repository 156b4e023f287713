//! The milling program of a fitted cam (DOMAIN.md §5), built on the NC model so that any
//! milling dialect writes it: a radial lead-in from outside the profile, every arc as a
//! circular move, straight moves across the gaps and steps of a partial cam, a radial
//! lead-out.

use nalgebra::{Point2, Vector2};

use super::program::{ArcDirection, Block, Machine, Program, Target, Word};
use crate::geometry::cam::{Arc, CamFit, Turn};

/// Cutter radius compensation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compensation {
    /// The programmed path is the profile itself (the cutter's centre follows it).
    Off,
    /// G41, cutter left of the path.
    Left,
    /// G42, cutter right of the path: outside a cam cut counter-clockwise.
    Right,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CamNcOptions {
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed: f64,
    /// Spindle speed, 1/min (M3).
    pub spindle: f64,
    /// Clearance height above the disc.
    pub z_safe: f64,
    /// Cutting depth (negative: into the disc).
    pub z_cut: f64,
    /// Length of the straight radial lead-in and lead-out, from outside the profile.
    pub lead: f64,
    pub compensation: Compensation,
    /// Tool offset number for G41/G42 (D word).
    pub tool: u32,
}

impl Default for CamNcOptions {
    fn default() -> CamNcOptions {
        CamNcOptions {
            feed: 200.0,
            plunge_feed: 100.0,
            spindle: 1000.0,
            z_safe: 5.0,
            z_cut: -12.0,
            lead: 5.0,
            compensation: Compensation::Off,
            tool: 1,
        }
    }
}

/// Digits after the point: the paper's machine (MAHO MHC-700) resolves 0.1 µm, and a
/// tolerance of 0.001 mm leaves no room for 0.5 µm of rounding.
pub const CAM_DECIMALS: usize = 4;

/// Consecutive arcs farther apart than this (mm) get a straight move between them.
const GAP: f64 = 1e-6;

/// The program for one disc.
pub fn cam_program(fit: &CamFit, options: &CamNcOptions) -> Program {
    let disc = if fit.disc.is_empty() { String::new() } else { format!("_{}", fit.disc) };
    let mut p = Program::new(&format!("CAM{disc}"), Machine::Mill);
    p.precision = Some(CAM_DECIMALS);
    let arcs: Vec<&Arc> = fit.arcs().collect();
    p.push(Block::Comment(format!("ncsheet cam {}: {} arcs, tolerance {} mm", fit.disc, arcs.len(), fit.tolerance)));
    let (Some(first), Some(last)) = (arcs.first(), arcs.last()) else { return p };
    let outward = |q: Point2<f64>| if q.coords.norm() > 0.0 { q.coords.normalize() } else { Vector2::x() };
    let entry = first.start + outward(first.start) * options.lead;
    p.push(words(&[('S', options.spindle), ('M', 3.0)]));
    p.push(Block::Rapid(Target { z: Some(options.z_safe), ..Target::default() }));
    p.push(Block::Rapid(Target::xy(entry.x, entry.y)));
    p.push(Block::Line { to: Target { z: Some(options.z_cut), ..Target::default() }, feed: Some(options.plunge_feed) });
    match options.compensation {
        Compensation::Off => {}
        Compensation::Left => {
            p.push(words(&[('G', 41.0), ('D', options.tool as f64)]));
        }
        Compensation::Right => {
            p.push(words(&[('G', 42.0), ('D', options.tool as f64)]));
        }
    }
    p.push(Block::Line { to: Target::xy(first.start.x, first.start.y), feed: Some(options.feed) });
    let mut previous_end = first.start;
    for a in &arcs {
        if (a.start - previous_end).norm() > GAP {
            // A gap or a step of a partial cam: straight across.
            p.push(Block::Line { to: Target::xy(a.start.x, a.start.y), feed: None });
        }
        let direction = if a.turn == Turn::Ccw { ArcDirection::CounterClockwise } else { ArcDirection::Clockwise };
        let (to, centre) = (Target::xy(a.end.x, a.end.y), Target::xy(a.centre.x, a.centre.y));
        p.push(Block::Arc { direction, to, centre, feed: None });
        previous_end = a.end;
    }
    let exit = last.end + outward(last.end) * options.lead;
    if options.compensation != Compensation::Off {
        p.push(words(&[('G', 40.0)]));
    }
    p.push(Block::Line { to: Target::xy(exit.x, exit.y), feed: None });
    p.push(Block::Rapid(Target { z: Some(options.z_safe), ..Target::default() }));
    p.push(words(&[('M', 5.0)]));
    p
}

fn words(list: &[(char, f64)]) -> Block {
    Block::Words(list.iter().map(|&(address, value)| Word { address, value }).collect())
}
