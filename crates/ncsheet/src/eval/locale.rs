//! The user's locale, as Excel applies it at the edges of a workbook: how typed numbers,
//! dates and formulas are spelled, how values are shown, and how text becomes a number while
//! formulas compute (arithmetic on text, VALUE, NUMBERVALUE's defaults, TEXT's format codes).
//! Files stay canonical (en-US formulas, numbers as numbers): only what is typed, shown and
//! converted changes. A workbook owns its locale in its `Settings`; the evaluator reaches it
//! through `Env::locale`, never through a thread's or the process's state.
//!
//! The data is CLDR's (decimal and group symbols, date order, month and day names) with
//! Windows' choices where Excel follows Windows rather than CLDR: the group separator of the
//! space-grouping locales is shown as U+00A0 (CLDR's fr has U+202F; Excel on Windows shows a
//! no-break space), and `;` is the list separator of every decimal-comma locale.

use std::fmt;

use super::coerce::parse_plain_number;
use super::dates::{self, DateSystem};
use super::format::number_format::{general, ShownFormats};
use super::value::{Array, Value, XlError};

/// The order of day, month and year in a short date.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DateOrder {
    MonthDayYear,
    DayMonthYear,
    YearMonthDay,
}

/// Excel's built-in date format (14) as the file spells it: every locale shows it as its
/// short date ([`LocaleData::short_date`]).
pub const BUILTIN_DATE: &str = "m/d/yyyy";

/// Excel's built-in date and time format (22) as the file spells it: the short date and the
/// time in every locale.
pub const BUILTIN_DATE_TIME: &str = "m/d/yyyy h:mm";

/// One locale's facts (see the module doc for their source).
#[derive(Debug, PartialEq, Eq)]
pub struct LocaleData {
    /// The BCP 47 tag, as `--locale` takes it.
    pub tag: &'static str,
    pub english_name: &'static str,
    pub decimal: char,
    /// The group (thousands) separator as Excel shows it.
    pub group: char,
    /// Further group separators a user may type (a plain space where Excel shows U+00A0).
    pub group_typed: &'static [char],
    /// Between a formula's arguments.
    pub list: char,
    pub date_order: DateOrder,
    pub date_separator: char,
    /// The separators a typed date may have between its day, month and year (besides ISO's
    /// `2025-03-12`, which every locale reads), as LibreOffice set to the locale reads them:
    /// only `.` in de-DE and et-EE (`12/03/2025` is text there), `/`, `.` or `-` in fr-FR.
    pub date_separators_typed: &'static str,
    /// Day and month typed without a year, which mean the current year's day (LibreOffice's
    /// date acceptance patterns, as it reads them: de-DE `12.03.` with the last `.`, et-EE
    /// `12.03` with or without it, fr-FR `12/03`). `D` is the day, `M` the month.
    pub year_less: &'static [&'static str],
    /// The short date as a canonical format code (what Excel's built-in format 14 shows).
    pub short_date: &'static str,
    /// The time Excel's built-in date and time (22) shows after the short date, as
    /// LibreOffice set to the locale shows it (`hh:mm`; en-US and et-EE `h:mm`).
    pub short_time: &'static str,
    /// The months' full names, January first, between spaces.
    pub months: &'static str,
    /// The weekdays' full names, Sunday first, between spaces.
    pub days: &'static str,
    /// The months' short names (`mmm`), then the weekdays' (`ddd`), between spaces, as
    /// LibreOffice set to the locale shows them (the issue's oracle).
    pub months_short: &'static str,
    pub days_short: &'static str,
    /// The date letters this locale's users type in format codes, each with the canonical
    /// letter it stands for, either case (de-DE `TT.MM.JJJJ`, fr-FR `JJ/MM/AAAA`).
    pub format_letters: &'static [(char, char)],
    /// The currency symbol DOLLAR writes: before the amount in en-US (`$1,234.50`), after it
    /// and a space elsewhere here (`1.234,50 €`), as LibreOffice set to the locale shows it.
    pub currency: &'static str,
    /// TRUE and FALSE as this locale's Excel and LibreOffice show and read them (de-DE
    /// `WAHR`, `FALSCH`): LibreOffice's csv export in the locale writes them so.
    pub booleans: [&'static str; 2],
    /// The word for General in format codes besides `General` (de-DE and fr-FR `Standard`),
    /// as that Excel and LibreOffice read TEXT's code; empty: none.
    pub general: &'static str,
    /// What `AM/PM` in a format code shows before and after noon, as LibreOffice set to the
    /// locale shows it (de-DE `vorm.` and `nachm.`).
    pub am_pm: [&'static str; 2],
    /// The colour words of format codes (`[Red]`), between spaces, and the word before a
    /// colour's number (`[Color10]`), as LibreOffice set to the locale reads TEXT's code:
    /// de-DE `[Rot]` and `[Farbe10]` (and not `[Red]`), English in fr-FR and et-EE.
    pub colours: &'static str,
    pub colour_number: &'static str,
    /// What may part a weekday's full name from the date after it, which LibreOffice set to
    /// the locale reads as that date (`Mittwoch, 12. März 2025`; fr-FR `mercredi 12 mars
    /// 2025`, not `mercredi, 12 mars 2025`). The name itself is not checked against the date.
    pub after_weekday: &'static [&'static str],
    /// The format LibreOffice set to the locale gives a percent it reads from a csv, as a
    /// canonical code: two decimals, and the locale's space before `%` (de-DE U+00A0, fr-FR
    /// a plain space, et-EE none).
    pub percent_code: &'static str,
}

const SPACES: &[char] = &[' ', '\u{202F}'];

/// The colour words Excel reads in a format code: the eight of Microsoft's "Review guidelines
/// for customizing a number format" (LibreOffice set to en-US also reads `[Brown]` and
/// `[Grey]`, which Excel refuses: en-US follows Excel).
const EXCEL_COLOURS: &str = "Black Blue Cyan Green Magenta Red White Yellow";
/// LibreOffice's English colour words, which it reads in fr-FR and et-EE.
const ENGLISH_COLOURS: &str = "Black Blue Cyan Green Magenta Red White Yellow Brown Grey";
const GERMAN_COLOURS: &str = "Schwarz Blau Cyan Grün Magenta Rot Weiss Gelb Braun Grau";

static EN_US: LocaleData = LocaleData {
    tag: "en-US",
    english_name: "English (United States)",
    decimal: '.',
    group: ',',
    group_typed: &[],
    list: ',',
    date_order: DateOrder::MonthDayYear,
    date_separator: '/',
    // en-US reads dates through `dates::parse_date_text`, not these.
    date_separators_typed: "/-",
    year_less: &[],
    short_date: "m/d/yyyy",
    short_time: "h:mm",
    months: "January February March April May June July August September October November December",
    days: "Sunday Monday Tuesday Wednesday Thursday Friday Saturday",
    months_short: "Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec",
    days_short: "Sun Mon Tue Wed Thu Fri Sat",
    format_letters: &[],
    currency: "$",
    booleans: ["TRUE", "FALSE"],
    general: "",
    am_pm: ["AM", "PM"],
    colours: EXCEL_COLOURS,
    colour_number: "Color",
    after_weekday: &[", ", " "],
    percent_code: "0.00%",
};

/// What the decimal-comma locales share (each says what it does otherwise): a no-break space
/// between groups, `;` between arguments, day.month.year.
const DECIMAL_COMMA: LocaleData = LocaleData {
    tag: "",
    english_name: "",
    decimal: ',',
    group: '\u{A0}',
    group_typed: SPACES,
    list: ';',
    date_order: DateOrder::DayMonthYear,
    date_separator: '.',
    date_separators_typed: ".",
    year_less: &["D.M"],
    short_date: "dd.mm.yyyy",
    short_time: "hh:mm",
    months: "",
    days: "",
    months_short: "",
    days_short: "",
    format_letters: &[],
    currency: "€",
    booleans: ["", ""],
    general: "",
    am_pm: ["AM", "PM"],
    colours: ENGLISH_COLOURS,
    colour_number: "Color",
    after_weekday: &[", ", " "],
    percent_code: "0.00%",
};

static LOCALES: [&LocaleData; 8] = [
    &EN_US,
    &LocaleData {
        tag: "de-DE",
        english_name: "German (Germany)",
        group: '.',
        group_typed: &[],
        months: "Januar Februar März April Mai Juni Juli August September Oktober November Dezember",
        days: "Sonntag Montag Dienstag Mittwoch Donnerstag Freitag Samstag",
        months_short: "Jan Feb Mär Apr Mai Jun Jul Aug Sep Okt Nov Dez",
        days_short: "So Mo Di Mi Do Fr Sa",
        format_letters: &[('T', 'd'), ('J', 'y')],
        booleans: ["WAHR", "FALSCH"],
        general: "Standard",
        am_pm: ["vorm.", "nachm."],
        colours: GERMAN_COLOURS,
        colour_number: "Farbe",
        percent_code: "0.00\u{A0}%",
        year_less: &["D.M."],
        ..DECIMAL_COMMA
    },
    &LocaleData {
        tag: "fr-FR",
        english_name: "French (France)",
        date_separator: '/',
        date_separators_typed: "/.-",
        year_less: &["D/M"],
        short_date: "dd/mm/yyyy",
        months: "janvier février mars avril mai juin juillet août septembre octobre novembre décembre",
        days: "dimanche lundi mardi mercredi jeudi vendredi samedi",
        months_short: "janv. févr. mars avr. mai juin juil. août sept. oct. nov. déc.",
        days_short: "dim. lun. mar. mer. jeu. ven. sam.",
        format_letters: &[('J', 'd'), ('A', 'y')],
        booleans: ["VRAI", "FAUX"],
        after_weekday: &[" "],
        percent_code: "0.00 %",
        general: "Standard",
        ..DECIMAL_COMMA
    },
    &LocaleData {
        tag: "et-EE",
        english_name: "Estonian (Estonia)",
        // The day without a leading zero (`1.01.1998`), as LibreOffice set to et-EE shows it.
        short_date: "d.mm.yyyy",
        short_time: "h:mm",
        months: "jaanuar veebruar märts aprill mai juuni juuli august september oktoober november detsember",
        days: "pühapäev esmaspäev teisipäev kolmapäev neljapäev reede laupäev",
        months_short: "jaan veebr märts apr mai juuni juuli aug sept okt nov dets",
        days_short: "P E T K N R L",
        booleans: ["TÕENE", "VÄÄR"],
        // LibreOffice set to et-EE shows them without a last `.`.
        am_pm: ["e.l", "p.l"],
        year_less: &["D.M", "D.M."],
        ..DECIMAL_COMMA
    },
    &LocaleData {
        tag: "uk-UA",
        english_name: "Ukrainian (Ukraine)",
        months: "січень лютий березень квітень травень червень липень серпень вересень жовтень листопад грудень",
        days: "неділя понеділок вівторок середа четвер пʼятниця субота",
        months_short: "січ лют бер квт трв чер лип сер вер жов лис гру",
        currency: "грн.",
        days_short: "Нд Пн Вт Ср Чт Пт Сб",
        booleans: ["ІСТИНА", "БРЕХНЯ"],
        ..DECIMAL_COMMA
    },
    &LocaleData {
        tag: "sk-SK",
        english_name: "Slovak (Slovakia)",
        short_date: "d.m.yyyy",
        months: "január február marec apríl máj jún júl august september október november december",
        days: "nedeľa pondelok utorok streda štvrtok piatok sobota",
        months_short: "I II III IV V VI VII VIII IX X XI XII",
        days_short: "Ne Po Ut St Št Pi So",
        booleans: ["PRAVDA", "NEPRAVDA"],
        year_less: &["D.M."],
        ..DECIMAL_COMMA
    },
    &LocaleData {
        tag: "sr-RS",
        english_name: "Serbian (Latin, Serbia)",
        group: '.',
        group_typed: &[],
        short_date: "d.m.yyyy",
        months: "januar februar mart april maj jun jul avgust septembar oktobar novembar decembar",
        days: "nedelja ponedeljak utorak sreda četvrtak petak subota",
        months_short: "jan feb mar apr maj jun jul avg sep okt nov dec",
        currency: "RSD",
        days_short: "ned pon uto sre čet pet sub",
        booleans: ["TAČNO", "NETAČNO"],
        ..DECIMAL_COMMA
    },
    &LocaleData {
        tag: "hu-HU",
        english_name: "Hungarian (Hungary)",
        date_order: DateOrder::YearMonthDay,
        short_date: "yyyy.mm.dd.",
        months: "január február március április május június július augusztus szeptember október november december",
        days: "vasárnap hétfő kedd szerda csütörtök péntek szombat",
        months_short: "I. II. III. IV. V. VI. VII. VIII. IX. X. XI. XII.",
        currency: "Ft",
        days_short: "V H K Sze Cs P Szo",
        booleans: ["IGAZ", "HAMIS"],
        year_less: &["M.D", "M.D."],
        ..DECIMAL_COMMA
    },
];

