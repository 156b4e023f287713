//! Excel's date serial numbers, in one place: the date functions, TEXT's date formats and the
//! reading of date and time text (`VALUE("1/10/2024")`, `DATEVALUE`, `TIMEVALUE`) all convert
//! through here.
//!
//! The 1900 date system: serial 1 is 1900-01-01, a day is 1, a time of day the fraction.
//! Excel copies Lotus 1-2-3 in counting 1900 as a leap year, so serial 60 is the fictitious
//! 1900-02-29 and the days before it fall on the weekday after their real one. Serial 0 is
//! shown as 1900-01-00. From 1900-03-01 (serial 61) on the calendar is the real Gregorian one.

/// Serial 0 of the 1904 system, 1904-01-01, is serial 1462 of the 1900 system.
const OFFSET_1904: i64 = 1462;

/// Which day a workbook's serial numbers count from: a setting of the workbook (its
/// `<workbookPr date1904="1"/>`), handed to every conversion below, so that two workbooks
/// evaluated on one thread each keep their own dates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DateSystem {
    /// Serial 1 is 1900-01-01 (Excel on Windows, every new workbook, and VBA's Date type for
    /// days from March 1900 on).
    #[default]
    From1900,
    /// Serial 0 is 1904-01-01 (old Mac workbooks).
    From1904,
}

impl DateSystem {
    /// The system a workbook's 1904 flag names.
    pub fn from_1904_flag(date_1904: bool) -> DateSystem {
        if date_1904 {
            DateSystem::From1904
        } else {
            DateSystem::From1900
        }
    }

    pub fn is_1904(self) -> bool {
        self == DateSystem::From1904
    }

    /// A serial of this system as the 1900 system counts it, which the calendar below uses.
    fn to_1900(self, serial: i64) -> i64 {
        match self {
            DateSystem::From1900 => serial,
            DateSystem::From1904 => serial + OFFSET_1904,
        }
    }

    /// A serial as the 1900 system counts it, in this system.
    fn of_1900(self, serial: i64) -> i64 {
        match self {
            DateSystem::From1900 => serial,
            DateSystem::From1904 => serial - OFFSET_1904,
        }
    }
}

/// 9999-12-31, the last day Excel has.
pub const LAST_SERIAL: i64 = 2_958_465;

/// The days a macro's Date holds ("Date data type": January 1, 100 to December 31, 9999),
/// as serials from 1899-12-30: the first, and the one after the last.
pub const VBA_DATE_RANGE: std::ops::Range<f64> = -657_434.0..(LAST_SERIAL + 1) as f64;

/// Seconds in a day.
const DAY_SECONDS: f64 = 86_400.0;

/// Whether `year` has a February 29 in Excel's calendar (1900 has, for Lotus compatibility).
pub fn is_leap_year(year: i64) -> bool {
    (year % 4 == 0 && year % 100 != 0) || year % 400 == 0 || year == 1900
}

