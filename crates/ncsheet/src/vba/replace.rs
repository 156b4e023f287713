//! `Range.Replace` ("Range.Replace method"), `Range.Find` ("Range.Find method") and
//! `Range.FindNext`/`FindPrevious`: Excel's Find and Replace over a range's cells, as a
//! recorded macro runs it (`Columns("B:B").Replace What:=",", Replacement:=".", LookAt:=xlPart`,
//! `Cells.Find("*", SearchOrder:=xlByRows, SearchDirection:=xlPrevious).Row`) and as the
//! find-all loop of Microsoft's example goes round (`Set c = .FindNext(c)` until the first
//! address comes back).

use regex::{NoExpand, Regex};

use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;

use super::ast::Link;
use super::interp::{Interp, Run};
use super::sheet_ops::argument;
use super::value::{Obj, Var};

use super::resolve::constant_number as xl;

/// The work a filled cell searched by Find or Replace counts ([`Interp::add_work`]): a
/// statement's worth, as reading its text (a number shown as text) and matching it cost
/// about what a statement does (0.45 µs in release). A blank cell counts an item. Uncounted,
/// `Columns(1).Find` over 100,000 cells in a loop ran for minutes counting a statement a turn.
const CELL_SEARCHED: u64 = super::interp::WORK_PER_STATEMENT;

impl Interp<'_, '_> {
    /// `rng.Replace What, Replacement, [LookAt], [SearchOrder], [MatchCase], [MatchByte],
    /// [SearchFormat], [ReplaceFormat]`: in every cell of the range whose formula (or constant,
    /// as typed) holds `What`, the text is replaced and the cell typed again, so "1,5" made
    /// "1.5" is the number 1.5 and a changed formula computes anew. `What` takes Excel's
    /// wildcards (`*`, `?`, `~` before either for itself); case is ignored unless MatchCase is
    /// True. Cells without a match are left as they are. The result is True. "The settings for
    /// LookAt, SearchOrder, MatchCase, and MatchByte are saved each time you use this method. If
    /// you don't specify values for these arguments the next time you call the method, the saved
    /// values are used. Setting these arguments changes the settings in the Find dialog box"
    /// (Range.Replace method): one saved set with Find's ([`FindSettings`]).
    pub(super) fn replace_in_range(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        let needed = |what: &str| self.fault_at(link.span, format!("Range.Replace needs {what}:="));
        let what = self.text_argument(link, 0, "What")?.ok_or_else(|| needed("What"))?;
        let replacement = self.text_argument(link, 1, "Replacement")?.ok_or_else(|| needed("Replacement"))?;
        let saved = self.find_conditions.borrow().saved;
        let settings = FindSettings {
            whole: self.xl_choice(link, 2, "LookAt", ("xlWhole", "xlPart"), saved.whole)?,
            by_columns: self.xl_choice(link, 3, "SearchOrder", ("xlByColumns", "xlByRows"), saved.by_columns)?,
            match_case: self.flag_argument(link, 4, "MatchCase")?.unwrap_or(saved.match_case),
            ..saved
        };
        for (position, name) in [(6, "SearchFormat"), (7, "ReplaceFormat")] {
            if self.flag_argument(link, position, name)?.unwrap_or(false) {
                let why = format!("Range.Replace {name}:=True: ncsheet does not search or replace by cell format");
                return Err(self.unsupported(link.span, why));
            }
        }
        if what.is_empty() {
            return Err(self.fault_at(link.span, "Range.Replace: What:= is empty; name the text to replace"));
        }
        self.find_conditions.borrow_mut().saved = settings;
        let pattern = wildcard_pattern(&what, settings.whole, settings.match_case);
        let pattern =
            Regex::new(&pattern).map_err(|e| self.fault_at(link.span, format!("Range.Replace What:={what}: {e}")))?;
        let used = ctx.clip_to_used(sheet, rect);
        for row in used.first.row..=used.last.row {
            for col in used.first.col..=used.last.col {
                let cell = Rect::cell(Pos::new(row, col));
                self.add_work(1);
                let Value::Text(typed) = self.formulas(sheet, cell, false) else { continue };
                self.add_work(CELL_SEARCHED);
                let replaced = pattern.replace_all(&typed, NoExpand(&replacement));
                if replaced != *typed {
                    let replaced = replaced.into_owned();
                    self.write_range(sheet, cell, &Value::text(replaced))?;
                }
            }
        }
        Ok(Obj::Value(Value::Bool(true)))
    }

