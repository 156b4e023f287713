//! A ball path as a program writes it (issue 32, scope 5): every programmed point on the grid
//! of the dialect's decimals, and the program's tolerance kept on what is written, not only
//! on what was computed.
//!
//! Rounding moves each programmed point by up to half a step in x, y and z, and the straight
//! move between two written points is not the move between the computed ones: over a slope
//! the ball goes deeper by the slope times its shift, and between two points the slope may be
//! steeper than at either. So each written point starts from the computed one raised by
//! [`written_reserve`] and rounded as the dialect rounds (half away from zero); then the exact
//! drop-cutter of the gouge check ([`super::dropcutter`]) checks each written ball and each
//! written move. A ball or move that cuts deeper than `gouge_tol` is mended on the grid: a
//! ball is lifted by its depth rounded up to a whole step, a move gets a point halfway (on
//! the grid, dropped onto the surface and rounded up), or, where no grid point lies between
//! its ends, both ends are lifted by its depth rounded up (raising an end raises the whole
//! swept ball, so no move already checked is made worse).

use nalgebra::Point3;

use super::{BallPath, Checker, Goal, Inserted, PathError, PathPoint, Surface, Sweep, Verdict, MAX_MOVE_HALVINGS};

/// How an NC program writes a ball path's programmed points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Written {
    /// The step (mm) the dialect writes coordinates in, 10^−decimals (0: exact).
    pub resolution: f64,
    /// How far the programmed point lies above the ball's centre: −R for the tip, 0 for the
    /// centre.
    pub programmed_dz: f64,
}

impl Written {
    /// Grid steps per mm (1000 for 3 decimals): a whole number, so that k / scale is the
    /// double nearest the decimal the dialect writes.
    fn scale(&self) -> f64 {
        (1.0 / self.resolution).round()
    }

    fn exact(&self) -> bool {
        self.resolution.is_nan() || self.resolution <= 0.0
    }

    /// `v` as the dialect writes it: the nearest step, half away from zero.
    fn nearest(&self, v: f64) -> f64 {
        if self.exact() {
            return v;
        }
        let s = self.scale();
        (v * s).round() / s
    }

    /// The lowest step at or above `v` (a value already on the grid stays where it is).
    fn at_or_above(&self, v: f64) -> f64 {
        if self.exact() {
            return v;
        }
        let s = self.scale();
        ((v * s) - 1e-6).ceil() / s
    }

    /// The ball whose programmed point is at the grid point nearest `centre`'s in x and y and
    /// at the height `programmed_z` (already on the grid).
    fn ball(&self, centre: Point3<f64>, programmed_z: f64) -> Point3<f64> {
        Point3::new(self.nearest(centre.x), self.nearest(centre.y), programmed_z - self.programmed_dz)
    }

    /// Lifts `p`'s programmed point by at least `depth`, to the grid; returns the rise.
    fn lift(&self, p: &mut PathPoint, depth: f64) -> f64 {
        let old = p.centre.z + self.programmed_dz;
        let new = self.at_or_above(old + depth);
        p.centre.z = new - self.programmed_dz;
        new - old
    }
}

/// How much higher (mm) a cutting point is programmed so that rounding its coordinates to
/// `resolution` is unlikely to take the ball deeper: half a step for its own z, and for x and
/// y (each moved up to half a step, √2/2 steps in all) the drop-cutter height's rise over
/// that shift, its slope taken as the steepest surface slope at the point and its neighbours
/// on the line. It is the written path's starting guess; the check after it is what holds.
pub fn written_reserve(resolution: f64, slope: f64) -> f64 {
    resolution * (0.5 + slope * std::f64::consts::FRAC_1_SQRT_2)
}

/// The surface's slope |∇f| where ball position `p` touches it: the normal from the contact
/// to the centre is (−f_x, −f_y, 1)/√(1 + |∇f|²). A normal lying flat is taken as a steep
/// wall (slope 10⁶).
fn slope_at(p: &PathPoint) -> f64 {
    let n = p.centre - p.contact;
    let flat = n.x.hypot(n.y);
    if n.z <= flat * 1e-6 {
        1e6
    } else {
        flat / n.z
    }
}

