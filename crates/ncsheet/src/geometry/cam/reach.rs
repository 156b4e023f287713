//! What a cutter of a given radius can reach along a profile cut with cutter compensation:
//! concave corners (and concave arcs) tighter than the cutter are rounded by a tangent arc
//! of the cutter's radius and a little more, the circle that rolls along the profile on the
//! cutter's side. A control with compensation refuses such a corner (LinuxCNC: "Arc move in
//! concave corner cannot be reached by the tool without gouging"); a CAM package leaves the
//! material there and says so. The rounded profile is what the cutter cuts, and the report
//! says where and how much is left.
//!
//! The profile is a chain of [`Element`]s in cutting order; the side is where the cutter is,
//! left or right of the travel (G41/G42).

use nalgebra::{Point2, Vector2};

use super::arc::{Arc, Turn};
use super::piece::cross;

/// A move of the profile: an arc, or a straight line (across a gap of a partial cam).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Element {
    Arc(Arc),
    Line { start: Point2<f64>, end: Point2<f64> },
}

/// Where the cutter is, seen along the travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutterSide {
    Left,
    Right,
}

impl CutterSide {
    fn sign(self) -> f64 {
        match self {
            CutterSide::Left => 1.0,
            CutterSide::Right => -1.0,
        }
    }
}

/// One rounded place: the corner (or the tightest point of the concave arcs) replaced, the
/// rounding arc, and the most material it leaves (mm, measured from the rounding arc to the
/// profile it replaces).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rounding {
    pub at: Point2<f64>,
    pub arc: Arc,
    pub left: f64,
}

/// Joints turning by less than this (radians) toward the cutter are tangent: not corners.
const TANGENT: f64 = 1e-7;

/// How many elements on each side of a corner a rounding arc may span before the search gives
/// up (a rounding that long would leave a profile nobody asked for).
const SPAN: usize = 64;

impl Element {
    pub fn start(&self) -> Point2<f64> {
        match self {
            Element::Arc(a) => a.start,
            Element::Line { start, .. } => *start,
        }
    }

    pub fn end(&self) -> Point2<f64> {
        match self {
            Element::Arc(a) => a.end,
            Element::Line { end, .. } => *end,
        }
    }

    /// Unit direction of travel at `p` (on the element).
    fn tangent_at(&self, p: Point2<f64>) -> Vector2<f64> {
        match self {
            Element::Arc(a) => a.tangent_at(p),
            Element::Line { start, end } => (end - start).normalize(),
        }
    }

    fn length(&self) -> f64 {
        match self {
            Element::Arc(a) => a.length(),
            Element::Line { start, end } => (end - start).norm(),
        }
    }

    /// Whether this arc bends toward the cutter more tightly than a cutter of radius `r`
    /// can follow: its offset by `r` on the cutter's side is empty.
    fn tighter_than(&self, r: f64, side: CutterSide) -> bool {
        matches!(self, Element::Arc(a) if offset_radius(a, r, side) <= 0.0)
    }

    /// The point of the element nearest to `q`, when it lies inside the element (not at an
    /// end beyond it): where a circle centred at `q` touches it.
    fn foot(&self, q: Point2<f64>) -> Option<Point2<f64>> {
        match self {
            Element::Arc(a) => {
                let radial = q - a.centre;
                if radial.norm() == 0.0 {
                    return None;
                }
                let p = a.centre + radial.normalize() * a.radius;
                let along = Arc { end: p, ..*a };
                let within = along.sweep() <= a.sweep() + 1e-12 || (p - a.start).norm() <= 1e-9;
                within.then_some(p)
            }
            Element::Line { start, end } => {
                let d = end - start;
                let u = (q - start).dot(&d) / d.norm_squared();
                (-1e-12..=1.0 + 1e-12).contains(&u).then(|| start + d * u.clamp(0.0, 1.0))
            }
        }
    }

    /// The distance from `q` to the element (its nearest point, an end included).
    fn distance(&self, q: Point2<f64>) -> f64 {
        match self {
            Element::Arc(a) => a.distance(q),
            Element::Line { .. } => match self.foot(q) {
                Some(p) => (q - p).norm(),
                None => (q - self.start()).norm().min((q - self.end()).norm()),
            },
        }
    }

    /// The element from its start to `p` (on it).
    fn ending_at(&self, p: Point2<f64>) -> Element {
        match *self {
            Element::Arc(a) => Element::Arc(Arc { end: p, ..a }),
            Element::Line { start, .. } => Element::Line { start, end: p },
        }
    }

