//! Members of Excel's and VBA's object model that work on any object the macro holds:
//! `CallByName` (a member named by a text at run time), `Application.Intersect` and
//! `Application.Union` of ranges, and the `Parent` and `Application` of Excel's objects.

use crate::eval::coerce::to_number;
use crate::eval::dates::DateSystem;
use crate::eval::functions::vba::errors;
use crate::eval::{Ctx, Value};
use crate::formula::address::Rect;
use crate::formula::ast::{ExprKind, SheetId};

use super::ast::{Arg, Link};
use super::interp::{Fault, Interp, Run};
use super::value::{print_text, Obj, Var};

/// VbCallType ("CallByName function"): what the call does with the member it names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CallType {
    /// vbMethod, 1: a Sub or Function called.
    Method,
    /// vbGet, 2: a property read.
    Get,
    /// vbLet, 4: a property given a value; the last argument is the value.
    Let,
    /// vbSet, 8: a property given an object; the last argument is the object.
    Set,
}

impl CallType {
    fn from_number(n: f64) -> Option<CallType> {
        match n {
            1.0 => Some(CallType::Method),
            2.0 => Some(CallType::Get),
            4.0 => Some(CallType::Let),
            8.0 => Some(CallType::Set),
            _ => None,
        }
    }
}

/// Which of Application's range operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum RangeSet {
    Intersect,
    Union,
}

impl RangeSet {
    fn name(self) -> &'static str {
        match self {
            RangeSet::Intersect => "Intersect",
            RangeSet::Union => "Union",
        }
    }
}

impl Interp<'_, '_> {
    fn coded_fault(&self, link: &Link, code: u32, detail: &str) -> Fault {
        let mut fault = self.fault_at(
            link.span,
            format!("{}: {} (run-time error {code}){detail}", link.name, errors::description(code)),
        );
        fault.code = code;
        fault
    }

    /// `CallByName(object, procName, callType, args…)` ("CallByName function"): runs the
    /// member of `object` that the text `procName` names, as `object.procName args…` would:
    /// a method (vbMethod 1), a property read (vbGet 2), or a property given the last argument
    /// (vbLet 4, vbSet 8). The object is one the macro already holds (an object of a class
    /// module, a Collection, a Dictionary, a Range, a Worksheet …): no program is reached.
    pub(super) fn call_by_name(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let args = link.args.as_deref().unwrap_or(&[]);
        if args.len() < 3 || args[..3].iter().any(|a| a.name.is_some() || a.value.kind == ExprKind::Missing) {
            return Err(self.coded_fault(link, 449, ": CallByName(object, procName, callType, args…)"));
        }
        let object = match self.var_of(&args[0].value, true)? {
            Var::Obj(Obj::Value(Value::Blank)) => return Err(self.coded_fault(link, 91, "")),
            Var::Obj(object) => self.alive(object, link.span)?,
            _ => return Err(self.coded_fault(link, 424, ": its first argument is not an object")),
        };
        let member = print_text(&self.eval(&args[1].value)?);
        let kind = to_number(&self.eval(&args[2].value)?, DateSystem::From1900).ok().and_then(CallType::from_number);
        let Some(kind) = kind else {
            return Err(self.coded_fault(link, 5, ": callType is vbMethod (1), vbGet (2), vbLet (4) or vbSet (8)"));
        };
        let rest = &args[3..];
        let copy = |given: &[Arg]| -> Vec<Arg> {
            given.iter().map(|a| Arg { name: a.name.clone(), value: a.value.clone() }).collect()
        };
        match kind {
            CallType::Method | CallType::Get => {
                let args = (!rest.is_empty()).then(|| copy(rest));
                self.member(ctx, object, &Link { name: member.into(), args, span: link.span })
            }
            CallType::Let | CallType::Set => {
                let Some((value, index)) = rest.split_last() else {
                    return Err(self.coded_fault(link, 449, &format!(": {member} is given no value")));
                };
                let args = (!index.is_empty()).then(|| copy(index));
                let target = Link { name: member.into(), args, span: link.span };
                self.set_member(ctx, object, &target, &value.value)?;
                Ok(Obj::Value(Value::Blank))
            }
        }
    }

