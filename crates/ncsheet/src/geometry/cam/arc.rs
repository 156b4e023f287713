//! A circular arc as an NC control cuts it (G2/G3): start, end, centre, radius, direction.

use std::f64::consts::TAU;

use nalgebra::{Point2, Vector2};

use super::piece::cross;

/// Which way an arc turns, seen from +Z (G17 plane).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Turn {
    /// Counter-clockwise, G3.
    Ccw,
    /// Clockwise, G2.
    Cw,
}

impl Turn {
    /// +1 counter-clockwise, −1 clockwise (the `dir` column of ARCH_FIT and of the csv table).
    pub fn sign(self) -> f64 {
        match self {
            Turn::Ccw => 1.0,
            Turn::Cw => -1.0,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    pub start: Point2<f64>,
    pub end: Point2<f64>,
    pub centre: Point2<f64>,
    pub radius: f64,
    pub turn: Turn,
}

/// An end point closer to the start than this (relative to the radius) makes a full circle.
const FULL_CIRCLE: f64 = 1e-12;

impl Arc {
    /// Swept angle in radians, in (0, 2π], measured in the arc's own direction.
    pub fn sweep(&self) -> f64 {
        if (self.end - self.start).norm() <= FULL_CIRCLE * self.radius {
            return TAU;
        }
        let a0 = angle_of(self.start - self.centre);
        let a1 = angle_of(self.end - self.centre);
        (self.turn.sign() * (a1 - a0)).rem_euclid(TAU)
    }

    /// Length along the arc, mm.
    pub fn length(&self) -> f64 {
        self.radius * self.sweep()
    }

    /// The point a fraction `u` ∈ [0, 1] of the way along the arc.
    pub fn point_at(&self, u: f64) -> Point2<f64> {
        let a = angle_of(self.start - self.centre) + self.turn.sign() * u * self.sweep();
        self.centre + Vector2::new(a.cos(), a.sin()) * self.radius
    }

    /// Unit tangent in the direction of travel at `p` on the circle.
    pub fn tangent_at(&self, p: Point2<f64>) -> Vector2<f64> {
        let radial = (p - self.centre).normalize();
        Vector2::new(-radial.y, radial.x) * self.turn.sign()
    }

    /// Exact distance from `q` to the arc: to the circle when `q` lies in the arc's angular
    /// span, else to the nearer end point.
    pub fn distance(&self, q: Point2<f64>) -> f64 {
        let to_q = q - self.centre;
        let span = self.sweep();
        let off = (self.turn.sign() * (angle_of(to_q) - angle_of(self.start - self.centre))).rem_euclid(TAU);
        if off <= span && to_q.norm() > 0.0 {
            (to_q.norm() - self.radius).abs()
        } else {
            (q - self.start).norm().min((q - self.end).norm())
        }
    }
}

fn angle_of(v: Vector2<f64>) -> f64 {
    v.y.atan2(v.x)
}

/// The arc that leaves `start` along the unit `tangent` and passes through `end`: the centre
/// lies on the normal at `start` and on the chord's bisector. Its signed curvature is
/// 2·(T × w)/|w|² for the chord w. `None` when the chord is (almost) straight along the tangent,
/// where the circle degenerates into a line.
pub fn arc_through(start: Point2<f64>, tangent: Vector2<f64>, end: Point2<f64>) -> Option<Arc> {
    let chord = end - start;
    let curvature = 2.0 * cross(tangent, chord) / chord.norm_squared();
    if !curvature.is_finite() || curvature.abs() < 1e-14 {
        return None;
    }
    let normal = Vector2::new(-tangent.y, tangent.x);
    let turn = if curvature > 0.0 { Turn::Ccw } else { Turn::Cw };
    Some(Arc { start, end, centre: start + normal / curvature, radius: 1.0 / curvature.abs(), turn })
}

/// The tangent at the end of [`arc_through`]: the start tangent mirrored in the chord, which
/// stays exact where the centre is far away.
pub fn end_tangent(tangent: Vector2<f64>, start: Point2<f64>, end: Point2<f64>) -> Vector2<f64> {
    let chord = (end - start).normalize();
    chord * (2.0 * tangent.dot(&chord)) - tangent
}