/// What localizing a number shown under a format code needs to know of the code
/// ([`Locale::reading_of`]).
#[derive(Default)]
pub struct CodeReading {
    /// `None` for a number's code, or in the canonical locale (nothing to change but marks).
    date: Option<DateReading>,
}

/// A date or time code's parts that are shown in words or marks of a locale.
struct DateReading {
    /// Whose month and weekday names: the locale's, or the one the code's `[$-LCID]` names.
    names: Locale,
    /// The code's longest month is `mmm` (English `May` is then the short name).
    short_may: bool,
    /// `AM/PM` in either case.
    meridiem: bool,
    /// Fractions of a second (`ss.0`).
    fraction_of_seconds: bool,
}

/// A locale: a handle on static data, cheap to copy, with the year of the workbook's clock
/// when its settings fix one ([`Locale::at_year`]), which a date typed without a year falls in.
#[derive(Clone, Copy)]
pub struct Locale {
    data: &'static LocaleData,
    /// The year a day and month typed without a year fall in (`None`: the system clock's).
    year: Option<i32>,
}

/// Two locales are the same when their data is: the clock's year is the workbook's, not the
/// locale's.
impl PartialEq for Locale {
    fn eq(&self, other: &Locale) -> bool {
        self.data == other.data
    }
}

impl Eq for Locale {}

impl Default for Locale {
    fn default() -> Locale {
        Locale::EN_US
    }
}

impl fmt::Debug for Locale {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.data.tag)
    }
}

impl fmt::Display for Locale {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.data.tag)
    }
}

impl std::ops::Deref for Locale {
    type Target = LocaleData;
    fn deref(&self) -> &LocaleData {
        self.data
    }
}

/// Where a locale in force came from, for `ncsheet info`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FromEnvironment {
    pub locale: Locale,
    /// The variable and its value that chose it (`None`: none is set, or it says C/POSIX).
    pub variable: Option<(String, String)>,
    /// A value naming a locale ncsheet has no data for (then en-US is used).
    pub unknown: bool,
}

impl Locale {
    /// Excel's and the file format's own locale: formulas and numbers as files store them.
    pub const EN_US: Locale = Locale { data: &EN_US, year: None };

    /// Every locale ncsheet knows.
    pub fn all() -> impl Iterator<Item = Locale> {
        LOCALES.iter().map(|d| Locale { data: d, year: None })
    }

    /// This locale with `year` as the year a day and month typed without a year fall in (the
    /// year of the workbook's fixed clock: `Settings::locale_in_force`); `None`: the system
    /// clock's.
    pub fn at_year(self, year: Option<i32>) -> Locale {
        Locale { year, ..self }
    }

    /// The year a day and month typed without a year fall in: the workbook's clock's, else
    /// the system clock's (as Excel and LibreOffice read it, the value changes with the year).
    fn this_year(self) -> i64 {
        use chrono::Datelike;
        i64::from(self.year.unwrap_or_else(|| chrono::Local::now().year()))
    }

    /// The locale a tag names: `et-EE`, `et_EE`, `et_EE.UTF-8`, `et` (its country's),
    /// `sr-Latn-RS`; case aside. `C` and `POSIX` are en-US, as LibreOffice reads them.
    pub fn from_tag(tag: &str) -> Option<Locale> {
        let tag = tag.split(['.', '@']).next().unwrap_or(tag).replace('_', "-");
        if tag.eq_ignore_ascii_case("C") || tag.eq_ignore_ascii_case("POSIX") {
            return Some(Locale::EN_US);
        }
        let tag = tag.replace("-Latn", "").replace("-latn", "");
        let language = tag.split('-').next().unwrap_or("");
        Locale::all().find(|l| l.tag.eq_ignore_ascii_case(&tag)).or_else(|| {
            (!tag.contains('-')).then(|| Locale::all().find(|l| l.tag[..2].eq_ignore_ascii_case(language)))?
        })
    }

    /// The locale the environment asks for, read as LibreOffice reads it: LC_ALL, then
    /// LC_NUMERIC, then LANG; unset, empty, `C` and `POSIX` are en-US.
    pub fn from_environment(var: impl Fn(&str) -> Option<String>) -> FromEnvironment {
        for name in ["LC_ALL", "LC_NUMERIC", "LANG"] {
            let Some(value) = var(name).filter(|v| !v.is_empty()) else { continue };
            let found = Locale::from_tag(&value);
            let neutral = value == "C" || value == "POSIX" || value.starts_with("C.");
            let variable = (!neutral).then(|| (name.to_string(), value.clone()));
            return FromEnvironment { locale: found.unwrap_or(Locale::EN_US), variable, unknown: found.is_none() };
        }
        FromEnvironment { locale: Locale::EN_US, variable: None, unknown: false }
    }

    /// Whether numbers and formulas are spelled as files store them (`.` and `,`).
    pub fn is_canonical(self) -> bool {
        self.decimal == '.' && self.list == ','
    }

    /// Typed or computed text as a number, as this locale's Excel reads it (VALUE, arithmetic
    /// on text, a typed value): numbers with the locale's decimal mark and group separators,
    /// a percent, a currency sign; a fraction `1 1/2`; a date or time in the locale's order.
    /// Dates are serials of `system`, the workbook's date system.
    pub fn read_number(self, text: &str, system: DateSystem) -> Option<f64> {
        if self.is_canonical() {
            return super::coerce::parse_number(text, system);
        }
        self.read_plain_number(text).or_else(|| self.read_number_beyond_plain(text, system))
    }

    /// [`Locale::read_number`] of text already found to be no plain number of this
    /// non-canonical locale: a mixed fraction, a date or a time.
    pub fn read_number_beyond_plain(self, text: &str, system: DateSystem) -> Option<f64> {
        super::coerce::parse_mixed_fraction(text).or_else(|| self.read_date(text.trim(), system))
    }

    /// [`Locale::read_number`] without dates and times.
    pub fn read_plain_number(self, text: &str) -> Option<f64> {
        if self.is_canonical() {
            return parse_plain_number(text);
        }
        parse_plain_number(&self.canonical_number_text(text)?)
    }

    /// A number typed in this locale spelled as en-US reads it (`1 234,5` → `1,234.5`);
    /// `None` when the text has a mark the locale does not use in numbers (`0.8` in et-EE).
    fn canonical_number_text(self, text: &str) -> Option<String> {
        let t = text.trim_matches(|c: char| c.is_whitespace() || c == '\u{A0}');
        // Only this locale's currency sign makes text a number (LibreOffice set to de-DE
        // refuses `$1,5`).
        if t.chars().any(|c| matches!(c, '$' | '€' | '£') && !self.currency.contains(c)) {
            return None;
        }
        // A minus after the number (`1,5-`) is its sign, as LibreOffice set to the locale
        // reads it.
        let signed_after;
        let t = match t.strip_suffix('-') {
            Some(rest) if !rest.starts_with(['-', '+']) && rest.ends_with(|c: char| c.is_ascii_digit()) => {
                signed_after = format!("-{rest}");
                signed_after.as_str()
            }
            _ => t,
        };
        let is_group = |c: char| c == self.group || self.group_typed.contains(&c);
        let chars: Vec<char> = t.chars().collect();
        let digit = |i: Option<usize>| i.and_then(|i| chars.get(i)).is_some_and(char::is_ascii_digit);
        let mut out = String::with_capacity(t.len());
        for (i, &c) in chars.iter().enumerate() {
            let between_digits = digit(i.checked_sub(1)) && digit(Some(i + 1));
            match c {
                _ if c == self.decimal => out.push('.'),
                // A space groups digits; before a percent or a currency (`12,5 %`, `1,5 €`)
                // it is only a space.
                _ if is_group(c) && (between_digits || !is_space(c)) => out.push(','),
                _ if is_space(c) => out.push(' '),
                // The canonical marks that mean nothing here make the text no number.
                '.' | ',' => return None,
                c => out.push(c),
            }
        }
        Some(out)
    }

    /// A date, a time, or both (`12.03.2025`, `12.03.2025 13:30`, `2025-03-12`, `13:30`) in the
    /// locale's date order.
    pub fn read_date(self, text: &str, system: DateSystem) -> Option<f64> {
        self.read_date_text(text, system).map(dates::DateText::serial)
    }

    /// [`Locale::read_date`]'s date and time apart (DATEVALUE, TIMEVALUE).
    pub fn read_date_text(self, text: &str, system: DateSystem) -> Option<dates::DateText> {
        if self.is_canonical() {
            return dates::parse_date_text(system, text);
        }
        let text = &self.canonical_date_time_text(text)?;
        if let Some(date) = self.read_day(text, system) {
            return Some(dates::DateText { date: Some(date), time: None });
        }
        if let Some((named, _)) = self.named_month_date(text) {
            return Some(dates::DateText { date: Some(valid_serial(system, named)?), time: None });
        }
        if !text.contains(':') {
            return None;
        }
        let text = &self.canonical_fraction_of_seconds(text);
        if let Some((day, time)) = text.split_once(' ') {
            if let Some(date) = self.read_day(day.trim(), system) {
                let time = dates::parse_date_text(system, time.trim())?.time?;
                return Some(dates::DateText { date: Some(date), time: Some(time) });
            }
        }
        // A named month's date with its year typed, and a time (`12. März 2025 14:30`); a
        // day and month alone take no time (LibreOffice in de-DE refuses `12. März 14:30`).
        if let Some((day, time)) = text.rsplit_once(' ') {
            if let Some((named, true)) = self.named_month_date(day.trim()) {
                let time = dates::parse_date_text(system, time.trim())?.time?;
                return Some(dates::DateText { date: Some(valid_serial(system, named)?), time: Some(time) });
            }
        }
        // A time alone reads the same everywhere; a date in another order does not.
        dates::parse_date_text(system, text).filter(|t| t.date.is_none())
    }

    /// Date and time text as LibreOffice set to the locale reads it, in the spelling the
    /// readers below take: a weekday's full name before a date left out, ISO 8601's `T`
    /// between a date and a time as a space (`2025-03-12T14:30`), and the locale's words
    /// for before and after noon as en-US's ([`Locale::canonical_meridiem`]).
    pub(crate) fn canonical_date_time_text(self, text: &str) -> Option<String> {
        let text = self.without_weekday(text);
        let iso_date = |head: &str| {
            let parts: Vec<&str> = head.split('-').collect();
            parts.len() == 3
                && parts[0].len() == 4
                && parts.iter().all(|p| !p.is_empty() && p.len() <= 4 && p.bytes().all(|b| b.is_ascii_digit()))
        };
        let text = match text.split_once(['T', 't']) {
            Some((date, time)) if iso_date(date) && time.starts_with(|c: char| c.is_ascii_digit()) => {
                format!("{date} {time}")
            }
            _ => text.to_string(),
        };
        self.canonical_meridiem(&text)
    }

