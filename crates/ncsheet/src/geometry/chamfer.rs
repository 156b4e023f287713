//! Start and end points of a chamfer cut on a lathe, with the insert's nose radius
//! compensated (docs/domain.md §1, Tamul & Olt).
//!
//! Coordinates in the lathe's (Z, X) plane: Z along the spindle axis with the part's face
//! at Z = 0 and material at Z < 0; X radial. Results give X as a diameter.
//!
//! ```text
//!   outer (shaft end)              pipe / blind (bore mouth)
//!        X                               X
//!        |   B                           |        B
//!   R ---A--\                        R+h |       /
//!        |   \ h = f·tan α               |      / h = f·tan α
//!        |    \                       R ---A---/
//!   -f   +-----+ 0   Z              -f     +---+ 0   Z
//! ```
//!
//! The chamfer is one straight line from A = (−f, R) to B = (0, R ∓ h), R = D/2, axial
//! length f and radial height h = f·tan α for every kind. The insert's nose is a circle of
//! radius r tangent to that line (extended past A or B); the programmed point is the
//! theoretical tip T, the corner of the nose's tangents parallel to Z and X:
//! T = centre − (r, r) for an outer tool and T = centre + (r, −r) in (X, Z) for a boring tool.
//!
//! Where the nose sits along Z (centre Zc):
//! - T1 (start, past A): outer Zc = −f − eA − r (the nose stays eA short of A);
//!   pipe Zc = −f − eA + r (the tip stays eA past A, as the paper's formula 23 places it);
//!   blind Zc = −f + r (the nose also touches the bore bottom at Z = −f; eA is ignored).
//! - T2 (end, past B, outside the face): Zc = eB + r for every kind (the nose stays eB off
//!   the face).
//!
//! This equals the paper's formulas 1–14 for the outer chamfer at every α, and formulas
//! 15–23 for inner chamfers at 45°. At other angles the paper's inner T1 uses f·tan α as
//! the axial depth (ZA = −f′), which contradicts its own T2; here the chamfer is defined
//! once, so ZA = −(f + eA) for a pipe and −f for a blind bore (docs/domain.md [fix]).

use nalgebra::{Point2, Vector2};

use super::{ensure, GeometryError};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChamferKind {
    /// Outer chamfer at a shaft end; D is the shaft diameter.
    Outer,
    /// Inner chamfer at the mouth of a through bore; D is the bore diameter.
    Pipe,
    /// Inner chamfer down to the bottom of a blind bore; D is the bore diameter.
    Blind,
}

impl ChamferKind {
    /// `"outer"`, `"pipe"` or `"blind"`, in any case.
    pub fn parse(word: &str) -> Result<ChamferKind, GeometryError> {
        match word.trim().to_ascii_lowercase().as_str() {
            "outer" => Ok(ChamferKind::Outer),
            "pipe" => Ok(ChamferKind::Pipe),
            "blind" => Ok(ChamferKind::Blind),
            _ => Err(GeometryError::UnknownWord(format!(
                "chamfer kind '{word}' is not one of \"outer\", \"pipe\", \"blind\""
            ))),
        }
    }

    fn is_inner(self) -> bool {
        self != ChamferKind::Outer
    }
}

/// What the drawing and the insert catalogue give, in mm and degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChamferSpec {
    pub kind: ChamferKind,
    /// Shaft diameter (outer) or bore diameter (inner).
    pub diameter: f64,
    /// Chamfer length along Z.
    pub length: f64,
    /// Chamfer angle to the Z axis, degrees, strictly between 0 and 90.
    pub angle_deg: f64,
    /// Insert nose radius (0 for a sharp tip).
    pub nose_radius: f64,
    /// Clearance at the start, past end A (ignored for a blind bore).
    pub clearance_a: f64,
    /// Clearance at the end, off the face past end B.
    pub clearance_b: f64,
}

impl ChamferSpec {
    /// The spec from CHAMFER's numeric arguments in their order: D, f, α, r, eA, eB.
    pub fn from_arguments(
        kind: ChamferKind,
        [diameter, length, angle_deg, nose_radius, clearance_a, clearance_b]: [f64; 6],
    ) -> ChamferSpec {
        ChamferSpec { kind, diameter, length, angle_deg, nose_radius, clearance_a, clearance_b }
    }
}

/// Points in the (Z, X-radius) plane: `p.x` is Z, `p.y` is the radius.
pub type ZxPoint = Point2<f64>;

