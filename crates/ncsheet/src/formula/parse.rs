//! Formula text to syntax tree: binds `crates/ncsheet/grammar/formula.pest` and holds the one Pratt table.
//!
//! Precedence, lowest first (Excel's, every binary operator left-associative):
//!
//! ```text
//! = <> < <= > >=      comparison
//! &                   concatenation
//! + -                 addition
//! * /                 multiplication
//! ^                   power        (2^3^2 = 64)
//! %                   percent      (postfix)
//! - +                 negation     (prefix: -2^2 = 4)
//! @                   implicit intersection
//! ,                   union        (only inside parentheses: `(A1:A3,C1)`)
//! (space)             intersection (`A1:C3 B2:D4`)
//! #                   spill range  (postfix)
//! :                   range
//! ```
//!
//! The macro language (crates/ncsheet/src/vba) is compiled into the same parser (`crates/ncsheet/grammar/macro.pest`
//! beside `crates/ncsheet/grammar/formula.pest`, one `Rule` enum) and its expressions go through this table
//! too. Its operators follow the table for everything a formula has — so `-2^2` is 4 in a
//! macro as in a cell (VBA says -4) — and add VBA's own at VBA's levels, none of which formula
//! text can produce:
//!
//! ```text
//! Imp < Eqv < Xor < Or < And < Not (prefix)   below the comparisons
//! Mod < \                                     between + - and * /
//! ```

use std::rc::Rc;
use std::sync::LazyLock;

use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::{Pair, Pairs};
use pest::pratt_parser::{Assoc, Op, PrattParser};
use pest::Parser;
use pest_derive::Parser;

use super::address::{column_index, Pos, MAX_COLS, MAX_ROWS};
use super::ast::*;
use super::limits::{check_nesting, tree_depth_error, Language, MAX_TREE_DEPTH};

/// The one parser: formulas (`Rule::formula`) and macro modules (`Rule::module`).
#[derive(Parser)]
#[grammar = "../grammar/formula.pest"]
#[grammar = "../grammar/macro.pest"]
pub struct FormulaGrammar;

/// Every operator's binding power, lowest first: Excel's levels, with the macro language's
/// logical operators below the comparisons and `Mod`, `\\` between `+ -` and `* /`. The Pratt
/// table is built from this, and code that builds trees (derivatives) parenthesises by it:
/// precedence is written here and nowhere else.
pub fn binary_precedence(op: BinOp) -> u8 {
    match op {
        BinOp::Imp => 1,
        BinOp::Eqv => 2,
        BinOp::Xor => 3,
        BinOp::Or => 4,
        BinOp::And => 5,
        BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Like => 7,
        BinOp::Concat => 8,
        BinOp::Add | BinOp::Sub => 9,
        BinOp::Mod => 10,
        BinOp::IntDiv => 11,
        BinOp::Mul | BinOp::Div => 12,
        BinOp::Pow => 13,
        // Excel's reference operators bind tighter than negation: `:` > space > `,`.
        BinOp::Union => 17,
        BinOp::Intersect => 18,
        BinOp::Range => 20,
    }
}

/// The binding power of prefix and postfix operators, on the scale of [`binary_precedence`].
pub fn unary_precedence(op: UnaryOp) -> u8 {
    match op {
        UnaryOp::Not => 6,
        UnaryOp::Percent => 14,
        UnaryOp::Neg | UnaryOp::Plus => 15,
        UnaryOp::Implicit => 16,
        UnaryOp::Spill => 19,
    }
}

const INFIX_RULES: [(Rule, BinOp); 23] = [
    (Rule::range_op, BinOp::Range),
    (Rule::isect_op, BinOp::Intersect),
    (Rule::union_op, BinOp::Union),
    (Rule::pow, BinOp::Pow),
    (Rule::mul, BinOp::Mul),
    (Rule::div, BinOp::Div),
    (Rule::add, BinOp::Add),
    (Rule::sub, BinOp::Sub),
    (Rule::concat, BinOp::Concat),
    (Rule::eq, BinOp::Eq),
    (Rule::ne, BinOp::Ne),
    (Rule::lt, BinOp::Lt),
    (Rule::le, BinOp::Le),
    (Rule::gt, BinOp::Gt),
    (Rule::ge, BinOp::Ge),
    (Rule::mod_op, BinOp::Mod),
    (Rule::int_div, BinOp::IntDiv),
    (Rule::and_op, BinOp::And),
    (Rule::or_op, BinOp::Or),
    (Rule::xor_op, BinOp::Xor),
    (Rule::eqv_op, BinOp::Eqv),
    (Rule::imp_op, BinOp::Imp),
    (Rule::like_op, BinOp::Like),
];

const PREFIX_RULES: [(Rule, UnaryOp); 6] = [
    (Rule::neg, UnaryOp::Neg),
    (Rule::plus, UnaryOp::Plus),
    (Rule::not_op, UnaryOp::Not),
    (Rule::implicit, UnaryOp::Implicit),
    (Rule::vneg, UnaryOp::Neg),
    (Rule::vplus, UnaryOp::Plus),
];

/// A macro's sign (`vneg`, `vplus`): VBA ranks it below `^` and above `* /` ([MS-VBAL]
/// 5.6.9.3), where Excel ranks it above `^` (`-2^2` is -4 in VBA, 4 in a cell). The Pratt
/// table has a level between `* /` and `^` for it alone; cells never reach it.
fn is_macro_sign(rule: Rule) -> bool {
    matches!(rule, Rule::vneg | Rule::vplus)
}

