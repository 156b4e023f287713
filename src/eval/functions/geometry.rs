//! ncsheet's geometry built-ins: the only place the evaluator touches `crate::geometry`.
//! Each body reads its arguments, calls a pure function and maps a geometry error to
//! `#NUM!` (a number out of range) or `#VALUE!` (an unknown word) with its message.

use nalgebra::{Point3, Vector3};

use crate::eval::coerce::{to_number, to_text};
use crate::eval::evaluator::Ctx;
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;
use crate::geometry::cam::{fit_piece, Piece, PieceKind};
use crate::geometry::chamfer::{chamfer, ChamferKind, ChamferPoints, ChamferSpec};
use crate::geometry::head::head_ab;
use crate::geometry::GeometryError;

use super::args::lift;
use super::FnSpec;

const CHAMFER_ARGS: &str = "(kind, D, f, alpha, r, eA, eB)";

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "CHAMFER",
        7,
        7,
        chamfer_row,
        "CHAMFER(kind, D, f, alpha, r, eA, eB)",
        "Spills {XA, ZA, XB, ZB}: tool tip at chamfer start and end, X as diameter (mm, degrees)",
    ),
    FnSpec::value(
        "CHAMFER_XA",
        7,
        7,
        chamfer_xa,
        "CHAMFER_XA(kind, D, f, alpha, r, eA, eB)",
        "X (diameter) of tip T1 past chamfer end A; kind \"outer\", \"pipe\" or \"blind\"",
    ),
    FnSpec::value(
        "CHAMFER_ZA",
        7,
        7,
        chamfer_za,
        "CHAMFER_ZA(kind, D, f, alpha, r, eA, eB)",
        "Z of tip T1 past chamfer end A",
    ),
    FnSpec::value(
        "CHAMFER_XB",
        7,
        7,
        chamfer_xb,
        "CHAMFER_XB(kind, D, f, alpha, r, eA, eB)",
        "X (diameter) of tip T2 past chamfer end B, off the face",
    ),
    FnSpec::value(
        "CHAMFER_ZB",
        7,
        7,
        chamfer_zb,
        "CHAMFER_ZB(kind, D, f, alpha, r, eA, eB)",
        "Z of tip T2 off the face",
    ),
    FnSpec::value(
        "HEAD_AB",
        7,
        7,
        head_row,
        "HEAD_AB(xT, yT, zT, ax, ay, az, H)",
        "Spills {X, Y, Z, A, B}: pivot point and angles (degrees) of an (A,B) 5-axis head",
    ),
    FnSpec::value(
        "ARCH_FIT",
        6,
        6,
        arch_fit,
        "ARCH_FIT(kind, r0, phi0, r1, phi1, tol)",
        "Spills one row {x0, y0, x1, y1, cx, cy, r, dir} per tangent arc within tol of a cam piece",
    ),
];

/// The chamfer from seven scalar arguments, or the error with its message kept in `notes`.
fn chamfer_points(values: &[Value]) -> Result<ChamferPoints, (XlError, String)> {
    let kind_text = to_text(&values[0]).map_err(|e| (e, format!("CHAMFER kind is {e}")))?;
    let kind = ChamferKind::parse(&kind_text).map_err(geometry_error)?;
    let mut n = [0.0; 6];
    for (i, v) in values[1..].iter().enumerate() {
        n[i] = to_number(v).map_err(|e| (e, format!("argument {} of {CHAMFER_ARGS} is {e}", i + 2)))?;
    }
    let spec = ChamferSpec {
        kind,
        diameter: n[0],
        length: n[1],
        angle_deg: n[2],
        nose_radius: n[3],
        clearance_a: n[4],
        clearance_b: n[5],
    };
    chamfer(&spec).map(|g| g.points()).map_err(geometry_error)
}

fn geometry_error(e: GeometryError) -> (XlError, String) {
    match e {
        GeometryError::OutOfRange(m) => (XlError::Num, m),
        GeometryError::UnknownWord(m) => (XlError::Value, m),
    }
}

/// One chamfer coordinate, lifted over arrays so a column of inputs gives a column of results.
fn chamfer_coordinate(ctx: &mut Ctx, args: &[Expr], pick: fn(&ChamferPoints) -> f64) -> XlResult<Value> {
    let failures = std::cell::RefCell::new(Vec::new());
    let out = lift(ctx, args, &|v| match chamfer_points(v) {
        Ok(p) => Ok(Value::Number(pick(&p))),
        Err((e, message)) => {
            failures.borrow_mut().push((e, message));
            Err(e)
        }
    });
    for (e, message) in failures.into_inner() {
        ctx.explain(e, message);
    }
    out
}

fn chamfer_xa(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    chamfer_coordinate(ctx, args, |p| p.xa)
}

fn chamfer_za(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    chamfer_coordinate(ctx, args, |p| p.za)
}

fn chamfer_xb(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    chamfer_coordinate(ctx, args, |p| p.xb)
}

fn chamfer_zb(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    chamfer_coordinate(ctx, args, |p| p.zb)
}

fn scalars(ctx: &mut Ctx, args: &[Expr]) -> Vec<Value> {
    args.iter().map(|a| ctx.eval(a).unwrap_single()).collect()
}

fn chamfer_row(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values = scalars(ctx, args);
    match chamfer_points(&values) {
        Ok(p) => Ok(number_row(&[p.xa, p.za, p.xb, p.zb])),
        Err((e, message)) => Err(ctx.explain(e, message)),
    }
}

fn head_row(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut n = [0.0; 7];
    for (i, v) in scalars(ctx, args).iter().enumerate() {
        n[i] = to_number(v)?;
    }
    let pose = head_ab(Point3::new(n[0], n[1], n[2]), Vector3::new(n[3], n[4], n[5]), n[6]).map_err(|e| {
        let (err, m) = geometry_error(e);
        ctx.explain(err, m)
    })?;
    Ok(number_row(&[pose.pivot.x, pose.pivot.y, pose.pivot.z, pose.a_deg, pose.b_deg]))
}

const ARCH_FIT_ARGS: &str = "(kind, r0, phi0, r1, phi1, tol)";

/// A cam piece ("arch", "log" or "circle") replaced by tangent arcs: one row per arc, dir = 1
/// counter-clockwise, −1 clockwise.
fn arch_fit(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values = scalars(ctx, args);
    let kind_text = to_text(&values[0]).map_err(|e| ctx.explain(e, format!("ARCH_FIT kind is {e}")))?;
    let mut n = [0.0; 5];
    for (i, v) in values[1..].iter().enumerate() {
        n[i] = to_number(v).map_err(|e| ctx.explain(e, format!("argument {} of {ARCH_FIT_ARGS} is {e}", i + 2)))?;
    }
    let [r0, phi0, r1, phi1, tol] = n;
    let arcs = PieceKind::parse(&kind_text)
        .and_then(|kind| Piece::new(kind, r0, phi0, r1, phi1))
        .and_then(|piece| fit_piece(&piece, tol))
        .map_err(|e| {
            let (err, m) = geometry_error(e);
            ctx.explain(err, m)
        })?;
    let mut data = Vec::with_capacity(arcs.len() * 8);
    for a in &arcs {
        let row = [a.start.x, a.start.y, a.end.x, a.end.y, a.centre.x, a.centre.y, a.radius, a.turn.sign()];
        data.extend(row.iter().map(|&v| Value::Number(v)));
    }
    Ok(Array::new(arcs.len(), 8, data).into())
}

fn number_row(values: &[f64]) -> Value {
    Array::row(values.iter().map(|&v| Value::Number(v)).collect()).into()
}