/// The whole construction, for drawing and checking, not only the programmed numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChamferGeometry {
    /// Chamfer end in the material (Z = −f).
    pub a: ZxPoint,
    /// Chamfer end on the face (Z = 0).
    pub b: ZxPoint,
    /// Nose centre at the start and at the end of the cut.
    pub centre1: ZxPoint,
    pub centre2: ZxPoint,
    /// Theoretical tool tip at the start (T1) and at the end (T2).
    pub tip1: ZxPoint,
    pub tip2: ZxPoint,
}

/// The four numbers an NC program needs: X as diameter, Z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChamferPoints {
    pub xa: f64,
    pub za: f64,
    pub xb: f64,
    pub zb: f64,
}

impl ChamferGeometry {
    pub fn points(&self) -> ChamferPoints {
        ChamferPoints { xa: 2.0 * self.tip1.y, za: self.tip1.x, xb: 2.0 * self.tip2.y, zb: self.tip2.x }
    }
}

/// Builds the chamfer and both tool positions, or says which input has no geometry.
pub fn chamfer(spec: &ChamferSpec) -> Result<ChamferGeometry, GeometryError> {
    validate(spec)?;
    let alpha = spec.angle_deg.to_radians();
    let r = spec.nose_radius;
    let radius = spec.diameter / 2.0;
    let height = spec.length * alpha.tan();
    let inner = spec.kind.is_inner();
    let b_radius = if inner { radius + height } else { radius - height };
    let a = ZxPoint::new(-spec.length, radius);
    let b = ZxPoint::new(0.0, b_radius);

    // Unit normal of the chamfer line pointing into the air, where the nose is.
    let along = (b - a).normalize();
    let mut normal = Vector2::new(-along.y, along.x);
    if (normal.y < 0.0) != inner {
        normal = -normal;
    }
    let centre_at = |z: f64| {
        let on_offset = a + normal * r;
        ZxPoint::new(z, on_offset.y + (z - on_offset.x) * along.y / along.x)
    };
    let z1 = match spec.kind {
        ChamferKind::Outer => a.x - spec.clearance_a - r,
        ChamferKind::Pipe => a.x - spec.clearance_a + r,
        ChamferKind::Blind => a.x + r,
    };
    let centre1 = centre_at(z1);
    let centre2 = centre_at(b.x + spec.clearance_b + r);
    let tip = |c: ZxPoint| ZxPoint::new(c.x - r, if inner { c.y + r } else { c.y - r });
    let geometry = ChamferGeometry { a, b, centre1, centre2, tip1: tip(centre1), tip2: tip(centre2) };
    stays_off_the_axis(&geometry, r)?;
    Ok(geometry)
}

/// The nose must stay on its side of the spindle axis at both ends of the cut: a steep
/// chamfer on a thin shaft, or a wide nose in a small bore, would put it across the axis,
/// and X would come out negative (a point on the other side of the part).
fn stays_off_the_axis(g: &ChamferGeometry, r: f64) -> Result<(), GeometryError> {
    for (name, centre, tip) in [("T1", g.centre1, g.tip1), ("T2", g.centre2, g.tip2)] {
        ensure(centre.y - r >= 0.0, || {
            format!(
                "the tool would cross the spindle axis at {name} (tip X = {:.3} as a diameter, nose down to \
                 radius {:.3}): the chamfer does not fit this part and tool",
                2.0 * tip.y,
                centre.y - r
            )
        })?;
    }
    Ok(())
}

fn validate(s: &ChamferSpec) -> Result<(), GeometryError> {
    let all = [s.diameter, s.length, s.angle_deg, s.nose_radius, s.clearance_a, s.clearance_b];
    ensure(all.iter().all(|v| v.is_finite()), || "chamfer inputs must be finite numbers".into())?;
    ensure(s.diameter > 0.0, || format!("diameter D = {} must be greater than 0 mm", s.diameter))?;
    ensure(s.length > 0.0, || format!("chamfer length f = {} must be greater than 0 mm", s.length))?;
    ensure(s.angle_deg > 0.0 && s.angle_deg < 90.0, || {
        format!("chamfer angle α = {}° must be strictly between 0° and 90°", s.angle_deg)
    })?;
    ensure(s.nose_radius >= 0.0, || format!("nose radius r = {} must not be negative", s.nose_radius))?;
    ensure(s.clearance_b >= 0.0, || format!("clearance eB = {} must not be negative", s.clearance_b))?;
    if s.kind != ChamferKind::Blind {
        ensure(s.clearance_a >= 0.0, || format!("clearance eA = {} must not be negative", s.clearance_a))?;
    }
    if s.kind == ChamferKind::Outer {
        let height = s.length * s.angle_deg.to_radians().tan();
        ensure(height < s.diameter / 2.0, || {
            format!("chamfer height f·tan α = {height} mm reaches the axis of a shaft of diameter {}", s.diameter)
        })?;
    }
    Ok(())
}
