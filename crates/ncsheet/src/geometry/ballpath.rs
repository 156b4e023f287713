//! Ball-end mill finishing path over a surface z = f(x, y) (docs/domain.md §3, Král's EqCAM).
//!
//! Zig-zag raster over a rectangle: lines of constant x (or y) at x0 + k·stepover, the last one
//! on x1 (so the last stepover may be shorter), each running the full width with both edges
//! included, alternating direction. Along a line the contact points are a fixed step apart (the
//! last step shortened to end on the edge), or, with a chord tolerance, as far apart as the
//! tool path allows: a segment is halved until the programmed point at its middle is within
//! the tolerance of the chord, so flat parts get few points and curved parts many.
//!
//! At each contact point T = (x, y, f) the ball touches the surface; its centre is
//! C = T + R·n̂ with the *outward* normal n̂ = (−f_x, −f_y, 1)/√(1 + f_x² + f_y²) (the paper
//! prints the inward gradient and wrong partial derivatives: docs/domain.md [fix]). The tip, the
//! lowest point of the ball, is C − (0, 0, R).
//!
//! Gouge check: a ball placed by its contact point may still cut the surface elsewhere (a
//! concave region whose curvature radius is below R, a steep wall nearby), and the straight
//! move between two positions may dip below the surface (a chord across a dome). Every
//! position and every move is checked by the exact drop-cutter of [`super::dropcutter`] to
//! within `gouge_tol` (vertical depth: how far the ball must rise to clear the surface). A
//! gouge is reported, or the ball is lifted to the drop-cutter height and points are inserted
//! (at that height) where a move dips. Only the surface inside the rectangle is the part.
//!
//! This module knows nothing of formulas: it reads the surface through [`Surface`].

use nalgebra::{Point3, Vector3};

use super::dropcutter::{self, Goal, GridAxis, Map, MapError, Sweep};
use super::{ensure, GeometryError};

mod written;
pub use written::{written_reserve, Written};

/// A surface z = f(x, y) with its gradient.
pub trait Surface {
    /// Why the surface has no height or slope at a point (kept as the caller's own type).
    type Error;

    fn height(&mut self, x: f64, y: f64) -> Result<f64, Self::Error>;

    /// Height and gradient at once, so an implementation can share work between them.
    fn sample(&mut self, x: f64, y: f64) -> Result<Sample, Self::Error>;
}

/// The surface at one point: its height and slopes ∂f/∂x, ∂f/∂y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub z: f64,
    pub dzdx: f64,
    pub dzdy: f64,
}

/// Which way the raster lines run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lines {
    /// Lines of constant x, running along y (the paper's).
    #[default]
    ConstantX,
    ConstantY,
}

/// Which way each raster line is cut.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Direction {
    /// Every other line backwards, linked to the next (the default: no empty travel).
    #[default]
    Zigzag,
    /// One way, climb milling on every pass: with the spindle turning M3 (clockwise seen from
    /// above) the uncut side, where the next line lies, is on the right of the feed.
    Climb,
    /// One way, conventional milling on every pass: the uncut side on the left of the feed.
    Conventional,
}

impl Direction {
    /// Whether every line runs the same way (retract and return between lines).
    pub fn is_one_way(self) -> bool {
        self != Direction::Zigzag
    }

    /// Whether line `k` runs towards the end of its range (the first line of a zig-zag does).
    /// The lines step across towards +x (lines of constant x) or +y (constant y); climb puts
    /// that side on the right of the feed: +y along lines of constant x, −x along lines of
    /// constant y.
    pub fn forwards(self, k: usize, lines: Lines) -> bool {
        let climb_forwards = lines == Lines::ConstantX;
        match self {
            Direction::Zigzag => k.is_multiple_of(2),
            Direction::Climb => climb_forwards,
            Direction::Conventional => !climb_forwards,
        }
    }
}

/// How points are spaced along a line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spacing {
    /// Contact points this far apart along the line.
    Step(f64),
    /// Programmed points within `tolerance` of the chords between them, at most `max_step` apart.
    Chord { tolerance: f64, max_step: f64 },
}

/// What to do about a ball position that cuts the surface elsewhere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GougeCheck {
    /// Report each gouge (the caller decides whether that is an error).
    #[default]
    Report,
    /// Raise the ball until it clears the surface, and report how far it went.
    Lift,
    /// Do not check.
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallPathSpec {
    pub radius: f64,
    pub x: [f64; 2],
    pub y: [f64; 2],
    pub stepover: f64,
    pub spacing: Spacing,
    pub lines: Lines,
    /// Zig-zag, or one way (climb or conventional) on every line.
    pub direction: Direction,
    pub gouge: GougeCheck,
    /// Cuts no deeper than this (mm) are not gouges; the check finds every deeper one.
    pub gouge_tol: f64,
    /// Surface samples the gouge check may take in all ([`GOUGE_SAMPLES`] by default):
    /// past them it stops with an error rather than run for hours.
    pub gouge_samples: u64,
    /// Whether the moves linking one raster line to the next are cut (and so checked).
    pub check_links: bool,
    /// Refuse paths longer than this (a sheet holds 1,048,576 rows).
    pub max_points: usize,
}

/// One ball position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// Where the ball touches the surface.
    pub contact: Point3<f64>,
    pub centre: Point3<f64>,
}

impl PathPoint {
    /// The lowest point of the ball.
    pub fn tip(&self, radius: f64) -> Point3<f64> {
        self.centre - Vector3::new(0.0, 0.0, radius)
    }
}

/// A ball position, or a straight move from one, that cuts the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gouge {
    /// Index of the ball position in [`BallPath::points`] (of the move's start).
    pub point: usize,
    pub kind: GougeKind,
    /// The contact point the ball was placed by (the move's start).
    pub contact: Point3<f64>,
    /// The surface point deepest inside the ball (the swept ball).
    pub at: Point3<f64>,
    /// How far the ball must rise (mm) to clear the surface, within half the tolerance.
    pub depth: f64,
}

/// What cuts: the ball where it is placed, or the ball moving straight to the next position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GougeKind {
    Position,
    Move,
}

