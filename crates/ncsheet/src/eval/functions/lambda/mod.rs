//! LET and LAMBDA, the language's own names and functions, and ISOMITTED: LET binds names
//! for its calculation; a LAMBDA is a value (`Value::Lambda`, a closure) called through a LET
//! name, a parameter or a defined name (the evaluator binds its parameters,
//! `Ctx::call_defined_lambda`), where an expression gives it (`f(3)(4)`), or by the functions
//! of `arrays.rs` that run one over arrays (MAP, REDUCE …). [`as_lambda`] is how the rest of the engine reads one.

pub(crate) mod arrays;

use std::rc::Rc;
use std::sync::LazyLock;

use crate::eval::functions::api::{bind_own_name, Ctx, FnSpec, MANY};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind, FnId};

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[FUNCTIONS, arrays::FUNCTIONS];

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "LET",
        3,
        MANY,
        let_fn,
        "LET(name1, value1, [name2, value2, …], calculation)",
        "calculation with each name bound to its value, in order",
    )
    .future(),
    FnSpec::value(
        "LAMBDA",
        1,
        MANY,
        lambda,
        "LAMBDA([parameter1, …], calculation)",
        "A function of its parameters, called through a defined name (bump(1, 2)); alone in a cell #CALC!",
    )
    .future()
    .dynamic()
    .reads_trees(),
    FnSpec::value(
        "ISOMITTED",
        1,
        1,
        isomitted,
        "ISOMITTED(argument)",
        "TRUE for a LAMBDA parameter whose argument the call left out (f(1,))",
    )
    .future(),
];

fn let_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    if args.len().is_multiple_of(2) {
        return Err(XlError::Value);
    }
    Ok(bind_names(ctx, args))
}

/// Binds the first name/value pair and recurses into the rest, so that each value sees
/// the names before it and the calculation sees them all.
fn bind_names(ctx: &mut Ctx, args: &[Expr]) -> Value {
    let [name, value, rest @ ..] = args else {
        return ctx.eval(&args[0]);
    };
    let ExprKind::Name(name) = &name.kind else {
        return Value::Error(XlError::Value);
    };
    let name: Rc<str> = name.clone();
    // A LAMBDA (or what gives one) is bound as a value: `f(3)` calls it, its own body too.
    let mut value = ctx.eval(value);
    bind_own_name(&mut value, &name);
    ctx.with_local(name, value, |ctx| bind_names(ctx, rest))
}

/// A LAMBDA is a value to call, remembering the names around it; left alone in a cell it
/// shows `#CALC!` (`Ctx::eval_formula`). Parameters that are not names are `#VALUE!`.
fn lambda(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let call = Expr { kind: ExprKind::Call(*LAMBDA_ID, args.to_vec()), span: Default::default() };
    if as_lambda(&call).is_none() {
        return Err(XlError::Value);
    }
    Ok(ctx.closure(call))
}

/// ISOMITTED: only a parameter can be omitted; any other argument is FALSE.
fn isomitted(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let omitted = match &args[0].kind {
        ExprKind::Name(name) => ctx.is_omitted(name),
        _ => false,
    };
    Ok(Value::Bool(omitted))
}

/// `LAMBDA(p1, …, body)` taken apart.
pub struct Lambda<'e> {
    /// The parameters, each an `ExprKind::Name` or an `ExprKind::OptionalParam` (`[b]`).
    pub params: &'e [Expr],
    pub body: &'e Expr,
}

impl<'e> Lambda<'e> {
    pub fn param_names(&self) -> impl Iterator<Item = &'e Rc<str>> {
        self.params.iter().map(|p| match &p.kind {
            ExprKind::Name(n) | ExprKind::OptionalParam(n) => n,
            _ => unreachable!("as_lambda checked the parameters"),
        })
    }

    /// Whether a call may pass `n` arguments: every parameter up to the last required one,
    /// and at most all of them (the optional ones after it may be left out).
    pub fn accepts(&self, n: usize) -> bool {
        let required = self.params.iter().rposition(|p| matches!(p.kind, ExprKind::Name(_))).map_or(0, |i| i + 1);
        (required..=self.params.len()).contains(&n)
    }
}

static LAMBDA_ID: LazyLock<FnId> =
    LazyLock::new(|| crate::eval::functions::find("LAMBDA").expect("LAMBDA is registered"));

/// The names LET and LAMBDA bind anywhere in `expr` (parameters and LET's names): they are
/// not unknown, whatever the workbook defines.
pub fn bound_names(expr: &Expr) -> Vec<Rc<str>> {
    let mut names = Vec::new();
    expr.visit(&mut |e| {
        let ExprKind::Call(id, args) = &e.kind else { return };
        let bound: Vec<&Expr> = match crate::eval::functions::spec(*id).name {
            "LET" => args.iter().step_by(2).take(args.len() / 2).collect(),
            "LAMBDA" => args.iter().take(args.len().saturating_sub(1)).collect(),
            _ => return,
        };
        names.extend(bound.into_iter().filter_map(|a| match &a.kind {
            ExprKind::Name(n) => Some(n.clone()),
            _ => None,
        }));
    });
    names
}