    /// The element from `p` (on it) to its end.
    fn starting_at(&self, p: Point2<f64>) -> Element {
        match *self {
            Element::Arc(a) => Element::Arc(Arc { start: p, ..a }),
            Element::Line { end, .. } => Element::Line { start: p, end },
        }
    }
}

/// The radius of arc `a`'s offset by `rho` on the cutter's side (≤ 0: the arc bends toward
/// the cutter more tightly than `rho`).
fn offset_radius(a: &Arc, rho: f64, side: CutterSide) -> f64 {
    // Left of the travel is toward the centre on a counter-clockwise arc.
    let toward_centre = side.sign() * a.turn.sign() > 0.0;
    if toward_centre {
        a.radius - rho
    } else {
        a.radius + rho
    }
}

/// The profile `chain` as a cutter of radius `cutter` on `side` cuts it with the control's
/// compensation: every concave place the control cannot reach replaced by a tangent arc of
/// radius `rho` (above `cutter`, so that the control's offset of the rounding arc is not a
/// point), with a [`Rounding`] for each. A control reaches a concave corner where the offsets
/// of the two moves meeting there cross within them (LinuxCNC looks one move ahead); it does
/// not reach one where the cutter's circle would have to bridge further moves, nor an arc
/// bending toward the cutter more tightly than the cutter. Places where no rounding arc fits
/// within [`SPAN`] elements are left as they are (the control will say so).
pub fn round_concave(chain: &[Element], side: CutterSide, cutter: f64, rho: f64) -> (Vec<Element>, Vec<Rounding>) {
    let mut out: Vec<Element> = chain.to_vec();
    let mut roundings = Vec::new();
    let mut k = 0;
    // `k` walks the joints (between out[k] and out[k + 1]) and the tight arcs (out[k]).
    while k < out.len() {
        let tight = out[k].tighter_than(cutter, side);
        let corner = !tight
            && k + 1 < out.len()
            && concave_joint(&out[k], &out[k + 1], side)
            && !reached_by_the_control(&out[k], &out[k + 1], side, cutter);
        // A move between two concave corners the control reaches one by one, but which the
        // two pull-backs overlap on: the control's offset of it would run backwards.
        let swallowed = !(corner || tight) && k + 2 < out.len() && swallowed(&out[k..k + 3], side, cutter);
        if !(corner || tight || swallowed) {
            k += 1;
            continue;
        }
        // A tight arc is spanned from the element before it to the one after, a swallowed
        // move from the one before to the one after.
        let (before, after) = match (tight, swallowed) {
            (true, _) => (k.saturating_sub(1), k + 1),
            (false, true) => (k, k + 2),
            (false, false) => (k, k + 1),
        };
        match rounding_between(&out, before, after, side, rho, SPAN) {
            Some((i, j, centre, first_foot, last_foot)) => {
                let arc = rounding_arc(centre, first_foot, last_foot, rho, side);
                let left = material_left(&out[i..=j], &arc);
                let at = if tight { out[k].start() } else { out[k].end() };
                roundings.push(Rounding { at, arc, left });
                let mut replaced = Vec::with_capacity(3);
                if (first_foot - out[i].start()).norm() > 1e-9 {
                    replaced.push(out[i].ending_at(first_foot));
                }
                replaced.push(Element::Arc(arc));
                if (out[j].end() - last_foot).norm() > 1e-9 {
                    replaced.push(out[j].starting_at(last_foot));
                }
                let next = i + replaced.len() - 1;
                out.splice(i..=j, replaced);
                k = next;
            }
            None => k += 1,
        }
    }
    (out, roundings)
}

/// Whether the control's compensation reaches the concave corner where `a` meets `b`: the
/// cutter's circle touches both inside them.
fn reached_by_the_control(a: &Element, b: &Element, side: CutterSide, cutter: f64) -> bool {
    control_contact(a, b, side, cutter).is_some()
}

/// Where the cutter's circle touches `a` and `b` at their concave corner, as the control
/// places it (both inside the moves).
fn control_contact(a: &Element, b: &Element, side: CutterSide, cutter: f64) -> Option<(Point2<f64>, Point2<f64>)> {
    rounding_between(&[*a, *b], 0, 1, side, cutter, 1).map(|(_, _, _, fa, fb)| (fa, fb))
}

