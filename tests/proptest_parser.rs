//! The parser never panics, and what it accepts prints back to text that parses to the
//! same tree.
//!
//! Inputs are arbitrary strings and formula-like strings glued from tokens (operators,
//! parentheses, references, names, quoted strings, numbers, commas, braces). For each:
//! `parse_formula` returns without panicking; an error renders; an accepted formula
//! evaluates without panicking, prints, and the printed text parses to the same tree
//! (source spans aside).
//!
//! The cases come from the fixed seed of `common::fuzz` (the seed is named when one fails).

mod common;

use ncsheet::eval::functions::Registry;
use ncsheet::eval::testing::MapEnv;
use ncsheet::eval::{Ctx, Value};
use ncsheet::formula::ast::{ArrayLit, Expr, ExprKind, SheetId, Span};
use ncsheet::formula::print::print_formula;
use ncsheet::formula::{parse_formula, ParseContext, Pos};
use proptest::prelude::*;

fn sheet_id(name: &str) -> Option<SheetId> {
    if name.eq_ignore_ascii_case("Sheet1") {
        Some(0)
    } else if name.eq_ignore_ascii_case("Chamfer data") {
        Some(1)
    } else {
        None
    }
}

fn sheet_name(id: SheetId) -> String {
    match id {
        0 => "Sheet1".to_string(),
        1 => "Chamfer data".to_string(),
        _ => "#REF".to_string(),
    }
}

fn parse(text: &str, at: Pos) -> Result<Expr, ncsheet::formula::ParseError> {
    parse_formula(text, &ParseContext { at, functions: &Registry, sheet: &sheet_id })
}

/// The tree with every span zeroed, so that trees parsed from different spellings compare.
fn without_spans(e: &Expr) -> Expr {
    let kind = match &e.kind {
        ExprKind::Paren(a) => ExprKind::Paren(Box::new(without_spans(a))),
        ExprKind::Unary(op, a) => ExprKind::Unary(*op, Box::new(without_spans(a))),
        ExprKind::Binary(op, a, b) => ExprKind::Binary(*op, Box::new(without_spans(a)), Box::new(without_spans(b))),
        ExprKind::Call(id, args) => ExprKind::Call(*id, args.iter().map(without_spans).collect()),
        ExprKind::UnknownCall(name, args) => {
            ExprKind::UnknownCall(name.clone(), args.iter().map(without_spans).collect())
        }
        ExprKind::Invoke(callee, args) => {
            ExprKind::Invoke(Box::new(without_spans(callee)), args.iter().map(without_spans).collect())
        }
        ExprKind::Array(lit) => ExprKind::Array(std::rc::Rc::new(ArrayLit {
            rows: lit.rows,
            cols: lit.cols,
            items: lit.items.iter().map(without_spans).collect(),
        })),
        other => other.clone(),
    };
    Expr::new(kind, Span::default())
}

/// A few cells for formulas to read.
fn env() -> MapEnv {
    MapEnv::with(&[
        ("A1", Value::Number(2.0)),
        ("A2", Value::text("x")),
        ("A3", Value::Bool(true)),
        ("B1", Value::Number(-1.5)),
        ("B2", Value::Error(ncsheet::eval::XlError::Div0)),
    ])
}

/// Everything the parser's users do with a text; panics are the failures looked for.
fn exercise(text: &str, at: Pos) -> Result<(), TestCaseError> {
    match parse(text, at) {
        Err(e) => {
            let _ = e.render(text);
            let _ = e.column(text);
        }
        Ok(expr) => {
            let env = env();
            let _ = Ctx::new(&env, 0, at).eval(&expr);
            let printed = print_formula(&expr, at, &Registry, &sheet_name);
            match parse(&printed, at) {
                Ok(again) => prop_assert_eq!(
                    without_spans(&again),
                    without_spans(&expr),
                    "{:?} printed as {:?} parses to another tree",
                    text,
                    printed
                ),
                Err(e) => {
                    return Err(TestCaseError::fail(format!(
                        "{text:?} printed as {printed:?}, which does not parse:\n{}",
                        e.render(&printed)
                    )))
                }
            }
        }
    }
    Ok(())
}

fn at() -> impl Strategy<Value = Pos> {
    prop_oneof![Just(Pos::new(0, 0)), Just(Pos::new(9, 3)), (0u32..50, 0u32..30).prop_map(|(r, c)| Pos::new(r, c))]
}