#[derive(Clone, Debug, PartialEq)]
pub struct BallPath {
    pub radius: f64,
    /// Ball positions in cutting order.
    pub points: Vec<PathPoint>,
    /// Index of the first point of each raster line.
    pub line_starts: Vec<usize>,
    /// Gouges found (with [`GougeCheck::Lift`]: the positions lifted and the moves cleared
    /// by inserting points).
    pub gouges: Vec<Gouge>,
    /// The lowest and highest surface heights seen: the contacts the balls were placed by
    /// (before any lift) and, when checked, the gouge map's nodes over the whole rectangle.
    /// The stock block encloses these, not the lifted contacts.
    pub surface_z: [f64; 2],
}

/// Why there is no path.
#[derive(Clone, Debug, PartialEq)]
pub enum PathError<E> {
    Spec(GeometryError),
    /// The surface has no height or slope at (x, y).
    Surface {
        x: f64,
        y: f64,
        error: E,
    },
    /// The path would pass `BallPathSpec::max_points`: counted before any point is placed
    /// (`at_least` of them), or while the chord tolerance inserts points.
    TooManyPoints {
        at_least: Option<f64>,
        limit: usize,
    },
}

impl<E> PathError<E> {
    /// The message of [`PathError::TooManyPoints`].
    pub fn point_limit_message(at_least: Option<f64>, limit: usize) -> String {
        match at_least {
            Some(n) => format!("the path would have {n} points, more than the {limit} points allowed"),
            None => format!("the path has more than the {limit} points allowed"),
        }
    }
}

impl<E> From<GeometryError> for PathError<E> {
    fn from(e: GeometryError) -> Self {
        PathError::Spec(e)
    }
}

/// The depth (mm) a gouge must exceed to count, unless the spec says otherwise: 1 µm.
pub const GOUGE_TOLERANCE: f64 = 1e-3;

/// The surface samples a gouge check may take unless the spec says otherwise: a formula
/// sample costs about a microsecond, so some tens of seconds at most.
pub const GOUGE_SAMPLES: u64 = 20_000_000;

/// The finest chord tolerance (mm): a nanometre, a thousandth of what a control resolves.
pub const MIN_CHORD_TOLERANCE: f64 = 1e-6;

/// Halving a chord stops at this depth (max_step / 2^20).
const MAX_HALVINGS: u32 = 20;