    /// `text` without a weekday's full name in this locale's words (either case) and what
    /// may follow it ([`LocaleData::after_weekday`]) before a date.
    fn without_weekday(self, text: &str) -> &str {
        for day in self.days.split(' ').filter(|d| !d.is_empty()) {
            let Some(head) = text.get(..day.len()).filter(|h| h.to_lowercase() == day.to_lowercase()) else { continue };
            let rest = &text[head.len()..];
            if let Some(date) = self.after_weekday.iter().find_map(|sep| rest.strip_prefix(sep)) {
                if date.starts_with(|c: char| c.is_alphanumeric()) {
                    return date;
                }
            }
        }
        text
    }

    /// A time with this locale's words for before and after noon (de-DE `2:30 nachm.`,
    /// et-EE `2:30 p.l`; either case, with or without a space) spelled with en-US's
    /// (`2:30 PM`), and an hour alone given its minutes (`2 nachm.` is 14:00), as LibreOffice
    /// set to the locale reads them; `None` for en-US's words where the locale has its own
    /// (LibreOffice set to de-DE or et-EE refuses `2:30 PM`).
    fn canonical_meridiem(self, text: &str) -> Option<String> {
        let Some(end) = text.rfind(|c: char| c.is_ascii_digit()).map(|i| i + 1) else { return Some(text.to_string()) };
        let (head, word) = (&text[..end], text[end..].trim_start_matches(is_space));
        let same = |a: &str, b: &str| a.to_lowercase() == b.to_lowercase();
        let own = self.am_pm.iter().position(|w| same(w, word));
        let at = match own {
            Some(at) if !word.is_empty() => at,
            _ if self.am_pm != EN_US.am_pm && EN_US.am_pm.iter().any(|w| same(w, word)) => return None,
            _ => return Some(text.to_string()),
        };
        // An hour alone is a time; after a date it is not (`12.03.2025 2 nachm.` is text).
        let minutes = if head.contains(':') || head.contains(is_space) { "" } else { ":00" };
        Some(format!("{head}{minutes} {}", EN_US.am_pm[at]))
    }

    /// Year, month and day of date text naming its month in this locale's words, either
    /// case, and whether all three were typed, as LibreOffice set to the locale reads it
    /// (probed in de-DE, fr-FR and et-EE, tests/locale.rs):
    /// - a day, then the month: `12. März`, `12.März`, `12 März` (fr-FR `12/mars`, not
    ///   `12. mars`: after the day only spaces or the locale's date separator), the current
    ///   year's day, as a day and month in numbers are;
    /// - the same with a year after a space (`12. März 2025`, `12.Mär.2025` after a short
    ///   name's `.`), or between dashes (`12-März-2025`, not `12-März`);
    /// - the month, then one number: that is a year, and the date its month's first day
    ///   (`März 12` is 1 March 2012, `Mär.25`, `März-5`);
    /// - the month, a day and a year, between spaces (`März 12 2025`).
    ///
    /// A short name may have a `.` after it (`Mär.`, et-EE `veebr.`); a full name may not
    /// (de-DE `12. März.`, fr-FR `mars. 12` are text), nor may any other separator follow.
    fn named_month_date(self, text: &str) -> Option<((i64, i64, i64), bool)> {
        use DatePiece::{Between, Month, Number};
        let pieces = self.date_pieces(text.trim())?;
        let spaces = |s: &str| s.chars().all(is_space);
        // After a day: spaces, or the date separator and spaces (`12. März`, `12/mars`).
        let after_day = |s: &str| s.strip_prefix(self.date_separator).map_or(spaces(s), spaces);
        // After a month, before its year: spaces, a dash, or the date separator where that is
        // no `.` (fr-FR `mars/12`); a short name's `.` is separator enough (`Mär.12`).
        let after_month = |s: &str| spaces(s) || s == "-" || (self.date_separator != '.' && self.is_date_separator(s));
        let date = match pieces.as_slice() {
            [Number(d, _), Between(a), Month(m, _)] if after_day(a) => ((self.this_year(), *m, *d), false),
            [Number(d, _), Between(a), Month(m, dot), Between(b), Number(y, n)]
                if (after_day(a) && spaces(b)) || (a == "-" && b == "-" && !dot) =>
            {
                ((full_year(*y, *n)?, *m, *d), true)
            }
            [Number(d, _), Between(a), Month(m, true), Number(y, n)] if after_day(a) => {
                ((full_year(*y, *n)?, *m, *d), true)
            }
            [Month(m, _), Between(a), Number(y, n), rest @ ..] if after_month(a) && self.ends_date(rest) => {
                ((full_year(*y, *n)?, *m, 1), false)
            }
            [Month(m, true), Number(y, n), rest @ ..] if self.ends_date(rest) => ((full_year(*y, *n)?, *m, 1), false),
            [Month(m, _), Between(a), Number(d, _), Between(b), Number(y, n)] if spaces(a) && spaces(b) => {
                ((full_year(*y, *n)?, *m, *d), true)
            }
            _ => return None,
        };
        Some(date)
    }

    /// Whether what follows a date's last number may end it: nothing, or the date separator
    /// (de-DE `März 12.`).
    fn ends_date(self, rest: &[DatePiece]) -> bool {
        match rest {
            [] => true,
            [DatePiece::Between(s)] => self.is_date_separator(s),
            _ => false,
        }
    }

    fn is_date_separator(self, s: &str) -> bool {
        s.len() == self.date_separator.len_utf8() && s.starts_with(self.date_separator)
    }

    /// Date text as numbers, month names and what stands between them; `None` when a word is
    /// no month's name here or a number has more than four digits.
    fn date_pieces(self, text: &str) -> Option<Vec<DatePiece>> {
        let mut pieces = Vec::new();
        let mut rest = text;
        while let Some(c) = rest.chars().next() {
            let end = if c.is_ascii_digit() {
                let end = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
                pieces.push(DatePiece::Number(rest[..end].parse().ok()?, end));
                end
            } else if c.is_alphabetic() {
                let (month, end, short) = self.month_at(rest)?;
                // LibreOffice reads a `.` after a short name as part of it.
                let dot = short && rest[end..].starts_with('.');
                pieces.push(DatePiece::Month(month, dot));
                end + usize::from(dot)
            } else {
                let end = rest.find(char::is_alphanumeric).unwrap_or(rest.len());
                pieces.push(DatePiece::Between(rest[..end].to_string()));
                end
            };
            rest = &rest[end..];
        }
        pieces.iter().all(|p| !matches!(p, DatePiece::Number(_, n) if *n > 4)).then_some(pieces)
    }

    /// The month (1 to 12) whose name `text` starts with as a whole word, either case, the
    /// name's length in `text` and whether it is the short name. Full names are tried first
    /// (fr-FR `mars` is both, so `mars.` is the full name and a `.`), and the short name
    /// `Sep` stands for `Sept` and the other way round, as LibreOffice reads them.
    fn month_at(self, text: &str) -> Option<(i64, usize, bool)> {
        let find = |names: &str| names.split(' ').enumerate().find_map(|(i, name)| Some((i, word_at(text, name)?)));
        if let Some((i, len)) = find(self.months) {
            return Some((i as i64 + 1, len, false));
        }
        if let Some((i, len)) = find(self.months_short) {
            return Some((i as i64 + 1, len, true));
        }
        let september = self.months_short.split(' ').nth(8)?.to_lowercase();
        let other = match september.as_str() {
            "sep" => "sept",
            "sept" => "sep",
            _ => return None,
        };
        word_at(text, other).map(|len| (9, len, true))
    }

    /// A time's fraction of a second with this locale's decimal mark (`14:30:15,5`) as en-US
    /// writes it (`14:30:15.5`): the mark after the last `:`.
    fn canonical_fraction_of_seconds(self, text: &str) -> String {
        match text.rfind(':') {
            Some(colon) => format!("{}{}", &text[..colon], text[colon..].replace(self.decimal, ".")),
            None => text.to_string(),
        }
    }

    /// A short date in the locale's order with one of its typed separators between its parts
    /// (and ISO's `2025-03-12`, which every Excel and LibreOffice reads), or a day and month
    /// without a year in one of the locale's forms, as its serial.
    fn read_day(self, text: &str, system: DateSystem) -> Option<i64> {
        valid_serial(system, self.full_date(text).or_else(|| self.year_less_date(text))?)
    }

    /// Year, month and day of a date with all three typed (`12.03.2025`, hu-HU
    /// `2025.03.12.`): one separator throughout, one this locale reads in dates.
    fn full_date(self, text: &str) -> Option<(i64, i64, i64)> {
        let t = text.strip_suffix('.').unwrap_or(text);
        let separator = t.chars().find(|c| matches!(c, '.' | '/' | '-'))?;
        let parts: Vec<&str> = t.split(separator).map(str::trim).collect();
        let [a, b, c] = parts.as_slice() else { return None };
        let iso = separator == '-' && a.len() == 4;
        if !iso && !self.date_separators_typed.contains(separator) {
            return None;
        }
        let (a_n, b_n, c_n) = (date_number(a)?, date_number(b)?, date_number(c)?);
        let (year, month, day, year_text) = if iso || self.date_order == DateOrder::YearMonthDay {
            (a_n, b_n, c_n, *a)
        } else if self.date_order == DateOrder::DayMonthYear {
            (c_n, b_n, a_n, *c)
        } else {
            (c_n, a_n, b_n, *c)
        };
        Some((full_year(year, year_text.len())?, month, day))
    }

    /// Year, month and day of a day and month typed without a year in one of this locale's
    /// forms ([`LocaleData::year_less`]): the current year's, as Excel and LibreOffice read
    /// it (the value changes with the year, as it does there).
    fn year_less_date(self, text: &str) -> Option<(i64, i64, i64)> {
        self.year_less.iter().find_map(|form| {
            let form: Vec<char> = form.chars().collect();
            let separator = form[1];
            let body = if form.len() == 4 { text.strip_suffix(separator)? } else { text };
            let (first, second) = body.split_once(separator)?;
            let part = |s: &str| (s.trim().len() <= 2).then(|| date_number(s.trim()))?;
            let (first, second) = (part(first)?, part(second)?);
            let (month, day) = if form[0] == 'D' { (second, first) } else { (first, second) };
            (month <= 12 && day <= 31).then(|| (self.this_year(), month, day))
        })
    }

    /// A value with its text read as a number in this locale, for arithmetic: text that is no
    /// number here is `#VALUE!`; other values, and everything under en-US, unchanged.
    pub fn numbers_for_arithmetic(self, v: Value, system: DateSystem) -> Value {
        if self.is_canonical() {
            return v;
        }
        match v {
            Value::Text(s) => self.read_number(&s, system).map_or(Value::Error(XlError::Value), Value::Number),
            Value::Array(a) if a.data.iter().any(|x| matches!(x, Value::Text(_))) => {
                let data = a.data.iter().map(|x| self.numbers_for_arithmetic(x.clone(), system)).collect();
                Value::Array(std::rc::Rc::new(Array::new(a.rows, a.cols, data)))
            }
            v => v,
        }
    }

