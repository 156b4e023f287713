//! A surface z = f(x, y) written in the formula language: text such as
//! `0.3*EXP(-16*(x^2+y^2))` (variables `x` and `y`), or a `LAMBDA(x, y, …)` typed into a
//! formula or held by a defined name. It is parsed by the one grammar, its partial derivatives
//! are formulas too ([`super::diff`]), and all three are run by the one evaluator with the
//! variables bound as local names, so slopes are exact to rounding.
//!
//! Nothing here knows about tool paths: `eval/functions/geometry/` adapts a
//! [`BoundSurface`] to `geometry::ballpath::Surface`.

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use crate::formula::ast::{BinOp, Expr, ExprKind, SheetId, Span, UnaryOp};
use crate::formula::parse::{parse_formula, ParseContext, ParseError};

use crate::formula::address::{Pos, Rect};

use super::coerce::{to_number, to_text};
use super::dates::DateSystem;
use super::diff::{derivative, is_pure_numeric, DiffError};
use super::evaluator::{Ctx, Env};
use super::functions::{self, as_lambda, FnKind, Registry};
use super::value::{Value, XlError};

/// A surface formula with its two partial derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct FormulaSurface {
    pub height: Expr,
    pub dx: Expr,
    pub dy: Expr,
    /// The names standing for x and y (a LAMBDA's parameters, or `x` and `y`).
    pub params: [Rc<str>; 2],
    /// The three formulas with their common parts computed once.
    shared: Shared,
}

/// Why a formula is not a surface.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceDefError {
    Parse(ParseError),
    Diff(DiffError),
    /// A LAMBDA with other than two parameters.
    Params(usize),
}

impl SurfaceDefError {
    /// The problem under the surface text, with a caret where the text has one.
    pub fn render(&self, text: &str) -> String {
        match self {
            SurfaceDefError::Parse(e) => e.render(text),
            SurfaceDefError::Diff(e) => {
                ParseError { offset: e.span.start as usize, message: e.message.clone() }.render(text)
            }
            SurfaceDefError::Params(n) => format!("{text}\na surface LAMBDA takes two parameters (x, y), not {n}"),
        }
    }

    pub fn message(&self) -> String {
        match self {
            SurfaceDefError::Parse(e) => e.message.clone(),
            SurfaceDefError::Diff(e) => e.message.clone(),
            SurfaceDefError::Params(n) => format!("a surface LAMBDA takes two parameters (x, y), not {n}"),
        }
    }
}

impl FormulaSurface {
    /// A surface from text: a formula in `x` and `y`, or a `LAMBDA(x, y, …)` (a leading `=`
    /// is allowed). Relative references are read from `ctx.at`.
    pub fn parse(text: &str, ctx: &ParseContext) -> Result<FormulaSurface, SurfaceDefError> {
        let e = parse_formula(text, ctx).map_err(SurfaceDefError::Parse)?;
        let surface = FormulaSurface::from_expr(&e)?;
        if as_lambda(&e).is_none() {
            refuse_cell_references(&e, text)?;
        }
        Ok(surface)
    }

    /// A `LAMBDA(x, y, body)`, or any other formula read as a function of `x` and `y`.
    pub fn from_expr(e: &Expr) -> Result<FormulaSurface, SurfaceDefError> {
        let Some(lambda) = as_lambda(e) else {
            return FormulaSurface::from_body(e.clone(), ["x".into(), "y".into()]);
        };
        let names: Vec<Rc<str>> = lambda.param_names().cloned().collect();
        let [x, y] = <[Rc<str>; 2]>::try_from(names).map_err(|n| SurfaceDefError::Params(n.len()))?;
        FormulaSurface::from_body(lambda.body.clone(), [x, y])
    }

    fn from_body(height: Expr, params: [Rc<str>; 2]) -> Result<FormulaSurface, SurfaceDefError> {
        let dx = derivative(&height, &params[0]).map_err(SurfaceDefError::Diff)?;
        let dy = derivative(&height, &params[1]).map_err(SurfaceDefError::Diff)?;
        let shared = Shared::of([&height, &dx, &dy]);
        Ok(FormulaSurface { height, dx, dy, params, shared })
    }

    /// The surface evaluated in `ctx` (its sheet and cell decide what references read).
    pub fn bind<'s, 'c, 'a>(&'s self, ctx: &'c mut Ctx<'a>) -> BoundSurface<'s, 'c, 'a> {
        BoundSurface { surface: self, ctx }
    }
}