const POSTFIX_RULES: [(Rule, UnaryOp); 2] = [(Rule::percent, UnaryOp::Percent), (Rule::spill_ref, UnaryOp::Spill)];

/// The Pratt table, level by level from [`binary_precedence`] and [`unary_precedence`]; every
/// binary operator is left-associative (`2^3^2` is 64).
static PRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    let mut pratt = PrattParser::new();
    for level in 1..=binary_precedence(BinOp::Range) {
        if level == binary_precedence(BinOp::Pow) {
            pratt = pratt.op(Op::prefix(Rule::vneg) | Op::prefix(Rule::vplus));
        }
        let infix = INFIX_RULES
            .iter()
            .filter(|(_, op)| binary_precedence(*op) == level)
            .map(|(r, _)| Op::infix(*r, Assoc::Left));
        let prefix = PREFIX_RULES
            .iter()
            .filter(|(r, op)| !is_macro_sign(*r) && unary_precedence(*op) == level)
            .map(|(r, _)| Op::prefix(*r));
        let postfix =
            POSTFIX_RULES.iter().filter(|(_, op)| unary_precedence(*op) == level).map(|(r, _)| Op::postfix(*r));
        if let Some(ops) = infix.chain(prefix).chain(postfix).reduce(|a, b| a | b) {
            pratt = pratt.op(ops);
        }
    }
    pratt
});

/// What the parser needs to know about functions; the evaluator's registry provides it.
pub trait FunctionTable {
    /// The id and argument bounds of a function, by name in any case (`_xlfn.` already removed).
    fn lookup(&self, name: &str) -> Option<FnInfo>;
    /// The canonical name of a function id.
    fn name(&self, id: FnId) -> &str;
}

#[derive(Clone, Copy, Debug)]
pub struct FnInfo {
    pub id: FnId,
    pub min_args: usize,
    pub max_args: usize,
}

/// Where a formula lives, which decides how its relative references are stored.
pub struct ParseContext<'a> {
    /// The cell that holds the formula (relative references are offsets from it).
    pub at: Pos,
    pub functions: &'a dyn FunctionTable,
    /// Resolves a sheet name used in a reference; `None` means the workbook has no such sheet.
    pub sheet: &'a dyn Fn(&str) -> Option<SheetId>,
}

/// A sheet name as written, bare (`Sheet2`) or quoted (`'Jan''s'`).
fn unquoted_sheet_name(raw: &str) -> String {
    match raw.strip_prefix('\'').and_then(|s| s.strip_suffix('\'')) {
        Some(quoted) => quoted.replace("''", "'"),
        None => raw.to_string(),
    }
}

/// `depth` when within [`MAX_TREE_DEPTH`], else the error at the operator `op`.
fn deeper(depth: u32, op: &Pair<Rule>) -> Result<u32, ParseError> {
    if depth > MAX_TREE_DEPTH {
        Err(tree_depth_error(op.as_span().start()))
    } else {
        Ok(depth)
    }
}

/// A formula that does not parse: where (byte offset in the text as typed) and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    pub offset: usize,
    pub message: String,
}

impl ParseError {
    fn at(offset: usize, message: impl Into<String>) -> ParseError {
        ParseError { offset, message: message.into() }
    }

    /// 1-based column in characters.
    pub fn column(&self, text: &str) -> usize {
        text.get(..self.offset.min(text.len())).map_or(self.offset, |s| s.chars().count()) + 1
    }

    /// The formula, a caret under the place, and the message:
    ///
    /// ```text
    /// =1+*2
    ///    ^ column 4: expected a value
    /// ```
    pub fn render(&self, text: &str) -> String {
        let e = self.explained(text);
        let col = e.column(text);
        let (shown, caret) = excerpt_around(text, col);
        format!("{shown}\n{}^ column {col}: {}", " ".repeat(caret), e.message)
    }

    /// The error as a user can act on it: a `(` never closed is shown at the `(` itself, and
    /// a `;` where an operator was expected is the argument separator of some locales.
    fn explained(&self, text: &str) -> ParseError {
        let rest = text.get(self.offset..).unwrap_or("");
        if rest.starts_with(';') {
            let message = format!("{}: arguments are separated by , (not ;)", self.message);
            return ParseError::at(self.offset, message);
        }
        if rest.trim().is_empty() {
            if let Some(open) = unclosed_paren(text) {
                return ParseError::at(open, "this ( is never closed: a ) is missing");
            }
        }
        self.clone()
    }
}

/// How many characters of a long line an error shows on each side of its place.
const EXCERPT_HALF: usize = 60;

/// The stretch of `line` an error shows around 1-based character column `col`, and how many
/// characters of it come before the column (where the caret goes). A long line is cut to
/// about 120 characters with `…` where it was cut, so that an error stays readable: a refused
/// formula or macro line may be 100,000 characters long.
pub fn excerpt_around(line: &str, col: usize) -> (String, usize) {
    let before = col.saturating_sub(1);
    let length = line.chars().count();
    if length <= 2 * EXCERPT_HALF {
        return (line.to_string(), before);
    }
    let from = before.saturating_sub(EXCERPT_HALF);
    let lead = if from > 0 { "…" } else { "" };
    let tail = if from + 2 * EXCERPT_HALF < length { "…" } else { "" };
    let shown: String = line.chars().skip(from).take(2 * EXCERPT_HALF).collect();
    (format!("{lead}{shown}{tail}"), lead.chars().count() + before - from)
}

