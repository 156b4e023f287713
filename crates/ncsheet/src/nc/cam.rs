//! The milling program of a fitted cam (docs/domain.md §5), built on the NC model so that any
//! milling dialect writes it: a radial lead-in from outside the profile, every arc as a
//! circular move, straight moves across the gaps and steps of a partial cam, a radial
//! lead-out.

use nalgebra::{Point2, Vector2};

pub use super::program::Compensation;
use super::program::{ArcDirection, Block, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange};
pub use crate::geometry::cam::reach::Rounding;
use crate::geometry::cam::reach::{round_concave, CutterSide, Element};
use crate::geometry::cam::{Arc, CamFit, Turn};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CamNcOptions {
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed: f64,
    /// Spindle speed, 1/min (M3).
    pub spindle: f64,
    /// Clearance height above the disc: rapids over the part, the start and the end.
    pub z_safe: f64,
    /// Retract height: the rapid down ends here, the plunge at `plunge_feed` starts here.
    pub z_retract: f64,
    /// Cutting depth (negative: into the disc).
    pub z_cut: f64,
    /// Length of the lead-in and lead-out line, from the cutter's side of the profile: longer
    /// than the cutter's radius, so that compensation has room to come on (LinuxCNC refuses an
    /// entry move no longer than the radius) and the plunge is clear of the profile.
    pub lead: f64,
    /// A straight lead perpendicular to the profile, or a quarter arc of radius `lead`
    /// tangent to it after the straight move.
    pub lead_kind: LeadKind,
    /// The cutter's diameter, mm.
    pub cutter_diameter: f64,
    pub compensation: Compensation,
    /// The tool called at the start (its offset is the one G41/G42 use unless
    /// `radius_offset` names another).
    pub tool: u32,
    /// The register G41/G42 take the cutter's radius from (`D21`), where the dialect has
    /// one apart from the tool; `None`: the tool's own.
    pub radius_offset: Option<u32>,
}

/// How the cutter comes onto the profile and leaves it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeadKind {
    #[default]
    Line,
    Arc,
}

/// The default cutter (mm) and how much longer than its radius the default lead is.
pub const DEFAULT_CUTTER_DIAMETER: f64 = 10.0;
pub const LEAD_BEYOND_RADIUS: f64 = 2.0;

