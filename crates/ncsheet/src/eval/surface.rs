//! A surface z = f(x, y) written in the formula language: text such as
//! `0.3*EXP(-16*(x^2+y^2))` (variables `x` and `y`), or a `LAMBDA(x, y, …)` typed into a
//! formula or held by a defined name. It is parsed by the one grammar, its partial derivatives
//! are formulas too ([`super::diff`]), and all three are run by the one evaluator with the
//! variables bound as local names, so slopes are exact to rounding.
//!
//! Nothing here knows about tool paths: `eval/functions/geometry/` adapts a
//! [`BoundSurface`] to `geometry::ballpath::Surface`.

use std::collections::HashMap;
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
    /// What evaluating the surface costs, in formula steps (nodes evaluated).
    steps: Steps,
}

/// The formula steps (nodes evaluated, [`Steps`]) one ball path may spend on its surface:
/// every sample of the path, its gouge check and its written check together. About 13 s at
/// the 27 ns a step measured on a 999-term sum; the paper's Gaussian bump (24 steps a point
/// with its slopes) takes its 20,000,000 gouge samples within them, a formula of thousands
/// of steps a point is stopped before it runs for minutes.
pub const MAX_SURFACE_STEPS: u64 = 500_000_000;

/// The steps (nodes evaluated, names looked up: [`twelfths`]) of a height alone and of a
/// height with its slopes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Steps {
    pub height: u64,
    pub sample: u64,
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
        let shared = Shared::of([&height, &dx, &dy], &params);
        let height_steps = twelfths(&height, &Locals::new(params.iter()), 2).div_ceil(12);
        let steps = Steps { height: height_steps, sample: shared.steps(&params) };
        Ok(FormulaSurface { height, dx, dy, params, shared, steps })
    }

    /// What one evaluation costs, in formula steps.
    pub fn steps(&self) -> Steps {
        self.steps
    }

    /// The surface evaluated in `ctx` (its sheet and cell decide what references read), within
    /// [`MAX_SURFACE_STEPS`].
    pub fn bind<'s, 'c, 'a>(&'s self, ctx: &'c mut Ctx<'a>) -> BoundSurface<'s, 'c, 'a> {
        self.bind_within(ctx, MAX_SURFACE_STEPS)
    }

    /// The surface evaluated in `ctx` until its evaluations have taken `steps` formula steps.
    pub fn bind_within<'s, 'c, 'a>(&'s self, ctx: &'c mut Ctx<'a>, steps: u64) -> BoundSurface<'s, 'c, 'a> {
        BoundSurface { surface: self, ctx, room: steps, limit: steps }
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

/// Why the surface has no value at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceFault {
    /// The formula gave an error value (or text, or an array) instead of a number.
    Value { error: XlError, part: Part },
    /// The evaluations so far took the `limit` steps they may take, at `per_sample` steps a
    /// height and slopes.
    OutOfSteps { limit: u64, per_sample: u64 },
}

impl SurfaceFault {
    /// The error value a sheet function gives for it.
    pub fn error(self) -> XlError {
        match self {
            SurfaceFault::Value { error, .. } => error,
            SurfaceFault::OutOfSteps { .. } => XlError::Num,
        }
    }

    /// What went wrong at (x, y).
    pub fn describe(self, x: f64, y: f64) -> String {
        match self {
            SurfaceFault::Value { error, part } => {
                format!("the surface's {} is {error} at x={x}, y={y}", part.describe())
            }
            SurfaceFault::OutOfSteps { limit, per_sample } => format!(
                "evaluating the surface took the {limit} formula steps one path may spend ({per_sample} a point \
                 with its slopes) and stopped at x={x}, y={y}; write the surface shorter, or ask for fewer \
                 points and a coarser gouge check"
            ),
        }
    }
}

/// A surface ready to evaluate, within a number of formula steps.
pub struct BoundSurface<'s, 'c, 'a> {
    surface: &'s FormulaSurface,
    ctx: &'c mut Ctx<'a>,
    /// Steps the evaluations may still take, of `limit`.
    room: u64,
    limit: u64,
}

impl BoundSurface<'_, '_, '_> {
    pub fn height_at(&mut self, x: f64, y: f64) -> Result<f64, SurfaceFault> {
        self.charge(self.surface.steps.height)?;
        let s = self.surface;
        self.with_xy(x, y, |ctx| number(ctx.eval(&s.height), Part::Height, ctx.dates()))
    }

    /// Height and slopes (∂f/∂x, ∂f/∂y), with x and y bound once and the parts the three
    /// formulas share computed once.
    pub fn sample_at(&mut self, x: f64, y: f64) -> Result<[f64; 3], SurfaceFault> {
        self.charge(self.surface.steps.sample)?;
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

    /// Takes `steps` from the room left, before they are spent.
    fn charge(&mut self, steps: u64) -> Result<(), SurfaceFault> {
        let out_of_steps = SurfaceFault::OutOfSteps { limit: self.limit, per_sample: self.surface.steps.sample };
        self.room = self.room.checked_sub(steps).ok_or(out_of_steps)?;
        Ok(())
    }

    fn with_xy<T>(&mut self, x: f64, y: f64, body: impl FnOnce(&mut Ctx) -> T) -> T {
        let [px, py] = &self.surface.params;
        let (px, py) = (px.clone(), py.clone());
        self.ctx.restart_lambda_work();
        self.ctx.with_local(px, Value::Number(x), |ctx| ctx.with_local(py, Value::Number(y), body))
    }
}