/// The byte offset of the last `(` without its `)`, outside string literals and quoted
/// sheet names.
fn unclosed_paren(text: &str) -> Option<usize> {
    let mut open = Vec::new();
    let mut quote: Option<char> = None;
    for (i, c) in text.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '(') => open.push(i),
            (None, ')') => {
                open.pop();
            }
            _ => {}
        }
    }
    open.last().copied()
}

/// Parses a formula (with or without its leading `=`).
pub fn parse_formula(text: &str, ctx: &ParseContext) -> Result<Expr, ParseError> {
    parse_as(text, ctx, Rule::formula, Rule::expr)
}

/// Parses a formula written in R1C1 style (VBA's `FormulaR1C1`), with or without its `=`:
/// the same grammar, references read as R1C1 ones, into the same tree.
pub fn parse_formula_r1c1(text: &str, ctx: &ParseContext) -> Result<Expr, ParseError> {
    check_nesting(text, Language::Formula)?;
    let mut pairs = FormulaGrammar::parse(Rule::r1c1_formula, text).map_err(from_pest)?;
    let formula = pairs.next().expect("r1c1_formula rule");
    let expr = formula.into_inner().find(|p| p.as_rule() == Rule::expr).expect("expr");
    Builder { ctx, host: None }.expr(expr.into_inner())
}

/// Parses a defined name's formula, where a union of references may stand without
/// parentheses as Excel stores it (`Sheet1!$A$1:$A$3,Sheet1!$C$1`).
pub fn parse_name_formula(text: &str, ctx: &ParseContext) -> Result<Expr, ParseError> {
    parse_as(text, ctx, Rule::name_formula, Rule::paren_expr)
}

/// The tree of `text` read as the grammar's `top` rule, whose `inner` pair is the expression.
fn parse_as(text: &str, ctx: &ParseContext, top: Rule, inner: Rule) -> Result<Expr, ParseError> {
    check_nesting(text, Language::Formula)?;
    let mut pairs = FormulaGrammar::parse(top, text).map_err(from_pest)?;
    let formula = pairs.next().expect("the top rule matched");
    let expr = formula.into_inner().find(|p| p.as_rule() == inner).expect("its expression");
    Builder { ctx, host: None }.expr(expr.into_inner())
}

/// The primaries of the macro language that formulas do not have (variables, member paths,
/// `[B3]`): the macro parser builds them, calling [`build_expr`] for their inner expressions.
pub trait HostPrimaries {
    fn primary(&self, pair: Pair<Rule>) -> Result<Expr, ParseError>;
}

/// Builds the tree of an `expr` (formula) or `vexpr` (macro) pair through the one Pratt table.
/// Offsets in errors and spans are in the text the pair was parsed from.
pub fn build_expr(pair: Pair<Rule>, ctx: &ParseContext, host: Option<&dyn HostPrimaries>) -> Result<Expr, ParseError> {
    Builder { ctx, host }.expr(pair.into_inner())
}

fn from_pest(err: pest::error::Error<Rule>) -> ParseError {
    from_pest_with(err, |positives| expected_kinds(positives, describe, "unexpected character", "one of: "))
}

/// A pest error at its offset, what was wanted said by `expected` (formulas and macros each
/// word it in their own language; the grammar is one).
pub(crate) fn from_pest_with(err: pest::error::Error<Rule>, expected: impl Fn(&[Rule]) -> String) -> ParseError {
    let offset = match err.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let message = match &err.variant {
        ErrorVariant::CustomError { message } => message.clone(),
        ErrorVariant::ParsingError { positives, .. } => expected(positives),
    };
    ParseError::at(offset, message)
}

/// "expected X" for the kinds of thing the wanted rules are (`describe`d, each once), "expected
/// `several`X, Y" for more than one kind, `nothing` when none is known.
pub(crate) fn expected_kinds(
    positives: &[Rule],
    describe: fn(Rule) -> &'static str,
    nothing: &str,
    several: &str,
) -> String {
    let mut wanted: Vec<&str> = positives.iter().map(|r| describe(*r)).collect();
    wanted.sort_unstable();
    wanted.dedup();
    match wanted.as_slice() {
        [] => nothing.to_string(),
        [one] => format!("expected {one}"),
        many => format!("expected {several}{}", many.join(", ")),
    }
}

fn describe(rule: Rule) -> &'static str {
    match rule {
        Rule::expr | Rule::arg | Rule::paren | Rule::call | Rule::number | Rule::string => "a value",
        Rule::reference | Rule::cell | Rule::cell_range | Rule::name => "a value",
        Rule::EOI => "an operator or the end of the formula",
        Rule::array_item | Rule::signed_number => "a constant in the array",
        Rule::array_row => "an array row",
        _ if is_operator(rule) => "an operator",
        _ => "a value",
    }
}

/// Whether a rule is an operator token (for "expected an operator" messages, formulas and
/// macros alike).
pub(crate) fn is_operator(rule: Rule) -> bool {
    matches!(
        rule,
        Rule::range_op
            | Rule::isect_op
            | Rule::union_op
            | Rule::le
            | Rule::ge
            | Rule::ne
            | Rule::eq
            | Rule::lt
            | Rule::gt
            | Rule::concat
            | Rule::add
            | Rule::sub
            | Rule::mul
            | Rule::div
            | Rule::pow
            | Rule::percent
            | Rule::spill_ref
            | Rule::mod_op
            | Rule::int_div
            | Rule::and_op
            | Rule::or_op
            | Rule::xor_op
            | Rule::eqv_op
            | Rule::imp_op
            | Rule::like_op
    )
}