    /// `Intersect(r1, r2, …)` and `Union(r1, r2, …)` ("Application.Intersect method",
    /// "Application.Union method", two to thirty ranges): the cells all the ranges share
    /// (Nothing when none, so `Intersect(…) Is Nothing` tests it), or the cells of any, as
    /// one Range of one or several areas (`areas.rs`). Ranges of different sheets are
    /// Excel's run-time error 1004.
    pub(super) fn range_set(&self, link: &Link, op: RangeSet) -> Run<Obj> {
        let args = link.args.as_deref().unwrap_or(&[]);
        if args.len() < 2 || args.len() > 30 {
            return Err(self.coded_fault(link, 449, &format!(": {} takes 2 to 30 ranges", op.name())));
        }
        let mut ranges: Vec<(SheetId, Vec<Rect>)> = Vec::with_capacity(args.len());
        for a in args {
            match self.var_of(&a.value, true)? {
                Var::Obj(Obj::Range(sheet, rect)) => ranges.push((sheet, vec![rect])),
                Var::Obj(Obj::Areas(sheet, areas)) => ranges.push((sheet, areas.to_vec())),
                // Nothing too: `Union(Nothing, c)` is error 5, which is why macros test
                // `If u Is Nothing Then Set u = c Else Set u = Union(u, c)`.
                _ => return Err(self.coded_fault(link, 5, &format!(": {} takes ranges", op.name()))),
            }
        }
        let sheet = ranges[0].0;
        if ranges.iter().any(|(s, _)| *s != sheet) {
            let why =
                format!(": Method '{}' of object '_Application' failed: the ranges are on different sheets", op.name());
            return Err(self.coded_fault(link, 1004, &why));
        }
        let whole = match op {
            RangeSet::Intersect => {
                let mut lists = ranges.into_iter().map(|(_, areas)| areas);
                let first = lists.next().expect("two ranges or more");
                lists.fold(first, |whole, areas| super::areas::intersection(&whole, &areas))
            }
            RangeSet::Union => {
                // The first range's areas as they are: `Set u = Union(u, c)` in a loop adds
                // one area to those already joined, without joining them all again.
                let mut lists = ranges.into_iter().map(|(_, areas)| areas);
                let mut whole = lists.next().expect("two ranges or more");
                for rect in lists.flatten() {
                    super::areas::add_area(&mut whole, rect)
                        .map_err(|why| self.fault_at(link.span, format!("Union: {why}")))?;
                }
                whole
            }
        };
        Ok(match whole.is_empty() {
            true => Obj::Value(Value::Blank),
            false => super::areas::range_of(sheet, whole),
        })
    }

    /// `x.Application` and `x.Parent` of Excel's objects ("Range.Parent property" is the
    /// Worksheet, "Worksheet.Parent property" the Workbook, "Workbook.Parent property" and
    /// every object's `Application` the Application); `None` for another member or object.
    pub(super) fn family_member(&self, obj: &Obj, link: &Link) -> Option<Obj> {
        let excel = matches!(
            obj,
            Obj::Range(..)
                | Obj::Areas(..)
                | Obj::Lines(..)
                | Obj::Look(..)
                | Obj::Sheet(_)
                | Obj::Sheets
                | Obj::Workbook
                | Obj::App
        );
        if !excel || link.args.is_some() {
            return None;
        }
        match (super::objects::lower(link).as_str(), obj) {
            ("application", _) => Some(Obj::App),
            ("parent", Obj::Sheet(_) | Obj::Sheets) => Some(Obj::Workbook),
            ("parent", Obj::Workbook | Obj::App) => Some(Obj::App),
            ("parent", Obj::Lines(sheet, ..)) => Some(Obj::Sheet(*sheet)),
            ("parent", Obj::Look(sheet, rect, _)) => Some(Obj::Range(*sheet, *rect)),
            _ => None,
        }
    }
}
