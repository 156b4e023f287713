//! Members of Excel's objects that ncsheet has no code for, decided by one table.
//!
//! A member that only touches Excel's window, its manners or a look ncsheet does not keep
//! (`ScreenUpdating`, `StatusBar`, `Borders`, `ActiveWindow.Zoom` …) is harmless: setting or
//! calling it does nothing, as it would change no value and no file ncsheet writes. Any other
//! member stops the run with its name, even under `On Error Resume Next`: skipping it, as a
//! trapped error 438 would, leaves the macro computing without the member's effect, which is a
//! silent wrong answer (issue 31: "where ncsheet deliberately differs, it refuses with the
//! reason instead of computing something else").

use super::ast::Link;
use super::interp::{Fault, Interp, Run};
use super::value::Obj;
use crate::eval::Value;

/// The code of a member, argument or form ncsheet does not model: no `On Error` traps it.
pub(super) const NOT_MODELLED: u32 = crate::eval::functions::vba::errors::NOT_SUPPORTED;

/// The Excel object a harmless member belongs to.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Owner {
    App,
    Workbook,
    Sheet,
    Range,
    Font,
    Interior,
}

/// What a harmless member does.
#[derive(Clone, Copy)]
enum Harmless {
    /// A setting of Excel's window or manners: a write does nothing; a read gives what Excel
    /// gives while a macro runs (`None`: a look ncsheet does not keep, so a read is refused).
    Setting(Option<Read>),
    /// A method whose effect ncsheet already has, or that only shows something: a call does
    /// nothing.
    Method,
    /// An object of such settings and methods (`Borders(xlEdgeBottom)`, `ActiveWindow`): every
    /// member of it is set or called as a no-op ([`Obj::Unkept`]).
    Object(&'static str),
}

/// The value a harmless setting reads as.
#[derive(Clone, Copy)]
enum Read {
    Bool(bool),
    Number(f64),
}

/// The one table: (object, member in lower case, what it is). Members absent here and absent
/// from the objects' own code are refused by name.
const HARMLESS: &[(Owner, &str, Harmless)] = &[
    // "Application.ScreenUpdating/DisplayAlerts/EnableEvents": True unless a macro set them.
    (Owner::App, "screenupdating", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "displayalerts", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "enableevents", Harmless::Setting(Some(Read::Bool(true)))),
    // "Application.StatusBar": False while Excel has control of the status bar.
    (Owner::App, "statusbar", Harmless::Setting(Some(Read::Bool(false)))),
    (Owner::App, "displaystatusbar", Harmless::Setting(Some(Read::Bool(true)))),
    // ncsheet computes every formula whenever a cell changes: xlCalculationAutomatic (-4105),
    // and the Calculate methods have nothing left to do.
    (Owner::App, "calculation", Harmless::Setting(Some(Read::Number(-4105.0)))),
    (Owner::App, "calculatebeforesave", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "calculatefull", Harmless::Method),
    (Owner::App, "calculatefullrebuild", Harmless::Method),
    // "Application.Wait method": pauses the macro until a time; no value or file depends on
    // the pause, and ncsheet's run is not paced by the clock.
    (Owner::App, "wait", Harmless::Method),
    // "Application.Cursor": xlDefault (-4143).
    (Owner::App, "cursor", Harmless::Setting(Some(Read::Number(-4143.0)))),
    (Owner::App, "interactive", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "enableanimations", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "asktoupdatelinks", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "displayformulabar", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::App, "displayfullscreen", Harmless::Setting(Some(Read::Bool(false)))),
    // "XlEnableCancelKey": xlInterrupt (1).
    (Owner::App, "enablecancelkey", Harmless::Setting(Some(Read::Number(1.0)))),
    (Owner::App, "activewindow", Harmless::Object("ActiveWindow")),
    (Owner::App, "windows", Harmless::Object("Windows")),
    (Owner::App, "commandbars", Harmless::Object("CommandBars")),
    (Owner::Workbook, "activate", Harmless::Method),
    (Owner::Workbook, "windows", Harmless::Object("Windows")),
    (Owner::Sheet, "calculate", Harmless::Method),
    (Owner::Sheet, "enablecalculation", Harmless::Setting(Some(Read::Bool(true)))),
    (Owner::Sheet, "displaypagebreaks", Harmless::Setting(Some(Read::Bool(false)))),
    (Owner::Sheet, "scrollarea", Harmless::Setting(None)),
    (Owner::Sheet, "tab", Harmless::Object("Tab")),
    (Owner::Range, "calculate", Harmless::Method),
    (Owner::Range, "dirty", Harmless::Method),
    (Owner::Range, "show", Harmless::Method),
    (Owner::Range, "borders", Harmless::Object("Borders")),
    (Owner::Range, "borderaround", Harmless::Method),
    (Owner::Range, "formatconditions", Harmless::Object("FormatConditions")),
    (Owner::Range, "orientation", Harmless::Setting(None)),
    (Owner::Range, "indentlevel", Harmless::Setting(None)),
    (Owner::Range, "addindent", Harmless::Setting(None)),
    (Owner::Range, "shrinktofit", Harmless::Setting(None)),
    (Owner::Font, "strikethrough", Harmless::Setting(None)),
    (Owner::Font, "superscript", Harmless::Setting(None)),
    (Owner::Font, "subscript", Harmless::Setting(None)),
    (Owner::Font, "shadow", Harmless::Setting(None)),
    (Owner::Font, "outlinefont", Harmless::Setting(None)),
    (Owner::Font, "themecolor", Harmless::Setting(None)),
    (Owner::Font, "themefont", Harmless::Setting(None)),
    (Owner::Font, "tintandshade", Harmless::Setting(None)),
    (Owner::Interior, "pattern", Harmless::Setting(None)),
    (Owner::Interior, "patterncolor", Harmless::Setting(None)),
    (Owner::Interior, "patterncolorindex", Harmless::Setting(None)),
    (Owner::Interior, "patterntintandshade", Harmless::Setting(None)),
    (Owner::Interior, "themecolor", Harmless::Setting(None)),
    (Owner::Interior, "tintandshade", Harmless::Setting(None)),
];

/// Every member of Excel's Sheets and Worksheets collections ("Sheets Members (Excel)",
/// "Worksheets Members (Excel)", with Excel 2013's Add2 and the hidden `_Default` and
/// `_PrintOut`). A name not here is no member of theirs at all: VBA's error 438, which a macro
/// probing an object for a method (`On Error Resume Next: found = x.Exists(k)`) traps.
const SHEETS_MEMBERS: &str = "_default _printout add add2 application copy count creator delete \
    fillacrosssheets hpagebreaks item move parent printout printpreview select visible vpagebreaks";

/// Whether Excel's class of `obj` has `member` (lower case); `None` for the classes whose
/// whole list of members is not kept here.
fn excel_has(obj: &Obj, member: &str) -> Option<bool> {
    match obj {
        Obj::Sheets => Some(SHEETS_MEMBERS.split_whitespace().any(|m| m == member)),
        _ => None,
    }
}

/// The names a macro reaches the window by without an object before them.
pub(super) fn window_root(name: &str) -> Option<Obj> {
    match name {
        "activewindow" => Some(Obj::Unkept("ActiveWindow".into())),
        "windows" => Some(Obj::Unkept("Windows".into())),
        _ => None,
    }
}

/// The owner of `obj`'s members in [`HARMLESS`]; `None` for objects without harmless members.
fn owner(obj: &Obj) -> Option<Owner> {
    use super::formats::LookPart;
    Some(match obj {
        Obj::App => Owner::App,
        Obj::Workbook => Owner::Workbook,
        Obj::Sheet(_) | Obj::SheetGroup(_) => Owner::Sheet,
        Obj::Range(..) | Obj::Lines(..) => Owner::Range,
        Obj::Look(_, _, LookPart::Font) => Owner::Font,
        Obj::Look(_, _, LookPart::Interior) => Owner::Interior,
        _ => return None,
    })
}

/// The table's row for `member` (lower case) of `obj`.
fn harmless(obj: &Obj, member: &str) -> Option<Harmless> {
    let owner = owner(obj)?;
    HARMLESS.iter().find(|(o, m, _)| *o == owner && *m == member).map(|(_, _, h)| *h)
}

/// Where a harmless setting the macro wrote is kept: by sheet for a sheet's, else by class.
fn setting_key(obj: &Obj, member: &str) -> String {
    match obj {
        Obj::Sheet(id) => format!("Worksheet {id}.{member}"),
        _ => format!("{}.{member}", class_name(obj)),
    }
}

/// How a message names `obj`: Excel's class, as `Application.Wait` or `Range.Merge`.
fn class_name(obj: &Obj) -> &str {
    use super::formats::LookPart;
    match obj {
        Obj::App => "Application",
        Obj::Workbook => "Workbook",
        Obj::Sheets => "Worksheets",
        Obj::Sheet(_) | Obj::SheetGroup(_) => "Worksheet",
        Obj::Range(..) | Obj::Lines(..) => "Range",
        Obj::Look(_, _, LookPart::Font) => "Font",
        Obj::Look(_, _, LookPart::Interior) => "Interior",
        Obj::Hyperlinks(..) => "Hyperlinks",
        Obj::Hyperlink(..) => "Hyperlink",
        Obj::Table(t) => t.class(),
        Obj::SheetSort(_) => "Sort",
        Obj::SortFields(_) => "SortFields",
        Obj::Files(super::files::FileObj::System) => "FileSystemObject",
        Obj::Files(super::files::FileObj::Stream(_)) => "TextStream",
        Obj::Unkept(what) => what.as_ref(),
        other => other.describe(),
    }
}

/// Whether `obj.Member = v` sets a harmless setting (any member of an [`Obj::Unkept`]), which
/// does nothing.
pub(super) fn harmless_setting(obj: &Obj, link: &Link) -> bool {
    match obj {
        Obj::Unkept(_) => true,
        _ => matches!(harmless(obj, &super::objects::lower(link)), Some(Harmless::Setting(_))),
    }
}

impl Interp<'_, '_> {
    /// A member of Excel's object `obj` that its own code does not have: the harmless ones
    /// as no-ops, any other refused by name whatever `On Error` says.
    pub(super) fn unmodelled(&self, obj: &Obj, link: &Link) -> Run<Obj> {
        let name = super::objects::lower(link);
        match harmless(obj, &name) {
            Some(Harmless::Setting(Some(default))) => {
                let set = self.harmless_settings.borrow().get(&setting_key(obj, &name)).cloned();
                Ok(Obj::Value(set.unwrap_or(match default {
                    Read::Bool(b) => Value::Bool(b),
                    Read::Number(n) => Value::Number(n),
                })))
            }
            Some(Harmless::Setting(None) | Harmless::Method) => {
                Ok(Obj::Unkept(format!("{}.{}", class_name(obj), link.name).into()))
            }
            Some(Harmless::Object(what)) => Ok(Obj::Unkept(what.into())),
            None if excel_has(obj, &name) == Some(false) => Err(self.not_a_member(obj, link)),
            None => Err(self.not_modelled(obj, link)),
        }
    }

