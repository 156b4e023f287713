//! Replaces a spiral piece by a tangent-continuous chain of circular arcs that stays within a
//! tolerance H of the curve on both sides (docs/domain.md §5). See docs/cam.md for why this is near
//! the fewest arcs possible.
//!
//! The fitter keeps every joint (knot) of the chain on the curve. An arc that leaves a knot
//! along the previous arc's end tangent and ends at a given curve point is unique, so a whole
//! chain is fixed by the first arc's start tangent and the knot parameters. Each arc is made as
//! long as the tolerance allows (greedy), and the start tangent is chosen by a search that
//! minimises the number of arcs (shooting). The last arc ends exactly at the piece's end point
//! because that end point is simply the last knot.
//!
//! Why this is near-minimal: where the curvature changes linearly along the curve, the error of
//! an arc is a cubic in arc length. With no continuity a circle can level it to ±H at four
//! points (the lower bound, [`lower_bound`]); a tangent-continuous chain in steady state can
//! only level it at interior points with the joints on the curve, and reaches 1/1.155 of that
//! length per arc. The greedy chain started with the right tangent settles into that steady
//! state, so it needs about 1.15 times the lower bound.

use nalgebra::{Matrix4, Point2, Vector2, Vector4};

use super::arc::{arc_through, end_tangent, Arc, Turn};
use super::piece::{cross, Piece, PieceKind};
use crate::geometry::{ensure, GeometryError};

/// The most arcs one piece may need before the tolerance is called too small.
pub const MAX_ARCS_PER_PIECE: usize = 1000;

/// The fitter aims at (1 − MARGIN)·H so that what its sampled search misses stays inside H.
const MARGIN: f64 = 1e-3;

/// Samples per arc when searching the largest error of a trial arc; the error is a smooth
/// function with at most two interior extrema, and each extremum is refined afterwards.
const TRIAL_SAMPLES: usize = 12;

/// Where the arcs may lie with respect to the cam's profile.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Side {
    /// Away from the cam centre: an outer cam finished from the material side comes out never
    /// undersize (the paper's arcs "envelop the theoretical curve from outside").
    #[default]
    Outside,
    /// Towards the cam centre: an inner profile (a groove's inner wall) finished from its
    /// material side.
    Inside,
    /// Either side, within the tolerance: the fewest arcs.
    Both,
}

impl Side {
    /// `"outside"`, `"inside"` or `"both"`.
    pub fn word(self) -> &'static str {
        match self {
            Side::Outside => "outside",
            Side::Inside => "inside",
            Side::Both => "both",
        }
    }
}

/// Fits `piece` with arcs that lie on `side` of it: for [`Side::Outside`] every arc point is
/// between `reserve` and `tolerance` mm from the profile, away from the cam centre (towards it
/// for [`Side::Inside`]), and the profile is within `tolerance` of the arcs; `reserve` keeps
/// room for what the written program's rounding moves the arcs. [`Side::Both`] is
/// [`fit_piece`] (within `tolerance` either side; `reserve` unused).
///
/// The one-sided fit is the two-sided fit, with half the band, of the curve at the band's
/// middle: the profile offset by (reserve + tolerance)/2. Its chain starts and ends on that
/// offset curve, off the profile's ends by the same distance, so consecutive pieces of a cam
/// are joined by a short straight move (in the band too).
pub fn fit_piece_on_side(piece: &Piece, tolerance: f64, side: Side, reserve: f64) -> Result<Vec<Arc>, GeometryError> {
    match side_curve(piece, tolerance, side, reserve)? {
        None => fit_piece(piece, tolerance),
        Some((curve, half_band)) => fit_piece(&curve, half_band),
    }
}

/// For a one-sided fit, the curve the arcs aim at (the profile offset to the band's middle)
/// and the half width of the band; `None` for [`Side::Both`]. Checks the tolerance first.
pub fn side_curve(
    piece: &Piece,
    tolerance: f64,
    side: Side,
    reserve: f64,
) -> Result<Option<(Piece, f64)>, GeometryError> {
    let sign = match side {
        Side::Both => return Ok(None),
        Side::Outside => 1.0,
        Side::Inside => -1.0,
    };
    check_tolerance(piece, tolerance)?;
    ensure(reserve.is_finite() && reserve >= 0.0 && reserve < tolerance, || {
        format!(
            "tolerance tol = {tolerance} mm leaves no band on the {} after {reserve} mm kept for the program's rounding",
            side.word()
        )
    })?;
    let half_band = 0.5 * (tolerance - reserve);
    let middle = 0.5 * (tolerance + reserve);
    if piece.kind != PieceKind::Circle {
        let radius = smallest_radius_of_curvature(piece);
        ensure(middle < radius, || {
            format!(
                "tolerance tol = {tolerance} mm is not small beside the profile's smallest radius of curvature \
                 {radius:.4} mm: no curve at that distance on the {}",
                side.word()
            )
        })?;
    }
    Ok(Some((piece.offset_outward(sign * middle), half_band)))
}

