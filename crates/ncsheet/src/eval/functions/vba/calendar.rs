//! VBA's calendar arithmetic: `DateAdd`, `DateDiff`, `DatePart`, `WeekdayName`, `MonthName`,
//! `DateValue` and `TimeValue`, as the Office VBA language reference's pages of those names
//! give them. A Date is taken apart into its day (counted from 1899-12-30, VBA's day 0) and
//! the second of that day, both whole numbers, so that a month added or the hours between two
//! moments are counted on the calendar and never on the Date's double, whose fraction is the
//! time of day on either side of day 0 ([MS-VBAL] 2.1.1.1, "Date data type").

use crate::eval::coerce::to_number;
use crate::eval::dates::DateTime;
use crate::eval::format::text_format::{MONTHS, WEEKDAYS};
use crate::eval::functions::api::Ctx;
use crate::eval::value::{Value, XlResult};
use crate::formula::ast::Expr;

use super::conversions::{days_from_civil, vba_date_time, Raised};
use super::{lift_vba, vba_text, FIRST, NO_NULL, VBA_DATES};

const DAY_SECONDS: i64 = 86_400;
const LONG_MAX: f64 = 2_147_483_647.0;

/// A VBA Date taken apart: its calendar day and the second of that day.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Moment {
    /// Days from 1899-12-30.
    day: i64,
    /// Seconds since the day's midnight, 0 to 86,399.
    second: i64,
}

impl Moment {
    /// A Date argument as CDate reads it (a number, date text, True); outside VBA's dates,
    /// 100-01-01 to 9999-12-31, Overflow (error 6) as CDate gives.
    fn of(raised: &Raised, v: &Value) -> XlResult<Moment> {
        let parts = vba_date_time(raised, v)?;
        let second = i64::from(parts.hour) * 3600 + i64::from(parts.minute) * 60 + i64::from(parts.second);
        Ok(Moment { day: parts.serial, second })
    }

    /// The day's year, month and day (its time is in `second`).
    fn parts(self) -> DateTime {
        DateTime::from_vba_date(self.day as f64, 0)
    }

    /// Seconds from 1899-12-30 00:00, counting on through the calendar on both sides of day 0.
    fn seconds(self) -> i64 {
        self.day * DAY_SECONDS + self.second
    }

    fn from_seconds(seconds: i64) -> Moment {
        Moment { day: seconds.div_euclid(DAY_SECONDS), second: seconds.rem_euclid(DAY_SECONDS) }
    }

    /// The Date's double: whole days, and the time of day as the fraction's absolute value
    /// (-1.25 is 1899-12-29 6:00 AM). `None` outside VBA's dates.
    fn serial(self) -> Option<f64> {
        let first = days_from_civil(100, 1, 1);
        let last = days_from_civil(9999, 12, 31);
        if !(first..=last).contains(&self.day) {
            return None;
        }
        let time = self.second as f64 / DAY_SECONDS as f64;
        Some(if self.day >= 0 { self.day as f64 + time } else { self.day as f64 - time })
    }
}

/// The number of days of `month` (1 to 12) of `year`, in the proleptic Gregorian calendar.
fn month_length(year: i64, month: i64) -> i64 {
    let next = year * 12 + month;
    days_from_civil(next.div_euclid(12), next.rem_euclid(12) + 1, 1) - days_from_civil(year, month, 1)
}

/// The `interval` argument ("Settings" of DateAdd, DateDiff and DatePart), case ignored.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Interval {
    Year,
    Quarter,
    Month,
    DayOfYear,
    Day,
    Weekday,
    Week,
    Hour,
    Minute,
    Second,
}

