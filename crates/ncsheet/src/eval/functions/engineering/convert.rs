//! CONVERT: Excel's unit table (weight, distance, time, pressure, force, energy, power,
//! magnetism, temperature, volume, area, information, speed) with its metric and binary
//! prefixes. A value goes through the class's base unit (gram, metre, second, …; kelvin for
//! temperature, whose scales have offsets).

use crate::eval::functions::api::{check, finite, scalar, Ctx, FnSpec};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

pub const FUNCTIONS: &[FnSpec] = &[FnSpec::value(
    "CONVERT",
    3,
    3,
    convert,
    "CONVERT(number, from_unit, to_unit)",
    "number in from_unit expressed in to_unit (\"in\", \"mm\", \"lbm\", \"kg\", \"C\", \"F\", …)",
)];

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Class {
    Weight,
    Distance,
    Time,
    Pressure,
    Force,
    Energy,
    Power,
    Magnetism,
    Temperature,
    Volume,
    Area,
    Information,
    Speed,
}

/// Which prefixes a unit takes, and to what power (a square metre takes the prefix squared).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Prefixes {
    None,
    Metric(i32),
    /// Metric and binary (ki, Mi, …): bit and byte.
    Binary,
}

struct Unit {
    names: &'static [&'static str],
    class: Class,
    /// The unit in the class's base unit (for temperature: the kelvin size of one degree).
    size: f64,
    prefixes: Prefixes,
}

const fn unit(names: &'static [&'static str], class: Class, size: f64, prefixes: Prefixes) -> Unit {
    Unit { names, class, size, prefixes }
}

use Class::*;
use Prefixes::{Binary, Metric, None as Plain};

const INCH: f64 = 0.0254;
const FOOT: f64 = 0.3048;
const MILE: f64 = 1609.344;
const NAUTICAL_MILE: f64 = 1852.0;
const LIGHT_YEAR: f64 = 9460730472580800.0;
const PICA_POINT: f64 = INCH / 72.0;
const POUND: f64 = 453.59237;
const POUND_FORCE: f64 = 4.4482216152605;
const HORSEPOWER: f64 = 745.699_871_582_270_2;
const US_PINT: f64 = 4.73176473e-4;

