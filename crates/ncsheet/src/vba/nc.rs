//! The `Nc` object: ncsheet's NC program under construction, filled by a macro.
//!
//! `Nc` (an ncsheet object, not VBA's): `Nc.Rapid x, z`, `Nc.Line x, z [, f]`,
//! `Nc.ArcCW x, z, cx, cz [, f]` / `Nc.ArcCCW` (centre absolute, written like a point),
//! `Nc.Dwell seconds`, `Nc.Comment text`, `Nc.Block "G1", "X", x, …`; on a mill the points are
//! `x, y, z` (arcs `x, y, cx, cy`). Any coordinate may be named (`Z:=-2`) or left out
//! (`Nc.Line , -10` keeps X). Properties: `Nc.Feed` (modal, written when it changes),
//! `Nc.Machine` ("lathe" or "mill"), `Nc.Name`, `Nc.Number`, `Nc.Dialect` (read only),
//! `Nc.Count` (blocks so far). On a lathe X is a diameter, as everywhere in ncsheet.
//!
//! The machine's state: `Nc.FeedPerRev [f]` / `Nc.FeedPerMin [f]` (what F means from here on;
//! a lathe program must say it before its first cut), `Nc.Spindle 800` (M3), `Nc.Spindle 800,
//! "ccw"` (M4), `Nc.Spindle 0` (stop), `Nc.Spindle Vc:=180, Limit:=2500` (constant surface
//! speed on a lathe: m/min, and the spindle limit in 1/min), `Nc.Tool 3`, `Nc.Coolant True`.
//!
//! A cycle the NC31 may run as a subprogram (docs/domain.md §2, "Calls with values"):
//! `Nc.Subprogram "L16 XR1 WR2", "N1 …", …, "N9 M17"` gives its header and blocks as the
//! control reads them; `Nc.Cycle "L16", x, w` … `Nc.EndCycle` around the blocks a use of it
//! emits marks them as that use, with the values of its header's letters in order. The blocks
//! are emitted as ever; only `run --subprograms` writes the use as a call (and checks that the
//! subprogram does what the blocks do). A subprogram may call another (`N4 L03`), which is
//! written with it. `Nc.ChordsCW(x0, z0, x, z, cx, cz)` (and `Nc.ChordsCCW`) gives the ends of
//! the lines an arc becomes on a control without circular interpolation, at the run's
//! `--arc-tol`, for a subprogram that cuts the arc as the program's own arc blocks are cut.

use crate::eval::coerce::to_bool;
use crate::eval::{Ctx, Value};
use crate::formula::ast::{Expr, ExprKind};
use crate::nc::dialect::arc_as_lines;
use crate::nc::program::DEFAULT_ARC_TOLERANCE;
use crate::nc::{
    ArcDirection, Block, FeedMode, Machine, Spindle, SpindleDirection, Subprogram, SubprogramCall, Target, ToolChange,
    ToolOffset, Word,
};

use super::ast::{Link, Span};
use super::interp::{Interp, Run};
use super::objects::lower;
use super::value::{input_text, print_text, Obj};

/// The modal state of the program being emitted.
#[derive(Debug, Default)]
pub struct NcState {
    /// The feed the next cut uses (`Nc.Feed = 0.1` or `F:=` on a cut).
    feed: Option<f64>,
    /// The feed last written into a block: a cut writes F only when it changes.
    written: Option<f64>,
    /// The use of a subprogram `Nc.Cycle` opened, as its index in the program's calls.
    open_cycle: Option<usize>,
}

impl Interp<'_, '_> {
    fn machine(&self) -> Machine {
        self.out.borrow().program.machine
    }

