//! Exact drop-cutter for a ball over a surface z = f(x, y) on a rectangle, for a ball at rest
//! and for a ball swept along a straight move (docs/ballpath.md, "Gouges", argues why it
//! cannot miss).
//!
//! The ball's lower boundary over a point p of the plane is `z_low(p)`: for a ball centred at
//! C, C_z − √(R² − |p − C|²); for a ball swept from A to B, the lowest such height over the
//! move. The ball cuts the surface by `max_p f(p) − z_low(p)` over the part (the rectangle):
//! how far it must rise to clear it. That maximum is found by branch and bound over squares of
//! the footprint, with an upper bound for each square from the surface's exact slope at its
//! centre and a bound Λ on the surface's curvature there, and a lower bound from the samples:
//! the search stops when no square can beat the best sample by more than the tolerance.
//!
//! Λ comes from the map: the surface's height and exact slope on a grid over the rectangle;
//! each map cell's Hessian is estimated from the slopes at its corners, and Λ (the upper bound
//! of its eigenvalues) and Γ (the lower, negated) take the extremes over the cell's neighbours
//! plus their spread. The map also gives two cheap proofs used before any search: a ball
//! placed by its contact point clears a footprint where Λ ≤ 1/R (the surface bends up less
//! than the ball), and a move between two clear balls dips at most Γ·L²/8 where RΛ < 1.
//! Those proofs take Λ and Γ over every cell under the ball's footprint (3,600 cells for a
//! 3 mm ball on a 0.1 mm map, each position and each move): they are read from the maxima
//! over square blocks of 2^L cells, a handful of reads per footprint.

use std::cell::OnceCell;
use std::collections::BinaryHeap;

use nalgebra::{Point3, Vector2};

use super::ballpath::{Sample, Surface};

/// A place (x, y) where a map cell does not resolve the surface, and by how much (mm).
type Unresolved = (f64, f64, f64);

/// A ball of radius `r`, at rest (`a == b`) or swept in a straight line from centre `a` to `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep {
    pub a: Point3<f64>,
    pub b: Point3<f64>,
    pub r: f64,
}

/// The ball's lowest height over a point of the plane and its slope there.
struct Low {
    z: f64,
    grad: Vector2<f64>,
    /// √(R² − d²) at the centre that is lowest over the point: 0 on the footprint's rim.
    root: f64,
}

impl Sweep {
    pub fn at_rest(c: Point3<f64>, r: f64) -> Sweep {
        Sweep { a: c, b: c, r }
    }

    fn horizontal(&self) -> Vector2<f64> {
        Vector2::new(self.b.x - self.a.x, self.b.y - self.a.y)
    }

    /// The horizontal distance from `p` to the path of the centre.
    fn distance(&self, p: Vector2<f64>) -> f64 {
        let a = Vector2::new(self.a.x, self.a.y);
        let e = self.horizontal();
        let len2 = e.norm_squared();
        let t = if len2 > 0.0 { ((p - a).dot(&e) / len2).clamp(0.0, 1.0) } else { 0.0 };
        (p - (a + e * t)).norm()
    }

    /// The lowest point of the (swept) ball over `p`, if p is under it. The centre lowest
    /// over p minimises C_z(τ) − √(R² − |p − C(τ)|²), convex in τ: its free minimum is
    /// τ* = α − m·ρ/√(1 + m²) (α, β: p along and across the move, ρ² = R² − β², m the move's
    /// slope), clamped to the move and to the chord over p.
    fn low(&self, p: Vector2<f64>) -> Option<Low> {
        let r2 = self.r * self.r;
        let e = self.horizontal();
        let len = e.norm();
        let a = Vector2::new(self.a.x, self.a.y);
        let (c, cz) = if len <= 1e-12 * self.r {
            // At rest, or straight up and down: the lower end is the lowest.
            let lower = if self.a.z <= self.b.z { self.a } else { self.b };
            (Vector2::new(lower.x, lower.y), lower.z)
        } else {
            let u = e / len;
            let w = p - a;
            let alpha = w.dot(&u);
            let rho2 = r2 - (w.norm_squared() - alpha * alpha).max(0.0);
            if rho2 <= 0.0 {
                return None;
            }
            let rho = rho2.sqrt();
            let m = (self.b.z - self.a.z) / len;
            let (lo, hi) = ((alpha - rho).max(0.0), (alpha + rho).min(len));
            if lo > hi {
                return None;
            }
            let tau = (alpha - m * rho / (1.0 + m * m).sqrt()).clamp(lo, hi);
            (a + u * tau, self.a.z + m * tau)
        };
        let d = p - c;
        let room = r2 - d.norm_squared();
        if room < 0.0 {
            return None;
        }
        let root = room.sqrt();
        let grad = if root > 0.0 { d / root } else { Vector2::new(f64::INFINITY, f64::INFINITY) };
        Some(Low { z: cz - root, grad, root })
    }

