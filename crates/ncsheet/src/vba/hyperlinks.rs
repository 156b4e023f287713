//! Excel's hyperlinks as macros make and read them: `ws.Hyperlinks.Add Anchor, Address,
//! SubAddress, ScreenTip, TextToDisplay` ("Hyperlinks.Add method": returns the new Hyperlink),
//! `.Count`, `.Item(i)` / `(i)`, `.Delete`, For Each; `Range.Hyperlinks` (the links on its
//! cells) and `Range.ClearHyperlinks`; a Hyperlink's `Address`, `SubAddress`,
//! `TextToDisplay`, `ScreenTip`, `Range` and `Delete`. The links are part of the sheet's look
//! (`SheetLook::hyperlinks`): the run starts from the file's and leaves its own to be saved.
//!
//! A Hyperlink object names its link by an id the sheet gave it, not by its place in the
//! list, so a variable holding one still means it after another was deleted.

use crate::eval::functions::vba::errors;
use crate::eval::{Ctx, Operand, Value};
use crate::formula::address::Rect;
use crate::formula::ast::{Expr, SheetId};
use crate::workbook::Hyperlink;

use super::ast::Link;
use super::interp::{Interp, Run};
use super::objects::lower;
use super::sheet_ops::{argument, intersect};
use super::value::{print_text, Obj, Var};

impl Interp<'_, '_> {
    /// `ws.Hyperlinks` or `r.Hyperlinks` (the links on `within`'s cells), or with `(i)` its item.
    pub(super) fn hyperlinks(&self, ctx: &mut Ctx, sheet: SheetId, within: Rect, link: &Link) -> Run<Obj> {
        match link.args {
            Some(_) => self.hyperlink_item(ctx, sheet, within, link),
            None => Ok(Obj::Hyperlinks(sheet, within)),
        }
    }

    /// The ids of the links on `within`, in the order they were made.
    fn links_within(&self, sheet: SheetId, within: Rect) -> Vec<u32> {
        let mut looks = self.looks.borrow_mut();
        let state = looks.sheet(sheet);
        state.hyperlinks.iter().filter(|(_, l)| meets(l.anchor, within)).map(|(id, _)| *id).collect()
    }

    /// The link `id` of `sheet`, or run-time error 424 when it was deleted.
    fn hyperlink(&self, sheet: SheetId, id: u32, link: &Link) -> Run<Hyperlink> {
        let found =
            self.looks.borrow_mut().sheet(sheet).hyperlinks.iter().find(|(i, _)| *i == id).map(|(_, l)| l.clone());
        found.ok_or_else(|| {
            let mut fault =
                self.fault_at(link.span, errors::message(424, "the Hyperlink was deleted (Delete or its cells)"));
            fault.code = 424;
            fault
        })
    }

    /// For Each over a Hyperlinks collection.
    pub(super) fn hyperlinks_each(&self, sheet: SheetId, within: Rect) -> Vec<Var> {
        self.links_within(sheet, within).into_iter().map(|id| Var::Obj(Obj::Hyperlink(sheet, id))).collect()
    }

    /// `Hyperlinks(i)`, `Hyperlinks.Item(i)`: the i-th link, counted from 1 (error 9 past them).
    fn hyperlink_item(&self, ctx: &mut Ctx, sheet: SheetId, within: Rect, link: &Link) -> Run<Obj> {
        let ids = self.links_within(sheet, within);
        let index = match self.numbers(ctx, link)?.as_slice() {
            [i] => *i,
            _ => return Err(self.fault_at(link.span, "Hyperlinks(index): one number, counted from 1")),
        };
        let at = index.round();
        if at < 1.0 || at > ids.len() as f64 {
            let why = format!("there are {} hyperlink(s), not a hyperlink {index}", ids.len());
            let mut fault = self.fault_at(link.span, errors::message(9, why));
            fault.code = 9;
            return Err(fault);
        }
        Ok(Obj::Hyperlink(sheet, ids[at as usize - 1]))
    }

    /// The members of a Hyperlinks collection.
    pub(super) fn hyperlinks_member(&self, ctx: &mut Ctx, sheet: SheetId, within: Rect, link: &Link) -> Run<Obj> {
        match lower(link).as_str() {
            "count" => Ok(Obj::Value(Value::Number(self.links_within(sheet, within).len() as f64))),
            "item" => self.hyperlink_item(ctx, sheet, within, link),
            "add" => self.add_hyperlink(ctx, link),
            "delete" => Ok(self.delete_hyperlinks(sheet, within)),
            _ => self.unmodelled(&Obj::Hyperlinks(sheet, within), link),
        }
    }

    /// `Hyperlinks.Delete`, `Range.ClearHyperlinks`: the links on `within` go; the cells keep
    /// the text they show.
    pub(super) fn delete_hyperlinks(&self, sheet: SheetId, within: Rect) -> Obj {
        self.looks.borrow_mut().sheet(sheet).hyperlinks.retain(|(_, l)| !meets(l.anchor, within));
        Obj::Value(Value::Blank)
    }

