//! The trapezoidal velocity profile of docs/domain.md §4: each block starts and ends at rest,
//! accelerates at a constant a to the programmed feed v, cruises, and brakes at a; a block
//! too short to reach v is a triangle peaking at √(a·L). Axis velocities follow by the
//! direction cosines δᵢ/√(Σδ²), without trigonometry.

use std::f64::consts::TAU;

use super::program::{ArcDirection, Block, FeedMode, Machine, Program, Spindle, Target};

/// Why a time cannot be given: the block at fault.
pub type MotionError = super::program::BlockError;

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
/// revolution are turned into mm/min with the spindle's speed: fixed (G97), or under constant
/// surface speed (G96) 1000·v/(π·D) at the diameter D the tool is at, never above the
/// spindle limit (G50 S / LIMS=), so that it varies along a cut across the diameter. A block
/// that only sets the feed (`G1 F100`) takes no time.
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
            Block::Line { to, feed: Some(f) } if *to == Target::default() => feed = Some(*f),
            Block::Rapid(t) | Block::Line { to: t, .. } | Block::Arc { to: t, .. } => {
                let end = moved(&at, t);
                let (kind, path) = match block {
                    Block::Rapid(_) => ("rapid", Path::Line),
                    Block::Line { feed: f, .. } => {
                        feed = f.or(feed);
                        ("line", Path::Line)
                    }
                    Block::Arc { direction, centre, feed: f, .. } => {
                        feed = f.or(feed);
                        ("arc", Path::Arc { centre, direction: *direction })
                    }
                    _ => unreachable!("only moves reach here"),
                };
                let length = match path {
                    // A rapid may set an axis no move has set yet: the standard safe approach
                    // raises Z, then moves over in XY from wherever the machine stood. The
                    // travel of an axis from an unknown place is unknown; it counts as none.
                    Path::Line if kind == "rapid" => line_length(program.machine, &known_from(&at, &end), &end),
                    Path::Line => line_length(program.machine, &at, &end),
                    Path::Arc { centre, direction } => arc_length(program.machine, &at, &end, centre, direction),
                }
                .map_err(fail)?;
                let time = if kind == "rapid" {
                    constant_time(length, m.rapid, m.accel)
                } else {
                    let rate = FeedRate::new(feed, mode, &spindle, program.machine).map_err(fail)?;
                    cut_time(program.machine, &at, &end, path, length, rate, m.accel)
                }
                .map_err(fail)?;
                out.push(BlockTime { block: i + 1, kind, length, ..time });
                at = end;
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The start of a rapid with every axis it sets for the first time taken as already there.
fn known_from(at: &[Option<f64>; 3], end: &[Option<f64>; 3]) -> [Option<f64>; 3] {
    let mut from = *at;
    for i in 0..3 {
        if from[i].is_none() && at.iter().any(Option::is_some) {
            from[i] = end[i];
        }
    }
    from
}

fn moved(at: &[Option<f64>; 3], t: &Target) -> [Option<f64>; 3] {
    [t.x.or(at[0]), t.y.or(at[1]), t.z.or(at[2])]
}

/// The shape of a cutting block, for the diameter along it.
#[derive(Clone, Copy)]
enum Path<'a> {
    Line,
    Arc { centre: &'a Target, direction: ArcDirection },
}

/// The feed along the path in mm/min: fixed, or per revolution at a spindle speed that
/// depends on the diameter (constant surface speed).
#[derive(Clone, Copy, Debug)]
enum FeedRate {
    Fixed(f64),
    /// F mm/rev at 1000·v/(π·D) 1/min (v in m/min), at most `max_rpm`.
    SurfaceSpeed {
        per_rev: f64,
        metres_per_min: f64,
        max_rpm: f64,
    },
}

impl FeedRate {
    fn new(feed: Option<f64>, mode: FeedMode, spindle: &Spindle, machine: Machine) -> Result<FeedRate, String> {
        let f = feed.ok_or("a cut with no feed programmed (F) before it")?;
        match (mode, *spindle) {
            (FeedMode::PerMinute, _) => Ok(FeedRate::Fixed(f)),
            (FeedMode::PerRevolution, Spindle::Rpm { rpm, .. }) => Ok(FeedRate::Fixed(f * rpm)),
            (FeedMode::PerRevolution, Spindle::SurfaceSpeed { .. }) if machine != Machine::Lathe => {
                Err("constant surface speed on a mill: no diameter to turn it into a spindle speed".into())
            }
            (FeedMode::PerRevolution, Spindle::SurfaceSpeed { metres_per_min, max_rpm, .. }) => {
                Ok(FeedRate::SurfaceSpeed { per_rev: f, metres_per_min, max_rpm })
            }
            (FeedMode::PerRevolution, Spindle::Stop) => Err("a feed per revolution with the spindle stopped".into()),
        }
    }

    /// mm/min with the tool at `diameter` (mm).
    fn at(&self, diameter: f64) -> f64 {
        match *self {
            FeedRate::Fixed(f) => f,
            FeedRate::SurfaceSpeed { per_rev, metres_per_min, max_rpm } => {
                let rpm = 1000.0 * metres_per_min / (std::f64::consts::PI * diameter.abs());
                per_rev * rpm.min(max_rpm)
            }
        }
    }
}

/// A block at one speed: the closed-form trapezoid (or triangle).
fn constant_time(length: f64, feed: f64, accel: f64) -> Result<BlockTime, String> {
    let profile = trapezoid(length, feed, accel)?;
    Ok(BlockTime { block: 0, kind: "", length, feed, profile: Some(profile), time: profile.total })
}

/// Segments a cut is divided into when its feed varies along it.
const SEGMENTS: usize = 4096;

/// A cutting block's time. At a feed that varies along the path (constant surface speed
/// across the diameter) the path is cut into [`SEGMENTS`] pieces, each with the feed at its
/// middle as its limit; the tool then accelerates and brakes at `accel` from rest to rest
/// under that limit, exactly per piece. The feed reported is the one at the block's start.
fn cut_time(
    machine: Machine,
    from: &[Option<f64>; 3],
    to: &[Option<f64>; 3],
    path: Path,
    length: f64,
    rate: FeedRate,
    accel: f64,
) -> Result<BlockTime, String> {
    let diameter_at = |fraction: f64| diameter_along(from, to, path, fraction);
    let surface_speed = matches!(rate, FeedRate::SurfaceSpeed { .. }) && machine == Machine::Lathe;
    let varies = surface_speed && (from[0] != to[0] || matches!(path, Path::Arc { .. }));
    let start_feed = match rate {
        FeedRate::Fixed(f) => f,
        FeedRate::SurfaceSpeed { .. } => rate.at(diameter_at(0.0).ok_or(NO_DIAMETER)?),
    };
    if !varies {
        return constant_time(length, start_feed, accel);
    }
    if !(accel.is_finite() && accel > 0.0) {
        return Err(format!("the acceleration must be above 0 mm/s², not {accel}"));
    }
    let ds = length / SEGMENTS as f64;
    let mut limits = Vec::with_capacity(SEGMENTS);
    for k in 0..SEGMENTS {
        let d = diameter_at((k as f64 + 0.5) / SEGMENTS as f64).ok_or(NO_DIAMETER)?;
        limits.push(rate.at(d) / 60.0);
    }
    let time = limited_profile(&limits, ds, accel);
    Ok(BlockTime { block: 0, kind: "", length, feed: start_feed, profile: None, time })
}

const NO_DIAMETER: &str = "constant surface speed needs the diameter: a move that sets X before the cut";

/// The diameter (model X) a `fraction` of the way along a block.
fn diameter_along(from: &[Option<f64>; 3], to: &[Option<f64>; 3], path: Path, fraction: f64) -> Option<f64> {
    let (x0, x1) = (from[0]?, to[0]?);
    match path {
        Path::Line => Some(x0 + (x1 - x0) * fraction),
        Path::Arc { centre, direction } => {
            // In the lathe's plane (Z, X/2): the angle turns evenly along the arc.
            let (z0, z1) = (from[2]?, to[2]?);
            let (cz, cr) = (centre.z?, centre.x? / 2.0);
            let a0 = (x0 / 2.0 - cr).atan2(z0 - cz);
            let a1 = (x1 / 2.0 - cr).atan2(z1 - cz);
            let r = (z0 - cz).hypot(x0 / 2.0 - cr);
            let mut sweep = match direction {
                ArcDirection::CounterClockwise => (a1 - a0).rem_euclid(TAU),
                ArcDirection::Clockwise => -(a0 - a1).rem_euclid(TAU),
            };
            if sweep.abs() < 1e-12 {
                sweep = if direction == ArcDirection::CounterClockwise { TAU } else { -TAU };
            }
            Some(2.0 * (cr + r * (a0 + sweep * fraction).sin()))
        }
    }
}

/// Time (s) of a move from rest to rest over pieces of length `ds` with
/// speed limits `limits` (mm/s), at acceleration `a`: the speeds at the pieces' ends by a
/// forward (accelerating) and a backward (braking) pass, then each piece exactly: speed up
/// to its peak, cruise, brake to its end speed.
fn limited_profile(limits: &[f64], ds: f64, a: f64) -> f64 {
    let n = limits.len();
    let mut ends = vec![0.0f64; n + 1];
    for k in 1..n {
        ends[k] = limits[k - 1].min(limits[k]);
    }
    for k in 1..=n {
        ends[k] = ends[k].min((ends[k - 1] * ends[k - 1] + 2.0 * a * ds).sqrt());
    }
    for k in (0..n).rev() {
        ends[k] = ends[k].min((ends[k + 1] * ends[k + 1] + 2.0 * a * ds).sqrt());
    }
    let mut time = 0.0;
    for k in 0..n {
        let (u0, u1) = (ends[k], ends[k + 1]);
        let peak = limits[k].min(((u0 * u0 + u1 * u1) / 2.0 + a * ds).sqrt());
        let ramps = (2.0 * peak * peak - u0 * u0 - u1 * u1) / (2.0 * a);
        let cruise = if peak > 0.0 { (ds - ramps).max(0.0) / peak } else { 0.0 };
        time += (2.0 * peak - u0 - u1) / a + cruise;
    }
    time
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
    fn the_safe_approach_raise_z_then_over_in_xy_is_timed() {
        // G0 Z5, G0 X10 Y10 from wherever the machine stood, G1 Z0 F100: the cut is 5 mm
        // at 100/60 mm/s, which it reaches after (100/60)²/1000 mm; by hand 5/(5/3) + (5/3)/1000.
        let mut p = Program::new("P", Machine::Mill);
        p.blocks.push(Block::Rapid(Target { z: Some(5.0), ..Target::default() }));
        p.blocks.push(Block::Rapid(Target::xy(10.0, 10.0)));
        p.blocks.push(Block::Line { to: Target { z: Some(0.0), ..Target::default() }, feed: Some(100.0) });
        let times = program_times(&p, Rates { accel: 1000.0, rapid: 5000.0 }).unwrap();
        let cut = times.iter().find(|t| t.kind == "line").unwrap();
        assert!((cut.time - (3.0 + 5.0 / 3.0 / 1000.0)).abs() < 1e-9, "{times:?}");
        // A cut (not a rapid) into an axis no move has set stays refused.
        let mut q = Program::new("Q", Machine::Mill);
        q.blocks.push(Block::Rapid(Target { z: Some(5.0), ..Target::default() }));
        q.blocks.push(Block::Line { to: Target::xy(10.0, 10.0), feed: Some(100.0) });
        assert!(program_times(&q, Rates { accel: 1000.0, rapid: 5000.0 }).is_err());
    }

    #[test]
    fn axis_velocities_by_direction_cosines() {
        let v = axis_velocities(&[3.0, 4.0], 10.0);
        assert!((v[0] - 6.0).abs() < 1e-12 && (v[1] - 8.0).abs() < 1e-12);
    }
}