    /// `rng.Find What, [After], [LookIn], [LookAt], [SearchOrder], [SearchDirection],
    /// [MatchCase]`: the first cell after `After` (the range's first cell when omitted), by rows
    /// or by columns (xlByRows or xlByColumns), forward (xlNext) or backward (xlPrevious),
    /// coming round from the range's other end, `After` itself searched last, whose formula or
    /// typed constant (LookIn:=xlFormulas) or shown text (xlValues) holds `What` as Replace
    /// matches it; Nothing when no cell does. Empty cells never match. "The settings for
    /// LookIn, LookAt, SearchOrder, and MatchByte are saved each time you use this method. If
    /// you don't specify values for these arguments the next time you call the method, the
    /// saved values are used" (Range.Find method), saved with Replace's ([`FindSettings`]):
    /// the run starts with the Find dialog's xlFormulas, xlPart, xlByRows. MatchCase is not
    /// among them ("The default value is False"). What, MatchCase and those settings are the
    /// conditions `FindNext` and `FindPrevious` go on with.
    pub(super) fn find_in_range(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        let what =
            self.text_argument(link, 0, "What")?.ok_or_else(|| self.fault_at(link.span, "Range.Find needs What:="))?;
        let after = self.after_argument(link, 1, rect)?;
        let saved = self.find_conditions.borrow().saved;
        let settings = FindSettings {
            by_values: self.find_setting(link, 2, "LookIn", "xlvalues", saved.by_values)?,
            whole: self.find_setting(link, 3, "LookAt", "xlwhole", saved.whole)?,
            by_columns: self.find_setting(link, 4, "SearchOrder", "xlbycolumns", saved.by_columns)?,
            ..saved
        };
        let conditions = FindConditions {
            what: Some(what),
            by_values: settings.by_values,
            whole: settings.whole,
            by_columns: settings.by_columns,
            match_case: self.flag_argument(link, 6, "MatchCase")?.unwrap_or(false),
            saved: settings,
        };
        let backward = self.find_setting(link, 5, "SearchDirection", "xlprevious", false)?;
        *self.find_conditions.borrow_mut() = conditions.clone();
        self.search_cells(ctx, sheet, rect, after, backward, &conditions, link)
    }

    /// `rng.FindNext [After]` and `rng.FindPrevious [After]` ("Range.FindNext method":
    /// "Continues a search that was begun with the Find method. Finds the next cell that matches
    /// those same conditions"): the last Find's What, LookIn, LookAt, SearchOrder and MatchCase
    /// over this range, after `After` (the range's first cell when omitted), coming round at the
    /// range's end, forward or (FindPrevious) backward. The loop of Microsoft's example stops
    /// when the address found first comes round again.
    pub(super) fn find_next_in_range(
        &self,
        ctx: &mut Ctx,
        sheet: SheetId,
        rect: Rect,
        link: &Link,
        backward: bool,
    ) -> Run<Obj> {
        let conditions = self.find_conditions.borrow().clone();
        if conditions.what.is_none() {
            let method = if backward { "FindPrevious" } else { "FindNext" };
            let why = format!("Range.{method} continues a search begun with Range.Find, and this run has made none");
            return Err(self.fault_at(link.span, why));
        }
        let after = self.after_argument(link, 0, rect)?;
        self.search_cells(ctx, sheet, rect, after, backward, &conditions, link)
    }

    /// The `After:=` cell of Find and FindNext: the first cell of the range given, or the
    /// searched range's first cell when omitted.
    fn after_argument(&self, link: &Link, position: usize, rect: Rect) -> Run<Pos> {
        match argument(link, position, "After").map(|e| self.var_of(e, true)).transpose()? {
            Some(Var::Obj(Obj::Range(_, r))) => Ok(r.first),
            None => Ok(rect.first),
            Some(_) => {
                Err(self.fault_at(link.span, format!("Range.{} After:= takes one cell of the range", link.name)))
            }
        }
    }

    /// One of Find's Xl-constant settings: whether it is `yes` (xlValues, xlWhole,
    /// xlByColumns, xlPrevious), the saved choice when the argument is left out.
    fn find_setting(&self, link: &Link, position: usize, name: &str, yes: &str, saved: bool) -> Run<bool> {
        match argument(link, position, name).map(|e| self.eval(e)).transpose()? {
            None => Ok(saved),
            Some(Value::Number(n)) => Ok(n == xl(yes)),
            Some(_) => Err(self.fault_at(link.span, format!("Range.Find {name}:= takes an Xl constant"))),
        }
    }