    /// `obj.Member = v` for a harmless setting ([`harmless_setting`]): `v` is computed and
    /// kept for the setting's reads; nothing else happens.
    pub(super) fn set_harmless(&self, obj: &Obj, link: &Link, value: &crate::formula::ast::Expr) -> Run<()> {
        let v = self.eval(value)?;
        if !matches!(obj, Obj::Unkept(_)) {
            self.harmless_settings.borrow_mut().insert(setting_key(obj, &super::objects::lower(link)), v);
        }
        Ok(())
    }

    /// ncsheet's refusal of what VBA or Excel would do and ncsheet has no code for, at `span`:
    /// the run stops there whatever `On Error` says, since a trapped refusal lets the macro go
    /// on without the statement's effect (r08 of session 30: `On Error Resume Next` skipped a
    /// refused paste and the merged sheet came out empty). Every such refusal is made here.
    #[cold]
    #[inline(never)]
    pub(super) fn unsupported(&self, span: super::ast::Span, message: impl Into<String>) -> Fault {
        let mut fault = self.fault_at(span, message);
        fault.code = NOT_MODELLED;
        fault
    }

    /// [`Interp::unsupported`] at the running statement, for a refusal made below the place
    /// that knows its span.
    #[cold]
    #[inline(never)]
    pub(super) fn unsupported_here(&self, message: impl Into<String>) -> Fault {
        let mut fault = self.fault(message);
        fault.code = NOT_MODELLED;
        fault
    }

