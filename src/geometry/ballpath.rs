//! Ball-end mill finishing path over a surface z = f(x, y) (DOMAIN.md §3, Král's EqCAM).
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
//! prints the inward gradient and wrong partial derivatives: DOMAIN.md [fix]). The tip, the
//! lowest point of the ball, is C − (0, 0, R).
//!
//! Gouge check: a ball placed by its contact point may still cut the surface elsewhere (a
//! concave region whose curvature radius is below R, a steep wall nearby). The surface inside
//! the rectangle is sampled once on a grid (spacing R/3, coarser for huge maps); for each
//! centre the samples within R horizontally are compared with the ball's lower hemisphere, and
//! where one pokes into it the deepest point is refined against the surface itself. The depth
//! is vertical: how far the ball must rise to clear the surface (drop-cutter). A gouge is
//! reported, or the ball is lifted by that depth so it touches the surface at the refined point
//! instead. Only the surface inside the rectangle is the part; what lies beyond it is not
//! checked. Moves between programmed points are not checked.
//!
//! This module knows nothing of formulas: it reads the surface through [`Surface`].

use nalgebra::{Point3, Vector3};

use super::{ensure, GeometryError};

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
    pub gouge: GougeCheck,
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

/// A ball position that cuts the surface away from its contact point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gouge {
    /// Index of the ball position in [`BallPath::points`].
    pub point: usize,
    /// The contact point the ball was placed by.
    pub contact: Point3<f64>,
    /// The surface point deepest inside the ball.
    pub at: Point3<f64>,
    /// How far the ball must rise (mm) to clear the surface.
    pub depth: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct BallPath {
    pub radius: f64,
    /// Ball positions in cutting order.
    pub points: Vec<PathPoint>,
    /// Index of the first point of each raster line.
    pub line_starts: Vec<usize>,
    /// Gouges found (with [`GougeCheck::Lift`]: the positions that were lifted).
    pub gouges: Vec<Gouge>,
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
}

impl<E> From<GeometryError> for PathError<E> {
    fn from(e: GeometryError) -> Self {
        PathError::Spec(e)
    }
}

/// Gouges shallower than this (mm) are rounding, not cutting.
pub const GOUGE_TOLERANCE: f64 = 1e-7;

/// Halving a chord stops at this depth (max_step / 2^20).
const MAX_HALVINGS: u32 = 20;