/// The ball path of `spec` over `surface`. `progress(done, total)` is called after each line.
pub fn ball_path<S: Surface>(
    surface: &mut S,
    spec: &BallPathSpec,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<BallPath, PathError<S::Error>> {
    Ok(build(surface, spec, None, progress)?.0)
}

/// The ball path of `spec` over `surface`, and the same path as a program writes it
/// ([`Written`]): its programmed points on the dialect's grid, each position and each written
/// move kept within `spec.gouge_tol` of the drop-cutter height by lifting points or inserting
/// them (issue 32, scope 5). With [`GougeCheck::Off`] only the reserve of
/// [`written_reserve`] is kept; with [`GougeCheck::Report`] and gouges found the written path
/// is the computed one, rounded (the path is refused anyway).
pub fn ball_path_as_written<S: Surface>(
    surface: &mut S,
    spec: &BallPathSpec,
    written: Written,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(BallPath, BallPath), PathError<S::Error>> {
    let (path, as_written) = build(surface, spec, Some(written), progress)?;
    Ok((path, as_written.expect("a written path was asked for")))
}

fn build<S: Surface>(
    surface: &mut S,
    spec: &BallPathSpec,
    written: Option<Written>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(BallPath, Option<BallPath>), PathError<S::Error>> {
    check_spec(spec)?;
    check_point_count(spec)?;
    let (across, along) = match spec.lines {
        Lines::ConstantX => (spec.x, spec.y),
        Lines::ConstantY => (spec.y, spec.x),
    };
    let along_stations = stations(along, spacing_step(spec.spacing));
    let stations = stations(across, spec.stepover);
    let n_lines = stations.len();
    // Progress counts lines placed, then lines checked for gouges.
    let total = n_lines * if spec.gouge == GougeCheck::Off { 1 } else { 2 };
    let mut path = BallPath {
        radius: spec.radius,
        points: Vec::new(),
        line_starts: Vec::new(),
        gouges: Vec::new(),
        surface_z: [f64::INFINITY, f64::NEG_INFINITY],
    };
    if let Spacing::Step(step) = spec.spacing {
        let per_line = ((along[1] - along[0]) / step).ceil() + 1.0;
        path.points.reserve((per_line * stations.len() as f64).min(spec.max_points as f64) as usize);
    }
    // The gouge check samples the surface again on its map and in its searches: where that
    // is a station the path was placed by, it reads the sample kept here.
    let kept = (spec.gouge != GougeCheck::Off).then(|| Kept::new(spec, &stations, &along_stations));
    let mut placer = Placer { surface, radius: spec.radius, lines: spec.lines, kept };
    for (k, &u) in stations.iter().enumerate() {
        path.line_starts.push(path.points.len());
        let start = path.points.len();
        placer.line(k, u, along, spec.spacing, &mut path.points, spec.max_points)?;
        // Zig-zag: odd lines run backwards; one way: every line the same way.
        if !spec.direction.forwards(k, spec.lines) {
            path.points[start..].reverse();
        }
        progress(k + 1, total);
    }
    path.surface_z = height_range(path.points.iter().map(|p| p.contact.z));
    if spec.gouge == GougeCheck::Off {
        let as_written = written.map(|w| written::rounded(&path, w));
        return Ok((path, as_written));
    }
    let mut kept = placer.kept.take().expect("kept for the check");
    let nodes = kept.take_nodes(spec);
    let mut known = Known { surface: placer.surface, lines: spec.lines, across: stations, along: along_stations, kept };
    let (mut check, spent) = check_gouges(&mut known, spec, nodes, &mut path, &mut |k| progress(n_lines + k, total))?;
    let as_written = match written {
        Some(w) if spec.gouge == GougeCheck::Lift || path.gouges.is_empty() => Some(check.as_written(&path, w, spent)?),
        Some(w) => Some(written::rounded(&path, w)),
        None => None,
    };
    Ok((path, as_written))
}

/// The largest coordinate or length of a ball path, in mm: a kilometre, past any machine.
pub const MAX_LENGTH: f64 = 1.0e6;

/// The lowest and highest of `heights` (∞, −∞ for none).
fn height_range(heights: impl Iterator<Item = f64>) -> [f64; 2] {
    heights.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], z| [lo.min(z), hi.max(z)])
}

fn check_spec(spec: &BallPathSpec) -> Result<(), GeometryError> {
    let finite = [spec.radius, spec.x[0], spec.x[1], spec.y[0], spec.y[1], spec.stepover].iter().all(|v| v.is_finite());
    ensure(finite, || "every number of a ball path must be finite".into())?;
    // Past any machine's travel the search for gouges splits squares of a sweep longer than
    // f64 can resolve against the ball: it would not end.
    let lengths = [spec.radius, spec.x[0], spec.x[1], spec.y[0], spec.y[1], spec.stepover];
    let steps = match spec.spacing {
        Spacing::Step(s) => [s, 0.0],
        Spacing::Chord { tolerance, max_step } => [tolerance, max_step],
    };
    ensure(lengths.iter().chain(&steps).all(|v| v.abs() <= MAX_LENGTH), || {
        format!("a ball path's lengths are millimetres within ±{MAX_LENGTH} (a kilometre)")
    })?;
    ensure(spec.radius > 0.0, || format!("ball radius R must be > 0, not {}", spec.radius))?;
    ensure(spec.x[0] <= spec.x[1], || format!("x0 ({}) must not be beyond x1 ({})", spec.x[0], spec.x[1]))?;
    ensure(spec.y[0] <= spec.y[1], || format!("y0 ({}) must not be beyond y1 ({})", spec.y[0], spec.y[1]))?;
    ensure(spec.stepover > 0.0, || format!("stepover must be > 0, not {}", spec.stepover))?;
    ensure(spec.gouge_tol > 0.0 && spec.gouge_tol.is_finite(), || {
        format!("the gouge tolerance must be > 0, not {}", spec.gouge_tol)
    })?;
    match spec.spacing {
        Spacing::Step(s) => ensure(s > 0.0 && s.is_finite(), || format!("step must be > 0, not {s}"))?,
        Spacing::Chord { tolerance, max_step } => {
            ensure(tolerance > 0.0 && tolerance.is_finite(), || {
                format!("chord tolerance must be > 0, not {tolerance}")
            })?;
            // Finer than any machine moves, and each tenfold finer asks for ~3 times the
            // points: a nanometre would take hours to reach the point limit.
            ensure(tolerance >= MIN_CHORD_TOLERANCE, || {
                format!("chord tolerance must be at least {MIN_CHORD_TOLERANCE} mm (a nanometre), not {tolerance}")
            })?;
            ensure(max_step > 0.0 && max_step.is_finite(), || format!("step must be > 0, not {max_step}"))?;
        }
    }
    Ok(())
}

/// The fewest points the path of `spec` can have (each one a surface sample), from its
/// rectangle, stepover and step alone.
pub fn fewest_points(spec: &BallPathSpec) -> f64 {
    let across = match spec.lines {
        Lines::ConstantX => spec.x,
        Lines::ConstantY => spec.y,
    };
    let along = match spec.lines {
        Lines::ConstantX => spec.y,
        Lines::ConstantY => spec.x,
    };
    let n_lines = ((across[1] - across[0]) / spec.stepover).ceil() + 1.0;
    let step = spacing_step(spec.spacing);
    let per_line = ((along[1] - along[0]) / step).ceil() + 1.0;
    n_lines * per_line
}

/// The fewest points the path can have, counted before any is placed: a step of 1e-9 must
/// not ask for the memory of 1e10 stations.
fn check_point_count<E>(spec: &BallPathSpec) -> Result<(), PathError<E>> {
    let least = fewest_points(spec);
    if least > spec.max_points as f64 {
        return Err(PathError::TooManyPoints { at_least: Some(least), limit: spec.max_points });
    }
    Ok(())
}

/// `a, a + s, a + 2s, …` up to `b`, with `b` itself last (both edges included). A count within
/// rounding of a whole number of steps does not add a sliver step.
fn stations(range: [f64; 2], step: f64) -> Vec<f64> {
    let [a, b] = range;
    let n = ((b - a) / step - 1e-9).ceil().max(0.0) as usize;
    let mut out: Vec<f64> = (0..n).map(|k| a + k as f64 * step).collect();
    out.push(b);
    out
}

/// The longest step along a line: the fixed step, or the chord tolerance's largest.
fn spacing_step(spacing: Spacing) -> f64 {
    match spacing {
        Spacing::Step(s) | Spacing::Chord { max_step: s, .. } => s,
    }
}

/// The surface, with the samples the path was placed by at the raster's stations where the
/// gouge map reads it ([`Kept`]). A sample asked for at exactly such a station's coordinates
/// is that one (the same formula at the same point), so the gouge check's map and searches
/// evaluate the surface only where nothing was placed.
struct Known<'s, S> {
    surface: &'s mut S,
    lines: Lines,
    across: Vec<f64>,
    along: Vec<f64>,
    kept: Kept,
}

impl<S> Known<'_, S> {
    fn kept(&self, x: f64, y: f64) -> Option<Sample> {
        let (u, v) = match self.lines {
            Lines::ConstantX => (x, y),
            Lines::ConstantY => (y, x),
        };
        // Exactly the station's bits (total_cmp tells −0 from +0).
        let k = self.across.binary_search_by(|s| s.total_cmp(&u)).ok()?;
        let j = self.along.binary_search_by(|s| s.total_cmp(&v)).ok()?;
        self.kept.get(k, j)
    }
}

impl<S: Surface> Surface for Known<'_, S> {
    type Error = S::Error;

    fn height(&mut self, x: f64, y: f64) -> Result<f64, S::Error> {
        match self.kept(x, y) {
            Some(s) => Ok(s.z),
            None => self.surface.height(x, y),
        }
    }

    fn sample(&mut self, x: f64, y: f64) -> Result<Sample, S::Error> {
        match self.kept(x, y) {
            Some(s) => Ok(s),
            None => self.surface.sample(x, y),
        }
    }
}

