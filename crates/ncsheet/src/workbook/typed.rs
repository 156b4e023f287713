//! What a user types, read in the workbook's locale (its `Settings`): `0,8`, `1 234,5`,
//! `12.03.2025` and `=ROUND(B5*0,5;3)` in a decimal-comma locale become the canonical input
//! the workbook stores (`0.8`, `1234.5`, the date's serial, `=ROUND(B5*0.5,3)`). Files and
//! macros' `.Formula` stay canonical: only typing goes through here. A value that is a number
//! in another locale but not in this one is refused with the spelling the user meant, never
//! stored as text that breaks the cells reading it.

use std::borrow::Cow;

use crate::eval::dates::DateSystem;
use crate::eval::{Locale, Value};

use super::Input;

impl Input {
    /// [`Input::parse`] as a user of `locale` types: numbers and dates in its spelling,
    /// formulas with its separators (turned into the file syntax).
    pub fn parse_in(text: &str, locale: Locale, dates: DateSystem) -> Input {
        if locale.is_canonical() {
            return Input::parse(text, dates);
        }
        match Input::parse(text, dates) {
            Input::Formula(f) => Input::Formula(locale.canonical_formula(&f)),
            // A forced text, a boolean or an error literal reads the same in every locale.
            Input::Empty => Input::Empty,
            Input::Value(v @ (Value::Bool(_) | Value::Error(_))) => Input::Value(v),
            _ if text.starts_with('\'') => Input::parse(text, dates),
            // The locale's own words for TRUE and FALSE (de-DE `WAHR`) read as its Excel reads them.
            _ => match (locale.read_boolean(text), locale.read_number(text, dates)) {
                (Some(b), _) => Input::Value(Value::Bool(b)),
                (None, Some(n)) => Input::Value(Value::Number(n)),
                (None, None) => Input::Value(Value::text(text)),
            },
        }
    }
}

impl super::Workbook {
    /// What the user typed, as the canonical input [`super::Workbook::set_input`] stores:
    /// read in the workbook's locale. `Err` says why a value is refused: it is a number in
    /// another locale and only text in this one (`0.8` in et-EE, `0,8` in en-US), with the
    /// spelling meant.
    pub fn typed_input<'t>(&self, text: &'t str) -> Result<Cow<'t, str>, String> {
        let locale = self.settings.locale_in_force(self.date_system());
        let input = Input::parse_in(text, locale, self.date_system());
        if let Input::Value(Value::Text(_)) = &input {
            if let Some((other, meant)) = locale.number_elsewhere(text) {
                return Err(format!(
                    "'{}' is a number in {other} but not in {locale}, the locale in force: type {meant} (or '{} \
                     for text, or choose the locale with --locale)",
                    text.trim(),
                    text.trim()
                ));
            }
        }
        if locale.is_canonical() {
            return Ok(Cow::Borrowed(text));
        }
        Ok(match input {
            Input::Empty => Cow::Borrowed(""),
            Input::Formula(f) => Cow::Owned(f),
            Input::Value(Value::Number(n)) => Cow::Owned(canonical_number(n)),
            Input::Value(Value::Bool(b)) => Cow::Borrowed(if b { "TRUE" } else { "FALSE" }),
            Input::Value(Value::Error(e)) => Cow::Owned(e.to_string()),
            Input::Value(_) if text.starts_with('\'') => Cow::Borrowed(text),
            // Text that the canonical reading would take for something else is forced text.
            Input::Value(_) if !matches!(Input::parse(text, self.date_system()), Input::Value(Value::Text(_))) => {
                Cow::Owned(format!("'{text}"))
            }
            Input::Value(_) => Cow::Borrowed(text),
        })
    }
}

/// A number spelled so that the canonical reading gives it back exactly (Rust's shortest
/// round-trip digits, never an exponent the reading could take otherwise).
fn canonical_number(n: f64) -> String {
    format!("{n}")
}