    /// How strongly convex z_low is: 1/R for a ball at rest, 0 once it moves (along the move
    /// the swept ball's underside is straight).
    fn convexity(&self) -> f64 {
        if self.horizontal().norm() <= 1e-12 * self.r {
            1.0 / self.r
        } else {
            0.0
        }
    }

    /// The lowest the ball gets over any point of a square of half-diagonal `rho` around `q`.
    fn low_bound(&self, q: Vector2<f64>, rho: f64) -> f64 {
        let d = (self.distance(q) - rho).max(0.0);
        self.a.z.min(self.b.z) - (self.r * self.r - d * d).max(0.0).sqrt()
    }
}

/// The deepest cut of a ball found by [`Map::deepest`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cut {
    /// How far the ball must rise to clear the surface, within the tolerance (negative: it
    /// clears by that much). The true depth is in [depth, depth + tolerance].
    pub depth: f64,
    /// The surface point where it cuts deepest (or comes closest).
    pub at: Point3<f64>,
    /// False when the sample budget ran out before the search ended: `depth` is then only a
    /// lower bound.
    pub complete: bool,
}

/// What a search is after: the deepest cut to within a tolerance, or only whether any cut
/// is deeper than a threshold (it stops at the first sample that is, and drops every square
/// that cannot be).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Goal {
    Within(f64),
    Deeper(f64),
}

/// The surface on a grid over the rectangle, with curvature bounds per cell.
pub struct Map {
    x0: f64,
    y0: f64,
    hx: f64,
    hy: f64,
    /// Cells along x and y (at least 1: a rectangle of zero width is one cell wide).
    cx: usize,
    cy: usize,
    /// Per cell, row-major by y: Λ ≥ the Hessian's eigenvalues, Γ ≥ minus them (Γ ≥ 0).
    lambda: Vec<f64>,
    gamma: Vec<f64>,
    /// Per level L ≥ 1, made when first asked for: Λ and Γ maximised over the block of
    /// 2^L × 2^L cells from each cell (cut at the map's edges).
    blocks: Vec<OnceCell<Blocks>>,
    /// The lowest and highest node heights.
    heights: [f64; 2],
    /// The samples at the nodes, row-major by y.
    nodes: Vec<Sample>,
}

/// One axis of a map's grid: nodes at `start + i·step` (i = 0 ..= cells; only `start` for a
/// step of 0), cells between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridAxis {
    pub start: f64,
    pub step: f64,
    pub cells: usize,
}

impl GridAxis {
    /// How many nodes: one past the cells, or one where the axis has no width.
    pub fn nodes(&self) -> usize {
        if self.step > 0.0 {
            self.cells + 1
        } else {
            1
        }
    }

    /// Whether the map samples the surface at coordinate `v` (exactly these bits) as a node.
    pub fn is_node(&self, v: f64) -> bool {
        self.near(v, 0.0).any(|i| i < self.nodes() && self.start + i as f64 * self.step == v)
    }

    /// Whether the map samples the surface at coordinate `v` (exactly these bits) as a cell's
    /// middle: where it checks that the cell resolves the surface, or where a search starts.
    pub fn is_middle(&self, v: f64) -> bool {
        let half = 0.5 * self.step;
        self.near(v, 0.5).any(|i| {
            let corner = self.start + i as f64 * self.step;
            i < self.cells && (self.start + (i as f64 + 0.5) * self.step == v || corner + half == v)
        })
    }

    /// The indices i around where `start + (i + offset)·step` is `v`.
    fn near(&self, v: f64, offset: f64) -> impl Iterator<Item = usize> {
        let i = if self.step > 0.0 { ((v - self.start) / self.step - offset).round() } else { 0.0 };
        let first = if i.is_finite() && i >= 1.0 { i as usize - 1 } else { 0 };
        let count = if i.is_finite() && i >= -1.0 { 3 } else { 0 };
        first..first + count
    }
}

