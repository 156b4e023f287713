//! Excel number formats as TEXT and FIXED apply them: `0.000`, `#,##0.00`, `0.0%`,
//! `0.00E+00`, `+0.000;-0.000;0`, quoted literals, `@`, `General`, and dates and times
//! (`yyyy-mm-dd hh:mm:ss`).
//!
//! Digits come from the number's 15 significant decimal digits and are rounded in
//! decimal, half away from zero, as Excel displays them (2.675 shows as 2.68 although the
//! binary double is a little below).

use super::number_format::{round15, significant_digits};
use crate::eval::dates::{DateSystem, DateTime, LAST_SERIAL, VBA_DATE_RANGE};
use crate::eval::value::{XlError, XlResult};

/// One piece of a format section.
#[derive(Clone, Debug, PartialEq)]
enum Tok {
    /// A digit placeholder: `0` (always a digit), `#` (digit if significant), `?` (digit
    /// or space).
    Digit(char),
    Point,
    Comma,
    Percent,
    /// `E+` (sign always shown) or `E-` (only a minus sign); `e+`/`e-` in VBA's Format,
    /// which writes a small `e`.
    Exp {
        plus: bool,
        small: bool,
    },
    Lit(String),
    /// `@`: the text value.
    TextAt,
    General,
    Date(DatePart),
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum DatePart {
    Year(usize),
    /// `m` runs: a month, unless it sits after hours or before seconds (then minutes).
    Month(usize),
    Day(usize),
    Hour(usize),
    Minute(usize),
    Second(usize),
    /// `[h]`, `[m]`, `[s]`: hours, minutes or seconds elapsed in total.
    Elapsed(char, usize),
    /// `.0`, `.00`, `.000` after seconds.
    SubSecond(usize),
    /// VBA's `w`: the day of the week, 1 for the first day of the week.
    Weekday,
    /// VBA's `ww`: the week of the year.
    Week,
    /// VBA's `y`: the day of the year (1-366).
    DayOfYear,
    /// VBA's `q`: the quarter of the year (1-4).
    Quarter,
    /// VBA's `c`: the General Date, the date and the time as the value has them.
    GeneralDate,
    /// `AM/PM` or `A/P`, with the case as written.
    AmPm {
        short: bool,
        lower: bool,
    },
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

#[derive(Clone, Debug, Default)]
struct Section {
    tokens: Vec<Tok>,
    condition: Option<(Cmp, f64)>,
    /// How a number section shows its digits, worked out once when the code is read: worked
    /// out per number, TEXT of a code of thousands of placeholders over an array scanned and
    /// copied the code's placeholders again for every item. `None` for a date section.
    shape: Option<Shape>,
}

/// What a number section is, and where its digits go.
#[derive(Clone, Debug)]
enum Shape {
    /// `General`, with literals around it.
    General,
    /// No digit placeholder: literals, `@` or `%` alone.
    Literal,
    Fraction(FractionLayout),
    /// A fraction whose fixed denominator is past [`MAX_FIXED_DENOMINATOR`].
    FractionPastResolution,
    Digits {
        layout: Layout,
        scientific: bool,
    },
}

impl Shape {
    fn of(tokens: &[Tok]) -> Shape {
        if tokens.contains(&Tok::General) {
            return Shape::General;
        }
        if !tokens.iter().any(|t| matches!(t, Tok::Digit(_))) {
            return Shape::Literal;
        }
        match FractionLayout::of(tokens) {
            Ok(Some(fraction)) => Shape::Fraction(fraction),
            Err(DenominatorPastResolution) => Shape::FractionPastResolution,
            Ok(None) => {
                let scientific = tokens.iter().any(|t| matches!(t, Tok::Exp { .. }));
                Shape::Digits { layout: layout(tokens), scientific }
            }
        }
    }
}

impl Section {
    fn is_date(&self) -> bool {
        self.tokens.iter().any(|t| matches!(t, Tok::Date(_)))
    }

    fn has(&self, tok: &Tok) -> bool {
        self.tokens.contains(tok)
    }
}

#[cfg(test)]
thread_local! {
    static CODES_PARSED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    static SECTIONS_LAID_OUT: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Number sections laid out on this thread so far (where a fraction's parts are, or the
/// integer, decimal and exponent placeholders): counted for tests, as [`codes_parsed`].
#[cfg(test)]
pub(crate) fn sections_laid_out() -> u64 {
    SECTIONS_LAID_OUT.with(|c| c.get())
}

/// Format codes parsed on this thread so far: tests bound a call's parses by this count (a
/// count holds on a loaded machine, where a wall-clock bound would not). Only for tests: the
/// binary keeps no such state.
#[cfg(test)]
pub(crate) fn codes_parsed() -> u64 {
    CODES_PARSED.with(|c| c.get())
}

/// A parsed format: up to four `;`-separated sections (positive; negative; zero; text).
pub struct NumberFormat {
    sections: Vec<Section>,
}

/// Whose reading of a format code: Excel's (a cell's format, TEXT) or VBA's Format. Both
/// read `E+`, `E-`, `e+` and `e-` as scientific and write the `E` or `e` given (the values
/// Excel caches for such cells keep the small `e`); in Excel an `e` or `ee` standing alone
/// is the year as `yyyy` ([MS-OI29500] 2.1.713 f).
#[derive(Clone, Copy, PartialEq)]
enum Dialect {
    Excel,
    Vba,
}

impl NumberFormat {
    pub fn parse(format: &str) -> XlResult<NumberFormat> {
        NumberFormat::parse_as(format, Dialect::Excel)
    }

    /// A format code as VBA's Format reads it (`e+` is scientific with a small `e`).
    pub fn parse_vba(format: &str) -> XlResult<NumberFormat> {
        NumberFormat::parse_as(format, Dialect::Vba)
    }

    fn parse_as(format: &str, dialect: Dialect) -> XlResult<NumberFormat> {
        #[cfg(test)]
        CODES_PARSED.with(|c| c.set(c.get() + 1));
        let sections =
            split_sections(format).iter().map(|s| parse_section(s, dialect)).collect::<XlResult<Vec<_>>>()?;
        Ok(NumberFormat { sections })
    }

    /// A number as text under this format; a date format reads it as a serial of `dates`.
    pub fn format_number(&self, n: f64, dates: DateSystem) -> XlResult<String> {
        self.format_with_dates(n, &|section, serial| format_date(section, serial, dates))
    }

    /// A number as VBA's Format shows it: a date format reads it as a macro's Date (from
    /// 100-01-01, a negative date's time counted forward: [`DateTime::from_vba_date`]), its
    /// `w` and `ww` numbered by `weeks`.
    pub fn format_vba_number(&self, n: f64, weeks: WeekNumbers) -> XlResult<String> {
        self.format_with_dates(n, &|section, serial| format_vba_date(section, serial, weeks))
    }

    fn format_with_dates(&self, n: f64, date: DateFormatter) -> XlResult<String> {
        if self.no_condition_holds(n) {
            // `[<10]0" Wow"` given 10: Excel shows the number in General.
            return Ok(general_text(n));
        }
        let (section, value, signed) = self.choose(n);
        if section.tokens.is_empty() {
            return Ok(String::new());
        }
        if section.is_date() {
            return date(section, value);
        }
        format_in_section(section, value, signed)
    }

    /// A text value under this format: the text section when there is one, else the text
    /// unchanged.
    pub fn format_text(&self, text: &str) -> String {
        let section = match self.sections.len() {
            4.. => Some(&self.sections[3]),
            1 if self.sections[0].has(&Tok::TextAt) => Some(&self.sections[0]),
            _ => None,
        };
        let Some(section) = section else {
            return text.to_string();
        };
        let mut out = String::new();
        for tok in &section.tokens {
            match tok {
                Tok::TextAt => out.push_str(text),
                Tok::Lit(s) => out.push_str(s),
                _ => {}
            }
        }
        out
    }

    /// Whether the numeric sections all carry conditions and none holds for `n`.
    fn no_condition_holds(&self, n: f64) -> bool {
        let mut numeric = self.sections.iter().take(3).filter(|s| !(self.sections.len() > 1 && is_text_section(s)));
        numeric.all(|s| s.condition.is_some_and(|(cmp, limit)| !holds(cmp, n, limit)))
            && self.sections.iter().take(3).any(|s| s.condition.is_some())
    }

    /// The section for `n`, the value it shows, and whether that section prints a minus
    /// sign itself (only a single section covering negatives does).
    fn choose(&self, n: f64) -> (&Section, f64, bool) {
        let numeric: Vec<&Section> =
            self.sections.iter().take(3).filter(|s| !(self.sections.len() > 1 && is_text_section(s))).collect();
        if numeric.iter().any(|s| s.condition.is_some()) {
            return choose_by_condition(&numeric, n);
        }
        match (numeric.len(), n) {
            (0, _) => (&self.sections[0], n, true),
            (1, _) => (numeric[0], n, true),
            (_, n) if n < 0.0 => (numeric[1], -n, false),
            (3.., n) if n == 0.0 => (numeric[2], n, false),
            _ => (numeric[0], n, false),
        }
    }
}

/// A section with `@` formats text, not numbers.
fn is_text_section(s: &Section) -> bool {
    s.has(&Tok::TextAt)
}

/// Sections with conditions (`[>=100]0;[<0]-0;0.00`) are tried in order; the first
/// without a condition catches the rest. A negative number keeps its minus sign: a
/// condition, unlike the negative section, does not imply one.
fn choose_by_condition<'a>(sections: &[&'a Section], n: f64) -> (&'a Section, f64, bool) {
    let chosen = sections
        .iter()
        .find(|s| s.condition.is_none_or(|(cmp, limit)| holds(cmp, n, limit)))
        .unwrap_or(&sections[sections.len() - 1]);
    (chosen, n, true)
}

fn holds(cmp: Cmp, n: f64, limit: f64) -> bool {
    match cmp {
        Cmp::Lt => n < limit,
        Cmp::Le => n <= limit,
        Cmp::Gt => n > limit,
        Cmp::Ge => n >= limit,
        Cmp::Eq => n == limit,
        Cmp::Ne => n != limit,
    }
}

// ---------------------------------------------------------------------------------------
// Parsing

/// Splits at `;` outside quotes, brackets and escapes.
fn split_sections(format: &str) -> Vec<String> {
    let mut sections = vec![String::new()];
    let mut chars = format.chars();
    let mut quoted = false;
    let mut bracket = false;
    while let Some(c) = chars.next() {
        let current = sections.last_mut().expect("one section at least");
        match c {
            '"' => quoted = !quoted,
            '[' if !quoted => bracket = true,
            ']' if !quoted => bracket = false,
            '\\' | '_' | '*' if !quoted => {
                current.push(c);
                if let Some(next) = chars.next() {
                    current.push(next);
                }
                continue;
            }
            ';' if !quoted && !bracket => {
                sections.push(String::new());
                continue;
            }
            _ => {}
        }
        current.push(c);
    }
    sections
}

fn parse_section(text: &str, dialect: Dialect) -> XlResult<Section> {
    let chars: Vec<char> = text.chars().collect();
    let mut section = Section::default();
    let mut seen_digit = false;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let lower = c.to_ascii_lowercase();
        i += 1;
        let tok = match lower {
            '"' => {
                let end = chars[i..].iter().position(|&q| q == '"').map(|p| i + p);
                let end = end.unwrap_or(chars.len());
                let lit: String = chars[i..end].iter().collect();
                i = end + 1;
                Tok::Lit(lit)
            }
            '\\' => {
                i += 1;
                Tok::Lit(chars.get(i - 1).map(|c| c.to_string()).unwrap_or_default())
            }
            '_' => {
                // Space as wide as the next character: one space in text.
                i += 1;
                Tok::Lit(" ".to_string())
            }
            '*' => {
                // Fill character: TEXT has no column width to fill.
                i += 1;
                continue;
            }
            '[' => {
                let end = chars[i..].iter().position(|&q| q == ']').map(|p| i + p);
                let end = end.ok_or(XlError::Value)?;
                let inner: String = chars[i..end].iter().collect();
                i = end + 1;
                match bracket(&inner, &mut section, dialect)? {
                    Some(tok) => tok,
                    None => continue,
                }
            }
            '0' | '#' | '?' => Tok::Digit(c),
            '.' => Tok::Point,
            ',' => Tok::Comma,
            '%' => Tok::Percent,
            '@' => Tok::TextAt,
            'e' if matches!(chars.get(i), Some('+' | '-')) => {
                i += 1;
                Tok::Exp { plus: chars[i - 1] == '+', small: c == 'e' }
            }
            'e' if c == 'e' && dialect == Dialect::Excel => {
                // The era year, `yyyy` outside Japanese and Chinese (Taiwan) locales.
                i += chars[i..].iter().take_while(|&&x| x == 'e').count();
                Tok::Date(DatePart::Year(4))
            }
            'g' if starts_with_ignore_case(&chars[i - 1..], "general") => {
                i += "general".len() - 1;
                Tok::General
            }
            'a' if starts_with_ignore_case(&chars[i - 1..], "am/pm") => {
                i += 4;
                // Excel writes capitals however `am/pm` is typed; VBA's Format keeps the case
                // ("Format function": "hh:mm:ss am/pm" returns "05:04:23 pm").
                Tok::Date(DatePart::AmPm { short: false, lower: c == 'a' && dialect == Dialect::Vba })
            }
            'a' if dialect == Dialect::Vba && starts_with_ignore_case(&chars[i - 1..], "ampm") => {
                // The system's designators, AM and PM in English (United States).
                i += 3;
                Tok::Date(DatePart::AmPm { short: false, lower: false })
            }
            'a' if starts_with_ignore_case(&chars[i - 1..], "a/p") => {
                i += 2;
                Tok::Date(DatePart::AmPm { short: true, lower: c == 'a' })
            }
            // VBA reads a section as a number once a digit placeholder came: a date letter
            // after one is written as it is (LibreOffice's VBA mode: Format(5, "0 w") is "5 w").
            'c' | 'd' | 'h' | 'm' | 'n' | 'q' | 's' | 't' | 'w' | 'y' if dialect == Dialect::Vba && seen_digit => {
                Tok::Lit(c.to_string())
            }
            'n' | 'q' | 'c' if dialect == Dialect::Vba => {
                // "Format function": `n`/`nn` the minute, `q` the quarter, `c` the date as
                // `ddddd` and the time as `ttttt`.
                let run =
                    if lower == 'n' && chars.get(i).is_some_and(|x| x.eq_ignore_ascii_case(&'n')) { 2 } else { 1 };
                i += run - 1;
                Tok::Date(match lower {
                    'n' => DatePart::Minute(run),
                    'q' => DatePart::Quarter,
                    _ => DatePart::GeneralDate,
                })
            }
            't' if dialect == Dialect::Vba && starts_with_ignore_case(&chars[i - 1..], "ttttt") => {
                // The system's long time, `h:mm:ss AM/PM` in English (United States).
                i += 4;
                section.tokens.extend(vba_expansion(VBA_LONG_TIME));
                continue;
            }
            'y' if dialect == Dialect::Vba && !chars.get(i).is_some_and(|x| x.eq_ignore_ascii_case(&'y')) => {
                Tok::Date(DatePart::DayOfYear)
            }
            'd' if dialect == Dialect::Vba
                && chars[i - 1..].iter().take(5).take_while(|x| x.eq_ignore_ascii_case(&'d')).count() == 5 =>
            {
                // Five letters decide it: counting the whole run at each group of six made a
                // run of 200,000 `d` take 15 s.
                // `ddddd` the system's short date, `dddddd` its long date.
                let run = chars[i - 1..].iter().take(6).take_while(|x| x.eq_ignore_ascii_case(&'d')).count();
                i += run - 1;
                section.tokens.extend(vba_expansion(if run == 5 { VBA_SHORT_DATE } else { VBA_LONG_DATE }));
                continue;
            }
            'w' if dialect == Dialect::Vba => {
                // "Format function": `w` the day of the week, `ww` the week of the year.
                let week = chars.get(i).is_some_and(|x| x.eq_ignore_ascii_case(&'w'));
                i += usize::from(week);
                Tok::Date(if week { DatePart::Week } else { DatePart::Weekday })
            }
            'y' | 'm' | 'd' | 'h' | 's' => {
                let run = 1 + chars[i..].iter().take_while(|x| x.to_ascii_lowercase() == lower).count();
                i += run - 1;
                Tok::Date(match lower {
                    'y' => DatePart::Year(run),
                    'm' => DatePart::Month(run),
                    'd' => DatePart::Day(run),
                    'h' => DatePart::Hour(run),
                    _ => DatePart::Second(run),
                })
            }
            _ => Tok::Lit(c.to_string()),
        };
        seen_digit |= matches!(tok, Tok::Digit(_));
        section.tokens.push(tok);
    }
    if section.is_date() {
        settle_date_tokens(&mut section)?;
    } else {
        section.shape = Some(Shape::of(&section.tokens));
    }
    Ok(section)
}

/// The system's short date, long date and long time in English (United States), which VBA's
/// `ddddd`, `dddddd` and `ttttt` show, as its named formats Short Date, Long Date and Long
/// Time do.
pub(crate) const VBA_SHORT_DATE: &str = "m/d/yyyy";
pub(crate) const VBA_LONG_DATE: &str = "dddd, mmmm d, yyyy";
pub(crate) const VBA_LONG_TIME: &str = "h:mm:ss AM/PM";

/// The tokens of one of the system formats above, for the VBA code that stands for it.
fn vba_expansion(code: &str) -> Vec<Tok> {
    parse_section(code, Dialect::Excel).map(|s| s.tokens).unwrap_or_default()
}

/// A fraction section (`# ?/?`, `# ??/??`, `?/8`, `0 ??/16`): where its parts are among
/// the tokens. Without integer placeholders before the numerator the fraction is improper
/// (`?/?` shows 1.25 as 5/4).
#[derive(Clone, Debug)]
struct FractionLayout {
    /// The integer part's placeholders, in order (empty: an improper fraction).
    int_places: Vec<char>,
    /// Tokens `[numerator_at, slash)` are the numerator's placeholders.
    numerator_at: usize,
    slash: usize,
    /// Tokens `(slash, denominator_end)` are the denominator: placeholders or a number.
    denominator_end: usize,
    numerator_places: Vec<char>,
    denominator: Denominator,
}

#[derive(Clone, Debug)]
enum Denominator {
    /// At most this many digits (`??`: up to 99), the closest fraction chosen.
    Digits(Vec<char>),
    /// A fixed denominator (`/16`), never reduced.
    Fixed(u64),
}

/// The largest fixed denominator shown (2^53): past it the denominator and the numerator
/// are no longer whole numbers a double holds exactly, and a denominator past a u64 came
/// out as garbage digits (issue 30).
const MAX_FIXED_DENOMINATOR: u64 = 1 << 53;

/// A fraction section whose fixed denominator is past `MAX_FIXED_DENOMINATOR`: the number
/// is shown as General, as LibreOffice shows `# ?/100000000000000000000`.
struct DenominatorPastResolution;

impl FractionLayout {
    /// The fraction layout of a section, `Ok(None)` when it is no fraction.
    fn of(tokens: &[Tok]) -> Result<Option<FractionLayout>, DenominatorPastResolution> {
        #[cfg(test)]
        SECTIONS_LAID_OUT.with(|c| c.set(c.get() + 1));
        // Matched in place: comparing with a made `Tok::Lit("/")` allocated once per token,
        // and a section is formatted once per item of an array.
        let Some(slash) = tokens.iter().position(|t| matches!(t, Tok::Lit(s) if s == "/")) else { return Ok(None) };
        let numerator_at = tokens[..slash].iter().rposition(|t| !matches!(t, Tok::Digit(_))).map_or(0, |p| p + 1);
        if numerator_at == slash {
            return Ok(None);
        }
        let after = &tokens[slash + 1..];
        let placeholders = after.iter().take_while(|t| matches!(t, Tok::Digit(_))).count();
        let (denominator, len) = if placeholders > 0 {
            (Denominator::Digits(digit_places(&after[..placeholders])), placeholders)
        } else {
            let len = after.iter().take_while(|t| matches!(t, Tok::Digit('0')) || is_digit_literal(t)).count();
            let text: String = after[..len]
                .iter()
                .map(|t| match t {
                    Tok::Lit(s) => s.clone(),
                    _ => "0".to_string(),
                })
                .collect();
            if text.is_empty() || text.bytes().all(|b| b == b'0') {
                return Ok(None);
            }
            match text.parse::<u64>() {
                Ok(d) if d <= MAX_FIXED_DENOMINATOR => (Denominator::Fixed(d), len),
                _ => return Err(DenominatorPastResolution),
            }
        };
        Ok(Some(FractionLayout {
            int_places: digit_places(&tokens[..numerator_at]),
            numerator_at,
            slash,
            denominator_end: slash + 1 + len,
            numerator_places: digit_places(&tokens[numerator_at..slash]),
            denominator,
        }))
    }