/// Whether the middle of three moves is swallowed: both its ends are concave corners the
/// control reaches, but the cutter leaves it (at the second corner) before it comes onto it
/// (at the first).
fn swallowed(three: &[Element], side: CutterSide, cutter: f64) -> bool {
    let [a, m, b] = three else { return false };
    if !(concave_joint(a, m, side) && concave_joint(m, b, side)) {
        return false;
    }
    match (control_contact(a, m, side, cutter), control_contact(m, b, side, cutter)) {
        (Some((_, on)), Some((off, _))) => along(m, on) > along(m, off) + 1e-9,
        _ => false,
    }
}

/// How far along element `e` its point `p` is (mm).
fn along(e: &Element, p: Point2<f64>) -> f64 {
    match e {
        Element::Arc(a) if (p - a.start).norm() > 1e-12 => (Arc { end: p, ..*a }).sweep() * a.radius,
        Element::Arc(_) => 0.0,
        Element::Line { start, end } => (p - start).dot(&(end - start).normalize()),
    }
}

/// Whether the travel turns toward the cutter where `a` meets `b`: a corner the cutter's
/// circle cannot follow into.
fn concave_joint(a: &Element, b: &Element, side: CutterSide) -> bool {
    let (ta, tb) = (a.tangent_at(a.end()), b.tangent_at(b.start()));
    let turn = cross(ta, tb).atan2(ta.dot(&tb));
    turn * side.sign() > TANGENT
}

/// A rounding circle's reach: the first and last elements it touches (indices), its centre,
/// and where it touches them.
type Span = (usize, usize, Point2<f64>, Point2<f64>, Point2<f64>);

/// The rounding circle for the place between elements `before` and `after`: the nearest
/// elements `i ≤ before`, `j ≥ after` whose offsets by `rho` meet at a centre that touches
/// both inside them and keeps `rho` from every element between (the circle rolls past
/// them on the cutter's side). Returns (i, j, centre, foot on i, foot on j).
fn rounding_between(
    chain: &[Element],
    before: usize,
    after: usize,
    side: CutterSide,
    rho: f64,
    spans: usize,
) -> Option<Span> {
    for span in 0..spans {
        for back in 0..=span {
            let (Some(i), j) = (before.checked_sub(back), after + (span - back)) else { continue };
            if j >= chain.len() {
                continue;
            }
            for (centre, fi, fj) in contacts(&chain[i], &chain[j], side, rho) {
                let clear = chain[i..=j].iter().all(|e| e.distance(centre) >= rho * (1.0 - 1e-9));
                let on_side = side_of(&chain[i], fi, centre) * side.sign() > 0.0;
                if clear && on_side {
                    return Some((i, j, centre, fi, fj));
                }
            }
        }
    }
    None
}

/// The circles of radius `rho` on the cutter's side that touch `a` and `b`: tangent to both
/// inside them, or tangent to one and through the other's end nearest the place (a corner
/// that bends away from the cutter, which the rolling circle turns about). Each with its
/// centre and where it touches `a` and `b`.
fn contacts(a: &Element, b: &Element, side: CutterSide, rho: f64) -> Vec<(Point2<f64>, Point2<f64>, Point2<f64>)> {
    let mut out = Vec::new();
    for centre in offset_crossings(a, b, side, rho) {
        if let (Some(fa), Some(fb)) = (a.foot(centre), b.foot(centre)) {
            out.push((centre, fa, fb));
        }
    }
    let (a_end, b_start) = (a.end(), b.start());
    for centre in offset_crossing_point(a, b_start, side, rho) {
        if let Some(fa) = a.foot(centre) {
            out.push((centre, fa, b_start));
        }
    }
    for centre in offset_crossing_point(b, a_end, side, rho) {
        if let Some(fb) = b.foot(centre) {
            out.push((centre, a_end, fb));
        }
    }
    out
}

/// The points of element `e`'s offset by `rho` on the cutter's side at distance `rho` from
/// point `v`.
fn offset_crossing_point(e: &Element, v: Point2<f64>, side: CutterSide, rho: f64) -> Vec<Point2<f64>> {
    match offset(e, side, rho) {
        Some(Offset::Circle(c, r)) => circle_circle(c, r, v, rho),
        Some(Offset::Line(p, d)) => line_circle(p, d, v, rho),
        None => Vec::new(),
    }
}

/// +1 when `q` is left of element `e`'s travel at its point `p`, −1 when right.
fn side_of(e: &Element, p: Point2<f64>, q: Point2<f64>) -> f64 {
    cross(e.tangent_at(p), q - p).signum()
}