fn span_of(pair: &Pair<Rule>) -> Span {
    let s = pair.as_span();
    Span { start: s.start() as u32, end: s.end() as u32 }
}

fn join(a: Span, b: Span) -> Span {
    Span { start: a.start.min(b.start), end: a.end.max(b.end) }
}

/// Prefixes Excel writes into stored formulas for functions newer than Excel 2007.
pub fn strip_future_prefix(name: &str) -> &str {
    for prefix in ["_xlfn._xlws.", "_xlfn.", "_xlws.", "_xlpm."] {
        if name.len() > prefix.len() && name.get(..prefix.len()).is_some_and(|p| p.eq_ignore_ascii_case(prefix)) {
            return &name[prefix.len()..];
        }
    }
    name
}

/// The name of an optional LAMBDA parameter as a file writes it (`_xlop.b`): an argument
/// that is that name alone.
fn file_optional_parameter(expr: &Pair<Rule>) -> Option<String> {
    let mut parts = expr.clone().into_inner();
    let (Some(only), None) = (parts.next(), parts.next()) else { return None };
    let text = only.as_str();
    let prefixed = only.as_rule() == Rule::name && text.len() > 6 && text[..6].eq_ignore_ascii_case("_xlop.");
    prefixed.then(|| text[6..].to_string())
}

/// The `_xlfn.` prefix a file put before a function name, in Excel's case, or "".
fn file_prefix_of(name: &str) -> &'static str {
    let starts = |prefix: &str| {
        name.len() > prefix.len() && name.get(..prefix.len()).is_some_and(|p| p.eq_ignore_ascii_case(prefix))
    };
    if starts("_xlfn._xlws.") {
        "_xlfn._xlws."
    } else if starts("_xlfn.") {
        "_xlfn."
    } else {
        ""
    }
}

struct Builder<'a, 'c> {
    ctx: &'a ParseContext<'c>,
    host: Option<&'a dyn HostPrimaries>,
}

type Built = Result<Expr, ParseError>;

impl Builder<'_, '_> {
    fn expr(&self, pairs: Pairs<Rule>) -> Built {
        self.expr_depth(pairs).map(|(e, _)| e)
    }

    /// The tree of an expression and its depth, refused past [`MAX_TREE_DEPTH`] at the
    /// operator that passes it (`1+1+…` nests as deep as it is long).
    fn expr_depth(&self, pairs: Pairs<Rule>) -> Result<(Expr, u32), ParseError> {
        PRATT
            .map_primary(|p| self.primary_depth(p))
            .map_prefix(|op, rhs| {
                let (rhs, d) = rhs?;
                let depth = deeper(d + 1, &op)?;
                let kind = unary_op(&PREFIX_RULES, op.as_rule());
                let span = join(span_of(&op), rhs.span);
                Ok((Expr::new(ExprKind::Unary(kind, Box::new(rhs)), span), depth))
            })
            .map_postfix(|lhs, op| {
                let (lhs, d) = lhs?;
                let depth = deeper(d + 1, &op)?;
                let kind = unary_op(&POSTFIX_RULES, op.as_rule());
                let span = join(lhs.span, span_of(&op));
                Ok((Expr::new(ExprKind::Unary(kind, Box::new(lhs)), span), depth))
            })
            .map_infix(|lhs, op, rhs| {
                let ((lhs, dl), (rhs, dr)) = (lhs?, rhs?);
                let depth = deeper(dl.max(dr) + 1, &op)?;
                let span = join(lhs.span, rhs.span);
                if op.as_rule() == Rule::isect_op && lhs.span.end >= rhs.span.start {
                    // `(A1)(B1)`: two operands with nothing between them.
                    return Err(ParseError::at(rhs.span.start as usize, "expected an operator"));
                }
                if matches!(op.as_rule(), Rule::isect_op | Rule::union_op) {
                    if let Some(value) = [&lhs, &rhs].into_iter().find(|e| !may_be_reference(e)) {
                        let symbol = if op.as_rule() == Rule::union_op { "," } else { "a space" };
                        let message = format!("{symbol} joins references: this is a value");
                        return Err(ParseError::at(value.span.start as usize, message));
                    }
                }
                if op.as_rule() == Rule::range_op {
                    if let Some(r) = cell_range(&lhs, &rhs) {
                        return Ok((Expr::new(ExprKind::Ref(r), span), depth));
                    }
                }
                let kind = ExprKind::Binary(binary_op(op.as_rule()), Box::new(lhs), Box::new(rhs));
                Ok((Expr::new(kind, span), depth))
            })
            .parse(pairs)
    }

    /// A primary and the depth of the tree inside it: a bracket or a call is one level more
    /// than its deepest operand.
    fn primary_depth(&self, pair: Pair<Rule>) -> Result<(Expr, u32), ParseError> {
        let start = pair.as_span().start();
        let (expr, depth) = match pair.as_rule() {
            Rule::paren | Rule::vparen => {
                let span = span_of(&pair);
                let inner = pair.into_inner().next().expect("paren holds expr");
                let (e, d) = self.expr_depth(inner.into_inner())?;
                (Expr::new(ExprKind::Paren(Box::new(e)), span), d + 1)
            }
            Rule::call => self.call_depth(pair)?,
            _ => (self.primary(pair)?, 1),
        };
        if depth > MAX_TREE_DEPTH {
            return Err(tree_depth_error(start));
        }
        Ok((expr, depth))
    }

