//! ncsheet's geometry built-ins: the only place the evaluator touches `crate::geometry`.
//! Each body reads its arguments, calls a pure function and maps a geometry error to
//! `#NUM!` (a number out of range) or `#VALUE!` (an unknown word) with its message.

use nalgebra::{Point3, Vector3};

use crate::eval::coerce::{to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{lift, Ctx, FnSpec};
use crate::eval::surface::{
    surface_argument, BoundSurface, EmptyEnv, FormulaSurface, Home, SurfaceFault, MAX_SURFACE_STEPS,
};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::address::Pos;
use crate::formula::ast::{Expr, ExprKind};
use crate::geometry::ballpath::{
    ball_path, ball_path_as_written, fewest_points, BallPath, BallPathSpec, Gouge, GougeCheck, GougeKind, Lines,
    PathError, Sample, Spacing, Surface, Written, GOUGE_TOLERANCE,
};
use crate::geometry::cam::{fit_piece, Piece, PieceKind};
use crate::geometry::chamfer::{chamfer, ChamferKind, ChamferPoints, ChamferSpec};
use crate::geometry::head::head_ab;
use crate::geometry::GeometryError;

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
    FnSpec::value(
        "BALLPATH",
        8,
        10,
        ballpath,
        "BALLPATH(surface, R, x0, x1, y0, y1, stepover, step, [program], [gouge])",
        "Spills {x, y, z} of a ball-end mill's zig-zag path over z = surface(x, y); program \"tip\" or \"centre\", gouge \"fail\" or \"lift\"",
    ),
];

/// The chamfer from seven scalar arguments, or the error with its message kept in `notes`.
fn chamfer_points(values: &[Value], dates: DateSystem) -> Result<ChamferPoints, (XlError, String)> {
    let kind_text = to_text(&values[0]).map_err(|e| (e, format!("CHAMFER kind is {e}")))?;
    let kind = ChamferKind::parse(&kind_text).map_err(geometry_error)?;
    let mut n = [0.0; 6];
    for (i, v) in values[1..].iter().enumerate() {
        n[i] = to_number(v, dates).map_err(|e| (e, format!("argument {} of {CHAMFER_ARGS} is {e}", i + 2)))?;
    }
    chamfer(&ChamferSpec::from_arguments(kind, n)).map(|g| g.points()).map_err(geometry_error)
}

fn geometry_error(e: GeometryError) -> (XlError, String) {
    match e {
        GeometryError::OutOfRange(m) => (XlError::Num, m),
        GeometryError::UnknownWord(m) => (XlError::Value, m),
    }
}

