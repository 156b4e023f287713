//! `DefLng A-Z`, `DefStr S`: a module's implicit declared types ([MS-VBAL] 5.2.2 "Implicit
//! Definition Directives"; "Deftype statements"). A name declared without `As` and without a
//! type character (a variable, a parameter, a Function's or Property Get's result, and a
//! variable used without any declaration) takes the type its module's directive gives its
//! first letter; with none it is a Variant.

use pest::iterators::Pair;

use crate::formula::parse::{ParseError, Rule};

use super::ast::{Block, Stmt, StmtKind, Ty, VarDecl};
use super::parser::{start, ty_named, Build, Res};

/// One letter spec of a module's directive and the type it gives.
#[derive(Clone, Debug)]
pub(super) struct ImplicitType {
    /// The module of the project (`Module::parts`) the directive is in: it rules only there.
    part: usize,
    /// The first letters it covers, ASCII lower case; `None` for `A-Z`, which [MS-VBAL] 5.2.2
    /// makes universal (any first character, not only the ASCII letters).
    letters: Option<(u8, u8)>,
    ty: Ty,
}

/// The declared type a `Def…` keyword gives ("Deftype statements": DefLngPtr is LongPtr, a
/// LongLong in 64-bit Office).
fn directive_ty(keyword: &str) -> Ty {
    ty_named(match keyword.get(3..).unwrap_or_default().to_ascii_lowercase().as_str() {
        "bool" => "boolean",
        "byte" => "byte",
        "cur" => "currency",
        "date" => "date",
        "dbl" => "double",
        "dec" => "decimal",
        "int" => "integer",
        "lng" => "long",
        "lnglng" => "longlong",
        "lngptr" => "longptr",
        "obj" => "object",
        "sng" => "single",
        "str" => "string",
        _ => "variant",
    })
}

/// The letters of one letter spec (`A`, `c-f`, `A-Z`), `None` for the universal `A-Z`.
fn letters_of(spec: &str) -> Result<Option<(u8, u8)>, String> {
    let mut ends = spec.split('-').map(str::trim);
    let first = ends.next().unwrap_or_default();
    let last = ends.next().unwrap_or(first);
    // [MS-VBAL] 5.2.2: the universal range is upper-case A to upper-case Z.
    if first == "A" && last == "Z" {
        return Ok(None);
    }
    let (a, z) = (first.as_bytes()[0].to_ascii_lowercase(), last.as_bytes()[0].to_ascii_lowercase());
    if a > z {
        return Err(format!("{spec}: the first letter of a range comes before the last"));
    }
    Ok(Some((a, z)))
}

impl Build<'_> {
    /// Notes a module's `Def…` directive for the names declared after it.
    pub(super) fn deftype(&self, pair: &Pair<Rule>) -> Res<()> {
        let mut inner = pair.clone().into_inner();
        let ty = directive_ty(inner.next().expect("Def keyword").as_str());
        let part = self.current_part.get();
        for spec in inner.filter(|p| p.as_rule() == Rule::letter_spec) {
            let letters = letters_of(spec.as_str()).map_err(|message| ParseError { offset: start(&spec), message })?;
            self.implicit_types.borrow_mut().push(ImplicitType { part, letters, ty: ty.clone() });
        }
        Ok(())
    }

    /// The type the current module's directives give `name`, declared without a type; `None`
    /// for a Variant (no directive covers its first letter, or `DefVar` does).
    pub(super) fn implicit_ty(&self, name: &str) -> Option<Ty> {
        let first = name.chars().next()?;
        let part = self.current_part.get();
        let covers = |d: &&ImplicitType| {
            d.part == part
                && d.letters.is_none_or(|(a, z)| {
                    first.is_ascii_alphabetic() && (a..=z).contains(&(first as u8).to_ascii_lowercase())
                })
        };
        // A later directive of the module overrides an earlier one for its letters.
        let types = self.implicit_types.borrow();
        types.iter().rev().find(covers).map(|d| d.ty.clone()).filter(|ty| *ty != Ty::Variant)
    }

    /// Notes the procedure's variable `name`, used at `offset` without a declaration, as one
    /// of the type `ty` its module's directive gives it ([MS-VBAL] 5.2.2: an implicitly
    /// declared variable's declared type is the one the directive gives its first letter).
    pub(super) fn declare_implicit_var(&self, offset: usize, name: &str, ty: Ty) {
        let span = self.span(offset);
        let decl = VarDecl { name: name.into(), ty: Some(ty), bounds: None, new: None, span, field: None, item: None };
        self.implicit_vars.borrow_mut().push(decl);
    }

    /// Declares the procedure's implicitly typed variables at its start, so each has its
    /// type's value and range from the first statement: `i` under `DefInt I-N` is an Integer
    /// 0, and `i = 40000` overflows (error 6) as a declared Integer does.
    pub(super) fn declare_implicit_vars(&self, body: &mut Block) {
        let vars = std::mem::take(&mut *self.implicit_vars.borrow_mut());
        let Some(first) = vars.first() else { return };
        let span = first.span;
        // In a Static Sub every local keeps its value, the implicit ones too ([MS-VBAL] 5.3.1.2).
        let kind = if self.scope.borrow().all_static { StmtKind::Static(vars) } else { StmtKind::Dim(vars) };
        body.prepend(Stmt { kind, span });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_letter_spec_is_one_letter_a_range_or_the_universal_range() {
        assert_eq!(letters_of("c"), Ok(Some((b'c', b'c'))));
        assert_eq!(letters_of("S-u"), Ok(Some((b's', b'u'))));
        assert_eq!(letters_of("A-Z"), Ok(None));
        assert_eq!(letters_of("a-z"), Ok(Some((b'a', b'z'))));
        assert!(letters_of("Z-A").is_err());
    }

    #[test]
    fn each_keyword_gives_its_type() {
        assert_eq!(directive_ty("DefLng"), ty_named("long"));
        assert_eq!(directive_ty("defstr"), ty_named("string"));
        assert_eq!(directive_ty("DefLngLng"), ty_named("longlong"));
        assert_eq!(directive_ty("DefVar"), Ty::Variant);
    }
}