/// The points at distance `rho` from both elements on the cutter's side: crossings of their
/// offsets (circles for arcs, lines for lines).
fn offset_crossings(a: &Element, b: &Element, side: CutterSide, rho: f64) -> Vec<Point2<f64>> {
    match (offset(a, side, rho), offset(b, side, rho)) {
        (Some(Offset::Circle(c1, r1)), Some(Offset::Circle(c2, r2))) => circle_circle(c1, r1, c2, r2),
        (Some(Offset::Circle(c, r)), Some(Offset::Line(p, d)))
        | (Some(Offset::Line(p, d)), Some(Offset::Circle(c, r))) => line_circle(p, d, c, r),
        (Some(Offset::Line(p1, d1)), Some(Offset::Line(p2, d2))) => line_line(p1, d1, p2, d2).into_iter().collect(),
        _ => Vec::new(),
    }
}

enum Offset {
    Circle(Point2<f64>, f64),
    Line(Point2<f64>, Vector2<f64>),
}

fn offset(e: &Element, side: CutterSide, rho: f64) -> Option<Offset> {
    match e {
        Element::Arc(a) => {
            let r = offset_radius(a, rho, side);
            (r > 0.0).then_some(Offset::Circle(a.centre, r))
        }
        Element::Line { start, end } => {
            let d = end - start;
            if d.norm() == 0.0 {
                return None;
            }
            let left = Vector2::new(-d.y, d.x).normalize();
            Some(Offset::Line(start + left * (side.sign() * rho), d))
        }
    }
}

fn circle_circle(c1: Point2<f64>, r1: f64, c2: Point2<f64>, r2: f64) -> Vec<Point2<f64>> {
    let d = c2 - c1;
    let dist = d.norm();
    if dist == 0.0 || dist > r1 + r2 || dist < (r1 - r2).abs() {
        return Vec::new();
    }
    let a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let mid = c1 + d * (a / dist);
    let across = Vector2::new(-d.y, d.x) / dist;
    vec![mid + across * h, mid - across * h]
}

fn line_circle(p: Point2<f64>, d: Vector2<f64>, c: Point2<f64>, r: f64) -> Vec<Point2<f64>> {
    let u = d.normalize();
    let foot = p + u * (c - p).dot(&u);
    let h2 = r * r - (c - foot).norm_squared();
    if h2 < 0.0 {
        return Vec::new();
    }
    let h = h2.sqrt();
    vec![foot + u * h, foot - u * h]
}

fn line_line(p1: Point2<f64>, d1: Vector2<f64>, p2: Point2<f64>, d2: Vector2<f64>) -> Option<Point2<f64>> {
    let det = cross(d1, d2);
    if det.abs() < 1e-15 * d1.norm() * d2.norm() {
        return None;
    }
    let t = cross(p2 - p1, d2) / det;
    Some(p1 + d1 * t)
}

/// The rounding arc around `centre` from `from` to `to`, turning toward the cutter as the
/// profile does at a concave place.
fn rounding_arc(centre: Point2<f64>, from: Point2<f64>, to: Point2<f64>, rho: f64, side: CutterSide) -> Arc {
    // The cutter is on the circle's centre side; travelling with the centre on the cutter's
    // side means turning toward it: left (counter-clockwise) when the cutter is on the left.
    let turn = if side == CutterSide::Left { Turn::Ccw } else { Turn::Cw };
    Arc { start: from, end: to, centre, radius: rho, turn }
}

/// The most material the rounding arc leaves: the largest distance from the replaced
/// elements' points to the arc, sampled finely along them.
fn material_left(replaced: &[Element], arc: &Arc) -> f64 {
    let mut worst: f64 = 0.0;
    for e in replaced {
        let n = ((e.length() / 0.01).ceil() as usize).clamp(8, 20_000);
        for s in 0..=n {
            let p = point_along(e, s as f64 / n as f64);
            // Only the stretch the arc replaces: points whose foot lies on the arc.
            let radial = p - arc.centre;
            if radial.norm() == 0.0 {
                continue;
            }
            let on = arc.centre + radial.normalize() * arc.radius;
            if (Arc { end: on, ..*arc }).sweep() <= arc.sweep() + 1e-12 {
                worst = worst.max(radial.norm() - arc.radius);
            }
        }
    }
    worst.max(0.0)
}