    /// The cell Find, FindNext or FindPrevious lands on: the nearest match past `after` in the
    /// search's order and direction, coming round from the range's other end, `after` last.
    #[allow(clippy::too_many_arguments)]
    fn search_cells(
        &self,
        ctx: &mut Ctx,
        sheet: SheetId,
        rect: Rect,
        after: Pos,
        backward: bool,
        conditions: &FindConditions,
        link: &Link,
    ) -> Run<Obj> {
        let what = conditions.what.as_deref().unwrap_or_default();
        let pattern = wildcard_pattern(what, conditions.whole, conditions.match_case);
        let pattern =
            Regex::new(&pattern).map_err(|e| self.fault_at(link.span, format!("Range.Find What:={what}: {e}")))?;
        let by_columns = conditions.by_columns;
        let key = |p: Pos| if by_columns { (p.col, p.row) } else { (p.row, p.col) };
        let used = ctx.clip_to_used(sheet, rect);
        let mut found: Option<Pos> = None;
        let better = |candidate: Pos, best: Option<Pos>| {
            // Ahead of `after` in the search's direction, the nearest first; else, coming round,
            // the farthest; `after` itself last of all.
            let rank = |p: Pos| {
                let (k, a) = (key(p), key(after));
                let ahead = if backward { k < a } else { k > a };
                let lap = if ahead {
                    0
                } else if p == after {
                    2
                } else {
                    1
                };
                (lap, if backward { (u32::MAX - k.0, u32::MAX - k.1) } else { k })
            };
            best.is_none_or(|b| rank(candidate) < rank(b))
        };
        for row in used.first.row..=used.last.row {
            for col in used.first.col..=used.last.col {
                let p = Pos::new(row, col);
                self.add_work(1);
                let text = match conditions.by_values {
                    true if self.wb.borrow().value(sheet, p) == Value::Blank => continue,
                    true => self.shown_text(ctx, sheet, p),
                    false => match self.formulas(sheet, Rect::cell(p), false) {
                        Value::Text(t) if !t.is_empty() => t.to_string(),
                        _ => continue,
                    },
                };
                self.add_work(CELL_SEARCHED);
                if !text.is_empty() && pattern.is_match(&text) && better(p, found) {
                    found = Some(p);
                }
            }
        }
        Ok(match found {
            Some(p) => Obj::Range(sheet, Rect::cell(p)),
            None => Obj::Value(Value::Blank),
        })
    }

    /// One of Replace's two-way settings (LookAt:=xlWhole or xlPart, SearchOrder:=xlByColumns
    /// or xlByRows, named as Excel spells them): whether it is the first of `(yes, no)`, the
    /// saved choice when left out; any other value is refused naming the two.
    fn xl_choice(&self, link: &Link, position: usize, name: &str, (yes, no): (&str, &str), saved: bool) -> Run<bool> {
        let (yes_n, no_n) = (xl(&yes.to_ascii_lowercase()), xl(&no.to_ascii_lowercase()));
        match argument(link, position, name).map(|e| self.eval(e)).transpose()? {
            None => Ok(saved),
            Some(Value::Number(n)) if n == yes_n || n == no_n => Ok(n == yes_n),
            Some(_) => Err(self.fault_at(link.span, format!("Range.Replace {name}:= is {yes} or {no}"))),
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
    use super::{wildcard_pattern, xl};

    /// Microsoft's "XlLookAt", "XlFindLookIn", "XlSearchOrder" and "XlSearchDirection"
    /// enumeration pages, as Replace and Find read them from the one table of constants.
    #[test]
    fn find_and_replace_read_excels_constants_from_the_one_table() {
        let got =
            ["xlwhole", "xlpart", "xlformulas", "xlvalues", "xlbyrows", "xlbycolumns", "xlnext", "xlprevious"].map(xl);
        assert_eq!(got, [1.0, 2.0, -4123.0, -4163.0, 1.0, 2.0, 1.0, 2.0]);
    }

    #[test]
    fn wildcards_become_a_pattern_and_other_characters_stand_for_themselves() {
        assert_eq!(wildcard_pattern("a*b?", false, true), "(?s)a.*b.");
        assert_eq!(wildcard_pattern("~*.~?", true, false), "(?si)^\\*\\.\\?$");
    }
}

/// What `Range.Find` was last asked for, which `FindNext` and `FindPrevious` continue, and the
/// Find dialog's settings Find and Replace save. The run starts with Excel's Find dialog:
/// xlFormulas, xlPart, xlByRows, Match case off, no search made.
#[derive(Clone, Default)]
pub(super) struct FindConditions {
    what: Option<String>,
    by_values: bool,
    whole: bool,
    by_columns: bool,
    match_case: bool,
    saved: FindSettings,
}

/// The settings of Excel's Find dialog a Find or Replace leaving them out uses and naming
/// them saves: LookIn (Find's only), LookAt, SearchOrder, and MatchCase (Replace's only),
/// as the two methods' pages list them.
#[derive(Clone, Copy, Default)]
pub(super) struct FindSettings {
    by_values: bool,
    whole: bool,
    by_columns: bool,
    match_case: bool,
}