/// A surface written as text names x, y and defined names, never cells: `x2+y2` (meant as
/// x²+y²) would read cells X2 and Y2 as blank and give a flat surface without a word.
fn refuse_cell_references(e: &Expr, text: &str) -> Result<(), SurfaceDefError> {
    let mut first: Option<Span> = None;
    e.visit(&mut |node| {
        if matches!(node.kind, ExprKind::Ref(_)) && first.is_none() {
            first = Some(node.span);
        }
    });
    let Some(span) = first else { return Ok(()) };
    let cell = text.get(span.start as usize..span.end as usize).unwrap_or("");
    let message =
        format!("{cell} is a cell reference; a surface names only x, y and defined names (x^2 for x squared)");
    Err(SurfaceDefError::Parse(ParseError { offset: span.start as usize, message }))
}

/// Which of the three formulas failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    Height,
    SlopeX,
    SlopeY,
}

impl Part {
    pub fn describe(self) -> &'static str {
        match self {
            Part::Height => "height",
            Part::SlopeX => "slope ∂f/∂x",
            Part::SlopeY => "slope ∂f/∂y",
        }
    }
}

/// The surface's formula gave an error value (or text, or an array) instead of a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceFault {
    pub error: XlError,
    pub part: Part,
}

/// A surface ready to evaluate.
pub struct BoundSurface<'s, 'c, 'a> {
    surface: &'s FormulaSurface,
    ctx: &'c mut Ctx<'a>,
}

impl BoundSurface<'_, '_, '_> {
    pub fn height_at(&mut self, x: f64, y: f64) -> Result<f64, SurfaceFault> {
        let s = self.surface;
        self.with_xy(x, y, |ctx| number(ctx.eval(&s.height), Part::Height, ctx.dates()))
    }

    /// Height and slopes (∂f/∂x, ∂f/∂y), with x and y bound once and the parts the three
    /// formulas share computed once.
    pub fn sample_at(&mut self, x: f64, y: f64) -> Result<[f64; 3], SurfaceFault> {
        let shared = &self.surface.shared;
        self.with_xy(x, y, |ctx| {
            shared.with_temps(ctx, &mut |ctx| {
                let [h, dx, dy] = &shared.roots;
                Ok([
                    number(ctx.eval(h), Part::Height, ctx.dates())?,
                    number(ctx.eval(dx), Part::SlopeX, ctx.dates())?,
                    number(ctx.eval(dy), Part::SlopeY, ctx.dates())?,
                ])
            })
        })
    }

    fn with_xy<T>(&mut self, x: f64, y: f64, body: impl FnOnce(&mut Ctx) -> T) -> T {
        let [px, py] = &self.surface.params;
        let (px, py) = (px.clone(), py.clone());
        self.ctx.restart_lambda_work();
        self.ctx.with_local(px, Value::Number(x), |ctx| ctx.with_local(py, Value::Number(y), body))
    }
}

fn number(v: Value, part: Part, dates: DateSystem) -> Result<f64, SurfaceFault> {
    let fault = |error| SurfaceFault { error, part };
    match v {
        Value::Number(n) => Ok(n),
        Value::Array(a) if a.data.len() != 1 => Err(fault(XlError::Value)),
        v => to_number(&v.unwrap_single(), dates).map_err(fault),
    }
}

/// Common subformulas of the height and its slopes, bound once as local names: for the
/// Gaussian bump `EXP(-16*(x^2+y^2))` appears in all three, so it is computed once per point
/// instead of three times.
///
/// Only value-producing arithmetic and elementary functions are shared (never a reference or
/// a function that may return one). A shared part used only inside an IF branch is computed
/// even where the other branch is taken; an error there stays in its name, unread. Formulas
/// with LET are left alone (its names are bound inside, they cannot be lifted out).
#[derive(Clone, Debug, PartialEq)]
struct Shared {
    temps: Vec<(Rc<str>, Expr)>,
    roots: [Expr; 3],
}

impl Shared {
    fn of(roots: [&Expr; 3]) -> Shared {
        let plain = || Shared { temps: Vec::new(), roots: roots.map(|r| r.clone()) };
        let has_let = roots.iter().any(|r| {
            let mut found = false;
            r.visit(&mut |e| found |= matches!(e.kind, ExprKind::Call(id, _) if functions::spec(id).name == "LET"));
            found
        });
        if has_let {
            return plain();
        }
        let mut counter = Counter::default();
        for r in roots {
            counter.visit(r);
        }
        let chosen: HashMap<String, Rc<str>> = counter
            .order
            .iter()
            .filter(|k| counter.refs[*k] >= 2)
            .enumerate()
            // Names no formula can spell, differing in their first byte: the evaluator finds a
            // local by comparing names from the first byte on.
            .map(|(i, k)| (k.clone(), Rc::from(format!("{}∂", i + 1))))
            .collect();
        // Keys in the order first met: a part's own parts come before it.
        let temps = counter
            .order
            .iter()
            .filter_map(|k| Some((chosen.get(k)?.clone(), replace_children(&counter.exprs[k], &chosen))))
            .collect();
        Shared { temps, roots: roots.map(|r| replace(r, &chosen)) }
    }