    /// ncsheet's limit on what one statement may do (write, paste, format or hide more cells
    /// than docs/limits.md allows), at `span` or the running statement: a limit, which no
    /// `On Error` traps, as the statement and memory limits are; a trapped one let the macro
    /// go on as if the cells had been written.
    #[cold]
    #[inline(never)]
    pub(super) fn beyond_limit(&self, span: Option<super::ast::Span>, message: impl Into<String>) -> Fault {
        let mut fault = self.fault(message);
        fault.span = span.or(fault.span);
        fault.kind = super::ErrorKind::Limit;
        fault
    }

    /// The refusal of `obj.Member`: untrappable, naming the member.
    pub(super) fn not_modelled(&self, obj: &Obj, link: &Link) -> Fault {
        self.unsupported(
            link.span,
            format!(
                "{}.{} is not modelled by ncsheet: its effect on the workbook's values or files would be \
                 lost, so the run stops here (On Error does not skip it)",
                class_name(obj),
                link.name
            ),
        )
    }

    /// `obj.Member` where Excel's class has no such member: VBA's error 438, trappable as in
    /// Excel, since skipping it loses no effect Excel would have had.
    fn not_a_member(&self, obj: &Obj, link: &Link) -> Fault {
        let description = crate::eval::functions::vba::errors::description(438);
        let mut fault =
            self.fault_at(link.span, format!("{}.{}: {description} (run-time error 438)", class_name(obj), link.name));
        fault.code = 438;
        fault
    }

    /// Reading a value from a harmless object or setting ncsheet does not keep.
    pub(super) fn unkept_read(&self, what: &str, span: super::ast::Span) -> Fault {
        self.unsupported(
            span,
            format!(
                "{what}: ncsheet keeps no such setting or look (setting it does nothing), so it has no value to \
                 read"
            ),
        )
    }
}