    /// Integer part, numerator and denominator shown for `x` (not negative), from its 15
    /// significant digits as every number format shows a number: 1234567890123456.5 is
    /// 1234567890123460 with no fraction left.
    /// The numerator is a whole number held as a double: an improper fraction of 1E+20 has
    /// one past a u64, which saturated to 18446744073709551615.
    fn parts(&self, x: f64) -> (f64, f64, u64) {
        let x = round15(x);
        let mixed = !self.int_places.is_empty();
        let (mut whole, frac) = if mixed { (x.floor(), x - x.floor()) } else { (0.0, x) };
        let (mut numerator, denominator) = match &self.denominator {
            Denominator::Fixed(d) => ((frac * *d as f64).round_ties_even(), *d),
            // From 2^52 up a double is whole: the number over 1.
            Denominator::Digits(_) if frac >= 4_503_599_627_370_496.0 => (frac, 1),
            Denominator::Digits(places) => {
                let (n, d) = closest_fraction(frac, 10u64.pow(places.len().min(6) as u32) - 1);
                (n as f64, d)
            }
        };
        if mixed && numerator == denominator as f64 {
            whole += 1.0;
            numerator = 0.0;
        }
        (whole, numerator, denominator)
    }

    /// The section's text for `x`; `None` when the numerator passes the largest double
    /// (`?/8` of 1E+308), which is shown as General.
    fn render(&self, tokens: &[Tok], x: f64) -> Option<String> {
        let (whole, numerator, denominator) = self.parts(x);
        if !numerator.is_finite() {
            return None;
        }
        let mixed = !self.int_places.is_empty();
        let int_text = match (whole, numerator) {
            // Its 15 digits and zeros after them: every digit of the double 1E+308 was
            // shown (10000000000000000109790636294404554174049230967731184633681068290315…).
            (w, _) if w > 0.0 => whole_digits(w),
            (_, 0.0) => "0".to_string(),
            _ => String::new(),
        };
        // Excel blanks a zero fraction of a mixed number, and the space before an empty
        // integer part: as spaces when the numerator pads with `?`, else not at all.
        let pads = self.numerator_places.contains(&'?');
        let blank_fraction = mixed && numerator == 0.0;
        let blank_gap = mixed && int_text.is_empty();
        let int_texts = integer_texts(&int_text, &self.int_places);
        let numerator_text = padded_left(&whole_digits(numerator), &self.numerator_places);
        let mut out = String::new();
        let mut int_i = 0;
        let last_int = tokens[..self.numerator_at].iter().rposition(|t| matches!(t, Tok::Digit(_)));
        for (i, t) in tokens.iter().enumerate() {
            let in_gap = last_int.is_some_and(|l| i > l) && i < self.numerator_at;
            let in_fraction = (self.numerator_at..self.denominator_end).contains(&i);
            if (in_gap || in_fraction) && blank_fraction || in_gap && blank_gap {
                if pads && !(in_fraction && i > self.slash && matches!(self.denominator, Denominator::Fixed(_))) {
                    out.push_str(&" ".repeat(token_width(t)));
                }
                continue;
            }
            match t {
                Tok::Digit(_) if i < self.numerator_at => {
                    out.push_str(int_texts[int_i]);
                    int_i += 1;
                }
                _ if i == self.numerator_at => out.push_str(&numerator_text),
                _ if i > self.numerator_at && i < self.slash => {}
                _ if i == self.slash => {
                    out.push('/');
                    out.push_str(&match &self.denominator {
                        Denominator::Digits(places) => denominator_text(&denominator.to_string(), places),
                        Denominator::Fixed(d) => d.to_string(),
                    });
                }
                _ if i > self.slash && i < self.denominator_end => {}
                Tok::Lit(s) => out.push_str(s),
                Tok::Percent => out.push('%'),
                _ => {}
            }
        }
        Some(out)
    }
}

/// A whole number's digits: exact below 2^53 (a fixed denominator's numerator may have 16),
/// its 15 significant digits and zeros from there up.
fn whole_digits(v: f64) -> String {
    if v < 9_007_199_254_740_992.0 {
        (v as u64).to_string()
    } else {
        fixed_digits(v, 0).0
    }
}

fn digit_places(tokens: &[Tok]) -> Vec<char> {
    tokens
        .iter()
        .filter_map(|t| match t {
            Tok::Digit(c) => Some(*c),
            _ => None,
        })
        .collect()
}

fn is_digit_literal(t: &Tok) -> bool {
    matches!(t, Tok::Lit(s) if s.len() == 1 && s.as_bytes()[0].is_ascii_digit())
}

fn token_width(t: &Tok) -> usize {
    match t {
        Tok::Lit(s) => s.chars().count(),
        _ => 1,
    }
}

/// The fraction n/d closest to `x` with d at most `max_denominator` (the smallest such d
/// on a tie). The closest fraction with a bounded denominator is one of `x`'s continued
/// fraction convergents or the last intermediate fraction before the bound (Khinchin,
/// *Continued Fractions*, §6), so only those denominators are tried, each as a search over
/// every denominator would try it: a few dozen instead of up to 999,999 for each number a
/// `??????/??????` code shows.
fn closest_fraction(x: f64, max_denominator: u64) -> (u64, u64) {
    let mut best = ((x.round()) as u64, 1, (x - x.round()).abs());
    for d in candidate_denominators(x, max_denominator) {
        let n = (x * d as f64).round();
        let error = (x - n / d as f64).abs();
        if error < best.2 || (error == best.2 && d < best.1) {
            best = (n as u64, d, error);
        }
    }
    (best.0, best.1)
}

/// The denominators of `x`'s convergents up to `max_denominator`, and of the intermediate
/// fraction between the last two, from the exact continued fraction of the double `x`.
fn candidate_denominators(x: f64, max_denominator: u64) -> Vec<u64> {
    // Below half of 1/max every numerator rounds to 0, and from 2^52 up x is whole: the
    // first candidate, round(x)/1, is the answer.
    if !(x.is_finite() && x * max_denominator as f64 >= 0.5 && x < 4_503_599_627_370_496.0) {
        return Vec::new();
    }
    // x = m / 2^k exactly, k at most 74 here (x ≥ 0.5/999,999 > 2^-21, 53-bit m).
    let (mut num, mut den) = exact_ratio(x);
    // The convergents' denominators: q(-2) = 1, q(-1) = 0, q(i) = a(i)·q(i-1) + q(i-2).
    let (mut q_prev, mut q) = (1u128, 0u128);
    let mut out = Vec::new();
    while den != 0 {
        let a = num / den;
        (num, den) = (den, num % den);
        let next = a.saturating_mul(q).saturating_add(q_prev);
        if next > u128::from(max_denominator) {
            // The intermediate fraction with the most of this term that fits.
            let t = (u128::from(max_denominator) - q_prev) / q;
            if t > 0 {
                out.push((q_prev + t * q) as u64);
            }
            break;
        }
        (q_prev, q) = (q, next);
        out.push(q as u64);
    }
    out
}

/// `x` (finite, 0 ≤ x < 2^52, not below 2^-22) as numerator / 2^k.
fn exact_ratio(x: f64) -> (u128, u128) {
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32;
    let mantissa = bits & ((1u64 << 52) - 1);
    let (m, e) = if exponent == 0 { (mantissa, -1074) } else { (mantissa | 1 << 52, exponent - 1075) };
    if e >= 0 {
        (u128::from(m) << e, 1)
    } else {
        // Halving both while m is even keeps them small; k ≤ 74 needs no more than u128.
        let (mut m, mut k) = (u128::from(m), -e as u32);
        while k > 0 && m % 2 == 0 {
            m /= 2;
            k -= 1;
        }
        (m, 1u128 << k)
    }
}

/// Digits right-aligned under placeholders: `?` pads with a space, `0` with a zero.
fn padded_left(digits: &str, places: &[char]) -> String {
    let pad: String =
        places.iter().take(places.len().saturating_sub(digits.len())).filter_map(|&p| pad_of(p)).collect();
    format!("{pad}{digits}")
}

/// A denominator's digits under its placeholders: each place the digits leave empty is a
/// zero before them for a `0` (LibreOffice shows 1.5 in `# ?/000` as "1 1/002") and a space
/// after them for a `?`, so that `??` aligns the fraction bar ("1 1/2 ").
fn denominator_text(digits: &str, places: &[char]) -> String {
    let empty = &places[..places.len().saturating_sub(digits.len())];
    let count = |place: char| empty.iter().filter(|&&p| p == place).count();
    format!("{}{digits}{}", "0".repeat(count('0')), " ".repeat(count('?')))
}

fn pad_of(place: char) -> Option<char> {
    match place {
        '?' => Some(' '),
        '0' => Some('0'),
        _ => None,
    }
}

fn starts_with_ignore_case(chars: &[char], word: &str) -> bool {
    let n = word.chars().count();
    chars.len() >= n && chars[..n].iter().zip(word.chars()).all(|(a, b)| a.eq_ignore_ascii_case(&b))
}

/// `[Red]`, `[Color5]`, `[$-409]`: ignored; `[$€-407]`: the currency text;
/// `[>=100]`: a condition; `[h]`, `[mm]`, `[ss]`: elapsed time. Any other word makes no code
/// in Excel's reading ([`known_bracket_word`]).
fn bracket(inner: &str, section: &mut Section, dialect: Dialect) -> XlResult<Option<Tok>> {
    if let Some(currency) = inner.strip_prefix('$') {
        let symbol = currency.split('-').next().unwrap_or("");
        return Ok((!symbol.is_empty()).then(|| Tok::Lit(symbol.to_string())));
    }
    if let Some(cond) = parse_condition(inner) {
        section.condition = Some(cond);
        return Ok(None);
    }
    let lower = inner.to_ascii_lowercase();
    if let Some(unit) = lower.chars().next().filter(|c| matches!(c, 'h' | 'm' | 's')) {
        if lower.chars().all(|c| c == unit) {
            return Ok(Some(Tok::Date(DatePart::Elapsed(unit, lower.len()))));
        }
    }
    // Colours and locale codes change nothing in text.
    if dialect == Dialect::Vba || known_bracket_word(&lower) {
        return Ok(None);
    }
    Err(XlError::Value)
}

/// A word in brackets, lower case, that Excel reads in a format code besides conditions,
/// currencies and elapsed times: a colour (`[Red]`, `[Color10]`, a locale's `[Rot]`) or the
/// East Asian numerals (`[DBNum1]`). Excel and LibreOffice refuse any other (`[Foo]0`:
/// TEXT gives #VALUE!); they read only their own locale's colour words, which TEXT checks
/// ([`crate::eval::Locale::foreign_colour`]).
fn known_bracket_word(lower: &str) -> bool {
    let numerals = ["dbnum", "natnum"]
        .iter()
        .any(|kind| lower.strip_prefix(kind).is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())));
    numerals || crate::eval::locale::names_a_colour(lower)
}

