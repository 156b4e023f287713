//! The milling program of a fitted cam (docs/domain.md §5), built on the NC model so that any
//! milling dialect writes it: a radial lead-in from outside the profile, every arc as a
//! circular move, straight moves across the gaps and steps of a partial cam, a radial
//! lead-out.

use nalgebra::{Point2, Vector2};

pub use super::program::Compensation;
use super::program::{ArcDirection, Block, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange};
use crate::geometry::cam::{Arc, CamFit, Turn};

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
    /// The tool called at the start (its offset is the one G41/G42 use).
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

/// Digits after the point for a program within `tol` of its curve: at least
/// [`CAM_DECIMALS`], and enough that rounding moves an arc by at most a quarter of `tol`.
pub fn written_decimals(tol: f64) -> usize {
    let mut decimals = CAM_DECIMALS;
    while decimals < 6 && ROUNDING_REACH * 10f64.powi(-(decimals as i32)) > tol / 4.0 {
        decimals += 1;
    }
    decimals
}

/// How far the written arcs may lie from the fitted ones, in units of the last digit: the
/// start point rounds by half a digit in each axis (0.71), the centre offset from it as well
/// (0.71), so the centre moves 0.71 and the radius 1.42; 2.13 in all, rounded up.
const ROUNDING_REACH: f64 = 2.2;

/// The tolerance to fit at so that the program written with [`written_decimals`] stays within
/// `tol` of the curve.
pub fn fit_tolerance(tol: f64) -> f64 {
    tol - ROUNDING_REACH * 10f64.powi(-(written_decimals(tol) as i32))
}

/// Consecutive arcs farther apart than this (mm) get a straight move between them.
const GAP: f64 = 1e-6;

/// The program for one disc.
pub fn cam_program(fit: &CamFit, options: &CamNcOptions) -> Program {
    let disc = if fit.disc.is_empty() { String::new() } else { format!("_{}", fit.disc) };
    let mut p = Program::new(&format!("CAM{disc}"), Machine::Mill);
    p.precision = Some(written_decimals(fit.tolerance));
    let arcs: Vec<&Arc> = fit.arcs().collect();
    p.push(Block::Comment(format!("ncsheet cam {}: {} arcs, tolerance {} mm", fit.disc, arcs.len(), fit.tolerance)));
    let (Some(first), Some(last)) = (arcs.first(), arcs.last()) else { return p };
    let outward = |q: Point2<f64>| if q.coords.norm() > 0.0 { q.coords.normalize() } else { Vector2::x() };
    let entry = first.start + outward(first.start) * options.lead;
    let reach = arcs.iter().map(|a| a.start.coords.norm().max(a.end.coords.norm())).fold(0.0, f64::max);
    p.blank = Some(([-reach, -reach, options.z_cut.min(0.0)], [reach, reach, 0.0]));
    let safe = Target { z: Some(options.z_safe), ..Target::default() };
    p.retract = Some(safe);
    p.push(Block::FeedMode(FeedMode::PerMinute));
    p.push(Block::Tool(ToolChange::new(options.tool)));
    p.push(Block::Spindle(Spindle::Rpm { rpm: options.spindle, direction: SpindleDirection::Clockwise }));
    p.push(Block::Rapid(safe));
    p.push(Block::Rapid(Target::xy(entry.x, entry.y)));
    p.push(Block::Line { to: Target { z: Some(options.z_cut), ..Target::default() }, feed: Some(options.plunge_feed) });
    if options.compensation != Compensation::Off {
        p.push(Block::Compensation(options.compensation));
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
        p.push(Block::Compensation(Compensation::Off));
    }
    p.push(Block::Line { to: Target::xy(exit.x, exit.y), feed: None });
    p
}
