//! The dialogs a macro asks its user through: VBA's `InputBox`, Excel's `Application.InputBox`,
//! `Application.GetOpenFilename` and `Application.GetSaveAsFilename`.
//!
//! A run has no user. With `ncsheet run --input TEXT` (repeatable) the answers are given
//! beforehand and each dialog takes the next, in the order the macro opens them; once none is
//! left, the dialog is cancelled, which each reports as Microsoft's reference says (below).
//! Without any `--input` a dialog stops the run by name whatever `On Error` says: a macro
//! going on without the answer it asked for would compute something else than in Excel.

use super::ast::Link;
use super::interp::{Interp, Run};
use super::sheet_ops::argument;
use super::value::Obj;
use crate::eval::Ctx;
use crate::eval::Value;

/// `Application.InputBox`'s Type bits ("Application.InputBox method": 0 a formula, 1 a
/// number, 2 text, 4 a logical value, 8 a cell reference, 16 an error value, 64 an array of
/// values; a sum allows several).
const TYPE_NUMBER: u32 = 1;
const TYPE_LOGICAL: u32 = 4;
const TYPE_REFERENCE: u32 = 8;
/// The types whose answer ncsheet gives as text: a formula (0) and text (2).
const TYPE_TEXT: u32 = 2;
const TYPES_KNOWN: u32 = TYPE_NUMBER | TYPE_TEXT | TYPE_LOGICAL | TYPE_REFERENCE;

impl Interp<'_, '_> {
    /// The next `--input` answer; `None` when the user pressed Cancel (the answers are spent).
    /// Without `--input` the dialog `what` is refused.
    fn next_answer(&self, what: &str, link: &Link) -> Run<Option<String>> {
        let Some(answers) = self.options.answers.as_ref() else {
            return Err(self.unsupported(
                link.span,
                format!(
                    "{what}: a macro runs without a user; answer its dialogs in order with `ncsheet run --input \
                     TEXT` (repeatable; past the last answer a dialog is cancelled), or pass values with --arg \
                     NAME=VALUE or read them from cells"
                ),
            ));
        };
        let k = self.answered.get();
        self.answered.set(k + 1);
        Ok(answers.get(k).cloned())
    }

    /// VBA's `InputBox(Prompt, Title, Default, …)`: the answer as a String; Cancel gives ""
    /// ("InputBox function": "If the user chooses Cancel, the function returns a zero-length
    /// string").
    #[inline(never)]
    pub(super) fn input_box(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        self.values(ctx, link)?;
        let answer = self.next_answer("InputBox", link)?;
        Ok(Obj::Value(Value::text(answer.unwrap_or_default())))
    }

    /// `Application.InputBox(Prompt, Title, Default, Left, Top, HelpFile, HelpContextID, Type)`:
    /// the answer read as Type asks (text when Type is left out); Cancel gives False
    /// ("Application.InputBox method").
    #[inline(never)]
    pub(super) fn application_input_box(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let ty = match argument(link, 7, "type") {
            None => TYPE_TEXT,
            Some(e) => {
                let v = ctx.eval(e).unwrap_single();
                self.take_pending()?;
                let n = self.number_of(&v, "Application.InputBox's Type").map_err(|m| self.fault_at(link.span, m))?;
                n.round() as u32
            }
        };
        self.values(ctx, link)?;
        if ty & !TYPES_KNOWN != 0 || ty == 0 {
            return Err(self.unsupported(
                link.span,
                format!(
                    "Application.InputBox Type:={ty}: ncsheet answers a number (1), text (2), a logical value (4) \
                     or a cell reference (8), or a sum of these; a formula, an error value or an array is not read"
                ),
            ));
        }
        let Some(answer) = self.next_answer("Application.InputBox", link)? else {
            return Ok(Obj::Value(Value::Bool(false)));
        };
        self.typed_answer(&answer, ty, link)
    }

    /// `answer` as the first of Type's kinds it reads as: a reference, a number, a logical
    /// value, then text. An answer of none of them is refused by name, where Excel would say
    /// so and ask again.
    fn typed_answer(&self, answer: &str, ty: u32, link: &Link) -> Run<Obj> {
        let trimmed = answer.trim();
        if ty & TYPE_REFERENCE != 0 {
            let here = self.unqualified_sheet();
            if let Ok((sheet, rect)) = self.resolve(here, trimmed.trim_start_matches('='), link.span) {
                return Ok(Obj::Range(sheet, rect));
            }
        }
        if ty & TYPE_NUMBER != 0 {
            if let Some(n) = crate::eval::coerce::parse_plain_number(trimmed) {
                return Ok(Obj::Value(Value::Number(n)));
            }
        }
        if ty & TYPE_LOGICAL != 0 {
            match trimmed.to_ascii_uppercase().as_str() {
                "TRUE" => return Ok(Obj::Value(Value::Bool(true))),
                "FALSE" => return Ok(Obj::Value(Value::Bool(false))),
                _ => {}
            }
        }
        if ty & TYPE_TEXT != 0 {
            return Ok(Obj::Value(Value::text(answer)));
        }
        Err(self.unsupported(
            link.span,
            format!(
                "Application.InputBox Type:={ty}: the --input answer \"{answer}\" is not of that type (Excel would \
                 ask again)"
            ),
        ))
    }

    /// `Application.GetOpenFilename` / `GetSaveAsFilename`: the answer is the file's name as
    /// the user typed it, which the macro's file statements then find in the --out-dir folder
    /// or among the --in-file files as any other name; Cancel gives False ("Application.
    /// GetOpenFilename method", "Application.GetSaveAsFilename method").
    #[inline(never)]
    pub(super) fn file_name_dialog(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let open = link.name.eq_ignore_ascii_case("getopenfilename");
        if open {
            if let Some(e) = argument(link, 4, "multiselect") {
                let v = ctx.eval(e).unwrap_single();
                self.take_pending()?;
                if crate::eval::coerce::to_bool(&v).unwrap_or(false) {
                    return Err(self.unsupported(
                        link.span,
                        "Application.GetOpenFilename MultiSelect:=True: ncsheet answers one file name per dialog \
                         (its array of names is not made)",
                    ));
                }
            }
        }
        self.values(ctx, link)?;
        let what = format!("Application.{}", link.name);
        Ok(Obj::Value(match self.next_answer(&what, link)? {
            Some(name) => Value::text(name),
            None => Value::Bool(false),
        }))
    }
}