    pub(super) fn nc_member(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let name = lower(link);
        // `Nc.Feed 0.1`, a statement as a VBA user writes it, sets the feed as `Nc.Feed = 0.1`.
        if let (Some([arg]), "feed") = (link.args.as_deref(), name.as_str()) {
            self.set_nc("feed", &arg.value, link.span)?;
            return Ok(Obj::Value(Value::Blank));
        }
        let out = self.out.borrow();
        let property = match name.as_str() {
            "name" => Some(Value::text(out.program.name.clone())),
            "number" => Some(Value::Number(out.program.number.unwrap_or(0) as f64)),
            "machine" => Some(Value::text(if out.program.machine == Machine::Lathe { "lathe" } else { "mill" })),
            "feed" => Some(self.nc.borrow().feed.map_or(Value::Blank, Value::Number)),
            "dialect" => Some(Value::text(self.options.dialect.map_or("", |d| d.name()))),
            "count" => Some(Value::Number(out.program.blocks.len() as f64)),
            _ => None,
        };
        drop(out);
        if let Some(v) = property {
            return Ok(Obj::Value(v));
        }
        if name == "chordscw" || name == "chordsccw" {
            return self.chords(ctx, link, name == "chordscw").map(Obj::Value);
        }
        let marked = match name.as_str() {
            "subprogram" => Some(self.subprogram(ctx, link)),
            "cycle" => Some(self.cycle(ctx, link)),
            "endcycle" => Some(self.end_cycle(link)),
            _ => None,
        };
        if let Some(done) = marked {
            return done.map(|()| Obj::Value(Value::Blank));
        }
        let block = match name.as_str() {
            "rapid" => {
                let a = self.nc_args(ctx, link, &self.axes(&[]))?;
                Block::Rapid(self.target(&a, link)?)
            }
            "line" => {
                let a = self.nc_args(ctx, link, &self.axes(&["f"]))?;
                let to = self.target(&a, link)?;
                Block::Line { to, feed: self.feed(get(&a, "f"), link)? }
            }
            "arccw" | "arcccw" => self.arc(ctx, link, name == "arccw")?,
            "dwell" => match self.numbers(ctx, link)?.as_slice() {
                [s] if *s >= 0.0 => Block::Dwell(*s),
                _ => return Err(self.fault_at(link.span, "Nc.Dwell takes the seconds to wait")),
            },
            "comment" => {
                let values = self.values(ctx, link)?;
                Block::Comment(values.iter().map(print_text).collect::<Vec<_>>().join(" "))
            }
            "block" => Block::Words(self.words(ctx, link)?),
            "feedperrev" | "feedpermin" => {
                let mode = if name == "feedperrev" { FeedMode::PerRevolution } else { FeedMode::PerMinute };
                match self.numbers(ctx, link)?.as_slice() {
                    [] => {}
                    [f] if *f > 0.0 && f.is_finite() => self.nc.borrow_mut().feed = Some(*f),
                    _ => return Err(self.fault_at(link.span, format!("Nc.{} takes the feed, above 0", link.name))),
                }
                // F means something else now: the next cut writes it again.
                self.nc.borrow_mut().written = None;
                Block::FeedMode(mode)
            }
            "spindle" => Block::Spindle(self.spindle(ctx, link)?),
            "tool" => Block::Tool(self.tool(ctx, link)?),
            "coolant" => match self.values(ctx, link)?.as_slice() {
                [v] => {
                    Block::Coolant(to_bool(v).map_err(|_| self.fault_at(link.span, "Nc.Coolant takes True or False"))?)
                }
                _ => return Err(self.fault_at(link.span, "Nc.Coolant takes True or False")),
            },
            _ => return Err(self.no_member(&Obj::Nc, link)),
        };
        self.out.borrow_mut().program.push(block);
        Ok(Obj::Value(Value::Blank))
    }

    /// `Nc.Subprogram "L16 XR1 WR2 …", "N1 …", …`: the header, then the blocks (an argument
    /// may hold several, one a line). Given again, it must be the same.
    fn subprogram(&self, ctx: &mut Ctx, link: &Link) -> Run<()> {
        let values = self.values(ctx, link)?;
        let fault = |m: String| self.fault_at(link.span, format!("Nc.Subprogram: {m}"));
        let mut lines: Vec<String> = Vec::new();
        for v in &values {
            let Value::Text(t) = v else {
                return Err(fault(format!("{} is not the text of a block", print_text(v))));
            };
            lines.extend(t.lines().map(|l| l.trim().to_string()).filter(|l| !l.is_empty()));
        }
        if lines.len() < 2 {
            return Err(fault("it takes the header (\"L16 XR1 WR2\") and the blocks, the last with M17".into()));
        }
        let header = lines.remove(0);
        let subprogram = Subprogram::new(&header, lines).map_err(fault)?;
        let mut out = self.out.borrow_mut();
        let subprograms = &mut out.program.subprograms;
        match subprograms.iter().find(|s| s.number == subprogram.number) {
            Some(s) if *s == subprogram => {}
            Some(_) => return Err(fault(format!("L{:02} is given twice, differently", subprogram.number))),
            None => subprograms.push(subprogram),
        }
        Ok(())
    }

