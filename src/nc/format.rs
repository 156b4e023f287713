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
        let mut text = format!("{:.*}", self.decimals, v);
        if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
            text = text.trim_start_matches('-').to_string();
        }
        if !self.trailing_zeros && text.contains('.') {
            text = text.trim_end_matches('0').to_string();
            if !self.always_point {
                text = text.trim_end_matches('.').to_string();
            }
        }
        if self.plus_sign && !text.starts_with('-') {
            text.insert(0, '+');
        }
        text
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
}