impl Interval {
    fn of(v: &Value) -> XlResult<Option<Interval>> {
        let text = vba_text(v)?;
        Ok(Some(match text.to_ascii_lowercase().as_str() {
            "yyyy" => Interval::Year,
            "q" => Interval::Quarter,
            "m" => Interval::Month,
            "y" => Interval::DayOfYear,
            "d" => Interval::Day,
            "w" => Interval::Weekday,
            "ww" => Interval::Week,
            "h" => Interval::Hour,
            "n" => Interval::Minute,
            "s" => Interval::Second,
            _ => return Ok(None),
        }))
    }
}

const BAD_INTERVAL: &str = "the interval is not one of yyyy, q, m, y, d, w, ww, h, n, s";
const OUT_OF_RANGE: &str = "the date is outside 100-01-01 to 9999-12-31";

/// `firstdayofweek` (vbSunday 1 … vbSaturday 7; left out, Sunday; vbUseSystemDayOfWeek 0,
/// the system's: Sunday in en-US); `None` past 0 to 7.
fn first_day_of_week(raised: &Raised, v: Option<&Value>) -> XlResult<Option<i64>> {
    match v {
        None | Some(Value::Blank) => Ok(Some(1)),
        Some(f) => Ok(match raised.whole(f, 32767.0)? as i64 {
            0 => Some(1),
            f @ 1..=7 => Some(f),
            _ => None,
        }),
    }
}

/// `firstweekofyear` (vbFirstJan1 1, vbFirstFourDays 2, vbFirstFullWeek 3; left out or
/// vbUseSystem 0, the system's: January 1 in en-US); `None` past 0 to 3.
fn first_week_of_year(raised: &Raised, v: Option<&Value>) -> XlResult<Option<FirstWeek>> {
    let n = match v {
        None | Some(Value::Blank) => 1,
        Some(w) => raised.whole(w, 32767.0)? as i64,
    };
    Ok(match n {
        0 | 1 => Some(FirstWeek::Jan1),
        2 => Some(FirstWeek::FourDays),
        3 => Some(FirstWeek::FullWeek),
        _ => None,
    })
}