/// The samples kept at the stations (across k, along j) where the gouge map first reads the
/// surface: where both coordinates are its nodes', or both its cells' middles (a map of
/// twice the path's spacing reads half the stations). A block for each kind, row-major by y
/// like the map's nodes: the block of nodes becomes the map's when it holds every node.
struct Kept {
    lines: Lines,
    /// Per station across and along the lines, its place among the node coordinates and
    /// among the middle ones of that axis (`None`: not one).
    across: Vec<[Option<usize>; 2]>,
    along: Vec<[Option<usize>; 2]>,
    /// How many node and middle coordinates lie on each axis, x and y.
    counts: [[usize; 2]; 2],
    samples: [Vec<Sample>; 2],
}

impl Kept {
    fn new(spec: &BallPathSpec, across: &[f64], along: &[f64]) -> Kept {
        let [x, y] = Map::grid(spec.x, spec.y, map_spacing(spec));
        let (across_axis, along_axis) = match spec.lines {
            Lines::ConstantX => (x, y),
            Lines::ConstantY => (y, x),
        };
        let (across, across_count) = Kept::places(across, across_axis);
        let (along, along_count) = Kept::places(along, along_axis);
        let counts = match spec.lines {
            Lines::ConstantX => [across_count, along_count],
            Lines::ConstantY => [along_count, across_count],
        };
        // Every station is placed before the check reads any: each slot is written.
        let unset = Sample { z: f64::NAN, dzdx: f64::NAN, dzdy: f64::NAN };
        let samples = [0, 1].map(|kind| vec![unset; counts[0][kind] * counts[1][kind]]);
        Kept { lines: spec.lines, across, along, counts, samples }
    }

    /// Each station's place among the node and among the middle coordinates of `axis`, and
    /// how many of each there are.
    fn places(stations: &[f64], axis: GridAxis) -> (Vec<[Option<usize>; 2]>, [usize; 2]) {
        let mut count = [0usize; 2];
        let places = stations
            .iter()
            .map(|&v| {
                let mut place = |kind: usize, read: bool| {
                    read.then(|| {
                        count[kind] += 1;
                        count[kind] - 1
                    })
                };
                [place(0, axis.is_node(v)), place(1, axis.is_middle(v))]
            })
            .collect();
        (places, count)
    }

    /// Which block the sample at station (k, j) is kept in, and where.
    fn slot(&self, k: usize, j: usize) -> Option<(usize, usize)> {
        let (across, along) = (self.across.get(k)?, self.along.get(j)?);
        let (x, y) = match self.lines {
            Lines::ConstantX => (across, along),
            Lines::ConstantY => (along, across),
        };
        (0..2).find_map(|kind| Some((kind, y[kind]? * self.counts[0][kind] + x[kind]?)))
    }

    /// Keeps the sample at station (k, j) if the map reads it.
    fn keep(&mut self, k: usize, j: usize, s: Sample) {
        if let Some((kind, at)) = self.slot(k, j) {
            self.samples[kind][at] = s;
        }
    }

    fn get(&self, k: usize, j: usize) -> Option<Sample> {
        let (kind, at) = self.slot(k, j)?;
        self.samples[kind].get(at).copied()
    }

    /// The samples at every node of the map's first grid, row-major by y, where every node is
    /// a station (else none): the map takes them, and they are kept here no longer.
    fn take_nodes(&mut self, spec: &BallPathSpec) -> Vec<Sample> {
        let [x, y] = Map::grid(spec.x, spec.y, map_spacing(spec));
        if [self.counts[0][0], self.counts[1][0]] != [x.nodes(), y.nodes()] {
            return Vec::new();
        }
        std::mem::take(&mut self.samples[0])
    }
}

/// Places balls by their contact points.
struct Placer<'s, S> {
    surface: &'s mut S,
    radius: f64,
    lines: Lines,
    /// The samples taken at the raster's stations, kept for the gouge check (`None`: not kept).
    kept: Option<Kept>,
}

impl<S: Surface> Placer<'_, S> {
    /// The ball touching the surface at line coordinate `u`, position `v` along the line.
    fn place(&mut self, u: f64, v: f64) -> Result<PathPoint, PathError<S::Error>> {
        Ok(self.place_sampled(u, v)?.0)
    }

    /// The ball at station (k, j) of the raster, its sample kept if asked for.
    fn place_station(&mut self, (k, j): (usize, usize), u: f64, v: f64) -> Result<PathPoint, PathError<S::Error>> {
        let (p, s) = self.place_sampled(u, v)?;
        if let Some(kept) = &mut self.kept {
            kept.keep(k, j, s);
        }
        Ok(p)
    }

    fn place_sampled(&mut self, u: f64, v: f64) -> Result<(PathPoint, Sample), PathError<S::Error>> {
        let (x, y) = match self.lines {
            Lines::ConstantX => (u, v),
            Lines::ConstantY => (v, u),
        };
        let s = self.surface.sample(x, y).map_err(|error| PathError::Surface { x, y, error })?;
        Ok((ball_at(Point3::new(x, y, s.z), s.dzdx, s.dzdy, self.radius), s))
    }

    /// Places line `k`, at line coordinate `u`.
    fn line(
        &mut self,
        k: usize,
        u: f64,
        along: [f64; 2],
        spacing: Spacing,
        out: &mut Vec<PathPoint>,
        max_points: usize,
    ) -> Result<(), PathError<S::Error>> {
        let too_many = || PathError::TooManyPoints { at_least: None, limit: max_points };
        match spacing {
            Spacing::Step(step) => {
                let vs = stations(along, step);
                if out.len() + vs.len() > max_points {
                    return Err(too_many());
                }
                out.reserve(vs.len());
                for (j, v) in vs.into_iter().enumerate() {
                    out.push(self.place_station((k, j), u, v)?);
                }
            }
            Spacing::Chord { tolerance, max_step } => {
                let vs = stations(along, max_step);
                let mut prev = (vs[0], self.place_station((k, 0), u, vs[0])?);
                out.push(prev.1);
                for (j, &v) in vs.iter().enumerate().skip(1) {
                    let next = (v, self.place_station((k, j), u, v)?);
                    self.refine(u, prev, next, tolerance, MAX_HALVINGS, out)?;
                    out.push(next.1);
                    if out.len() > max_points {
                        return Err(too_many());
                    }
                    prev = next;
                }
            }
        }
        Ok(())
    }

    /// Pushes the points strictly between `a` and `b` that keep every chord within `tolerance`.
    fn refine(
        &mut self,
        u: f64,
        a: (f64, PathPoint),
        b: (f64, PathPoint),
        tolerance: f64,
        halvings_left: u32,
        out: &mut Vec<PathPoint>,
    ) -> Result<(), PathError<S::Error>> {
        if halvings_left == 0 {
            return Ok(());
        }
        let vm = 0.5 * (a.0 + b.0);
        let m = (vm, self.place(u, vm)?);
        if distance_to_segment(&m.1.centre, &a.1.centre, &b.1.centre) <= tolerance {
            return Ok(());
        }
        self.refine(u, a, m, tolerance, halvings_left - 1, out)?;
        out.push(m.1);
        self.refine(u, m, b, tolerance, halvings_left - 1, out)
    }
}