/// Excel's units. Sizes are exact definitions where one exists (the inch, the pound, the
/// US gallon) and Excel's own constants otherwise (atomic mass unit, electron volt, BTU).
static UNITS: &[Unit] = &[
    unit(&["g"], Weight, 1.0, Metric(1)),
    unit(&["sg"], Weight, POUND_FORCE / FOOT * 1000.0, Plain),
    unit(&["lbm"], Weight, POUND, Plain),
    unit(&["u"], Weight, 1.660538782e-24, Metric(1)),
    unit(&["ozm"], Weight, POUND / 16.0, Plain),
    unit(&["grain"], Weight, 0.06479891, Plain),
    unit(&["cwt", "shweight"], Weight, POUND * 100.0, Plain),
    unit(&["uk_cwt", "lcwt", "hweight"], Weight, POUND * 112.0, Plain),
    unit(&["stone"], Weight, POUND * 14.0, Plain),
    unit(&["ton"], Weight, POUND * 2000.0, Plain),
    unit(&["uk_ton", "LTON", "brton"], Weight, POUND * 2240.0, Plain),
    unit(&["m"], Distance, 1.0, Metric(1)),
    unit(&["mi"], Distance, MILE, Plain),
    unit(&["Nmi"], Distance, NAUTICAL_MILE, Plain),
    unit(&["in"], Distance, INCH, Plain),
    unit(&["ft"], Distance, FOOT, Plain),
    unit(&["yd"], Distance, 0.9144, Plain),
    unit(&["ang"], Distance, 1e-10, Metric(1)),
    unit(&["ell"], Distance, 1.143, Plain),
    unit(&["ly"], Distance, LIGHT_YEAR, Metric(1)),
    unit(&["parsec", "pc"], Distance, 3.0856775812815532e16, Metric(1)),
    unit(&["Picapt", "Pica"], Distance, PICA_POINT, Plain),
    unit(&["pica"], Distance, INCH / 6.0, Plain),
    unit(&["survey_mi"], Distance, 1609.3472186944373, Plain),
    unit(&["yr"], Time, 31557600.0, Plain),
    unit(&["day", "d"], Time, 86400.0, Plain),
    unit(&["hr"], Time, 3600.0, Plain),
    unit(&["mn", "min"], Time, 60.0, Plain),
    unit(&["sec", "s"], Time, 1.0, Metric(1)),
    unit(&["Pa", "p"], Pressure, 1.0, Metric(1)),
    unit(&["atm", "at"], Pressure, 101325.0, Metric(1)),
    unit(&["mmHg"], Pressure, 133.322, Metric(1)),
    unit(&["psi"], Pressure, POUND_FORCE / (INCH * INCH), Plain),
    unit(&["Torr"], Pressure, 101325.0 / 760.0, Plain),
    unit(&["N"], Force, 1.0, Metric(1)),
    unit(&["dyn", "dy"], Force, 1e-5, Metric(1)),
    unit(&["lbf"], Force, POUND_FORCE, Plain),
    unit(&["pond"], Force, 9.80665e-3, Metric(1)),
    unit(&["J"], Energy, 1.0, Metric(1)),
    unit(&["e"], Energy, 1e-7, Metric(1)),
    unit(&["c"], Energy, 4.184, Metric(1)),
    unit(&["cal"], Energy, 4.1868, Metric(1)),
    unit(&["eV", "ev"], Energy, 1.602176487e-19, Metric(1)),
    unit(&["HPh", "hh"], Energy, HORSEPOWER * 3600.0, Plain),
    unit(&["Wh", "wh"], Energy, 3600.0, Metric(1)),
    unit(&["flb"], Energy, POUND_FORCE * FOOT, Plain),
    unit(&["BTU", "btu"], Energy, 1055.05585262, Plain),
    unit(&["HP", "h"], Power, HORSEPOWER, Plain),
    unit(&["PS"], Power, 735.49875, Plain),
    unit(&["W", "w"], Power, 1.0, Metric(1)),
    unit(&["T"], Magnetism, 1.0, Metric(1)),
    unit(&["ga"], Magnetism, 1e-4, Metric(1)),
    unit(&["C", "cel"], Temperature, 1.0, Plain),
    unit(&["F", "fah"], Temperature, 5.0 / 9.0, Plain),
    unit(&["K", "kel"], Temperature, 1.0, Metric(1)),
    unit(&["Rank"], Temperature, 5.0 / 9.0, Plain),
    unit(&["Reau"], Temperature, 1.25, Plain),
    unit(&["tsp"], Volume, US_PINT / 96.0, Plain),
    unit(&["tspm"], Volume, 5e-6, Plain),
    unit(&["tbs"], Volume, US_PINT / 32.0, Plain),
    unit(&["oz"], Volume, US_PINT / 16.0, Plain),
    unit(&["cup"], Volume, US_PINT / 2.0, Plain),
    unit(&["pt", "us_pt"], Volume, US_PINT, Plain),
    unit(&["uk_pt"], Volume, 5.6826125e-4, Metric(1)),
    unit(&["qt"], Volume, US_PINT * 2.0, Plain),
    unit(&["uk_qt"], Volume, 5.6826125e-4 * 2.0, Plain),
    unit(&["gal"], Volume, US_PINT * 8.0, Plain),
    unit(&["uk_gal"], Volume, 4.54609e-3, Plain),
    unit(&["l", "L", "lt"], Volume, 1e-3, Metric(1)),
    unit(&["ang3", "ang^3"], Volume, 1e-30, Metric(3)),
    unit(&["barrel"], Volume, US_PINT * 8.0 * 42.0, Plain),
    unit(&["bushel"], Volume, 0.03523907016688, Plain),
    unit(&["ft3", "ft^3"], Volume, FOOT * FOOT * FOOT, Plain),
    unit(&["in3", "in^3"], Volume, INCH * INCH * INCH, Plain),
    unit(&["ly3", "ly^3"], Volume, LIGHT_YEAR * LIGHT_YEAR * LIGHT_YEAR, Plain),
    unit(&["m3", "m^3"], Volume, 1.0, Metric(3)),
    unit(&["mi3", "mi^3"], Volume, MILE * MILE * MILE, Plain),
    unit(&["yd3", "yd^3"], Volume, 0.9144 * 0.9144 * 0.9144, Plain),
    unit(&["Nmi3", "Nmi^3"], Volume, NAUTICAL_MILE * NAUTICAL_MILE * NAUTICAL_MILE, Plain),
    unit(&["Picapt3", "Picapt^3", "Pica3", "Pica^3"], Volume, PICA_POINT * PICA_POINT * PICA_POINT, Plain),
    unit(&["GRT", "regton"], Volume, FOOT * FOOT * FOOT * 100.0, Plain),
    unit(&["MTON"], Volume, FOOT * FOOT * FOOT * 40.0, Plain),
    unit(&["uk_acre"], Area, 4046.8564224, Plain),
    unit(&["us_acre"], Area, 4046.8726098742522, Plain),
    unit(&["ang2", "ang^2"], Area, 1e-20, Metric(2)),
    unit(&["ar"], Area, 100.0, Metric(1)),
    unit(&["ft2", "ft^2"], Area, FOOT * FOOT, Plain),
    unit(&["ha"], Area, 10000.0, Plain),
    unit(&["in2", "in^2"], Area, INCH * INCH, Plain),
    unit(&["ly2", "ly^2"], Area, LIGHT_YEAR * LIGHT_YEAR, Plain),
    unit(&["m2", "m^2"], Area, 1.0, Metric(2)),
    unit(&["Morgen"], Area, 2500.0, Plain),
    unit(&["mi2", "mi^2"], Area, MILE * MILE, Plain),
    unit(&["Nmi2", "Nmi^2"], Area, NAUTICAL_MILE * NAUTICAL_MILE, Plain),
    unit(&["Picapt2", "Pica2", "Pica^2", "Picapt^2"], Area, PICA_POINT * PICA_POINT, Plain),
    unit(&["yd2", "yd^2"], Area, 0.9144 * 0.9144, Plain),
    unit(&["bit"], Information, 1.0, Binary),
    unit(&["byte"], Information, 8.0, Binary),
    unit(&["admkn"], Speed, 6080.0 * FOOT / 3600.0, Plain),
    unit(&["kn"], Speed, NAUTICAL_MILE / 3600.0, Plain),
    unit(&["m/h", "m/hr"], Speed, 1.0 / 3600.0, Metric(1)),
    unit(&["m/s", "m/sec"], Speed, 1.0, Metric(1)),
    unit(&["mph"], Speed, MILE / 3600.0, Metric(1)),
];