impl Default for CamNcOptions {
    fn default() -> CamNcOptions {
        CamNcOptions {
            feed: 200.0,
            plunge_feed: 100.0,
            spindle: 1000.0,
            z_safe: 5.0,
            z_retract: 2.0,
            z_cut: -12.0,
            lead: DEFAULT_CUTTER_DIAMETER / 2.0 + LEAD_BEYOND_RADIUS,
            lead_kind: LeadKind::Line,
            cutter_diameter: DEFAULT_CUTTER_DIAMETER,
            compensation: Compensation::Off,
            tool: 1,
            radius_offset: None,
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

/// The program for one disc, or why the approach cannot be made with these options (a lead
/// not longer than the cutter's radius, heights out of order, a plunge point the cutter would
/// cut the profile at).
pub fn cam_program(fit: &CamFit, options: &CamNcOptions) -> Result<Program, String> {
    cam_program_reporting(fit, options).map(|(program, _)| program)
}

/// [`cam_program`] and the concave places the cutter cannot reach with the control's
/// compensation, rounded in the program (`geometry::cam::reach`): each with the material it
/// leaves, for the user to be told.
pub fn cam_program_reporting(fit: &CamFit, options: &CamNcOptions) -> Result<(Program, Vec<Unreached>), String> {
    check_approach(options)?;
    let disc = if fit.disc.is_empty() { String::new() } else { format!("_{}", fit.disc) };
    let mut p = Program::new(&format!("CAM{disc}"), Machine::Mill);
    p.precision = Some(written_decimals(fit.tolerance));
    p.radius_offset = options.radius_offset;
    let arcs: Vec<&Arc> = fit.arcs().collect();
    p.push(Block::Comment(format!("ncsheet cam {}: {} arcs, tolerance {} mm", fit.disc, arcs.len(), fit.tolerance)));
    p.push(Block::Comment(format!(
        "cutter D{} T{}, depth {}, lead {} {} mm",
        options.cutter_diameter,
        options.tool,
        options.z_cut,
        if options.lead_kind == LeadKind::Arc { "arc" } else { "line" },
        options.lead
    )));
    let arcs = entry_order(arcs, options)?;
    let (Some(first), Some(last)) = (arcs.first(), arcs.last()) else { return Ok((p, Vec::new())) };
    let side = |a: &Arc, at: Point2<f64>| cutter_side(a, at, options.compensation);
    let lead_in = lead_path(first.start, tangent(first, first.start), side(first, first.start), options, true);
    let lead_out = lead_path(last.end, tangent(last, last.end), side(last, last.end), options, false);
    let reach = arcs.iter().map(|a| a.start.coords.norm().max(a.end.coords.norm())).fold(0.0, f64::max);
    p.blank = Some(([-reach, -reach, options.z_cut.min(0.0)], [reach, reach, 0.0]));
    let safe = Target { z: Some(options.z_safe), ..Target::default() };
    p.retract = Some(safe);
    p.push(Block::FeedMode(FeedMode::PerMinute));
    p.push(Block::Tool(ToolChange::new(options.tool)));
    p.push(Block::Spindle(Spindle::Rpm { rpm: options.spindle, direction: SpindleDirection::Clockwise }));
    // The lead-in's straight entry (and arc) are the chain's first moves: a concave corner
    // where the lead meets the profile is the control's to reach like any other.
    let (mut chain, roundings) = reachable_chain(&lead_in, &arcs, options);
    let Element::Line { start: plunge, end: entered } = chain.remove(0) else {
        unreachable!("reachable_chain starts with the lead's straight entry")
    };
    p.push(Block::Rapid(safe));
    p.push(Block::Rapid(Target::xy(plunge.x, plunge.y)));
    p.push(Block::Rapid(Target { z: Some(options.z_retract), ..Target::default() }));
    p.push(Block::Line { to: Target { z: Some(options.z_cut), ..Target::default() }, feed: Some(options.plunge_feed) });
    if options.compensation != Compensation::Off {
        p.push(Block::Compensation(options.compensation));
    }
    p.push(Block::Line { to: Target::xy(entered.x, entered.y), feed: Some(options.feed) });
    let roundings: Vec<Unreached> = roundings
        .into_iter()
        .map(|rounding| Unreached { at_entry: (rounding.at - lead_in.inner).norm() <= GAP, rounding })
        .collect();
    for u in &roundings {
        let r = &u.rounding;
        p.push(Block::Comment(format!(
            "concave place at X{:.3} Y{:.3}{} beyond the reach of the D{} cutter: rounded R{:.3}, {:.3} mm left",
            r.at.x,
            r.at.y,
            if u.at_entry { " (the entry)" } else { "" },
            options.cutter_diameter,
            r.arc.radius,
            r.left
        )));
    }
    for e in &chain {
        match e {
            Element::Line { end, .. } => {
                p.push(Block::Line { to: Target::xy(end.x, end.y), feed: None });
            }
            Element::Arc(a) => {
                let direction =
                    if a.turn == Turn::Ccw { ArcDirection::CounterClockwise } else { ArcDirection::Clockwise };
                let (to, centre) = (Target::xy(a.end.x, a.end.y), Target::xy(a.centre.x, a.centre.y));
                p.push(Block::Arc { direction, to, centre, feed: None });
            }
        }
    }
    if let Some((centre, direction)) = lead_out.arc {
        p.push(Block::Arc {
            direction,
            to: Target::xy(lead_out.inner.x, lead_out.inner.y),
            centre: Target::xy(centre.x, centre.y),
            feed: None,
        });
    }
    if options.compensation != Compensation::Off {
        p.push(Block::Compensation(Compensation::Off));
    }
    p.push(Block::Line { to: Target::xy(lead_out.outer.x, lead_out.outer.y), feed: None });
    Ok((p, roundings))
}

/// A concave place the cutter cannot reach under the control's compensation, rounded in the
/// program; `at_entry` when it is where the lead meets the profile (a straight lead into a
/// move shorter than the pull-back the corner needs: an arc lead enters without a corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unreached {
    pub rounding: Rounding,
    pub at_entry: bool,
}

/// How much a rounding arc's radius exceeds the cutter's (mm): the control's offset of it is
/// then a small arc, not a point it would refuse, and the written decimals cannot make it
/// smaller than the cutter.
const ROUNDING_MARGIN: f64 = 0.01;

/// The lead-in and the profile as moves in cutting order (straight across the gaps and steps
/// of a partial cam), with the concave places the cutter cannot reach under compensation
/// rounded. The first move is the lead's straight entry; when a rounding shortens it, it
/// starts farther out along its line, so that the control still has the lead's length to
/// turn compensation on along.
fn reachable_chain(lead: &Lead, arcs: &[&Arc], o: &CamNcOptions) -> (Vec<Element>, Vec<Rounding>) {
    let first = arcs[0].start;
    let mut chain = Vec::with_capacity(arcs.len() + 4);
    chain.push(Element::Line { start: lead.outer, end: lead.inner });
    if let Some((centre, direction)) = lead.arc {
        let turn = if direction == ArcDirection::CounterClockwise { Turn::Ccw } else { Turn::Cw };
        let radius = (lead.inner - centre).norm();
        chain.push(Element::Arc(Arc { start: lead.inner, end: first, centre, radius, turn }));
    }
    let mut previous_end = first;
    for a in arcs {
        if (a.start - previous_end).norm() > GAP {
            // A gap or a step of a partial cam: straight across.
            chain.push(Element::Line { start: previous_end, end: a.start });
        }
        chain.push(Element::Arc(**a));
        previous_end = a.end;
    }
    let side = match o.compensation {
        Compensation::Left => CutterSide::Left,
        Compensation::Right => CutterSide::Right,
        // Without compensation the program is the path of the cutter's centre.
        Compensation::Off => return (chain, Vec::new()),
    };
    let radius = o.cutter_diameter / 2.0;
    let (mut chain, roundings) = round_concave(&chain, side, radius, radius + ROUNDING_MARGIN);
    if let Element::Line { start, end } = chain[0] {
        let length = (end - start).norm();
        if length < o.lead && length > 0.0 {
            chain[0] = Element::Line { start: end + (start - end) * (o.lead / length), end };
        }
    }
    (chain, roundings)
}

/// The arcs in cutting order from an entry the cutter can plunge at clear of the profile:
/// the first arc's start when it is, else (on a closed profile, which may be cut from any
/// joint) the first joint that is. An open profile is cut from its start or refused.
fn entry_order<'a>(arcs: Vec<&'a Arc>, o: &CamNcOptions) -> Result<Vec<&'a Arc>, String> {
    let (Some(first), Some(last)) = (arcs.first(), arcs.last()) else { return Ok(arcs) };
    if o.compensation == Compensation::Off {
        return Ok(arcs);
    }
    let radius = o.cutter_diameter / 2.0;
    let closed = (last.end - first.start).norm() <= GAP;
    let joints = if closed { arcs.len() } else { 1 };
    // On a closed profile the cutter's side is its outside or its inside: a plunge point on the
    // other side is in the material however far it is from the line.
    let outline = closed.then(|| outline(&arcs));
    let wants_outside =
        outline.as_ref().map(|poly| (signed_area(poly) > 0.0) == (o.compensation == Compensation::Right));
    let on_its_side = |q: Point2<f64>| match (&outline, wants_outside) {
        (Some(poly), Some(outside)) => inside(poly, q) != outside,
        _ => true,
    };
    let plunge_clearance = |k: usize| {
        let a = arcs[k];
        let lead = lead_path(a.start, tangent(a, a.start), cutter_side(a, a.start, o.compensation), o, true);
        let nearest = arcs.iter().map(|b| distance_to_arc(b, lead.outer)).fold(f64::INFINITY, f64::min);
        let sided = on_its_side(lead.outer) && on_its_side(lead.inner);
        (lead.outer, if sided { nearest } else { 0.0 })
    };
    for k in 0..joints {
        if plunge_clearance(k).1 > radius {
            let mut order = arcs[k..].to_vec();
            order.extend_from_slice(&arcs[..k]);
            return Ok(order);
        }
    }
    let (plunge, nearest) = plunge_clearance(0);
    Err(format!(
        "the plunge point X{:.3} Y{:.3} is {nearest:.3} mm from the profile, not clear of it for a cutter of radius \
         {radius} mm{}: a longer --lead, or a smaller cutter",
        plunge.x,
        plunge.y,
        if closed { ", nor is any other joint's" } else { "" }
    ))
}