    /// A value with its numbers as text as this locale's Excel joins them (`=A1&""` is
    /// `0,8` in et-EE); other values unchanged.
    pub fn numbers_for_joining(self, v: Value) -> Value {
        if self.is_canonical() {
            return v;
        }
        match v {
            Value::Number(n) => Value::Text(self.localize_shown(&general(n)).into()),
            Value::Array(a) if a.data.iter().any(|x| matches!(x, Value::Number(_))) => {
                let data = a.data.iter().map(|x| self.numbers_for_joining(x.clone())).collect();
                Value::Array(std::rc::Rc::new(Array::new(a.rows, a.cols, data)))
            }
            v => v,
        }
    }

    /// A number as en-US shows it (`1,234.5`, `-0.8`, `1.5E+20`, `12.5%`) with this locale's
    /// marks (`1 234,5`). Only a `.` or `,` after a digit and before a digit is a mark: the
    /// other text a format code adds (`kg.`, `m/s`) is kept.
    pub fn localize_shown(self, shown: &str) -> String {
        if self.is_canonical() {
            return shown.to_string();
        }
        let chars: Vec<char> = shown.chars().collect();
        let digit = |i: Option<usize>| i.and_then(|i| chars.get(i)).is_some_and(char::is_ascii_digit);
        let mut out = String::with_capacity(shown.len() + 4);
        for (i, &c) in chars.iter().enumerate() {
            let between_digits = digit(i.checked_sub(1)) && digit(Some(i + 1));
            match c {
                '.' if between_digits => out.push(self.decimal),
                ',' if between_digits => out.push(self.group),
                c => out.push(c),
            }
        }
        out
    }

    /// A number as a cell with the number format `code` shows it in this locale: its marks,
    /// and the short date for Excel's built-in date format (format 14, which follows the
    /// system's short date).
    pub fn shown_number(self, n: f64, code: Option<&str>, system: DateSystem) -> String {
        self.shown_number_with(&mut ShownFormats::default(), n, code, system)
    }

    /// [`Locale::shown_number`] for one of many cells, each code parsed once in `formats`.
    pub fn shown_number_with(
        self,
        formats: &mut ShownFormats,
        n: f64,
        code: Option<&str>,
        system: DateSystem,
    ) -> String {
        let date_time;
        let code = match code {
            Some(BUILTIN_DATE | "mm-dd-yy" | "m/d/yy") => Some(self.short_date),
            // Excel's built-in date and time (22) is the short date and the time, as
            // LibreOffice set to the locale shows it; in en-US with the year's four digits
            // (`3/12/2025 14:30`, as Excel and LibreOffice show it, not the file's `m/d/yy`).
            Some(BUILTIN_DATE_TIME | "m/d/yy h:mm") => {
                date_time = self.date_time_code();
                Some(date_time.as_str())
            }
            // `mmmmm` shows the first letter of the month's name in the locale's words.
            Some(code) if !self.is_canonical() && code.contains(['m', 'M']) && longest_run(code, 'm') == 5 => {
                date_time = month_letter_code(code);
                Some(date_time.as_str())
            }
            code => code,
        };
        let shown = formats.shown(n, code, system);
        self.localize_formatted(code.unwrap_or(""), &shown)
    }

