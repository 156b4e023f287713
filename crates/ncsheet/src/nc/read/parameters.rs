//! LinuxCNC's parameters and expressions, as its interpreter reads them (LinuxCNC's G-code
//! overview, "Parameters" and "Expressions"; rs274ngc is the check): `#1 = 10`, `#<depth> = 2`,
//! `X[#1 * 2]`, `Z-#<depth>`, `Y[ATAN[#2]/[#3]]`. A word's value is a number, a bracketed
//! expression, a parameter or a function of a bracketed expression, each with an optional
//! sign. Inside brackets `**` binds first, then `* / MOD`, then `+ -`, then `EQ NE GT GE LT
//! LE`, then `AND OR XOR`, each from left to right; a sign belongs to the value it stands
//! before (`-2**2` is 4). Angles are degrees. A line's settings take effect after the whole
//! line is read (`#1=2 G0 X#1` moves to the old #1).
//!
//! Numbered parameters #1–#5000 are the program's: one it has not set reads 0, as on a control
//! just started. #5001–#5601 hold the control's state (probe results, homes, work offsets, the
//! tool, the position): read before the program sets one, or set when it changes a work
//! offset or the tool, they are refused by name rather than taken as 0. A named parameter
//! must be set before it is read, except LinuxCNC's predefined ones (`#<_x>`, `#<_feed>` …:
//! [`predefined`]), which are read-only.

use std::collections::HashMap;

use super::predefined::{self, Control};
use super::{quoted_briefly, Fail};

/// The deepest nesting of brackets and functions one value may have: the reader descends
/// once per level, and a line of a million `[` must be refused, not overflow the stack.
pub const MAX_NESTING: usize = 100;

/// LinuxCNC's highest parameter number (rs274ngc refuses #5602).
const LAST_NUMBERED: u32 = 5601;

/// The last parameter number that is the program's own (#31–#5000 "G-code user parameters").
const LAST_USER: u32 = 5000;

/// From this number on, setting a parameter changes the control's state (probe, G28/G30
/// homes, G92 and work offsets, the tool, the position).
const FIRST_STATE: u32 = 5061;

/// LinuxCNC's tolerance of EQ and NE.
const EQUAL_WITHIN: f64 = 0.0001;

/// How close to a whole number a parameter's number must be (rs274ngc's "Non integer value
/// for integer").
const WHOLE_WITHIN: f64 = 0.0001;

/// A parameter, as a line names it: `#12` or `#<name>` (spaces dropped, lower case).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Name {
    Numbered(u32),
    Named(String),
}

impl std::fmt::Display for Name {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Name::Numbered(n) => write!(f, "#{n}"),
            Name::Named(name) => write!(f, "#<{name}>"),
        }
    }
}

/// The parameters a program has set so far.
#[derive(Default)]
pub struct Parameters {
    values: HashMap<Name, f64>,
    /// The control's state the predefined parameters (`#<_x>`, `#<_feed>` …) read.
    pub(super) control: Control,
}

/// One `#… = value` of a line, applied once the line is read.
pub struct Setting {
    pub name: Name,
    pub value: f64,
}

/// What a subroutine call hides of its caller's parameters: #1–#30 and the named ones not
/// starting with `_` (LinuxCNC's locals), given back when it returns.
pub struct Hidden(Vec<(Name, f64)>);

/// The numbered parameters a subroutine call sets from its values.
const CALL_VALUES: u32 = 30;

fn is_local(name: &Name) -> bool {
    match name {
        Name::Numbered(n) => *n <= CALL_VALUES,
        Name::Named(s) => !s.starts_with('_'),
    }
}

impl Parameters {
    /// Enters a subroutine called with `values`: the caller's locals are hidden, #1… hold the
    /// values.
    pub fn enter_call(&mut self, values: &[f64]) -> Hidden {
        let locals: Vec<Name> = self.values.keys().filter(|n| is_local(n)).cloned().collect();
        let hidden = locals.into_iter().filter_map(|n| self.values.remove_entry(&n)).collect();
        for (n, v) in (1..).zip(values) {
            self.values.insert(Name::Numbered(n), *v);
        }
        Hidden(hidden)
    }