/// A closed profile as a polygon through points of its arcs, 2° apart at most.
fn outline(arcs: &[&Arc]) -> Vec<Point2<f64>> {
    let mut points = Vec::new();
    for a in arcs {
        let sweep = a.sweep();
        let n = (sweep / 2f64.to_radians()).ceil().max(1.0) as usize;
        let a0 = (a.start.y - a.centre.y).atan2(a.start.x - a.centre.x);
        let turn = if a.turn == Turn::Ccw { 1.0 } else { -1.0 };
        for k in 0..n {
            let angle = a0 + turn * sweep * k as f64 / n as f64;
            points.push(a.centre + Vector2::new(angle.cos(), angle.sin()) * a.radius);
        }
    }
    points
}

/// The polygon's signed area, above 0 when it runs counter-clockwise.
fn signed_area(poly: &[Point2<f64>]) -> f64 {
    let n = poly.len();
    (0..n).map(|i| poly[i].x * poly[(i + 1) % n].y - poly[(i + 1) % n].x * poly[i].y).sum::<f64>() / 2.0
}

/// Whether `q` is inside the polygon (even-odd crossings of a ray along +x).
fn inside(poly: &[Point2<f64>], q: Point2<f64>) -> bool {
    let n = poly.len();
    let mut crossings = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            crossings = !crossings;
        }
    }
    crossings
}

