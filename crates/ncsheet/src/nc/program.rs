//! The NC program model: what a macro or a geometry command emits, before any dialect
//! decides how it is written. Units are millimetres and degrees; on a lathe X is a diameter.

use std::fmt;

/// Why a program cannot be plotted, timed or checked: the 1-based block of the model at
/// fault, when one is (the backplot's `PlotError` and the planner's `MotionError`).
#[derive(Clone, Debug, PartialEq)]
pub struct BlockError {
    pub block: Option<usize>,
    pub message: String,
}

impl fmt::Display for BlockError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.block {
            Some(b) => write!(f, "block {b}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for BlockError {}

/// Which machine the program is for; it decides the plane and how X is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Machine {
    /// Z along the spindle, X a diameter, arcs in the ZX plane (G18).
    Lathe,
    /// X, Y, Z milling, arcs in the XY plane (G17) unless a block says otherwise.
    Mill,
}

/// A position; axes left `None` keep their current value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Target {
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub z: Option<f64>,
    pub a: Option<f64>,
    pub b: Option<f64>,
    pub c: Option<f64>,
}

impl Target {
    pub fn xz(x: f64, z: f64) -> Target {
        Target { x: Some(x), z: Some(z), ..Target::default() }
    }

    pub fn xy(x: f64, y: f64) -> Target {
        Target { x: Some(x), y: Some(y), ..Target::default() }
    }

    pub fn xyz(x: f64, y: f64, z: f64) -> Target {
        Target { x: Some(x), y: Some(y), z: Some(z), ..Target::default() }
    }

    /// The axes that are set, as (letter, value), in the order controls print them.
    pub fn axes(&self) -> impl Iterator<Item = (char, f64)> {
        [('X', self.x), ('Y', self.y), ('Z', self.z), ('A', self.a), ('B', self.b), ('C', self.c)]
            .into_iter()
            .filter_map(|(l, v)| v.map(|v| (l, v)))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArcDirection {
    Clockwise,
    CounterClockwise,
}

/// One word of a raw block: `G1`, `X12.5`, `M30`, `T0101`.
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    pub address: char,
    pub value: f64,
    /// The number as the user typed it in text (`0101` of `T0101`): a code word (tool,
    /// offset, G and M codes) is written with these digits, so that `T0101` (tool 1,
    /// offset 1 on a lathe) does not become `T101`. `None` for a number computed.
    pub typed: Option<String>,
}

impl Word {
    /// A word of a computed number.
    pub fn new(address: char, value: f64) -> Word {
        Word { address, value, typed: None }
    }

    /// A word read from text, keeping the digits as typed.
    pub fn typed(address: char, value: f64, typed: &str) -> Word {
        Word { address, value, typed: Some(typed.to_string()) }
    }
}

/// What an F word means: mm per minute (milling, G94) or mm per spindle revolution
/// (turning, G95; Fanuc lathes in G-code system A say G98/G99).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedMode {
    PerMinute,
    PerRevolution,
}

/// Which way the spindle turns: M3 (clockwise seen from the spindle) or M4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpindleDirection {
    Clockwise,
    CounterClockwise,
}

/// The spindle's state from a block on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spindle {
    /// M5.
    Stop,
    /// A fixed speed in revolutions per minute (G97 S… M3).
    Rpm { rpm: f64, direction: SpindleDirection },
    /// Constant surface speed on a lathe: `metres_per_min` at the cut, the spindle never
    /// faster than `max_rpm` (G50 S… / LIMS=… then G96 S… M3).
    SurfaceSpeed { metres_per_min: f64, max_rpm: f64, direction: SpindleDirection },
}

/// Cutter radius compensation from a block on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compensation {
    /// The programmed path is the cutter's centre (G40, R0).
    Off,
    /// Cutter left of the path (G41, RL).
    Left,
    /// Cutter right of the path (G42, RR): outside a contour cut counter-clockwise.
    Right,
}

/// Which tool offset (length, and on a lathe the X/Z geometry) the control applies from a
/// tool change on: whether the program's coordinates are the tool's tip or the spindle's
/// own point (the post's pivot), and from which offset register.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolOffset {
    /// The tool's own offset from the control's tool table: Fanuc lathe `T0101`, mill
    /// `T1 M6 G43 H1`, LinuxCNC `T1 M6 G43`, Sinumerik `T1 D1`,
    /// plain language `TOOL CALL 1` (docs/dialects.md).
    /// The coordinates are the tool tip's.
    Own,
    /// Offset register `n` (1 or more) of the tool table: Fanuc lathe `T0102`, mill and
    /// LinuxCNC `G43 H2`, Sinumerik `D2` (its cutting edge 2).
    Number(u32),
    /// No offset: the coordinates are the spindle's point the machine zero is set for, the
    /// tool table's length left out (LinuxCNC and Fanuc mill `G49`, Fanuc lathe `T0100`,
    /// Sinumerik `D0`). The (A,B) post writes the pivot with its length compensated. A
    /// hand-written `T1 M6` without G43 reads so on LinuxCNC and a Fanuc mill while no G43
    /// is in force (they power on in G49; M6 changes no offset).
    Cancelled,
}

/// A tool change: the tool and the offset applied with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ToolChange {
    pub number: u32,
    pub offset: ToolOffset,
}

impl ToolChange {
    /// Tool `number` with its own offset: coordinates of the tool tip.
    pub fn new(number: u32) -> ToolChange {
        ToolChange { number, offset: ToolOffset::Own }
    }
}