const METRIC_PREFIXES: &[(&str, f64)] = &[
    ("Y", 1e24),
    ("Z", 1e21),
    ("E", 1e18),
    ("P", 1e15),
    ("T", 1e12),
    ("G", 1e9),
    ("M", 1e6),
    ("k", 1e3),
    ("h", 1e2),
    ("da", 1e1),
    ("e", 1e1),
    ("d", 1e-1),
    ("c", 1e-2),
    ("m", 1e-3),
    ("u", 1e-6),
    ("n", 1e-9),
    ("p", 1e-12),
    ("f", 1e-15),
    ("a", 1e-18),
    ("z", 1e-21),
    ("y", 1e-24),
];

const BINARY_PREFIXES: &[(&str, f64)] = &[
    ("Yi", 1208925819614629174706176.0),
    ("Zi", 1180591620717411303424.0),
    ("Ei", 1152921504606846976.0),
    ("Pi", 1125899906842624.0),
    ("Ti", 1099511627776.0),
    ("Gi", 1073741824.0),
    ("Mi", 1048576.0),
    ("ki", 1024.0),
];

/// A unit name, with or without a prefix: its class and its size in the class's base unit.
fn lookup(name: &str) -> Option<(Class, f64)> {
    let exact = |n: &str| UNITS.iter().find(|u| u.names.contains(&n));
    if let Some(u) = exact(name) {
        return Some((u.class, u.size));
    }
    let prefixed = |table: &[(&str, f64)], binary: bool| {
        table.iter().find_map(|(p, factor)| {
            let u = exact(name.strip_prefix(p)?)?;
            let power = match (u.prefixes, binary) {
                (Metric(power), false) => power,
                (Binary, _) => 1,
                _ => return None,
            };
            Some((u.class, u.size * factor.powi(power)))
        })
    };
    prefixed(BINARY_PREFIXES, true).or_else(|| prefixed(METRIC_PREFIXES, false))
}