    /// Runs `body` with every shared part bound to its name.
    fn with_temps<T>(&self, ctx: &mut Ctx, body: &mut dyn FnMut(&mut Ctx) -> T) -> T {
        bind(ctx, &self.temps, body)
    }
}

fn bind<T>(ctx: &mut Ctx, temps: &[(Rc<str>, Expr)], body: &mut dyn FnMut(&mut Ctx) -> T) -> T {
    let Some(((name, def), rest)) = temps.split_first() else { return body(ctx) };
    let value = ctx.eval(def);
    ctx.with_local(name.clone(), value, |ctx| bind(ctx, rest, body))
}

/// How often each shareable subformula is used: once per distinct parent, so the parts of a
/// repeated part are not counted again.
#[derive(Default)]
struct Counter {
    refs: HashMap<String, usize>,
    exprs: HashMap<String, Expr>,
    /// Keys of shareable subformulas, children before parents.
    order: Vec<String>,
    seen: HashSet<String>,
}

impl Counter {
    fn visit(&mut self, e: &Expr) {
        let e = bare(e);
        let k = key(e);
        if !self.seen.insert(k.clone()) {
            *self.refs.entry(k).or_default() += 1;
            return;
        }
        children(e).for_each(|c| self.visit(c));
        if shareable(e) {
            self.refs.insert(k.clone(), 1);
            self.exprs.insert(k.clone(), e.clone());
            self.order.push(k);
        }
    }
}

/// Worth a name: arithmetic or an elementary function over something, not a leaf.
fn shareable(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Binary(op, ..) => *op != BinOp::Range,
        ExprKind::Unary(op, _) => matches!(op, UnaryOp::Neg | UnaryOp::Percent),
        ExprKind::Call(id, args) => {
            let f = functions::spec(*id);
            matches!(f.kind, FnKind::Value(_)) && is_pure_numeric(f.name) && !args.is_empty()
        }
        _ => false,
    }
}

fn bare(e: &Expr) -> &Expr {
    match &e.kind {
        ExprKind::Paren(inner) => bare(inner),
        _ => e,
    }
}

fn children(e: &Expr) -> Box<dyn Iterator<Item = &Expr> + '_> {
    match &e.kind {
        ExprKind::Unary(_, a) | ExprKind::Paren(a) => Box::new(std::iter::once(&**a)),
        ExprKind::Binary(_, a, b) => Box::new([&**a, &**b].into_iter()),
        ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => Box::new(args.iter()),
        ExprKind::Array(lit) => Box::new(lit.items.iter()),
        _ => Box::new(std::iter::empty()),
    }
}

/// A structural key: equal for equal subformulas, whatever their spans and parentheses.
fn key(e: &Expr) -> String {
    let e = bare(e);
    let inner = |args: &mut dyn Iterator<Item = &Expr>| args.map(key).collect::<Vec<_>>().join(",");
    match &e.kind {
        ExprKind::Number(v) => format!("#{}", v.to_bits()),
        ExprKind::Name(n) => format!("${}", n.to_lowercase()),
        ExprKind::Unary(op, a) => format!("{op:?}({})", key(a)),
        ExprKind::Binary(op, a, b) => format!("{op:?}({},{})", key(a), key(b)),
        ExprKind::Call(id, args) => format!("f{id}({})", inner(&mut args.iter())),
        ExprKind::UnknownCall(name, args) => format!("u{name}({})", inner(&mut args.iter())),
        ExprKind::Array(lit) => format!("{{{}x{}:{}}}", lit.rows, lit.cols, inner(&mut lit.items.iter())),
        other => format!("{other:?}"),
    }
}

/// `e` with each chosen part replaced by its name, and without what only printing needs:
/// parentheses (the tree already says what they said) and negated literals (`-16` is a
/// number). Evaluation is unchanged, with fewer steps.
fn replace(e: &Expr, chosen: &HashMap<String, Rc<str>>) -> Expr {
    let e = bare(e);
    if let Some(name) = chosen.get(&key(e)) {
        return Expr::new(ExprKind::Name(name.clone()), Span::default());
    }
    if let ExprKind::Unary(UnaryOp::Neg, inner) = &e.kind {
        if let ExprKind::Number(v) = bare(inner).kind {
            return Expr::new(ExprKind::Number(-v), e.span);
        }
    }
    replace_children(e, chosen)
}