/// Where the offset curves of two pieces that meet at a corner cross, as (parameter on the
/// first, parameter on the second), when they do so near the corner: on the side where the
/// corner's angle is the smaller one, each offset runs past the other, and each must stop at
/// the crossing or its arcs would come closer to the other piece than the band allows (or
/// cross it). `None` where they do not cross (they diverge, and a short straight move joins
/// them) or where they meet already.
pub fn offset_crossing(first: &Piece, second: &Piece) -> Option<(f64, f64)> {
    let (mut s, mut u) = (1.0, 0.0);
    if (first.point(s) - second.point(u)).norm() <= 1e-12 {
        return None;
    }
    for _ in 0..60 {
        let (a, b) = (first.jet(s), second.jet(u));
        let f = a.p - b.p;
        let det = cross(a.d1, -b.d1);
        if det.abs() < 1e-300 {
            return None;
        }
        // [a.d1  −b.d1]·(ds, du) = −f by Cramer's rule.
        let ds = cross(-f, -b.d1) / det;
        let du = cross(a.d1, -f) / det;
        s += ds;
        u += du;
        if !(s.is_finite() && u.is_finite()) || s < -1.0 || u > 2.0 {
            return None;
        }
        if ds.abs() + du.abs() < 1e-15 {
            break;
        }
    }
    let meets = (first.point(s) - second.point(u)).norm() <= 1e-9;
    (meets && (0.0..1.0).contains(&s) && u > 0.0 && u <= 1.0).then_some((s, u))
}

/// The smallest radius of curvature of a profile piece, sampled (the pieces here curve
/// smoothly, the parabolic one with a jump at its middle).
fn smallest_radius_of_curvature(piece: &Piece) -> f64 {
    const STEPS: usize = 256;
    (0..=STEPS).map(|i| 1.0 / piece.curvature(i as f64 / STEPS as f64).abs()).fold(f64::INFINITY, f64::min)
}

/// Fits `piece` with arcs within `tolerance` mm, or says why it cannot.
pub fn fit_piece(piece: &Piece, tolerance: f64) -> Result<Vec<Arc>, GeometryError> {
    check_tolerance(piece, tolerance)?;
    if piece.kind == PieceKind::Circle {
        return Ok(vec![circle_arc(piece)]);
    }
    let mut margin = MARGIN;
    for _ in 0..4 {
        let run = best_run(piece, tolerance * (1.0 - margin))?;
        let arcs = to_arcs(piece, &run)?;
        if max_trial_error(piece, &run, 8 * TRIAL_SAMPLES) <= tolerance {
            return Ok(arcs);
        }
        // The coarse search underestimated an error: aim lower and fit again.
        margin *= 4.0;
    }
    Err(GeometryError::OutOfRange(format!(
        "could not keep the arcs within tolerance {tolerance} mm of this piece (numerical limit)"
    )))
}

/// The fewest arcs with which any arc chain, even one with no continuity at all, stays within
/// `tolerance` of `piece`: the curve split greedily into the longest parts that one minimax
/// circle each fits within the tolerance.
pub fn lower_bound(piece: &Piece, tolerance: f64) -> Result<usize, GeometryError> {
    check_tolerance(piece, tolerance)?;
    if piece.kind == PieceKind::Circle {
        return Ok(1);
    }
    let mut t = 0.0;
    let mut count = 0;
    let mut last_step = 1.0;
    while t < 1.0 {
        let ta = t;
        let step = longest(1.0 - ta, last_step, tolerance, |l| minimax_circle_error(piece, ta, ta + l));
        count += 1;
        ensure(count <= MAX_ARCS_PER_PIECE, || too_many(tolerance))?;
        t = if step >= 1.0 - ta { 1.0 } else { ta + step };
        last_step = step;
    }
    Ok(count)
}