fn point_along(e: &Element, u: f64) -> Point2<f64> {
    match e {
        Element::Arc(a) => a.point_at(u),
        Element::Line { start, end } => start + (end - start) * u,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(a: (f64, f64), b: (f64, f64)) -> Element {
        Element::Line { start: Point2::new(a.0, a.1), end: Point2::new(b.0, b.1) }
    }

    /// A right-angle inside corner of two lines, the cutter inside the L: the rounding circle
    /// of radius ρ touches both legs ρ from the corner, and leaves ρ(√2 − 1) in the corner.
    #[test]
    fn an_inside_corner_of_two_lines_is_rounded_by_the_circle_touching_both_legs() {
        // Along +x, then up +y: a left turn; the cutter on the left is inside the corner.
        let chain = [line((0.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (10.0, 10.0))];
        // A control reaches this corner itself (the cutter's circle touches both legs)...
        assert!(round_concave(&chain, CutterSide::Left, 2.0, 2.0).1.is_empty());
        // ... but not past a short leg: with the first leg 1 mm long the circle of radius 2
        // cannot touch it, and the rounding bridges from the leg before.
        let chain = [line((-10.0, 0.0), (9.0, 0.0)), line((9.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (10.0, 10.0))];
        let (out, roundings) = round_concave(&chain, CutterSide::Left, 2.0, 2.0);
        assert_eq!(roundings.len(), 1, "{out:?}");
        let r = roundings[0];
        assert!((r.arc.centre - Point2::new(8.0, 2.0)).norm() < 1e-12, "{r:?}");
        assert!((r.left - 2.0 * (2f64.sqrt() - 1.0)).abs() < 1e-3, "{r:?}");
        assert_eq!(out.len(), 3);
        assert_eq!(out[0], line((-10.0, 0.0), (8.0, 0.0)));
        assert_eq!(out[2], line((10.0, 2.0), (10.0, 10.0)));
        // The cutter on the right of the same path is outside the corner: nothing to round.
        assert!(round_concave(&chain, CutterSide::Right, 2.0, 2.0).1.is_empty());
    }

    /// A notch narrower than the cutter: two short legs between long ones. The rolling circle
    /// cannot enter; it bridges from the first long leg to the last.
    #[test]
    fn a_notch_narrower_than_the_cutter_is_bridged() {
        // Cutter on the left (above the path along +x); a 1 mm wide, 1 mm deep slot at x 5..6.
        let chain = [
            line((0.0, 0.0), (5.0, 0.0)),
            line((5.0, 0.0), (5.0, -1.0)),
            line((5.0, -1.0), (6.0, -1.0)),
            line((6.0, -1.0), (6.0, 0.0)),
            line((6.0, 0.0), (11.0, 0.0)),
        ];
        let (out, roundings) = round_concave(&chain, CutterSide::Left, 3.0, 3.0);
        // Each inside corner of the slot's bottom is reached by nothing of radius 3: the
        // circle stays on the top line, so whatever is rounded keeps the cutter above y = 0.
        for e in &out {
            for s in 0..=20 {
                let p = point_along(e, s as f64 / 20.0);
                assert!(p.y >= -1.0 - 1e-9, "{p:?}");
            }
        }
        for r in &roundings {
            assert!(r.arc.radius == 3.0);
        }
    }

    /// An arc bending toward the cutter more tightly than the cutter (a concave R1 between
    /// two lines, the cutter R2 on its inside) is replaced by the rounding circle through the
    /// lines, which the cutter can follow.
    #[test]
    fn a_concave_arc_tighter_than_the_cutter_is_replaced() {
        // Along +x to (9, 0), a quarter circle R1 about (9, 1) up to (10, 1), then up.
        let arc = Arc {
            start: Point2::new(9.0, 0.0),
            end: Point2::new(10.0, 1.0),
            centre: Point2::new(9.0, 1.0),
            radius: 1.0,
            turn: Turn::Ccw,
        };
        let chain = [line((0.0, 0.0), (9.0, 0.0)), Element::Arc(arc), line((10.0, 1.0), (10.0, 10.0))];
        let (out, roundings) = round_concave(&chain, CutterSide::Left, 2.0, 2.0);
        assert_eq!(roundings.len(), 1, "{out:?}");
        assert!((roundings[0].arc.centre - Point2::new(8.0, 2.0)).norm() < 1e-9, "{roundings:?}");
        // What is left bends no tighter than the rounding circle itself.
        assert!(out.iter().all(|e| !e.tighter_than(2.0 - 1e-9, CutterSide::Left)));
    }
}
