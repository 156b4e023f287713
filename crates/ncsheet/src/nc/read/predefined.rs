//! LinuxCNC's predefined named parameters (LinuxCNC manual, "Predefined Named Parameters";
//! rs274 of LinuxCNC 2.9 is the check): `#<_x>`, `#<_feed>`, `#<_metric>`, `#<_coord_system>`
//! … read the control's state and cannot be set ("Cannot assign to read-only parameter").
//! The reader answers from its own modal state, which starts where LinuxCNC powers on (G21
//! G90 G17 G94 G97 G40 G54 G80, spindle and coolant off) as every other word it reads
//! assumes; what it does not model (where an axis is before the program moves it, the tool
//! table, machine coordinates, whether a preview or the machine runs the program) is refused
//! by name, never taken as 0.

/// Where an axis is, as the program can know it.
#[derive(Clone, Copy, Default)]
pub enum Axis {
    /// Not moved by the program yet: where it starts is the control's.
    #[default]
    Unknown,
    /// Moved with cutter compensation on (G41/G42): LinuxCNC reports the tool centre, off
    /// the programmed path by the tool's radius.
    Compensated,
    /// The position in the program's units (X a radius on a lathe, as rs274 holds it).
    At(f64),
}

/// The reader's modal state before a line, as the predefined parameters read it.
#[derive(Clone, Copy)]
pub struct Control {
    /// The source line (1-based) being read: `#<_line>`.
    pub line: usize,
    /// Subroutine calls in progress: `#<_call_level>`.
    pub call_level: usize,
    /// X Y Z A B C.
    pub axes: [Axis; 6],
    /// The F in force as written (LinuxCNC sets it to 0 at power on and at G93/G94/G95).
    pub feed: f64,
    /// The S in force as written (rpm, or the surface speed under G96).
    pub speed: f64,
    pub inches: bool,
    pub incremental: bool,
    /// The motion mode as LinuxCNC numbers it (G code × 10; G80 = 800 at power on).
    pub motion_mode: u32,
    /// 170, 180 or 190.
    pub plane: u32,
    /// 400 (G40), 410 (G41), 420 (G42).
    pub compensation: u32,
    pub per_revolution: bool,
    pub surface_speed: bool,
    pub diameter: bool,
    /// Turning, and whether clockwise.
    pub spindle: Option<bool>,
    pub flood: bool,
    /// The tool in the spindle, once a tool change said which.
    pub tool: Option<u32>,
    /// The tool a T word selected.
    pub selected: Option<u32>,
}

impl Default for Control {
    fn default() -> Control {
        Control {
            line: 0,
            call_level: 0,
            axes: [Axis::Unknown; 6],
            feed: 0.0,
            speed: 0.0,
            inches: false,
            incremental: false,
            motion_mode: 800,
            plane: 170,
            compensation: 400,
            per_revolution: false,
            surface_speed: false,
            diameter: false,
            spindle: None,
            flood: false,
            tool: None,
            selected: None,
        }
    }
}

/// Every predefined name rs274 2.9 knows (each refuses "Cannot assign to read-only
/// parameter"). `_value` and `_value_returned` are set by returns from subroutines.
const NAMES: &[&str] = &[
    "_vmajor",
    "_vminor",
    "_line",
    "_motion_mode",
    "_plane",
    "_ccomp",
    "_metric",
    "_imperial",
    "_absolute",
    "_incremental",
    "_inverse_time",
    "_units_per_minute",
    "_units_per_rev",
    "_coord_system",
    "_tool_offset",
    "_retract_r_plane",
    "_retract_old_z",
    "_spindle_rpm_mode",
    "_spindle_css_mode",
    "_ijk_absolute_mode",
    "_lathe_diameter_mode",
    "_lathe_radius_mode",
    "_spindle_on",
    "_spindle_cw",
    "_mist",
    "_flood",
    "_speed_override",
    "_feed_override",
    "_adaptive_feed",
    "_feed_hold",
    "_feed",
    "_rpm",
    "_x",
    "_y",
    "_z",
    "_a",
    "_b",
    "_c",
    "_u",
    "_v",
    "_w",
    "_abs_x",
    "_abs_y",
    "_abs_z",
    "_abs_a",
    "_abs_b",
    "_abs_c",
    "_current_tool",
    "_current_pocket",
    "_selected_tool",
    "_selected_pocket",
    "_value",
    "_value_returned",
    "_task",
    "_call_level",
    "_remap_level",
];

/// Whether `name` (lower case, without `#<>`) is one of LinuxCNC's predefined parameters.
pub fn is_predefined(name: &str) -> bool {
    NAMES.contains(&name)
}