/// A temperature in kelvin, from a scale whose degree is `size` kelvin.
fn to_kelvin(x: f64, unit: &str) -> f64 {
    match unit_zero(unit) {
        Some((zero, size)) => (x - zero) * size,
        None => x,
    }
}

fn from_kelvin(k: f64, unit: &str) -> f64 {
    match unit_zero(unit) {
        Some((zero, size)) => k / size + zero,
        None => k,
    }
}

/// A temperature scale's reading at 0 K and its degree in kelvin (None for kelvin itself,
/// prefixed or not).
fn unit_zero(unit: &str) -> Option<(f64, f64)> {
    match unit {
        "C" | "cel" => Some((-273.15, 1.0)),
        "F" | "fah" => Some((-459.67, 5.0 / 9.0)),
        "Rank" => Some((0.0, 5.0 / 9.0)),
        "Reau" => Some((-218.52, 1.25)),
        _ => None,
    }
}

fn convert(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        check(!matches!(a.value(0), Value::Bool(_)), XlError::Value)?;
        let x = a.num(0)?;
        let (Value::Text(from), Value::Text(to)) = (a.value(1), a.value(2)) else {
            return Err(XlError::NA);
        };
        let (from_class, from_size) = lookup(from).ok_or(XlError::NA)?;
        let (to_class, to_size) = lookup(to).ok_or(XlError::NA)?;
        check(from_class == to_class, XlError::NA)?;
        if from_class == Temperature {
            // Prefixed kelvin ("mK") has no offset: its size carries the prefix.
            let kelvin = to_kelvin(x, from) * if unit_zero(from).is_none() { from_size } else { 1.0 };
            let out = from_kelvin(kelvin, to) / if unit_zero(to).is_none() { to_size } else { 1.0 };
            return finite(out);
        }
        finite(x * from_size / to_size)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_resolve_with_their_prefixes_as_excel_documents() {
        // Microsoft's CONVERT page: 1 "in" is 2.54 "cm"; "mm" is milli-metre; "kibyte" 1024 bytes.
        let (c, cm) = lookup("cm").expect("cm");
        assert_eq!(c, Distance);
        assert!((INCH / cm - 2.54).abs() < 1e-12);
        assert_eq!(lookup("mm"), Some((Distance, 1e-3)));
        assert_eq!(lookup("kibyte"), Some((Information, 8192.0)));
        // A prefix on a unit that takes none is no unit.
        assert_eq!(lookup("Min"), None);
        assert_eq!(lookup("kift"), None);
        // Exact names first: "Pa" is the pascal, not peta-"a".
        assert_eq!(lookup("Pa"), Some((Pressure, 1.0)));
    }
}
