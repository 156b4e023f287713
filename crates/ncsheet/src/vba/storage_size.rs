//! `Len(varname)` and `LenB(varname)` of a variable declared of a type other than String or
//! Variant: the bytes its value takes, not the length of its text. Microsoft's "Len function":
//! "Returns a Long containing the number of characters in a string or the number of bytes
//! required to store a variable"; its example gives `Len(MyInt)` 2 for an Integer, `Len(MyCur)`
//! 8 for a Currency and `Len(Customer)` 42 for a Type of an Integer, a `String * 10` and a
//! `String * 30` ("With user-defined types, Len returns the size as it will be written to the
//! file"). A Variant is read "the same as a String", as is a String. LenB of a record is its
//! size in memory "including any padding between elements", which ncsheet does not lay out:
//! refused by name rather than answered with Len's figure.

use crate::eval::Value;
use crate::formula::ast::{Expr, ExprKind};

use super::ast::{Node, Span, Ty};
use super::interp::{Interp, Run};
use super::typing::Declared;
use super::value::Var;

/// The bytes a value of type `ty` takes, for the types whose size does not depend on the
/// value ("Data type summary": Byte 1, Boolean and Integer 2, Long and Single 4, Double,
/// Currency, Date and LongLong 8); `None` for String and Variant.
fn fixed_bytes(ty: Declared) -> Option<u64> {
    match ty {
        Declared::Byte => Some(1),
        Declared::Boolean | Declared::Integer => Some(2),
        Declared::Long | Declared::Single => Some(4),
        Declared::Double | Declared::Currency | Declared::Date | Declared::LongLong => Some(8),
        Declared::Decimal => Some(14),
        Declared::String | Declared::Variant => None,
    }
}

impl Interp<'_, '_> {
    /// `Len(x)` / `LenB(x)` (`call`, the function table's call of them): the storage size of a
    /// variable of a fixed-size type or of a Type, else what the call gives (the characters).
    pub(super) fn storage_len(&self, call: &Expr, bytes: bool, span: Span) -> Run<Value> {
        let ExprKind::Call(_, args) = &call.kind else { return self.eval(call) };
        let [arg] = args.as_slice() else { return self.eval(call) };
        if !self.names_a_variable(arg) {
            return self.eval(call);
        }
        if let Some(record) = self.record_type_of(arg) {
            return self.record_len(record, bytes, span).map(|n| Value::Number(n as f64));
        }
        match fixed_bytes(self.declared_type(arg)) {
            Some(n) => Ok(Value::Number(n as f64)),
            None => self.eval(call),
        }
    }

    /// `arg` is a variable, an array's item or a Type's field, which Len measures by its
    /// declaration; a call (`Len(F())`) is run and its text measured.
    fn names_a_variable(&self, arg: &Expr) -> bool {
        match &arg.kind {
            // A whole array is no variable's value (`Len(a)`): read as the call reads it.
            ExprKind::Name(name) => self.peek(name, |v| !matches!(v, Var::Array(_))).unwrap_or(true),
            ExprKind::Host(id) => matches!(self.module.nodes[*id as usize], Node::Element { .. } | Node::Path(_)),
            _ => false,
        }
    }

    /// The Type of the record `arg` names, found without evaluating anything: a variable of a
    /// Type, or an item of an array of one (`Len(a(1))`).
    fn record_type_of(&self, arg: &Expr) -> Option<usize> {
        let (name, item) = match &arg.kind {
            ExprKind::Name(name) => (name.clone(), false),
            ExprKind::Host(id) => match &self.module.nodes[*id as usize] {
                Node::Element { var, .. } => (var.clone(), true),
                _ => return None,
            },
            _ => return None,
        };
        let held = self.with_slot(&name, |s| (matches!(s.var(), Var::Array(_)), s.ty.clone()))?;
        match held {
            (array, Some(Ty::Record(i))) if array == item => Some(i),
            _ => None,
        }
    }

    /// Len of a record of Type `record`: each field's size, `String * n` its n characters, a
    /// fixed array of a fixed-size type its items', a Type field its own record's.
    fn record_len(&self, record: usize, bytes: bool, span: Span) -> Run<u64> {
        let def = &self.module.types[record];
        if bytes {
            let why = format!(
                "LenB of a {} value: its size in memory, padding between fields included (\"Len function\"), is not \
                 laid out by ncsheet; Len gives the size as written to a file",
                def.name
            );
            return Err(self.unsupported(span, why));
        }
        let mut total = 0u64;
        for (k, (field, ty)) in def.fields.iter().enumerate() {
            let size = match ty {
                Ty::FixedString(n) => Some(u64::from(*n)),
                Ty::Record(inner) if *inner != record => Some(self.record_len(*inner, false, span)?),
                ty => fixed_bytes(Declared::of_ty(Some(ty))),
            };
            let items = match &def.bounds[k] {
                None => Some(1),
                Some(bounds) => self.fixed_items(bounds)?,
            };
            let Some((size, items)) = size.zip(items) else {
                let why = format!(
                    "Len of a {} value: its field {field} has no fixed size (a String without * n, a Variant, an \
                     object or a dynamic array), and \"Len function\" says Len \"may not be able to determine\" it",
                    def.name
                );
                return Err(self.unsupported(span, why));
            };
            total = total.saturating_add(size.saturating_mul(items));
        }
        Ok(total)
    }

    /// The items of a Type's fixed array field (`x(1 To 3, 2) As Integer`): the product of
    /// each dimension's count, its lower bound the Option Base where left out; `None` for a
    /// dynamic one (`v() As Double`, no bounds).
    fn fixed_items(&self, bounds: &super::ast::Bounds) -> Run<Option<u64>> {
        if bounds.is_empty() {
            return Ok(None);
        }
        let mut items = 1u64;
        for (lower, upper) in bounds {
            let lower = match lower {
                Some(e) => self.index(e, "a lower bound")?,
                None => self.option_base(),
            };
            let count = (self.index(upper, "an upper bound")? - lower + 1).max(0) as u64;
            items = items.saturating_mul(count);
        }
        Ok(Some(items))
    }
}