/// The ball path of `spec` over `surface`. `progress(done, total)` is called after each line.
pub fn ball_path<S: Surface>(
    surface: &mut S,
    spec: &BallPathSpec,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<BallPath, PathError<S::Error>> {
    check_spec(spec)?;
    let (across, along) = match spec.lines {
        Lines::ConstantX => (spec.x, spec.y),
        Lines::ConstantY => (spec.y, spec.x),
    };
    let stations = stations(across, spec.stepover);
    // Progress counts lines placed, then lines checked for gouges.
    let total = stations.len() * if spec.gouge == GougeCheck::Off { 1 } else { 2 };
    let mut path = BallPath { radius: spec.radius, points: Vec::new(), line_starts: Vec::new(), gouges: Vec::new() };
    if let Spacing::Step(step) = spec.spacing {
        let per_line = ((along[1] - along[0]) / step).ceil() + 1.0;
        path.points.reserve((per_line * stations.len() as f64).min(spec.max_points as f64) as usize);
    }
    let mut placer = Placer { surface, radius: spec.radius, lines: spec.lines };
    for (k, &u) in stations.iter().enumerate() {
        path.line_starts.push(path.points.len());
        let start = path.points.len();
        placer.line(u, along, spec.spacing, &mut path.points, spec.max_points)?;
        // Odd lines run backwards: zig-zag.
        if k % 2 == 1 {
            path.points[start..].reverse();
        }
        progress(k + 1, total);
    }
    if spec.gouge != GougeCheck::Off {
        let map = HeightMap::sample(placer.surface, spec)?;
        check_gouges(placer.surface, &map, spec, &mut path, &mut |k| progress(stations.len() + k, total))?;
    }
    Ok(path)
}

fn check_spec(spec: &BallPathSpec) -> Result<(), GeometryError> {
    let finite = [spec.radius, spec.x[0], spec.x[1], spec.y[0], spec.y[1], spec.stepover].iter().all(|v| v.is_finite());
    ensure(finite, || "every number of a ball path must be finite".into())?;
    ensure(spec.radius > 0.0, || format!("ball radius R must be > 0, not {}", spec.radius))?;
    ensure(spec.x[0] <= spec.x[1], || format!("x0 ({}) must not be beyond x1 ({})", spec.x[0], spec.x[1]))?;
    ensure(spec.y[0] <= spec.y[1], || format!("y0 ({}) must not be beyond y1 ({})", spec.y[0], spec.y[1]))?;
    ensure(spec.stepover > 0.0, || format!("stepover must be > 0, not {}", spec.stepover))?;
    match spec.spacing {
        Spacing::Step(s) => ensure(s > 0.0 && s.is_finite(), || format!("step must be > 0, not {s}"))?,
        Spacing::Chord { tolerance, max_step } => {
            ensure(tolerance > 0.0 && tolerance.is_finite(), || {
                format!("chord tolerance must be > 0, not {tolerance}")
            })?;
            ensure(max_step > 0.0 && max_step.is_finite(), || format!("step must be > 0, not {max_step}"))?;
        }
    }
    let across = match spec.lines {
        Lines::ConstantX => spec.x,
        Lines::ConstantY => spec.y,
    };
    let n_lines = ((across[1] - across[0]) / spec.stepover).ceil() + 1.0;
    ensure(n_lines <= spec.max_points as f64, || {
        format!("the path would have {n_lines} lines, more than the {} points allowed", spec.max_points)
    })
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

/// Places balls by their contact points.
struct Placer<'s, S> {
    surface: &'s mut S,
    radius: f64,
    lines: Lines,
}

impl<S: Surface> Placer<'_, S> {
    /// The ball touching the surface at line coordinate `u`, position `v` along the line.
    fn place(&mut self, u: f64, v: f64) -> Result<PathPoint, PathError<S::Error>> {
        let (x, y) = match self.lines {
            Lines::ConstantX => (u, v),
            Lines::ConstantY => (v, u),
        };
        let s = self.surface.sample(x, y).map_err(|error| PathError::Surface { x, y, error })?;
        Ok(ball_at(Point3::new(x, y, s.z), s.dzdx, s.dzdy, self.radius))
    }

    fn line(
        &mut self,
        u: f64,
        along: [f64; 2],
        spacing: Spacing,
        out: &mut Vec<PathPoint>,
        max_points: usize,
    ) -> Result<(), PathError<S::Error>> {
        let too_many =
            || PathError::Spec(GeometryError::OutOfRange(format!("the path has more than {max_points} points")));
        match spacing {
            Spacing::Step(step) => {
                let vs = stations(along, step);
                if out.len() + vs.len() > max_points {
                    return Err(too_many());
                }
                out.reserve(vs.len());
                for v in vs {
                    out.push(self.place(u, v)?);
                }
            }
            Spacing::Chord { tolerance, max_step } => {
                let vs = stations(along, max_step);
                let mut prev = (vs[0], self.place(u, vs[0])?);
                out.push(prev.1);
                for &v in &vs[1..] {
                    let next = (v, self.place(u, v)?);
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

/// Heights of the surface on a regular grid over the rectangle.
struct HeightMap {
    x0: f64,
    y0: f64,
    hx: f64,
    hy: f64,
    /// 1/hx and 1/hy (0 for a map one sample wide): multiplying is faster than dividing.
    inv_hx: f64,
    inv_hy: f64,
    nx: usize,
    ny: usize,
    /// Row-major by y: `z[j * nx + i]` is the height at (x0 + i·hx, y0 + j·hy).
    z: Vec<f64>,
}

/// Grids above this many samples get coarser than R/3.
const MAX_MAP_SAMPLES: f64 = 4.0e6;

impl HeightMap {
    fn sample<S: Surface>(surface: &mut S, spec: &BallPathSpec) -> Result<HeightMap, PathError<S::Error>> {
        let (w, h) = (spec.x[1] - spec.x[0], spec.y[1] - spec.y[0]);
        let spacing = (spec.radius / 3.0).max((w * h / MAX_MAP_SAMPLES).sqrt());
        let count = |len: f64| (len / spacing).ceil().max(1.0) as usize + 1;
        let (nx, ny) = (count(w), count(h));
        let (hx, hy) = (w / (nx - 1) as f64, h / (ny - 1) as f64);
        let mut z = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (spec.x[0] + i as f64 * hx, spec.y[0] + j as f64 * hy);
                z.push(surface.height(x, y).map_err(|error| PathError::Surface { x, y, error })?);
            }
        }
        let inverse = |h: f64| if h > 0.0 { 1.0 / h } else { 0.0 };
        Ok(HeightMap { x0: spec.x[0], y0: spec.y[0], hx, hy, inv_hx: inverse(hx), inv_hy: inverse(hy), nx, ny, z })
    }

    /// The sample poking deepest into the ball centred at `c` (vertical depth), if any does
    /// by more than [`GOUGE_TOLERANCE`].
    fn deepest(&self, c: &Point3<f64>, r: f64) -> Option<(f64, f64, f64)> {
        // Indices of the samples within `half` of `c` along one axis.
        let range = |c: f64, half: f64, origin: f64, inv_h: f64, n: usize| {
            if inv_h == 0.0 {
                return 0..1;
            }
            // `as` truncates (and saturates at 0): floor for the non-negative, without libm.
            let (a, b) = ((c - half - origin) * inv_h, (c + half - origin) * inv_h);
            let lo = a as usize + usize::from(a > 0.0 && a.fract() != 0.0);
            let hi = if b < 0.0 { 0 } else { (b as usize + 1).min(n) };
            lo.min(hi)..hi
        };
        let mut best: Option<(f64, f64, f64)> = None;
        let mut best_depth = GOUGE_TOLERANCE;
        let r2 = r * r;
        for j in range(c.y, r, self.y0, self.inv_hy, self.ny) {
            let y = self.y0 + j as f64 * self.hy;
            let room_row = r2 - (y - c.y) * (y - c.y);
            // Only the chord of the ball's footprint on this row.
            let cols = range(c.x, room_row.max(0.0).sqrt(), self.x0, self.inv_hx, self.nx);
            let first = cols.start;
            let mut dx = self.x0 + first as f64 * self.hx - c.x;
            for (k, &z) in self.z[j * self.nx + first..j * self.nx + cols.end].iter().enumerate() {
                // room = R² − d²; the depth z − c.z + √room beats the best only if
                // √room > best + c.z − z: squared, no root for the samples that do not.
                let room = room_row - dx * dx;
                dx += self.hx;
                let a = best_depth + c.z - z;
                if room <= 0.0 || (a >= 0.0 && room <= a * a) {
                    continue;
                }
                let depth = z - c.z + room.sqrt();
                if depth > best_depth {
                    best_depth = depth;
                    best = Some((self.x0 + (first + k) as f64 * self.hx, y, depth));
                }
            }
        }
        best
    }
}

fn check_gouges<S: Surface>(
    surface: &mut S,
    map: &HeightMap,
    spec: &BallPathSpec,
    path: &mut BallPath,
    lines_checked: &mut dyn FnMut(usize),
) -> Result<(), PathError<S::Error>> {
    for k in 0..path.line_starts.len() {
        let end = path.line_starts.get(k + 1).copied().unwrap_or(path.points.len());
        for index in path.line_starts[k]..end {
            let original = path.points[index];
            let Some((lifted, depth)) = gouge_at(surface, map, spec, original)? else { continue };
            path.gouges.push(Gouge { point: index, contact: original.contact, at: lifted.contact, depth });
            if spec.gouge == GougeCheck::Lift {
                path.points[index] = lifted;
            }
        }
        lines_checked(k + 1);
    }
    Ok(())
}

/// Whether the ball `p` cuts the surface: the ball raised clear of it (touching it at the
/// deepest point) and how far it rose; `None` where it does not cut.
fn gouge_at<S: Surface>(
    surface: &mut S,
    map: &HeightMap,
    spec: &BallPathSpec,
    original: PathPoint,
) -> Result<Option<(PathPoint, f64)>, PathError<S::Error>> {
    let mut p = original;
    let mut lift = 0.0;
    // A lifted ball may still touch another hollow whose samples were shallower: check again
    // from the new height (twice is plenty in practice; the cap stops a loop). Reporting needs
    // only the first.
    let rounds = if spec.gouge == GougeCheck::Lift { 4 } else { 1 };
    for _ in 0..rounds {
        let Some((x, y, _)) = map.deepest(&p.centre, spec.radius) else { break };
        let (at, depth) = refine_gouge(surface, spec, &p.centre, x, y)?;
        if depth <= GOUGE_TOLERANCE {
            break;
        }
        lift += depth;
        p = PathPoint { contact: at, centre: p.centre + Vector3::new(0.0, 0.0, depth) };
    }
    Ok((lift > 0.0).then_some((p, lift)))
}

/// Climbs from the sample (x, y) to the deepest point of the surface inside the ball centred
/// at `c`, by a compass search on the vertical depth `f(u, v) − (c_z − √(R² − d²))` over the
/// disk of radius R around c (inside the rectangle).
fn refine_gouge<S: Surface>(
    surface: &mut S,
    spec: &BallPathSpec,
    c: &Point3<f64>,
    x: f64,
    y: f64,
) -> Result<(Point3<f64>, f64), PathError<S::Error>> {
    let r2 = spec.radius * spec.radius;
    let mut depth_at = |u: f64, v: f64| -> Result<Option<(f64, f64)>, PathError<S::Error>> {
        let d2 = (u - c.x).powi(2) + (v - c.y).powi(2);
        let inside = d2 < r2 && (spec.x[0]..=spec.x[1]).contains(&u) && (spec.y[0]..=spec.y[1]).contains(&v);
        if !inside {
            return Ok(None);
        }
        let z = surface.height(u, v).map_err(|error| PathError::Surface { x: u, y: v, error })?;
        Ok(Some((z - (c.z - (r2 - d2).sqrt()), z)))
    };
    let (mut u, mut v) = (x, y);
    let Some((mut best, mut z)) = depth_at(u, v)? else { return Ok((Point3::new(x, y, c.z), 0.0)) };
    let mut step = spec.radius / 8.0;
    const D: f64 = std::f64::consts::FRAC_1_SQRT_2;
    const DIRECTIONS: [(f64, f64); 8] =
        [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (D, D), (-D, -D), (D, -D), (-D, D)];
    // The depth is smooth where the surface is: at a step of 1e-10·R the position is as good
    // as the depth needs (the depth's error goes with the square of the step).
    while step > spec.radius * 1e-10 {
        let mut moved = false;
        for (du, dv) in DIRECTIONS {
            let (nu, nv) = (u + du * step, v + dv * step);
            if let Some((d, nz)) = depth_at(nu, nv)? {
                if d > best {
                    (u, v, best, z) = (nu, nv, d, nz);
                    moved = true;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    Ok((Point3::new(u, v, z), best))
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
    fn a_bad_spec_names_the_argument() {
        let bad = BallPathSpec { radius: 0.0, ..spec() };
        let err = ball_path(&mut Plane(0.0, 0.0, 0.0), &bad, &mut |_, _| {}).unwrap_err();
        assert_eq!(err, PathError::Spec(GeometryError::OutOfRange("ball radius R must be > 0, not 0".into())));
    }
}