/// The ball of radius `r` touching the surface at `contact`, where the slopes are `fx`, `fy`.
pub fn ball_at(contact: Point3<f64>, fx: f64, fy: f64, r: f64) -> PathPoint {
    let n = Vector3::new(-fx, -fy, 1.0);
    let centre = contact + n * (r / n.norm());
    PathPoint { contact, centre }
}

fn distance_to_segment(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + ab * t)).norm()
}

// ---- gouge check ---------------------------------------------------------------------------

/// The checker after the computed path's check, and its buffer of bounds, spent.
type Checked<'a, S> = (Checker<'a, S>, Vec<f64>);

/// Checks every ball position and every straight move between consecutive ones (the links
/// between lines too, unless `check_links` is off) with the exact drop-cutter of
/// [`dropcutter`]; reports or lifts what cuts deeper than `spec.gouge_tol`. Returns the
/// checker and its buffer of bounds, spent (the written path's check reuses it). `nodes`:
/// the samples at the map's nodes where the path was placed by them ([`Map::sample`]).
fn check_gouges<'a, S: Surface>(
    surface: &'a mut S,
    spec: &'a BallPathSpec,
    nodes: Vec<Sample>,
    path: &mut BallPath,
    lines_checked: &mut dyn FnMut(usize),
) -> Result<Checked<'a, S>, PathError<S::Error>> {
    // The map is made finer where the surface between its nodes is more than a quarter of the
    // tolerance from what they show (a feature narrower than the path's spacing, a step).
    let map =
        Map::sample(surface, spec.x, spec.y, map_spacing(spec), 0.25 * spec.gouge_tol, nodes).map_err(map_error)?;
    let [lo, hi] = map.heights();
    path.surface_z = [path.surface_z[0].min(lo), path.surface_z[1].max(hi)];
    let mut check =
        Checker { surface, map, spec, gouges: Vec::new(), samples_left: spec.gouge_samples, placed: Vec::new() };
    let below = check.positions(path, lines_checked)?;
    check.moves(path, &below)?;
    path.gouges = std::mem::take(&mut check.gouges);
    Ok((check, below))
}

/// The gouge map's spacing: it resolves the surface at least as finely as the path does.
fn map_spacing(spec: &BallPathSpec) -> f64 {
    (spec.radius / 4.0).min(spec.stepover.max(spacing_step(spec.spacing)))
}

fn surface_error<E>((x, y, error): (f64, f64, E)) -> PathError<E> {
    PathError::Surface { x, y, error }
}

/// A surface the map cannot resolve is refused by name: the check would not be exact there.
fn map_error<E>(e: MapError<E>) -> PathError<E> {
    match e {
        MapError::Surface(x, y, error) => PathError::Surface { x, y, error },
        MapError::Unresolved { x, y, spacing, mismatch } => PathError::Spec(GeometryError::OutOfRange(format!(
            "the surface near ({x:.4}, {y:.4}) jumps or bends more sharply than the gouge check resolves at its \
             finest spacing {spacing:.3e} mm (its middle is {mismatch:.4} mm off what its neighbours allow): a step \
             (IF, ROUND, INT …) or a feature narrower than that cannot be checked exactly; write a step as a \
             continuous wall, check a smaller area, or give --gouge off"
        ))),
    }
}

/// What the check says of a ball or a move.
enum Verdict {
    /// Proved no deeper than this (mm) below the drop-cutter height (≤ the tolerance).
    Clear(f64),
    /// Cuts deeper than the tolerance; the depth found is within half the tolerance of the
    /// true one, below it.
    Gouge(dropcutter::Cut),
}

/// How many times a move is halved, at most, to clear it by inserting points.
const MAX_MOVE_HALVINGS: u32 = 16;

struct Checker<'a, S> {
    surface: &'a mut S,
    map: Map,
    spec: &'a BallPathSpec,
    gouges: Vec<Gouge>,
    /// Surface samples the searches may still take.
    samples_left: u64,
    /// Per point of the checked path: still the ball placed by its contact point (tangent to
    /// the surface there), neither lifted nor inserted; the written path's proofs start there.
    placed: Vec<bool>,
}