    /// Leaves a subroutine: its locals go, the caller's come back, and a returned value is
    /// `#<_value>` (`#<_value_returned>` says whether one was).
    pub fn leave_call(&mut self, hidden: Hidden, returned: Option<f64>) {
        self.values.retain(|n, _| !is_local(n));
        self.values.extend(hidden.0);
        self.values.insert(Name::Named("_value".into()), returned.unwrap_or(0.0));
        self.values.insert(Name::Named("_value_returned".into()), if returned.is_some() { 1.0 } else { 0.0 });
    }

    /// Applies a line's settings, in the order written.
    pub fn apply(&mut self, settings: Vec<Setting>) {
        for s in settings {
            self.values.insert(s.name, s.value);
        }
    }

    fn value(&self, name: &Name, column: usize) -> Result<f64, Fail> {
        if let Some(v) = self.values.get(name) {
            return Ok(*v);
        }
        match name {
            Name::Numbered(n) if *n <= LAST_USER => Ok(0.0),
            Name::Numbered(n) => Err((
                column,
                format!(
                    "#{n} is read before the program sets it: it holds the control's state (probe results, homes, \
                     work offsets, the tool, the position), which ncsheet does not model"
                ),
            )),
            Name::Named(s) => match self.control.value(s) {
                Some(v) => v.map_err(|m| (column, m)),
                // `#<_value>` and `#<_value_returned>` before any subroutine returned.
                None if predefined::is_predefined(s) => Ok(0.0),
                None => Err((column, unset_named(s))),
            },
        }
    }
}

/// Why the named parameter `s` has no value: not set yet, or the control's (an INI file's
/// entry `#<_ini[section]name>`, a HAL pin `#<_hal[pin]>`).
fn unset_named(s: &str) -> String {
    if s.starts_with("_ini[") || s.starts_with("_hal[") {
        return format!("#<{s}> reads the control's INI file or HAL, which ncsheet does not have");
    }
    format!("#<{s}> is read before the program sets it")
}

/// Reads a `#… = value` setting whose `#` is at `from`; returns it and where it ends.
pub fn setting(chars: &[char], from: usize, params: &Parameters) -> Result<(Setting, usize), Fail> {
    let mut r = Reader { chars, at: from, params, depth: 0 };
    let name = r.parameter_name()?;
    if let Name::Numbered(n) = name {
        if n >= FIRST_STATE {
            return Err((
                from + 1,
                format!(
                    "setting #{n} changes the control's state (a work offset, a home, the tool): ncsheet does not \
                     model it; set work offsets with the control"
                ),
            ));
        }
    }
    if let Name::Named(s) = &name {
        if predefined::is_predefined(s) {
            return Err((
                from + 1,
                format!("#<{s}> is read-only: LinuxCNC's predefined parameters hold the control's state"),
            ));
        }
    }
    r.skip_spaces();
    if r.peek() != Some('=') {
        return Err((r.column(), format!("a parameter {name} outside a word is a setting and takes `=` and a value")));
    }
    r.at += 1;
    let value = r.real_value()?;
    Ok((Setting { name, value }, r.at))
}

/// Reads a word's value starting at `from`: a number, `[expression]`, `#parameter`, a
/// function such as `SIN[30]`, each with an optional sign; returns it and where it ends.
pub fn real_value(chars: &[char], from: usize, params: &Parameters) -> Result<(f64, usize), Fail> {
    let mut r = Reader { chars, at: from, params, depth: 0 };
    let v = r.real_value()?;
    Ok((v, r.at))
}

/// Whether the text at `from` is a value only [`real_value`] reads (an expression, a
/// parameter, a function), not a plain number.
pub fn starts_computed_value(chars: &[char], from: usize) -> bool {
    let mut i = from;
    while matches!(chars.get(i), Some('+' | '-' | ' ')) {
        i += 1;
    }
    matches!(chars.get(i), Some(c) if *c == '[' || *c == '#' || c.is_ascii_alphabetic())
}

