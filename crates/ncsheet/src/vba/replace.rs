//! `Range.Replace` ("Range.Replace method"): Excel's Find and Replace over a range's cells, as a
//! recorded macro runs it (`Columns("B:B").Replace What:=",", Replacement:=".", LookAt:=xlPart`).

use regex::{NoExpand, Regex};

use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;

use super::ast::Link;
use super::interp::{Interp, Run};
use super::sheet_ops::argument;
use super::value::Obj;

/// `XlLookAt`: the whole cell must match (`xlWhole`, 1) or a part of it (`xlPart`, 2).
const XL_WHOLE: f64 = 1.0;
const XL_PART: f64 = 2.0;

impl Interp<'_, '_> {
    /// `rng.Replace What, Replacement, [LookAt], [SearchOrder], [MatchCase], [MatchByte],
    /// [SearchFormat], [ReplaceFormat]`: in every cell of the range whose formula (or constant,
    /// as typed) holds `What`, the text is replaced and the cell typed again, so "1,5" made
    /// "1.5" is the number 1.5 and a changed formula computes anew. `What` takes Excel's
    /// wildcards (`*`, `?`, `~` before either for itself); case is ignored unless MatchCase is
    /// True. Cells without a match are left as they are. The result is True.
    pub(super) fn replace_in_range(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        let needed = |what: &str| self.fault_at(link.span, format!("Range.Replace needs {what}:="));
        let what = self.text_argument(link, 0, "What")?.ok_or_else(|| needed("What"))?;
        let replacement = self.text_argument(link, 1, "Replacement")?.ok_or_else(|| needed("Replacement"))?;
        let look_at = self.look_at(link)?;
        let match_case = self.flag_argument(link, 4, "MatchCase")?.unwrap_or(false);
        for (position, name) in [(6, "SearchFormat"), (7, "ReplaceFormat")] {
            if self.flag_argument(link, position, name)?.unwrap_or(false) {
                let why = format!("Range.Replace {name}:=True: ncsheet does not search or replace by cell format");
                return Err(self.fault_at(link.span, why));
            }
        }
        if what.is_empty() {
            return Err(self.fault_at(link.span, "Range.Replace: What:= is empty; name the text to replace"));
        }
        let pattern = wildcard_pattern(&what, look_at == XL_WHOLE, match_case);
        let pattern =
            Regex::new(&pattern).map_err(|e| self.fault_at(link.span, format!("Range.Replace What:={what}: {e}")))?;
        let used = ctx.clip_to_used(sheet, rect);
        for row in used.first.row..=used.last.row {
            for col in used.first.col..=used.last.col {
                let cell = Rect::cell(Pos::new(row, col));
                let Value::Text(typed) = self.formulas(sheet, cell, false) else { continue };
                let replaced = pattern.replace_all(&typed, NoExpand(&replacement));
                if replaced != *typed {
                    let replaced = replaced.into_owned();
                    self.write_range(sheet, cell, &Value::text(replaced))?;
                }
            }
        }
        Ok(Obj::Value(Value::Bool(true)))
    }

    /// LookAt:=xlPart (2, the default) or xlWhole (1).
    fn look_at(&self, link: &Link) -> Run<f64> {
        let Some(e) = argument(link, 2, "LookAt") else { return Ok(XL_PART) };
        match self.eval(e)? {
            Value::Number(n) if n == XL_WHOLE || n == XL_PART => Ok(n),
            _ => Err(self.fault_at(link.span, "Range.Replace LookAt:= is xlPart or xlWhole")),
        }
    }
}

/// The regular expression of Excel's Find-and-Replace text: `*` any run of characters, `?`
/// any one, `~*` `~?` `~~` the character itself; every other character stands for itself.
fn wildcard_pattern(what: &str, whole: bool, match_case: bool) -> String {
    let mut pattern = String::from(if match_case { "(?s)" } else { "(?si)" });
    if whole {
        pattern.push('^');
    }
    let mut chars = what.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '~' if matches!(chars.peek(), Some('*' | '?' | '~')) => {
                pattern += &regex::escape(&chars.next().expect("peeked").to_string());
            }
            '*' => pattern += ".*",
            '?' => pattern.push('.'),
            other => pattern += &regex::escape(&other.to_string()),
        }
    }
    if whole {
        pattern.push('$');
    }
    pattern
}

#[cfg(test)]
mod tests {
    use super::wildcard_pattern;

    #[test]
    fn wildcards_become_a_pattern_and_other_characters_stand_for_themselves() {
        assert_eq!(wildcard_pattern("a*b?", false, true), "(?s)a.*b.");
        assert_eq!(wildcard_pattern("~*.~?", true, false), "(?si)^\\*\\.\\?$");
    }
}
