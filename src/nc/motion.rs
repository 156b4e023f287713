//! The trapezoidal velocity profile of DOMAIN.md §4: each block starts and ends at rest,
//! accelerates at a constant a to the programmed feed v, cruises, and brakes at a; a block
//! too short to reach v is a triangle peaking at √(a·L). Axis velocities follow by the
//! direction cosines δᵢ/√(Σδ²), without trigonometry.

use std::f64::consts::TAU;
use std::fmt;

use super::program::{ArcDirection, Block, FeedMode, Machine, Program, Spindle, Target};

/// Why a time cannot be given.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionError {
    /// 1-based block of the program model, when one block is at fault.
    pub block: Option<usize>,
    pub message: String,
}

impl fmt::Display for MotionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.block {
            Some(b) => write!(f, "block {b}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for MotionError {}

/// One block's velocity profile (lengths in mm, speeds in mm/s, times in s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trapezoid {
    pub length: f64,
    /// The highest speed reached: the feed, or √(a·L) for a triangle.
    pub peak: f64,
    /// Time to accelerate to the peak (and, the same, to brake from it).
    pub t_accel: f64,
    pub t_cruise: f64,
    pub total: f64,
}

/// The profile of a block of `length` mm at `feed` mm/min with acceleration `accel` mm/s².
pub fn trapezoid(length: f64, feed: f64, accel: f64) -> Result<Trapezoid, String> {
    if !(length.is_finite() && length >= 0.0) {
        return Err(format!("a block's length is a number of mm from 0 up, not {length}"));
    }
    if !(feed.is_finite() && feed > 0.0) {
        return Err(format!("the feed must be above 0 mm/min, not {feed}"));
    }
    if !(accel.is_finite() && accel > 0.0) {
        return Err(format!("the acceleration must be above 0 mm/s², not {accel}"));
    }
    let v = feed / 60.0;
    // Accelerating to v and braking from it take v²/a of the block together.
    let (peak, t_cruise) =
        if length * accel >= v * v { (v, length / v - v / accel) } else { ((accel * length).sqrt(), 0.0) };
    let t_accel = peak / accel;
    Ok(Trapezoid { length, peak, t_accel, t_cruise, total: 2.0 * t_accel + t_cruise })
}

/// Each axis's share of a path speed `v`: v·δᵢ/√(Σδ²) (zero for a block that does not move).
pub fn axis_velocities(delta: &[f64], v: f64) -> Vec<f64> {
    let length = delta.iter().map(|d| d * d).sum::<f64>().sqrt();
    delta.iter().map(|d| if length > 0.0 { v * d / length } else { 0.0 }).collect()
}

/// The time of one block of a program.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockTime {
    /// 1-based block of the program model.
    pub block: usize,
    pub kind: &'static str,
    pub length: f64,
    /// The path speed asked for, mm/min (the rapid rate for a rapid).
    pub feed: f64,
    pub profile: Option<Trapezoid>,
    /// Seconds, dwells included.
    pub time: f64,
}

/// How the machine moves: acceleration (mm/s²) and rapid rate (mm/min).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rates {
    pub accel: f64,
    pub rapid: f64,
}

/// Times of every moving block and dwell, block by block from rest to rest. Feeds per
/// revolution are turned into mm/min with the spindle's fixed speed; under constant surface
/// speed the speed varies along the cut, which this does not model (an error names the block).
pub fn program_times(program: &Program, m: Rates) -> Result<Vec<BlockTime>, MotionError> {
    let mut at = [None::<f64>; 3];
    let mut feed: Option<f64> = None;
    let mut mode = FeedMode::PerMinute;
    let mut spindle = Spindle::Stop;
    let mut out = Vec::new();
    for (i, block) in program.blocks.iter().enumerate() {
        let fail = |message: String| MotionError { block: Some(i + 1), message };
        match block {
            Block::FeedMode(f) => mode = *f,
            Block::Spindle(s) => spindle = *s,
            Block::Dwell(s) => {
                out.push(BlockTime { block: i + 1, kind: "dwell", length: 0.0, feed: 0.0, profile: None, time: *s })
            }
            Block::Rapid(t) | Block::Line { to: t, .. } | Block::Arc { to: t, .. } => {
                let end = moved(&at, t);
                let (kind, length, speed) = match block {
                    Block::Rapid(_) => ("rapid", line_length(program.machine, &at, &end).map_err(fail)?, m.rapid),
                    Block::Line { feed: f, .. } => {
                        feed = f.or(feed);
                        let v = path_feed(feed, mode, &spindle).map_err(fail)?;
                        ("line", line_length(program.machine, &at, &end).map_err(fail)?, v)
                    }
                    Block::Arc { direction, centre, feed: f, .. } => {
                        feed = f.or(feed);
                        let v = path_feed(feed, mode, &spindle).map_err(fail)?;
                        ("arc", arc_length(program.machine, &at, &end, centre, *direction).map_err(fail)?, v)
                    }
                    _ => unreachable!("only moves reach here"),
                };
                let profile = trapezoid(length, speed, m.accel).map_err(fail)?;
                out.push(BlockTime {
                    block: i + 1,
                    kind,
                    length,
                    feed: speed,
                    profile: Some(profile),
                    time: profile.total,
                });
                at = end;
            }
            _ => {}
        }
    }
    Ok(out)
}

