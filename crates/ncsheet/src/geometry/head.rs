//! The (A, B) swivel head of a 5-axis mill (docs/domain.md §4, Glavonjić, table T8.1.4).
//!
//! The head tilts by A about X, then by B about Y, so the tool axis is
//! a = R_Y(B)·R_X(A)·k = (cos A·sin B, −sin A, cos A·cos B). Given a tool axis the angles are
//! A = −asin(a_y), B = atan2(a_x, a_z). The pivot sits H above the tip along the axis; the
//! machine zero already holds H along k, so the programmed pivot is
//! (x_T + H·a_x, y_T + H·a_y, z_T + H·(a_z − 1)). |a_y| = 1 (A = ±90°) is the head's
//! singular position, where B is undefined.

use nalgebra::{Point3, Rotation3, Vector3};

use super::{ensure, GeometryError};

/// Programmed pivot (mm) and head angles (degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadPose {
    pub pivot: Point3<f64>,
    pub a_deg: f64,
    pub b_deg: f64,
}

/// Below this distance from |a_y| = 1 the B angle has no meaning.
const SINGULAR_TOLERANCE: f64 = 1e-12;

/// Pivot and angles that put the tool tip at `tip` with the tool along `axis`
/// (normalised first), for a pivot-to-tip distance `h`.
pub fn head_ab(tip: Point3<f64>, axis: Vector3<f64>, h: f64) -> Result<HeadPose, GeometryError> {
    let finite = tip.iter().chain(axis.iter()).all(|v| v.is_finite()) && h.is_finite();
    ensure(finite, || "head inputs must be finite numbers".into())?;
    let length = axis.norm();
    ensure(length > 0.0, || "the tool axis (ax, ay, az) has zero length".into())?;
    let a = axis / length;
    ensure(1.0 - a.y.abs() > SINGULAR_TOLERANCE, || {
        "tool axis along ±Y is the head's singular position (A = ±90°, B undefined)".into()
    })?;
    let a_rad = -a.y.asin();
    let b_rad = a.x.atan2(a.z);
    let pivot = Point3::new(tip.x + h * a.x, tip.y + h * a.y, tip.z + h * (a.z - 1.0));
    Ok(HeadPose { pivot, a_deg: a_rad.to_degrees(), b_deg: b_rad.to_degrees() })
}

/// The tool axis the head points along at angles A, B (degrees): R_Y(B)·R_X(A)·k.
pub fn axis_of(a_deg: f64, b_deg: f64) -> Vector3<f64> {
    let rx = Rotation3::from_axis_angle(&Vector3::x_axis(), a_deg.to_radians());
    let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), b_deg.to_radians());
    ry * rx * Vector3::z()
}