/// One chamfer coordinate, lifted over arrays so a column of inputs gives a column of results.
fn chamfer_coordinate(ctx: &mut Ctx, args: &[Expr], pick: fn(&ChamferPoints) -> f64) -> XlResult<Value> {
    let dates = ctx.dates();
    let failures = std::cell::RefCell::new(Vec::new());
    let out = lift(ctx, args, &|v| match chamfer_points(v, dates) {
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
    let dates = ctx.dates();
    let values = scalars(ctx, args);
    match chamfer_points(&values, dates) {
        Ok(p) => Ok(number_row(&[p.xa, p.za, p.xb, p.zb])),
        Err((e, message)) => Err(ctx.explain(e, message)),
    }
}

fn head_row(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let mut n = [0.0; 7];
    for (i, v) in scalars(ctx, args).iter().enumerate() {
        n[i] = to_number(v, dates)?;
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
    let dates = ctx.dates();
    let values = scalars(ctx, args);
    let kind_text = to_text(&values[0]).map_err(|e| ctx.explain(e, format!("ARCH_FIT kind is {e}")))?;
    let mut n = [0.0; 5];
    for (i, v) in values[1..].iter().enumerate() {
        n[i] =
            to_number(v, dates).map_err(|e| ctx.explain(e, format!("argument {} of {ARCH_FIT_ARGS} is {e}", i + 2)))?;
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

// ---- BALLPATH ------------------------------------------------------------------------------

/// Excel's last row: a spill cannot be longer.
const SHEET_ROWS: usize = 1_048_576;

impl Surface for BoundSurface<'_, '_, '_> {
    type Error = SurfaceFault;

    fn height(&mut self, x: f64, y: f64) -> Result<f64, SurfaceFault> {
        self.height_at(x, y)
    }

    fn sample(&mut self, x: f64, y: f64) -> Result<Sample, SurfaceFault> {
        let [z, dzdx, dzdy] = self.sample_at(x, y)?;
        Ok(Sample { z, dzdx, dzdy })
    }
}

/// The ball path over a formula surface, evaluated where `home` says; a failure as an error
/// value with its message.
pub fn formula_ball_path(
    ctx: &mut Ctx,
    surface: &FormulaSurface,
    home: Home,
    spec: &BallPathSpec,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<BallPath, (XlError, String)> {
    match typed_ball_path(ctx, surface, home, spec, None, progress) {
        Ok(paths) => Ok(paths.0),
        Err(PathFailure::TooManyPoints { message, .. }) => Err((XlError::Num, message)),
        Err(PathFailure::Other(error, message)) => Err((error, message)),
    }
}

/// Why there is no ball path over a formula surface.
#[derive(Clone, Debug, PartialEq)]
pub enum PathFailure {
    /// Past `BallPathSpec::max_points` (the CLI names the option that raises it).
    TooManyPoints { at_least: Option<f64>, limit: usize, message: String },
    /// An error value, with its message.
    Other(XlError, String),
}

fn typed_ball_path(
    ctx: &mut Ctx,
    surface: &FormulaSurface,
    home: Home,
    spec: &BallPathSpec,
    written: Option<Written>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(BallPath, Option<BallPath>), PathFailure> {
    if ctx.in_surface {
        return Err(PathFailure::Other(XlError::Calc, "a surface formula cannot itself compute a BALLPATH".into()));
    }
    check_surface_steps(surface, spec)?;
    ctx.in_surface = true;
    let result = match home {
        Home::Here => both_paths(&mut surface.bind(ctx), spec, written, progress),
        Home::Name(sheet) => {
            let mut named = Ctx::new(ctx.env, sheet, ctx.at);
            named.in_surface = true;
            both_paths(&mut surface.bind(&mut named), spec, written, progress)
        }
    };
    ctx.in_surface = false;
    result.map_err(|e| match e {
        PathError::Spec(g) => {
            let (error, message) = geometry_error(g);
            PathFailure::Other(error, message)
        }
        PathError::Surface { x, y, error } => PathFailure::Other(error.error(), error.describe(x, y)),
        PathError::TooManyPoints { at_least, limit } => PathFailure::TooManyPoints {
            at_least,
            limit,
            message: PathError::<SurfaceFault>::point_limit_message(at_least, limit),
        },
    })
}

/// Refuses a path whose points alone would take the surface past [`MAX_SURFACE_STEPS`],
/// before any is placed: a formula of thousands of steps over a fine grid ran for minutes.
/// (The steps are counted again as they are spent, the gouge check's included.)
fn check_surface_steps(surface: &FormulaSurface, spec: &BallPathSpec) -> Result<(), PathFailure> {
    let points = fewest_points(spec);
    // Past the point limit (or not a count at all) the path refuses itself, naming that limit.
    let within_point_limit = points <= spec.max_points as f64;
    let per_point = surface.steps().sample;
    if !within_point_limit || points * per_point as f64 <= MAX_SURFACE_STEPS as f64 {
        return Ok(());
    }
    Err(PathFailure::Other(
        XlError::Num,
        format!(
            "the surface takes {per_point} formula steps a point with its slopes, and the path's {points} \
             points alone would take more than the {MAX_SURFACE_STEPS} steps one path may spend; write the \
             surface shorter, or ask for fewer points"
        ),
    ))
}

/// The path and, with `written`, the path as written, in one run: the written one's check
/// reads the gouge check's map.
fn both_paths<S: Surface>(
    surface: &mut S,
    spec: &BallPathSpec,
    written: Option<Written>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(BallPath, Option<BallPath>), PathError<S::Error>> {
    match written {
        Some(w) => ball_path_as_written(surface, spec, w, progress).map(|(path, w)| (path, Some(w))),
        None => ball_path(surface, spec, progress).map(|path| (path, None)),
    }
}

/// The ball path over a surface formula typed on its own (`ncsheet ballpath`), evaluated on
/// an [`EmptyEnv`]: a reference in it reads a blank cell (0). With `written`, also the path
/// as a program in those decimals writes it, checked as written
/// (`geometry::ballpath::ball_path_as_written`).
pub fn standalone_ball_path(
    surface: &FormulaSurface,
    spec: &BallPathSpec,
    written: Option<Written>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(BallPath, Option<BallPath>), PathFailure> {
    let env = EmptyEnv::default();
    let mut ctx = Ctx::new(&env, 0, Pos::new(0, 0));
    typed_ball_path(&mut ctx, surface, Home::Here, spec, written, progress)
}

/// One gouge, said in a line: where the ball was placed, where it cuts and how deep.
pub fn describe_gouge(g: &Gouge) -> String {
    let p = |v: f64| format!("{v:.4}");
    let what = match g.kind {
        GougeKind::Position => "the ball touching",
        GougeKind::Move => "the move from the ball touching",
    };
    format!(
        "{what} ({}, {}, {}) cuts {} mm into the surface at ({}, {}, {})",
        p(g.contact.x),
        p(g.contact.y),
        p(g.contact.z),
        p(g.depth),
        p(g.at.x),
        p(g.at.y),
        p(g.at.z)
    )
}

fn ballpath(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let mut n = [0.0; 7];
    for (i, e) in args[1..8].iter().enumerate() {
        n[i] = to_number(&ctx.eval(e).unwrap_single(), dates)?;
    }
    let centre = match word(ctx, args.get(8), "tip")?.as_str() {
        "tip" => false,
        "centre" | "center" => true,
        other => {
            return Err(ctx.explain(XlError::Value, format!("BALLPATH program '{other}' is not \"tip\" or \"centre\"")))
        }
    };
    let gouge = match word(ctx, args.get(9), "fail")?.as_str() {
        "fail" => GougeCheck::Report,
        "lift" => GougeCheck::Lift,
        other => {
            return Err(ctx.explain(XlError::Value, format!("BALLPATH gouge '{other}' is not \"fail\" or \"lift\"")))
        }
    };
    let spec = BallPathSpec {
        radius: n[0],
        x: [n[1], n[2]],
        y: [n[3], n[4]],
        stepover: n[5],
        spacing: Spacing::Step(n[6]),
        lines: Lines::ConstantX,
        gouge,
        gouge_tol: GOUGE_TOLERANCE,
        gouge_samples: crate::geometry::ballpath::GOUGE_SAMPLES,
        check_links: true,
        direction: crate::geometry::ballpath::Direction::Zigzag,
        max_points: SHEET_ROWS,
    };
    let explained = |ctx: &mut Ctx, (e, message): (XlError, String)| ctx.explain(e, message);
    let (surface, home) = surface_argument(ctx, &args[0]).map_err(|f| explained(ctx, f))?;
    let path = formula_ball_path(ctx, &surface, home, &spec, &mut |_, _| {}).map_err(|f| explained(ctx, f))?;
    if let (GougeCheck::Report, Some(first)) = (gouge, path.gouges.first()) {
        let message = format!(
            "{} gouges; the first: {} (BALLPATH(…, \"lift\") lifts the ball)",
            path.gouges.len(),
            describe_gouge(first)
        );
        return Err(ctx.explain(XlError::Num, message));
    }
    let mut data = Vec::with_capacity(path.points.len() * 3);
    for p in &path.points {
        let at = if centre { p.centre } else { p.tip(path.radius) };
        data.extend([Value::Number(at.x), Value::Number(at.y), Value::Number(at.z)]);
    }
    Ok(Array::new(path.points.len(), 3, data).into())
}

/// An optional word argument in lower case.
fn word(ctx: &mut Ctx, e: Option<&Expr>, default: &str) -> XlResult<String> {
    match e {
        None => Ok(default.to_string()),
        Some(e) if e.kind == ExprKind::Missing => Ok(default.to_string()),
        Some(e) => Ok(to_text(&ctx.eval(e))?.trim().to_ascii_lowercase()),
    }
}