fn truth(t: bool) -> f64 {
    if t {
        1.0
    } else {
        0.0
    }
}

impl Control {
    /// The value of the predefined parameter `name` (`None`: not one of them), or why the
    /// reader cannot know it.
    pub fn value(&self, name: &str) -> Option<Result<f64, String>> {
        let known = |v: f64| Some(Ok(v));
        match name {
            // The reader reads as LinuxCNC 2.9.0 does (GE and LE exact, as there).
            "_vmajor" => known(2.9),
            "_vminor" => known(0.0),
            "_line" => known(self.line as f64),
            "_call_level" => known(self.call_level as f64),
            // The reader runs no remaps.
            "_remap_level" => known(0.0),
            "_motion_mode" => known(f64::from(self.motion_mode)),
            "_plane" => known(f64::from(self.plane)),
            "_ccomp" => known(f64::from(self.compensation)),
            "_metric" => known(truth(!self.inches)),
            "_imperial" => known(truth(self.inches)),
            "_absolute" => known(truth(!self.incremental)),
            "_incremental" => known(truth(self.incremental)),
            // G93 is not read: the feed mode is G94 or G95.
            "_inverse_time" => known(0.0),
            "_units_per_minute" => known(truth(!self.per_revolution)),
            "_units_per_rev" => known(truth(self.per_revolution)),
            // G54–G59.3 are not read: the program stays in the power-on G54.
            "_coord_system" => known(540.0),
            // G98/G99 and the canned cycles are not read: the power-on G98.
            "_retract_r_plane" => known(1.0),
            "_retract_old_z" => known(0.0),
            "_spindle_rpm_mode" => known(truth(!self.surface_speed)),
            "_spindle_css_mode" => known(truth(self.surface_speed)),
            // G90.1 is not read: arc centres are incremental (G91.1), as at power on.
            "_ijk_absolute_mode" => known(0.0),
            "_lathe_diameter_mode" => known(truth(self.diameter)),
            "_lathe_radius_mode" => known(truth(!self.diameter)),
            "_spindle_on" => known(truth(self.spindle.is_some())),
            "_spindle_cw" => known(truth(self.spindle == Some(true))),
            // M7 is not read.
            "_mist" => known(0.0),
            "_flood" => known(truth(self.flood)),
            // M48–M53 are not read: the overrides stay as at power on.
            "_speed_override" | "_feed_override" | "_feed_hold" => known(1.0),
            "_adaptive_feed" => known(0.0),
            "_feed" => known(self.feed),
            "_rpm" => known(self.speed),
            "_x" | "_y" | "_z" | "_a" | "_b" | "_c" => Some(self.axis(name)),
            "_current_tool" => Some(self.tool.map(f64::from).ok_or_else(|| {
                format!("#<{name}> is read before the program's first tool change (T… M6): the tool in the spindle is the control's")
            })),
            "_selected_tool" => Some(self.selected.map(f64::from).ok_or_else(|| {
                format!("#<{name}> is read before the program selects a tool (T…): the tool selected is the control's")
            })),
            "_u" | "_v" | "_w" => Some(Err(format!(
                "#<{name}> reads an axis this reader does not move (it reads X Y Z A B C): its position is the control's"
            ))),
            _ if name.starts_with("_abs_") => Some(Err(format!(
                "#<{name}> is a machine coordinate: it depends on the control's work offsets (G54–G59.3, G92) and \
                 tool length, which ncsheet does not model"
            ))),
            "_tool_offset" => Some(Err(format!(
                "#<{name}> says whether a length offset other than zero is applied: it depends on the tool table's \
                 lengths, which ncsheet does not read"
            ))),
            "_current_pocket" | "_selected_pocket" => {
                Some(Err(format!("#<{name}> is a pocket of the tool table, which ncsheet does not read")))
            }
            "_task" => Some(Err(format!(
                "#<{name}> tells the machine running the program (1) from a preview reading it (0), and programs do \
                 different things by it: ncsheet does not guess which is meant"
            ))),
            _ => None,
        }
    }

    fn axis(&self, name: &str) -> Result<f64, String> {
        let i = "xyzabc".find(&name[1..]).expect("an axis name");
        let letter = name[1..].to_ascii_uppercase();
        match self.axes[i] {
            Axis::At(v) => Ok(v),
            Axis::Unknown => Err(format!(
                "#<{name}> is read before the program moves {letter}: where the axis starts is the control's"
            )),
            Axis::Compensated => Err(format!(
                "#<{name}> is read after a move with cutter compensation (G41/G42): LinuxCNC gives the tool centre, \
                 off the programmed {letter} by the tool's radius, which ncsheet does not model"
            )),
        }
    }
}