fn number(v: Value, part: Part, dates: DateSystem) -> Result<f64, SurfaceFault> {
    let fault = |error| SurfaceFault::Value { error, part };
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
    fn of(roots: [&Expr; 3], params: &[Rc<str>; 2]) -> Shared {
        let has_let = roots.iter().any(|r| {
            let mut found = false;
            r.visit(&mut |e| found |= matches!(e.kind, ExprKind::Call(id, _) if functions::spec(id).name == "LET"));
            found
        });
        if has_let {
            return Shared { temps: Vec::new(), roots: roots.map(|r| r.clone()) };
        }
        let mut parts = Parts::default();
        for r in roots {
            parts.intern(r);
        }
        let mut counter =
            Counter { refs: vec![0; parts.first.len()], seen: vec![false; parts.first.len()], order: Vec::new() };
        for r in roots {
            counter.visit(r, &parts);
        }
        let mut chosen: HashMap<u32, Rc<str>> = HashMap::new();
        // Names no formula can spell, differing in their first byte: the evaluator finds a
        // local by comparing names from the first byte on.
        for (i, id) in counter.order.iter().filter(|id| counter.refs[**id as usize] >= 2).enumerate() {
            chosen.insert(*id, Rc::from(format!("{}∂", i + 1)));
        }
        let shared = Shared::rewritten(&parts, &chosen, &counter.order, roots);
        let plain = Shared::rewritten(&parts, &HashMap::new(), &[], roots);
        // A shared part is computed once but read through a local name, which the evaluator
        // finds by searching the names bound after it: past some thousands of shared parts
        // (a 999-term sum) the searches cost more than they save.
        if shared.steps(params) <= plain.steps(params) {
            shared
        } else {
            plain
        }
    }

    /// The three formulas with the `chosen` parts (of `order`, children first) as names.
    fn rewritten(parts: &Parts, chosen: &HashMap<u32, Rc<str>>, order: &[u32], roots: [&Expr; 3]) -> Shared {
        let rewrite = Rewrite { parts, chosen };
        let temps = order
            .iter()
            .filter_map(|id| Some((chosen.get(id)?.clone(), rewrite.children(parts.first[*id as usize]))))
            .collect();
        Shared { temps, roots: roots.map(|r| rewrite.replace(r)) }
    }

    /// The steps one evaluation of the three formulas takes (see [`twelfths`]): the parameters
    /// are bound first, then each shared part in turn.
    fn steps(&self, params: &[Rc<str>; 2]) -> u64 {
        let names = Locals::new(params.iter().chain(self.temps.iter().map(|(n, _)| n)));
        let temps: u64 = self.temps.iter().enumerate().map(|(i, (_, def))| twelfths(def, &names, 2 + i)).sum();
        let roots: u64 = self.roots.iter().map(|r| twelfths(r, &names, names.len())).sum();
        (temps + roots).div_ceil(12)
    }

    /// Runs `body` with every shared part bound to its name.
    fn with_temps<T>(&self, ctx: &mut Ctx, body: &mut dyn FnMut(&mut Ctx) -> T) -> T {
        bind(ctx, &self.temps, body)
    }
}

/// Local names in the order they are bound, each with its place.
struct Locals(HashMap<String, usize>);

impl Locals {
    fn new<'n>(names: impl Iterator<Item = &'n Rc<str>>) -> Locals {
        // A name bound again is found at its last place.
        Locals(names.enumerate().map(|(i, name)| (name.to_lowercase(), i)).collect())
    }

    fn len(&self) -> usize {
        self.0.len()
    }
}

/// The steps the evaluator takes through `e` with the first `bound` of `names` bound, in
/// twelfths of a step: a node is a step, and a name costs a twelfth for each local the
/// evaluator compares it with before it finds it (it searches from the innermost out; a name
/// that is no local there is compared with all of them). A comparison of two names takes about
/// a twelfth of the time of a node: measured on a 500-fold nested SIN, whose 500 shared parts
/// (2,005 nodes, 126,756 comparisons a point) ran 5.6 times as fast as the formulas without
/// them (65,005 nodes, 1,506 comparisons).
fn twelfths(e: &Expr, names: &Locals, bound: usize) -> u64 {
    let mut n = 0;
    e.visit(&mut |node| {
        n += 12;
        if let ExprKind::Name(name) = &node.kind {
            let compared = match names.0.get(&name.to_lowercase()) {
                Some(&place) if place < bound => bound - place,
                _ => bound,
            };
            n += compared as u64;
        }
    });
    n
}