struct Reader<'a> {
    chars: &'a [char],
    at: usize,
    params: &'a Parameters,
    depth: usize,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Op {
    Power,
    Times,
    Divide,
    Modulo,
    Plus,
    Minus,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    fn binding(self) -> u8 {
        match self {
            Op::Power => 4,
            Op::Times | Op::Divide | Op::Modulo => 3,
            Op::Plus | Op::Minus => 2,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 1,
            Op::And | Op::Or | Op::Xor => 0,
        }
    }

    fn named(word: &str) -> Option<Op> {
        Some(match word {
            "MOD" => Op::Modulo,
            "EQ" => Op::Eq,
            "NE" => Op::Ne,
            "GT" => Op::Gt,
            "GE" => Op::Ge,
            "LT" => Op::Lt,
            "LE" => Op::Le,
            "AND" => Op::And,
            "OR" => Op::Or,
            "XOR" => Op::Xor,
            _ => return None,
        })
    }

    /// `a op b`, or why it has no value.
    fn apply(self, a: f64, b: f64) -> Result<f64, String> {
        let truth = |t: bool| if t { 1.0 } else { 0.0 };
        let v = match self {
            Op::Power => {
                if a < 0.0 && b.fract() != 0.0 {
                    return Err(format!("{a} ** {b} raises a negative number to a power that is not whole"));
                }
                a.powf(b)
            }
            Op::Times => a * b,
            Op::Divide if b == 0.0 => return Err(format!("{a} / {b} divides by zero")),
            Op::Divide => a / b,
            Op::Modulo if b == 0.0 => return Err(format!("{a} MOD {b} has no value (MOD 0)")),
            // LinuxCNC's MOD is never negative: -7 MOD 3 is 2.
            Op::Modulo => {
                let r = a % b;
                if r < 0.0 {
                    r + b.abs()
                } else {
                    r
                }
            }
            Op::Plus => a + b,
            Op::Minus => a - b,
            Op::Eq => truth((a - b).abs() < EQUAL_WITHIN),
            Op::Ne => truth((a - b).abs() >= EQUAL_WITHIN),
            // LinuxCNC 2.9.0 compares GT GE LT LE exactly; later versions give GE and LE the
            // tolerance of EQ.
            Op::Gt => truth(a > b),
            Op::Ge => truth(a >= b),
            Op::Lt => truth(a < b),
            Op::Le => truth(a <= b),
            Op::And => truth(a != 0.0 && b != 0.0),
            Op::Or => truth(a != 0.0 || b != 0.0),
            Op::Xor => truth((a != 0.0) != (b != 0.0)),
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("the value is not a finite number ({a} and {b})"))
        }
    }
}

/// LinuxCNC's functions of one bracketed value (ATAN takes two: `ATAN[y]/[x]`).
const FUNCTIONS: &str = "ABS ACOS ASIN ATAN COS EXISTS EXP FIX FUP LN ROUND SIN SQRT TAN";