    /// `Nc.Cycle "L16", x, w, …`: the blocks emitted until `Nc.EndCycle` are a use of L16
    /// with these values for its header's letters, in their order.
    fn cycle(&self, ctx: &mut Ctx, link: &Link) -> Run<()> {
        let values = self.values(ctx, link)?;
        let fault = |m: String| self.fault_at(link.span, format!("Nc.Cycle: {m}"));
        let name = values.first().map(print_text).unwrap_or_default();
        let number = name
            .trim()
            .strip_prefix(['L', 'l'])
            .and_then(|d| d.parse::<u32>().ok())
            .ok_or_else(|| fault(format!("\"{name}\" is not a subprogram's name (\"L16\")")))?;
        let numbers = values[1..]
            .iter()
            .map(|v| {
                self.number_of(v, &format!("Nc.Cycle: a value of L{number:02}"))
                    .map_err(|m| self.fault_at(link.span, m))
            })
            .collect::<Run<Vec<f64>>>()?;
        let mut out = self.out.borrow_mut();
        let Some(subprogram) = out.program.subprograms.iter().find(|s| s.number == number) else {
            return Err(fault(format!("L{number:02} has no Nc.Subprogram before it")));
        };
        if subprogram.parameters.len() != numbers.len() {
            let letters: Vec<String> = subprogram.parameters.iter().map(|(l, _)| l.to_string()).collect();
            return Err(fault(format!(
                "L{number:02} takes {} values ({}), not {}",
                letters.len(),
                letters.join(" "),
                numbers.len()
            )));
        }
        let mut nc = self.nc.borrow_mut();
        if let Some(open) = nc.open_cycle {
            let inside = out.program.calls[open].number;
            return Err(fault(format!("inside the use of L{inside:02}: close it with Nc.EndCycle first")));
        }
        let first = out.program.blocks.len();
        nc.open_cycle = Some(out.program.calls.len());
        out.program.calls.push(SubprogramCall { number, values: numbers, first, end: None });
        Ok(())
    }

    fn end_cycle(&self, link: &Link) -> Run<()> {
        if link.args.as_ref().is_some_and(|a| !a.is_empty()) {
            return Err(self.fault_at(link.span, "Nc.EndCycle takes no arguments"));
        }
        let open = self.nc.borrow_mut().open_cycle.take();
        let Some(open) = open else {
            return Err(self.fault_at(link.span, "Nc.EndCycle without an Nc.Cycle before it"));
        };
        let mut out = self.out.borrow_mut();
        let end = out.program.blocks.len();
        out.program.calls[open].end = Some(end);
        Ok(())
    }

    /// `Nc.Spindle S [, Dir]`, `Nc.Spindle Vc:=…, Limit:=… [, Dir:=…]`; S 0 stops it.
    fn spindle(&self, ctx: &mut Ctx, link: &Link) -> Run<Spindle> {
        const NAMES: [&str; 4] = ["s", "dir", "vc", "limit"];
        let usage = "Nc.Spindle takes S (1/min) and Dir (\"cw\" or \"ccw\"), or Vc:= (m/min) and Limit:= (1/min)";
        let mut got: Vec<(&str, Value)> = Vec::new();
        for (i, a) in link.args.as_deref().unwrap_or(&[]).iter().enumerate() {
            let key = match &a.name {
                Some(n) => NAMES.iter().find(|k| k.eq_ignore_ascii_case(n)).copied(),
                None => NAMES.get(i).copied().filter(|_| i < 2),
            };
            let Some(key) = key else { return Err(self.fault_at(link.span, usage)) };
            if a.value.kind == ExprKind::Missing {
                continue;
            }
            let v = ctx.eval(&a.value).unwrap_single();
            self.take_pending()?;
            got.push((key, v));
        }
        let find = |k: &str| got.iter().find(|(n, _)| *n == k).map(|(_, v)| v);
        let number = |k: &str| -> Run<Option<f64>> {
            find(k)
                .map(|v| self.number_of(v, &format!("Nc.Spindle: {}", k.to_uppercase())))
                .transpose()
                .map_err(|m| self.fault_at(link.span, m))
        };
        let direction = match find("dir").map(print_text).map(|t| t.to_ascii_lowercase()) {
            None => SpindleDirection::Clockwise,
            Some(t) if t == "cw" || t == "m3" => SpindleDirection::Clockwise,
            Some(t) if t == "ccw" || t == "m4" => SpindleDirection::CounterClockwise,
            Some(t) => {
                return Err(self.fault_at(link.span, format!("Nc.Spindle: Dir is \"cw\" or \"ccw\", not \"{t}\"")))
            }
        };
        match (number("s")?, number("vc")?, number("limit")?) {
            (Some(0.0), None, None) => Ok(Spindle::Stop),
            (Some(rpm), None, None) if rpm > 0.0 => Ok(Spindle::Rpm { rpm, direction }),
            (None, Some(v), Some(max)) if v > 0.0 && max > 0.0 => {
                Ok(Spindle::SurfaceSpeed { metres_per_min: v, max_rpm: max, direction })
            }
            _ => Err(self.fault_at(link.span, usage)),
        }
    }