/// Λ and Γ over blocks of cells, row-major as the cells.
struct Blocks {
    lambda: Vec<f64>,
    gamma: Vec<f64>,
}

/// Largest number of map nodes (the map costs one sample each).
const MAX_NODES: f64 = 250_000.0;

/// A square of the search smaller than this fraction of R is not split further.
const SMALLEST: f64 = 1e-9;

/// Why there is no map: the surface has no value somewhere, or it is not resolved at the
/// finest spacing the node limit allows.
#[derive(Clone, Debug, PartialEq)]
pub enum MapError<E> {
    Surface(f64, f64, E),
    Unresolved {
        /// The middle of the cell the surface is not resolved in.
        x: f64,
        y: f64,
        /// The map's spacing there (mm): the finest the node limit allows.
        spacing: f64,
        /// How far (mm) the surface at the cell's middle is from what its corners allow.
        mismatch: f64,
    },
}

impl<E> From<(f64, f64, E)> for MapError<E> {
    fn from((x, y, e): (f64, f64, E)) -> Self {
        MapError::Surface(x, y, e)
    }
}

impl Map {
    /// The map over [x0, x1] × [y0, y1] at about `spacing` or finer: a map is made finer
    /// (its spacing halved) while a cell's middle lies farther than `accept` (mm) outside
    /// what the curvature bounds and its corners allow — a bump narrower than the spacing, a
    /// step — so that features between the path's points are found; at the node limit
    /// ([`MAX_NODES`]) such a cell is an error naming it. `nodes`: the samples at the nodes of
    /// the first grid ([`Map::grid`], row-major by y) where the caller holds them, taken as
    /// they are if there is one per node (else the nodes are sampled).
    pub fn sample<S: Surface>(
        surface: &mut S,
        x: [f64; 2],
        y: [f64; 2],
        spacing: f64,
        accept: f64,
        nodes: Vec<Sample>,
    ) -> Result<Map, MapError<S::Error>> {
        let (mut spacing, mut given) = (spacing, nodes);
        let mut cells = (0, 0);
        loop {
            let map = Map::sample_at(surface, x, y, spacing, std::mem::take(&mut given))?;
            let Some((mx, my, mismatch)) = map.unresolved_cell(surface, accept)? else { return Ok(map) };
            let finest = map.hx.max(map.hy);
            // A map no finer than the last: the node limit holds the spacing.
            if (map.cx, map.cy) == cells {
                return Err(MapError::Unresolved { x: mx, y: my, spacing: finest, mismatch });
            }
            cells = (map.cx, map.cy);
            spacing = 0.5 * finest;
        }
    }

    /// `spacing`, or coarser where the rectangle would need more than [`MAX_NODES`] nodes.
    fn spacing_within_limit(x: [f64; 2], y: [f64; 2], spacing: f64) -> f64 {
        let (w, h) = (x[1] - x[0], y[1] - y[0]);
        spacing.max((w.max(spacing) * h.max(spacing) / MAX_NODES).sqrt())
    }