    /// TRUE or FALSE as this locale shows it (de-DE `WAHR`, fr-FR `FAUX`).
    pub fn boolean_name(self, b: bool) -> &'static str {
        self.booleans[usize::from(!b)]
    }

    /// This locale's word for TRUE or FALSE, either case (`wahr`, `Faux`), as its Excel and
    /// LibreOffice read a typed value or a csv field.
    pub fn read_boolean(self, text: &str) -> Option<bool> {
        let upper = text.trim().to_uppercase();
        self.booleans.iter().position(|word| *word == upper).map(|i| i == 0)
    }

    /// A value other than a number as a cell shows it here: booleans in the locale's words,
    /// text and errors as they are (LibreOffice names errors in English in every locale).
    /// Numbers take their cell's format ([`Locale::shown_number`]).
    pub fn shown_value(self, v: &Value) -> String {
        match v {
            Value::Bool(b) => self.boolean_name(*b).to_string(),
            Value::Array(a) => a.data.first().map_or_else(String::new, |first| self.shown_value(first)),
            v => v.to_string(),
        }
    }

    /// The format code of a date with a time (Excel's built-in format 22) in this locale.
    fn date_time_code(self) -> String {
        format!("{} {}", self.short_date, self.short_time)
    }

    /// An amount DOLLAR shows (`digits` already in the locale's marks, without a sign): en-US
    /// `$1,234.50` and `($1,234.50)`; elsewhere `1.234,50 €` and `-1.234,50 €`.
    pub fn currency_amount(self, digits: &str, negative: bool) -> String {
        match (self.data == &EN_US, negative) {
            (true, false) => format!("{}{digits}", self.currency),
            (true, true) => format!("({}{digits})", self.currency),
            (false, false) => format!("{digits} {}", self.currency),
            (false, true) => format!("-{digits} {}", self.currency),
        }
    }

    /// A date as en-US shows it with its month's and weekday's full names (`mmmm`, `dddd`)
    /// in this locale's words (`märts`, `kolmapäev`).
    pub fn localize_names(self, shown: &str) -> String {
        self.localize_names_for("mmmm", shown)
    }

    /// A date the format `code` showed in en-US with its month and weekday names in this
    /// locale's words: full names (`mmmm`, `dddd`) and short ones (`mmm`, `ddd`), word by
    /// word (`Mon` is a word, not the start of `Montag`). English `May` is both; it is the
    /// short name when the code's longest month is `mmm`.
    pub fn localize_names_for(self, code: &str, shown: &str) -> String {
        // A code tagged with a language (`[$-409]mmmm d, yyyy`) names months in that one.
        let names = tagged_language(code).unwrap_or(self);
        names_in(names, longest_run(code, 'm') == 3, shown)
    }

    /// A format code with this locale's date letters (de-DE `TT.MM.JJJJ`) in the canonical
    /// ones (`dd.mm.yyyy`); quoted text, `\`-escapes, `[…]` and AM/PM are left alone.
    ///
    /// The canonical letters the locale replaces (`d` and `y` in de-DE and fr-FR) are no date
    /// letters there: Excel reads TEXT's code with the letters of the user's regional
    /// settings and shows any other letter as it is (TEXT(NOW(),"dd/mm/yyyy") gives
    /// `01/02/yyyy` on Norwegian Windows, whose year letter is `å`: Bullen et al., Excel 2007
    /// VBA Programmer's Reference, "The TEXT worksheet function"). LibreOffice set to the
    /// locale shows `dd\ mmm\ yyyy` so too (`dd Mär yyyy`) but guesses other such codes
    /// are en-US ones.
    fn canonical_date_letters(self, code: &str) -> String {
        // `General` (fr-FR `Standard`) holds letters that are no date here.
        if self.format_letters.is_empty() || code.to_ascii_lowercase().contains("general") {
            return code.to_string();
        }
        rewrite_code_letters(code, |chars, i, out| {
            let rest: String = chars[i..].iter().take(5).collect::<String>().to_ascii_uppercase();
            if rest.starts_with("AM/PM") || rest.starts_with("A/P") {
                let n = if rest.starts_with("AM/PM") { 5 } else { 3 };
                out.extend(&chars[i..i + n]);
                return n;
            }
            let c = chars[i];
            match self.format_letters.iter().find(|(l, _)| l.eq_ignore_ascii_case(&c)) {
                Some((_, canonical)) => out.push(*canonical),
                None if self.replaces_letter(c) => out.extend(['\\', c]),
                None => out.push(c),
            }
            1
        })
    }

    /// Whether `c` is a canonical date letter this locale spells otherwise (de-DE `d`, `y`).
    fn replaces_letter(self, c: char) -> bool {
        self.format_letters.iter().any(|(_, canonical)| canonical.eq_ignore_ascii_case(&c))
    }

    /// The first colour word of TEXT's `code` (`[Red]`) that names a colour in another
    /// locale's words and not in this one's: LibreOffice set to de-DE refuses `[Red]` and
    /// `[Color10]` (Err:502) and reads `[Rot]` and `[Farbe10]`; set to fr-FR, et-EE or
    /// en-US, the other way round (en-US also refuses `[Brown]`, as Excel does).
    pub fn foreign_colour(self, code: &str) -> Option<String> {
        bracket_words(code)
            .into_iter()
            .find(|word| names_a_colour(word) && !self.data.names_colour(word))
            .map(|word| format!("[{word}]"))
    }

    /// What a canonical format `code` showed (`shown`) with this locale's marks: numbers
    /// localized, dates left as their code spells them.
    pub fn localize_formatted(self, code: &str, shown: &str) -> String {
        self.localize_read(&self.reading_of(code), shown)
    }

    /// What [`Locale::localize_read`] needs to know of the code `code`, read once for all the
    /// numbers shown under it (TEXT over an array): read per number, the code was scanned
    /// again for every item.
    pub fn reading_of(self, code: &str) -> CodeReading {
        if self.is_canonical() || !is_date_code(code) {
            return CodeReading::default();
        }
        let lower = code.to_ascii_lowercase();
        CodeReading {
            date: Some(DateReading {
                names: tagged_language(code).unwrap_or(self),
                short_may: longest_run(code, 'm') == 3,
                meridiem: lower.contains("am/pm"),
                fraction_of_seconds: lower.contains("s.0"),
            }),
        }
    }

    /// What a canonical format code, read by [`Locale::reading_of`], showed (`shown`) with
    /// this locale's marks: numbers localized, dates left as their code spells them.
    pub fn localize_read(self, reading: &CodeReading, shown: &str) -> String {
        if self.is_canonical() {
            return shown.to_string();
        }
        if let Some(date) = &reading.date {
            let named = month_letters(&names_in(date.names, date.short_may, shown));
            let named = if date.meridiem { self.localize_meridiem(&named) } else { named };
            let named = if date.fraction_of_seconds { self.localize_fraction_of_seconds(&named) } else { named };
            return literal_marks(&named);
        }
        literal_marks(&self.localize_shown(shown))
    }

    /// A time that `AM/PM` in its code showed (`02:24 PM`) with this locale's words for before
    /// and after noon (de-DE `02:24 nachm.`), either case in the code.
    fn localize_meridiem(self, shown: &str) -> String {
        if self.am_pm == EN_US.am_pm {
            return shown.to_string();
        }
        replace_words(shown, |word| match word.to_ascii_uppercase().as_str() {
            "AM" => Some(self.am_pm[0]),
            "PM" => Some(self.am_pm[1]),
            _ => None,
        })
    }

    /// A time shown with fractions of a second (`ss.000`: `14:30:27.500`) with the locale's
    /// decimal mark (`14:30:27,500`), as LibreOffice set to the locale shows it: the first
    /// `.` between digits after the time's `:`.
    fn localize_fraction_of_seconds(self, shown: &str) -> String {
        let chars: Vec<char> = shown.chars().collect();
        let digit = |i: usize| chars.get(i).is_some_and(char::is_ascii_digit);
        let Some(colon) = chars.iter().position(|&c| c == ':') else { return shown.to_string() };
        let mark = (colon..chars.len()).find(|&i| chars[i] == '.' && i > 0 && digit(i - 1) && digit(i + 1));
        chars.iter().enumerate().map(|(i, &c)| if Some(i) == mark { self.decimal } else { c }).collect()
    }

    /// A number format code as this locale's user types it (TEXT's second argument) in the
    /// canonical spelling: in a decimal-comma locale `0,00` is two decimals (`0.00`) and
    /// `#.##0` or `# ##0` groups thousands (`#,##0`). Date and time codes, quoted text,
    /// `\`-escaped characters and `[…]` sections are left as they are.
    pub fn canonical_format_code(self, code: &str) -> String {
        if self.is_canonical() {
            return code.to_string();
        }
        let code = &self.canonical_date_letters(&self.canonical_general(code));
        if is_date_code(code) {
            return month_letter_code(&self.canonical_fraction_of_seconds_code(code));
        }
        if self.reads_as_en_us(code) {
            return code.to_string();
        }
        let chars: Vec<char> = code.chars().collect();
        let placeholder = |i: Option<usize>| i.and_then(|i| chars.get(i)).is_some_and(|c| matches!(c, '0' | '#' | '?'));
        // In a fraction (`# ?/?`) a space parts the whole number from the fraction, as
        // LibreOffice set to fr-FR or et-EE shows it (`1 3/4`): it groups nothing.
        let fraction = has_unquoted_slash(code);
        let is_group = |c: char| (c == self.group || self.group_typed.contains(&c)) && !(fraction && is_space(c));
        // Whether the group marks before `i` (if any) follow a digit placeholder.
        // Whether the group marks from `i` on are followed by a `[$…]` currency tag.
        let before_currency_tag = |i: usize| {
            let next = chars[i..].iter().position(|&c| !is_group(c)).map(|j| i + j);
            next.is_some_and(|j| chars[j..].starts_with(&['[', '$']))
        };
        let after_placeholder = |i: usize| {
            let before = chars[..i].iter().rposition(|&c| !is_group(c));
            before.is_some_and(|j| placeholder(Some(j)))
        };
        let mut out = String::with_capacity(code.len());
        let mut section = Section::default();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            match c {
                '"' => {
                    let end = chars[i + 1..].iter().position(|&q| q == '"').map_or(chars.len(), |p| i + 2 + p);
                    out.extend(chars[i..end.min(chars.len())].iter().map(|&c| protected_mark(c)));
                    i = end;
                    continue;
                }
                '[' => {
                    let end = chars[i..].iter().position(|&q| q == ']').map_or(chars.len(), |p| i + p + 1);
                    out.extend(&chars[i..end]);
                    i = end;
                    continue;
                }
                '\\' => {
                    out.extend(chars[i..(i + 2).min(chars.len())].iter().map(|&c| protected_mark(c)));
                    i += 2;
                    continue;
                }
                _ if c == self.decimal => {
                    section.decimal = true;
                    out.push('.');
                }
                // A group mark among the decimals groups the integer part, as LibreOffice set
                // to the locale reads it (de-DE `#,##0.000` shows `1.234,500000`).
                _ if is_group(c) && placeholder(i.checked_sub(1)) && placeholder(Some(i + 1)) => {
                    if section.decimal {
                        section.group_among_decimals = true;
                    } else {
                        section.grouped = true;
                        out.push(',');
                    }
                }
                // Group separators after the last placeholder scale by 1000 each, as `,` does:
                // a space too where spaces group digits (fr-FR `0,0 €` shows 1234.5 as
                // `1,2€`, `0  ` divides by a million), as LibreOffice set to the locale does;
                // but a space before a currency tag is text (`#.##0,00 [$€-407]` shows
                // `1.234,50 €` there).
                _ if is_group(c) && after_placeholder(i) && !before_currency_tag(i) => out.push(','),
                // A mark that is neither the decimal nor the group here is a literal character.
                '.' | ',' => {
                    out.push('\\');
                    out.push(protected_mark(c));
                }
                ';' => {
                    section.finish(&mut out);
                    section = Section::default();
                    out.push(c);
                }
                c => {
                    if placeholder(Some(i)) && !section.decimal && section.integer_at.is_none() {
                        section.integer_at = Some(out.len());
                    }
                    out.push(c);
                }
            }
            i += 1;
        }
        section.finish(&mut out);
        out
    }

    /// A format code with the locale's word for General (de-DE `Standard`, either case, not
    /// in quotes) as `General`.
    fn canonical_general(self, code: &str) -> String {
        if self.general.is_empty() {
            return code.to_string();
        }
        let word: Vec<char> = self.general.chars().collect();
        let chars: Vec<char> = code.chars().collect();
        let mut out = String::with_capacity(code.len());
        let (mut quoted, mut i) = (false, 0);
        while i < chars.len() {
            let here = chars.get(i..i + word.len());
            let is_word = here.is_some_and(|h| h.iter().zip(&word).all(|(a, b)| a.to_lowercase().eq(b.to_lowercase())));
            if !quoted && is_word {
                out.push_str("General");
                i += word.len();
                continue;
            }
            quoted ^= chars[i] == '"';
            out.push(chars[i]);
            i += 1;
        }
        out
    }

    /// A time code with the fraction of a second after this locale's decimal mark
    /// (`hh:mm:ss,00`) as the file spells it (`hh:mm:ss.00`), as LibreOffice set to the
    /// locale reads TEXT's code: the mark between an `s` and a `0`, not in quotes.
    fn canonical_fraction_of_seconds_code(self, code: &str) -> String {
        let chars: Vec<char> = code.chars().collect();
        let mut quoted = false;
        let mut out = String::with_capacity(code.len());
        for (i, &c) in chars.iter().enumerate() {
            quoted ^= c == '"';
            let after_seconds = i > 0 && chars[i - 1].eq_ignore_ascii_case(&'s');
            let fraction = !quoted && c == self.decimal && after_seconds && chars.get(i + 1) == Some(&'0');
            out.push(if fraction { '.' } else { c });
        }
        out
    }

    /// Whether a number format code is read as en-US writes it: where `.` is neither the
    /// decimal nor a group mark (fr-FR, et-EE), a `.` between digit placeholders with no
    /// decimal comma after it (`00.00`, `#,##0.00`; not `#.##0,00`) makes no code of the locale. Excel's reading of such a code is not
    /// documented; LibreOffice set to the locale reads it as an en-US code (`1234,50`,
    /// `1 234,50`), and so does ncsheet. So it reads `#,##0`, the one code of its en-US
    /// built-ins (`0.00`, `#,##0`, `#,##0.00`, `0.00%`, `0.00E+00`) without a `.`, as en-US
    /// (`1 235`, not `1234,500`: LibreOffice 7.4 set to fr-FR and et-EE).
    fn reads_as_en_us(self, code: &str) -> bool {
        if self.decimal == '.' || self.group == '.' || self.group_typed.contains(&'.') {
            return false;
        }
        if code == "#,##0" {
            return true;
        }
        let chars: Vec<char> = code.chars().collect();
        let placeholder = |i: usize| chars.get(i).is_some_and(|c| matches!(c, '0' | '#' | '?'));
        let (mut quoted, mut escaped) = (false, false);
        for (i, &c) in chars.iter().enumerate() {
            match c {
                _ if escaped => escaped = false,
                '"' => quoted = !quoted,
                '\\' if !quoted => escaped = true,
                // `#.##0,00` has its decimal comma after: the `.` is a literal there.
                '.' if !quoted && i > 0 && placeholder(i - 1) && placeholder(i + 1) => {
                    return !chars[i..].contains(&self.decimal)
                }
                _ => {}
            }
        }
        false
    }

    /// A formula typed in this locale (`=ROUND(B5*0,5;3)`) in the file syntax
    /// (`=ROUND(B5*0.5,3)`).
    pub fn canonical_formula(self, typed: &str) -> String {
        if self.is_canonical() {
            return typed.to_string();
        }
        crate::formula::locale_syntax::from_semicolon_locale(typed)
    }

    /// A formula in the file syntax as this locale's Excel shows it.
    pub fn local_formula(self, canonical: &str) -> String {
        if self.is_canonical() {
            return canonical.to_string();
        }
        crate::formula::locale_syntax::to_semicolon_locale(canonical)
    }

    /// When `text` is no number here but is one in another locale ncsheet knows, that
    /// locale and the spelling this locale's user means (`0.8` in et-EE: en-US, `0,8`).
    pub fn number_elsewhere(self, text: &str) -> Option<(Locale, String)> {
        // Whether it reads at all does not depend on the date system.
        if self.read_number(text, DateSystem::From1900).is_some() || text.trim().is_empty() {
            return None;
        }
        if let Some(date) = self.date_spelled_elsewhere(text.trim()) {
            return Some(date);
        }
        let other = if self.is_canonical() { Locale::from_tag("de-DE")? } else { Locale::EN_US };
        let n = other.read_plain_number(text)?;
        // Text with letters besides an exponent, or a currency, is left alone: only numbers.
        if text.trim().chars().any(|c| c.is_alphabetic() && c != 'E' && c != 'e') {
            return None;
        }
        Some((other, self.localize_shown(&general(n))))
    }

    /// A date typed with a separator this locale does not read between its parts
    /// (`12/03/2025` in de-DE): a locale of the same date order that reads it, and the same
    /// parts with this locale's separator (`12.03.2025`).
    fn date_spelled_elsewhere(self, text: &str) -> Option<(Locale, String)> {
        if self.is_canonical() {
            return None;
        }
        let separator = text.chars().find(|c| matches!(c, '.' | '/' | '-'))?;
        if self.date_separators_typed.contains(separator) {
            return None;
        }
        let own = text.replace(separator, &self.date_separator.to_string());
        self.read_day(&own, DateSystem::From1900)?;
        let reads = |l: &Locale| l.read_day(text, DateSystem::From1900).is_some();
        let other =
            Locale::all().find(|l| *l != self && !l.is_canonical() && l.date_order == self.date_order && reads(l))?;
        Some((other, own))
    }
}

/// The serial of a year, month and day typed, when that day is in Excel's calendar.
fn valid_serial(system: DateSystem, (year, month, day): (i64, i64, i64)) -> Option<i64> {
    let valid = (1900..=9999).contains(&year)
        && (1..=12).contains(&month)
        && day >= 1
        && day <= i64::from(dates::days_in_month(year, month as u32));
    valid.then(|| dates::serial_from_ymd(system, year, month, day))
}

/// A year typed with `digits` digits: two (or one) are 1930 to 2029, as Excel and
/// LibreOffice read them; four as typed; others none.
fn full_year(year: i64, digits: usize) -> Option<i64> {
    match digits {
        1 | 2 if year < 30 => Some(2000 + year),
        1 | 2 => Some(1900 + year),
        4 => Some(year),
        _ => None,
    }
}

/// The bytes of `text` that spell `name` at its start, either case, as a whole word (no
/// letter after it).
fn word_at(text: &str, name: &str) -> Option<usize> {
    let mut chars = text.chars();
    let mut end = 0;
    for n in name.chars() {
        let c = chars.next()?;
        if !c.to_lowercase().eq(n.to_lowercase()) {
            return None;
        }
        end += c.len_utf8();
    }
    (!name.is_empty() && !text[end..].starts_with(char::is_alphabetic)).then_some(end)
}

/// One piece of date text naming its month ([`Locale::named_month_date`]).
enum DatePiece {
    /// Digits: their value and how many there are.
    Number(i64, usize),
    /// A month (1 to 12) by its name, and whether a short name's `.` followed it.
    Month(i64, bool),
    /// What stands between two numbers or names.
    Between(String),
}

/// A part of a typed date: one to four digits.
fn date_number(s: &str) -> Option<i64> {
    (!s.is_empty() && s.len() <= 4 && s.bytes().all(|b| b.is_ascii_digit())).then(|| s.parse().ok())?
}

/// What [`Locale::canonical_format_code`] tracks in one section of a number format code.
#[derive(Default)]
struct Section {
    /// Where the integer part's first placeholder went in the canonical code.
    integer_at: Option<usize>,
    decimal: bool,
    grouped: bool,
    group_among_decimals: bool,
}