fn replace_children(e: &Expr, chosen: &HashMap<String, Rc<str>>) -> Expr {
    let r = |a: &Expr| Box::new(replace(a, chosen));
    let kind = match &e.kind {
        ExprKind::Unary(op, a) => ExprKind::Unary(*op, r(a)),
        ExprKind::Paren(a) => return replace(a, chosen),
        ExprKind::Binary(op, a, b) => ExprKind::Binary(*op, r(a), r(b)),
        ExprKind::Call(id, args) => ExprKind::Call(*id, args.iter().map(|a| replace(a, chosen)).collect()),
        ExprKind::UnknownCall(n, args) => {
            ExprKind::UnknownCall(n.clone(), args.iter().map(|a| replace(a, chosen)).collect())
        }
        other => other.clone(),
    };
    Expr::new(kind, e.span)
}

/// Where a surface argument's formula is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Home {
    /// In the calling formula's cell (LET names in scope, as a LAMBDA typed there sees them).
    Here,
    /// On this sheet, at the calling cell, without the caller's LET names: a defined name's
    /// LAMBDA, evaluated as names are (relative references follow the cell using the name).
    Name(SheetId),
}

/// The surface a sheet function's argument names: a `LAMBDA(x, y, …)` typed as the argument,
/// a defined name holding one, or text (typed, or in a cell) with a formula in x and y.
pub fn surface_argument(ctx: &mut Ctx, e: &Expr) -> Result<(FormulaSurface, Home), (XlError, String)> {
    let definition = |r: Result<FormulaSurface, SurfaceDefError>| {
        r.map_err(|err| (XlError::Value, format!("the surface: {}", err.message())))
    };
    if as_lambda(e).is_some() {
        return Ok((definition(FormulaSurface::from_expr(e))?, Home::Here));
    }
    let value = ctx.eval(e);
    if let (Value::Lambda(_), ExprKind::Name(name)) = (&value, &e.kind) {
        // A defined name holding a LAMBDA: the surface, evaluated as names are.
        if let Some((expr, sheet)) = ctx.env.defined_name(name, ctx.sheet).filter(|(x, _)| as_lambda(x).is_some()) {
            return Ok((definition(FormulaSurface::from_expr(&expr))?, Home::Name(sheet)));
        }
    }
    // A LAMBDA that a LET name holds or an expression gives, evaluated here.
    if let Value::Lambda(closure) = &value {
        return Ok((definition(FormulaSurface::from_expr(closure.expr()))?, Home::Here));
    }
    let text = to_text(&value.unwrap_single()).map_err(|err| match err {
        XlError::Calc => (err, "the surface is #CALC!: a LAMBDA in a cell has no value; define it as a name".into()),
        _ => (err, format!("the surface is {err}")),
    })?;
    let env = ctx.env;
    let sheet = |name: &str| env.sheet_id(name);
    let parse_ctx = ParseContext { at: ctx.at, functions: &Registry, sheet: &sheet };
    Ok((definition(FormulaSurface::parse(&text, &parse_ctx))?, Home::Here))
}

/// An empty workbook of one sheet, `Sheet1`, as an [`Env`]: where a surface formula typed on
/// its own (`ncsheet ballpath --surface`) is evaluated, a reference reading a blank cell (0).
#[derive(Default)]
pub struct EmptyEnv {
    /// The clock and random sequence of a formula evaluated on its own.
    settings: super::Settings,
}

impl Env for EmptyEnv {
    fn now(&self) -> f64 {
        self.settings.now(self.date_system())
    }

    fn next_random(&self) -> f64 {
        self.settings.next_random()
    }

    fn value(&self, _: SheetId, _: Pos) -> Value {
        Value::Blank
    }

    fn for_each_value(&self, _: SheetId, _: Rect, _: &mut dyn FnMut(Pos, &Value)) {}

    fn used_rect(&self, _: SheetId) -> Option<Rect> {
        None
    }

    fn defined_name(&self, _: &str, _: SheetId) -> Option<(Rc<Expr>, SheetId)> {
        None
    }

    fn spill_rect(&self, _: SheetId, _: Pos) -> Option<Rect> {
        None
    }

    fn sheet_count(&self) -> usize {
        1
    }

    fn sheet_name(&self, sheet: SheetId) -> Option<String> {
        (sheet == 0).then(|| "Sheet1".to_string())
    }
}

/// Parses a surface formula typed on its own: it has no sheet to refer to.
pub fn parse_standalone(text: &str) -> Result<FormulaSurface, SurfaceDefError> {
    FormulaSurface::parse(text, &ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None })
}