    /// The first cell the surface is not resolved in, with its middle and by how much (mm)
    /// past `accept`. Taylor's bounds with the cell's curvature bounds say how far f(p) may
    /// lie from f(c) + ∇f(c)·(p − c): up to ½Λ|p − c|² above, ½Γ|p − c|² below. Along each
    /// edge, from either end, the other end must keep them (a step, whose slopes show no
    /// rise, does not; a kink's jump of slope makes Λ large enough); and the cell's middle
    /// must keep them from one corner at least (a bump between the nodes does not; across a
    /// kink the corner on the middle's side does).
    fn unresolved_cell<S: Surface>(
        &self,
        surface: &mut S,
        accept: f64,
    ) -> Result<Option<Unresolved>, (f64, f64, S::Error)> {
        let nx = if self.hx > 0.0 { self.cx + 1 } else { 1 };
        let ny = if self.hy > 0.0 { self.cy + 1 } else { 1 };
        let node = |i: usize, j: usize| {
            let (i, j) = (i.min(nx - 1), j.min(ny - 1));
            (self.x0 + i as f64 * self.hx, self.y0 + j as f64 * self.hy, self.nodes[j * nx + i])
        };
        for j in 0..self.cy {
            for i in 0..self.cx {
                let (lambda, gamma) = (self.lambda[j * self.cx + i], self.gamma[j * self.cx + i]);
                if !(lambda.is_finite() && gamma.is_finite()) {
                    continue;
                }
                // How far f at (px, py) lies outside the bounds from node `c`.
                let excess = |c: (f64, f64, Sample), px: f64, py: f64, z: f64| {
                    let (dx, dy) = (px - c.0, py - c.1);
                    let d2 = dx * dx + dy * dy;
                    let r = z - c.2.z - c.2.dzdx * dx - c.2.dzdy * dy;
                    // Rounding of the heights themselves is no feature.
                    let noise = 1e-12 * (1.0 + z.abs() + c.2.z.abs());
                    (r - 0.5 * lambda.max(0.0) * d2 - noise).max(-r - 0.5 * gamma * d2 - noise)
                };
                let corners = [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
                let mut worst = f64::NEG_INFINITY;
                for k in 0..4 {
                    let (a, b) = (corners[k], corners[(k + 1) % 4]);
                    worst = worst.max(excess(a, b.0, b.1, b.2.z)).max(excess(b, a.0, a.1, a.2.z));
                }
                let (mx, my) = (self.x0 + (i as f64 + 0.5) * self.hx, self.y0 + (j as f64 + 0.5) * self.hy);
                // Only its height: the middle's slopes take no part.
                let m = surface.height(mx, my).map_err(|e| (mx, my, e))?;
                let middle = corners.iter().map(|&c| excess(c, mx, my, m)).fold(f64::INFINITY, f64::min);
                worst = worst.max(middle);
                if worst > accept || worst.is_nan() {
                    return Ok(Some((mx, my, worst)));
                }
            }
        }
        Ok(None)
    }

    /// The map at `spacing` (coarser if that would exceed [`MAX_NODES`]), its nodes `given`
    /// where there is one per node.
    fn sample_at<S: Surface>(
        surface: &mut S,
        x: [f64; 2],
        y: [f64; 2],
        spacing: f64,
        given: Vec<Sample>,
    ) -> Result<Map, (f64, f64, S::Error)> {
        let [ax, ay] = Map::grid(x, y, spacing);
        let (cx, cy, hx, hy) = (ax.cells, ay.cells, ax.step, ay.step);
        let (nx, ny) = (ax.nodes(), ay.nodes());
        let nodes = if given.len() == nx * ny { given } else { Map::sample_nodes(surface, ax, ay)? };
        let heights = nodes.iter().fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], n| [lo.min(n.z), hi.max(n.z)]);
        let node = |i: usize, j: usize| nodes[j.min(ny - 1) * nx + i.min(nx - 1)];
        let mut up = Vec::with_capacity(cx * cy);
        let mut lo = Vec::with_capacity(cx * cy);
        for j in 0..cy {
            for i in 0..cx {
                let (u, l) = cell_curvature([node(i, j), node(i + 1, j), node(i, j + 1), node(i + 1, j + 1)], hx, hy);
                up.push(u);
                lo.push(l);
            }
        }
        // Between its corners a cell's curvature may exceed what its corners show: take the
        // extremes over the cell and its neighbours, widened by their spread.
        let mut lambda = vec![0.0; cx * cy];
        let mut gamma = vec![0.0; cx * cy];
        for j in 0..cy {
            for i in 0..cx {
                let (mut umax, mut umin, mut lmax, mut lmin) = (f64::MIN, f64::MAX, f64::MIN, f64::MAX);
                for jj in j.saturating_sub(1)..(j + 2).min(cy) {
                    for ii in i.saturating_sub(1)..(i + 2).min(cx) {
                        let (u, l) = (up[jj * cx + ii], lo[jj * cx + ii]);
                        (umax, umin, lmax, lmin) = (umax.max(u), umin.min(u), lmax.max(l), lmin.min(l));
                    }
                }
                let widened =
                    |extreme: f64, spread: f64| if spread.is_finite() { extreme + spread } else { f64::INFINITY };
                lambda[j * cx + i] = widened(umax, umax - umin);
                gamma[j * cx + i] = widened(-lmin, lmax - lmin).max(0.0);
            }
        }
        let levels = usize::BITS - cx.max(cy).leading_zeros();
        let blocks = (0..levels).map(|_| OnceCell::new()).collect();
        Ok(Map { x0: x[0], y0: y[0], hx, hy, cx, cy, lambda, gamma, blocks, heights, nodes })
    }

    /// The axes of the grid the map over [x0, x1] × [y0, y1] first samples at `spacing`
    /// (coarser if that would exceed [`MAX_NODES`]), before any cell is made finer.
    pub fn grid(x: [f64; 2], y: [f64; 2], spacing: f64) -> [GridAxis; 2] {
        let spacing = Map::spacing_within_limit(x, y, spacing);
        let axis = |[start, end]: [f64; 2]| {
            let len = end - start;
            // Clamped: with extents near f64::MAX the product above overflows and the count
            // with it.
            let n = (len / spacing).ceil();
            let cells = if n.is_nan() { 1 } else { n.clamp(1.0, MAX_NODES) as usize };
            GridAxis { start, step: len / cells as f64, cells }
        };
        [axis(x), axis(y)]
    }

    /// The samples at the nodes of the grid, row-major by y.
    fn sample_nodes<S: Surface>(
        surface: &mut S,
        ax: GridAxis,
        ay: GridAxis,
    ) -> Result<Vec<Sample>, (f64, f64, S::Error)> {
        let mut nodes = Vec::with_capacity(ax.nodes() * ay.nodes());
        for j in 0..ay.nodes() {
            for i in 0..ax.nodes() {
                let (px, py) = (ax.start + i as f64 * ax.step, ay.start + j as f64 * ay.step);
                nodes.push(surface.sample(px, py).map_err(|e| (px, py, e))?);
            }
        }
        Ok(nodes)
    }

    /// The lowest and highest surface heights at the map's nodes.
    pub fn heights(&self) -> [f64; 2] {
        self.heights
    }

    /// Λ and Γ over the blocks of 2^level cells (level 0: the cells themselves).
    fn level(&self, level: usize) -> (&[f64], &[f64]) {
        if level == 0 {
            return (&self.lambda, &self.gamma);
        }
        match self.blocks[level - 1].get() {
            Some(b) => (&b.lambda, &b.gamma),
            None => self.make_level(level),
        }
    }

    /// [`Map::level`] the first time it is asked for (kept out of the proofs' hot path).
    #[cold]
    #[inline(never)]
    fn make_level(&self, level: usize) -> (&[f64], &[f64]) {
        let b = self.blocks[level - 1].get_or_init(|| {
            // Each block is the four blocks of half its side that it is made of.
            let (lambda, gamma) = self.level(level - 1);
            let half = 1 << (level - 1);
            let (cx, cy) = (self.cx, self.cy);
            let mut out = Blocks { lambda: Vec::with_capacity(cx * cy), gamma: Vec::with_capacity(cx * cy) };
            for j in 0..cy {
                for i in 0..cx {
                    let (mut l, mut g) = (lambda[j * cx + i], gamma[j * cx + i]);
                    for (ii, jj) in [(i + half, j), (i, j + half), (i + half, j + half)] {
                        if ii < cx && jj < cy {
                            (l, g) = (l.max(lambda[jj * cx + ii]), g.max(gamma[jj * cx + ii]));
                        }
                    }
                    out.lambda.push(l);
                    out.gamma.push(g);
                }
            }
            out
        });
        (&b.lambda, &b.gamma)
    }

    /// The cells (i range, j range) meeting the box [x0, x1] × [y0, y1].
    fn cells_in(&self, bx: [f64; 2], by: [f64; 2]) -> ([usize; 2], [usize; 2]) {
        let span = |lo: f64, hi: f64, origin: f64, h: f64, n: usize| {
            if h <= 0.0 {
                return [0, 1];
            }
            // A cast truncates, which for the non-negative (and NaN, made 0) is the floor.
            let a = ((lo - origin) / h).max(0.0) as usize;
            let b = (((hi - origin) / h).max(0.0) as usize + 1).min(n);
            [a.min(b.saturating_sub(1)), b]
        };
        (span(bx[0], bx[1], self.x0, self.hx, self.cx), span(by[0], by[1], self.y0, self.hy, self.cy))
    }

    /// Λ and Γ over the cells meeting the box around the swept ball's footprint.
    fn curvature(&self, s: &Sweep) -> (f64, f64) {
        let r = s.r;
        let bx = [s.a.x.min(s.b.x) - r, s.a.x.max(s.b.x) + r];
        let by = [s.a.y.min(s.b.y) - r, s.a.y.max(s.b.y) + r];
        let ([i0, i1], [j0, j1]) = self.cells_in(bx, by);
        let (mut lambda, mut gamma) = (f64::MIN, 0.0f64);
        if i0 >= i1 || j0 >= j1 {
            return (lambda, gamma);
        }
        // Squares of the largest side that fits, overlapping at the far edges: the maximum
        // over them is the maximum over the cells.
        let level = (usize::BITS - 1 - (i1 - i0).min(j1 - j0).leading_zeros()) as usize;
        let side = 1 << level;
        let (lambdas, gammas) = self.level(level);
        // Blocks every `side` cells from the near edge, the last ending at the far edge.
        let mut j = j0;
        loop {
            let row = j.min(j1 - side) * self.cx;
            let mut i = i0;
            loop {
                let k = row + i.min(i1 - side);
                lambda = lambda.max(lambdas[k]);
                gamma = gamma.max(gammas[k]);
                if i + side >= i1 {
                    break;
                }
                i += side;
            }
            if j + side >= j1 {
                break;
            }
            j += side;
        }
        (lambda, gamma)
    }

    /// Λ (≥ the surface Hessian's eigenvalues) over the cells meeting the box around the
    /// swept ball's footprint (`f64::MIN` off the map).
    pub fn upper_curvature(&self, s: &Sweep) -> f64 {
        self.curvature(s).0
    }

    /// Whether a ball placed by a contact point (tangent to the surface there) is proved
    /// clear of it: the surface bends up less than the ball over its whole footprint.
    pub fn proves_clear(&self, ball: &Sweep) -> bool {
        self.curvature(ball).0 * ball.r < 1.0
    }

    /// A bound on how far the move `m` dips below the drop-cutter height, given bounds on how
    /// far its ends are below it; `None` where the curvature gives none (RΛ ≥ 1).
    pub fn move_bound(&self, m: &Sweep, ends: [f64; 2]) -> Option<f64> {
        let (lambda, gamma) = self.curvature(m);
        if lambda.max(0.0) * m.r >= 1.0 {
            return None;
        }
        let len2 = m.horizontal().norm_squared();
        Some(ends[0].max(ends[1]) + gamma * len2 / 8.0)
    }

    /// The deepest cut of the ball `ball` into the surface, to within `tol`: the search
    /// starts from `seeds` (surface points known to be near the answer, such as contact points).
    /// `goal` says when to stop; `budget` is the surface samples it may take (decreased by
    /// those taken).
    pub fn deepest<S: Surface>(
        &self,
        surface: &mut S,
        ball: &Sweep,
        seeds: &[Point3<f64>],
        goal: Goal,
        budget: &mut u64,
    ) -> Result<Cut, (f64, f64, S::Error)> {
        let mut search = Search { ball, goal, best: None, queue: BinaryHeap::new(), budget };
        for s in seeds {
            search.offer(Vector2::new(s.x, s.y), s.z);
        }
        let r = ball.r;
        let bx = [ball.a.x.min(ball.b.x) - r, ball.a.x.max(ball.b.x) + r];
        let by = [ball.a.y.min(ball.b.y) - r, ball.a.y.max(ball.b.y) + r];
        let ([i0, i1], [j0, j1]) = self.cells_in(bx, by);
        for j in j0..j1 {
            for i in i0..i1 {
                let (ax, ay) = (0.5 * self.hx, 0.5 * self.hy);
                let q = Vector2::new(self.x0 + i as f64 * self.hx + ax, self.y0 + j as f64 * self.hy + ay);
                search.visit(surface, Square { q, ax, ay, lambda: self.lambda[j * self.cx + i] })?;
            }
        }
        while let Some(sq) = search.next() {
            for child in sq.split() {
                search.visit(surface, child)?;
            }
        }
        let complete = !search.out_of_budget();
        let cut = |(depth, at)| Cut { depth, at, complete };
        Ok(search.best.map_or(cut((f64::NEG_INFINITY, ball.a)), cut))
    }
}