impl Section {
    /// A section with a group mark among its decimals (de-DE `#,##0.000`) groups its integer
    /// part: `#,` goes before the integer part's first placeholder in the canonical code.
    fn finish(&self, out: &mut String) {
        if let (true, false, Some(at)) = (self.group_among_decimals, self.grouped, self.integer_at) {
            out.insert_str(at, "#,");
        }
    }
}

/// What the `[…]` of a format code hold, outside quotes and escapes.
/// Whether `word` (in a format code's brackets) names a colour in some locale's words, either
/// case: `Red`, `Color10` (1 to 56, as Excel's palette; `Color 10` too, as Excel and
/// LibreOffice read it), de-DE `Rot`, `Farbe10`.
pub fn names_a_colour(word: &str) -> bool {
    LOCALES.iter().any(|data| data.names_colour(word))
}

impl LocaleData {
    /// Whether `word` names a colour in this locale's words ([`names_a_colour`]).
    fn names_colour(&self, word: &str) -> bool {
        let prefix = self.colour_number.len();
        let numbered = word.get(..prefix).is_some_and(|w| w.eq_ignore_ascii_case(self.colour_number))
            && word[prefix..].trim_start().parse::<u8>().is_ok_and(|n| (1..=56).contains(&n));
        numbered || self.colours.split(' ').any(|c| c.to_lowercase() == word.to_lowercase())
    }
}

/// The first word in brackets of a format `code` that makes no code in Excel's reading
/// (`[Foo]` of `[Foo]0`), for TEXT to name.
pub fn refused_bracket_word(code: &str) -> Option<String> {
    bracket_words(code)
        .into_iter()
        .find(|word| super::format::text_format::NumberFormat::parse(&format!("[{word}]")).is_err())
        .map(|word| format!("[{word}]"))
}

/// Where (the character, from 1) a format `code` opens a `[` that no `]` closes (`[` alone, or
/// `[Red0`), for TEXT to name: Excel refuses such a code.
pub fn unclosed_bracket(code: &str) -> Option<usize> {
    let (mut quoted, mut escaped) = (false, false);
    for (place, (i, c)) in code.char_indices().enumerate() {
        match c {
            _ if escaped => escaped = false,
            '"' => quoted = !quoted,
            '\\' if !quoted => escaped = true,
            '[' if !quoted && !code[i + 1..].contains(']') => return Some(place + 1),
            _ => {}
        }
    }
    None
}

fn bracket_words(code: &str) -> Vec<&str> {
    let mut words = Vec::new();
    let (mut quoted, mut escaped) = (false, false);
    for (i, c) in code.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '"' => quoted = !quoted,
            '\\' if !quoted => escaped = true,
            '[' if !quoted => {
                if let Some(end) = code[i + 1..].find(']') {
                    words.push(&code[i + 1..i + 1 + end]);
                }
            }
            _ => {}
        }
    }
    words
}

/// Marks around a month's name that stands for its first letter (`mmmmm`): the canonical
/// code shows the full name between them, in English, and the locale's name replaces it
/// before [`month_letters`] keeps its first letter. Private-use characters, as above.
const MONTH_LETTER_OPEN: char = '\u{F8F2}';
const MONTH_LETTER_CLOSE: char = '\u{F8F3}';

/// A date code's `mmmmm` (the month's first letter, "J–D" in English: Microsoft's "Number
/// format codes") as the full name between [`MONTH_LETTER_OPEN`] and [`MONTH_LETTER_CLOSE`],
/// so that the letter is the first of the month's name in the code's language (fr-FR `m`
/// for `mars`), as LibreOffice set to the locale shows it. Quoted text, escapes and `[…]`
/// are left alone.
fn month_letter_code(code: &str) -> String {
    rewrite_code_letters(code, |chars, i, out| {
        if !chars[i].eq_ignore_ascii_case(&'m') {
            return 0;
        }
        let run = chars[i..].iter().take_while(|m| m.eq_ignore_ascii_case(&'m')).count();
        if run == 5 {
            out.extend(['\\', MONTH_LETTER_OPEN, 'm', 'm', 'm', 'm', '\\', MONTH_LETTER_CLOSE]);
        } else {
            out.extend(&chars[i..i + run]);
        }
        run
    })
}

/// `code` with what stands outside quotes, `[…]` and `\`-escapes rewritten by `rewrite`,
/// which is given the code's characters and a position there, writes what stands for what
/// is at it and says how many characters that was (none: the character is copied as it is).
fn rewrite_code_letters(code: &str, mut rewrite: impl FnMut(&[char], usize, &mut String) -> usize) -> String {
    let chars: Vec<char> = code.chars().collect();
    let mut out = String::with_capacity(code.len() + 8);
    let (mut quoted, mut bracket, mut i) = (false, false, 0);
    while i < chars.len() {
        let c = chars[i];
        let taken = match c {
            '"' => {
                quoted = !quoted;
                0
            }
            '[' if !quoted => {
                bracket = true;
                0
            }
            ']' if !quoted => {
                bracket = false;
                0
            }
            '\\' if !quoted => {
                let end = (i + 2).min(chars.len());
                out.extend(&chars[i..end]);
                end - i
            }
            _ if quoted || bracket => 0,
            _ => rewrite(&chars, i, &mut out),
        };
        if taken == 0 {
            out.push(c);
            i += 1;
        } else {
            i += taken;
        }
    }
    out
}

/// `shown` with its English month and weekday names in the words of `names` (see
/// [`Locale::localize_names_for`]); `short_may`: the code's longest month is `mmm`.
fn names_in(names: Locale, short_may: bool, shown: &str) -> String {
    if names.data == &EN_US || !shown.chars().any(char::is_alphabetic) {
        return shown.to_string();
    }
    let words = |names: &'static str| names.split(' ').collect::<Vec<_>>();
    let (months, days) = (words(names.months), words(names.days));
    let (months_short, days_short) = (words(names.months_short), words(names.days_short));
    let own = |english: &str| -> Option<&'static str> {
        let at = |list: &str| words_position(list, english);
        if english == "May" && short_may {
            return months_short.get(4).copied();
        }
        at(EN_US.months)
            .and_then(|i| months.get(i))
            .or_else(|| at(EN_US.days).and_then(|i| days.get(i)))
            .or_else(|| at(EN_US.months_short).and_then(|i| months_short.get(i)))
            .or_else(|| at(EN_US.days_short).and_then(|i| days_short.get(i)))
            .copied()
    };
    replace_words(shown, own)
}

/// What [`month_letter_code`]'s code showed, each marked month name as its first letter.
fn month_letters(shown: &str) -> String {
    if !shown.contains(MONTH_LETTER_OPEN) {
        return shown.to_string();
    }
    let mut out = String::with_capacity(shown.len());
    let mut rest = shown;
    while let Some((before, after)) = rest.split_once(MONTH_LETTER_OPEN) {
        out.push_str(before);
        let (name, tail) = after.split_once(MONTH_LETTER_CLOSE).unwrap_or((after, ""));
        out.extend(name.chars().next());
        rest = tail;
    }
    out.push_str(rest);
    out
}

/// Whether a format code has a `/` outside quotes and not escaped (a fraction's).
fn has_unquoted_slash(code: &str) -> bool {
    let (mut quoted, mut escaped) = (false, false);
    for c in code.chars() {
        match c {
            _ if escaped => escaped = false,
            '"' => quoted = !quoted,
            '\\' if !quoted => escaped = true,
            '/' if !quoted => return true,
            _ => {}
        }
    }
    false
}

/// A space between digits or beside a number: plain, no-break or narrow no-break.
fn is_space(c: char) -> bool {
    matches!(c, ' ' | '\u{A0}' | '\u{202F}')
}

/// Stand-ins for a literal `.` and `,` of a format code (quoted, escaped, or not a mark in the
/// locale), so that [`Locale::localize_shown`] leaves them alone; [`literal_marks`] puts
/// them back (TEXT calls it on what a text section showed). Private-use characters: no format code or number holds them.
const LITERAL_POINT: char = '\u{F8F0}';
const LITERAL_COMMA: char = '\u{F8F1}';

fn protected_mark(c: char) -> char {
    match c {
        '.' => LITERAL_POINT,
        ',' => LITERAL_COMMA,
        c => c,
    }
}

pub fn literal_marks(shown: &str) -> String {
    shown.replace(LITERAL_POINT, ".").replace(LITERAL_COMMA, ",")
}

/// The locale a format code's `[$-LCID]` or `[$currency-LCID]` tag names by its Windows
/// language id (`[$-409]` English (United States), `[$-407]` German), when ncsheet knows it;
/// the high bits (calendar, digits) are left aside.
fn tagged_language(code: &str) -> Option<Locale> {
    let (_, tag) = code.split_once("[$")?;
    let (tag, _) = tag.split_once(']')?;
    let (_, hex) = tag.rsplit_once('-')?;
    let language = u32::from_str_radix(hex, 16).ok()? & 0xFFFF;
    let tag = match language {
        0x409 => "en-US",
        0x407 => "de-DE",
        0x40C => "fr-FR",
        0x425 => "et-EE",
        0x422 => "uk-UA",
        0x41B => "sk-SK",
        0x81A | 0x241A => "sr-RS",
        0x40E => "hu-HU",
        _ => return None,
    };
    Locale::from_tag(tag)
}

/// `shown` with each word (a run of letters) that `own` has another word for replaced by it.
fn replace_words<'w>(shown: &str, own: impl Fn(&str) -> Option<&'w str>) -> String {
    let mut out = String::with_capacity(shown.len() + 8);
    let mut word = String::new();
    for c in shown.chars().chain(std::iter::once('\0')) {
        if c.is_alphabetic() {
            word.push(c);
            continue;
        }
        if !word.is_empty() {
            out.push_str(own(&word).unwrap_or(&word));
            word.clear();
        }
        if c != '\0' {
            out.push(c);
        }
    }
    out
}

/// The index of `word` among the space-separated `names`.
fn words_position(names: &str, word: &str) -> Option<usize> {
    names.split(' ').position(|n| n == word)
}

/// The longest run of `letter` (either case) in a format code, outside quotes.
fn longest_run(code: &str, letter: char) -> usize {
    let (mut longest, mut run, mut quoted) = (0, 0, false);
    for c in code.chars() {
        if c == '"' {
            quoted = !quoted;
        }
        run = if !quoted && c.eq_ignore_ascii_case(&letter) { run + 1 } else { 0 };
        longest = longest.max(run);
    }
    longest
}

/// Whether a format code shows a date or time (a d, m, y, h or s outside quotes and `[…]`).
pub fn is_date_code(code: &str) -> bool {
    #[cfg(test)]
    DATE_CODE_SCANS.with(|c| c.set(c.get() + 1));
    let mut quoted = false;
    let mut bracket = false;
    let mut escaped = false;
    for c in code.chars() {
        match c {
            _ if escaped => escaped = false,
            '\\' => escaped = true,
            '"' => quoted = !quoted,
            '[' if !quoted => bracket = true,
            ']' if !quoted => bracket = false,
            'd' | 'D' | 'm' | 'M' | 'y' | 'Y' | 'h' | 'H' | 's' | 'S' if !quoted && !bracket => return true,
            _ => {}
        }
    }
    false
}