/// Days in `month` (1–12) of `year`, Excel's calendar.
pub fn days_in_month(year: i64, month: u32) -> u32 {
    match month {
        2 if is_leap_year(year) => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// The serial of `day` of `month` of `year` as DATE computes it: a month outside 1–12 moves
/// the year (month 13 is January of the next year, month 0 December of the one before) and a
/// day outside the month counts on from its first (day 0 is the last day of the month before).
/// Any result, in or out of Excel's range, is returned for the caller to judge.
pub fn serial_from_ymd(dates: DateSystem, year: i64, month: i64, day: i64) -> i64 {
    let months = year * 12 + (month - 1);
    let (y, m) = (months.div_euclid(12), months.rem_euclid(12) + 1);
    dates.of_1900(first_of_month(y, m) + day - 1)
}

/// The serial of the first of a month. Before March 1900 Excel counts from 1899-12-31 (so
/// that 1900-02-29 fits in as 60); from then on days are real, counted from 1899-12-30.
fn first_of_month(year: i64, month: i64) -> i64 {
    let days = days_from_civil(year, month, 1);
    if (year, month) < (1900, 3) {
        days - days_from_civil(1899, 12, 31)
    } else {
        days - days_from_civil(1899, 12, 30)
    }
}

/// Year, month and day of a whole serial in Excel's calendar (0 is 1900-01-00, 60 is
/// 1900-02-29). Negative serials, which Excel refuses, count back from 1899-12-31.
pub fn ymd_from_serial(dates: DateSystem, serial: i64) -> (i64, u32, u32) {
    let serial = dates.to_1900(serial);
    match serial {
        ..=-1 => civil_from_days(serial + days_from_civil(1899, 12, 31)),
        0..=31 => (1900, 1, serial as u32),
        32..=60 => (1900, 2, (serial - 31) as u32),
        _ => civil_from_days(serial + days_from_civil(1899, 12, 30)),
    }
}

/// Day of the week of a whole serial, 0 for Sunday. Serial 1 is a Sunday in Excel (the real
/// 1900-01-01 was a Monday): from 1900-03-01 on weekdays are right.
pub fn weekday(dates: DateSystem, serial: i64) -> u32 {
    (dates.to_1900(serial) + 6).rem_euclid(7) as u32
}

/// Days since 1970-01-01 of a proleptic Gregorian date (Howard Hinnant's algorithm).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Proleptic Gregorian date of a day count from 1970-01-01 (Howard Hinnant's algorithm).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// A serial number split into calendar date and time of day.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DateTime {
    /// The whole day's serial.
    pub serial: i64,
    pub year: i64,
    pub month: u32,
    pub day: u32,
    /// 0 for Sunday.
    pub weekday: u32,
    pub hour: u32,
    pub minute: u32,
    pub second: u32,
    pub millis: u32,
    /// Seconds since serial 0, rounded as the time is, for elapsed-time formats (`[h]`).
    pub total_seconds: f64,
}

impl DateTime {
    /// Splits a non-negative serial, rounding the time to whole seconds (or to `sub_second_digits`
    /// decimals of a second) and carrying into the next day as Excel does: 0.99999999 is
    /// midnight of day 1, so HOUR gives 0 and DAY the next day, as TEXT shows it.
    pub fn from_serial(dates: DateSystem, serial: f64, sub_second_digits: usize) -> DateTime {
        let unit = 10f64.powi(sub_second_digits as i32);
        let total_seconds = (serial * DAY_SECONDS * unit).round() / unit;
        let days = (total_seconds / DAY_SECONDS).floor();
        let in_day = total_seconds - days * DAY_SECONDS;
        let secs = in_day.floor() as u32;
        let days = days as i64;
        let (year, month, day) = ymd_from_serial(dates, days);
        DateTime {
            serial: days,
            year,
            month,
            day,
            weekday: weekday(dates, days),
            hour: secs / 3600,
            minute: secs / 60 % 60,
            second: secs % 60,
            millis: ((in_day - in_day.floor()) * 1000.0).round() as u32,
            total_seconds,
        }
    }

    /// Splits a macro's Date ([MS-VBAL] 2.1.1.1 and "Date data type": whole days counted
    /// from 1899-12-30 on both sides of it in the proleptic Gregorian calendar, with no
    /// 1900-02-29, and the fraction's absolute value the time of day, so -1.25 is
    /// 1899-12-29 6:00 AM), rounding the time as [`DateTime::from_serial`] does.
    pub fn from_vba_date(serial: f64, sub_second_digits: usize) -> DateTime {
        let unit = 10f64.powi(sub_second_digits as i32);
        let mut days = serial.trunc();
        let mut in_day = ((serial - days).abs() * DAY_SECONDS * unit).round() / unit;
        if in_day >= DAY_SECONDS {
            // The time rounds up to the next midnight, forward on either side of day 0.
            in_day -= DAY_SECONDS;
            days += 1.0;
        }
        let days = days as i64;
        let secs = in_day.floor() as u32;
        let (year, month, day) = civil_from_days(days + days_from_civil(1899, 12, 30));
        DateTime {
            serial: days,
            year,
            month,
            day,
            // 1899-12-30 was a Saturday.
            weekday: (days + 6).rem_euclid(7) as u32,
            hour: secs / 3600,
            minute: secs / 60 % 60,
            second: secs % 60,
            millis: ((in_day - in_day.floor()) * 1000.0).round() as u32,
            total_seconds: days as f64 * DAY_SECONDS + in_day,
        }
    }
}

/// The system's local date and time now, as a serial of `dates` (what NOW returns unless the
/// workbook's settings fix the clock: `Settings::now`).
pub fn system_now(dates: DateSystem) -> f64 {
    use chrono::{Datelike, Timelike};
    let t = chrono::Local::now().naive_local();
    let day = serial_from_ymd(dates, i64::from(t.year()), i64::from(t.month()), i64::from(t.day()));
    let seconds = f64::from(t.num_seconds_from_midnight()) + f64::from(t.nanosecond() % 1_000_000_000) * 1e-9;
    day as f64 + seconds / DAY_SECONDS
}

// ---------------------------------------------------------------------------------------
// Date and time text

/// Longer than `September 30, 2024 12:30:45.125 PM` with room to spare: not a date.
const MAX_DATE_TEXT: usize = 64;

/// Date and time text as Excel (en-US) reads it: a date, a time, or a date and a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DateText {
    /// The date's serial, when the text has a date.
    pub date: Option<i64>,
    /// The time as a fraction of a day (may exceed 1: `25:00`), when it has a time.
    pub time: Option<f64>,
}

