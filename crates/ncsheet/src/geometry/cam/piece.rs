//! One segment of a cam profile: a circle, an Archimedean spiral, a logarithmic spiral or a
//! parabolic (constant-acceleration) piece about the cam centre, given as the design sheet gives
//! it (start/end radius in mm, start/end angle in degrees).
//!
//! Inside, a piece is a plane curve C(t), t ∈ [0, 1], with polar angle θ(t) = θ0 + t·Δθ and
//! - circle: r(t) = r0;
//! - Archimedean: r(t) = r0 + t·(r1 − r0), i.e. r = r0 + a·(φ − φ0) with a = Δr/Δφ;
//! - logarithmic: r(t) = r0·(r1/r0)^t, i.e. r = r0·e^(a(φ − φ0)) with a = ln(r1/r0)/Δφ
//!   (docs/domain.md §5 [fix]: the paper prints a = ln ΔR/Δφ);
//! - parabolic: the follower starts and ends at rest with a constant acceleration over the
//!   first half and the same deceleration over the second (the paper's "constant acceleration"
//!   idle pieces): r(t) = r0 + 2Δr·t² for t ≤ ½ and r1 − 2Δr·(1 − t)² after, Δr = r1 − r0.
//!
//! A piece may also be taken at a fixed distance from its curve ([`Piece::offset_outward`]):
//! the curve the arc fitter aims at when the arcs must lie on one side of the cam's profile.
//!
//! Parametrising by t rather than by φ keeps one code path for every kind and for pieces that
//! run clockwise (φ1 < φ0).

use nalgebra::{Point2, Vector2};

use crate::geometry::{ensure, GeometryError};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PieceKind {
    /// Dwell: constant radius.
    Circle,
    /// Working feed: the radius grows by a constant amount per degree.
    Archimedean,
    /// Approach or return: constant pressure angle.
    Logarithmic,
    /// Approach or return from rest to rest: constant acceleration, then constant deceleration.
    Parabolic,
}

impl PieceKind {
    /// `"circle"`, `"arch"`, `"log"` or `"parab"` in any case (the long names are accepted too).
    pub fn parse(word: &str) -> Result<PieceKind, GeometryError> {
        match word.trim().to_ascii_lowercase().as_str() {
            "circle" => Ok(PieceKind::Circle),
            "arch" | "archimedean" => Ok(PieceKind::Archimedean),
            "log" | "logarithmic" => Ok(PieceKind::Logarithmic),
            "parab" | "parabolic" => Ok(PieceKind::Parabolic),
            _ => Err(GeometryError::UnknownWord(format!(
                "piece kind '{word}' is not one of \"arch\", \"log\", \"parab\", \"circle\""
            ))),
        }
    }

    /// The word [`PieceKind::parse`] reads back.
    pub fn word(self) -> &'static str {
        match self {
            PieceKind::Circle => "circle",
            PieceKind::Archimedean => "arch",
            PieceKind::Logarithmic => "log",
            PieceKind::Parabolic => "parab",
        }
    }
}

/// A validated piece. Build it with [`Piece::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub kind: PieceKind,
    /// Radius at the start, mm.
    pub r0: f64,
    /// Polar angle at the start, degrees.
    pub phi0_deg: f64,
    /// Radius at the end, mm.
    pub r1: f64,
    /// Polar angle at the end, degrees.
    pub phi1_deg: f64,
    theta0: f64,
    sweep: f64,
    /// ln(r1/r0) for a logarithmic spiral, unused otherwise.
    log_ratio: f64,
    /// Distance of the curve taken from the profile, mm, along the normal that points away from
    /// the cam centre (negative: towards it); 0 for the profile itself.
    offset: f64,
    /// The part of the profile's parameter range this piece covers, [0, 1] unless trimmed.
    span: (f64, f64),
}

/// A point of the curve with its first and second derivatives with respect to t.
#[derive(Clone, Copy, Debug)]
pub struct Jet {
    pub p: Point2<f64>,
    pub d1: Vector2<f64>,
    pub d2: Vector2<f64>,
}