/// The heights in order and a lead the control can turn compensation on along.
fn check_approach(o: &CamNcOptions) -> Result<(), String> {
    let finite = [o.z_safe, o.z_retract, o.z_cut, o.lead, o.cutter_diameter].iter().all(|v| v.is_finite());
    if !finite {
        return Err("the approach's heights, lead and cutter must be numbers".into());
    }
    if o.cutter_diameter <= 0.0 {
        return Err(format!("the cutter diameter must be above 0, not {}", o.cutter_diameter));
    }
    if !(o.z_safe >= o.z_retract && o.z_retract > o.z_cut && o.z_retract >= 0.0) {
        return Err(format!(
            "the heights must be clearance {} ≥ retract {} ≥ 0 (the disc's top) > cut depth Z{}",
            o.z_safe, o.z_retract, o.z_cut
        ));
    }
    let radius = o.cutter_diameter / 2.0;
    if o.compensation != Compensation::Off && o.lead <= radius {
        return Err(format!(
            "the lead {} mm is not longer than the cutter's radius {radius} mm: the control has no room to turn \
             compensation on (LinuxCNC: \"Length of cutter compensation entry move is not greater than the tool \
             radius\"); give --lead above {radius}",
            o.lead
        ));
    }
    if o.lead <= 0.0 {
        return Err(format!("the lead must be longer than 0 mm, not {}", o.lead));
    }
    Ok(())
}

/// A lead-in (or, walked backwards, a lead-out): the point away from the profile the cutter
/// plunges at (or leaves from), the point the straight part ends at, and the tangent quarter
/// arc from there onto the profile (its centre and direction) when the lead is an arc.
struct Lead {
    outer: Point2<f64>,
    inner: Point2<f64>,
    arc: Option<(Point2<f64>, ArcDirection)>,
}

/// The lead at profile point `at` with cutting direction `t`, on the cutter's side `s`: a
/// straight line along `s` of length `lead`; for an arc lead, a quarter circle of radius
/// `lead` tangent to the profile at `at` (centre at + lead·s), reached by the straight line.
/// `entering`: the lead-in (the arc ends on the profile); else the lead-out (starts there).
fn lead_path(at: Point2<f64>, t: Vector2<f64>, s: Vector2<f64>, o: &CamNcOptions, entering: bool) -> Lead {
    match o.lead_kind {
        LeadKind::Line => Lead { outer: at + s * o.lead, inner: at, arc: None },
        LeadKind::Arc => {
            let rho = o.lead;
            let centre = at + s * rho;
            // The quarter circle meets the profile going along t: before it (lead-in) it
            // starts a quarter turn back, at centre − ρ·t; the lead-out ends at centre + ρ·t.
            let inner = if entering { centre - t * rho } else { centre + t * rho };
            // Turning from −s (at the profile) toward ±t: clockwise when s is to the right.
            let right = s.perp(&t) > 0.0;
            let direction = if right { ArcDirection::Clockwise } else { ArcDirection::CounterClockwise };
            Lead { outer: inner + s * o.lead, inner, arc: Some((centre, direction)) }
        }
    }
}

/// The unit direction of travel along arc `a` at its point `p`.
fn tangent(a: &Arc, p: Point2<f64>) -> Vector2<f64> {
    let r = (p - a.centre).normalize();
    let ccw = Vector2::new(-r.y, r.x);
    if a.turn == Turn::Ccw {
        ccw
    } else {
        -ccw
    }
}

/// The side of the profile the cutter is on at `p`: right or left of the travel with
/// compensation, radially outward without (the program then follows the profile with the
/// cutter's centre).
fn cutter_side(a: &Arc, p: Point2<f64>, compensation: Compensation) -> Vector2<f64> {
    let t = tangent(a, p);
    match compensation {
        Compensation::Right => Vector2::new(t.y, -t.x),
        Compensation::Left => Vector2::new(-t.y, t.x),
        Compensation::Off => {
            if p.coords.norm() > 0.0 {
                p.coords.normalize()
            } else {
                Vector2::x()
            }
        }
    }
}

/// The distance from `q` to the arc `a` (its nearest point: on the arc's sweep, or an end).
pub fn distance_to_arc(a: &Arc, q: Point2<f64>) -> f64 {
    let to_q = q - a.centre;
    let ends = (q - a.start).norm().min((q - a.end).norm());
    if to_q.norm() == 0.0 {
        return a.radius.min(ends);
    }
    let angle = |v: Vector2<f64>| v.y.atan2(v.x);
    let (a0, aq) = (angle(a.start - a.centre), angle(to_q));
    let sweep = a.sweep();
    let along = match a.turn {
        Turn::Ccw => (aq - a0).rem_euclid(std::f64::consts::TAU),
        Turn::Cw => (a0 - aq).rem_euclid(std::f64::consts::TAU),
    };
    if along <= sweep {
        (to_q.norm() - a.radius).abs()
    } else {
        ends
    }
}