/// An estimate of the arc count from the curvature's rate of change: ∫ (|κ′|/(32·H))^(1/3) ds
/// is the lower bound for curvature that changes linearly. Used to refuse hopeless tolerances
/// before fitting and to scale the start-tangent search.
pub fn estimate_arcs(piece: &Piece, tolerance: f64) -> f64 {
    const STEPS: usize = 32;
    let mut sum = 0.0;
    for i in 0..STEPS {
        let (ta, tb) = (i as f64 / STEPS as f64, (i + 1) as f64 / STEPS as f64);
        let ds = (piece.point(tb) - piece.point(ta)).norm();
        let dk = (piece.curvature(tb) - piece.curvature(ta)).abs();
        if ds > 0.0 {
            sum += (dk / ds / (32.0 * tolerance)).cbrt() * ds;
        }
    }
    sum
}

/// How far the arcs stray from the curve, measured both ways.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deviation {
    /// The largest distance from a curve point to the nearest arc.
    pub curve_to_arcs: f64,
    /// The largest distance from an arc point to the curve.
    pub arcs_to_curve: f64,
}

impl Deviation {
    pub fn max(&self) -> f64 {
        self.curve_to_arcs.max(self.arcs_to_curve)
    }
}

/// Two-sided deviation by dense sampling with exact point-to-arc and point-to-curve distances:
/// `samples_per_arc` points on every arc, and as many points on the curve in total. An
/// independent check of [`fit_piece`], which estimates errors its own way.
pub fn deviation(piece: &Piece, arcs: &[Arc], samples_per_arc: usize) -> Deviation {
    let n_curve = (samples_per_arc * arcs.len()).max(1000);
    let mut curve_to_arcs: f64 = 0.0;
    for i in 0..=n_curve {
        let q = piece.point(i as f64 / n_curve as f64);
        let nearest = arcs.iter().map(|a| a.distance(q)).fold(f64::INFINITY, f64::min);
        curve_to_arcs = curve_to_arcs.max(nearest);
    }
    let mut arcs_to_curve: f64 = 0.0;
    let mut hint = 0.0;
    for a in arcs {
        for j in 0..=samples_per_arc {
            let q = a.point_at(j as f64 / samples_per_arc as f64);
            let from_hint = piece.nearest(q, hint);
            let from_angle = piece.nearest(q, piece.t_guess(q));
            let best = if from_hint.1 <= from_angle.1 { from_hint } else { from_angle };
            hint = best.0;
            arcs_to_curve = arcs_to_curve.max(best.1);
        }
    }
    Deviation { curve_to_arcs, arcs_to_curve }
}

fn check_tolerance(piece: &Piece, tolerance: f64) -> Result<(), GeometryError> {
    ensure(tolerance.is_finite() && tolerance > 0.0, || {
        format!("tolerance tol = {tolerance} must be greater than 0 mm")
    })?;
    let estimate = estimate_arcs(piece, tolerance);
    ensure(estimate <= MAX_ARCS_PER_PIECE as f64, || too_many(tolerance))
}

fn too_many(tolerance: f64) -> String {
    format!("tolerance tol = {tolerance} mm is too small: this piece would need more than {MAX_ARCS_PER_PIECE} arcs")
}

/// A circle piece is cut by one arc about the cam centre (of the offset radius when the piece
/// is offset).
fn circle_arc(piece: &Piece) -> Arc {
    let turn = if piece.sweep() > 0.0 { Turn::Ccw } else { Turn::Cw };
    let radius = piece.r0 + piece.offset();
    Arc { start: piece.point(0.0), end: piece.point(1.0), centre: Point2::origin(), radius, turn }
}

/// A joint of the chain: a curve point and the tangent the arc leaving it must have.
#[derive(Clone, Copy, Debug)]
struct Knot {
    t: f64,
    p: Point2<f64>,
    tangent: Vector2<f64>,
}

/// One greedy chain: its knots, from the start point to the end point.
#[derive(Clone, Debug)]
struct Run {
    knots: Vec<Knot>,
}

impl Run {
    fn n_arcs(&self) -> usize {
        self.knots.len() - 1
    }

    /// Fewer arcs first; among equal counts, the one whose last arc has the least left to do,
    /// which leaves the most slack.
    fn score(&self) -> (usize, f64) {
        (self.n_arcs(), -self.knots[self.knots.len() - 2].t)
    }
}

fn better(a: &Option<Run>, b: &Option<Run>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => a.score() < b.score(),
        (Some(_), None) => true,
        _ => false,
    }
}