    /// `Nc.Tool N [, Offset]`: tool N with its own offset, or `Offset:=` another register
    /// (1–99: G43 H, Sinumerik D, a Fanuc lathe's T0102), or 0 for none (G49, D0, T0100).
    fn tool(&self, ctx: &mut Ctx, link: &Link) -> Run<ToolChange> {
        let usage = "Nc.Tool takes a tool number from 1 to 99";
        let bad_offset = "Nc.Tool: Offset is an offset number from 1 to 99, or 0 for none";
        let a = self.nc_args(ctx, link, &["tool", "offset"])?;
        let whole = |v: f64, from: f64| (from..=99.0).contains(&v) && v.fract() == 0.0;
        if a.iter().any(|(k, _)| k != "tool" && k != "offset") {
            return Err(self.fault_at(link.span, usage));
        }
        let number = match get(&a, "tool") {
            Some(n) if whole(n, 1.0) => n as u32,
            _ => return Err(self.fault_at(link.span, usage)),
        };
        let offset = match get(&a, "offset") {
            None => ToolOffset::Own,
            Some(0.0) => ToolOffset::Cancelled,
            Some(o) if whole(o, 1.0) => ToolOffset::Number(o as u32),
            Some(_) => return Err(self.fault_at(link.span, bad_offset)),
        };
        Ok(ToolChange { number, offset })
    }