    fn primary(&self, pair: Pair<Rule>) -> Built {
        let span = span_of(&pair);
        let kind = match pair.as_rule() {
            Rule::paren | Rule::vparen => {
                let inner = pair.into_inner().next().expect("paren holds expr");
                ExprKind::Paren(Box::new(self.expr(inner.into_inner())?))
            }
            Rule::call => return self.call(pair),
            Rule::array => ExprKind::Array(Rc::new(self.array(pair)?)),
            Rule::number => ExprKind::Number(number(&pair)?),
            Rule::string => ExprKind::Text(unescape(&pair).into()),
            Rule::error => ExprKind::Error(pair.as_str().parse().expect("grammar lists errors")),
            Rule::boolean => ExprKind::Bool(pair.as_str().eq_ignore_ascii_case("TRUE")),
            Rule::reference => ExprKind::Ref(self.reference(pair)?),
            Rule::structured => ExprKind::Table(Rc::new(structured(pair)?)),
            Rule::name => ExprKind::Name(strip_future_prefix(pair.as_str()).into()),
            Rule::sheet_name => {
                let mut parts = pair.into_inner();
                let sheet = self.sheet(parts.next().expect("sheet prefix"));
                ExprKind::SheetName(sheet, parts.next().expect("name").as_str().into())
            }
            rule => match self.host {
                Some(host) => return host.primary(pair),
                None => unreachable!("primary {rule:?}"),
            },
        };
        Ok(Expr::new(kind, span))
    }

    fn call(&self, pair: Pair<Rule>) -> Built {
        self.call_depth(pair).map(|(e, _)| e)
    }

    /// A call, and the in-place calls of its result that follow it (`LAMBDA(x,x+1)(2)`).
    fn call_depth(&self, pair: Pair<Rule>) -> Result<(Expr, u32), ParseError> {
        let start = pair.as_span().start() as u32;
        let mut inner = pair.into_inner();
        let name_pair = inner.next().expect("func_name");
        let name = strip_future_prefix(name_pair.as_str());
        let declares_parameters = name.eq_ignore_ascii_case("LAMBDA");
        let first = inner.next().expect("arguments");
        let call_span = join(span_of(&name_pair), span_of(&first));
        let (args, depth) = self.arguments(first, declares_parameters)?;
        let (mut expr, mut depth) = self.function_call(&name_pair, name, args, (call_span, depth))?;
        for list in inner {
            let list_span = span_of(&list);
            let (args, d) = self.arguments(list, false)?;
            depth = depth.max(d) + 1;
            if depth > MAX_TREE_DEPTH {
                return Err(tree_depth_error(list_span.start as usize));
            }
            let span = Span { start, end: list_span.end };
            expr = Expr::new(ExprKind::Invoke(Box::new(expr), args), span);
        }
        Ok((expr, depth))
    }

    /// The call of the function `name` on `args`, whose deepest tree is `depth`: a registered
    /// function checked for its argument count, or an unknown one kept as typed.
    fn function_call(
        &self,
        name_pair: &Pair<Rule>,
        name: &str,
        args: Vec<Expr>,
        (span, depth): (Span, u32),
    ) -> Result<(Expr, u32), ParseError> {
        let Some(info) = self.ctx.functions.lookup(name) else {
            // Kept as typed (it may be a LET or defined name's LAMBDA, `f(1)`, shown as
            // written); a newer Excel function we lack keeps the prefix it was read with, so
            // that it goes back to a file as it came.
            let unknown = format!("{}{name}", file_prefix_of(name_pair.as_str()));
            return Ok((Expr::new(ExprKind::UnknownCall(unknown.into(), args), span), depth + 1));
        };
        if args.len() < info.min_args || args.len() > info.max_args {
            let canonical = self.ctx.functions.name(info.id);
            return Err(ParseError::at(name_pair.as_span().start(), arity_message(canonical, info, args.len())));
        }
        Ok((Expr::new(ExprKind::Call(info.id, args), span), depth + 1))
    }

    /// One parenthesised argument list and the depth of its deepest argument. Where it is a
    /// LAMBDA's (`parameters`), every argument but the last (the calculation) may be an
    /// optional parameter: `[b]` as typed, `_xlop.b` as a file writes it.
    fn arguments(&self, list: Pair<Rule>, parameters: bool) -> Result<(Vec<Expr>, u32), ParseError> {
        let pairs: Vec<Pair<Rule>> = list.into_inner().collect();
        let calculation = pairs.len() - 1;
        let mut depth = 0;
        let mut args = Vec::with_capacity(pairs.len());
        for (i, arg) in pairs.into_iter().enumerate() {
            let arg_span = span_of(&arg);
            let may_be_optional = parameters && i < calculation;
            let Some(inner) = arg.into_inner().next() else {
                args.push(Expr::new(ExprKind::Missing, arg_span));
                continue;
            };
            let optional = match inner.as_rule() {
                // Outside a LAMBDA's parameters, `[Qty]` is a column of the formula's table.
                Rule::optional_param if !may_be_optional => {
                    let table = super::table_ref::parse_table_ref(None, inner.as_str());
                    let table = table.expect("a bracketed name is a column");
                    args.push(Expr::new(ExprKind::Table(Rc::new(table)), arg_span));
                    continue;
                }
                Rule::optional_param => {
                    inner.clone().into_inner().next().map(|n| strip_future_prefix(n.as_str()).to_string())
                }
                _ if may_be_optional => file_optional_parameter(&inner),
                _ => None,
            };
            if let Some(name) = optional {
                args.push(Expr::new(ExprKind::OptionalParam(name.into()), arg_span));
                continue;
            }
            let (e, d) = self.expr_depth(inner.into_inner())?;
            depth = depth.max(d);
            args.push(e);
        }
        // `PI()` has one empty argument slot in the grammar, and no argument.
        if args.len() == 1 && args[0].kind == ExprKind::Missing {
            args.clear();
        }
        Ok((args, depth))
    }

