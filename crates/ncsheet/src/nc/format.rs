//! Numbers as controls want them: fixed decimals, optional `+`, trailing zeros or not.

/// How one dialect writes a coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NumberStyle {
    /// Digits after the point (the control's resolution: 3 → 0.001 mm).
    pub decimals: usize,
    /// Write `+` before positive numbers (Heidenhain).
    pub plus_sign: bool,
    /// Keep zeros after the last significant digit (`1.500` rather than `1.5`).
    pub trailing_zeros: bool,
    /// Always write the point (`40.`): Fanuc reads `X40` as 40 µm in some modes.
    pub always_point: bool,
}

impl NumberStyle {
    pub fn resolution(&self) -> f64 {
        10f64.powi(-(self.decimals as i32))
    }

    /// Writes `v` rounded to the resolution (half away from zero; never `-0`).
    pub fn write(&self, v: f64) -> String {
        let mut out = String::new();
        self.write_to(&mut out, v);
        out
    }

    /// [`NumberStyle::write`] appending to `out`, without allocating (a program of a million
    /// points is written number by number).
    pub fn write_to(&self, out: &mut String, v: f64) {
        if !self.write_fast(out, v) {
            self.write_exact(out, v);
        }
    }

    /// Through std's `{:.N}` formatting: exact, and slow where it falls back to big numbers.
    fn write_exact(&self, out: &mut String, v: f64) {
        let full = format!("{:.*}", self.decimals, v);
        let mut text = full.as_str();
        if text.trim_start_matches('-').bytes().all(|c| c == b'0' || c == b'.') {
            text = text.trim_start_matches('-');
        }
        if !self.trailing_zeros && text.contains('.') {
            text = text.trim_end_matches('0');
            if !self.always_point {
                text = text.trim_end_matches('.');
            }
        }
        if self.plus_sign && !text.starts_with('-') {
            out.push('+');
        }
        out.push_str(text);
    }

    /// [`NumberStyle::write_exact`] by integer arithmetic, where that is sure to write the
    /// same: below 2^32 the scaled value is within 5e-7 of exact, so rounding it agrees with
    /// rounding the exact value unless that lies within 1e-6 of a tie (then `false`, nothing
    /// written).
    fn write_fast(&self, out: &mut String, v: f64) -> bool {
        const POW10: [u64; 10] =
            [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000, 10_000_000, 100_000_000, 1_000_000_000];
        let Some(&scale) = POW10.get(self.decimals) else { return false };
        let scaled = v.abs() * scale as f64;
        if scaled.is_nan() || scaled >= 4.0e9 {
            return false;
        }
        // `as` truncates: floor and round without calls into libm.
        let whole = scaled as u64;
        let fraction = scaled - whole as f64;
        if (fraction - 0.5).abs() < 1e-6 {
            return false;
        }
        let n = whole + u64::from(fraction > 0.5);
        if v.is_sign_negative() && n != 0 {
            out.push('-');
        } else if self.plus_sign {
            out.push('+');
        }
        push_digits(out, n / scale, 1);
        let (mut fraction, mut digits) = (n % scale, self.decimals);
        if !self.trailing_zeros {
            while digits > 0 && fraction % 10 == 0 {
                fraction /= 10;
                digits -= 1;
            }
        }
        if digits > 0 || (self.decimals > 0 && (self.always_point || self.trailing_zeros)) {
            out.push('.');
        }
        if digits > 0 {
            push_digits(out, fraction, digits);
        }
        true
    }
}

/// `n` in decimal, zero-padded to at least `width` digits.
fn push_digits(out: &mut String, mut n: u64, width: usize) {
    let mut buf = [b'0'; 20];
    let mut i = buf.len();
    while n > 0 || buf.len() - i < width {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
    }
    for &b in &buf[i..] {
        out.push(char::from(b));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn styles_of_the_controls() {
        let fanuc = NumberStyle { decimals: 3, plus_sign: false, trailing_zeros: false, always_point: true };
        assert_eq!(fanuc.write(40.0), "40.");
        assert_eq!(fanuc.write(-4.6), "-4.6");
        assert_eq!(fanuc.write(44.2627417), "44.263");
        assert_eq!(fanuc.write(-0.0001), "0.");
        let heidenhain = NumberStyle { decimals: 4, plus_sign: true, trailing_zeros: true, always_point: false };
        assert_eq!(heidenhain.write(25.0), "+25.0000");
        assert_eq!(heidenhain.write(-2.49892161), "-2.4989");
        let plain = NumberStyle { decimals: 3, plus_sign: false, trailing_zeros: false, always_point: false };
        assert_eq!(plain.write(34.0), "34");
        assert_eq!(plain.write(0.5), "0.5");
    }

    #[test]
    fn the_fast_path_writes_what_std_writes() {
        let values =
            [0.0, -0.0, 1.0, -1.5, 0.00005, -0.00004, 12345.678949, 0.1 + 0.2, -25.0048, 3999.99996, 7.0, 40.0];
        for decimals in [0, 1, 3, 4, 9] {
            for (plus_sign, trailing_zeros, always_point) in
                [(false, false, false), (true, true, false), (false, false, true)]
            {
                let style = NumberStyle { decimals, plus_sign, trailing_zeros, always_point };
                for v in values {
                    let (mut fast, mut exact) = (String::new(), String::new());
                    style.write_exact(&mut exact, v);
                    if style.write_fast(&mut fast, v) {
                        assert_eq!(fast, exact, "{v} in {style:?}");
                    }
                }
            }
        }
    }
}