impl Piece {
    /// Checks the inputs and builds the piece, or says which argument has no geometry.
    pub fn new(kind: PieceKind, r0: f64, phi0_deg: f64, r1: f64, phi1_deg: f64) -> Result<Piece, GeometryError> {
        let all = [r0, phi0_deg, r1, phi1_deg];
        ensure(all.iter().all(|v| v.is_finite()), || "piece radii and angles must be finite numbers".into())?;
        let sweep_deg = phi1_deg - phi0_deg;
        ensure(sweep_deg != 0.0, || {
            format!("start angle phi0 = {phi0_deg}° equals end angle phi1; a piece needs a sweep")
        })?;
        ensure(sweep_deg.abs() <= 360.0, || {
            format!("sweep phi1 − phi0 = {sweep_deg}° is more than one turn (at most 360°)")
        })?;
        match kind {
            PieceKind::Circle => {
                ensure(r0 > 0.0, || format!("circle radius r0 = {r0} must be greater than 0 mm"))?;
                ensure(r1 == r0, || format!("a circle keeps its radius: r1 = {r1} differs from r0 = {r0}"))?;
            }
            PieceKind::Archimedean | PieceKind::Parabolic => {
                ensure(r0 >= 0.0, || format!("start radius r0 = {r0} must not be negative"))?;
                ensure(r1 >= 0.0, || format!("end radius r1 = {r1} must not be negative"))?;
                ensure(r0 + r1 > 0.0, || format!("{} piece needs r0 or r1 greater than 0 mm", kind.word()))?;
            }
            PieceKind::Logarithmic => {
                ensure(r0 > 0.0, || {
                    format!("start radius r0 = {r0} of a logarithmic spiral must be greater than 0 mm")
                })?;
                ensure(r1 > 0.0, || format!("end radius r1 = {r1} of a logarithmic spiral must be greater than 0 mm"))?;
            }
        }
        let log_ratio = if kind == PieceKind::Logarithmic { (r1 / r0).ln() } else { 0.0 };
        Ok(Piece {
            kind,
            r0,
            phi0_deg,
            r1,
            phi1_deg,
            theta0: phi0_deg.to_radians(),
            sweep: sweep_deg.to_radians(),
            log_ratio,
            offset: 0.0,
            span: (0.0, 1.0),
        })
    }

    /// The curve at `distance` mm from this piece's profile, along the normal away from the cam
    /// centre (negative: towards it). Its ends are off the profile's ends by the same distance.
    pub fn offset_outward(&self, distance: f64) -> Piece {
        Piece { offset: distance, ..*self }
    }

    /// The part of this piece from parameter `from` to `to` (of this piece's own t; values
    /// outside [0, 1] extend it), again parametrised by t ∈ [0, 1].
    pub fn trimmed(&self, from: f64, to: f64) -> Piece {
        let (lo, hi) = self.span;
        Piece { span: (lo + from * (hi - lo), lo + to * (hi - lo)), ..*self }
    }

    /// The distance from the profile given to [`Piece::offset_outward`]; 0 for the profile.
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// Δθ in radians: positive when the piece runs counter-clockwise about the cam centre.
    pub fn sweep(&self) -> f64 {
        self.sweep
    }

    /// The spiral's constant a: mm per radian (Archimedean) or 1/radian (logarithmic); 0 for a
    /// circle.
    pub fn rate(&self) -> f64 {
        match self.kind {
            PieceKind::Circle => 0.0,
            PieceKind::Archimedean => (self.r1 - self.r0) / self.sweep,
            PieceKind::Logarithmic => self.log_ratio / self.sweep,
            // The mean rate; the radius changes fastest at the middle, at twice this.
            PieceKind::Parabolic => (self.r1 - self.r0) / self.sweep,
        }
    }

    /// Radius and its first three t-derivatives.
    fn radius_jet(&self, t: f64) -> [f64; 4] {
        let rise = self.r1 - self.r0;
        match self.kind {
            PieceKind::Circle => [self.r0, 0.0, 0.0, 0.0],
            PieceKind::Archimedean => [self.r0 + t * rise, rise, 0.0, 0.0],
            PieceKind::Logarithmic => {
                let (r, l) = (self.r0 * (t * self.log_ratio).exp(), self.log_ratio);
                [r, l * r, l * l * r, l * l * l * r]
            }
            PieceKind::Parabolic if t <= 0.5 => [self.r0 + 2.0 * rise * t * t, 4.0 * rise * t, 4.0 * rise, 0.0],
            PieceKind::Parabolic => {
                let u = 1.0 - t;
                [self.r1 - 2.0 * rise * u * u, 4.0 * rise * u, -4.0 * rise, 0.0]
            }
        }
    }

    /// The profile's point and its first three t-derivatives (of this piece's t, which a trim
    /// maps onto part of the profile's).
    fn profile_jet(&self, t: f64) -> [Vector2<f64>; 4] {
        let (lo, hi) = self.span;
        let (t, k) = (lo + t * (hi - lo), hi - lo);
        let [r, r1, r2, r3] = self.radius_jet(t);
        let [r1, r2, r3] = [r1 * k, r2 * k * k, r3 * k * k * k];
        let (sin, cos) = (self.theta0 + t * self.sweep).sin_cos();
        let radial = Vector2::new(cos, sin);
        let across = Vector2::new(-sin, cos);
        let w = self.sweep * k;
        [
            radial * r,
            radial * r1 + across * (r * w),
            radial * (r2 - r * w * w) + across * (2.0 * r1 * w),
            radial * (r3 - 3.0 * r1 * w * w) + across * (3.0 * r2 * w - r * w * w * w),
        ]
    }