/// Tokens of the formula language, valid and not, with the spaces between them.
fn token() -> impl Strategy<Value = String> {
    let fixed = prop::sample::select(vec![
        "+",
        "-",
        "*",
        "/",
        "^",
        "&",
        "=",
        "<>",
        "<",
        "<=",
        ">",
        ">=",
        "%",
        ":",
        ",",
        ";",
        "(",
        ")",
        "{",
        "}",
        "@",
        "#",
        "!",
        " ",
        " ",
        "$",
        "'",
        "\"",
        "A1",
        "$B$2",
        "c3",
        "A1:B2",
        "$A$1:A3",
        "A:A",
        "B:$C",
        "1:3",
        "$2:2",
        "Sheet1!A1",
        "'Chamfer data'!B4",
        "Nowhere!C3",
        "'it''s'!A1",
        "XFD1",
        "XFE1",
        "A1048577",
        "A0",
        "foo",
        "x.y",
        "_a",
        "\\b",
        "Dv",
        "TRUE",
        "false",
        "TRUE1",
        "#N/A",
        "#DIV/0!",
        "#REF!",
        "#NAME?",
        "#SPILL!",
        "0",
        "1",
        "2.5",
        ".5",
        "1e3",
        "1E-2",
        "1e999",
        "007",
        "SUM(",
        "SIN(",
        "IF(",
        "MAX(",
        "ROUND(",
        "PI(",
        "ABS(",
        "ATAN2(",
        "POWER(",
        "NOSUCH(",
        "_xlfn.SIN(",
        "LAMBDA(",
        ")(",
        "[b]",
        "_xlop.b",
        "sum(",
        "\"text\"",
        "\"a\"\"b\"",
        "\"\"",
        "é",
        "Ω",
        "\t",
    ]);
    prop_oneof![
        8 => fixed.prop_map(str::to_string),
        1 => (0.0f64..1e6).prop_map(|x| format!("{x}")),
        1 => "[A-Z]{1,3}[1-9][0-9]{0,2}",
        1 => "\"[^\"]{0,4}\"",
    ]
}

fn token_formula() -> impl Strategy<Value = String> {
    (prop::bool::ANY, prop::collection::vec(token(), 1..24)).prop_map(|(eq, tokens)| {
        let body = tokens.concat();
        if eq {
            format!("={body}")
        } else {
            body
        }
    })
}

/// Formulas that parse by construction, so the round trip is tested often.
fn valid_formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        prop::sample::select(vec![
            "A1",
            "$B$2",
            "B$3",
            "A1:B2",
            "$A$1:A3",
            "A:A",
            "1:3",
            "Sheet1!A1",
            "'Chamfer data'!B4",
            "Nowhere!C3",
            "TRUE",
            "FALSE",
            "#N/A",
            "#DIV/0!",
            "\"x\"",
            "\"a\"\"b\"",
            "\"\"",
            "Dv",
            "{1,2;3,4}",
            "{-1,\"a\";TRUE,#N/A}",
            "PI()",
            "LAMBDA(x,[y],x)(2)",
            "0.5",
            "1e300",
            "7",
        ])
        .prop_map(str::to_string),
        (0u32..1000).prop_map(|n| n.to_string()),
    ];
    leaf.prop_recursive(4, 32, 3, |inner| {
        let op = prop::sample::select(vec!["+", "-", "*", "/", "^", "&", "=", "<>", "<", "<=", ">", ">="]);
        let func = prop::sample::select(vec!["SUM", "MAX", "SIN", "ABS", "NOSUCH", "IF"]);
        prop_oneof![
            (inner.clone(), op, inner.clone()).prop_map(|(a, o, b)| format!("{a}{o}{b}")),
            (inner.clone(), " ", inner.clone()).prop_map(|(a, s, b)| format!("{a}{s}+{s}{b}")),
            inner.clone().prop_map(|a| format!("({a})")),
            inner.clone().prop_map(|a| format!("-{a}")),
            inner.clone().prop_map(|a| format!("{a}%")),
            inner.clone().prop_map(|a| format!("@{a}")),
            (func, prop::collection::vec(inner, 1..3)).prop_map(|(f, args)| {
                let args = if f == "IF" && args.len() < 2 { vec![args[0].clone(), "1".into()] } else { args };
                let args = if matches!(f, "SIN" | "ABS") { vec![args[0].clone()] } else { args };
                format!("{f}({})", args.join(","))
            }),
        ]
    })
}

proptest! {
    #![proptest_config(common::fuzz::with_regressions(1000))]

    #[test]
    fn arbitrary_strings_never_panic(text in any::<String>(), at in at()) {
        exercise(&text, at)?;
        exercise(&format!("={text}"), at)?;
    }

    #[test]
    fn formula_like_token_soup_never_panics_and_round_trips(text in token_formula(), at in at()) {
        exercise(&text, at)?;
    }

    #[test]
    fn valid_formulas_round_trip(body in valid_formula(), at in at()) {
        let text = format!("={body}");
        prop_assert!(parse(&text, at).is_ok(), "{} does not parse", text);
        exercise(&text, at)?;
    }
}

#[test]
fn known_tricky_texts() {
    for text in [
        "=",
        "==",
        "=(",
        "=)",
        "={",
        "={}",
        "=\"",
        "=''!A1",
        "=A1 :B2",
        "=A1: B2",
        "=SUM(A1:B2 C3)",
        "=-2^2",
        "=2^3^2",
        "=1+2&3",
        "=50%%",
        "=A1#",
        "=@A1:A3",
        "=SUM(,)",
        "=IF(,,)",
        "=PI( )",
        "=1e",
        "=.",
        "=$",
        "=$A",
        "=A$",
        "=#",
        "=é",
        "= 1",
        "=1 ",
        "=\u{a0}1",
        "=SIN(1,2)",
        "=_xlfn._xlws.SUM(1)",
        "=LAMBDA(x,[y],x+y)(1)",
        "=LAMBDA(x,x)(1)(2)",
        "=LAMBDA(x,x) (1)",
        "=LAMBDA([x])",
        "=SUM([x])",
        "=LAMBDA(x,x)(",
    ] {
        exercise(text, Pos::new(4, 4)).unwrap_or_else(|e| panic!("{text:?}: {e}"));
    }
}