/// The best chain over start tangents turned by α from the curve's tangent. The α that gives
/// the steady state is about ±10·H/L for arcs of length L, so a scan over ±24·H/L, with L the
/// estimated arc length, brackets it. The scan keeps the α whose first two arcs reach farthest
/// (as every later arc is chosen); chains from it and a few neighbours are then compared by
/// their arc count.
fn best_run(piece: &Piece, h: f64) -> Result<Run, GeometryError> {
    let n_estimate = estimate_arcs(piece, h).max(1.0);
    let first_length = piece.length() / n_estimate;
    let mut half_width = (24.0 * h / first_length).min(0.5);
    let reach = |alpha: f64| lookahead_step(piece, &start_knot(piece, alpha), h, 1.0).1;
    let mut centre = 0.0;
    for steps in [6, 2, 2] {
        let alphas = (-steps..=steps).map(|i| centre + half_width * i as f64 / steps as f64);
        centre = alphas.map(|a| (a, reach(a))).max_by(|x, y| x.1.total_cmp(&y.1)).map_or(centre, |x| x.0);
        half_width /= steps as f64;
    }
    let mut best: Option<Run> = None;
    for i in -2..=2 {
        let run = greedy(piece, centre + half_width * i as f64, h);
        if better(&run, &best) {
            best = run;
        }
    }
    best.ok_or_else(|| GeometryError::OutOfRange(too_many(h)))
}

fn start_knot(piece: &Piece, alpha: f64) -> Knot {
    let (sin, cos) = alpha.sin_cos();
    let t0 = piece.tangent(0.0);
    let tangent = Vector2::new(cos * t0.x - sin * t0.y, sin * t0.x + cos * t0.y);
    Knot { t: 0.0, p: piece.point(0.0), tangent }
}

/// The chain that starts along the curve tangent turned by `alpha` and makes every arc as long
/// as `h` allows, looking one arc ahead. `None` when it needs more than the limit.
fn greedy(piece: &Piece, alpha: f64, h: f64) -> Option<Run> {
    let mut knots = vec![start_knot(piece, alpha)];
    let mut last_step = 1.0;
    loop {
        let k = *knots.last().expect("the start knot");
        let (step, _) = lookahead_step(piece, &k, h, last_step);
        let t = if step >= 1.0 - k.t { 1.0 } else { k.t + step };
        knots.push(next_knot(piece, &k, t));
        if t >= 1.0 {
            return Some(Run { knots });
        }
        if knots.len() > MAX_ARCS_PER_PIECE || step <= 0.0 {
            return None;
        }
        last_step = step;
    }
}

fn next_knot(piece: &Piece, k: &Knot, t: f64) -> Knot {
    let p = piece.point(t);
    Knot { t, p, tangent: end_tangent(k.tangent, k.p, p) }
}

/// The longest arc from knot `k` within `h`, as a step in t.
fn longest_step(piece: &Piece, k: &Knot, h: f64, guess: f64) -> f64 {
    longest(1.0 - k.t, guess, h, |l| trial_error(piece, k, k.t + l, TRIAL_SAMPLES))
}

/// The step from knot `k` that carries this arc and the next one farthest, and that reach (in
/// t; 2 when this arc reaches the end). The longest arc alone can leave a tangent from which
/// the next arc must be short (the steady state is unstable on one side); giving up a little
/// length now avoids that.
fn lookahead_step(piece: &Piece, k: &Knot, h: f64, guess: f64) -> (f64, f64) {
    let l_max = longest_step(piece, k, h, guess);
    if l_max >= 1.0 - k.t {
        return (l_max, 2.0);
    }
    let reach = |l: f64| {
        let next = next_knot(piece, k, k.t + l);
        l + longest_step(piece, &next, h, l)
    };
    const TRIES: usize = 6;
    let mut best = (l_max, reach(l_max));
    for i in 1..=TRIES {
        let l = l_max * (1.0 - 0.3 * i as f64 / TRIES as f64);
        let r = reach(l);
        if r > best.1 {
            best = (l, r);
        }
    }
    best
}

fn to_arcs(piece: &Piece, run: &Run) -> Result<Vec<Arc>, GeometryError> {
    run.knots
        .windows(2)
        .map(|w| {
            arc_through(w[0].p, w[0].tangent, w[1].p).ok_or_else(|| {
                GeometryError::OutOfRange(format!(
                    "{} piece {}°–{}° is straight to within rounding: no arc radius for it",
                    piece.kind.word(),
                    piece.phi0_deg,
                    piece.phi1_deg
                ))
            })
        })
        .collect()
}