fn bind<T>(ctx: &mut Ctx, temps: &[(Rc<str>, Expr)], body: &mut dyn FnMut(&mut Ctx) -> T) -> T {
    let Some(((name, def), rest)) = temps.split_first() else { return body(ctx) };
    let value = ctx.eval(def);
    ctx.with_local(name.clone(), value, |ctx| bind(ctx, rest, body))
}

/// The distinct subformulas of the three trees, each given a number once from its head and
/// its children's numbers: equal numbers for equal subformulas, whatever their spans and
/// parentheses. The work is linear in the trees' size; a text key per node (the subformula
/// written out) was quadratic in their depth, 2.1 GB and minutes for a 999-term sum.
#[derive(Default)]
struct Parts<'e> {
    numbers: HashMap<(String, Vec<u32>), u32>,
    /// The number of each node, by its address (the trees are borrowed, so it is stable).
    of_node: HashMap<*const Expr, u32>,
    /// The first node met with each number.
    first: Vec<&'e Expr>,
}

impl<'e> Parts<'e> {
    fn intern(&mut self, e: &'e Expr) -> u32 {
        let e = bare(e);
        let children: Vec<u32> = children(e).map(|c| self.intern(c)).collect();
        let next = self.first.len() as u32;
        let id = *self.numbers.entry((head(e), children)).or_insert(next);
        if id == next {
            self.first.push(e);
        }
        self.of_node.insert(e as *const Expr, id);
        id
    }

    fn number(&self, e: &Expr) -> u32 {
        self.of_node[&(bare(e) as *const Expr)]
    }
}

/// How often each shareable subformula is used: once per distinct parent, so the parts of a
/// repeated part are not counted again.
struct Counter {
    refs: Vec<usize>,
    seen: Vec<bool>,
    /// Numbers of shareable subformulas, children before parents.
    order: Vec<u32>,
}

impl Counter {
    fn visit(&mut self, e: &Expr, parts: &Parts) {
        let e = bare(e);
        let id = parts.number(e);
        if std::mem::replace(&mut self.seen[id as usize], true) {
            self.refs[id as usize] += 1;
            return;
        }
        children(e).for_each(|c| self.visit(c, parts));
        if shareable(e) {
            self.refs[id as usize] = 1;
            self.order.push(id);
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

/// What a node is without its children: with the children's numbers, its identity.
fn head(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number(v) => format!("#{}", v.to_bits()),
        ExprKind::Name(n) => format!("${}", n.to_lowercase()),
        ExprKind::Unary(op, _) => format!("{op:?}"),
        ExprKind::Binary(op, ..) => format!("{op:?}"),
        ExprKind::Call(id, _) => format!("f{id}"),
        ExprKind::UnknownCall(name, _) => format!("u{name}"),
        ExprKind::Array(lit) => format!("{{{}x{}", lit.rows, lit.cols),
        other => format!("{other:?}"),
    }
}

/// The trees with each chosen part replaced by its name.
struct Rewrite<'p, 'e> {
    parts: &'p Parts<'e>,
    chosen: &'p HashMap<u32, Rc<str>>,
}

impl Rewrite<'_, '_> {
    /// `e` with each chosen part replaced by its name, and without what only printing needs:
    /// parentheses (the tree already says what they said) and negated literals (`-16` is a
    /// number). Evaluation is unchanged, with fewer steps.
    fn replace(&self, e: &Expr) -> Expr {
        let e = bare(e);
        if let Some(name) = self.chosen.get(&self.parts.number(e)) {
            return Expr::new(ExprKind::Name(name.clone()), Span::default());
        }
        if let ExprKind::Unary(UnaryOp::Neg, inner) = &e.kind {
            if let ExprKind::Number(v) = bare(inner).kind {
                return Expr::new(ExprKind::Number(-v), e.span);
            }
        }
        self.children(e)
    }

    /// `e` itself kept, its children replaced.
    fn children(&self, e: &Expr) -> Expr {
        let r = |a: &Expr| Box::new(self.replace(a));
        let kind = match &e.kind {
            ExprKind::Unary(op, a) => ExprKind::Unary(*op, r(a)),
            ExprKind::Paren(a) => return self.replace(a),
            ExprKind::Binary(op, a, b) => ExprKind::Binary(*op, r(a), r(b)),
            ExprKind::Call(id, args) => ExprKind::Call(*id, args.iter().map(|a| self.replace(a)).collect()),
            ExprKind::UnknownCall(n, args) => {
                ExprKind::UnknownCall(n.clone(), args.iter().map(|a| self.replace(a)).collect())
            }
            other => other.clone(),
        };
        Expr::new(kind, e.span)
    }
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