fn parse_condition(inner: &str) -> Option<(Cmp, f64)> {
    let (cmp, rest) =
        [("<=", Cmp::Le), (">=", Cmp::Ge), ("<>", Cmp::Ne), ("<", Cmp::Lt), (">", Cmp::Gt), ("=", Cmp::Eq)]
            .iter()
            .find_map(|(op, cmp)| inner.strip_prefix(op).map(|rest| (*cmp, rest)))?;
    rest.trim().parse().ok().map(|v| (cmp, v))
}

/// Resolves `m` to minutes next to hours or seconds, turns `.00` after seconds into
/// fractions of a second, and rejects digit placeholders mixed into a date (`mm###`).
fn settle_date_tokens(section: &mut Section) -> XlResult<()> {
    let tokens = std::mem::take(&mut section.tokens);
    let date_positions: Vec<usize> = (0..tokens.len()).filter(|&i| matches!(tokens[i], Tok::Date(_))).collect();
    let mut out = Vec::with_capacity(tokens.len());
    let mut i = 0;
    while i < tokens.len() {
        match &tokens[i] {
            Tok::Date(DatePart::Month(n)) if is_minute(&tokens, &date_positions, i) => {
                out.push(Tok::Date(DatePart::Minute(*n)));
            }
            Tok::Point if follows_seconds(&out) => {
                let zeros = tokens[i + 1..].iter().take_while(|t| **t == Tok::Digit('0')).count();
                if zeros == 0 {
                    out.push(Tok::Lit(".".to_string()));
                } else {
                    out.push(Tok::Date(DatePart::SubSecond(zeros.min(3))));
                    i += zeros;
                }
            }
            Tok::Point => out.push(Tok::Lit(".".to_string())),
            Tok::Comma => out.push(Tok::Lit(",".to_string())),
            Tok::Digit(_) | Tok::Exp { .. } | Tok::General => return Err(XlError::Value),
            other => out.push(other.clone()),
        }
        i += 1;
    }
    section.tokens = out;
    Ok(())
}