impl<S: Surface> Checker<'_, S> {
    /// The search's own tolerance: half the stated one, so that a gouge's reported depth is
    /// within it of the true depth and a lifted ball ends within it of the drop-cutter height.
    fn search_tol(&self) -> f64 {
        0.5 * self.spec.gouge_tol
    }

    fn deepest(
        &mut self,
        ball: &Sweep,
        seeds: &[Point3<f64>],
        goal: Goal,
    ) -> Result<dropcutter::Cut, PathError<S::Error>> {
        let cut = self.map.deepest(self.surface, ball, seeds, goal, &mut self.samples_left).map_err(surface_error)?;
        if !cut.complete {
            let c = ball.a;
            return Err(PathError::Spec(GeometryError::OutOfRange(format!(
                "the gouge check took its {} surface samples and stopped at the ball centred at ({:.4}, {:.4}, \
                 {:.4}): the surface bends too often under a ball this large for an exact check in that time; \
                 give a smaller area, a larger --gouge-tol, --gouge-samples to allow more, or --gouge off",
                self.spec.gouge_samples, c.x, c.y, c.z
            ))));
        }
        Ok(cut)
    }

    /// Whether `ball` cuts deeper than the tolerance (`--gouge-tol` means what it says: a cut
    /// deeper is a gouge, one no deeper is not). A search to half the tolerance decides
    /// unless its best sample lies within half the tolerance below it; then a second search
    /// refines until a sample cuts deeper or no square can.
    fn judge(&mut self, ball: &Sweep, seeds: &[Point3<f64>]) -> Result<Verdict, PathError<S::Error>> {
        let (tol, half) = (self.spec.gouge_tol, self.search_tol());
        let cut = self.deepest(ball, seeds, Goal::Within(half))?;
        if cut.depth > tol {
            return Ok(Verdict::Gouge(cut));
        }
        if cut.depth + half <= tol {
            return Ok(Verdict::Clear((cut.depth + half).max(0.0)));
        }
        let mut more = seeds.to_vec();
        more.push(cut.at);
        let decided = self.deepest(ball, &more, Goal::Deeper(tol))?;
        // The true depth is at most cut.depth + half < tol + half, so a sample past tol is
        // within half the tolerance of it.
        Ok(if decided.depth > tol { Verdict::Gouge(decided) } else { Verdict::Clear(tol) })
    }

    /// Checks (and with Lift, lifts) each position; returns for each a bound on how far it is
    /// below the drop-cutter height (0 where proved clear).
    fn positions(
        &mut self,
        path: &mut BallPath,
        lines_checked: &mut dyn FnMut(usize),
    ) -> Result<Vec<f64>, PathError<S::Error>> {
        let mut below = Vec::with_capacity(path.points.len());
        for k in 0..path.line_starts.len() {
            let end = path.line_starts.get(k + 1).copied().unwrap_or(path.points.len());
            for i in path.line_starts[k]..end {
                let (depth, lifted) = self.position(i, path.points[i])?;
                below.push(depth);
                self.placed.push(lifted.is_none());
                if let Some(p) = lifted {
                    path.points[i] = p;
                }
            }
            lines_checked(k + 1);
        }
        Ok(below)
    }

    /// One position: a bound on how far it is below the drop-cutter height, and with Lift
    /// the position lifted to it where it cuts.
    fn position(&mut self, i: usize, p: PathPoint) -> Result<(f64, Option<PathPoint>), PathError<S::Error>> {
        let (r, half) = (self.spec.radius, self.search_tol());
        let ball = Sweep::at_rest(p.centre, r);
        if self.map.proves_clear(&ball) {
            return Ok((0.0, None));
        }
        let cut = match self.judge(&ball, &[p.contact])? {
            Verdict::Clear(below) => return Ok((below, None)),
            Verdict::Gouge(cut) => cut,
        };
        self.gouges.push(Gouge {
            point: i,
            kind: GougeKind::Position,
            contact: p.contact,
            at: cut.at,
            depth: cut.depth,
        });
        if self.spec.gouge != GougeCheck::Lift {
            return Ok((cut.depth + half, None));
        }
        let lifted = PathPoint { contact: cut.at, centre: p.centre + Vector3::new(0.0, 0.0, cut.depth) };
        Ok((half, Some(lifted)))
    }

    /// Checks each straight move between consecutive positions; with Lift, inserts points at
    /// the drop-cutter height until every move clears, and renumbers the path (in its own
    /// buffer: the inserted points wait aside until the end).
    fn moves(&mut self, path: &mut BallPath, below: &[f64]) -> Result<(), PathError<S::Error>> {
        let n = path.points.len();
        let mut inserted = Inserted::default();
        for k in 0..path.line_starts.len() {
            let end = path.line_starts.get(k + 1).copied().unwrap_or(n);
            for i in path.line_starts[k]..end {
                if i + 1 == n || (i + 1 == end && !self.spec.check_links) {
                    continue;
                }
                let (a, b) = (path.points[i], path.points[i + 1]);
                self.one_move(i, a, b, [below[i], below[i + 1]], MAX_MOVE_HALVINGS, &mut inserted)?;
            }
        }
        // Positions were numbered in the old path; moves already in the new one.
        for g in self.gouges.iter_mut().filter(|g| g.kind == GougeKind::Position) {
            g.point += inserted.before(g.point);
        }
        // Points inserted in moves were dropped, not placed by a contact.
        inserted.spread(&mut self.placed, |_| false);
        inserted.into_path(path);
        Ok(())
    }

    /// The move from `a` to `b`, part of the move from the path's point `i` to the next,
    /// whose ends are at most `ends` below the drop-cutter height; the points it needs are
    /// inserted after `i` (after those already inserted there).
    fn one_move(
        &mut self,
        i: usize,
        a: PathPoint,
        b: PathPoint,
        ends: [f64; 2],
        halvings_left: u32,
        inserted: &mut Inserted,
    ) -> Result<(), PathError<S::Error>> {
        let (r, tol, half) = (self.spec.radius, self.spec.gouge_tol, self.search_tol());
        let sweep = Sweep { a: a.centre, b: b.centre, r };
        if self.map.move_bound(&sweep, ends).is_some_and(|bound| bound <= tol) {
            return Ok(());
        }
        let cut = match self.judge(&sweep, &[a.contact, b.contact])? {
            Verdict::Clear(_) => return Ok(()),
            Verdict::Gouge(cut) => cut,
        };
        let top = halvings_left == MAX_MOVE_HALVINGS;
        if top {
            // `a` is the path's point `i`, after every point inserted before it.
            let point = i + inserted.len();
            self.gouges.push(Gouge { point, kind: GougeKind::Move, contact: a.contact, at: cut.at, depth: cut.depth });
        }
        if self.spec.gouge != GougeCheck::Lift {
            return Ok(());
        }
        if halvings_left == 0 {
            return Err(PathError::Spec(GeometryError::OutOfRange(format!(
                "the move from ({:.4}, {:.4}) to ({:.4}, {:.4}) still cuts {:.4} mm into the surface after \
                 {MAX_MOVE_HALVINGS} halvings",
                a.contact.x, a.contact.y, b.contact.x, b.contact.y, cut.depth
            ))));
        }
        // The ball halfway, dropped onto the surface.
        let mid = Point3::from((a.centre.coords + b.centre.coords) * 0.5);
        let drop = self.deepest(&Sweep::at_rest(mid, r), &[cut.at, a.contact, b.contact], Goal::Within(half))?;
        let m = PathPoint { contact: drop.at, centre: mid + Vector3::new(0.0, 0.0, drop.depth) };
        self.one_move(i, a, m, [ends[0], half], halvings_left - 1, inserted)?;
        inserted.push(i, m);
        self.one_move(i, m, b, [half, ends[1]], halvings_left - 1, inserted)
    }
}