/// `path` with each programmed point raised by its reserve and rounded as the dialect
/// rounds it, unchecked (the gouge check is off, or the path is refused anyway).
pub(super) fn rounded(path: &BallPath, w: Written) -> BallPath {
    let points = if w.exact() { path.points.clone() } else { rounded_points(path, w) };
    BallPath {
        radius: path.radius,
        points,
        line_starts: path.line_starts.clone(),
        gouges: Vec::new(),
        surface_z: path.surface_z,
    }
}

/// Each point raised by its reserve for the written decimals, its slope the steepest of
/// itself and its neighbours on the same raster line, and rounded.
fn rounded_points(path: &BallPath, w: Written) -> Vec<PathPoint> {
    let mut out = Vec::with_capacity(path.points.len());
    for (k, &start) in path.line_starts.iter().enumerate() {
        let end = path.line_starts.get(k + 1).copied().unwrap_or(path.points.len());
        let line = &path.points[start..end];
        // The slopes of the point before, this one and the next (0 where there is none:
        // no slope is below it) slide along the line.
        let (mut before, mut here) = (0.0, line.first().map_or(0.0, slope_at));
        for (i, p) in line.iter().enumerate() {
            let next = line.get(i + 1).map_or(0.0, slope_at);
            let around = 0.0f64.max(before).max(here).max(next);
            let z = w.nearest(p.centre.z + w.programmed_dz + written_reserve(w.resolution, around));
            out.push(PathPoint { contact: p.contact, centre: w.ball(p.centre, z) });
            (before, here) = (here, next);
        }
    }
    out
}