/// The `firstdayofweek` and `firstweekofyear` arguments at `at` and after it; either past its
/// settings is error 5.
pub(super) fn week_arguments(raised: &Raised, v: &[Value], at: usize) -> XlResult<(i64, FirstWeek)> {
    let first = first_day_of_week(raised, v.get(at))?
        .ok_or_else(|| raised.set(5, "the first day of the week is not 0 to 7"))?;
    let rule = first_week_of_year(raised, v.get(at + 1))?
        .ok_or_else(|| raised.set(5, "the first week of the year is not 0 to 3"))?;
    Ok((first, rule))
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum FirstWeek {
    Jan1,
    FourDays,
    FullWeek,
}

/// The first day of the week that holds `day`, weeks starting on `first` (1 Sunday … 7
/// Saturday). Day 0, 1899-12-30, was a Saturday, so day `first` is the weekday `first`.
fn week_start(day: i64, first: i64) -> i64 {
    day - (day - first).rem_euclid(7)
}

/// The day of the week of `day`, 1 for `first`.
fn weekday_from(day: i64, first: i64) -> i64 {
    (day - first).rem_euclid(7) + 1
}

/// The first day of week 1 of `year`.
fn first_week_start(year: i64, first: i64, rule: FirstWeek) -> i64 {
    let jan1 = days_from_civil(year, 1, 1);
    let start = week_start(jan1, first);
    let days_in_year = 7 - (jan1 - start);
    match rule {
        FirstWeek::Jan1 => start,
        FirstWeek::FourDays if days_in_year >= 4 => start,
        FirstWeek::FullWeek if start == jan1 => start,
        _ => start + 7,
    }
}

/// DatePart's "ww": the week of the year. Days before the year's week 1 are in the last week
/// of the year before; with vbFirstFourDays the last days of December may be in week 1 of the
/// next year (the rule of ISO 8601 with vbMonday).
fn week_of_year(day: i64, year: i64, first: i64, rule: FirstWeek) -> i64 {
    if rule == FirstWeek::FourDays && day >= first_week_start(year + 1, first, rule) {
        return 1;
    }
    let start = first_week_start(year, first, rule);
    let start = if day < start { first_week_start(year - 1, first, rule) } else { start };
    (day - start).div_euclid(7) + 1
}

/// DatePart's "ww" as VBA gives it, bug for bug: [`week_of_year`], except that with vbMonday
/// and vbFirstFourDays a Monday on December 29, 30 or 31 before a leap year is week 53, where
/// ISO 8601 has it in week 1 of the next year. Microsoft's article "Format or DatePart
/// functions can return wrong week number for last Monday in Year" (the DatePart page's
/// warning) puts it down to Oleaut32 and lists the dates from 1850 on: 12/29/1851,
/// 12/31/1855, 12/30/1867, 12/29/1879, 12/31/1883, 12/30/1895 …, each such Monday before a
/// leap year and no other (1850-12-30 and 1856-12-29, Mondays before common years, are not
/// in it); its example, 12/29/2003, is one too.
fn vba_week_of_year(day: i64, year: i64, first: i64, rule: FirstWeek) -> i64 {
    const MONDAY: i64 = 2;
    let last_monday_before_leap_year = weekday_from(day, MONDAY) == 1
        && day >= days_from_civil(year, 12, 29)
        && days_from_civil(year + 2, 1, 1) - days_from_civil(year + 1, 1, 1) == 366;
    if first == MONDAY && rule == FirstWeek::FourDays && last_monday_before_leap_year {
        return 53;
    }
    week_of_year(day, year, first, rule)
}

/// Format's `w` and `ww` for a day: DatePart's "w" and "ww" by the same rules, so that the
/// week-53 bug Microsoft's article gives for both functions is in both.
pub(super) fn week_numbers(first: i64, rule: FirstWeek) -> impl Fn(&DateTime) -> (i64, i64) {
    move |dt: &DateTime| (weekday_from(dt.serial, first), vba_week_of_year(dt.serial, dt.year, first, rule))
}

/// Format's weeks when its call leaves them out: Sunday first, week 1 the week of January 1.
pub(super) fn default_week_numbers() -> impl Fn(&DateTime) -> (i64, i64) {
    week_numbers(1, FirstWeek::Jan1)
}

/// `DateAdd(interval, number, date)` ("DateAdd function"): `number` intervals added (rounded
/// to a whole number first); months, quarters and years keep the day of the month unless the
/// month is shorter (Jan 31 + 1 month is Feb 28 or 29); a result outside 100-01-01 to
/// 9999-12-31 is error 5. A Null date gives Null.
pub(super) fn date_add(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "DateAdd", 0b100, &|v| {
        let interval = Interval::of(&v[0])?.ok_or_else(|| raised.set(5, BAD_INTERVAL))?;
        let number = to_number(&v[1], VBA_DATES)?.round_ties_even();
        // More seconds than VBA's dates span: out of range whatever the date.
        if number.abs() > 1e12 {
            return Err(raised.set(5, OUT_OF_RANGE));
        }
        let number = number as i64;
        let at = Moment::of(&raised, &v[2])?;
        let moved = match interval {
            Interval::Year => add_months(at, number * 12),
            Interval::Quarter => add_months(at, number * 3),
            Interval::Month => add_months(at, number),
            Interval::DayOfYear | Interval::Day | Interval::Weekday => Some(Moment { day: at.day + number, ..at }),
            Interval::Week => Some(Moment { day: at.day + number * 7, ..at }),
            Interval::Hour => Some(Moment::from_seconds(at.seconds() + number * 3600)),
            Interval::Minute => Some(Moment::from_seconds(at.seconds() + number * 60)),
            Interval::Second => Some(Moment::from_seconds(at.seconds() + number)),
        };
        let serial = moved.and_then(Moment::serial).ok_or_else(|| raised.set(5, OUT_OF_RANGE))?;
        Ok(Value::Number(serial))
    });
    raised.raise(ctx, "DateAdd", result)
}