impl Reader<'_> {
    fn column(&self) -> usize {
        self.at + 1
    }

    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn skip_spaces(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.at += 1;
        }
    }

    /// Descends one level of nesting, refusing past [`MAX_NESTING`].
    fn deeper(&mut self) -> Result<(), Fail> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err((self.column(), format!("brackets and functions nested more than {MAX_NESTING} deep")));
        }
        Ok(())
    }

    fn real_value(&mut self) -> Result<f64, Fail> {
        self.deeper()?;
        self.skip_spaces();
        let v = match self.peek() {
            Some('-') => {
                self.at += 1;
                -self.real_value()?
            }
            Some('+') => {
                self.at += 1;
                self.real_value()?
            }
            Some('[') => self.bracketed()?,
            Some('#') => {
                let column = self.column();
                let name = self.parameter_name()?;
                self.params.value(&name, column)?
            }
            Some(c) if c.is_ascii_alphabetic() => self.function()?,
            _ => self.number()?,
        };
        self.depth -= 1;
        Ok(v)
    }

    fn number(&mut self) -> Result<f64, Fail> {
        let start = self.at;
        while self.peek().is_some_and(|c| c.is_ascii_digit() || c == '.') {
            self.at += 1;
        }
        let text: String = self.chars[start..self.at].iter().collect();
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err((start + 1, format!("a number too large for any control (`{}`)", quoted_briefly(&text)))),
            Err(_) if text.is_empty() => {
                let found = self.peek().map_or("the end of the line".to_string(), |c| format!("`{c}`"));
                Err((start + 1, format!("a value is missing here (found {found})")))
            }
            Err(_) => Err((start + 1, format!("`{}` is not a number", quoted_briefly(&text)))),
        }
    }

    /// `[expression]`, the `[` at the reader.
    fn bracketed(&mut self) -> Result<f64, Fail> {
        let open = self.column();
        self.at += 1;
        let v = self.expression()?;
        self.skip_spaces();
        if self.peek() != Some(']') {
            return Err((open, "an expression that is not closed by `]`".into()));
        }
        self.at += 1;
        Ok(v)
    }

    /// Operands and binary operators up to the closing `]`, bound as LinuxCNC binds them.
    fn expression(&mut self) -> Result<f64, Fail> {
        let first = self.real_value()?;
        let mut operands = vec![first];
        let mut ops: Vec<(Op, usize)> = Vec::new();
        while let Some((op, column)) = self.binary_operator()? {
            while let Some(&(top, top_column)) = ops.last() {
                if top.binding() < op.binding() {
                    break;
                }
                ops.pop();
                Self::reduce(&mut operands, top, top_column)?;
            }
            ops.push((op, column));
            operands.push(self.real_value()?);
        }
        while let Some((op, column)) = ops.pop() {
            Self::reduce(&mut operands, op, column)?;
        }
        Ok(operands[0])
    }

    fn reduce(operands: &mut Vec<f64>, op: Op, column: usize) -> Result<(), Fail> {
        let b = operands.pop().expect("an operand after each operator");
        let a = operands.pop().expect("an operand before each operator");
        operands.push(op.apply(a, b).map_err(|m| (column, m))?);
        Ok(())
    }

    /// The binary operator at the reader, if the expression goes on.
    fn binary_operator(&mut self) -> Result<Option<(Op, usize)>, Fail> {
        self.skip_spaces();
        let column = self.column();
        let op = match self.peek() {
            Some(']') | None => return Ok(None),
            Some('*') if self.chars.get(self.at + 1) == Some(&'*') => {
                self.at += 2;
                Op::Power
            }
            Some(c @ ('*' | '/' | '+' | '-')) => {
                self.at += 1;
                match c {
                    '*' => Op::Times,
                    '/' => Op::Divide,
                    '+' => Op::Plus,
                    _ => Op::Minus,
                }
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let word = self.word();
                Op::named(&word).ok_or_else(|| {
                    (
                        column,
                        format!(
                            "`{}` is not an operator (** * / MOD + - EQ NE GT GE LT LE AND OR XOR)",
                            quoted_briefly(&word)
                        ),
                    )
                })?
            }
            Some(c) => {
                return Err((column, format!("`{c}` is not an operator (** * / MOD + - EQ NE GT GE LT LE AND OR XOR)")))
            }
        };
        Ok(Some((op, column)))
    }

    /// The letters at the reader, in capitals.
    fn word(&mut self) -> String {
        let start = self.at;
        while self.peek().is_some_and(|c| c.is_ascii_alphabetic()) {
            self.at += 1;
        }
        self.chars[start..self.at].iter().collect::<String>().to_ascii_uppercase()
    }

    /// `NAME[value]` (or `ATAN[y]/[x]`, `EXISTS[#<name>]`), the name at the reader.
    fn function(&mut self) -> Result<f64, Fail> {
        let column = self.column();
        let name = self.word();
        if !FUNCTIONS.split(' ').any(|f| f == name) {
            return Err((
                column,
                format!("`{}` is not one of LinuxCNC's functions ({FUNCTIONS})", quoted_briefly(&name)),
            ));
        }
        self.skip_spaces();
        if self.peek() != Some('[') {
            return Err((self.column(), format!("{name} takes a value in brackets: {name}[…]")));
        }
        if name == "EXISTS" {
            return self.exists();
        }
        let x = self.bracketed()?;
        let degrees = |radians: f64| radians.to_degrees();
        let out_of = |what: &str| Err((column, format!("{name}[{x}] has no value ({what})")));
        let v = match name.as_str() {
            "ABS" => x.abs(),
            "ACOS" if !(-1.0..=1.0).contains(&x) => return out_of("its value must be from -1 to 1"),
            "ACOS" => degrees(x.acos()),
            "ASIN" if !(-1.0..=1.0).contains(&x) => return out_of("its value must be from -1 to 1"),
            "ASIN" => degrees(x.asin()),
            "ATAN" => degrees(x.atan2(self.atan_divisor()?)),
            "COS" => x.to_radians().cos(),
            "EXP" => x.exp(),
            "FIX" => x.floor(),
            "FUP" => x.ceil(),
            "LN" if x <= 0.0 => return out_of("the logarithm of a number not above 0"),
            "LN" => x.ln(),
            // Half away from zero by adding a half and cutting, as LinuxCNC does: 0.49999999999999994
            // rounds to 1 there (the sum is 1.0 in doubles), where `f64::round` gives 0.
            "ROUND" => (x + 0.5f64.copysign(x)).trunc(),
            "SIN" => x.to_radians().sin(),
            "SQRT" if x < 0.0 => return out_of("the square root of a negative number"),
            "SQRT" => x.sqrt(),
            _ => x.to_radians().tan(),
        };
        if !v.is_finite() {
            return Err((column, format!("{name}[{x}] is not a finite number")));
        }
        Ok(v)
    }

    /// The `/[x]` of `ATAN[y]/[x]`.
    fn atan_divisor(&mut self) -> Result<f64, Fail> {
        self.skip_spaces();
        if self.peek() != Some('/') {
            return Err((self.column(), "ATAN takes two values: ATAN[y]/[x]".into()));
        }
        self.at += 1;
        self.skip_spaces();
        if self.peek() != Some('[') {
            return Err((self.column(), "ATAN takes two values: ATAN[y]/[x]".into()));
        }
        self.bracketed()
    }

    /// `EXISTS[#<name>]`: 1 when the program has set the parameter (a numbered one always exists).
    fn exists(&mut self) -> Result<f64, Fail> {
        let open = self.column();
        self.at += 1;
        self.skip_spaces();
        if self.peek() != Some('#') {
            return Err((self.column(), "EXISTS takes a parameter: EXISTS[#<name>]".into()));
        }
        let name = self.parameter_name()?;
        self.skip_spaces();
        if self.peek() != Some(']') {
            return Err((open, "an expression that is not closed by `]`".into()));
        }
        self.at += 1;
        let set = match &name {
            Name::Numbered(_) => true,
            Name::Named(s) => predefined::is_predefined(s) || self.params.values.contains_key(&name),
        };
        Ok(if set { 1.0 } else { 0.0 })
    }

    /// `#<name>` or `#` and a value giving the number, the `#` at the reader.
    fn parameter_name(&mut self) -> Result<Name, Fail> {
        let column = self.column();
        self.at += 1;
        self.skip_spaces();
        if self.peek() == Some('<') {
            let close = self.chars[self.at..]
                .iter()
                .position(|&c| c == '>')
                .ok_or((column, "a parameter name that is not closed by `>`".to_string()))?;
            let name: String = self.chars[self.at + 1..self.at + close]
                .iter()
                .filter(|c| !c.is_whitespace())
                .collect::<String>()
                .to_ascii_lowercase();
            self.at += close + 1;
            if name.is_empty() {
                return Err((column, "a parameter with an empty name `#<>`".into()));
            }
            return Ok(Name::Named(name));
        }
        let n = self.real_value()?;
        let whole = n.round();
        if (n - whole).abs() > WHOLE_WITHIN {
            return Err((column, format!("a parameter's number must be whole (#{n})")));
        }
        if !(1.0..=f64::from(LAST_NUMBERED)).contains(&whole) {
            return Err((column, format!("#{whole} is not a parameter (LinuxCNC numbers them #1–#{LAST_NUMBERED})")));
        }
        Ok(Name::Numbered(whole as u32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(text: &str) -> Result<f64, Fail> {
        let chars: Vec<char> = text.chars().collect();
        real_value(&chars, 0, &Parameters::default()).map(|(v, _)| v)
    }

    /// A million `[` is refused at the nesting limit, not a stack overflow.
    #[test]
    fn deep_brackets_are_refused_at_the_limit() {
        let text = "[".repeat(1_000_000);
        let e = value(&text).unwrap_err();
        assert!(e.1.contains("nested more than"), "{e:?}");
    }
}