/// The extremes of a cell's Hessian's eigenvalues as its corners' slopes show them: the
/// Hessian averaged over the cell, and each edge's own second derivative along it. Corners are
/// (0,0), (1,0), (0,1), (1,1); a cell of zero width shows nothing across it.
fn cell_curvature(c: [Sample; 4], hx: f64, hy: f64) -> (f64, f64) {
    let mut along = Vec::with_capacity(4);
    let (mut a, mut b, mut d) = (0.0, 0.0, 0.0);
    if hx > 0.0 {
        let (e1, e2) = ((c[1].dzdx - c[0].dzdx) / hx, (c[3].dzdx - c[2].dzdx) / hx);
        along.extend([e1, e2]);
        a = 0.5 * (e1 + e2);
    }
    if hy > 0.0 {
        let (e1, e2) = ((c[2].dzdy - c[0].dzdy) / hy, (c[3].dzdy - c[1].dzdy) / hy);
        along.extend([e1, e2]);
        d = 0.5 * (e1 + e2);
    }
    if hx > 0.0 && hy > 0.0 {
        let fxy = 0.5 * ((c[2].dzdx - c[0].dzdx) + (c[3].dzdx - c[1].dzdx)) / hy;
        let fyx = 0.5 * ((c[1].dzdy - c[0].dzdy) + (c[3].dzdy - c[2].dzdy)) / hx;
        b = 0.5 * (fxy + fyx);
    }
    let mid = 0.5 * (a + d);
    let half = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    let up = along.iter().fold(mid + half, |m, &v| m.max(v));
    let lo = along.iter().fold(mid - half, |m, &v| m.min(v));
    // A slope that is not a number (a kink's far side) proves nothing: assume the worst.
    if up.is_nan() || lo.is_nan() {
        return (f64::INFINITY, f64::NEG_INFINITY);
    }
    (up, lo)
}

