//! Symbolic differentiation of formulas: `d/dx` of a syntax tree is another syntax tree, which
//! the one evaluator runs like any formula. A surface's normals are then exact to rounding, and
//! there is no second evaluator (dual numbers) to keep in step with Excel's semantics.
//!
//! Rules, for `u` and `v` depending on the variable (anything that does not — numbers, cell
//! references, other names, calls without the variable in their arguments — has derivative 0):
//!
//! - arithmetic `+ - * / ^ %`, `POWER`, `SQRT`, `EXP`, `LN`, `LOG10`, `LOG`, the trigonometric
//!   and hyperbolic functions and their inverses, `ATAN2`, `DEGREES`, `RADIANS`, `SQRTPI`, `MOD`:
//!   the textbook rules;
//! - `IF`, `IFS`, `CHOOSE`, `SWITCH`: the same choice between the differentiated branches, so a
//!   piecewise surface has the slope of the piece its condition picks (at a switch, that side's
//!   one-sided slope); `IFERROR(u, v)` becomes `IF(ISERROR(u), v', u')`;
//! - `ABS(u)` is `SIGN(u)·u'`: at the kink `u = 0` that is 0, a subgradient;
//! - `MIN`/`MAX` take the slope of the argument that is the minimum/maximum (the first one on
//!   a tie); `SUM` sums the slopes;
//! - rounding and step functions (`INT`, `ROUND`, `SIGN`, `FLOOR`, …) and comparisons are
//!   piecewise constant: slope 0 (at their jumps a surface has no slope at all);
//! - `LET(n, v, …)` binds `n` and its derivative `∂x.n` beside it.
//!
//! Anything else (a lookup, text functions, a call to a named LAMBDA) with the variable inside is
//! a [`DiffError`] naming the function. The results are simplified as they are built (constants
//! folded, `0·u` and `1·u` dropped) so derivative trees stay small, and parenthesised where
//! needed, so a derivative prints as a formula that reads back the same.

use std::rc::Rc;

use crate::formula::ast::{BinOp, Expr, ExprKind, Span, UnaryOp};
use crate::formula::parse::{binary_precedence, unary_precedence};

use super::functions;

/// A formula that cannot be differentiated: where (the node's span in the text) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffError {
    pub span: Span,
    pub message: String,
}

/// The parts (syntax-tree nodes) a slope may be built of: a surface's own formula is a few
/// dozen, a product of 1,400 factors about two million. Each part holds about 130 bytes.
pub const MAX_SLOPE_PARTS: usize = 1_000_000;

/// `∂e/∂var`, where `var` is a name (`x`, or a LAMBDA parameter) compared without case.
pub fn derivative(e: &Expr, var: &str) -> Result<Expr, DiffError> {
    derivative_within(e, var, MAX_SLOPE_PARTS)
}

/// [`derivative`], refused once building it has taken `parts` parts: the nodes of the
/// formula it differentiated and the parts of the formula it copied into the slope.
pub fn derivative_within(e: &Expr, var: &str, parts: usize) -> Result<Expr, DiffError> {
    let mut differ = Differ { var, lets: Vec::new(), room: parts.saturating_add(1) };
    differ.d(e).map_err(|err| match differ.room {
        // The limit is the whole formula's, not the node's where it ran out.
        0 => DiffError { span: e.span, message: slope_limit_message(var, parts) },
        _ => err,
    })
}

fn slope_limit_message(var: &str, parts: usize) -> String {
    format!(
        "the surface's slope by {var} would have more than {parts} parts; write the surface \
         shorter (a product of n factors has a slope of about n² parts)"
    )
}

struct Differ<'v> {
    var: &'v str,
    /// LET names in scope, innermost last, with the name of their derivative when it is not 0.
    lets: Vec<(Rc<str>, Option<Rc<str>>)>,
    /// Parts the slope may still take ([`MAX_SLOPE_PARTS`]).
    room: usize,
}