/// `e` as a LAMBDA (parentheses around it allowed); `None` for anything else, and for a
/// LAMBDA whose parameters are not all names.
pub fn as_lambda(e: &Expr) -> Option<Lambda<'_>> {
    match &e.kind {
        ExprKind::Paren(inner) => as_lambda(inner),
        ExprKind::Call(id, args) if *id == *LAMBDA_ID => {
            let (body, params) = args.split_last()?;
            let is_param = |p: &Expr| matches!(p.kind, ExprKind::Name(_) | ExprKind::OptionalParam(_));
            params.iter().all(is_param).then_some(Lambda { params, body })
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::n;
    use crate::eval::testing::MapEnv;
    use crate::eval::{Value, XlError};

    fn env() -> MapEnv {
        MapEnv::with(&[("A1", n(1.0)), ("B1", n(10.0)), ("B2", n(20.0)), ("B3", n(30.0))])
    }

    #[test]
    fn let_binds_in_order() {
        let env = env();
        assert_eq!(env.eval("=LET(x,2,y,x*3,x+y)"), n(8.0));
        assert_eq!(env.eval("=LET(r,B1:B3,SUM(r))"), n(60.0));
        assert_eq!(env.eval("=2+LET(x,8,LET(x,2,x+x)*x)"), n(34.0));
        assert_eq!(env.eval("=LET(x,1,x)+x"), Value::Error(XlError::Name));
        // Excel refuses an even argument count (no calculation after the last pair).
        assert_eq!(env.eval("=LET(x,1,y,2)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=LET(x,1,2,3,x)"), Value::Error(XlError::Value));
    }

    #[test]
    fn a_lambda_alone_is_calc() {
        let env = env();
        // Excel 365: =LAMBDA(x,x+1) in a cell shows #CALC!.
        assert_eq!(env.eval("=LAMBDA(x,x+1)"), Value::Error(XlError::Calc));
        assert_eq!(env.eval("=ISERROR(LAMBDA(1))"), Value::Bool(true));
    }

    #[test]
    fn isomitted_tells_a_left_out_argument() {
        let env = env();
        // Microsoft's ISOMITTED page: LAMBDA(x,y, IF(ISOMITTED(y),"Missing second argument",x+y))(1,).
        let docs = "LAMBDA(x,y,IF(ISOMITTED(y),\"Missing second argument\",x+y))";
        assert_eq!(env.eval(&format!("=LET(f,{docs},f(1,))")), Value::text("Missing second argument"));
        assert_eq!(env.eval(&format!("=LET(f,{docs},f(1,2))")), n(3.0));
        // calc_tests/INFORMATION/ISOMITTED.xlsx: A6 = 6 (b left out), A7 = 36, with A5 = 12, B5 = 3.
        let corpus = "LAMBDA(a,b,IF(ISOMITTED(b),a/2,a*b))";
        assert_eq!(env.eval(&format!("=LET(f,{corpus},f(12,))")), n(6.0));
        assert_eq!(env.eval(&format!("=LET(f,{corpus},f(12,3))")), n(36.0));
        // A name bound again inside the body is no longer the omitted parameter.
        assert_eq!(env.eval("=LET(f,LAMBDA(a,b,LET(b,1,ISOMITTED(b))),f(12,))"), Value::Bool(false));
    }

    #[test]
    fn a_lambda_called_in_place_binds_its_arguments_and_leaves_out_optional_ones() {
        let env = MapEnv::with(&[("A5", n(12.0)), ("B5", n(3.0))]);
        // Microsoft's ISOMITTED page, and ISOMITTED.xlsx's cached values: A1, A6 = 6, A7 = 36.
        let docs = "=LAMBDA(x,y, IF(ISOMITTED(y),\"Missing second argument\",x+y))(1,)";
        assert_eq!(env.eval(docs), Value::text("Missing second argument"));
        let corpus = "LAMBDA(a,[b],IF(ISOMITTED(b),a/2,a*b))";
        assert_eq!(env.eval(&format!("={corpus}(A5)")), n(6.0));
        assert_eq!(env.eval(&format!("={corpus}(A5, B5)")), n(36.0));
        // The same through a LET name: an optional parameter may be left out there too.
        assert_eq!(env.eval(&format!("=LET(f,{corpus},f(A5))")), n(6.0));
        // Too few (a required one left out) or too many arguments: #VALUE!.
        assert_eq!(env.eval(&format!("={corpus}()")), Value::Error(XlError::Value));
        assert_eq!(env.eval(&format!("={corpus}(1,2,3)")), Value::Error(XlError::Value));
        // The body sees the LET names around the call.
        assert_eq!(env.eval("=LET(k,10,LAMBDA(x,x+k)(5))"), n(15.0));
    }
}