impl DateText {
    /// The whole serial: date plus time.
    pub fn serial(self) -> f64 {
        self.date.unwrap_or(0) as f64 + self.time.unwrap_or(0.0)
    }
}

/// Reads date and time text. Dates: `2024-01-10` and `2024/1/10`; `1/10/2024`, `1-10-24` (month
/// first, as in the US); `10-Jan-2024`, `10 January 2024`; `Jan 10, 2024`, `January 10 2024`;
/// `Jan-2024` (the first). Times: `13:30`, `1:30:15.5`, `1:30 PM`, `1 PM`, `25:00`. A date and
/// a time are separated by spaces. Two-digit years 00–29 are 2000–2029, 30–99 are 1930–1999.
/// Dates without a year (`1/10`, `10-Jan`) are Excel's current year: not read here, since a
/// value would change with the clock. Surrounding spaces are the caller's to trim.
pub fn parse_date_text(dates: DateSystem, text: &str) -> Option<DateText> {
    // Every form is short and has a separator or AM/PM: plain numbers, words and long text
    // leave at once.
    let plausible = text.len() <= MAX_DATE_TEXT && text.contains(['-', '/', ':', ' ', 'm', 'M']);
    if !plausible || text.starts_with(' ') || text.ends_with(' ') {
        return None;
    }
    if let Some(date) = parse_date(dates, text) {
        return Some(DateText { date: Some(date), time: None });
    }
    if let Some(time) = parse_time(text) {
        return Some(DateText { date: None, time: Some(time) });
    }
    // A date and a time: try each space as the boundary (dates may hold spaces themselves).
    text.char_indices().filter(|&(_, c)| c == ' ').find_map(|(i, _)| {
        let date = parse_date(dates, text[..i].trim_end())?;
        let time = parse_time(text[i..].trim_start())?;
        Some(DateText { date: Some(date), time: Some(time) })
    })
}

/// One piece of date text: a run of digits (with how many) or a month name.
#[derive(Clone, Copy, PartialEq)]
enum Piece {
    Number(i64, usize),
    Month(i64),
}