fn is_minute(tokens: &[Tok], date_positions: &[usize], i: usize) -> bool {
    // The positions are in order: a search, where a scan made a code of 250,000 months
    // and days quadratic (a style's format code has no length limit).
    let k = date_positions.binary_search(&i).unwrap_or(0);
    let before = k
        .checked_sub(1)
        .map(|j| &tokens[date_positions[j]])
        .is_some_and(|t| matches!(t, Tok::Date(DatePart::Hour(_)) | Tok::Date(DatePart::Elapsed('h', _))));
    let after = date_positions
        .get(k + 1)
        .map(|&j| &tokens[j])
        .is_some_and(|t| matches!(t, Tok::Date(DatePart::Second(_)) | Tok::Date(DatePart::Elapsed('s', _))));
    before || after
}

fn follows_seconds(out: &[Tok]) -> bool {
    matches!(out.last(), Some(Tok::Date(DatePart::Second(_))) | Some(Tok::Date(DatePart::Elapsed('s', _))))
}

// ---------------------------------------------------------------------------------------
// Numbers

/// Decimal digits of a number rounded to `decimals` places: the integer digits without
/// leading zeros ("" for zero) and exactly `decimals` fraction digits.
pub fn fixed_digits(n: f64, decimals: usize) -> (String, String) {
    let (digits, exp) = significant_digits(n, 15);
    round_digits(&digits, exp, decimals)
}