/// Points inserted into a path while it is checked in order, kept aside until the end: then
/// the path's points move up in their own buffer to make room (one pass from the back), so
/// that a check that inserts a few points does not copy the path (48 bytes a point) into a
/// new one.
#[derive(Default)]
struct Inserted {
    /// For each inserted point, the index in the path of the point it follows (in order).
    after: Vec<usize>,
    points: Vec<PathPoint>,
}

impl Inserted {
    fn len(&self) -> usize {
        self.points.len()
    }

    /// Inserts `p` after the path's point `i`, after those already inserted there (`i` is
    /// never below an earlier one's).
    fn push(&mut self, i: usize, p: PathPoint) {
        debug_assert!(self.after.last().is_none_or(|&a| a <= i));
        self.after.push(i);
        self.points.push(p);
    }

    /// The last point inserted, where it follows the path's point `i`.
    fn last_after(&mut self, i: usize) -> Option<&mut PathPoint> {
        (self.after.last() == Some(&i)).then(|| self.points.last_mut()).flatten()
    }

    /// How many points are inserted before the path's point `i`: it moves up by as many.
    fn before(&self, i: usize) -> usize {
        self.after.partition_point(|&a| a < i)
    }

    /// `v`, one entry per point of the path, with `item(k)` in the place of inserted point k.
    fn spread<T: Copy>(&self, v: &mut Vec<T>, item: impl Fn(usize) -> T) {
        let Some(&fill) = v.first() else { return };
        let n = v.len();
        v.resize(n + self.len(), fill);
        // From the back: the entries after the k-th inserted point's move up by k + 1.
        let mut end = n;
        for (k, &a) in self.after.iter().enumerate().rev() {
            v.copy_within(a + 1..end, a + k + 2);
            v[a + k + 1] = item(k);
            end = a + 1;
        }
    }