impl<S: Surface> Checker<'_, S> {
    /// `path` as written with `w`: rounded, then each ball and each move checked against the
    /// surface and mended where it cuts deeper than the tolerance. The written path is checked
    /// in its own buffer, and its bounds kept in `buffer` (the computed check's, spent).
    pub(super) fn as_written(
        &mut self,
        path: &BallPath,
        w: Written,
        buffer: Vec<f64>,
    ) -> Result<BallPath, PathError<S::Error>> {
        let mut written = rounded(path, w);
        if w.exact() {
            return Ok(written);
        }
        let mut below = buffer;
        below.clear();
        for (i, p) in written.points.iter_mut().enumerate() {
            let placed = self.placed.get(i).copied().unwrap_or(false).then_some(&path.points[i]);
            below.push(self.written_position(p, placed, w)?);
        }
        let n = written.points.len();
        let mut out = Rewriting {
            points: &mut written.points,
            below: &mut below,
            at: 0,
            inserted: Inserted::default(),
            inserted_below: Vec::new(),
        };
        for k in 0..written.line_starts.len() {
            let end = written.line_starts.get(k + 1).copied().unwrap_or(n);
            for i in written.line_starts[k]..end {
                out.at = i;
                if i + 1 == n || (i + 1 == end && !self.spec.check_links) {
                    continue;
                }
                // The move may lift its far end: the next move starts from it as lifted.
                let (mut b, mut b_below) = (out.points[i + 1], out.below[i + 1]);
                self.written_move(&mut out, &mut b, &mut b_below, w, MAX_MOVE_HALVINGS)?;
                (out.points[i + 1], out.below[i + 1]) = (b, b_below);
            }
        }
        let inserted = out.inserted;
        inserted.into_path(&mut written);
        Ok(written)
    }

    /// Checks the written ball `p` (rounded from the computed one, `placed` where that is
    /// still the ball placed by its contact), lifting it on the grid where it cuts deeper than
    /// the tolerance; returns a bound on how far it is below the drop-cutter height.
    fn written_position(
        &mut self,
        p: &mut PathPoint,
        placed: Option<&PathPoint>,
        w: Written,
    ) -> Result<f64, PathError<S::Error>> {
        let proved = placed.and_then(|exact| self.shifted_bound(exact, p));
        if let Some(bound) = proved.filter(|&b| b <= self.spec.gouge_tol) {
            return Ok(bound.max(0.0));
        }
        let ball = Sweep::at_rest(p.centre, self.spec.radius);
        match self.judge(&ball, &[p.contact])? {
            Verdict::Clear(below) => Ok(below),
            Verdict::Gouge(cut) => {
                let rise = w.lift(p, cut.depth);
                Ok((cut.depth + self.search_tol() - rise).max(0.0))
            }
        }
    }

    /// A bound on how far the ball `moved` is below the drop-cutter height, proved from the
    /// ball `placed` it was moved from by δ, where that one is tangent to the surface at its
    /// contact T (slope s there) and the surface bends up less than the ball (Λ < 1/R) over
    /// both footprints: f lies under the paraboloid q of T's tangent plane and Λ, which lies
    /// under the placed ball by ½(1/R − Λ)|x − T|²; so for a point p of the moved footprint,
    /// x = p − δ, f(p) − low'(p) ≤ −½κ|x − T|² + (s + Λ|x − T|)·|δ| + ½Λ|δ|² − δz with
    /// κ = 1/R − Λ, at most s|δ| + ½Λ|δ|² + (Λ|δ|)²/(2κ) − δz. None where it does not apply.
    fn shifted_bound(&self, placed: &PathPoint, moved: &PathPoint) -> Option<f64> {
        let r = self.spec.radius;
        let lambda = self.map.upper_curvature(&Sweep { a: placed.centre, b: moved.centre, r }).max(0.0);
        let kappa = 1.0 / r - lambda;
        if kappa <= 0.0 {
            return None;
        }
        // Placed by its contact, the ball's centre lies along the surface's normal there.
        let s = slope_at(placed);
        let shift = (moved.centre.x - placed.centre.x).hypot(moved.centre.y - placed.centre.y);
        let rise = moved.centre.z - placed.centre.z;
        let lifted = lambda * shift;
        Some(s * shift + 0.5 * lambda * shift * shift + lifted * lifted / (2.0 * kappa) - rise)
    }

    /// The written move from the last point of `out` to `b` (whose bounds below the
    /// drop-cutter height are the last point's and `b_below`): a point halfway where it cuts
    /// deeper than the tolerance, or its ends lifted where the grid has no point between.
    fn written_move(
        &mut self,
        out: &mut Rewriting,
        b: &mut PathPoint,
        b_below: &mut f64,
        w: Written,
        halvings_left: u32,
    ) -> Result<(), PathError<S::Error>> {
        let (r, tol, half) = (self.spec.radius, self.spec.gouge_tol, self.search_tol());
        let (a, a_below) = out.last();
        let (a, a_below) = (*a, *a_below);
        let sweep = Sweep { a: a.centre, b: b.centre, r };
        if self.map.move_bound(&sweep, [a_below, *b_below]).is_some_and(|bound| bound <= tol) {
            return Ok(());
        }
        let cut = match self.judge(&sweep, &[a.contact, b.contact])? {
            Verdict::Clear(_) => return Ok(()),
            Verdict::Gouge(cut) => cut,
        };
        let middle = w.ball(Point3::from((a.centre.coords + b.centre.coords) * 0.5), 0.0);
        let on_an_end = |p: &PathPoint| p.centre.x == middle.x && p.centre.y == middle.y;
        if halvings_left == 0 || on_an_end(&a) || on_an_end(b) {
            // Both ends lifted by the depth lift the whole move by it at least.
            w.lift(out.last().0, cut.depth);
            w.lift(b, cut.depth);
            return Ok(());
        }
        let mid = Point3::new(middle.x, middle.y, 0.5 * (a.centre.z + b.centre.z));
        let drop = self.deepest(&Sweep::at_rest(mid, r), &[cut.at, a.contact, b.contact], Goal::Within(half))?;
        let mut m = PathPoint { contact: drop.at, centre: mid };
        m.centre.z = w.at_or_above(mid.z + drop.depth + w.programmed_dz) - w.programmed_dz;
        let mut m_below = half;
        self.written_move(out, &mut m, &mut m_below, w, halvings_left - 1)?;
        out.push(m, m_below);
        self.written_move(out, b, b_below, w, halvings_left - 1)
    }
}

/// The written path while its moves are checked, in its own buffer: the path's points up to
/// `at` are done, and the points inserted after them wait aside with their bounds.
struct Rewriting<'p> {
    points: &'p mut [PathPoint],
    /// Per point of the path, a bound on how far it is below the drop-cutter height.
    below: &'p mut [f64],
    /// The path's point the move being checked starts from.
    at: usize,
    inserted: Inserted,
    inserted_below: Vec<f64>,
}