/// A rectangle of the search: centre, half sides, and the curvature bound over it.
#[derive(Clone, Copy, Debug)]
struct Square {
    q: Vector2<f64>,
    ax: f64,
    ay: f64,
    lambda: f64,
}

impl Square {
    fn split(&self) -> impl Iterator<Item = Square> + '_ {
        let (ax, ay) = (0.5 * self.ax, 0.5 * self.ay);
        let xs: &[f64] = if self.ax > 0.0 { &[-1.0, 1.0] } else { &[0.0] };
        let ys: &[f64] = if self.ay > 0.0 { &[-1.0, 1.0] } else { &[0.0] };
        xs.iter().flat_map(move |&sx| {
            ys.iter().map(move |&sy| Square { q: self.q + Vector2::new(sx * ax, sy * ay), ax, ay, lambda: self.lambda })
        })
    }

    fn rho(&self) -> f64 {
        (self.ax * self.ax + self.ay * self.ay).sqrt()
    }
}

struct Search<'m> {
    ball: &'m Sweep,
    goal: Goal,
    /// Surface samples left.
    budget: &'m mut u64,
    /// The deepest cut sampled so far, and where.
    best: Option<(f64, Point3<f64>)>,
    /// Squares still open, highest bound first.
    queue: BinaryHeap<Open>,
}