/// One line of the program.
#[derive(Clone, Debug, PartialEq)]
pub enum Block {
    /// From here on F is per minute or per revolution.
    FeedMode(FeedMode),
    /// Spindle start, speed change or stop.
    Spindle(Spindle),
    /// Tool change, with the offset the control applies from it on.
    Tool(ToolChange),
    /// Another length offset for the tool in the spindle, without a tool change: `G43 H2`
    /// or `G49` between moves (Fanuc mill, LinuxCNC), Sinumerik `D2`/`D0`, a Fanuc lathe's
    /// `T0102` for the tool already indexed. `Own` is the current tool's own offset.
    LengthOffset(ToolOffset),
    /// Coolant on (M8) or off (M9).
    Coolant(bool),
    /// Cutter radius compensation for the moves that follow, with the current tool's radius.
    Compensation(Compensation),
    /// Rapid positioning (G0).
    Rapid(Target),
    /// Straight cut at a feed in mm/min (mill) or mm/rev (lathe) (G1).
    Line {
        to: Target,
        feed: Option<f64>,
    },
    /// Circular cut to `to` around the absolute `centre`, written like a position (on a
    /// lathe its X is a diameter too). The working plane is XY on a mill, ZX on a lathe.
    Arc {
        direction: ArcDirection,
        to: Target,
        centre: Target,
        feed: Option<f64>,
    },
    /// Dwell in seconds.
    Dwell(f64),
    Comment(String),
    /// Words as the user wrote them (`Nc.Block "G1", "X", x`), checked against the dialect.
    Words(Vec<Word>),
}

/// A whole program: a name, an optional number (for controls that want `O0001`), and blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    pub name: String,
    /// The program number for controls that store programs by number (Fanuc `O0001`);
    /// `None` writes none, which is also what LinuxCNC reads.
    pub number: Option<u32>,
    pub machine: Machine,
    pub blocks: Vec<Block>,
    /// Digits after the point, when the machine resolves finer than its dialect's default
    /// (a cam at 0.001 mm tolerance on a 0.1 µm machine).
    pub precision: Option<usize>,
    /// The safe position the program ends at: the writers move there in rapid, stop the
    /// spindle and the coolant, and end the program.
    pub retract: Option<Target>,
    /// The blank as (lowest corner, highest corner) of a box on a mill, for controls that
    /// draw it (Heidenhain BLK FORM).
    pub blank: Option<([f64; 3], [f64; 3])>,
    /// How far (mm) the chords may lie from an arc on a control without circular
    /// interpolation (NC31), which writes the arc as lines; `None`: [`DEFAULT_ARC_TOLERANCE`].
    pub arc_tolerance: Option<f64>,
    /// The register cutter compensation takes the radius from, where the control names one
    /// apart from the tool (`G41 D21` on Fanuc/ISO; on LinuxCNC D names a tool-table entry);
    /// `None`: the called tool's own number. One for the whole program.
    pub radius_offset: Option<u32>,
    /// Cycles the program may write once as NC31 subprograms (`Nc.Subprogram`), and
    /// [`calls`](Program::calls), the blocks each use of one stands for. Only
    /// `WordAddress::render_with_subprograms` writes them; every writer writes the blocks.
    pub subprograms: Vec<Subprogram>,
    pub calls: Vec<SubprogramCall>,
}

/// A cycle written once after the program's end as an NC31 subprogram (docs/domain.md §2,
/// "Calls with values"): its header `L16 XR1 WR2 …` and its blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct Subprogram {
    /// `L16`: 16.
    pub number: u32,
    /// The letters a call gives values to, each with the R parameter it sets, in the
    /// header's order (`X` → R1, `W` → R2, …).
    pub parameters: Vec<(char, u32)>,
    /// Its blocks after the header as the control reads them, the last one ending in `M17`.
    pub body: Vec<String>,
}

impl Subprogram {
    /// A subprogram from its header as the control reads it (`L16`, or `L16 XR1 WR2 …`
    /// binding letters to R parameters: docs/domain.md §2) and its blocks, the last one
    /// (and only it) ending in `M17`.
    pub fn new(header: &str, body: Vec<String>) -> Result<Subprogram, String> {
        let (number, parameters) = crate::nc::read::nc31_subprogram(header, &body)?;
        Ok(Subprogram { number, parameters, body })
    }
}

/// One use of a subprogram: the blocks `first..end` of the program are what the subprogram
/// runs when called with `values` (one per parameter, in the header's order).
#[derive(Clone, Debug, PartialEq)]
pub struct SubprogramCall {
    pub number: u32,
    pub values: Vec<f64>,
    pub first: usize,
    /// One past the use's last block; `None` when the macro never closed it (`Nc.EndCycle`).
    pub end: Option<usize>,
}

/// The chord tolerance (mm) arcs are written as lines within where the control has no
/// circular interpolation, unless the program says otherwise: a tenth of the usual 0.1 mm
/// finishing allowance, and ten of NC31's 0.001 mm steps.
pub const DEFAULT_ARC_TOLERANCE: f64 = 0.01;

impl Program {
    pub fn new(name: &str, machine: Machine) -> Program {
        Program {
            name: name.to_string(),
            number: None,
            machine,
            blocks: Vec::new(),
            precision: None,
            retract: None,
            blank: None,
            arc_tolerance: None,
            radius_offset: None,
            subprograms: Vec::new(),
            calls: Vec::new(),
        }
    }

    pub fn push(&mut self, block: Block) -> &mut Program {
        self.blocks.push(block);
        self
    }
}