#[cfg(test)]
thread_local! {
    static DATE_CODE_SCANS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Format codes scanned for date letters on this thread so far ([`is_date_code`]): counted
/// for tests, which bound a call's scans by it.
#[cfg(test)]
pub(crate) fn date_code_scans() -> u64 {
    DATE_CODE_SCANS.with(|c| c.get())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn locale(tag: &str) -> Locale {
        Locale::from_tag(tag).unwrap()
    }

    #[test]
    fn tags_as_users_and_environments_spell_them() {
        assert_eq!(locale("et_EE.UTF-8").tag, "et-EE");
        assert_eq!(locale("sr-Latn-RS").tag, "sr-RS");
        assert_eq!(locale("HU").tag, "hu-HU");
        assert_eq!(locale("C"), Locale::EN_US);
        assert!(Locale::from_tag("xx-YY").is_none());
        let env = |pairs: &'static [(&str, &str)]| {
            move |name: &str| pairs.iter().find(|(n, _)| *n == name).map(|(_, v)| v.to_string())
        };
        assert_eq!(Locale::from_environment(env(&[("LANG", "de_DE.UTF-8")])).locale.tag, "de-DE");
        let all = Locale::from_environment(env(&[("LC_ALL", "C"), ("LANG", "de_DE.UTF-8")]));
        assert_eq!(all.locale, Locale::EN_US);
        assert_eq!(Locale::from_environment(env(&[])).locale, Locale::EN_US);
    }

    #[test]
    fn every_locale_names_twelve_months_and_seven_days() {
        for l in Locale::all() {
            assert_eq!((l.months.split(' ').count(), l.days.split(' ').count()), (12, 7), "{l}");
        }
        assert_eq!(locale("et-EE").localize_names("Wednesday, March 12"), "kolmapäev, märts 12");
    }

    /// Excel's names of TRUE and FALSE in each language, either case when typed.
    #[test]
    fn booleans_take_the_locale_words() {
        for l in Locale::all() {
            assert!(l.booleans.iter().all(|w| !w.is_empty()), "{l}");
        }
        let et = locale("et-EE");
        assert_eq!((et.read_boolean("tõene"), et.read_boolean(" Väär")), (Some(true), Some(false)));
        assert_eq!(locale("de-DE").shown_value(&Value::Bool(false)), "FALSCH");
        assert_eq!(Locale::EN_US.read_boolean("WAHR"), None);
        assert_eq!(Locale::EN_US.shown_value(&Value::Bool(true)), "TRUE");
    }

    /// As LibreOffice set to the locale shows the public corpus's workbooks (POI's 45540 and
    /// DateFormatTests, xlcalculator's DATEDIF): a `[$-409]` code keeps English names, the
    /// fraction of a second takes the decimal comma, et-EE's short date has no leading zero.
    #[test]
    fn language_tags_fractions_of_seconds_and_short_dates() {
        let (fr, de) = (locale("fr-FR"), locale("de-DE"));
        assert_eq!(fr.localize_names_for("[$-409]mmmm d, yyyy", "September 11, 2006"), "September 11, 2006");
        assert_eq!(fr.localize_names_for("mmmm d, yyyy", "September 11, 2006"), "septembre 11, 2006");
        assert_eq!(fr.localize_names_for("[$-407]mmmm", "March"), "März");
        assert_eq!(de.localize_formatted("yyyy-mm-dd hh:mm:ss.0", "1904-01-02 00:00:00.4"), "1904-01-02 00:00:00,4");
        assert_eq!(de.localize_formatted("dd.mm.yyyy", "12.03.2025"), "12.03.2025");
        assert_eq!(locale("et-EE").shown_number(35796.0, Some("m/d/yyyy"), DateSystem::From1900), "1.01.1998");
    }

    #[test]
    fn numbers_and_dates_read_in_the_locale() {
        let et = locale("et-EE");
        assert_eq!(et.read_number("0,8", DateSystem::From1900), Some(0.8));
        assert_eq!(et.read_number("1 234,5", DateSystem::From1900), Some(1234.5));
        assert_eq!(et.read_number("1\u{A0}234,5", DateSystem::From1900), Some(1234.5));
        assert_eq!(et.read_number("25%", DateSystem::From1900), Some(0.25));
        assert_eq!(et.read_number("-0,0171", DateSystem::From1900), Some(-0.0171));
        assert_eq!(et.read_number("0.8", DateSystem::From1900), None);
        // 2025-03-12 is serial 45728 (DATE(2025,3,12) in Excel).
        assert_eq!(et.read_number("12.03.2025", DateSystem::From1900), Some(45728.0));
        assert_eq!(locale("hu-HU").read_number("2025.03.12.", DateSystem::From1900), Some(45728.0));
        assert_eq!(Locale::EN_US.read_number("3/12/2025", DateSystem::From1900), Some(45728.0));
        let de = locale("de-DE");
        assert_eq!(de.read_number("1.234,5", DateSystem::From1900), Some(1234.5));
        assert_eq!(de.read_number("1,5", DateSystem::From1900), Some(1.5));
        assert_eq!(de.read_number("12.3.2025 12:00", DateSystem::From1900), Some(45728.5));
    }

    /// What LibreOffice set to each locale reads as numbers (VALUE and DATEVALUE there): a
    /// fraction, a space before a percent or a currency sign, a time's fraction of a second
    /// with the decimal comma, and a month named in the locale's words.
    #[test]
    fn fractions_spaced_signs_and_named_months_read_in_the_locale() {
        let (fr, de, et) = (locale("fr-FR"), locale("de-DE"), locale("et-EE"));
        let read = |l: Locale, text: &str| l.read_number(text, DateSystem::From1900);
        assert_eq!(read(fr, "1 1/2"), Some(1.5));
        assert_eq!(read(de, "-2 3/4"), Some(-2.75));
        assert_eq!(read(fr, "12,5 %"), Some(0.125));
        assert_eq!(read(et, "1,5 €"), Some(1.5));
        assert_eq!(read(fr, "1 234,5 €"), Some(1234.5));
        assert_eq!(read(de, "$1,5"), None);
        assert_eq!(read(de, "1.234,5-"), Some(-1234.5));
        assert_eq!(read(de, "-1,5-"), None);
        // 14:30:15.5 is (14 * 3600 + 30 * 60 + 15.5) / 86400 of a day.
        let time = (14.0 * 3600.0 + 30.0 * 60.0 + 15.5) / 86400.0;
        assert!((read(de, "14:30:15,5").unwrap() - time).abs() < 1e-12);
        assert_eq!(read(de, "12. März 2025"), Some(45728.0));
        assert_eq!(read(fr, "12 mars 2025"), Some(45728.0));
        assert_eq!(read(fr, "1 janv. 2025"), Some(45658.0));
        assert_eq!(read(et, "12. märts 2025"), Some(45728.0));
        assert_eq!(read(de, "12. März 2025 12:00"), Some(45728.5));
        // A month of another language is no month here.
        assert_eq!(read(de, "12 mars 2025"), None);
    }

    /// What LibreOffice set to each locale reads as a date (DATEVALUE there): only its own
    /// separators between a date's parts (fr-FR also `.` and `-`), ISO's year-first form, and
    /// a day and month without a year in the locale's forms, which are the current year's.
    #[test]
    fn date_separators_and_dates_without_a_year_read_as_libreoffice_reads_them() {
        let (fr, de, et) = (locale("fr-FR"), locale("de-DE"), locale("et-EE"));
        let read = |l: Locale, text: &str| l.read_number(text, DateSystem::From1900);
        // 2025-03-12 is serial 45728 (DATE(2025,3,12) in Excel).
        for (l, text) in
            [(de, "12/03/2025"), (de, "12-03-2025"), (et, "12/3/25"), (de, "2025/03/12"), (fr, "2025.03.12")]
        {
            assert_eq!(read(l, text), None, "{l}: {text}");
        }
        for (l, text) in [(fr, "12/3/25"), (fr, "12-03-2025"), (fr, "12.03.2025"), (de, "2025-03-12"), (et, "12.3.25")]
        {
            assert_eq!(read(l, text), Some(45728.0), "{l}: {text}");
        }
        // The year is the clock's when the test runs (Excel and LibreOffice take it so).
        use chrono::Datelike;
        let year = i64::from(chrono::Local::now().year());
        let march_12 = dates::serial_from_ymd(DateSystem::From1900, year, 3, 12) as f64;
        for (l, text) in [(de, "12.03."), (de, "12.3."), (et, "12.03"), (et, "12.3."), (fr, "12/03"), (fr, "12/3")] {
            assert_eq!(read(l, text), Some(march_12), "{l}: {text}");
        }
        for (l, text) in [(de, "12. März"), (de, "12 Mär"), (fr, "12 mars"), (et, "12. märts")] {
            assert_eq!(read(l, text), Some(march_12), "{l}: {text}");
        }
        assert_eq!(locale("hu-HU").read_number("3.12.", DateSystem::From1900), Some(march_12));
        for (l, text) in [(de, "12.03"), (fr, "12.03."), (et, "12/03"), (de, "12-03"), (de, "12.13.")] {
            assert_eq!(read(l, text), None, "{l}: {text}");
        }
        // en-US reads no date without a year: its results stay as they were.
        assert_eq!(Locale::EN_US.read_number("3/12", DateSystem::From1900), None);
    }

    /// A day and month without a year fall in the year of the workbook's clock when its
    /// settings fix one, not the system clock's. 2031-06-01 is serial 48000, 2031-03-12
    /// 47919 (days since 1899-12-30).
    #[test]
    fn a_date_without_a_year_falls_in_the_year_of_the_fixed_clock() {
        let mut settings = crate::eval::Settings::default();
        settings.clock = Some(48000.5);
        settings.locale = locale("de-DE");
        let de = settings.locale_in_force(DateSystem::From1900);
        assert_eq!(de, locale("de-DE"));
        for text in ["12.03.", "12. März", "12.3."] {
            assert_eq!(de.read_number(text, DateSystem::From1900), Some(47919.0), "{text}");
        }
        // The clock's serial is the workbook's: in the 1904 system 48000 is 2035-06-02, and
        // 2035-03-12 is 47918 days after 1904-01-01.
        let de_1904 = settings.locale_in_force(DateSystem::From1904);
        assert_eq!(de_1904.read_number("12.03.", DateSystem::From1904), Some(47918.0));
    }

    /// Dates naming their month, as LibreOffice set to each locale reads them (the probes of
    /// tests/locale.rs): the month and one number are that year's first day of the month,
    /// 1 March 2012 is serial 40969, 2005's 38412, 1931's 11383, 12 March 2025 45728.
    #[test]
    fn named_months_read_as_libreoffice_reads_them() {
        let (fr, de, et) = (locale("fr-FR"), locale("de-DE"), locale("et-EE"));
        let read = |l: Locale, text: &str| l.read_number(text, DateSystem::From1900);
        for (l, text, serial) in [
            (de, "März 12", 40969.0),
            (de, "märz 12.", 40969.0),
            (de, "Mär.12", 40969.0),
            (de, "Sept. 12", 41153.0),
            (de, "März 5", 38412.0),
            (de, "März 31", 11383.0),
            (fr, "mars 12", 40969.0),
            (fr, "mars/12", 40969.0),
            (fr, "mars-12", 40969.0),
            (et, "märts 12", 40969.0),
            (de, "12-März-2025", 45728.0),
            (de, "12.März 2025", 45728.0),
            (de, "12.Mär.2025", 45728.0),
            (et, "12.veebr.2025", 45700.0),
            (fr, "12-sept.-2025", 45912.0),
            (fr, "12/mars 2025", 45728.0),
            (de, "März 12 2025", 45728.0),
        ] {
            assert_eq!(read(l, text), Some(serial), "{l}: {text}");
        }
        for (l, text) in [
            (fr, "12. mars"),
            (fr, "12 mars."),
            (fr, "12 janv"),
            (fr, "mars. 12"),
            (fr, "12/mars/2025"),
            (de, "12. März."),
            (de, "März.12"),
            (de, "12-März"),
            (de, "12.März.2025"),
            (de, "12-Mär.-2025"),
            (de, "März 12, 2025"),
            (de, "12 March"),
            (et, "12 märts."),
            (de, "32 März"),
        ] {
            assert_eq!(read(l, text), None, "{l}: {text}");
        }
    }

    /// TEXT of `n` with `code` typed in `l`, as TEXT computes it.
    fn text(l: Locale, n: f64, code: &str) -> String {
        let canonical = l.canonical_format_code(code);
        let format = crate::eval::functions::NumberFormat::parse(&canonical).unwrap();
        literal_marks(&l.localize_formatted(&canonical, &format.format_number(n, DateSystem::From1900).unwrap()))
    }

    /// LibreOffice 7.4 set to each locale, TEXT of 1234.5 and of 2025-03-12 (serial 45728):
    /// a space before a currency tag is text, not a scaling group mark (a plain `€` after
    /// the space still scales: `.1,23€`); `mmmmm` is the first letter of the month's name in
    /// the code's language; colour words are the locale's (de-DE `[Rot]`, not `[Red]`).
    #[test]
    fn currency_tags_month_letters_and_colour_words_as_libreoffice_reads_them() {
        let (de, fr, et) = (locale("de-DE"), locale("fr-FR"), locale("et-EE"));
        for l in [fr, et] {
            assert_eq!(text(l, 1234.5, "#.##0,00 [$€-407]"), "1.234,50 €", "{l}");
            assert_eq!(text(l, 1234.5, "#.##0,00 [$€]"), "1.234,50 €", "{l}");
            assert_eq!(text(l, 1234.5, "0,00 [$€-407]"), "1234,50 €", "{l}");
            assert_eq!(text(l, 1234.5, "#.##0,00 €"), ".1,23€", "{l}");
        }
        assert_eq!(text(de, 1234.5, "#.##0,00 [$€-407]"), "1.234,50 €");
        assert_eq!(text(de, 45728.0, "mmmmm"), "M");
        assert_eq!(text(fr, 45728.0, "mmmmm"), "m");
        assert_eq!(text(de, 45728.0, "[$-40C]mmmmm"), "m");
        // A cell's own format (canonical) shows it so too.
        assert_eq!(fr.shown_number(45728.0, Some("mmmmm d"), DateSystem::From1900), "m 12");
        assert_eq!(Locale::EN_US.shown_number(45728.0, Some("mmmmm d"), DateSystem::From1900), "M 12");
        assert_eq!(text(fr, 45728.0, r"[$-407]mmmmm \m\m\m\m\m mmmm"), "M mmmmm März");
        assert_eq!(de.foreign_colour("0;[Red]-0"), Some("[Red]".to_string()));
        assert_eq!(de.foreign_colour("[Color10]0"), Some("[Color10]".to_string()));
        assert_eq!(de.foreign_colour("[rot]0;[Farbe10]-0;\"[Red]\""), None);
        assert_eq!(fr.foreign_colour("[Rot]0"), Some("[Rot]".to_string()));
        assert_eq!(et.foreign_colour("[RED]0;[Color3]-0;[$-407][>1]"), None);
        assert_eq!(Locale::EN_US.foreign_colour("[Rot]0"), Some("[Rot]".to_string()));
        assert_eq!(Locale::EN_US.foreign_colour("[Brown]0"), Some("[Brown]".to_string()));
        assert_eq!(Locale::EN_US.foreign_colour("[red]0;[Color 56]0;[Foo]0"), None);
    }

    /// LibreOffice 7.4 set to each locale reading VALUE's text: its own words for before and
    /// after noon and not en-US's (de-DE, et-EE), an hour alone with them, ISO 8601's `T`,
    /// and a weekday's full name before a date (2025-03-12 is serial 45728, 14:30 is
    /// 14.5/24 of a day).
    #[test]
    fn meridiems_iso_times_and_weekdays_read_as_libreoffice_reads_them() {
        let (de, fr, et) = (locale("de-DE"), locale("fr-FR"), locale("et-EE"));
        let read = |l: Locale, text: &str| l.read_number(text, DateSystem::From1900);
        let close = |l: Locale, text: &str, serial: f64| {
            let found = read(l, text);
            assert!(found.is_some_and(|f| (f - serial).abs() < 1e-9), "{l}: {text}: {found:?}");
        };
        let half_past_two = 14.5 / 24.0;
        for (l, text, serial) in [
            (de, "2:30 nachm.", half_past_two),
            (de, "2:30NACHM.", half_past_two),
            (de, "2 nachm.", 14.0 / 24.0),
            (de, "12:30 vorm.", 0.5 / 24.0),
            (de, "12.03.2025 2:30 nachm.", 45728.0 + half_past_two),
            (et, "2:30 p.l", half_past_two),
            (et, "2 p.l", 14.0 / 24.0),
            (fr, "2 pm", 14.0 / 24.0),
            (fr, "2:30 PM", half_past_two),
            (de, "2025-03-12T14:30", 45728.0 + half_past_two),
            (fr, "2025-3-12t14:30", 45728.0 + half_past_two),
            (et, "2025-03-12T14:30:15,5", 45728.0 + (14.5 * 3600.0 + 15.5) / 86400.0),
            (de, "Mittwoch, 12. März 2025", 45728.0),
            (de, "montag 12.03.2025", 45728.0),
            (de, "Mittwoch, 12.03.2025 14:30", 45728.0 + half_past_two),
            (fr, "mercredi 12 mars 2025", 45728.0),
            (fr, "mercredi 12/03/2025", 45728.0),
            (et, "kolmapäev, 12. märts 2025", 45728.0),
        ] {
            close(l, text, serial);
        }
        for (l, text) in [
            (de, "2:30 PM"),
            (de, "2:30 pm"),
            (et, "2:30 AM"),
            (de, "2:30 nachm"),
            (et, "2:30 p.l."),
            (de, "Mittwoch,12.03.2025"),
            (de, "Mi, 12.03.2025"),
            (fr, "mercredi, 12 mars 2025"),
            (de, "mercredi 12 mars 2025"),
            (de, "Mittwoch"),
            (de, "12.03.2025 2 nachm."),
        ] {
            assert_eq!(read(l, text), None, "{l}: {text}");
        }
    }

    #[test]
    fn shown_numbers_and_format_codes_take_the_locale_marks() {
        let fr = locale("fr-FR");
        assert_eq!(fr.localize_shown("1,234.50 kg."), "1\u{A0}234,50 kg.");
        assert_eq!(fr.canonical_format_code("00,00"), "00.00");
        let code = fr.canonical_format_code("# ##0,00\" m.\"");
        assert_eq!(literal_marks(&code), "#,##0.00\" m.\"");
        assert_eq!(fr.localize_formatted(&code, "1,234.50 m\u{F8F0}"), "1\u{A0}234,50 m.");
        assert_eq!(locale("de-DE").canonical_format_code("#.##0,0"), "#,##0.0");
        // `d` and `y` are no date letters in fr-FR (`jj/mm/aaaa`): literal, as in Excel there.
        assert_eq!(fr.canonical_format_code("dd.mm.yyyy"), "\\d\\d.mm.\\y\\y\\y\\y");
        assert_eq!(locale("de-DE").canonical_format_code("dd\\ mmm\\ yyyy"), "\\d\\d\\ mmm\\ \\y\\y\\y\\y");
        // A `.` between placeholders where it is no mark: the code is read as en-US writes it.
        assert_eq!(fr.canonical_format_code("00.00"), "00.00");
        assert_eq!(locale("et-EE").canonical_format_code("#,##0.00"), "#,##0.00");
        // Spaces after the last placeholder scale by 1000 each where spaces group digits.
        assert_eq!(fr.canonical_format_code("0,0 \\€"), "0.0,\\€");
        assert_eq!(fr.canonical_format_code("0  "), "0,,");
        assert_eq!(fr.canonical_format_code("0,0\\ \\€"), "0.0\\ \\€");
        assert_eq!(locale("de-DE").canonical_format_code("0,0 \\€"), "0.0 \\€");
        // A group mark among the decimals groups the integer part (LibreOffice in de-DE).
        assert_eq!(locale("de-DE").canonical_format_code("#,##0.00;-#,##0.00"), "#,#.##000;-#,#.##000");
        assert_eq!(locale("de-DE").canonical_format_code("0,0.0"), "#,0.00");
    }

    /// TEXT's codes as LibreOffice set to the locale reads them: its word for General, a
    /// fraction of a second after its decimal mark, a fraction's space (no group there), and
    /// AM/PM in its words.
    #[test]
    fn general_fractions_and_meridiems_in_the_locale() {
        let (fr, de, et) = (locale("fr-FR"), locale("de-DE"), locale("et-EE"));
        assert_eq!(de.canonical_format_code("STANDARD\" kg\""), "General\" kg\"");
        assert_eq!(fr.canonical_format_code("\"Standard\" 0"), "\"Standard\" 0");
        assert_eq!(et.canonical_format_code("Standard"), "Standard");
        assert_eq!(de.canonical_format_code("[h]:mm:ss,00"), "[h]:mm:ss.00");
        assert_eq!(fr.canonical_format_code("# ??/??"), "# ??/??");
        assert_eq!(fr.canonical_format_code("# ##0,0\" m/s\""), "#,##0.0\" m/s\"");
        assert_eq!(de.localize_formatted("hh:mm AM/PM", "02:24 PM"), "02:24 nachm.");
        assert_eq!(et.localize_formatted("h am/pm", "7 AM"), "7 e.l");
        assert_eq!(fr.localize_formatted("h AM/PM", "7 AM"), "7 AM");
    }

    /// LibreOffice set to each locale (TEXT of 2025-03-12 and of the first of each month).
    #[test]
    fn date_letters_and_short_names_as_libreoffice_shows_them() {
        let de = locale("de-DE");
        assert_eq!(de.canonical_format_code("TT.MM.JJJJ"), "dd.MM.yyyy");
        assert_eq!(de.canonical_format_code("TTTT \"Tag\""), "dddd \"Tag\"");
        assert_eq!(locale("fr-FR").canonical_format_code("JJ/MM/AAAA hh:mm AM/PM"), "dd/MM/yyyy hh:mm AM/PM");
        assert_eq!(locale("et-EE").canonical_format_code("dd.mm.yyyy"), "dd.mm.yyyy");
        assert_eq!(de.localize_names_for("ddd, d. mmm", "Mon, 3. Mar"), "Mo, 3. Mär");
        assert_eq!(de.localize_names_for("dddd", "Monday"), "Montag");
        assert_eq!(locale("uk-UA").localize_names_for("mmm", "May"), "трв");
        assert_eq!(locale("uk-UA").localize_names_for("mmmm", "May"), "травень");
        assert_eq!(locale("fr-FR").localize_names_for("mmm yy", "Feb 25"), "févr. 25");
    }

    #[test]
    fn a_number_of_another_locale_is_named_with_the_spelling_meant() {
        let (other, meant) = locale("et-EE").number_elsewhere("0.8").unwrap();
        assert_eq!((other, meant.as_str()), (Locale::EN_US, "0,8"));
        assert_eq!(Locale::EN_US.number_elsewhere("0,8").unwrap().1, "0.8");
        assert!(Locale::EN_US.number_elsewhere("abc").is_none());
        // A date with a separator the locale does not read: its own separator meant.
        let (other, meant) = locale("de-DE").number_elsewhere("12/03/2025").unwrap();
        assert_eq!((other.tag, meant.as_str()), ("fr-FR", "12.03.2025"));
        assert_eq!(locale("et-EE").number_elsewhere("12-3-25").unwrap().1, "12.3.25");
        assert!(locale("fr-FR").number_elsewhere("12/03/2025").is_none());
    }
}