/// An open square and its bound, ordered by the bound.
struct Open(f64, Square);

impl PartialEq for Open {
    fn eq(&self, other: &Open) -> bool {
        self.0.total_cmp(&other.0).is_eq()
    }
}

impl Eq for Open {}

impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Open) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Open {
    fn cmp(&self, other: &Open) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl Search<'_> {
    fn offer(&mut self, p: Vector2<f64>, z: f64) -> Option<Low> {
        let low = self.ball.low(p)?;
        let depth = z - low.z;
        if self.best.is_none_or(|(b, _)| depth > b) {
            self.best = Some((depth, Point3::new(p.x, p.y, z)));
        }
        Some(low)
    }

    /// The bound a square must beat to be searched further.
    fn floor(&self) -> f64 {
        match self.goal {
            Goal::Within(tol) => self.best.map_or(f64::NEG_INFINITY, |(b, _)| b) + tol,
            Goal::Deeper(threshold) => threshold,
        }
    }

    /// Whether the goal is reached: a sample deeper than the threshold.
    fn found(&self) -> bool {
        matches!((self.goal, self.best), (Goal::Deeper(t), Some((b, _))) if b > t)
    }

    fn out_of_budget(&self) -> bool {
        *self.budget == 0
    }

    /// Samples the square's centre and keeps the square if the surface in it could cut
    /// deeper than the best sample by more than the tolerance.
    fn visit<S: Surface>(&mut self, surface: &mut S, sq: Square) -> Result<(), (f64, f64, S::Error)> {
        let rho = sq.rho();
        if self.ball.distance(sq.q) - rho >= self.ball.r || self.out_of_budget() {
            return Ok(());
        }
        *self.budget -= 1;
        let s = surface.sample(sq.q.x, sq.q.y).map_err(|e| (sq.q.x, sq.q.y, e))?;
        let slope = Vector2::new(s.dzdx, s.dzdy);
        let low = self.offer(sq.q, s.z);
        let up = sq.lambda.max(0.0);
        // Anywhere in the square: the surface at most its tangent plane plus the curvature
        // term, the ball at least its lowest over the square.
        let mut bound = s.z + slope.norm() * rho + 0.5 * up * rho * rho - self.ball.low_bound(sq.q, rho);
        if let Some(low) = low.filter(|l| l.root > 1e-9 * self.ball.r) {
            // Taylor from the centre for both: the gap f − z_low grows at most by its slope
            // and by the surface's curvature less the ball's convexity.
            let g = s.z - low.z;
            let a = (slope - low.grad).norm();
            let mu = sq.lambda - self.ball.convexity();
            let t = if mu < 0.0 { (a / -mu).min(rho) } else { rho };
            bound = bound.min(g + a * t + 0.5 * mu * t * t);
        }
        if (bound.is_nan() || bound > self.floor()) && rho > SMALLEST * self.ball.r {
            self.queue.push(Open(if bound.is_nan() { f64::INFINITY } else { bound }, sq));
        }
        Ok(())
    }

    /// The open square with the highest bound, while it can still beat the best.
    fn next(&mut self) -> Option<Square> {
        if self.found() || self.out_of_budget() {
            return None;
        }
        let Open(bound, sq) = self.queue.pop()?;
        // The rest are bounded lower still: none can beat the best.
        (bound > self.floor()).then_some(sq)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map of `cx` × `cy` cells of 0.1 mm with made-up curvature bounds.
    fn map(cx: usize, cy: usize, seed: u64) -> Map {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let lambda = (0..cx * cy).map(|_| next()).collect();
        let gamma = (0..cx * cy).map(|_| next().abs()).collect();
        let levels = usize::BITS - cx.max(cy).leading_zeros();
        let blocks = (0..levels).map(|_| OnceCell::new()).collect();
        Map {
            x0: 0.0,
            y0: 0.0,
            hx: 0.1,
            hy: 0.1,
            cx,
            cy,
            lambda,
            gamma,
            blocks,
            heights: [0.0, 0.0],
            nodes: Vec::new(),
        }
    }

    /// Λ and Γ read cell by cell over the box, as the proofs define them.
    fn every_cell(m: &Map, s: &Sweep) -> (f64, f64) {
        let r = s.r;
        let bx = [s.a.x.min(s.b.x) - r, s.a.x.max(s.b.x) + r];
        let by = [s.a.y.min(s.b.y) - r, s.a.y.max(s.b.y) + r];
        let ([i0, i1], [j0, j1]) = m.cells_in(bx, by);
        let (mut lambda, mut gamma) = (f64::MIN, 0.0f64);
        for j in j0..j1 {
            for i in i0..i1 {
                lambda = lambda.max(m.lambda[j * m.cx + i]);
                gamma = gamma.max(m.gamma[j * m.cx + i]);
            }
        }
        (lambda, gamma)
    }

    #[test]
    fn curvature_over_blocks_is_the_maximum_over_every_cell_of_the_footprint() {
        for (cx, cy) in [(1, 1), (1, 37), (50, 3), (64, 64), (97, 61)] {
            let m = map(cx, cy, (cx * 1000 + cy) as u64);
            for k in 0..400 {
                let t = k as f64;
                // Balls and moves of every size, partly or wholly off the map.
                let a = Point3::new((t * 0.37) % 11.0 - 1.0, (t * 0.53) % 8.0 - 1.0, 0.0);
                let b = a + nalgebra::Vector3::new((t * 0.11) % 3.0 - 1.5, (t * 0.07) % 2.0 - 1.0, 0.5);
                let r = 0.05 + (t * 0.013) % 4.0;
                let sweep = Sweep { a, b: if k % 3 == 0 { a } else { b }, r };
                assert_eq!(m.curvature(&sweep), every_cell(&m, &sweep), "{cx}×{cy} map, sweep {sweep:?}");
            }
        }
    }
}