/// `at` moved by `months`, its day of the month kept where the month has it, else the
/// month's last day; `None` outside the years 100 to 9999.
fn add_months(at: Moment, months: i64) -> Option<Moment> {
    let parts = at.parts();
    let total = parts.year * 12 + i64::from(parts.month) - 1 + months;
    let (year, month) = (total.div_euclid(12), total.rem_euclid(12) + 1);
    if !(100..=9999).contains(&year) {
        return None;
    }
    let day = i64::from(parts.day).min(month_length(year, month));
    Some(Moment { day: days_from_civil(year, month, day), second: at.second })
}

/// `DateDiff(interval, date1, date2[, firstdayofweek[, firstweekofyear]])` ("DateDiff
/// function"): the boundaries of `interval` crossed from `date1` to `date2` (negative when
/// `date1` is later): years between Dec 31 and Jan 1 is 1; "w" the whole weeks between; "ww"
/// the first days of the week after `date1` up to and including `date2`. A Long: past its
/// range Overflow. A Null date gives Null.
pub(super) fn date_diff(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "DateDiff", 0b110, &|v| {
        let interval = Interval::of(&v[0])?.ok_or_else(|| raised.set(5, BAD_INTERVAL))?;
        let (first, _) = week_arguments(&raised, v, 3)?;
        let (a, b) = (Moment::of(&raised, &v[1])?, Moment::of(&raised, &v[2])?);
        let (pa, pb) = (a.parts(), b.parts());
        let months = |p: &DateTime| p.year * 12 + i64::from(p.month);
        let quarters = |p: &DateTime| p.year * 4 + (i64::from(p.month) - 1) / 3;
        let n = match interval {
            Interval::Year => pb.year - pa.year,
            Interval::Quarter => quarters(&pb) - quarters(&pa),
            Interval::Month => months(&pb) - months(&pa),
            Interval::DayOfYear | Interval::Day => b.day - a.day,
            // Whole weeks, toward zero: from a Monday, the Mondays after it up to date2.
            Interval::Weekday => (b.day - a.day) / 7,
            Interval::Week => (week_start(b.day, first) - week_start(a.day, first)) / 7,
            Interval::Hour => b.seconds().div_euclid(3600) - a.seconds().div_euclid(3600),
            Interval::Minute => b.seconds().div_euclid(60) - a.seconds().div_euclid(60),
            Interval::Second => b.seconds() - a.seconds(),
        };
        if n.unsigned_abs() as f64 > LONG_MAX {
            return Err(raised.set(6, "the count is past the range of a Long"));
        }
        Ok(Value::Number(n as f64))
    });
    raised.raise(ctx, "DateDiff", result)
}

/// `DatePart(interval, date[, firstdayofweek[, firstweekofyear]])` ("DatePart function"):
/// one part of the date: "w" the day of the week (1 for `firstdayofweek`), "ww" the week of
/// the year by `firstweekofyear`, "y" the day of the year. A Null date gives Null.
pub(super) fn date_part(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "DatePart", 0b10, &|v| {
        let interval = Interval::of(&v[0])?.ok_or_else(|| raised.set(5, BAD_INTERVAL))?;
        let (first, rule) = week_arguments(&raised, v, 2)?;
        let at = Moment::of(&raised, &v[1])?;
        let p = at.parts();
        let n = match interval {
            Interval::Year => p.year,
            Interval::Quarter => (i64::from(p.month) - 1) / 3 + 1,
            Interval::Month => i64::from(p.month),
            Interval::DayOfYear => at.day - days_from_civil(p.year, 1, 1) + 1,
            Interval::Day => i64::from(p.day),
            Interval::Weekday => weekday_from(at.day, first),
            Interval::Week => vba_week_of_year(at.day, p.year, first, rule),
            Interval::Hour => at.second / 3600,
            Interval::Minute => at.second / 60 % 60,
            Interval::Second => at.second % 60,
        };
        Ok(Value::Number(n as f64))
    });
    raised.raise(ctx, "DatePart", result)
}