fn moved(at: &[Option<f64>; 3], t: &Target) -> [Option<f64>; 3] {
    [t.x.or(at[0]), t.y.or(at[1]), t.z.or(at[2])]
}

/// The feed along the path in mm/min.
fn path_feed(feed: Option<f64>, mode: FeedMode, spindle: &Spindle) -> Result<f64, String> {
    let f = feed.ok_or("a cut with no feed programmed (F) before it")?;
    match (mode, spindle) {
        (FeedMode::PerMinute, _) => Ok(f),
        (FeedMode::PerRevolution, Spindle::Rpm { rpm, .. }) => Ok(f * rpm),
        (FeedMode::PerRevolution, Spindle::SurfaceSpeed { .. }) => {
            Err("a feed per revolution under constant surface speed: the time depends on the diameter, not modelled"
                .into())
        }
        (FeedMode::PerRevolution, Spindle::Stop) => Err("a feed per revolution with the spindle stopped".into()),
    }
}

/// True lengths per axis between two positions: a lathe's X is a diameter, so its radial
/// move is half of ΔX. An axis never set before counts as not moving only if it is not set
/// now either.
fn deltas(machine: Machine, from: &[Option<f64>; 3], to: &[Option<f64>; 3]) -> Result<[f64; 3], String> {
    let mut d = [0.0; 3];
    for i in 0..3 {
        d[i] = match (from[i], to[i]) {
            (Some(a), Some(b)) => b - a,
            (None, None) => 0.0,
            (None, Some(_)) => {
                return Err("a move from an unknown position (the first move sets every axis it uses in rapid)".into())
            }
            (Some(_), None) => unreachable!("a position once known stays known"),
        };
    }
    if machine == Machine::Lathe {
        d[0] /= 2.0;
    }
    Ok(d)
}

fn line_length(machine: Machine, from: &[Option<f64>; 3], to: &[Option<f64>; 3]) -> Result<f64, String> {
    if from.iter().all(Option::is_none) {
        // The first rapid goes from wherever the machine is: no known length.
        return Ok(0.0);
    }
    let d = deltas(machine, from, to)?;
    Ok(d.iter().map(|v| v * v).sum::<f64>().sqrt())
}

/// The arc's length in its plane (a helix adds the third axis's travel).
fn arc_length(
    machine: Machine,
    from: &[Option<f64>; 3],
    to: &[Option<f64>; 3],
    centre: &Target,
    dir: ArcDirection,
) -> Result<f64, String> {
    let d = deltas(machine, from, to)?;
    // Plane coordinates (u, v) and the axis across: XY and Z on a mill, (Z, X/2) and Y on a lathe.
    let (s, e, c, across) = match machine {
        Machine::Mill => {
            let (sx, sy) = (from[0].ok_or("an arc from an unknown X")?, from[1].ok_or("an arc from an unknown Y")?);
            let c = (centre.x.ok_or("an arc centre without X")?, centre.y.ok_or("an arc centre without Y")?);
            ((sx, sy), (sx + d[0], sy + d[1]), c, d[2])
        }
        Machine::Lathe => {
            let (sz, sr) =
                (from[2].ok_or("an arc from an unknown Z")?, from[0].ok_or("an arc from an unknown X")? / 2.0);
            let c = (centre.z.ok_or("an arc centre without Z")?, centre.x.ok_or("an arc centre without X")? / 2.0);
            ((sz, sr), (sz + d[2], sr + d[0]), c, d[1])
        }
    };
    let angle = |p: (f64, f64)| (p.1 - c.1).atan2(p.0 - c.0);
    let r = (s.0 - c.0).hypot(s.1 - c.1);
    let turn = match dir {
        ArcDirection::CounterClockwise => angle(e) - angle(s),
        ArcDirection::Clockwise => angle(s) - angle(e),
    };
    let mut sweep = turn.rem_euclid(TAU);
    if sweep < 1e-12 {
        sweep = TAU;
    }
    Ok((r * sweep).hypot(across))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_block_reaching_its_feed_cruises() {
        let t = trapezoid(100.0, 6000.0, 1000.0).unwrap();
        assert_eq!(t.peak, 100.0);
        assert!((t.total - 1.1).abs() < 1e-12);
    }

    #[test]
    fn axis_velocities_by_direction_cosines() {
        let v = axis_velocities(&[3.0, 4.0], 10.0);
        assert!((v[0] - 6.0).abs() < 1e-12 && (v[1] - 8.0).abs() < 1e-12);
    }
}