/// A date as its serial in `dates`, from 1900-01-01 to 9999-12-31.
fn parse_date(dates: DateSystem, text: &str) -> Option<i64> {
    let pieces = date_pieces(text)?;
    let (y, m, d) = match pieces[..] {
        [Piece::Number(y, 4), Piece::Number(m, 1..=2), Piece::Number(d, 1..=2)] if !text.contains([' ', ',']) => {
            (y, m, d)
        }
        [Piece::Number(m, 1..=2), Piece::Number(d, 1..=2), Piece::Number(y, n)] if !text.contains([' ', ',']) => {
            (year(y, n)?, m, d)
        }
        [Piece::Number(d, 1..=2), Piece::Month(m), Piece::Number(y, n)] => (year(y, n)?, m, d),
        [Piece::Month(m), Piece::Number(d, 1..=2), Piece::Number(y, n)] => (year(y, n)?, m, d),
        [Piece::Month(m), Piece::Number(y, 4)] => (y, m, 1),
        _ => return None,
    };
    let valid =
        (1900..=9999).contains(&y) && (1..=12).contains(&m) && d >= 1 && d <= i64::from(days_in_month(y, m as u32));
    valid.then(|| serial_from_ymd(dates, y, m, d))
}

/// A year as typed: four digits as they are, two digits in 1930–2029 as Excel reads them.
fn year(y: i64, digits: usize) -> Option<i64> {
    match digits {
        4 => Some(y),
        1 | 2 if y < 30 => Some(2000 + y),
        1 | 2 => Some(1900 + y),
        _ => None,
    }
}

/// Splits date text at `-`, `/`, spaces and a comma after the day (`Jan 10, 2024`); one kind
/// of numeric separator only (`1/10-2024` is not a date).
fn date_pieces(text: &str) -> Option<Vec<Piece>> {
    if text.contains('-') && text.contains('/') {
        return None;
    }
    let mut pieces = Vec::with_capacity(3);
    for word in text.split(['-', '/', ' ']) {
        let word = match word.strip_suffix(',') {
            // Only `Jan 10, 2024` has a comma: after the day, which follows the month.
            Some(w) if matches!(pieces[..], [Piece::Month(_)]) => w,
            Some(_) => return None,
            None => word,
        };
        if word.is_empty() {
            // Runs of spaces separate; an empty piece between `-` or `/` does not.
            if text.contains(['-', '/']) {
                return None;
            }
            continue;
        }
        pieces.push(date_piece(word)?);
    }
    Some(pieces)
}

fn date_piece(word: &str) -> Option<Piece> {
    if !word.bytes().all(|b| b.is_ascii_digit()) {
        return month_number(word).map(Piece::Month);
    }
    if word.len() > 4 {
        return None;
    }
    Some(Piece::Number(word.parse().ok()?, word.len()))
}

const MONTH_NAMES: [&str; 12] = [
    "january",
    "february",
    "march",
    "april",
    "may",
    "june",
    "july",
    "august",
    "september",
    "october",
    "november",
    "december",
];

/// `Jan`, `jan`, `January`: 1. Three letters or the whole name.
fn month_number(word: &str) -> Option<i64> {
    let lower = word.to_ascii_lowercase();
    let i = MONTH_NAMES.iter().position(|name| lower == *name || (lower.len() == 3 && name.starts_with(&lower)))?;
    Some(i as i64 + 1)
}

/// A time of day as a fraction of a day: `h:mm`, `h:mm:ss`, `h:mm:ss.fff`, `mm:ss.f`, each
/// with an optional `AM`/`PM` (then also a bare hour, `1 PM`). Hours without AM/PM may pass 24.
fn parse_time(text: &str) -> Option<f64> {
    let (clock, meridiem) = split_meridiem(text);
    let parts: Vec<&str> = clock.split(':').collect();
    let (h, m, s) = match parts[..] {
        [h] if meridiem.is_some() => (whole(h, 2)?, 0, 0.0),
        [m, s] if s.contains('.') => (0, minutes(m)?, seconds(s)?),
        [h, m] => (whole(h, 4)?, minutes(m)?, 0.0),
        [h, m, s] => (whole(h, 4)?, minutes(m)?, seconds(s)?),
        _ => return None,
    };
    let h = match meridiem {
        Some(pm) if h <= 12 => h % 12 + if pm { 12 } else { 0 },
        Some(_) => return None,
        None => h,
    };
    Some((f64::from(h) * 3600.0 + f64::from(m) * 60.0 + s) / DAY_SECONDS)
}