    pub fn point(&self, t: f64) -> Point2<f64> {
        self.jet(t).p
    }

    /// C(t), C′(t), C″(t) (of the offset curve when the piece is offset).
    pub fn jet(&self, t: f64) -> Jet {
        let [p, d1, d2, d3] = self.profile_jet(t);
        if self.offset == 0.0 {
            return Jet { p: Point2::from(p), d1, d2 };
        }
        // P = C + o·N with N = σ·rot(C′)/|C′| the unit normal away from the centre (σ = −1 when
        // the piece runs counter-clockwise, where rot(C′) points inwards). With g = rot(C′)/|C′|:
        // g′ = rot(C″)/s − rot(C′)·(C′·C″)/s³ and g″ by the product rule once more.
        let sigma = if self.sweep > 0.0 { -1.0 } else { 1.0 };
        let rot = |v: Vector2<f64>| Vector2::new(-v.y, v.x);
        let s2 = d1.norm_squared();
        let s = s2.sqrt();
        let q = d1.dot(&d2);
        let q1 = d2.norm_squared() + d1.dot(&d3);
        let g = rot(d1) / s;
        let g1 = rot(d2) / s - rot(d1) * (q / (s * s2));
        let g2 = rot(d3) / s - rot(d2) * (2.0 * q / (s * s2)) - rot(d1) * (q1 / (s * s2) - 3.0 * q * q / (s2 * s2 * s));
        let o = self.offset * sigma;
        Jet { p: Point2::from(p + g * o), d1: d1 + g1 * o, d2: d2 + g2 * o }
    }

    /// Unit tangent in the direction of increasing t.
    pub fn tangent(&self, t: f64) -> Vector2<f64> {
        self.jet(t).d1.normalize()
    }

    /// Signed curvature (1/mm): positive where the curve turns left while t increases.
    pub fn curvature(&self, t: f64) -> f64 {
        let j = self.jet(t);
        cross(j.d1, j.d2) / j.d1.norm().powi(3)
    }

    /// Curve length, by Gauss–Legendre quadrature over 16 panels (the integrand is smooth).
    pub fn length(&self) -> f64 {
        integrate(|t| self.jet(t).d1.norm(), 16)
    }

    /// The curve point nearest to `q` and its distance, searching from `t_hint`. Newton on
    /// (C(t) − q)·C′(t) = 0, clamped to [0, 1]; the ends are compared too so a foot outside the
    /// piece lands on the nearer end.
    pub fn nearest(&self, q: Point2<f64>, t_hint: f64) -> (f64, f64) {
        let mut t = t_hint.clamp(0.0, 1.0);
        for _ in 0..50 {
            let j = self.jet(t);
            let w = j.p - q;
            let g = w.dot(&j.d1);
            let dg = j.d1.norm_squared() + w.dot(&j.d2);
            let step = if dg > 0.0 { g / dg } else { g / j.d1.norm_squared() };
            let next = (t - step).clamp(0.0, 1.0);
            let done = (next - t).abs() < 1e-15;
            t = next;
            if done {
                break;
            }
        }
        let mut best = (t, (self.point(t) - q).norm());
        for end in [0.0, 1.0] {
            let d = (self.point(end) - q).norm();
            if d < best.1 {
                best = (end, d);
            }
        }
        best
    }

    /// A first guess of the parameter whose point is nearest to `q`: the spirals here turn
    /// slowly, so the nearest point sits at nearly the same polar angle.
    pub fn t_guess(&self, q: Point2<f64>) -> f64 {
        use std::f64::consts::{PI, TAU};
        let (lo, hi) = self.span;
        let mid = self.theta0 + 0.5 * (lo + hi) * self.sweep;
        let off_mid = (q.y.atan2(q.x) - mid + PI).rem_euclid(TAU) - PI;
        (0.5 + off_mid / (self.sweep * (hi - lo))).clamp(0.0, 1.0)
    }

    /// Distance from `q` to the curve.
    pub fn distance(&self, q: Point2<f64>) -> f64 {
        self.nearest(q, self.t_guess(q)).1
    }
}

/// z-component of the cross product.
pub fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// ∫₀¹ f by 5-point Gauss–Legendre on `panels` equal panels.
pub fn integrate(f: impl Fn(f64) -> f64, panels: usize) -> f64 {
    const NODES: [f64; 5] =
        [0.0, -0.538_469_310_105_683, 0.538_469_310_105_683, -0.906_179_845_938_664, 0.906_179_845_938_664];
    const WEIGHTS: [f64; 5] = [
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
        0.236_926_885_056_189,
    ];
    let h = 1.0 / panels as f64;
    let mut sum = 0.0;
    for i in 0..panels {
        let mid = (i as f64 + 0.5) * h;
        for (x, w) in NODES.iter().zip(WEIGHTS) {
            sum += w * f(mid + 0.5 * h * x);
        }
    }
    sum * 0.5 * h
}