/// A name, or its first three letters when `abbreviate` (an optional Boolean) is True, as
/// the en-US locale abbreviates day and month names.
fn named(name: &str, abbreviate: Option<&Value>) -> XlResult<Value> {
    let short = match abbreviate {
        None | Some(Value::Blank) => false,
        Some(Value::Bool(b)) => *b,
        Some(other) => to_number(other, VBA_DATES)? != 0.0,
    };
    Ok(Value::text(if short { &name[..3] } else { name }))
}

/// `WeekdayName(weekday[, abbreviate[, firstdayofweek]])` ("WeekdayName function"): the name
/// of day `weekday` (1 to 7) of a week starting on `firstdayofweek` (Sunday unless given);
/// past 1 to 7 error 5.
pub(super) fn weekday_name(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "WeekdayName", NO_NULL, &|v| {
        let weekday = raised.whole(&v[0], LONG_MAX)? as i64;
        let first = first_day_of_week(&raised, v.get(2))?
            .ok_or_else(|| raised.set(5, "the first day of the week is not 0 to 7"))?;
        if !(1..=7).contains(&weekday) {
            return Err(raised.set(5, "the day of the week is not 1 to 7"));
        }
        named(WEEKDAYS[(weekday - 1 + first - 1).rem_euclid(7) as usize], v.get(1))
    });
    raised.raise(ctx, "WeekdayName", result)
}

/// `MonthName(month[, abbreviate])` ("MonthName function"): the month's name; past 1 to 12
/// error 5.
pub(super) fn month_name(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "MonthName", NO_NULL, &|v| {
        let month = raised.whole(&v[0], LONG_MAX)? as i64;
        if !(1..=12).contains(&month) {
            return Err(raised.set(5, "the month is not 1 to 12"));
        }
        named(MONTHS[month as usize - 1], v.get(1))
    });
    raised.raise(ctx, "MonthName", result)
}

/// `DateValue(date)` ("DateValue function"): the date of a date text or Date, its time left
/// out. Null gives Null.
pub(super) fn date_value(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "DateValue", FIRST, &|v| {
        let at = Moment::of(&raised, &v[0])?;
        Ok(Value::Number(at.day as f64))
    });
    raised.raise(ctx, "DateValue", result)
}

/// `TimeValue(time)` ("TimeValue function"): the time of day of a time text or Date, as a
/// fraction of a day. Null gives Null.
pub(super) fn time_value(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "TimeValue", FIRST, &|v| {
        let at = Moment::of(&raised, &v[0])?;
        Ok(Value::Number(at.second as f64 / DAY_SECONDS as f64))
    });
    raised.raise(ctx, "TimeValue", result)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weeks_start_on_their_first_day() {
        // 2024-01-01 was a Monday (days_from_civil gives its day): a Sunday week starts the
        // day before, a Monday week on it.
        let monday = days_from_civil(2024, 1, 1);
        assert_eq!(week_start(monday, 1), monday - 1);
        assert_eq!(week_start(monday, 2), monday);
        assert_eq!(weekday_from(monday, 1), 2);
        assert_eq!(weekday_from(monday, 2), 1);
    }

    #[test]
    fn iso_weeks_by_first_four_days_and_monday() {
        // ISO 8601 week numbers (Monday weeks, the week of January 4 is week 1):
        // 2021-01-03 is in 2020-W53, 2021-01-04 in 2021-W01, 2024-12-31 in 2025-W01.
        let week = |y, m, d| week_of_year(days_from_civil(y, m, d), y, 2, FirstWeek::FourDays);
        assert_eq!(week(2021, 1, 3), 53);
        assert_eq!(week(2021, 1, 4), 1);
        assert_eq!(week(2024, 12, 31), 1);
        assert_eq!(week(2024, 12, 29), 52);
    }
}