    /// `Hyperlinks.Add Anchor, Address, SubAddress, ScreenTip, TextToDisplay`: the link goes on
    /// the anchor's cells, in place of one they had (a cell has one hyperlink); the anchor's
    /// first cell shows TextToDisplay, or, when it was empty, the address the link leads to.
    fn add_hyperlink(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let Some(anchor) = argument(link, 0, "anchor") else {
            return Err(self.fault_at(link.span, "Hyperlinks.Add needs its Anchor, the range the link is on"));
        };
        let operand = ctx.operand(anchor);
        self.take_pending()?;
        let Operand::Ref(sheet, cells) = operand else {
            return Err(self.unsupported(link.span, "Hyperlinks.Add: the Anchor is a range (ncsheet has no shapes)"));
        };
        let Some(address) = argument(link, 1, "address") else {
            return Err(self.fault_at(link.span, "Hyperlinks.Add needs its Address (\"\" for a place in the workbook)"));
        };
        let address = self.link_text(address)?;
        let sub_address = match argument(link, 2, "subaddress") {
            Some(e) => self.link_text(e)?,
            None => String::new(),
        };
        let tip = argument(link, 3, "screentip").map(|e| self.link_text(e)).transpose()?;
        let text = argument(link, 4, "texttodisplay").map(|e| self.link_text(e)).transpose()?;
        let cell_empty = ctx.rect_value(sheet, Rect::cell(cells.first)).is_blank();
        let shown = match &text {
            Some(t) => Some(t.clone()),
            None if cell_empty => Some(if address.is_empty() { sub_address.clone() } else { address.clone() }),
            None => None,
        };
        if let Some(shown) = shown {
            self.write_range(sheet, Rect::cell(cells.first), &Value::text(shown))?;
        }
        let made = Hyperlink { anchor: cells, address, sub_address, text, tip };
        let mut looks = self.looks.borrow_mut();
        let state = looks.sheet(sheet);
        state.hyperlinks.retain(|(_, l)| !meets(l.anchor, cells));
        let id = state.next_link_id();
        state.hyperlinks.push((id, made));
        Ok(Obj::Hyperlink(sheet, id))
    }

    fn link_text(&self, e: &Expr) -> Run<String> {
        Ok(print_text(&self.eval(e)?))
    }

    /// The members of one Hyperlink.
    pub(super) fn hyperlink_member(&self, ctx: &mut Ctx, sheet: SheetId, id: u32, link: &Link) -> Run<Obj> {
        let hyperlink = self.hyperlink(sheet, id, link)?;
        let text = |t: &str| Ok(Obj::Value(Value::text(t)));
        match lower(link).as_str() {
            "address" => text(&hyperlink.address),
            "subaddress" => text(&hyperlink.sub_address),
            "screentip" => text(hyperlink.tip.as_deref().unwrap_or("")),
            // The text the anchor shows ("Hyperlink.TextToDisplay property").
            "texttodisplay" => match &hyperlink.text {
                Some(t) => text(t),
                None => text(&self.shown_text(ctx, sheet, hyperlink.anchor.first)),
            },
            // "Hyperlink.Name property": the link's address, or its subaddress within the book.
            "name" if hyperlink.address.is_empty() => text(&hyperlink.sub_address),
            "name" => text(&hyperlink.address),
            "range" => Ok(Obj::Range(sheet, hyperlink.anchor)),
            "parent" => Ok(Obj::Sheet(sheet)),
            "delete" => {
                self.looks.borrow_mut().sheet(sheet).hyperlinks.retain(|(i, _)| *i != id);
                Ok(Obj::Value(Value::Blank))
            }
            "follow" => Err(self.unsupported(
                link.span,
                "Hyperlink.Follow: a macro runs without a browser or a window, so no link is opened",
            )),
            _ => self.unmodelled(&Obj::Hyperlink(sheet, id), link),
        }
    }

    /// `h.Address = …`, `h.SubAddress`, `h.ScreenTip`, `h.TextToDisplay` (which the anchor's
    /// first cell then shows).
    pub(super) fn set_hyperlink_member(&self, sheet: SheetId, id: u32, link: &Link, value: &Expr) -> Run<()> {
        let mut hyperlink = self.hyperlink(sheet, id, link)?;
        let new = self.link_text(value)?;
        match lower(link).as_str() {
            "address" => hyperlink.address = new,
            "subaddress" => hyperlink.sub_address = new,
            "screentip" => hyperlink.tip = Some(new),
            "texttodisplay" => {
                self.write_range(sheet, Rect::cell(hyperlink.anchor.first), &Value::text(new.clone()))?;
                hyperlink.text = Some(new);
            }
            _ => return Err(self.fault_at(link.span, format!("a Hyperlink's {} cannot be set", link.name))),
        }
        let mut looks = self.looks.borrow_mut();
        if let Some(slot) = looks.sheet(sheet).hyperlinks.iter_mut().find(|(i, _)| *i == id) {
            slot.1 = hyperlink;
        }
        Ok(())
    }
}

/// Whether two rectangles share a cell.
fn meets(a: Rect, b: Rect) -> bool {
    intersect(a, b).is_some()
}