/// `1:30 PM` → (`1:30`, Some(true)); no AM/PM → (text, None).
fn split_meridiem(text: &str) -> (&str, Option<bool>) {
    let upper = text.len() >= 2 && text.is_char_boundary(text.len() - 2);
    if upper {
        let (clock, suffix) = text.split_at(text.len() - 2);
        let pm = match suffix.to_ascii_uppercase().as_str() {
            "AM" => Some(false),
            "PM" => Some(true),
            _ => None,
        };
        if let Some(pm) = pm {
            return (clock.trim_end(), Some(pm));
        }
    }
    (text, None)
}

/// Digits only, at most `max_len` of them.
fn whole(text: &str, max_len: usize) -> Option<u32> {
    let ok = !text.is_empty() && text.len() <= max_len && text.bytes().all(|b| b.is_ascii_digit());
    ok.then(|| text.parse().ok()).flatten()
}

/// Minutes of an hour: one or two digits, below 60.
fn minutes(text: &str) -> Option<u32> {
    whole(text, 2).filter(|&m| m < 60)
}

/// Seconds of a minute with optional decimals: `05`, `5.25`; below 60.
fn seconds(text: &str) -> Option<f64> {
    let (int, frac) = text.split_once('.').unwrap_or((text, ""));
    let whole_seconds = whole(int, 2)?;
    let ok = whole_seconds < 60 && frac.bytes().all(|b| b.is_ascii_digit());
    ok.then(|| text.parse().ok()).flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    const OLD: DateSystem = DateSystem::From1900;
    const MAC: DateSystem = DateSystem::From1904;

    #[test]
    fn serials_follow_excels_1900_calendar() {
        // Excel: DATE(1900,1,1)=1, DATE(1900,2,28)=59, DATE(1900,2,29)=60, DATE(1900,3,1)=61,
        // DATE(2024,1,10)=45301, DATE(9999,12,31)=2958465.
        assert_eq!(serial_from_ymd(OLD, 1900, 1, 1), 1);
        assert_eq!(serial_from_ymd(OLD, 1900, 2, 28), 59);
        assert_eq!(serial_from_ymd(OLD, 1900, 2, 29), 60);
        assert_eq!(serial_from_ymd(OLD, 1900, 3, 1), 61);
        assert_eq!(serial_from_ymd(OLD, 1900, 3, 0), 60);
        assert_eq!(serial_from_ymd(OLD, 1900, 1, 0), 0);
        assert_eq!(serial_from_ymd(OLD, 2024, 1, 10), 45301);
        assert_eq!(serial_from_ymd(OLD, 2023, 13, 1), serial_from_ymd(OLD, 2024, 1, 1));
        assert_eq!(serial_from_ymd(OLD, 9999, 12, 31), LAST_SERIAL);
        for serial in [0, 1, 31, 32, 59, 60, 61, 45301, LAST_SERIAL] {
            let (y, m, d) = ymd_from_serial(OLD, serial);
            assert_eq!(serial_from_ymd(OLD, y, i64::from(m), i64::from(d)), serial, "{serial}");
        }
        assert_eq!(ymd_from_serial(OLD, 60), (1900, 2, 29));
        assert_eq!(ymd_from_serial(OLD, 0), (1900, 1, 0));
        assert_eq!(ymd_from_serial(OLD, -1), (1899, 12, 30));
        // 2024-01-10 was a Wednesday; Excel's serial 1 a Sunday.
        assert_eq!(weekday(OLD, 45301), 3);
        assert_eq!(weekday(OLD, 1), 0);
    }

    #[test]
    fn times_round_to_the_second_and_carry_into_the_next_day() {
        let t = DateTime::from_serial(OLD, 45301.75, 0);
        assert_eq!((t.year, t.month, t.day, t.hour, t.minute, t.second), (2024, 1, 10, 18, 0, 0));
        let t = DateTime::from_serial(OLD, 45_301.999_999_9, 0);
        assert_eq!((t.day, t.hour), (11, 0));
    }

    fn serial(text: &str) -> Option<f64> {
        parse_date_text(OLD, text).map(DateText::serial)
    }

    #[test]
    fn date_and_time_text_reads_as_excel_reads_it() {
        for text in
            ["2024-01-10", "2024/1/10", "1/10/2024", "1-10-24", "10-Jan-2024", "10 January 2024", "Jan 10, 2024"]
        {
            assert_eq!(serial(text), Some(45301.0), "{text}");
        }
        assert_eq!(serial("Jan-2024"), Some(45292.0));
        assert_eq!(serial("29-Feb-1900"), Some(60.0));
        assert_eq!(serial("1/1/30"), Some(10_959.0));
        assert_eq!(serial("13:30"), Some(0.5625));
        assert_eq!(serial("1:30 PM"), Some(0.5625));
        assert_eq!(serial("12:00 AM"), Some(0.0));
        assert_eq!(serial("6 am"), Some(0.25));
        assert_eq!(serial("25:00"), Some(25.0 / 24.0));
        assert_eq!(serial("0:01:30.5"), Some(90.5 / 86_400.0));
        assert_eq!(serial("2024-02-29 06:00"), Some(45351.25));
        assert_eq!(serial("Jan 10, 2024 6:00 PM"), Some(45301.75));
        for text in
            ["2023-02-29", "1/10", "10-Jan", "13/1/2024", "1:60", "13:00 PM", "12", " 1:30", "1/10-2024", "Jan 10,"]
        {
            assert_eq!(serial(text), None, "{text}");
        }
    }

    #[test]
    fn each_conversion_follows_the_date_system_it_is_given() {
        // Excel's documentation of the two systems: 1904-01-01 is serial 0 of the 1904 system
        // and 1462 of the 1900 one, so 2024-01-10 is 45301 and 43839, and 43839 in the 1900
        // system is 2020-01-09. 1904-01-01 was a Friday.
        assert_eq!(serial_from_ymd(MAC, 1904, 1, 1), 0);
        assert_eq!(serial_from_ymd(OLD, 1904, 1, 1), 1462);
        assert_eq!(serial_from_ymd(MAC, 2024, 1, 10), 43839);
        assert_eq!(ymd_from_serial(MAC, 43839), (2024, 1, 10));
        assert_eq!(ymd_from_serial(OLD, 43839), (2020, 1, 9));
        assert_eq!(weekday(MAC, 0), 5);
        assert_eq!(weekday(OLD, 1462), 5);
        assert_eq!(weekday(MAC, 43839), 3);
        let t = DateTime::from_serial(MAC, 43839.75, 0);
        assert_eq!((t.year, t.month, t.day, t.weekday, t.hour), (2024, 1, 10, 3, 18));
        assert_eq!(parse_date_text(MAC, "2024-01-10 18:00").map(DateText::serial), Some(43839.75));
        // The other system again, with nothing set in between.
        assert_eq!(parse_date_text(OLD, "2024-01-10").map(DateText::serial), Some(45301.0));
        assert_eq!(DateTime::from_serial(OLD, 43839.0, 0).year, 2020);
        // A cell's date format shows a serial in the system it is handed.
        let shown = |serial, dates| crate::eval::format::number_format::shown(serial, Some("yyyy-mm-dd ddd"), dates);
        assert_eq!(shown(43839.0, MAC), "2024-01-10 Wed");
        assert_eq!(shown(43839.0, OLD), "2020-01-09 Thu");
        assert_eq!(shown(43839.0, MAC), "2024-01-10 Wed");
    }
}