    fn array(&self, pair: Pair<Rule>) -> Result<ArrayLit, ParseError> {
        let mut rows = 0;
        let mut cols = None;
        let mut items = Vec::new();
        for row in pair.into_inner() {
            let row_start = row.as_span().start();
            let before = items.len();
            for item in row.into_inner() {
                items.push(self.array_item(item.into_inner().next().expect("array item"))?);
            }
            let n = items.len() - before;
            if *cols.get_or_insert(n) != n {
                return Err(ParseError::at(row_start, "every row of an array constant needs the same number of items"));
            }
            rows += 1;
        }
        Ok(ArrayLit { rows, cols: cols.unwrap_or(0), items })
    }

    fn array_item(&self, pair: Pair<Rule>) -> Built {
        let span = span_of(&pair);
        if pair.as_rule() != Rule::signed_number {
            return self.primary(pair);
        }
        let mut negative = false;
        let mut value = 0.0;
        for part in pair.into_inner() {
            match part.as_rule() {
                Rule::neg => negative = !negative,
                Rule::number => value = number(&part)?,
                _ => {}
            }
        }
        Ok(Expr::new(ExprKind::Number(if negative { -value } else { value }), span))
    }

    fn reference(&self, pair: Pair<Rule>) -> Result<Reference, ParseError> {
        let mut sheet = SheetRef::Current;
        let mut shape = None;
        for part in pair.into_inner() {
            match part.as_rule() {
                Rule::sheet_prefix => sheet = self.sheet(part),
                Rule::cell => shape = Some(RefShape::Cell(self.cell(&part)?)),
                Rule::cell_range => {
                    let mut cells = part.into_inner();
                    let a = self.cell(&cells.next().expect("first cell"))?;
                    let b = self.cell(&cells.next().expect("second cell"))?;
                    shape = Some(RefShape::Cells(a, b));
                }
                Rule::col_range => {
                    let mut cols = part.into_inner();
                    let a = self.col(&cols.next().expect("first column"))?;
                    let b = self.col(&cols.next().expect("second column"))?;
                    shape = Some(RefShape::Cols(a, b));
                }
                Rule::row_range => {
                    let mut rows = part.into_inner();
                    let a = self.row(&rows.next().expect("first row"))?;
                    let b = self.row(&rows.next().expect("second row"))?;
                    shape = Some(RefShape::Rows(a, b));
                }
                Rule::r1c1_area => shape = Some(self.r1c1_area(part)?),
                rule => unreachable!("reference part {rule:?}"),
            }
        }
        Ok(Reference { sheet, shape: shape.expect("reference has a shape") })
    }

    /// `R2C3`, `R[-1]C:RC[2]`, `R3:R5`, `C[1]`.
    fn r1c1_area(&self, pair: Pair<Rule>) -> Result<RefShape, ParseError> {
        let inner: Vec<Pair<Rule>> = pair.into_inner().collect();
        let cell = |p: &Pair<Rule>| -> Result<CellCoord, ParseError> {
            let mut parts = p.clone().into_inner();
            let row = r1c1_coord(&parts.next().expect("R"), MAX_ROWS)?;
            let col = r1c1_coord(&parts.next().expect("C"), MAX_COLS)?;
            Ok(CellCoord { row, col })
        };
        let line = |p: &Pair<Rule>, count: u32| -> Result<(Coord, Coord), ParseError> {
            let ends: Vec<Pair<Rule>> = p.clone().into_inner().collect();
            let first = r1c1_coord(&ends[0], count)?;
            Ok((first, ends.get(1).map(|e| r1c1_coord(e, count)).transpose()?.unwrap_or(first)))
        };
        Ok(match inner.as_slice() {
            [a] if a.as_rule() == Rule::r1c1_cell => RefShape::Cell(cell(a)?),
            [a, b] => RefShape::Cells(cell(a)?, cell(b)?),
            [rows] if rows.as_rule() == Rule::r1c1_rows => {
                let (a, b) = line(rows, MAX_ROWS)?;
                RefShape::Rows(a, b)
            }
            [cols] => {
                let (a, b) = line(cols, MAX_COLS)?;
                RefShape::Cols(a, b)
            }
            _ => unreachable!("an R1C1 area has one or two parts"),
        })
    }

    /// The sheet of `Sheet2!`, or the sheets of a 3-D reference's `Sheet1:Sheet3!` (also
    /// quoted as one, `'Jan 1:Mar 1'!`, as Excel writes it: a sheet name has no `:`).
    fn sheet(&self, pair: Pair<Rule>) -> SheetRef {
        let mut names = Vec::with_capacity(2);
        for part in pair.into_inner() {
            let part = match part.as_rule() {
                Rule::sheet_span_start => part.into_inner().next().expect("first sheet name"),
                _ => part,
            };
            names.push(unquoted_sheet_name(part.as_str()));
        }
        if let [one] = names.as_slice() {
            if let Some((a, b)) = one.split_once(':') {
                names = vec![a.to_string(), b.to_string()];
            }
        }
        let id = |name: &str| (self.ctx.sheet)(name);
        match names.as_slice() {
            [name] => id(name).map_or_else(|| SheetRef::Missing(name.as_str().into()), SheetRef::Id),
            [first, last] => match (id(first), id(last)) {
                (Some(a), Some(b)) if a == b => SheetRef::Id(a),
                (Some(a), Some(b)) => SheetRef::Span(a, b),
                _ => SheetRef::Missing(format!("{first}:{last}").into()),
            },
            _ => unreachable!("a sheet prefix names one or two sheets"),
        }
    }