/// [`fixed_digits`] on a number given as significant digits and the exponent of the
/// first one.
fn round_digits(digits: &str, exp: i32, decimals: usize) -> (String, String) {
    if digits == "0" {
        return (String::new(), "0".repeat(decimals));
    }
    // All digits, the decimal point after `point` of them.
    let mut all: Vec<u8> = digits.bytes().map(|b| b - b'0').collect();
    let mut point = exp + 1;
    if point < 0 {
        let mut padded = vec![0; (-point) as usize];
        padded.extend(all);
        all = padded;
        point = 0;
    }
    let point = point as usize;
    if all.len() < point + decimals {
        all.resize(point + decimals, 0);
    }
    let keep = point + decimals;
    let round_up = all.get(keep).is_some_and(|&d| d >= 5);
    all.truncate(keep);
    if round_up && !increment(&mut all) {
        all.insert(0, 1);
    }
    let int_len = all.len() - decimals;
    let int: String = all[..int_len].iter().map(|d| char::from(b'0' + d)).skip_while(|&c| c == '0').collect();
    let frac: String = all[int_len..].iter().map(|d| char::from(b'0' + d)).collect();
    (int, frac)
}

/// Adds one unit in the last place; false when it carries out of the first digit.
fn increment(digits: &mut [u8]) -> bool {
    for d in digits.iter_mut().rev() {
        if *d == 9 {
            *d = 0;
        } else {
            *d += 1;
            return true;
        }
    }
    false
}

/// How a number section lays out its digits.
#[derive(Clone, Debug)]
struct Layout {
    int_places: Vec<char>,
    frac_places: Vec<char>,
    exp_places: Vec<char>,
    grouping: bool,
    /// Divide by 1000 per comma after the last integer placeholder.
    thousands: i32,
    percents: i32,
}

fn layout(tokens: &[Tok]) -> Layout {
    #[cfg(test)]
    SECTIONS_LAID_OUT.with(|c| c.set(c.get() + 1));
    let exp_at = tokens.iter().position(|t| matches!(t, Tok::Exp { .. })).unwrap_or(tokens.len());
    let point_at = tokens[..exp_at].iter().position(|t| *t == Tok::Point).unwrap_or(exp_at);
    let digits = |range: &[Tok]| -> Vec<char> {
        range
            .iter()
            .filter_map(|t| match t {
                Tok::Digit(c) => Some(*c),
                _ => None,
            })
            .collect()
    };
    let int = &tokens[..point_at];
    let last_int_digit = int.iter().rposition(|t| matches!(t, Tok::Digit(_)));
    let first_int_digit = int.iter().position(|t| matches!(t, Tok::Digit(_)));
    let mut grouping = false;
    for (i, t) in int.iter().enumerate() {
        if let (Tok::Comma, Some(first), Some(last)) = (t, first_int_digit, last_int_digit) {
            grouping |= i > first && i < last;
        }
    }
    // Commas right after the last digit placeholder scale by 1000 each, whether that
    // placeholder is an integer or a decimal one (`#,##0,` and `0.0,,"M"`).
    let last_digit = tokens[..exp_at].iter().rposition(|t| matches!(t, Tok::Digit(_)));
    let thousands = last_digit.map_or(0, |last| {
        tokens[last + 1..exp_at]
            .iter()
            .take_while(|t| !matches!(t, Tok::Digit(_)))
            .filter(|t| **t == Tok::Comma)
            .count()
    }) as i32;
    Layout {
        int_places: digits(int),
        frac_places: digits(&tokens[point_at.min(exp_at)..exp_at]),
        exp_places: digits(tokens.get(exp_at..).unwrap_or(&[])),
        grouping,
        thousands,
        percents: tokens.iter().filter(|t| **t == Tok::Percent).count() as i32,
    }
}

/// The digits a number section shows: integer and fraction digits, and the exponent
/// for scientific formats.
struct Shown {
    int: String,
    frac: String,
    exponent: Option<i32>,
}

impl Shown {
    fn is_zero(&self) -> bool {
        self.int.bytes().all(|b| b == b'0') && self.frac.bytes().all(|b| b == b'0')
    }
}

fn shown_digits(value: f64, layout: &Layout, scientific: bool) -> XlResult<Shown> {
    let scaled = if value == 0.0 { 0.0 } else { value * 100f64.powi(layout.percents) / 1000f64.powi(layout.thousands) };
    // `%` signs scale past the largest double (1E+308 as "0%", or hundreds of `%`).
    if !scaled.is_finite() {
        return Err(XlError::Num);
    }
    let decimals = layout.frac_places.len();
    if !scientific {
        let (int, frac) = fixed_digits(scaled, decimals);
        return Ok(Shown { int, frac, exponent: None });
    }
    let (digits, exp) = significant_digits(scaled, 15);
    if digits == "0" {
        let (int, frac) = round_digits("0", 0, decimals);
        return Ok(Shown { int, frac, exponent: Some(0) });
    }
    // The exponent steps by the count of integer placeholders (##0.0E+0 is engineering).
    let step = layout.int_places.len().max(1) as i32;
    let mut exponent = exp.div_euclid(step) * step;
    loop {
        let (int, frac) = round_digits(&digits, exp - exponent, decimals);
        if int.len() as i32 > step {
            exponent += step;
            continue;
        }
        return Ok(Shown { int, frac, exponent: Some(exponent) });
    }
}

fn format_in_section(section: &Section, value: f64, signed: bool) -> XlResult<String> {
    let worked_out;
    let shape = match &section.shape {
        Some(shape) => shape,
        None => {
            worked_out = Shape::of(&section.tokens);
            &worked_out
        }
    };
    let negative = signed && value < 0.0;
    match shape {
        Shape::General => Ok(with_sign(general_in_section(section, value.abs()), negative)),
        Shape::Literal => {
            // Literal-only sections (`"zero"`), or `@` showing the number as text.
            let mut out = String::new();
            for t in &section.tokens {
                match t {
                    Tok::Lit(s) => out.push_str(s),
                    Tok::TextAt => out.push_str(&crate::eval::format::number_format::general(value.abs())),
                    Tok::Percent => out.push('%'),
                    _ => {}
                }
            }
            Ok(with_sign(out, negative))
        }
        Shape::Fraction(fraction) => {
            let text = fraction.render(&section.tokens, value.abs());
            Ok(with_sign(text.unwrap_or_else(|| crate::eval::format::number_format::general(value.abs())), negative))
        }
        Shape::FractionPastResolution => {
            Ok(with_sign(crate::eval::format::number_format::general(value.abs()), negative))
        }
        Shape::Digits { layout, scientific } => {
            let shown = shown_digits(value.abs(), layout, *scientific)?;
            let body = render(section, layout, &shown);
            Ok(with_sign(body, negative && !shown.is_zero()))
        }
    }
}

fn with_sign(body: String, negative: bool) -> String {
    if negative {
        format!("-{body}")
    } else {
        body
    }
}

fn general_in_section(section: &Section, value: f64) -> String {
    let mut out = String::new();
    for t in &section.tokens {
        match t {
            Tok::General => out.push_str(&general_text(value)),
            Tok::Lit(s) => out.push_str(s),
            _ => {}
        }
    }
    out
}