    /// The point parameters of the machine: X Z on a lathe, X Y Z on a mill.
    fn axes(&self, extra: &[&'static str]) -> Vec<&'static str> {
        let mut names = match self.machine() {
            Machine::Lathe => vec!["x", "z"],
            Machine::Mill => vec!["x", "y", "z"],
        };
        names.extend_from_slice(extra);
        names
    }

    /// Numeric arguments by parameter name: positional in `names` order, or named (`Z:=`);
    /// the rotary axes A B C may only be named. Empty ones are left out.
    fn nc_args(&self, ctx: &mut Ctx, link: &Link, names: &[&'static str]) -> Run<Vec<(String, f64)>> {
        let mut out: Vec<(String, f64)> = Vec::new();
        let all: Vec<&str> = names.iter().copied().chain(["x", "y", "z", "a", "b", "c"]).collect();
        for (i, a) in link.args.as_deref().unwrap_or(&[]).iter().enumerate() {
            let key = match &a.name {
                Some(n) if all.contains(&n.to_ascii_lowercase().as_str()) => n.to_ascii_lowercase(),
                Some(n) => {
                    let list = names.join(", ").to_uppercase();
                    return Err(
                        self.fault_at(link.span, format!("Nc.{} has no argument {n} (it takes {list})", link.name))
                    );
                }
                None if i < names.len() => names[i].to_string(),
                None => {
                    let list = names.join(", ").to_uppercase();
                    return Err(self.fault_at(link.span, format!("Nc.{} takes {list}", link.name)));
                }
            };
            if a.value.kind == ExprKind::Missing {
                continue;
            }
            let v = ctx.eval(&a.value).unwrap_single();
            self.take_pending()?;
            let what = format!("Nc.{}: {}", link.name, key.to_uppercase());
            let n = self.number_of(&v, &what).map_err(|m| self.fault_at(self.expr_span(&a.value), m))?;
            if out.iter().any(|(k, _)| *k == key) {
                return Err(
                    self.fault_at(link.span, format!("Nc.{}: {} is given twice", link.name, key.to_uppercase()))
                );
            }
            out.push((key, n));
        }
        Ok(out)
    }

    fn target(&self, a: &[(String, f64)], link: &Link) -> Run<Target> {
        let t =
            Target { x: get(a, "x"), y: get(a, "y"), z: get(a, "z"), a: get(a, "a"), b: get(a, "b"), c: get(a, "c") };
        if t.axes().next().is_none() {
            return Err(self.fault_at(link.span, format!("Nc.{} needs a point to move to", link.name)));
        }
        Ok(t)
    }

    /// The feed of a cut: given, else the modal one; written only when it changes.
    fn feed(&self, given: Option<f64>, link: &Link) -> Run<Option<f64>> {
        let mut nc = self.nc.borrow_mut();
        if let Some(f) = given {
            if f <= 0.0 {
                return Err(self.fault_at(link.span, format!("Nc.{}: the feed must be above 0", link.name)));
            }
            nc.feed = Some(f);
        }
        let Some(feed) = nc.feed else {
            return Err(
                self.fault_at(link.span, format!("Nc.{} needs a feed: pass F:= or set Nc.Feed first", link.name))
            );
        };
        if nc.written == Some(feed) {
            return Ok(None);
        }
        nc.written = Some(feed);
        Ok(Some(feed))
    }

    fn arc(&self, ctx: &mut Ctx, link: &Link, clockwise: bool) -> Run<Block> {
        let names: &[&'static str] = match self.machine() {
            Machine::Lathe => &["x", "z", "cx", "cz", "f"],
            Machine::Mill => &["x", "y", "cx", "cy", "f", "z", "cz"],
        };
        let a = self.nc_args(ctx, link, names)?;
        let to = self.target(&a, link)?;
        let centre = Target { x: get(&a, "cx"), y: get(&a, "cy"), z: get(&a, "cz"), ..Target::default() };
        let in_plane = match self.machine() {
            Machine::Lathe => centre.x.is_some() && centre.z.is_some(),
            Machine::Mill => centre.x.is_some() && centre.y.is_some(),
        };
        if !in_plane {
            return Err(self
                .fault_at(link.span, format!("Nc.{} needs the centre (CX and C{})", link.name, self.plane_second())));
        }
        let direction = if clockwise { ArcDirection::Clockwise } else { ArcDirection::CounterClockwise };
        Ok(Block::Arc { direction, to, centre, feed: self.feed(get(&a, "f"), link)? })
    }

    /// `Nc.ChordsCW(x0, z0, x, z, cx, cz)` (a mill's `x0, y0, x, y, cx, cy`): the ends of the
    /// lines the program's writer puts for that arc on a control without circular
    /// interpolation, at the run's `--arc-tol` and as its words write them, as one array
    /// `x1, z1, x2, z2, …`. A subprogram that cuts the arc (the NC31 has no G2) is written
    /// with them and cuts what the program's own arc blocks become.
    fn chords(&self, ctx: &mut Ctx, link: &Link, clockwise: bool) -> Run<Value> {
        let second = self.plane_second();
        let usage =
            format!("Nc.{} takes the start X, {second}, the end X, {second} and the centre X, {second}", link.name);
        let [x0, v0, x, v, cx, cv] =
            <[f64; 6]>::try_from(self.numbers(ctx, link)?).map_err(|_| self.fault_at(link.span, usage.clone()))?;
        let machine = self.machine();
        let point = |x: f64, v: f64| match machine {
            Machine::Lathe => Target::xz(x, v),
            Machine::Mill => Target { x: Some(x), y: Some(v), ..Target::default() },
        };
        let program = &self.out.borrow().program;
        let resolution = match program.precision {
            Some(decimals) => 10f64.powi(-(decimals as i32)),
            None => self.options.dialect.map_or(0.001, |d| d.resolution()),
        };
        let tolerance = self.options.arc_tolerance.unwrap_or(DEFAULT_ARC_TOLERANCE);
        let direction = if clockwise { ArcDirection::Clockwise } else { ArcDirection::CounterClockwise };
        let ends =
            arc_as_lines(machine, &point(x0, v0), &point(x, v), &point(cx, cv), direction, tolerance, resolution)
                .map_err(|m| {
                    let why = format!("the lines keep within --arc-tol ({tolerance} mm) less the control's step");
                    self.fault_at(link.span, format!("Nc.{}: {m} ({why}, {resolution} mm)", link.name))
                })?;
        let written = |v: Option<f64>| Value::Number((v.unwrap_or(0.0) / resolution).round() * resolution);
        let items = ends
            .iter()
            .flat_map(|p| match machine {
                Machine::Lathe => [written(p.x), written(p.z)],
                Machine::Mill => [written(p.x), written(p.y)],
            })
            .collect();
        Ok(Value::Array(std::rc::Rc::new(crate::eval::Array::row(items))))
    }

    fn plane_second(&self) -> char {
        if self.machine() == Machine::Lathe {
            'Z'
        } else {
            'Y'
        }
    }

    /// `Nc.Block "G1", "X", x, "Z", z` or `Nc.Block "G1 X10 Z-2"`: words of letters and numbers.
    fn words(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<Word>> {
        let values = self.values(ctx, link)?;
        let bad = |m: String| self.fault_at(link.span, format!("Nc.Block: {m}"));
        let mut words = Vec::new();
        let mut letter: Option<char> = None;
        for v in &values {
            if let Value::Text(t) = v {
                for token in t.split_whitespace() {
                    // `Nc.Block "T", "0101"`: the number of a letter given before, as typed.
                    if let Some(l) = letter.take() {
                        let n = typed_number(token).ok_or_else(|| bad(format!("{l} needs a number after it")))?;
                        words.push(Word::typed(l, n, token));
                        continue;
                    }
                    let mut chars = token.chars();
                    let first = chars.next().expect("a token").to_ascii_uppercase();
                    if !first.is_ascii_alphabetic() {
                        return Err(bad(format!("\"{token}\" does not start with an address letter")));
                    }
                    let rest = chars.as_str();
                    if rest.is_empty() {
                        letter = Some(first);
                        continue;
                    }
                    let n =
                        typed_number(rest).ok_or_else(|| bad(format!("\"{token}\" is not a letter and a number")))?;
                    words.push(Word::typed(first, n, rest));
                }
                continue;
            }
            let Some(l) = letter.take() else {
                return Err(bad(format!("{} has no address letter before it", print_text(v))));
            };
            let n = self.number_of(v, &format!("Nc.Block: {l}")).map_err(|m| self.fault_at(link.span, m))?;
            words.push(Word::new(l, n));
        }
        if let Some(l) = letter {
            return Err(bad(format!("{l} needs a number after it")));
        }
        if words.is_empty() {
            return Err(bad("no words".into()));
        }
        Ok(words)
    }

    pub(super) fn set_nc(&self, name: &str, value: &Expr, span: Span) -> Run<()> {
        let v = self.eval(value)?;
        let text = || input_text(&v);
        match name {
            "feed" => {
                let f = self.number_of(&v, "Nc.Feed").map_err(|m| self.fault_at(span, m))?;
                if f <= 0.0 {
                    return Err(self.fault_at(span, "Nc.Feed must be above 0"));
                }
                self.nc.borrow_mut().feed = Some(f);
            }
            "name" => self.out.borrow_mut().program.name = text(),
            "number" => {
                let n = self.number_of(&v, "Nc.Number").map_err(|m| self.fault_at(span, m))?;
                if !(0.0..=99_999_999.0).contains(&n) || n.fract() != 0.0 {
                    return Err(self.fault_at(span, "Nc.Number is a whole number from 0"));
                }
                self.out.borrow_mut().program.number = Some(n as u32);
            }
            "machine" => {
                let machine = match text().to_ascii_lowercase().as_str() {
                    "lathe" => Machine::Lathe,
                    "mill" => Machine::Mill,
                    other => {
                        return Err(self.fault_at(span, format!("Nc.Machine is \"lathe\" or \"mill\", not \"{other}\"")))
                    }
                };
                self.out.borrow_mut().program.machine = machine;
            }
            _ => return Err(self.fault_at(span, format!("Nc.{name} cannot be assigned"))),
        }
        Ok(())
    }
}

/// The number of a word's text (`0101`, `-2.5`), finite.
fn typed_number(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().filter(|n| n.is_finite())
}

fn get(args: &[(String, f64)], key: &str) -> Option<f64> {
    args.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
}