    fn cell(&self, pair: &Pair<Rule>) -> Result<CellCoord, ParseError> {
        let text = pair.as_str();
        let split = text.rfind(|c: char| !c.is_ascii_digit()).map_or(0, |i| i + 1);
        let (col_text, row_text) = text.split_at(split);
        // `$A$1`: the `$` before the digits belongs to the row.
        let (col_text, row_text) = match col_text.strip_suffix('$') {
            Some(c) => (c, &text[c.len()..]),
            None => (col_text, row_text),
        };
        let off_sheet = || {
            ParseError::at(
                pair.as_span().start(),
                format!("{text} is off the sheet (columns A to XFD, rows 1 to {MAX_ROWS})"),
            )
        };
        let col = self.col_coord(col_text).ok_or_else(off_sheet)?;
        let row = self.row_coord(row_text).ok_or_else(off_sheet)?;
        Ok(CellCoord { row, col })
    }

    fn col(&self, pair: &Pair<Rule>) -> Result<Coord, ParseError> {
        self.col_coord(pair.as_str()).ok_or_else(|| {
            ParseError::at(pair.as_span().start(), format!("column {} is off the sheet (A to XFD)", pair.as_str()))
        })
    }

    fn row(&self, pair: &Pair<Rule>) -> Result<Coord, ParseError> {
        self.row_coord(pair.as_str()).ok_or_else(|| {
            ParseError::at(pair.as_span().start(), format!("row {} is off the sheet (1 to {MAX_ROWS})", pair.as_str()))
        })
    }

    fn col_coord(&self, text: &str) -> Option<Coord> {
        let (absolute, letters) = split_dollar(text);
        let col = column_index(letters)?;
        debug_assert!(col < MAX_COLS);
        Some(coord(absolute, col, self.ctx.at.col))
    }

    fn row_coord(&self, text: &str) -> Option<Coord> {
        let (absolute, digits) = split_dollar(text);
        let row: u32 = digits.parse().ok()?;
        if !(1..=MAX_ROWS).contains(&row) {
            return None;
        }
        Some(coord(absolute, row - 1, self.ctx.at.row))
    }
}

/// One `R…` or `C…` of an R1C1 reference: `R3` row 3, `R[-1]` one up, `R` this row.
fn r1c1_coord(pair: &Pair<Rule>, count: u32) -> Result<Coord, ParseError> {
    let text = &pair.as_str()[1..];
    let bad = || ParseError::at(pair.as_span().start(), format!("{} is off the sheet", pair.as_str()));
    if let Some(offset) = text.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
        let offset: i32 = offset.parse().map_err(|_| bad())?;
        return if offset.unsigned_abs() < count { Ok(Coord::relative(offset)) } else { Err(bad()) };
    }
    if text.is_empty() {
        return Ok(Coord::relative(0));
    }
    match text.parse::<u32>() {
        Ok(n) if (1..=count).contains(&n) => Ok(Coord::absolute(n - 1)),
        _ => Err(bad()),
    }
}

fn split_dollar(text: &str) -> (bool, &str) {
    match text.strip_prefix('$') {
        Some(rest) => (true, rest),
        None => (false, text),
    }
}

fn coord(absolute: bool, index: u32, base: u32) -> Coord {
    if absolute {
        Coord::absolute(index)
    } else {
        Coord::relative(index as i32 - base as i32)
    }
}

fn arity_message(name: &str, info: FnInfo, got: usize) -> String {
    let wanted = match (info.min_args, info.max_args) {
        (a, b) if a == b => format!("{a}"),
        (a, usize::MAX) => format!("at least {a}"),
        (a, b) => format!("{a} to {b}"),
    };
    let plural = if wanted == "1" { "" } else { "s" };
    format!("{name} takes {wanted} argument{plural}, not {got}")
}

fn number(pair: &Pair<Rule>) -> Result<f64, ParseError> {
    match pair.as_str().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => {
            Err(ParseError::at(pair.as_span().start(), format!("number {} is too large", shown_number(pair.as_str()))))
        }
    }
}

/// A number literal as a message quotes it: its start and its length past 40 characters. A
/// macro's literal of a million digits was quoted whole, a 1 MB line of message.
pub fn shown_number(text: &str) -> String {
    let length = text.chars().count();
    if length <= 40 {
        return text.to_string();
    }
    let start = text.char_indices().nth(30).map_or(text, |(at, _)| &text[..at]);
    format!("{start}… ({length} characters)")
}

fn unescape(pair: &Pair<Rule>) -> String {
    let inner = pair.clone().into_inner().next().map_or("", |p| p.as_str());
    inner.replace("\"\"", "\"")
}