fn max_trial_error(piece: &Piece, run: &Run, samples: usize) -> f64 {
    run.knots.windows(2).map(|w| trial_error(piece, &w[0], w[1].t, samples)).fold(0.0, f64::max)
}

/// The largest distance between the curve from knot `k` to parameter `tb` and the arc from the
/// knot (along its tangent) to C(tb). It is measured from curve points to the arc's circle with
/// a signed distance that stays exact for nearly straight arcs; the extremes are found on
/// `samples` points and then refined by golden-section search.
fn trial_error(piece: &Piece, k: &Knot, tb: f64, samples: usize) -> f64 {
    let chord = piece.point(tb) - k.p;
    let curvature = 2.0 * cross(k.tangent, chord) / chord.norm_squared();
    let normal = Vector2::new(-k.tangent.y, k.tangent.x);
    let offset = |t: f64| {
        let w = piece.point(t) - k.p;
        let a = curvature * w.norm_squared() - 2.0 * w.dot(&normal);
        a / (1.0 + (1.0 + curvature * a).max(0.0).sqrt())
    };
    extreme_abs(offset, k.t, tb, samples)
}

/// max |f| over [a, b], from `samples` intervals and a refinement of the largest and the
/// smallest sample.
fn extreme_abs(f: impl Fn(f64) -> f64, a: f64, b: f64, samples: usize) -> f64 {
    let h = (b - a) / samples as f64;
    let (mut top, mut bottom) = ((a, f64::NEG_INFINITY), (a, f64::INFINITY));
    for i in 0..=samples {
        let t = a + h * i as f64;
        let v = f(t);
        if v > top.1 {
            top = (t, v);
        }
        if v < bottom.1 {
            bottom = (t, v);
        }
    }
    let top = refine_peak(&f, top.0, top.1, h, (a, b));
    let bottom = -refine_peak(|t| -f(t), bottom.0, -bottom.1, h, (a, b));
    top.abs().max(bottom.abs())
}

/// The top of a smooth `f` near the sample (x, fx) on a grid of spacing h: successive
/// parabolas through three points a shrinking distance apart. Two rounds leave an error far
/// below the fitter's margin for the cubic-like errors met here.
fn refine_peak(f: impl Fn(f64) -> f64, mut x: f64, mut fx: f64, h: f64, (a, b): (f64, f64)) -> f64 {
    let mut best = fx;
    let mut d = h;
    for _ in 0..2 {
        let (fl, fr) = (f((x - d).max(a)), f((x + d).min(b)));
        best = best.max(fl).max(fr);
        let curvature = fl - 2.0 * fx + fr;
        if curvature >= 0.0 {
            break;
        }
        x = (x + 0.5 * (fl - fr) / curvature * d).clamp((x - d).max(a), (x + d).min(b));
        fx = f(x);
        best = best.max(fx);
        d *= 0.25;
    }
    best
}

/// The largest l in (0, l_max] with error(l) ≤ h, for an error that grows with l roughly like a
/// power of it (0 at l = 0). Each step assumes error ∝ l^m with m taken from the last two
/// evaluations, kept inside the bracket; it stops within 1e-4·h below h, which shortens an arc by
/// about 1e-4/3 of its length.
fn longest(l_max: f64, guess: f64, h: f64, error: impl Fn(f64) -> f64) -> f64 {
    let e_max = error(l_max);
    if e_max <= h {
        return l_max;
    }
    let (mut lo, mut hi) = (0.0, l_max);
    let mut prev: Option<(f64, f64)> = Some((l_max, e_max));
    let mut l = guess.clamp(l_max * 1e-9, l_max * (1.0 - 1e-9));
    for _ in 0..100 {
        let e = error(l);
        if e <= h {
            lo = l;
            if e >= h * (1.0 - 1e-4) {
                break;
            }
        } else {
            hi = l;
        }
        if hi - lo <= 1e-14 * l_max.max(1.0) {
            break;
        }
        let exponent = match prev {
            Some((lp, ep)) if e > 0.0 && ep > 0.0 && lp != l => ((ep / e).ln() / (lp / l).ln()).clamp(0.5, 8.0),
            _ => 3.0,
        };
        let mut next = if e > 0.0 { l * (h / e).powf(1.0 / exponent) } else { 2.0 * l };
        if !(next > lo && next < hi && next.is_finite()) {
            next = if lo > 0.0 { (lo * hi).sqrt() } else { 0.5 * hi };
        }
        prev = Some((l, e));
        l = next;
    }
    lo
}

