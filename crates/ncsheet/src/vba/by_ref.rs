//! VBA's compile error "ByRef argument type mismatch": a variable passed to a ByRef
//! parameter is the parameter itself while the procedure runs, so it must be declared with the
//! parameter's very type (Office VBA reference, "ByRef argument type mismatch": an Integer
//! variable where a Long is expected, a Variant where an Integer is; KB 158472: an item of a
//! Variant array where an Integer is). An expression, a variable in its own parentheses
//! `(x)`, a constant or a literal is evaluated into a temporary of the parameter's type, and a
//! ByVal parameter takes a copy: those convert. Checked while the calling procedure is built,
//! so the error is the calling procedure's, confined to it as every compile error is.

use std::rc::Rc;

use pest::iterators::Pair;

use crate::formula::ast::{Expr, ExprKind};
use crate::formula::parse::{ParseError, Rule};

use super::ast::{Arg, Node, Ty};
use super::parser::{find, kids, Build, Res};
use super::typing::Declared;

/// How a procedure takes one parameter, as far as a variable given to it is checked.
#[derive(Clone, Debug, Default)]
pub(super) struct Passing {
    /// ByRef, VBA's default (a ParamArray takes its arguments otherwise).
    by_ref: bool,
    /// `a() As Long`: an array of the type.
    array: bool,
    /// The type its `As` clause names (as written), or its type character's.
    as_name: Option<Rc<str>>,
    char_ty: Option<Ty>,
}

/// What a call's check needs of a declared variable: its type, and whether it is an array.
#[derive(Clone, Debug)]
pub(super) struct Declaration {
    /// `None`: declared without a type, a Variant.
    pub(super) ty: Option<Ty>,
    pub(super) array: bool,
}

/// The passing of the parameter `param` (a `param` pair), read before any procedure is built.
pub(super) fn passing(param: &Pair<Rule>, char_ty: Option<Ty>) -> Passing {
    let k = kids(param);
    let by_ref = find(&k, Rule::pass_mode).is_none_or(|m| m.as_str().eq_ignore_ascii_case("ByRef"));
    let as_name = find(&k, Rule::as_clause)
        .and_then(|a| find(&kids(&a), Rule::type_name))
        .map(|t| Rc::from(t.as_str().to_ascii_lowercase()));
    Passing {
        by_ref: by_ref && find(&k, Rule::k_paramarray).is_none(),
        array: find(&k, Rule::empty_parens).is_some(),
        as_name,
        char_ty,
    }
}

/// Two declared types one reference serves: the same type, a fixed-length String being a String.
fn same_type(a: &Ty, b: &Ty) -> bool {
    match (a, b) {
        (Ty::String | Ty::FixedString(_), Ty::String | Ty::FixedString(_)) => true,
        _ => a == b,
    }
}

/// A type as the message names it.
fn type_name(ty: Option<&Ty>) -> &'static str {
    match ty {
        Some(Ty::Record(_)) => "user-defined Type",
        ty => Declared::of_ty(ty).name(),
    }
}

impl Build<'_> {
    /// Notes a variable the procedure (or, at module level, the module) declares, for the
    /// ByRef check of the calls after it; the first declaration of a name is its type.
    pub(super) fn note_declaration(&self, name: &str, declaration: Declaration, at_module: bool) {
        let lower = name.to_ascii_lowercase();
        if at_module {
            let key = (self.current_part.get(), lower);
            self.module_declarations.borrow_mut().entry(key).or_insert(declaration);
        } else {
            self.scope.borrow_mut().declarations.entry(lower).or_insert(declaration);
        }
    }

    /// The declaration of the variable `name` the procedure being built sees: its own, else
    /// its module's; `None` for one it does not declare (a constant, another module's).
    fn declaration_of(&self, name: &str) -> Option<Declaration> {
        let lower = name.to_ascii_lowercase();
        if let Some(d) = self.scope.borrow().declarations.get(&lower) {
            return Some(d.clone());
        }
        self.module_declarations.borrow().get(&(self.current_part.get(), lower)).cloned()
    }

    /// The variable an argument is, when it is one as written (`x`, `a(i)`), with its name
    /// and declaration; `None` for anything evaluated into a temporary.
    fn argument_variable(&self, value: &Expr) -> Option<(String, Declaration)> {
        match &value.kind {
            ExprKind::Name(name) => Some((name.to_string(), self.declaration_of(name)?)),
            ExprKind::Host(id) => match &self.nodes.borrow()[*id as usize] {
                Node::Element { var, .. } => {
                    let d = self.declaration_of(var).filter(|d| d.array)?;
                    Some((format!("{var}(…)"), Declaration { ty: d.ty, array: false }))
                }
                _ => None,
            },
            _ => None,
        }
    }

    /// The declared type of a parameter, `None` for a Variant or a type not checked (an
    /// object's, which VBA checks by class, not followed here).
    fn parameter_type(&self, passing: &Passing) -> Option<Ty> {
        let ty = match &passing.as_name {
            Some(name) => self.type_by_name(name),
            None => passing.char_ty.clone()?,
        };
        (!matches!(ty, Ty::Variant | Ty::Object)).then_some(ty)
    }

    /// VBA's compile error for each variable of `args` given to a ByRef parameter of
    /// procedure `proc` declared with another type than the parameter's.
    pub(super) fn check_by_ref_args(&self, proc: usize, args: &[Arg]) -> Res<()> {
        let signature = &self.procs[proc];
        for (i, arg) in args.iter().enumerate() {
            let at = match &arg.name {
                Some(n) => signature.params.iter().position(|p| p.eq_ignore_ascii_case(n)),
                None => Some(i),
            };
            let Some(passing) = at.and_then(|i| signature.passing.get(i)).filter(|p| p.by_ref) else { continue };
            let Some(param_ty) = self.parameter_type(passing) else { continue };
            let Some((var, declared)) = self.argument_variable(&arg.value) else { continue };
            if declared.array != passing.array || matches!(declared.ty, Some(Ty::Object)) {
                continue;
            }
            if declared.ty.as_ref().is_some_and(|ty| same_type(ty, &param_ty)) {
                continue;
            }
            let param = &signature.params[at.expect("a parameter")];
            return Err(mismatch(&arg.value, &var, &declared, &signature.name, param, &param_ty));
        }
        Ok(())
    }
}

fn mismatch(value: &Expr, var: &str, declared: &Declaration, proc: &str, param: &str, ty: &Ty) -> ParseError {
    let items = if declared.array { " array" } else { "" };
    let (have, want) = (type_name(declared.ty.as_ref()), type_name(Some(ty)));
    ParseError {
        offset: value.span.start as usize,
        message: format!(
            "ByRef argument type mismatch: {var} is a{} {have}{items} and {proc}'s ByRef parameter {param} is \
             {want}{items}; pass ({var}) for a converted copy, or declare it As {want}",
            if have.starts_with(['A', 'E', 'I', 'O', 'U']) { "n" } else { "" }
        ),
    }
}
