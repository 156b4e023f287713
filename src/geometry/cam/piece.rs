//! One segment of a cam profile: a circle, an Archimedean spiral or a logarithmic spiral about
//! the cam centre, given as the design sheet gives it (start/end radius in mm, start/end angle in
//! degrees).
//!
//! Inside, a piece is a plane curve C(t), t ∈ [0, 1], with polar angle θ(t) = θ0 + t·Δθ and
//! - circle: r(t) = r0;
//! - Archimedean: r(t) = r0 + t·(r1 − r0), i.e. r = r0 + a·(φ − φ0) with a = Δr/Δφ;
//! - logarithmic: r(t) = r0·(r1/r0)^t, i.e. r = r0·e^(a(φ − φ0)) with a = ln(r1/r0)/Δφ
//!   (docs/domain.md §5 [fix]: the paper prints a = ln ΔR/Δφ).
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
}

impl PieceKind {
    /// `"circle"`, `"arch"` or `"log"` in any case (the long names are accepted too).
    pub fn parse(word: &str) -> Result<PieceKind, GeometryError> {
        match word.trim().to_ascii_lowercase().as_str() {
            "circle" => Ok(PieceKind::Circle),
            "arch" | "archimedean" => Ok(PieceKind::Archimedean),
            "log" | "logarithmic" => Ok(PieceKind::Logarithmic),
            _ => Err(GeometryError::UnknownWord(format!(
                "piece kind '{word}' is not one of \"arch\", \"log\", \"circle\""
            ))),
        }
    }

    /// The word [`PieceKind::parse`] reads back.
    pub fn word(self) -> &'static str {
        match self {
            PieceKind::Circle => "circle",
            PieceKind::Archimedean => "arch",
            PieceKind::Logarithmic => "log",
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
            PieceKind::Archimedean => {
                ensure(r0 >= 0.0, || format!("start radius r0 = {r0} must not be negative"))?;
                ensure(r1 >= 0.0, || format!("end radius r1 = {r1} must not be negative"))?;
                ensure(r0 + r1 > 0.0, || "an Archimedean piece needs r0 or r1 greater than 0 mm".into())?;
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
        })
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
        }
    }

    /// Radius and its first two t-derivatives.
    fn radius_jet(&self, t: f64) -> (f64, f64, f64) {
        match self.kind {
            PieceKind::Circle => (self.r0, 0.0, 0.0),
            PieceKind::Archimedean => (self.r0 + t * (self.r1 - self.r0), self.r1 - self.r0, 0.0),
            PieceKind::Logarithmic => {
                let r = self.r0 * (t * self.log_ratio).exp();
                (r, self.log_ratio * r, self.log_ratio * self.log_ratio * r)
            }
        }
    }

    pub fn point(&self, t: f64) -> Point2<f64> {
        let (r, _, _) = self.radius_jet(t);
        let (sin, cos) = (self.theta0 + t * self.sweep).sin_cos();
        Point2::new(r * cos, r * sin)
    }

    /// C(t), C′(t), C″(t).
    pub fn jet(&self, t: f64) -> Jet {
        let (r, r1, r2) = self.radius_jet(t);
        let (sin, cos) = (self.theta0 + t * self.sweep).sin_cos();
        let radial = Vector2::new(cos, sin);
        let across = Vector2::new(-sin, cos);
        let w = self.sweep;
        Jet {
            p: Point2::from(radial * r),
            d1: radial * r1 + across * (r * w),
            d2: radial * (r2 - r * w * w) + across * (2.0 * r1 * w),
        }
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
        let mid = self.theta0 + 0.5 * self.sweep;
        let off_mid = (q.y.atan2(q.x) - mid + PI).rem_euclid(TAU) - PI;
        (0.5 + off_mid / self.sweep).clamp(0.0, 1.0)
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