    /// The path with the inserted points in their places and its lines renumbered.
    fn into_path(self, path: &mut BallPath) {
        for start in &mut path.line_starts {
            *start += self.before(*start);
        }
        self.spread(&mut path.points, |k| self.points[k]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// z = a·x + b·y + c, by hand.
    struct Plane(f64, f64, f64);

    impl Surface for Plane {
        type Error = ();

        fn height(&mut self, x: f64, y: f64) -> Result<f64, ()> {
            Ok(self.0 * x + self.1 * y + self.2)
        }

        fn sample(&mut self, x: f64, y: f64) -> Result<Sample, ()> {
            Ok(Sample { z: self.height(x, y)?, dzdx: self.0, dzdy: self.1 })
        }
    }

    fn spec() -> BallPathSpec {
        BallPathSpec {
            radius: 2.0,
            x: [0.0, 1.0],
            y: [0.0, 1.0],
            stepover: 0.4,
            spacing: Spacing::Step(0.5),
            lines: Lines::ConstantX,
            gouge: GougeCheck::Report,
            gouge_tol: GOUGE_TOLERANCE,
            gouge_samples: GOUGE_SAMPLES,
            check_links: true,
            direction: Direction::Zigzag,
            max_points: 1000,
        }
    }

    #[test]
    fn stations_include_both_edges() {
        assert_eq!(stations([0.0, 1.0], 0.4), vec![0.0, 0.4, 0.8, 1.0]);
        assert_eq!(stations([0.0, 1.0], 0.5), vec![0.0, 0.5, 1.0]);
        assert_eq!(stations([0.0, 0.3], 0.1).len(), 4);
        assert_eq!(stations([2.0, 2.0], 0.5), vec![2.0]);
    }

    #[test]
    fn zig_zag_over_a_flat_plane() {
        let path = ball_path(&mut Plane(0.0, 0.0, 1.0), &spec(), &mut |_, _| {}).unwrap();
        let xy: Vec<(f64, f64)> = path.points.iter().map(|p| (p.contact.x, p.contact.y)).collect();
        #[rustfmt::skip]
        let expected = [
            (0.0, 0.0), (0.0, 0.5), (0.0, 1.0),
            (0.4, 1.0), (0.4, 0.5), (0.4, 0.0),
            (0.8, 0.0), (0.8, 0.5), (0.8, 1.0),
            (1.0, 1.0), (1.0, 0.5), (1.0, 0.0),
        ];
        assert_eq!(xy, expected);
        assert_eq!(path.line_starts, vec![0, 3, 6, 9]);
        assert!(path.points.iter().all(|p| p.centre.z == 3.0 && p.tip(2.0).z == 1.0));
        assert!(path.gouges.is_empty());
    }

    #[test]
    fn the_centre_sits_on_the_outward_normal() {
        // z = x: the normal is (−1, 0, 1)/√2.
        let p = ball_at(Point3::new(1.0, 0.0, 1.0), 1.0, 0.0, 2.0);
        let s = std::f64::consts::SQRT_2;
        assert!((p.centre - Point3::new(1.0 - s, 0.0, 1.0 + s)).norm() < 1e-15);
    }

    #[test]
    fn paths_past_the_point_limit_are_a_typed_error() {
        // 4 lines of 3 stations: 12 points, counted before any is placed.
        let few = BallPathSpec { max_points: 11, ..spec() };
        let err = ball_path(&mut Plane(0.0, 0.0, 0.0), &few, &mut |_, _| {}).unwrap_err();
        assert_eq!(err, PathError::TooManyPoints { at_least: Some(12.0), limit: 11 });
        // A chord tolerance inserts points on a sphere-like bump while the lines are placed.
        let chords =
            BallPathSpec { spacing: Spacing::Chord { tolerance: 1e-6, max_step: 0.5 }, max_points: 12, ..spec() };
        let err = ball_path(&mut Bowl, &chords, &mut |_, _| {}).unwrap_err();
        assert_eq!(err, PathError::TooManyPoints { at_least: None, limit: 12 });
    }

    /// z = x² + y²: curved, so chords need points between the stations.
    struct Bowl;

    impl Surface for Bowl {
        type Error = ();

        fn height(&mut self, x: f64, y: f64) -> Result<f64, ()> {
            Ok(x * x + y * y)
        }

        fn sample(&mut self, x: f64, y: f64) -> Result<Sample, ()> {
            Ok(Sample { z: x * x + y * y, dzdx: 2.0 * x, dzdy: 2.0 * y })
        }
    }

    /// The plane z = 0.1x + 0.2y, counting what is asked of it.
    #[derive(Default)]
    struct Counted {
        samples: usize,
        heights: usize,
    }

    impl Surface for Counted {
        type Error = ();

        fn height(&mut self, x: f64, y: f64) -> Result<f64, ()> {
            self.heights += 1;
            Ok(0.1 * x + 0.2 * y)
        }

        fn sample(&mut self, x: f64, y: f64) -> Result<Sample, ()> {
            self.samples += 1;
            Ok(Sample { z: 0.1 * x + 0.2 * y, dzdx: 0.1, dzdy: 0.2 })
        }
    }

    #[test]
    fn the_gouge_check_evaluates_the_surface_only_where_nothing_was_placed() {
        // Step and stepover 0.5 under a 3 mm ball: the map's spacing is the step (R/4 is
        // larger), so its 5 × 5 nodes are the path's stations, and its 4 × 4 cell middles,
        // which need only a height, are not. A plane needs no search.
        let plane = BallPathSpec { radius: 3.0, x: [0.0, 2.0], y: [0.0, 2.0], stepover: 0.5, ..spec() };
        let mut surface = Counted::default();
        let path = ball_path(&mut surface, &plane, &mut |_, _| {}).unwrap();
        assert_eq!(path.points.len(), 25);
        assert!(path.gouges.is_empty());
        assert_eq!((surface.samples, surface.heights), (25, 16));
    }

    /// A path of 12 points on the line x = 0 (point i at y = i) with 5 points inserted in its
    /// own buffer: two after point 0, one after point 4, two after point 11 (the last).
    #[test]
    fn inserted_points_take_their_places_in_the_paths_own_buffer() {
        let at = |y: f64| PathPoint { contact: Point3::new(0.0, y, 0.0), centre: Point3::new(0.0, y, 1.0) };
        let mut path = BallPath {
            radius: 1.0,
            points: (0..12).map(|i| at(i as f64)).collect(),
            line_starts: vec![0, 4, 8],
            gouges: Vec::new(),
            surface_z: [0.0, 0.0],
        };
        let mut inserted = Inserted::default();
        for (after, y) in [(0, 0.25), (0, 0.5), (4, 4.5), (11, 11.5), (11, 12.0)] {
            inserted.push(after, at(y));
        }
        assert_eq!((inserted.before(0), inserted.before(1), inserted.before(5), inserted.before(11)), (0, 2, 3, 3));
        let mut placed = vec![true; 12];
        inserted.spread(&mut placed, |_| false);
        inserted.into_path(&mut path);
        let ys: Vec<f64> = path.points.iter().map(|p| p.contact.y).collect();
        #[rustfmt::skip]
        let expected = [0.0, 0.25, 0.5, 1.0, 2.0, 3.0, 4.0, 4.5, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 11.5, 12.0];
        assert_eq!(ys, expected);
        // The lines began at y = 0, 4 and 8.
        assert_eq!(path.line_starts, vec![0, 6, 11]);
        let inserted_at: Vec<usize> = placed.iter().enumerate().filter(|(_, &p)| !p).map(|(i, _)| i).collect();
        assert_eq!(inserted_at, vec![1, 2, 7, 15, 16]);
    }

    /// The bump's raster of 0.05 mm over 50 × 50 mm would need a map of 1,002,001 nodes; the
    /// node limit makes it 0.1 mm, so the map reads the 501 × 501 stations at even places as
    /// nodes and the 500 × 500 at odd places as cells' middles: only those are kept.
    #[test]
    fn samples_are_kept_only_where_the_map_reads_them() {
        let spec = BallPathSpec {
            radius: 3.0,
            x: [-25.0, 25.0],
            y: [-25.0, 25.0],
            stepover: 0.05,
            spacing: Spacing::Step(0.05),
            lines: Lines::ConstantY,
            ..spec()
        };
        let [across, along] = [spec.y, spec.x].map(|range| stations(range, 0.05));
        assert_eq!((across.len(), along.len()), (1001, 1001));
        let kept = Kept::new(&spec, &across, &along);
        let kept_at = |k: usize, j: usize| kept.slot(k, j).is_some();
        for (k, j) in [(0, 0), (2, 998), (1000, 1000), (1, 1), (999, 3)] {
            assert!(kept_at(k, j), "({k}, {j})");
        }
        for (k, j) in [(0, 1), (1, 0), (1000, 999), (998, 1)] {
            assert!(!kept_at(k, j), "({k}, {j})");
        }
        let count = (0..1001).flat_map(|k| (0..1001).map(move |j| (k, j))).filter(|&(k, j)| kept_at(k, j)).count();
        assert_eq!(count, 501 * 501 + 500 * 500);
    }

    #[test]
    fn a_bad_spec_names_the_argument() {
        let bad = BallPathSpec { radius: 0.0, ..spec() };
        let err = ball_path(&mut Plane(0.0, 0.0, 0.0), &bad, &mut |_, _| {}).unwrap_err();
        assert_eq!(err, PathError::Spec(GeometryError::OutOfRange("ball radius R must be > 0, not 0".into())));
    }
}