/// Writes the section's tokens with the digits in place.
fn render(section: &Section, layout: &Layout, shown: &Shown) -> String {
    let int_texts = integer_texts(&shown.int, &layout.int_places);
    let frac_texts = fraction_texts(&shown.frac, &layout.frac_places);
    let mut out = String::new();
    let (mut int_i, mut frac_i, mut exp_i) = (0, 0, 0);
    let mut region = 0; // 0 integer part, 1 fraction, 2 exponent
    for t in &section.tokens {
        match t {
            Tok::Digit(_) if region == 0 => {
                if !layout.grouping {
                    out.push_str(int_texts[int_i]);
                } else if int_i == 0 {
                    out.push_str(&group_thousands(&int_texts.concat()));
                }
                int_i += 1;
            }
            Tok::Digit(_) if region == 1 => {
                out.push_str(&frac_texts[frac_i]);
                frac_i += 1;
            }
            Tok::Digit(_) => {
                if exp_i == 0 {
                    out.push_str(&exponent_text(shown.exponent.unwrap_or(0), &layout.exp_places));
                }
                exp_i += 1;
            }
            Tok::Point if region == 0 => {
                if layout.int_places.is_empty() {
                    // `.#` shows 1.25 as "1.3": the integer digits need no placeholder.
                    out.push_str(&shown.int);
                }
                out.push('.');
                region = 1;
            }
            Tok::Exp { plus, small } => {
                out.push(if *small { 'e' } else { 'E' });
                let e = shown.exponent.unwrap_or(0);
                if e < 0 {
                    out.push('-');
                } else if *plus {
                    out.push('+');
                }
                region = 2;
            }
            Tok::Percent => out.push('%'),
            Tok::Lit(s) => out.push_str(s),
            Tok::Point => out.push('.'),
            Tok::Comma | Tok::TextAt | Tok::General | Tok::Date(_) => {}
        }
    }
    out
}

/// What each integer placeholder shows: digits assigned from the right, the leftmost
/// placeholder taking all the digits left over. Each is a slice of `int` or a pad, not a
/// text of its own: a code of thousands of placeholders is shown once per item of an array.
fn integer_texts<'a>(int: &'a str, places: &[char]) -> Vec<&'a str> {
    let starts: Vec<usize> = int.char_indices().map(|(i, _)| i).collect();
    let end_of = |d: usize| starts.get(d + 1).copied().unwrap_or(int.len());
    let mut texts = Vec::with_capacity(places.len());
    for (slot, &place) in places.iter().enumerate() {
        let to_the_right = places.len() - 1 - slot;
        texts.push(match starts.len().checked_sub(to_the_right + 1) {
            Some(d) if slot == 0 => &int[..end_of(d)],
            Some(d) => &int[starts[d]..end_of(d)],
            None => match place {
                '0' => "0",
                '?' => " ",
                _ => "",
            },
        });
    }
    texts
}

/// What each fraction placeholder shows: trailing zeros vanish under `#` and become
/// spaces under `?`.
fn fraction_texts(frac: &str, places: &[char]) -> Vec<String> {
    let digits: Vec<char> = frac.chars().collect();
    let mut texts: Vec<String> = digits.iter().map(|d| d.to_string()).collect();
    for (i, &place) in places.iter().enumerate().rev() {
        if place == '0' || digits[i] != '0' {
            break;
        }
        texts[i] = if place == '?' { " ".to_string() } else { String::new() };
    }
    texts
}