/// Whether `e` may evaluate to a reference: the operands of the union and intersection
/// operators must (MS-XLSX's `ref-expression`), so Excel refuses `(-4,3)`, a decimal comma
/// that some applications wrote into files.
fn may_be_reference(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Ref(_) | ExprKind::Table(_) | ExprKind::Name(_) | ExprKind::Call(..) | ExprKind::UnknownCall(..) => {
            true
        }
        ExprKind::Error(err) => *err == XlError::Ref,
        ExprKind::Paren(inner) => may_be_reference(inner),
        ExprKind::Unary(op, _) => matches!(op, UnaryOp::Spill | UnaryOp::Implicit),
        ExprKind::Binary(op, ..) => matches!(op, BinOp::Range | BinOp::Intersect | BinOp::Union),
        _ => false,
    }
}

/// `A1 : B2` (spaces around the colon) is the range `A1:B2`, as Excel reads it: one
/// reference, which prints back as `A1:B2` and gives the dependency graph every cell.
fn cell_range(lhs: &Expr, rhs: &Expr) -> Option<Reference> {
    match (&lhs.kind, &rhs.kind) {
        (ExprKind::Ref(a), ExprKind::Ref(b)) if a.sheet == b.sheet => match (a.shape, b.shape) {
            (RefShape::Cell(x), RefShape::Cell(y)) => {
                Some(Reference { sheet: a.sheet.clone(), shape: RefShape::Cells(x, y) })
            }
            _ => None,
        },
        _ => None,
    }
}

fn binary_op(rule: Rule) -> BinOp {
    INFIX_RULES.iter().find(|(r, _)| *r == rule).map(|(_, op)| *op).unwrap_or_else(|| unreachable!("infix {rule:?}"))
}

fn unary_op(table: &[(Rule, UnaryOp)], rule: Rule) -> UnaryOp {
    table.iter().find(|(r, _)| *r == rule).map(|(_, op)| *op).unwrap_or_else(|| unreachable!("operator {rule:?}"))
}

/// A structured reference's table name and bracketed items, read by `table_ref`.
fn structured(pair: Pair<Rule>) -> Result<super::ast::TableRef, ParseError> {
    let start = pair.as_span().start();
    let (mut table, mut items) = (None, "");
    for part in pair.into_inner() {
        match part.as_rule() {
            Rule::table_name => table = Some(part.as_str()),
            _ => items = part.as_str(),
        }
    }
    super::table_ref::parse_table_ref(table, items).ok_or_else(|| {
        ParseError::at(start, "not a structured reference: a table's items are #All, #Data, #Headers, #Totals, #This Row and its columns' names")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoFunctions;

    impl FunctionTable for NoFunctions {
        fn lookup(&self, _: &str) -> Option<FnInfo> {
            None
        }

        fn name(&self, _: FnId) -> &str {
            ""
        }
    }

    #[test]
    fn dollar_signs_fix_the_column_or_the_row() {
        let ctx = ParseContext { at: Pos::new(2, 2), functions: &NoFunctions, sheet: &|_| None };
        let cell = |text: &str| match parse_formula(text, &ctx).expect("parses").kind {
            ExprKind::Ref(Reference { shape: RefShape::Cell(c), .. }) => (c.col, c.row),
            other => panic!("{other:?}"),
        };
        assert_eq!(cell("C$2"), (Coord::relative(0), Coord::absolute(1)));
        assert_eq!(cell("$A3"), (Coord::absolute(0), Coord::relative(0)));
        assert_eq!(cell("$B$1"), (Coord::absolute(1), Coord::absolute(0)));
        assert_eq!(cell("D4"), (Coord::relative(1), Coord::relative(1)));
    }

    #[test]
    fn a_lambda_declares_optional_parameters_and_is_called_in_place() {
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &NoFunctions, sheet: &|_| None };
        let parse = |text: &str| parse_formula(text, &ctx);
        let ExprKind::Invoke(callee, args) = parse("=LAMBDA(a,[b],a)(A5)").expect("parses").kind else {
            panic!("an in-place call")
        };
        assert_eq!(args.len(), 1);
        let ExprKind::UnknownCall(_, params) = &callee.kind else { panic!("the LAMBDA") };
        assert_eq!(params[1].kind, ExprKind::OptionalParam("b".into()));
        // As a file writes it (ISOMITTED.xlsx): `_xlop.`, and `_xlpm.` for the required ones.
        let file = parse("=_xlfn.LAMBDA(_xlpm.a,_xlop.b,_xlpm.a)(A5, B5)").expect("parses");
        let ExprKind::Invoke(callee, args) = file.kind else { panic!("an in-place call") };
        assert_eq!(args.len(), 2);
        let ExprKind::UnknownCall(_, params) = &callee.kind else { panic!("the LAMBDA") };
        assert_eq!(params[0].kind, ExprKind::Name("a".into()));
        assert_eq!(params[1].kind, ExprKind::OptionalParam("b".into()));
        // `[…]` is an optional parameter only in a LAMBDA's parameter list (the calculation is
        // no parameter); elsewhere it is a column of the formula's table (`[b]`).
        for column in ["=SUM([b])", "=LAMBDA([b])", "=LAMBDA(a,[b],a)([c])"] {
            let mut tables = 0;
            parse(column).expect(column).visit(&mut |e| tables += matches!(e.kind, ExprKind::Table(_)) as usize);
            assert_eq!(tables, 1, "{column}");
        }
        // A space before the second list is the intersection operator, as in Excel.
        assert!(matches!(parse("=F(A1) (A2)").expect("parses").kind, ExprKind::Binary(BinOp::Intersect, ..)));
        assert!(parse("=LAMBDA(x,x)(1").is_err());
    }
}