impl Rewriting<'_> {
    /// The written path's last point so far (where the move being checked starts) and its
    /// bound: the last inserted after `at`, or `at` itself.
    fn last(&mut self) -> (&mut PathPoint, &mut f64) {
        match self.inserted.last_after(self.at) {
            Some(p) => (p, self.inserted_below.last_mut().expect("one per inserted point")),
            None => (&mut self.points[self.at], &mut self.below[self.at]),
        }
    }

    fn push(&mut self, p: PathPoint, below: f64) {
        self.inserted.push(self.at, p);
        self.inserted_below.push(below);
    }
}

#[cfg(test)]
mod tests {
    use super::super::{check_spec, BallPathSpec, Direction, GougeCheck, Lines, Sample, Spacing};
    use super::*;
    use crate::geometry::dropcutter::Map;

    /// z = 2x + 0.00063: a ball of radius R over (cx, cy) rests with its centre at
    /// 2·cx + 0.00063 + R·√5 (the constant puts the tips just below a half step, so that
    /// rounding them takes little of the reserve).
    struct Slope;

    const LIFT: f64 = 0.00063;

    impl Surface for Slope {
        type Error = ();

        fn height(&mut self, x: f64, _: f64) -> Result<f64, ()> {
            Ok(2.0 * x + LIFT)
        }

        fn sample(&mut self, x: f64, _: f64) -> Result<Sample, ()> {
            Ok(Sample { z: 2.0 * x + LIFT, dzdx: 2.0, dzdy: 0.0 })
        }
    }

    fn drop_height(c: Point3<f64>, r: f64) -> f64 {
        2.0 * c.x + LIFT + r * 5f64.sqrt()
    }

    /// Balls at the drop-cutter height whose contacts say the surface is flat (so the reserve
    /// is half a step) and whose x rounds uphill by 0.4 steps: rounded alone they go up to
    /// 0.8 steps deeper, past a tolerance of a tenth of a step; as written they keep it.
    #[test]
    fn the_written_path_is_checked_not_only_reserved() {
        let (r, res) = (1.0, 0.001);
        let spec = BallPathSpec {
            radius: r,
            x: [-3.0, 3.0],
            y: [-3.0, 3.0],
            stepover: 1.0,
            spacing: Spacing::Step(0.1),
            lines: Lines::ConstantY,
            direction: Direction::Zigzag,
            gouge: GougeCheck::Lift,
            gouge_tol: 0.1 * res,
            gouge_samples: 10_000_000,
            check_links: true,
            max_points: 1000,
        };
        check_spec(&spec).unwrap();
        let points: Vec<PathPoint> = (0..9)
            .map(|k| {
                let c = Point3::new(-0.4 + 0.1 * k as f64 + 0.6 * res, 0.3 * k as f64 / 9.0, 0.0);
                let centre = Point3::new(c.x, c.y, drop_height(c, r));
                PathPoint { contact: centre - nalgebra::Vector3::new(0.0, 0.0, r), centre }
            })
            .collect();
        let path = BallPath { radius: r, points, line_starts: vec![0, 5], gouges: Vec::new(), surface_z: [-6.0, 6.0] };
        let w = Written { resolution: res, programmed_dz: -r };
        let depth = |p: &PathPoint| drop_height(p.centre, r) - p.centre.z;
        let rounded = rounded(&path, w);
        assert!(rounded.points.iter().map(depth).fold(f64::MIN, f64::max) > 0.5 * res);

        let mut surface = Slope;
        let map = Map::sample(&mut surface, spec.x, spec.y, 0.25, 0.25 * spec.gouge_tol, Vec::new()).unwrap();
        let mut check = Checker {
            surface: &mut surface,
            map,
            spec: &spec,
            gouges: Vec::new(),
            samples_left: 10_000_000,
            placed: Vec::new(),
        };
        let written = check.as_written(&path, w, Vec::new()).unwrap();
        assert_eq!(written.points.len(), path.points.len());
        for p in &written.points {
            // On the plane the depth along a move is linear: its ends bound it.
            assert!(depth(p) <= spec.gouge_tol, "{p:?} is {} deep", depth(p));
            let tip = p.centre.z - r;
            for v in [p.centre.x, p.centre.y, tip] {
                assert!((v * 1000.0 - (v * 1000.0).round()).abs() < 1e-6, "{v} is not on the grid");
            }
        }
    }
}