fn group_thousands(digits: &str) -> String {
    let lead = digits.len() - digits.trim_start_matches(' ').len();
    let (spaces, number) = digits.split_at(lead);
    let mut out = String::from(spaces);
    for (i, c) in number.chars().enumerate() {
        if i > 0 && (number.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

fn exponent_text(exponent: i32, places: &[char]) -> String {
    let min = places.iter().filter(|&&c| c == '0').count();
    zero_padded(i64::from(exponent.abs()), min)
}

/// `v` with zeros before its digits up to `width` characters, the sign counted, as
/// `format!("{v:0width$}")` writes it; by hand because that width is a u16 and a format code
/// may hold more than 65,535 zeros (`0E+000…`, `[sss…]`).
fn zero_padded(v: i64, width: usize) -> String {
    let digits = v.unsigned_abs().to_string();
    let sign = if v < 0 { "-" } else { "" };
    let zeros = width.saturating_sub(digits.len() + sign.len());
    let mut out = String::with_capacity(sign.len() + zeros + digits.len());
    out.push_str(sign);
    out.extend(std::iter::repeat_n('0', zeros));
    out.push_str(&digits);
    out
}

/// Excel's "General" in TEXT: at most 11 characters (sign aside), positional unless
/// scientific notation keeps more of the number.
pub fn general_text(n: f64) -> String {
    if n == 0.0 || !n.is_finite() {
        return "0".to_string();
    }
    let (digits, exp) = significant_digits(n, 15);
    let sign = if n < 0.0 { "-" } else { "" };
    let last_digit = exp - (digits.len() as i32 - 1);
    let int_len = (exp + 1).max(1);
    let sci_decimals = if exp.abs() >= 100 { 4 } else { 5 };
    let sci_unit = exp - sci_decimals;
    if int_len <= 11 {
        let decimals = (10 - int_len).max(0);
        let positional_exact = last_digit >= -decimals;
        if positional_exact || -decimals <= sci_unit {
            let (int, frac) = round_digits(&digits, exp, decimals as usize);
            let frac = frac.trim_end_matches('0');
            let int = if int.is_empty() { "0" } else { &int };
            return match frac {
                "" => format!("{sign}{int}"),
                f => format!("{sign}{int}.{f}"),
            };
        }
    }
    let (mut int, mut frac) = round_digits(&digits, 0, sci_decimals as usize);
    let mut exp = exp;
    if int.len() > 1 {
        // 9.999995 rounds up to 10.00000: 1E+(exp+1).
        exp += 1;
        (int, frac) = ("1".to_string(), String::new());
    }
    let frac = frac.trim_end_matches('0');
    let mantissa = match frac {
        "" => int,
        f => format!("{int}.{f}"),
    };
    let e_sign = if exp < 0 { '-' } else { '+' };
    format!("{sign}{mantissa}E{e_sign}{:02}", exp.abs())
}

// ---------------------------------------------------------------------------------------
// Dates and times

/// How a date section shows a serial: the sheet's calendar or a macro's.
type DateFormatter<'a> = &'a dyn Fn(&Section, f64) -> XlResult<String>;

/// A day's number in its week and its week's in the year, as VBA's Format numbers them for
/// `w` and `ww` by its `firstdayofweek` and `firstweekofyear` (the calendar's rules, which
/// DatePart shares, live beside DatePart).
pub type WeekNumbers<'a> = &'a dyn Fn(&DateTime) -> (i64, i64);

fn format_date(section: &Section, serial: f64, dates: DateSystem) -> XlResult<String> {
    if !(0.0..(LAST_SERIAL + 1) as f64).contains(&serial) {
        return Err(XlError::Value);
    }
    // Excel's codes have no `w`, so no week is ever asked for.
    Ok(write_date(section, &DateTime::from_serial(dates, serial, sub_second_digits(section)), &|_| (0, 0)))
}

fn format_vba_date(section: &Section, serial: f64, weeks: WeekNumbers) -> XlResult<String> {
    if !VBA_DATE_RANGE.contains(&serial) {
        return Err(XlError::Value);
    }
    Ok(write_date(section, &DateTime::from_vba_date(serial, sub_second_digits(section)), weeks))
}

/// The decimals of a second the section shows: the time is rounded to the finest unit
/// shown (whole seconds unless `.0`/`.00`/`.000`).
fn sub_second_digits(section: &Section) -> usize {
    section
        .tokens
        .iter()
        .find_map(|t| match t {
            Tok::Date(DatePart::SubSecond(n)) => Some(*n),
            _ => None,
        })
        .unwrap_or(0)
}

fn write_date(section: &Section, dt: &DateTime, weeks: WeekNumbers) -> String {
    let twelve_hour = section.tokens.iter().any(|t| matches!(t, Tok::Date(DatePart::AmPm { .. })));
    let mut out = String::new();
    for t in &section.tokens {
        match t {
            Tok::Date(DatePart::Weekday) => out.push_str(&weeks(dt).0.to_string()),
            Tok::Date(DatePart::Week) => out.push_str(&weeks(dt).1.to_string()),
            Tok::Date(part) => out.push_str(&date_part(*part, dt, twelve_hour)),
            Tok::Lit(s) => out.push_str(s),
            Tok::Percent => out.push('%'),
            _ => {}
        }
    }
    out
}

/// The en-US names of the months and of the days of the week (Sunday first), which VBA's
/// MonthName and WeekdayName give too.
pub(crate) const MONTHS: [&str; 12] = [
    "January",
    "February",
    "March",
    "April",
    "May",
    "June",
    "July",
    "August",
    "September",
    "October",
    "November",
    "December",
];

pub(crate) const WEEKDAYS: [&str; 7] = ["Sunday", "Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday"];

fn date_part(part: DatePart, dt: &DateTime, twelve_hour: bool) -> String {
    let month_name = MONTHS[dt.month as usize - 1];
    let weekday = WEEKDAYS[dt.weekday as usize];
    match part {
        DatePart::Year(n) if n <= 2 => format!("{:02}", dt.year % 100),
        DatePart::Year(_) => format!("{:04}", dt.year),
        DatePart::Month(1) => dt.month.to_string(),
        DatePart::Month(2) => format!("{:02}", dt.month),
        DatePart::Month(3) => month_name[..3].to_string(),
        DatePart::Month(5) => month_name[..1].to_string(),
        DatePart::Month(_) => month_name.to_string(),
        DatePart::Day(1) => dt.day.to_string(),
        DatePart::Day(2) => format!("{:02}", dt.day),
        DatePart::Day(3) => weekday[..3].to_string(),
        DatePart::Day(_) => weekday.to_string(),
        DatePart::Hour(n) => {
            let h = if twelve_hour { (dt.hour + 11) % 12 + 1 } else { dt.hour };
            padded(h, n)
        }
        DatePart::Minute(n) => padded(dt.minute, n),
        DatePart::Second(n) => padded(dt.second, n),
        DatePart::SubSecond(n) => {
            let digits = format!("{:03}", dt.millis);
            format!(".{}", &digits[..n])
        }
        DatePart::Elapsed(unit, n) => {
            let per = match unit {
                'h' => 3600.0,
                'm' => 60.0,
                _ => 1.0,
            };
            zero_padded((dt.total_seconds / per).floor() as i64, n)
        }
        // Numbered in `write_date`, by the Format call's week rules.
        DatePart::Weekday | DatePart::Week => String::new(),
        DatePart::DayOfYear => {
            let before: u32 = (1..dt.month).map(|m| crate::eval::dates::days_in_month(dt.year, m)).sum();
            (before + dt.day).to_string()
        }
        DatePart::Quarter => ((dt.month - 1) / 3 + 1).to_string(),
        DatePart::GeneralDate => vba_general_date(dt),
        DatePart::AmPm { short, lower } => {
            let pm = dt.hour >= 12;
            let text = match (short, pm) {
                (true, false) => "A",
                (true, true) => "P",
                (false, false) => "AM",
                (false, true) => "PM",
            };
            // Excel writes AM and PM in capitals however `am/pm` is typed (the tokenizer gives
            // it `lower` only in VBA's Format, which keeps the case typed); `a/p` keeps its case.
            if lower {
                text.to_ascii_lowercase()
            } else {
                text.to_string()
            }
        }
    }
}

/// VBA's General Date (`c`): the short date when the value has a day (or no time), the long
/// time when it has a time, both with a space between.
fn vba_general_date(dt: &DateTime) -> String {
    let has_time = dt.hour != 0 || dt.minute != 0 || dt.second != 0;
    // Day 0 of VBA's dates is 1899-12-30: a time alone.
    let has_day = !(dt.year == 1899 && dt.month == 12 && dt.day == 30 && has_time);
    let code = match (has_day, has_time) {
        (true, true) => format!("{VBA_SHORT_DATE} {VBA_LONG_TIME}"),
        (true, false) => VBA_SHORT_DATE.to_string(),
        _ => VBA_LONG_TIME.to_string(),
    };
    let section = parse_section(&code, Dialect::Excel).unwrap_or_default();
    write_date(&section, dt, &|_| (0, 0))
}

fn padded(v: u32, width: usize) -> String {
    if width >= 2 {
        format!("{v:02}")
    } else {
        v.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(n: f64, f: &str) -> String {
        NumberFormat::parse(f).unwrap().format_number(n, DateSystem::From1900).unwrap()
    }

    /// Every denominator tried in turn: the definition `closest_fraction` must agree with.
    fn closest_by_search(x: f64, max_denominator: u64) -> (u64, u64) {
        let mut best = ((x.round()) as u64, 1, (x - x.round()).abs());
        for d in 2..=max_denominator {
            let n = (x * d as f64).round();
            let error = (x - n / d as f64).abs();
            if error < best.2 {
                best = (n as u64, d, error);
            }
        }
        (best.0, best.1)
    }

    /// A fixed denominator past 2^53 (issue 30): a 21-digit one overflowed a u64 and the
    /// section showed garbage digits ("  /100000000000000000003" for 3.25). LibreOffice 7.4
    /// shows `# ?/100000000000000000000` as General ("3.25"), and so do we; denominators a
    /// double holds exactly keep their fractions (LibreOffice: "3 4/16", "3 262144/1048576").
    #[test]
    fn a_fixed_denominator_past_a_doubles_resolution_shows_general() {
        assert_eq!(fmt(3.25, "# ?/100000000000000000000"), "3.25");
        assert_eq!(fmt(-3.25, "# ?/1000000000000000000000"), "-3.25");
        assert_eq!(fmt(0.3, "?/18446744073709551616"), "0.3");
        assert_eq!(fmt(3.25, "# ?/16"), "3 4/16");
        assert_eq!(fmt(3.25, "# ?/1048576"), "3 262144/1048576");
        assert_eq!(fmt(3.25, "# ?/9007199254740992"), "3 2251799813685248/9007199254740992");
    }

    /// Zeros in a denominator pad it on the left, as LibreOffice 7 shows these
    /// (`=TEXT(x, code)` recalculated by `soffice --convert-to csv`); Microsoft's "Number
    /// format codes" page documents `?` in fractions only. Issue 30: `# ?/000` showed 1.5 as
    /// "1 1/200", the padding after the digits.
    #[test]
    #[allow(clippy::approx_constant)] // 3.14159 and 2.7182818 as typed into LibreOffice
    fn zeros_in_a_denominator_pad_it_on_the_left_as_libreoffice() {
        for (x, code, libreoffice) in [
            (1.5, "# ?/000", "1 1/002"),
            (0.25, "# ?/000", " 1/004"),
            (3.14159, "# ?/000", "3 16/113"),
            (0.123, "# ?/000", " 100/813"),
            (1.5, "# ??/00", "1  1/02"),
            (0.3, "0/00", "3/10"),
            (2.7182818, "# ???/000", "2 385/536"),
            (0.333, "?/00#", "332/997"),
            (0.333, "?/0#", "1/03"),
            (5.25, "# ?/00", "5 1/04"),
        ] {
            assert_eq!(fmt(x, code), libreoffice, "{x} in {code}");
        }
    }

    /// Every number format shows a number's 15 significant digits and zeros after them:
    /// "Excel therefore stores only 15 significant digits in a number, and changes digits
    /// after the fifteenth place to zeros" (Microsoft, KB 269370, "Last digits are changed to
    /// zeros when you type long numbers in cells of Excel", whose example is
    /// 1111222233334444 under `####-####-####-####` shown as 1111-2222-3333-4440). A
    /// fraction printed every digit of the double (TEXT(1E308, "# ?/?")) and split a 16-digit
    /// number's last digits into a fraction. LibreOffice 7.4 agrees with the 15-digit rule
    /// for `0`, `#,##0`, `0.00`, `0%`, `0,` and literals (the values below), not for
    /// fractions, where it prints the double's digits (`-123456789012345683968`), so for
    /// fractions Microsoft's rule is the oracle; the blanks after a whole number are its
    /// (`-100000000000000000000    ` for -1E+20 under `# ?/?`).
    #[test]
    fn numbers_past_fifteen_digits_show_fifteen_digits_then_zeros_in_every_format() {
        assert_eq!(fmt(1111222233334444.0, "####-####-####-####"), "1111-2222-3333-4440");
        let e308 = format!("1{}", "0".repeat(308));
        assert_eq!(fmt(1e308, "# ?/?"), format!("{e308}    "));
        assert_eq!(fmt(1e308, "0"), e308);
        assert_eq!(fmt(-1e20, "# ?/?"), "-100000000000000000000    ");
        assert_eq!(fmt(-1e20, "# ??/??"), "-100000000000000000000      ");
        assert_eq!(fmt(-1e20, "# ?/8"), "-100000000000000000000   ");
        assert_eq!(fmt(-1.2345678901234568e20, "# ?/?"), "-123456789012346000000    ");
        assert_eq!(fmt(1234567890123456.5, "# ?/?"), "1234567890123460    ");
        assert_eq!(fmt(1234567890123456.5, "?/?"), "1234567890123460/1");
        assert_eq!(fmt(-1234567890123.25, "# ?/4"), "-1234567890123 1/4");
        // An improper fraction's numerator past a u64 (it saturated to 18446744073709551615),
        // and past the largest double (shown as General).
        assert_eq!(fmt(1e20, "?/?"), "100000000000000000000/1");
        assert_eq!(fmt(1e308, "?/8"), "1E+308");
        // LibreOffice 7.4's values for the other kinds.
        assert_eq!(fmt(1.2345678901234568e20, "0"), "123456789012346000000");
        assert_eq!(fmt(1.2345678901234568e20, "#,##0"), "123,456,789,012,346,000,000");
        assert_eq!(fmt(1234567890123456.5, "0.00"), "1234567890123460.00");
        assert_eq!(fmt(1.2345678901234568e20, "0%"), "12345678901234600000000%");
        assert_eq!(fmt(9.87654321098765e16, "\"x\"0"), "x98765432109876500");
        assert_eq!(fmt(1234567890123456.5, "0,"), "1234567890123");
        assert_eq!(fmt(-1e20, "0.00E+00"), "-1.00E+20");
    }

    #[test]
    fn the_closest_fraction_is_the_one_a_search_of_every_denominator_finds() {
        // Numbers spread over [0, 3) by a fixed sequence, and some chosen ones: π, halves,
        // neighbours of fractions, the smallest shown numbers.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut xs: Vec<f64> = (0..3000)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64 * 3.0
            })
            .collect();
        xs.extend([
            0.0,
            0.5,
            1.0 / 3.0,
            std::f64::consts::PI,
            0.333_333_333,
            0.999_999_9,
            1e-7,
            5e-7,
            0.1 + 0.2,
            2.0 / 7.0,
        ]);
        for &x in &xs {
            for max in [1, 9, 99, 999] {
                assert_eq!(closest_fraction(x, max), closest_by_search(x, max), "{x} up to {max}");
            }
        }
        for &x in &xs[..40] {
            assert_eq!(closest_fraction(x, 99_999), closest_by_search(x, 99_999), "{x}");
        }
        assert_eq!(
            closest_fraction(std::f64::consts::PI - 3.0, 999_999),
            closest_by_search(std::f64::consts::PI - 3.0, 999_999)
        );
        // 355/113 for π's fraction part within three digits (Zu Chongzhi's ratio).
        assert_eq!(closest_fraction(std::f64::consts::PI - 3.0, 999), (16, 113));
    }

    #[test]
    fn decimal_rounding_is_half_away_from_zero_on_shown_digits() {
        assert_eq!(fixed_digits(2.675, 2), ("2".into(), "68".into()));
        assert_eq!(fixed_digits(0.5, 0), ("1".into(), "".into()));
        assert_eq!(fixed_digits(9.995, 2), ("10".into(), "00".into()));
        assert_eq!(fixed_digits(0.0004, 3), ("".into(), "000".into()));
        assert_eq!(fixed_digits(123.0, 0), ("123".into(), "".into()));
    }

    #[test]
    fn cnc_number_formats() {
        assert_eq!(fmt(12.3456, "0.000"), "12.346");
        assert_eq!(fmt(-0.5, "0.000"), "-0.500");
        assert_eq!(fmt(1234.5678, "#,##0.00"), "1,234.57");
        assert_eq!(fmt(0.1234, "0.0%"), "12.3%");
        assert_eq!(fmt(12345.678, "0.00E+00"), "1.23E+04");
        assert_eq!(fmt(0.000123, "0.00E+00"), "1.23E-04");
        assert_eq!(fmt(1.5, "+0.000;-0.000"), "+1.500");
        assert_eq!(fmt(-1.5, "+0.000;-0.000"), "-1.500");
        assert_eq!(fmt(0.0, "+0.000;-0.000;0"), "0");
        assert_eq!(fmt(25.0, "\"X\"0.0"), "X25.0");
        assert_eq!(fmt(7.0, "\\T00"), "T07");
        assert_eq!(fmt(-0.0001, "0.00"), "0.00");
        assert_eq!(fmt(12.0, "#.#"), "12.");
        assert_eq!(fmt(123456789012.0, "#,##,, \"M\""), "123,457 M");
        assert_eq!(fmt(-1234.5678, "#,##0.00"), "-1,234.57");
        assert_eq!(fmt(-0.25, "0%;(0%)"), "(25%)");
        assert_eq!(fmt(12.3, "000.000"), "012.300");
        assert_eq!(fmt(5.5, "?.??"), "5.5 ");
        assert_eq!(fmt(1e15, "#,##0"), "1,000,000,000,000,000");
        assert_eq!(fmt(12345.0, "##0.0E+0"), "12.3E+3");
        assert_eq!(fmt(1234567.0, "#,##0,"), "1,235");
        assert_eq!(fmt(150.0, "[>=100]\"big\";0"), "big");
        assert_eq!(fmt(-3.0, "[Red]0.0;[Blue]-0.0"), "-3.0");
        assert!(NumberFormat::parse("0.0\"/min\"").is_ok());
    }

    /// Scientific formats keep the case of the `E` as written, as the values Excel caches for
    /// cells formatted `0.00e+00` show (and VBA's Format documents for `e-` and `e+`); an `e`
    /// or `ee` alone is the year as `yyyy` ([MS-OI29500] 2.1.713 f).
    #[test]
    fn scientific_formats_keep_the_case_of_their_e() {
        assert_eq!(fmt(12345.678, "0.00E+00"), "1.23E+04");
        assert_eq!(fmt(0.000123, "0.00E-00"), "1.23E-04");
        assert_eq!(fmt(12345.678, "0.00e+00"), "1.23e+04");
        assert_eq!(fmt(0.000123, "0.0e-0"), "1.2e-4");
        assert_eq!(fmt(45000.0, "e"), "2023");
        assert_eq!(fmt(45000.0, "ee-mm-dd"), "2023-03-15");
        let vba = |n: f64, f: &str| NumberFormat::parse_vba(f).unwrap().format_number(n, DateSystem::From1900).unwrap();
        assert_eq!(vba(12345.678, "0.00e+00"), "1.23e+04");
        assert_eq!(vba(0.000123, "0.00e-00"), "1.23e-04");
        assert_eq!(vba(12345.678, "0.00E+00"), "1.23E+04");
    }

    /// Microsoft's "Number format codes": a comma after the digit placeholders scales by
    /// 1,000 (`#,` shows 12,000 as 12; `0.0,,` shows 12,200,000 as 12.2); `[h]`, `[mm]` and
    /// `[ss]` count elapsed hours, minutes and seconds past 24 and 60; `.00` after seconds
    /// shows hundredths.
    #[test]
    fn scaling_commas_and_elapsed_time_as_microsoft_documents_them() {
        assert_eq!(fmt(12000.0, "#,"), "12");
        assert_eq!(fmt(12200000.0, "0.0,,"), "12.2");
        assert_eq!(fmt(123456789.0, "0.0,,\"M\""), "123.5M");
        assert_eq!(fmt(25.02 / 24.0, "[h]:mm"), "25:01");
        assert_eq!(fmt((63.0 * 60.0 + 46.0) / 86400.0, "[mm]:ss"), "63:46");
        assert_eq!(fmt(0.01, "[ss]"), "864");
        assert_eq!(fmt((4.0 * 3600.0 + 36.0 * 60.0 + 3.75) / 86400.0, "h:mm:ss.00"), "4:36:03.75");
    }

    #[test]
    fn general_fits_eleven_characters() {
        assert_eq!(general_text(1.0 / 3.0), "0.333333333");
        assert_eq!(general_text(123456789012.0), "1.23457E+11");
        assert_eq!(general_text(25000000000.0), "25000000000");
        assert_eq!(general_text(-2.5e-9), "-2.5E-09");
        assert_eq!(general_text(-1e-8), "-0.00000001");
        assert_eq!(general_text(12345.6789), "12345.6789");
        assert_eq!(general_text(1e16), "1E+16");
    }

    #[test]
    fn dates_and_times() {
        assert_eq!(fmt(41181.0, "m/d/y"), "9/29/12");
        assert_eq!(fmt(41181.0, "dddd, mmmm d, yyyy"), "Saturday, September 29, 2012");
        assert_eq!(fmt(45000.75, "yyyy-mm-dd hh:mm:ss"), "2023-03-15 18:00:00");
        assert_eq!(fmt(0.5 + 1.0 / 86400.0, "h:mm:ss AM/PM"), "12:00:01 PM");
        assert_eq!(fmt(1.25, "[h]:mm"), "30:00");
        assert_eq!(fmt(60.0, "yyyy-mm-dd"), "1900-02-29");
        assert!(NumberFormat::parse("mm###").is_err());
    }

    #[test]
    fn long_date_codes_are_read_in_linear_time() {
        // A style's format code has no length limit. Each month of `m d m d …` looked for its
        // place among all the code's date letters, and each group of six `d` in VBA's Format
        // counted the whole run after it: 250,000 months took minutes, 400,000 `d` 10 s (not
        // timed here: a quadratic reading again is a hang the test run's limit ends). Serial
        // 1 is 1 January 1900: `m` the month and `d` the day without a leading zero.
        assert_eq!(fmt(1.0, &"m d ".repeat(250_000)), "1 1 ".repeat(250_000));
        // `dddddd` is VBA's long date (English, United States), six letters at a time.
        let long = NumberFormat::parse_vba(&"d".repeat(600_000)).unwrap().format_vba_number(1.0, &|_| (1, 1)).unwrap();
        assert_eq!(long, "Sunday, December 31, 1899".repeat(100_000));
    }
}