impl Differ<'_> {
    fn d(&mut self, e: &Expr) -> Result<Expr, DiffError> {
        self.room = self.room.saturating_sub(1);
        let slope = self.d_node(e)?;
        if self.room == 0 {
            return Err(DiffError { span: e.span, message: String::new() });
        }
        Ok(slope)
    }

    fn d_node(&mut self, e: &Expr) -> Result<Expr, DiffError> {
        Ok(match &e.kind {
            ExprKind::Name(name) => self.d_name(name),
            ExprKind::Paren(inner) => self.d(inner)?,
            ExprKind::Unary(op, inner) => match op {
                UnaryOp::Neg => neg(self.d(inner)?),
                UnaryOp::Plus | UnaryOp::Implicit => self.d(inner)?,
                UnaryOp::Percent => div(self.d(inner)?, num(100.0)),
                // Logical negation and spilled ranges are piecewise constant.
                UnaryOp::Spill | UnaryOp::Not => num(0.0),
            },
            ExprKind::Binary(op, a, b) => self.d_binary(e, *op, a, b)?,
            ExprKind::Call(id, args) => self.d_call(e, functions::spec(*id).name, args)?,
            ExprKind::UnknownCall(name, args) => {
                if self.all_constant(args)? {
                    num(0.0)
                } else {
                    return Err(unsupported(e, name));
                }
            }
            ExprKind::Number(_)
            | ExprKind::Text(_)
            | ExprKind::Bool(_)
            | ExprKind::Error(_)
            | ExprKind::Missing
            | ExprKind::Ref(_)
            | ExprKind::Table(_)
            | ExprKind::Array(_) => num(0.0),
            // `Sheet2!Rate` reads the workbook, not the surface's x and y.
            ExprKind::SheetName(..) => num(0.0),
            ExprKind::Invoke(..) => return Err(unsupported(e, "a LAMBDA called in place")),
            ExprKind::OptionalParam(name) => return Err(unsupported(e, name)),
            // Macro-only nodes never reach a surface formula.
            ExprKind::Host(_) => return Err(unsupported(e, "a macro expression")),
        })
    }

    fn d_name(&self, name: &str) -> Expr {
        match self.lets.iter().rev().find(|(n, _)| n.eq_ignore_ascii_case(name)) {
            Some((_, Some(dn))) => Expr::new(ExprKind::Name(dn.clone()), Span::default()),
            Some((_, None)) => num(0.0),
            None if name.eq_ignore_ascii_case(self.var) => num(1.0),
            None => num(0.0),
        }
    }

    fn d_binary(&mut self, e: &Expr, op: BinOp, a: &Expr, b: &Expr) -> Result<Expr, DiffError> {
        let (da, db) = (self.d(a)?, self.d(b)?);
        let (a, b) = (bare(a), bare(b));
        Ok(match op {
            BinOp::Add => add(da, db),
            BinOp::Sub => sub(da, db),
            // (uv)' = u'v + uv'
            BinOp::Mul => add(mul(da, self.copy(b)), mul(self.copy(a), db)),
            // (u/v)' = u'/v − u·v'/v²
            BinOp::Div => sub(div(da, self.copy(b)), div(mul(self.copy(a), db), pow(self.copy(b), num(2.0)))),
            BinOp::Pow => self.d_power(a, b, da, db),
            // A comparison is TRUE or FALSE on either side of its switch: slope 0.
            BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Like => num(0.0),
            // A reference operator is no number: its derivative is that of a constant.
            BinOp::Range | BinOp::Intersect | BinOp::Union => num(0.0),
            BinOp::Concat if is_zero(&da) && is_zero(&db) => num(0.0),
            BinOp::Concat => return Err(unsupported(e, "&")),
            // The macro language's logical operators are piecewise constant too.
            BinOp::And | BinOp::Or | BinOp::Xor | BinOp::Eqv | BinOp::Imp => num(0.0),
            BinOp::Mod | BinOp::IntDiv => return Err(unsupported(e, "Mod")),
        })
    }

    fn d_call(&mut self, e: &Expr, name: &str, args: &[Expr]) -> Result<Expr, DiffError> {
        match name {
            "LET" => return self.d_let(args),
            "IF" => return self.d_choice(name, args, 1),
            "IFS" => return self.d_ifs(args),
            "CHOOSE" => return self.d_choice(name, args, 1),
            "SWITCH" => return self.d_switch(args),
            "IFERROR" => return self.d_iferror(args),
            "MIN" | "MAX" => return self.d_extremum(name, args),
            "SUM" => return self.d_sum(args),
            _ => {}
        }
        let mut ds = args.iter().map(|a| self.d(a)).collect::<Result<Vec<_>, _>>()?;
        if ds.iter().all(is_zero) {
            return Ok(num(0.0));
        }
        if name == "LOG" {
            return Ok(self.d_log(args, ds));
        }
        let u = args.first().map(|a| self.copy(bare(a))).unwrap_or_else(|| num(0.0));
        let du = take(&mut ds, 0);
        // Most rules are f'(u)·u': `outer` is f'(u).
        let outer = match name {
            "ABS" => call("SIGN", vec![u]),
            "SQRT" => div(num(1.0), mul(num(2.0), call("SQRT", vec![u]))),
            "SQRTPI" => div(num(std::f64::consts::PI), mul(num(2.0), call("SQRTPI", vec![u]))),
            "EXP" => call("EXP", vec![u]),
            "LN" => div(num(1.0), u),
            "LOG10" => div(num(1.0), mul(u, num(std::f64::consts::LN_10))),
            "POWER" => return Ok(self.d_power(&u, bare(&args[1]), du, take(&mut ds, 1))),
            "SIN" => call("COS", vec![u]),
            "COS" => neg(call("SIN", vec![u])),
            "TAN" => div(num(1.0), pow(call("COS", vec![u]), num(2.0))),
            "COT" => neg(div(num(1.0), pow(call("SIN", vec![u]), num(2.0)))),
            "SEC" => mul(call("SEC", vec![self.copy(&u)]), call("TAN", vec![u])),
            "CSC" => neg(mul(call("CSC", vec![self.copy(&u)]), call("COT", vec![u]))),
            "ASIN" => div(num(1.0), call("SQRT", vec![sub(num(1.0), pow(u, num(2.0)))])),
            "ACOS" => neg(div(num(1.0), call("SQRT", vec![sub(num(1.0), pow(u, num(2.0)))]))),
            "ATAN" => div(num(1.0), add(num(1.0), pow(u, num(2.0)))),
            "ACOT" => neg(div(num(1.0), add(num(1.0), pow(u, num(2.0))))),
            "SINH" => call("COSH", vec![u]),
            "COSH" => call("SINH", vec![u]),
            "TANH" => div(num(1.0), pow(call("COSH", vec![u]), num(2.0))),
            "COTH" => neg(div(num(1.0), pow(call("SINH", vec![u]), num(2.0)))),
            "SECH" => neg(mul(call("SECH", vec![self.copy(&u)]), call("TANH", vec![u]))),
            "CSCH" => neg(mul(call("CSCH", vec![self.copy(&u)]), call("COTH", vec![u]))),
            "ASINH" => div(num(1.0), call("SQRT", vec![add(pow(u, num(2.0)), num(1.0))])),
            "ACOSH" => div(num(1.0), call("SQRT", vec![sub(pow(u, num(2.0)), num(1.0))])),
            "ATANH" | "ACOTH" => div(num(1.0), sub(num(1.0), pow(u, num(2.0)))),
            "DEGREES" => num(180.0 / std::f64::consts::PI),
            "RADIANS" => num(std::f64::consts::PI / 180.0),
            "ATAN2" => return Ok(self.d_atan2(&u, bare(&args[1]), du, take(&mut ds, 1))),
            "MOD" => return Ok(self.d_mod(&u, bare(&args[1]), du, take(&mut ds, 1))),
            _ if is_step_function(name) => return Ok(num(0.0)),
            _ => return Err(unsupported(e, name)),
        };
        Ok(mul(outer, du))
    }

    /// `LOG(u, [base])` is `LN(u)/LN(base)`.
    fn d_log(&mut self, args: &[Expr], mut ds: Vec<Expr>) -> Expr {
        let u = self.copy(bare(&args[0]));
        let du = take(&mut ds, 0);
        match args.get(1).filter(|b| b.kind != ExprKind::Missing) {
            None => div(du, mul(u, num(std::f64::consts::LN_10))),
            Some(base) => {
                let ln_u = call("LN", vec![self.copy(&u)]);
                let ln_b = call("LN", vec![self.copy(bare(base))]);
                let d_ln_u = div(du, u);
                let d_ln_b = div(take(&mut ds, 1), self.copy(bare(base)));
                sub(div(d_ln_u, self.copy(&ln_b)), div(mul(ln_u, d_ln_b), pow(ln_b, num(2.0))))
            }
        }
    }

    /// `LET(n1, v1, …, calc)`: each name gets its derivative bound beside it, so the values
    /// are not written out again in the derivative of `calc`.
    fn d_let(&mut self, args: &[Expr]) -> Result<Expr, DiffError> {
        let depth = self.lets.len();
        let out = self.d_let_pairs(args);
        self.lets.truncate(depth);
        out
    }

    fn d_let_pairs(&mut self, args: &[Expr]) -> Result<Expr, DiffError> {
        let (pairs, calc) = args.split_at(args.len() - 1);
        if pairs.len() % 2 != 0 {
            // LET with an even argument count is #VALUE!; its slope does not matter.
            return Ok(num(0.0));
        }
        let mut out = Vec::new();
        for pair in pairs.chunks(2) {
            let ExprKind::Name(name) = &pair[0].kind else { return Ok(num(0.0)) };
            let dv = self.d(&pair[1])?;
            out.extend([self.copy(&pair[0]), self.copy(&pair[1])]);
            let dname: Option<Rc<str>> = if is_zero(&dv) {
                None
            } else {
                let dname: Rc<str> = format!("∂{}.{}", self.var, name).into();
                out.extend([Expr::new(ExprKind::Name(dname.clone()), Span::default()), dv]);
                Some(dname)
            };
            self.lets.push((name.clone(), dname));
        }
        let dcalc = self.d(&calc[0])?;
        if let ExprKind::Number(_) = dcalc.kind {
            return Ok(dcalc);
        }
        out.push(dcalc);
        Ok(call("LET", out))
    }

    /// IF and CHOOSE: the arguments from `first` on are the alternatives, differentiated in
    /// place under the same condition or index.
    fn d_choice(&mut self, name: &str, args: &[Expr], first: usize) -> Result<Expr, DiffError> {
        let mut out: Vec<Expr> = args[..first].iter().map(|a| self.copy(a)).collect();
        for a in &args[first..] {
            out.push(self.d_branch(a)?);
        }
        // IF(c, a) is FALSE when c is: slope 0 there.
        if name == "IF" && out.len() == 2 {
            out.push(num(0.0));
        }
        Ok(if out[first..].iter().all(is_zero) { num(0.0) } else { call(name, out) })
    }

    fn d_branch(&mut self, e: &Expr) -> Result<Expr, DiffError> {
        if e.kind == ExprKind::Missing {
            return Ok(num(0.0));
        }
        self.d(e)
    }

    fn d_ifs(&mut self, args: &[Expr]) -> Result<Expr, DiffError> {
        let mut out = Vec::with_capacity(args.len());
        for pair in args.chunks(2) {
            out.push(self.copy(&pair[0]));
            if let Some(value) = pair.get(1) {
                out.push(self.d_branch(value)?);
            }
        }
        Ok(if out.iter().skip(1).step_by(2).all(is_zero) { num(0.0) } else { call("IFS", out) })
    }

    /// `SWITCH(e, v1, r1, …, [default])`: the results are differentiated, the cases kept.
    fn d_switch(&mut self, args: &[Expr]) -> Result<Expr, DiffError> {
        let mut out = vec![self.copy(&args[0])];
        let mut any = false;
        for (i, a) in args[1..].iter().enumerate() {
            let is_result = i % 2 == 1 || i == args.len() - 2;
            if is_result {
                let da = self.d_branch(a)?;
                any |= !is_zero(&da);
                out.push(da);
            } else {
                out.push(self.copy(a));
            }
        }
        Ok(if any { call("SWITCH", out) } else { num(0.0) })
    }

    fn d_iferror(&mut self, args: &[Expr]) -> Result<Expr, DiffError> {
        let (dv, dalt) = (self.d(&args[0])?, self.d_branch(&args[1])?);
        if is_zero(&dv) && is_zero(&dalt) {
            return Ok(num(0.0));
        }
        Ok(call("IF", vec![call("ISERROR", vec![self.copy(&args[0])]), dalt, dv]))
    }

    /// `MAX(a, b, …)`: the slope of the first argument equal to the maximum. Arguments without
    /// the variable (ranges included) have slope 0 and need no test.
    fn d_extremum(&mut self, name: &str, args: &[Expr]) -> Result<Expr, DiffError> {
        let whole = call(name, args.iter().map(|a| self.copy(a)).collect());
        let mut out = num(0.0);
        for a in args.iter().rev() {
            let da = self.d(a)?;
            if !is_zero(&da) {
                let attained = Expr::new(
                    ExprKind::Binary(
                        BinOp::Eq,
                        Box::new(wrap(self.copy(bare(a)), binary_precedence(BinOp::Eq) + 1)),
                        Box::new(self.copy(&whole)),
                    ),
                    Span::default(),
                );
                out = call("IF", vec![attained, da, out]);
            }
        }
        Ok(out)
    }

    fn d_sum(&mut self, args: &[Expr]) -> Result<Expr, DiffError> {
        let ds: Vec<Expr> = args.iter().map(|a| self.d(a)).collect::<Result<Vec<_>, _>>()?;
        let ds: Vec<Expr> = ds.into_iter().filter(|d| !is_zero(d)).collect();
        Ok(if ds.is_empty() { num(0.0) } else { call("SUM", ds) })
    }

    fn all_constant(&mut self, args: &[Expr]) -> Result<bool, DiffError> {
        for a in args {
            if !is_zero(&self.d(a)?) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// `(a^b)'`: `b·a^(b−1)·a'` for a constant exponent (so `x^2` at x = 0 has slope 0, where the
    /// general rule would take `LN(0)`), `a^b·LN(a)·b'` for a constant base, both terms otherwise.
    fn d_power(&mut self, a: &Expr, b: &Expr, da: Expr, db: Expr) -> Expr {
        match (is_zero(&da), is_zero(&db)) {
            (true, true) => num(0.0),
            (false, true) => self.power_rule(a, b, da),
            (true, false) => self.exponent_rule(a, b, db),
            (false, false) => add(self.power_rule(a, b, da), self.exponent_rule(a, b, db)),
        }
    }

    fn power_rule(&mut self, a: &Expr, b: &Expr, da: Expr) -> Expr {
        match b.kind {
            ExprKind::Number(n) => mul(mul(num(n), pow(self.copy(a), num(n - 1.0))), da),
            _ => mul(mul(self.copy(b), pow(self.copy(a), sub(self.copy(b), num(1.0)))), da),
        }
    }

    fn exponent_rule(&mut self, a: &Expr, b: &Expr, db: Expr) -> Expr {
        mul(mul(pow(self.copy(a), self.copy(b)), call("LN", vec![self.copy(a)])), db)
    }

    /// Excel's `ATAN2(x, y)` is the angle of the point (x, y): slope `(x·y' − y·x')/(x² + y²)`.
    fn d_atan2(&mut self, x: &Expr, y: &Expr, dx: Expr, dy: Expr) -> Expr {
        let r2 = add(pow(self.copy(x), num(2.0)), pow(self.copy(y), num(2.0)));
        div(sub(mul(self.copy(x), dy), mul(self.copy(y), dx)), r2)
    }

    /// `MOD(n, d) = n − d·INT(n/d)`; INT is piecewise constant.
    fn d_mod(&mut self, n: &Expr, d: &Expr, dn: Expr, dd: Expr) -> Expr {
        sub(dn, mul(dd, call("INT", vec![div(self.copy(n), self.copy(d))])))
    }

    /// A copy of a part of the formula in its slope, charged to [`MAX_SLOPE_PARTS`]: a product
    /// of n factors has a slope of n²/2 parts, a chain of them would fill the memory.
    fn copy(&mut self, e: &Expr) -> Expr {
        let mut parts = 0usize;
        e.visit(&mut |_| parts += 1);
        self.room = self.room.saturating_sub(parts);
        e.clone()
    }
}

/// Numeric functions of numbers with a derivative rule here: no references, no side notes.
pub fn is_pure_numeric(name: &str) -> bool {
    is_step_function(name)
        || matches!(
            name,
            "ABS"
                | "SQRT"
                | "SQRTPI"
                | "EXP"
                | "LN"
                | "LOG10"
                | "LOG"
                | "POWER"
                | "SIN"
                | "COS"
                | "TAN"
                | "COT"
                | "SEC"
                | "CSC"
                | "ASIN"
                | "ACOS"
                | "ATAN"
                | "ACOT"
                | "SINH"
                | "COSH"
                | "TANH"
                | "COTH"
                | "SECH"
                | "CSCH"
                | "ASINH"
                | "ACOSH"
                | "ATANH"
                | "ACOTH"
                | "DEGREES"
                | "RADIANS"
                | "ATAN2"
                | "MOD"
        )
}

/// Functions whose value only jumps: slope 0 between the jumps.
fn is_step_function(name: &str) -> bool {
    matches!(
        name,
        "SIGN"
            | "INT"
            | "TRUNC"
            | "ROUND"
            | "ROUNDUP"
            | "ROUNDDOWN"
            | "MROUND"
            | "EVEN"
            | "ODD"
            | "FACT"
            | "QUOTIENT"
            | "FLOOR"
            | "FLOOR.MATH"
            | "FLOOR.PRECISE"
            | "CEILING"
            | "CEILING.MATH"
            | "CEILING.PRECISE"
            | "ISO.CEILING"
            | "NOT"
            | "AND"
            | "OR"
            | "XOR"
            | "TRUE"
            | "FALSE"
            | "PI"
    )
}

fn unsupported(e: &Expr, name: &str) -> DiffError {
    DiffError {
        span: e.span,
        message: format!(
            "cannot differentiate {name} with respect to the surface's variables; write the surface with \
             arithmetic and the elementary functions (docs/ballpath.md lists them)"
        ),
    }
}

// ---- building simplified trees ------------------------------------------------------------

/// The `i`th of the arguments' slopes, moved out (a slope can be large; it is used once).
fn take(ds: &mut [Expr], i: usize) -> Expr {
    std::mem::replace(&mut ds[i], num(0.0))
}

fn num(v: f64) -> Expr {
    Expr::new(ExprKind::Number(v), Span::default())
}

fn number_of(e: &Expr) -> Option<f64> {
    match e.kind {
        ExprKind::Number(v) => Some(v),
        _ => None,
    }
}

fn is_zero(e: &Expr) -> bool {
    number_of(e) == Some(0.0)
}

/// A subtree without its outer parentheses (they are added back where the new parent needs
/// them).
fn bare(e: &Expr) -> &Expr {
    match &e.kind {
        ExprKind::Paren(inner) => bare(inner),
        _ => e,
    }
}

/// How tightly a node binds when printed, on the parser's one precedence scale (atoms bind
/// tightest).
fn precedence(e: &Expr) -> u8 {
    match &e.kind {
        ExprKind::Binary(op, ..) => binary_precedence(*op),
        ExprKind::Unary(op, _) => unary_precedence(*op),
        // A negative number prints with its sign, like a negation.
        ExprKind::Number(v) if v.is_sign_negative() => unary_precedence(UnaryOp::Neg),
        _ => u8::MAX,
    }
}

/// Parenthesises `e` unless it binds at least as tightly as `min`.
fn wrap(e: Expr, min: u8) -> Expr {
    if precedence(&e) >= min {
        e
    } else {
        let span = e.span;
        Expr::new(ExprKind::Paren(Box::new(e)), span)
    }
}

/// A left-associative binary node: the right operand must bind tighter than the operator.
fn binary(op: BinOp, a: Expr, b: Expr) -> Expr {
    let p = binary_precedence(op);
    Expr::new(ExprKind::Binary(op, Box::new(wrap(a, p)), Box::new(wrap(b, p + 1))), Span::default())
}

/// A folded constant, unless folding overflows (then the evaluator reports it as it would).
fn folded(v: f64) -> Option<Expr> {
    v.is_finite().then(|| num(v))
}

fn add(a: Expr, b: Expr) -> Expr {
    match (number_of(&a), number_of(&b)) {
        (Some(0.0), _) => b,
        (_, Some(0.0)) => a,
        (Some(x), Some(y)) => folded(x + y).unwrap_or_else(|| binary(BinOp::Add, a, b)),
        _ => match into_negated(b) {
            Ok(inner) => sub(a, inner),
            Err(b) => binary(BinOp::Add, a, b),
        },
    }
}

fn sub(a: Expr, b: Expr) -> Expr {
    match (number_of(&a), number_of(&b)) {
        (_, Some(0.0)) => a,
        (Some(0.0), _) => neg(b),
        (Some(x), Some(y)) => folded(x - y).unwrap_or_else(|| binary(BinOp::Sub, a, b)),
        _ => binary(BinOp::Sub, a, b),
    }
}

/// The operand of a negation (`-u` → `u`, `-3` → `3`), for `a + -u` → `a - u`; `e` itself
/// back when it is none. Taken apart, not copied: a derivative's terms can be large.
fn into_negated(e: Expr) -> Result<Expr, Expr> {
    let span = e.span;
    match e.kind {
        ExprKind::Unary(UnaryOp::Neg, inner) => Ok(unparen(*inner)),
        ExprKind::Number(v) if v < 0.0 => Ok(num(-v)),
        kind => Err(Expr::new(kind, span)),
    }
}

/// `e` without its outer parentheses, taken apart.
fn unparen(e: Expr) -> Expr {
    match e.kind {
        ExprKind::Paren(inner) => unparen(*inner),
        kind => Expr::new(kind, e.span),
    }
}

fn neg(a: Expr) -> Expr {
    if let Some(v) = number_of(&a) {
        return num(-v);
    }
    let a = match into_negated(a) {
        Ok(inner) => return inner,
        Err(a) => a,
    };
    // −(c·u) = (−c)·u keeps constants in front where they fold.
    if let ExprKind::Binary(BinOp::Mul, c, _) = &a.kind {
        if let Some(c) = number_of(c) {
            let (_, u) = split_constant(a);
            return mul(num(-c), u.expect("a product has a factor besides its constant"));
        }
    }
    let inner = wrap(a, unary_precedence(UnaryOp::Neg));
    Expr::new(ExprKind::Unary(UnaryOp::Neg, Box::new(inner)), Span::default())
}

/// A product with its constant factor (if any) in front: `c·u` → (c, u).
fn split_constant(e: Expr) -> (f64, Option<Expr>) {
    if let Some(v) = number_of(&e) {
        return (v, None);
    }
    let span = e.span;
    match e.kind {
        ExprKind::Binary(BinOp::Mul, c, u) if number_of(&c).is_some() => (constant_factor(&c), Some(unparen(*u))),
        ExprKind::Unary(UnaryOp::Neg, inner) => {
            let (c, u) = split_constant(unparen(*inner));
            (-c, u)
        }
        kind => (1.0, Some(Expr::new(kind, span))),
    }
}

/// The constant [`split_constant`] finds, read without taking `e` apart.
fn constant_factor(e: &Expr) -> f64 {
    if let Some(v) = number_of(e) {
        return v;
    }
    match &e.kind {
        ExprKind::Binary(BinOp::Mul, c, _) => number_of(c).unwrap_or(1.0),
        ExprKind::Unary(UnaryOp::Neg, inner) => -constant_factor(bare(inner)),
        _ => 1.0,
    }
}

fn mul(a: Expr, b: Expr) -> Expr {
    if is_zero(&a) || is_zero(&b) {
        // 0·u is 0 in a derivative even where u has no value (it comes from a constant's
        // slope), as in every differentiation by hand.
        return num(0.0);
    }
    let c = constant_factor(&a) * constant_factor(&b);
    if !c.is_finite() {
        return binary(BinOp::Mul, a, b);
    }
    let rest = match (split_constant(a).1, split_constant(b).1) {
        (None, None) => return num(c),
        (Some(u), None) | (None, Some(u)) => u,
        (Some(u), Some(v)) => binary(BinOp::Mul, u, v),
    };
    if c == 1.0 {
        rest
    } else if c == -1.0 {
        neg(rest)
    } else {
        binary(BinOp::Mul, num(c), rest)
    }
}

fn div(a: Expr, b: Expr) -> Expr {
    match (number_of(&a), number_of(&b)) {
        (Some(0.0), _) => num(0.0),
        (_, Some(1.0)) => a,
        (Some(x), Some(y)) if y != 0.0 => folded(x / y).unwrap_or_else(|| binary(BinOp::Div, a, b)),
        _ => binary(BinOp::Div, a, b),
    }
}

fn pow(a: Expr, b: Expr) -> Expr {
    match number_of(&b) {
        Some(1.0) => a,
        // u^0 is 1 except where u is 0 (Excel: 0^0 is #NUM!); the derivative of u^1 asks for
        // u^0 and means 1.
        Some(0.0) => num(1.0),
        _ => binary(BinOp::Pow, a, b),
    }
}

fn call(name: &str, args: Vec<Expr>) -> Expr {
    let id = functions::find(name).unwrap_or_else(|| panic!("{name} is in the registry"));
    let args = args.into_iter().map(|a| if let ExprKind::Paren(inner) = a.kind { *inner } else { a }).collect();
    Expr::new(ExprKind::Call(id, args), Span::default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::functions::Registry;
    use crate::formula::address::Pos;
    use crate::formula::parse::{parse_formula, ParseContext};
    use crate::formula::print::print_formula;

    fn parse(text: &str) -> Expr {
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
        parse_formula(text, &ctx).unwrap_or_else(|e| panic!("{}", e.render(text)))
    }

    /// The derivative of `text` with respect to x, printed.
    fn dx(text: &str) -> String {
        let d = derivative(&parse(text), "x").unwrap_or_else(|e| panic!("{text}: {}", e.message));
        print_formula(&d, Pos::new(0, 0), &Registry, &|_| String::new())
    }

    #[test]
    fn textbook_rules_come_out_small() {
        assert_eq!(dx("x^3"), "3*x^2");
        assert_eq!(dx("x^2"), "2*x");
        assert_eq!(dx("5*x"), "5");
        assert_eq!(dx("y*x"), "y");
        assert_eq!(dx("7+y"), "0");
        // Excel's -x^2 is (-x)^2; the negation of a square needs its parentheses.
        assert_eq!(dx("-x^2"), "2*x");
        assert_eq!(dx("-(x^2)"), "-2*x");
        assert_eq!(dx("x*y*x"), "y*x+x*y");
        assert_eq!(dx("ATAN2(x,y)"), "-y/(x^2+y^2)");
        assert_eq!(dx("SIN(2*x)"), "2*COS(2*x)");
        assert_eq!(dx("0.3*EXP(-16*x^2-16*y^2)"), "-9.6*(EXP(-16*x^2-16*y^2)*x)");
        assert_eq!(dx("1/x"), "-(1/x^2)");
        assert_eq!(dx("ABS(x-1)"), "SIGN(x-1)");
        assert_eq!(dx("2^x"), "2^x*LN(2)");
    }

    #[test]
    fn choices_keep_their_conditions() {
        assert_eq!(dx("IF(x>0,x^2,-x)"), "IF(x>0,2*x,-1)");
        assert_eq!(dx("IF(x>0,x^2)"), "IF(x>0,2*x,0)");
        assert_eq!(dx("MAX(x,2*x,A1)"), "IF(x=MAX(x,2*x,A1),1,IF(2*x=MAX(x,2*x,A1),2,0))");
        assert_eq!(dx("LET(rr,x^2+y^2,EXP(-rr))"), "LET(rr,x^2+y^2,∂x.rr,2*x,-(EXP(-rr)*∂x.rr))");
        assert_eq!(dx("LET(x,3,x*y)"), "0");
        assert_eq!(dx("ROUND(x,2)+B7"), "0");
    }

    #[test]
    fn what_has_no_derivative_is_named() {
        let err = derivative(&parse("=1+VLOOKUP(x,A1:B9,2)"), "x").unwrap_err();
        assert!(err.message.starts_with("cannot differentiate VLOOKUP"), "{}", err.message);
        assert_eq!(err.span, Span { start: 3, end: 21 });
        assert_eq!(dx("VLOOKUP(y,A1:B9,2)*x"), "VLOOKUP(y,A1:B9,2)");
        // An unknown function is named as typed.
        assert!(derivative(&parse("bump(x,1)"), "x").unwrap_err().message.contains("bump"));
    }
}