/// Error of the best (minimax) circle through the curve part [ta, tb], by the Remez exchange:
/// the error |C(t) − M| − R of the best circle alternates ±E at four points (its three
/// parameters plus one), the two ends and two interior extremes. Once the exchange settles,
/// returns the levelled |E|, which does not exceed the true minimax error, so counts built on it
/// stay lower bounds. Where it does not settle (parts far from any circle, whose error has more
/// extremes, far longer than any part a fit uses) it returns the error of the circle found,
/// which only says "too long" sooner.
fn minimax_circle_error(piece: &Piece, ta: f64, tb: f64) -> f64 {
    const N: usize = 48;
    let d = tb - ta;
    let h = d / N as f64;
    let at = |i: usize| ta + h * i as f64;
    let mut nodes = [ta, ta + 0.25 * d, ta + 0.75 * d, tb];
    let (mut centre, mut radius) = circle_through(piece.point(ta), piece.point(ta + 0.5 * d), piece.point(tb));
    let mut level = 0.0;
    let mut worst = f64::INFINITY;
    for _ in 0..12 {
        (centre, radius, level) = level_circle(piece, nodes, centre, radius, level);
        let err = |t: f64| (piece.point(t) - centre).norm() - radius;
        let sign = if level >= 0.0 { 1.0 } else { -1.0 };
        // The error runs +E, −E, +E, −E (times `sign`): u2 is the highest interior peak, u1
        // the lowest valley before it.
        let v: Vec<f64> = (0..=N).map(|i| sign * err(at(i))).collect();
        worst = v.iter().fold(0.0, |m: f64, e| m.max(e.abs()));
        let peaks = (1..N).filter(|&i| v[i] >= v[i - 1] && v[i] >= v[i + 1]);
        let Some(i2) = peaks.max_by(|&i, &j| v[i].total_cmp(&v[j])) else { break };
        let valleys = (1..i2).filter(|&i| v[i] <= v[i - 1] && v[i] <= v[i + 1]);
        let Some(i1) = valleys.min_by(|&i, &j| v[i].total_cmp(&v[j])) else { break };
        let u2 = golden_arg(|t| sign * err(t), at(i2 - 1), at(i2 + 1));
        let u1 = golden_arg(|t| -sign * err(t), at(i1 - 1), at(i1 + 1));
        worst = [u1, u2].iter().fold(worst, |m, &t| m.max(err(t).abs()));
        if worst <= level.abs() * (1.0 + 1e-6) + 1e-15 {
            return level.abs();
        }
        if !(ta < u1 && u1 < u2 && u2 < tb) {
            break;
        }
        nodes = [ta, u1, u2, tb];
    }
    worst.max(level.abs())
}

/// Newton's method on |C(u_j) − M| − R = (−1)^j·E for the four nodes.
fn level_circle(
    piece: &Piece,
    nodes: [f64; 4],
    centre: Point2<f64>,
    radius: f64,
    level: f64,
) -> (Point2<f64>, f64, f64) {
    let points = nodes.map(|t| piece.point(t));
    let mut x = Vector4::new(centre.x, centre.y, radius, level);
    for _ in 0..8 {
        let mut jac = Matrix4::zeros();
        let mut res = Vector4::zeros();
        for (j, p) in points.iter().enumerate() {
            let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
            let w = Vector2::new(p.x - x[0], p.y - x[1]);
            let dist = w.norm();
            res[j] = dist - x[2] - sign * x[3];
            jac[(j, 0)] = -w.x / dist;
            jac[(j, 1)] = -w.y / dist;
            jac[(j, 2)] = -1.0;
            jac[(j, 3)] = -sign;
        }
        let Some(step) = jac.lu().solve(&(-res)) else { break };
        x += step;
        if step.norm() <= 1e-13 * x[2].abs() {
            break;
        }
    }
    (Point2::new(x[0], x[1]), x[2], x[3])
}

/// The circle through three points (centre, radius).
fn circle_through(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>) -> (Point2<f64>, f64) {
    let (ab, ac) = (b - a, c - a);
    let det = 2.0 * cross(ab, ac);
    let (nb, nc) = (ab.norm_squared(), ac.norm_squared());
    let offset = Vector2::new(ac.y * nb - ab.y * nc, ab.x * nc - ac.x * nb) / det;
    (a + offset, offset.norm())
}

/// Where a unimodal `f` peaks on [a, b].
fn golden_arg(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_895;
    for _ in 0..40 {
        let c = b - INV_PHI * (b - a);
        let d = a + INV_PHI * (b - a);
        if f(c) > f(d) {
            b = d;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}
