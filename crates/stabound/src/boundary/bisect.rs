//! The general boundary engine: any plane of two of `(alpha, beta, delta, d)`.
//!
//! Method: a coarse grid of point tests (rayon), marching squares to find and order the grid
//! edges the boundary crosses into closed polylines (Lorensen and Cline, "Marching cubes",
//! SIGGRAPH 1987, in its 2-D form, saddles resolved by a test at the cell centre), bisection
//! of each crossing edge to `tol`, then adaptive refinement: the midpoint of every chord is
//! moved onto the boundary by bisection along the chord's normal, recursively, until the
//! boundary is within `tol` of the chord. Only point tests are used (Schur-Cohn on the unit
//! circle), so this engine is independent of the D-decomposition of [`super::exact()`].
//!
//! At `alpha = 0` exactly the root `z = 1` is always present; the point is judged by the
//! other roots, `q(z) / (z - 1)` (the limit `alpha -> 0+`, `docs/MODEL.md` section 4).
//!
//! [`bisect`] and [`bisect_alpha_beta`] run the same engine on a [`Loop`] with elements
//! (the model document, docs/MODEL.md, section 8), its point test that of [`Checker`]
//! on the loop's general polynomial; on a `delta` or `d` axis the loop is rebuilt at every
//! point with that plant.

use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

use super::exact::orient_and_close;
use super::{Boundary, Piece, Vertex, check_tol};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::geometry::polygon_area;
use crate::params::{MAX_DELAY, MAX_DELTA, Normalized, Plant, Wall};
use crate::poly::deflate_linear;
use crate::poly::{MAX_COEFFS, PaperPoly};
use crate::stability::Checker;
use crate::stability::schur_cohn;

/// The rightmost stable wall `(alpha, beta)` of the paper's loop on a plant, by the
/// `alpha_max` search with its default options: the seed of a grid whose stable region is
/// smaller than its cells. The `alpha_max` layer implements it (`amax/mod.rs`): that layer
/// falls back on these engines where its direct search confirms no point, so the engines
/// take the search through this interface rather than import it.
pub(crate) trait RightmostWall {
    /// `(alpha_max, beta_at_max)` of the paper's loop on this plant.
    fn rightmost_wall(&self) -> Result<(f64, f64)>;
}

/// One of the four normalized parameters, as a plane axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Axis {
    /// Stiffness `alpha`.
    Alpha,
    /// Virtual damping `beta`.
    Beta,
    /// Physical damping `delta`.
    Delta,
    /// Delay factor `d`.
    D,
}

impl Axis {
    /// The parameter's name.
    pub fn name(self) -> &'static str {
        match self {
            Axis::Alpha => "alpha",
            Axis::Beta => "beta",
            Axis::Delta => "delta",
            Axis::D => "d",
        }
    }

    fn set(self, p: &mut Normalized, v: f64) {
        match self {
            Axis::Alpha => p.alpha = v,
            Axis::Beta => p.beta = v,
            Axis::Delta => p.delta = v,
            Axis::D => p.d = v,
        }
    }

    /// Whether the engine may choose this axis' range itself (wall parameters only: the
    /// stable region is bounded in `alpha` and `beta`, not in `delta` or `d`).
    fn auto(self) -> bool {
        matches!(self, Axis::Alpha | Axis::Beta)
    }
}

/// A parameter plane: two axes, the other two parameters fixed at their values in `at`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Plane {
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// The fixed parameters (the values of `x` and `y` in it are ignored).
    pub at: Normalized,
}

/// Options of [`bisect`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BisectOptions {
    /// Accuracy of every point and largest deviation of the polyline from the boundary.
    pub tol: f64,
    /// Cells per axis of the coarse grid (8 to 4096).
    pub grid: usize,
    /// Range of the horizontal axis; `None` (only for `alpha` and `beta`) lets the engine find
    /// the stable region by growing and shrinking a box.
    pub x_range: Option<(f64, f64)>,
    /// Range of the vertical axis, as `x_range`.
    pub y_range: Option<(f64, f64)>,
}

/// The most work the coarse grid may grow to, in units of one operation of the point tests
/// (grid points times the squared degree of the characteristic polynomial): 3e9 is a few
/// seconds on two cores, the default 96 x 96 grid at d = 500. The grid is refined (doubled)
/// only while a finer one fits.
const MAX_GRID_WORK: f64 = 3e9;

/// The most work all point tests of one contour may take, in the units of
/// [`MAX_GRID_WORK`]: some 20 seconds on two cores. Beyond it [`bisect`] stops with
/// [`Error::InvalidRequest`] instead of running for many minutes (a contour at `d` near 500
/// needs a quarter of a million operations per test).
const MAX_TEST_WORK: u64 = 30_000_000_000;

impl Default for BisectOptions {
    fn default() -> Self {
        Self {
            tol: super::DEFAULT_TOL,
            grid: 96,
            x_range: None,
            y_range: None,
        }
    }
}

/// The boundary of the stable region in a plane: closed polylines (last point = first),
/// counterclockwise around stable parts, largest area first.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Contour {
    /// The plane.
    pub plane: Plane,
    /// The final ranges used.
    pub x_range: (f64, f64),
    /// See `x_range`.
    pub y_range: (f64, f64),
    /// Closed polylines; each vertex's piece is [`Piece::Bisection`], or [`Piece::Clipped`]
    /// on the edge of a requested range.
    pub loops: Vec<Vec<Vertex>>,
}

/// The point test of a loop with elements.
enum LoopTest {
    /// The plant is fixed (the `(alpha, beta)` plane): one checker for every point.
    Fixed(Box<Checker>),
    /// A `delta` or `d` axis: the loop is rebuilt with each point's plant.
    PerPoint(Loop),
}

struct Tester {
    plane: Plane,
    /// Prebuilt when the plant is fixed (the `(alpha, beta)` plane).
    poly: Option<PaperPoly>,
    /// A loop with elements; `None` for the paper's loop.
    elements: Option<LoopTest>,
    x_box: Option<(f64, f64)>,
    y_box: Option<(f64, f64)>,
    /// Diagonal of a coarse grid cell: the farthest a refinement search looks.
    cell: f64,
    /// Work of the point tests so far (the squared length of each polynomial tested),
    /// against [`MAX_TEST_WORK`].
    work: AtomicU64,
}

impl Tester {
    /// An error once the point tests have used up [`MAX_TEST_WORK`].
    fn within_budget(&self, at: &Normalized) -> Result<()> {
        if self.work.load(Ordering::Relaxed) <= MAX_TEST_WORK {
            return Ok(());
        }
        Err(Error::InvalidRequest(format!(
            "the bisection contour at delay factor d = {} would take more than about 20 seconds of point tests (each costs about d^2 operations); use a larger tolerance, smaller ranges, a smaller d, or the exact engine in the alpha-beta plane",
            at.d()
        )))
    }

    /// Is `(x, y)` stable (and inside any user box)?
    fn stable(&self, x: f64, y: f64) -> bool {
        if crate::cancel::stopped() {
            return false;
        }
        let inside = |r: Option<(f64, f64)>, v: f64| r.is_none_or(|(lo, hi)| v >= lo && v <= hi);
        if !(inside(self.x_box, x) && inside(self.y_box, y)) {
            return false;
        }
        let mut p = self.plane.at;
        self.plane.x.set(&mut p, x);
        self.plane.y.set(&mut p, y);
        if let Some(e) = &self.elements {
            return self.loop_stable(e, &p);
        }
        let built;
        let poly = match &self.poly {
            Some(cp) => cp,
            None => {
                // outside the model's domain counts as not stable
                let Ok(plant) = Plant::new(p.delta(), p.d()) else {
                    return false;
                };
                built = PaperPoly::new(&plant);
                &built
            }
        };
        let mut buf = [0.0; MAX_COEFFS];
        let q = poly.coefficients_into(
            &Wall {
                alpha: p.alpha(),
                beta: p.beta(),
            },
            &mut buf,
        );
        let units = (q.len() * q.len()) as u64;
        if self.work.fetch_add(units, Ordering::Relaxed) + units > MAX_TEST_WORK {
            // over budget: the remaining tests are skipped and `bisect` reports the error
            return false;
        }
        // Radius exactly 1: the boundary is where a root crosses the circle; bisection then
        // lands on it to rounding instead of a margin away.
        if p.alpha() == 0.0 {
            // exactly zero on purpose: only there is z = 1 a root for every beta
            let mut out = [0.0; MAX_COEFFS];
            schur_cohn(deflate_linear(q, 1.0, &mut out), 1.0).stable
        } else {
            schur_cohn(q, 1.0).stable
        }
    }
}

impl Tester {
    /// The loop's point test at `p`: its polynomial at radius exactly 1 (as for the paper's
    /// loop), a plant outside the model's domain or a loop its elements refuse counting as
    /// not stable.
    fn loop_stable(&self, e: &LoopTest, p: &Normalized) -> bool {
        let wall = Wall {
            alpha: p.alpha,
            beta: p.beta,
        };
        let test = |c: &Checker| {
            let units = ((c.degree() + 1) * (c.degree() + 1)) as u64;
            if self.work.fetch_add(units, Ordering::Relaxed) + units > MAX_TEST_WORK {
                return false;
            }
            c.unit_circle_stable(&wall)
        };
        match e {
            LoopTest::Fixed(c) => test(c),
            LoopTest::PerPoint(lp) => {
                let Ok(plant) = Plant::new(p.delta, p.d) else {
                    return false;
                };
                let Ok(lp) = lp.with_plant(plant) else {
                    return false;
                };
                Checker::new(lp, crate::stability::Options::default()).is_ok_and(|c| test(&c))
            }
        }
    }
}

fn check_range(name: &'static str, r: Option<(f64, f64)>) -> Result<()> {
    if let Some((lo, hi)) = r
        && !(lo.is_finite() && hi.is_finite() && hi > lo)
    {
        return Err(Error::InvalidRequest(format!(
            "the {name} range [{lo}, {hi}] must be finite with the upper end above the lower"
        )));
    }
    Ok(())
}

/// The boundary of the stable region of the loop `lp` in `plane` (grid, bisection and
/// refinement; see the module documentation). The loop's elements are kept; its plant is the
/// plane's: the fixed `delta` and `d` of `plane.at`, or each point's on a `delta` or `d` axis
/// (where a point whose plant the elements refuse, such as a handle-side damping above
/// `delta`, counts as not stable). For the paper's loop pass the plane's plant
/// ([`Normalized::plant`]).
///
/// ```
/// use stabound::boundary::{Axis, BisectOptions, Plane, bisect};
/// use stabound::elements::{Actuator, Loop};
/// use stabound::params::{Normalized, Plant};
///
/// let plane = Plane { x: Axis::Delta, y: Axis::Beta, at: Normalized::new(0.05, 0.0, 0.0, 1.0)? };
/// let opts = BisectOptions { tol: 1e-5, grid: 24, x_range: Some((0.0, 1.0)), y_range: None };
/// let bare = bisect(plane.at.plant(), &plane, &opts)?;
/// let lagged = Loop::new(Plant::new(0.1, 1.0)?).with_actuator(Actuator::new(0.5)?)?;
/// let c = bisect(&lagged, &plane, &opts)?;
/// assert!(!bare.loops.is_empty() && !c.loops.is_empty());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// Invalid `tol` or `grid`, a missing range for a `delta` or `d` axis, two equal axes, or no
/// stable point found; the loop's own errors at the fixed plant.
pub fn bisect(lp: impl Into<Loop>, plane: &Plane, options: &BisectOptions) -> Result<Contour> {
    let lp = lp.into();
    bisect_with(plane, options, (!lp.is_paper()).then_some(&lp))
}

fn bisect_with(plane: &Plane, options: &BisectOptions, lp: Option<&Loop>) -> Result<Contour> {
    let tol = check_tol(options.tol)?;
    if !(8..=4096).contains(&options.grid) {
        return Err(Error::InvalidRequest(format!(
            "grid = {} cells per axis; accepted range is 8 to 4096",
            options.grid
        )));
    }
    if plane.x == plane.y {
        return Err(Error::InvalidRequest(format!(
            "a plane needs two different axes, got {} twice",
            plane.x.name()
        )));
    }
    check_range(plane.x.name(), options.x_range)?;
    check_range(plane.y.name(), options.y_range)?;
    for (axis, r) in [(plane.x, options.x_range), (plane.y, options.y_range)] {
        if r.is_none() && !axis.auto() {
            return Err(Error::InvalidRequest(format!(
                "give a range for the {} axis (only alpha and beta ranges are found automatically)",
                axis.name()
            )));
        }
    }
    // the fixed parameters must be valid
    let at = plane.at;
    for axis in [Axis::Alpha, Axis::Beta, Axis::Delta, Axis::D] {
        if axis != plane.x && axis != plane.y {
            let (v, lo, hi) = match axis {
                Axis::Alpha => (at.alpha(), f64::MIN, f64::MAX),
                Axis::Beta => (at.beta(), f64::MIN, f64::MAX),
                Axis::Delta => (at.delta(), 0.0, MAX_DELTA),
                Axis::D => (at.d(), 0.0, MAX_DELAY),
            };
            crate::params::in_range(axis.name(), v, lo, hi)?;
        }
    }
    let fixed_plant =
        !matches!(plane.x, Axis::Delta | Axis::D) && !matches!(plane.y, Axis::Delta | Axis::D);
    let elements = match lp {
        None => None,
        Some(lp) if fixed_plant => {
            let lp = lp.with_plant(Plant::new(at.delta, at.d)?)?;
            Some(LoopTest::Fixed(Box::new(Checker::new(
                lp,
                crate::stability::Options::default(),
            )?)))
        }
        Some(lp) => Some(LoopTest::PerPoint(*lp)),
    };
    let tester = Tester {
        plane: *plane,
        poly: if fixed_plant && elements.is_none() {
            Some(PaperPoly::new(&Plant::new(at.delta, at.d)?))
        } else {
            None
        },
        elements,
        x_box: options.x_range,
        y_box: options.y_range,
        cell: 0.0,
        work: AtomicU64::new(0),
    };
    let mut tester = tester;

    let s = 1.0 + at.delta();
    let initial = |axis: Axis| match axis {
        Axis::Alpha => (-0.05 * s, s),
        _ => (-at.delta() - 0.25 * s, at.delta() + s),
    };
    let mut xr = options.x_range.unwrap_or_else(|| initial(plane.x));
    let mut yr = options.y_range.unwrap_or_else(|| initial(plane.y));
    let (auto_x, auto_y) = (options.x_range.is_none(), options.y_range.is_none());
    let mut grid = options.grid;
    let mut values;
    let mut attempts = 0;
    let mut seeded = false;
    // the characteristic polynomial's degree, bounding the cost of one point test (Schur-Cohn
    // takes about degree^2 operations)
    let d_max = match (plane.x, plane.y) {
        (Axis::D, _) => xr.1,
        (_, Axis::D) => yr.1,
        _ => at.d(),
    };
    // the elements add their states to the degree
    let extra = lp.map_or(0.0, |lp| (lp.degree() - lp.plant().degree()) as f64);
    let degree = d_max.max(0.0).ceil() + 3.0 + extra;
    loop {
        attempts += 1;
        values = eval_grid(&tester, xr, yr, grid);
        let n = grid;
        let mut bbox: Option<(usize, usize, usize, usize)> = None;
        for i in 0..=n {
            for j in 0..=n {
                if values[i * (n + 1) + j] {
                    bbox = Some(match bbox {
                        None => (i, i, j, j),
                        Some((a, b, c, d)) => (a.min(i), b.max(i), c.min(j), d.max(j)),
                    });
                }
            }
        }
        if attempts > 40 {
            break;
        }
        let Some((i0, i1, j0, j1)) = bbox else {
            // A stable region too small for the grid (alpha_max = 6e-6 at d = 500): seed the
            // box with the rightmost stable point, found by the alpha_max search, and let the
            // growing and shrinking below fit it.
            if !seeded
                && lp.is_none()
                && auto_x
                && auto_y
                && (plane.x, plane.y) == (Axis::Alpha, Axis::Beta)
            {
                seeded = true;
                let plant = Plant::new(at.delta(), at.d())?;
                if let Ok((a, beta_at_max)) = plant.rightmost_wall()
                    && a > 0.0
                {
                    xr = (-0.05 * a, 1.05 * a);
                    yr = (beta_at_max - 2.0 * a, beta_at_max + 2.0 * a);
                    continue;
                }
            }
            let next = 2 * grid + 1;
            let work = (next * next) as f64 * degree * degree;
            if grid < 1536 && attempts < 40 && work <= MAX_GRID_WORK {
                grid *= 2;
                continue;
            }
            if work > MAX_GRID_WORK {
                return Err(Error::InvalidRequest(format!(
                    "no stable point found in {} [{}, {}] x {} [{}, {}] on a {grid} x {grid} grid, and a finer grid would take too long at delay factor {}: any stable region there is below the grid's resolution; give ranges around it",
                    plane.x.name(),
                    xr.0,
                    xr.1,
                    plane.y.name(),
                    yr.0,
                    yr.1,
                    degree - 3.0
                )));
            }
            return Err(Error::Numerical(format!(
                "no stable point found in {} [{}, {}] x {} [{}, {}]; give other ranges",
                plane.x.name(),
                xr.0,
                xr.1,
                plane.y.name(),
                yr.0,
                yr.1
            )));
        };
        let mut changed = false;
        let grow = |r: &mut (f64, f64), lo_hit: bool, hi_hit: bool| {
            let span = r.1 - r.0;
            if lo_hit {
                r.0 -= span;
            }
            if hi_hit {
                r.1 += span;
            }
            lo_hit || hi_hit
        };
        if auto_x {
            changed |= grow(&mut xr, i0 == 0, i1 == n);
        }
        if auto_y {
            changed |= grow(&mut yr, j0 == 0, j1 == n);
        }
        if changed {
            continue;
        }
        // zoom in when the region covers a small part of the box
        let shrink = |r: &mut (f64, f64), a: usize, b: usize| {
            if (b - a) * 3 < n {
                let h = (r.1 - r.0) / n as f64;
                let (lo, hi) = (r.0 + h * (a as f64 - 2.0), r.0 + h * (b as f64 + 2.0));
                *r = (lo, hi);
                true
            } else {
                false
            }
        };
        if auto_x {
            changed |= shrink(&mut xr, i0, i1);
        }
        if auto_y {
            changed |= shrink(&mut yr, j0, j1);
        }
        if !changed {
            break;
        }
    }
    crate::cancel::poll()?;
    tester.within_budget(&at)?;

    tester.cell = (xr.1 - xr.0).hypot(yr.1 - yr.0) / grid as f64;
    let coarse = march(&tester, &values, xr, yr, grid, tol);
    // Counterclockwise: the stable region on the left (outer boundaries; the refinement
    // relies on it).
    let mut loops: Vec<Vec<Vertex>> = coarse
        .into_iter()
        .map(|mut lp| {
            let xy: Vec<(f64, f64)> = lp.iter().map(|p| (p.x, p.y)).collect();
            if polygon_area(&xy) < 0.0 {
                lp.reverse();
            }
            let mut lp = refine_loop(&tester, lp, tol, options.x_range, options.y_range);
            if let Some(&p0) = lp.first() {
                lp.push(p0);
            }
            lp
        })
        .collect();
    let area =
        |l: &Vec<Vertex>| polygon_area(&l.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>()).abs();
    loops.sort_by(|a, b| area(b).total_cmp(&area(a)));
    crate::cancel::poll()?;
    tester.within_budget(&at)?;
    Ok(Contour {
        plane: *plane,
        x_range: xr,
        y_range: yr,
        loops,
    })
}

/// The `(alpha, beta)` boundary of the loop `lp` (a [`Plant`] for the paper's loop, at its
/// own plant) by the bisection engine: the largest loop of [`bisect`], as a [`Boundary`]
/// (pieces [`Piece::Bisection`], or [`Piece::Clipped`] on a requested range's edge),
/// counterclockwise from its lowest point; the independent check of [`super::exact()`].
///
/// ```
/// use stabound::boundary::{BisectOptions, bisect_alpha_beta};
/// use stabound::elements::{Hand, Loop};
/// use stabound::params::Plant;
///
/// let lp = Loop::new(Plant::new(0.2, 1.0)?).with_hand(Hand::new(0.5, 0.1, 0.01)?)?;
/// let b = bisect_alpha_beta(&lp, &BisectOptions { tol: 1e-6, ..BisectOptions::default() })?;
/// // walls of negative stiffness down to -kappa_h are stable
/// assert!(b.points.iter().any(|p| p.x < -0.009));
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn bisect_alpha_beta(lp: impl Into<Loop>, options: &BisectOptions) -> Result<Boundary> {
    let lp = lp.into();
    alpha_beta(lp.plant(), options, (!lp.is_paper()).then_some(&lp))
}

fn alpha_beta(plant: &Plant, options: &BisectOptions, lp: Option<&Loop>) -> Result<Boundary> {
    let plane = Plane {
        x: Axis::Alpha,
        y: Axis::Beta,
        at: Normalized {
            alpha: 0.0,
            beta: 0.0,
            delta: plant.delta(),
            d: plant.d(),
        },
    };
    let c = bisect_with(&plane, options, lp)?;
    let lp = c.loops.into_iter().next().unwrap_or_default();
    let mut points: Vec<Vertex> = lp[..lp.len().saturating_sub(1)].to_vec();
    orient_and_close(&mut points, options.tol, 0.0);
    Ok(Boundary {
        delta: plant.delta(),
        d: plant.d(),
        tol: options.tol,
        points,
        fallback: None,
    })
}

fn coord(r: (f64, f64), n: usize, i: usize) -> f64 {
    if i == n {
        r.1
    } else {
        r.0 + (r.1 - r.0) * i as f64 / n as f64
    }
}

/// Point tests on the `(n + 1) x (n + 1)` nodes, row-major in `x`, in parallel.
fn eval_grid(t: &Tester, xr: (f64, f64), yr: (f64, f64), n: usize) -> Vec<bool> {
    (0..(n + 1) * (n + 1))
        .into_par_iter()
        .map(|k| t.stable(coord(xr, n, k / (n + 1)), coord(yr, n, k % (n + 1))))
        .collect()
}

/// Marching squares on the grid padded with a ring of unstable nodes (placed on the box
/// edge, so a region cut by a requested range closes along that edge), then bisection of
/// each crossing edge. Returns the coarse closed loops (without repeated first point).
fn march(
    t: &Tester,
    values: &[bool],
    xr: (f64, f64),
    yr: (f64, f64),
    n: usize,
    tol: f64,
) -> Vec<Vec<Vertex>> {
    let w = n + 3; // padded nodes per axis
    let val = |i: usize, j: usize| -> bool {
        if i == 0 || j == 0 || i == n + 2 || j == n + 2 {
            false
        } else {
            values[(i - 1) * (n + 1) + (j - 1)]
        }
    };
    let pos = |i: usize, j: usize| -> (f64, f64) {
        let ci = i.clamp(1, n + 1) - 1;
        let cj = j.clamp(1, n + 1) - 1;
        (coord(xr, n, ci), coord(yr, n, cj))
    };
    let h_id = |i: usize, j: usize| 2 * (i * w + j);
    let v_id = |i: usize, j: usize| 2 * (i * w + j) + 1;
    const NONE: u32 = u32::MAX;
    let mut adj: Vec<[u32; 2]> = vec![[NONE, NONE]; 2 * w * w];
    let mut link = |a: usize, b: usize| {
        for (x, y) in [(a, b), (b, a)] {
            let slot = &mut adj[x];
            if slot[0] == NONE {
                slot[0] = y as u32;
            } else {
                slot[1] = y as u32;
            }
        }
    };
    for i in 0..w - 1 {
        for j in 0..w - 1 {
            let c = [val(i, j), val(i + 1, j), val(i + 1, j + 1), val(i, j + 1)];
            let e = [h_id(i, j), v_id(i + 1, j), h_id(i, j + 1), v_id(i, j)];
            let cross: Vec<usize> = (0..4).filter(|&k| c[k] != c[(k + 1) % 4]).collect();
            match cross.len() {
                2 => link(e[cross[0]], e[cross[1]]),
                4 => {
                    let real = i >= 1 && j >= 1 && i < n + 1 && j < n + 1;
                    let centre = real && {
                        let (x0, y0) = pos(i, j);
                        let (x1, y1) = pos(i + 1, j + 1);
                        t.stable(0.5 * (x0 + x1), 0.5 * (y0 + y1))
                    };
                    // stable diagonal joined through a stable centre: cut off the unstable
                    // corners; otherwise cut off the stable ones.
                    if centre == c[0] {
                        link(e[0], e[1]);
                        link(e[2], e[3]);
                    } else {
                        link(e[3], e[0]);
                        link(e[1], e[2]);
                    }
                }
                _ => {}
            }
        }
    }
    // walk loops of edge ids
    let mut seen = vec![false; adj.len()];
    let mut loops_ids: Vec<Vec<usize>> = Vec::new();
    for start in 0..adj.len() {
        if seen[start] || adj[start][0] == NONE {
            continue;
        }
        let mut ids = vec![start];
        seen[start] = true;
        let (mut prev, mut cur) = (start, adj[start][0] as usize);
        while cur != start && !seen[cur] {
            seen[cur] = true;
            ids.push(cur);
            let [a, b] = adj[cur];
            let next = if a as usize == prev { b } else { a };
            if next == NONE {
                break;
            }
            prev = cur;
            cur = next as usize;
        }
        loops_ids.push(ids);
    }
    // edge id -> point, bisected in parallel (order kept)
    let edge_point = |id: usize| -> Vertex {
        let node = id / 2;
        let (i, j) = (node / w, node % w);
        let (i2, j2) = if id.is_multiple_of(2) {
            (i + 1, j)
        } else {
            (i, j + 1)
        };
        let (a, b) = (pos(i, j), pos(i2, j2));
        let (mut s, mut u) = if val(i, j) { (a, b) } else { (b, a) };
        let ring = [i, j, i2, j2].iter().any(|&k| k == 0 || k == n + 2);
        if ring {
            return Vertex {
                x: s.0,
                y: s.1,
                piece: Piece::Clipped,
            };
        }
        while (s.0 - u.0).abs() + (s.1 - u.1).abs() > tol {
            let m = (0.5 * (s.0 + u.0), 0.5 * (s.1 + u.1));
            if m == s || m == u {
                break;
            }
            if t.stable(m.0, m.1) {
                s = m;
            } else {
                u = m;
            }
        }
        Vertex {
            x: 0.5 * (s.0 + u.0),
            y: 0.5 * (s.1 + u.1),
            piece: Piece::Bisection,
        }
    };
    loops_ids
        .into_iter()
        .map(|ids| ids.par_iter().map(|&id| edge_point(id)).collect())
        .collect()
}

/// Refines every chord of a closed loop by bisection along its normal (parallel over the
/// chords; order kept).
fn refine_loop(
    t: &Tester,
    lp: Vec<Vertex>,
    tol: f64,
    xr: Option<(f64, f64)>,
    yr: Option<(f64, f64)>,
) -> Vec<Vertex> {
    let n = lp.len();
    let pieces: Vec<Vec<Vertex>> = (0..n)
        .into_par_iter()
        .map(|k| {
            let (a, b) = (lp[k], lp[(k + 1) % n]);
            let mut out = vec![a];
            if !(a.clipped() && b.clipped()) {
                refine_chord(t, a, b, tol, 0, xr, yr, &mut out);
            }
            out
        })
        .collect();
    pieces.into_iter().flatten().collect()
}

#[allow(clippy::too_many_arguments)]
fn refine_chord(
    t: &Tester,
    a: Vertex,
    b: Vertex,
    tol: f64,
    depth: u32,
    xr: Option<(f64, f64)>,
    yr: Option<(f64, f64)>,
    out: &mut Vec<Vertex>,
) {
    // 40 halvings take any chord of the grid below f64 resolution.
    if depth >= 40 {
        return;
    }
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len = dx.hypot(dy);
    if len.is_nan() || len <= tol {
        return;
    }
    let (nx, ny) = (-dy / len, dx / len);
    let m = (0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
    let at = |s: f64| (m.0 + s * nx, m.1 + s * ny);
    // The loop runs with the stable side on its left, so the boundary lies to the right of
    // a stable midpoint and to the left of an unstable one. Search that way, from len out,
    // doubling up to a grid cell until the far end has the other verdict (the chord may sit
    // inside a thin tip of the region, such as a corner with alpha = 0).
    let pm = at(0.0);
    let s_m = t.stable(pm.0, pm.1);
    let dir = if s_m { -1.0 } else { 1.0 };
    let mut reach = len;
    loop {
        let p = at(dir * reach);
        if t.stable(p.0, p.1) != s_m {
            break;
        }
        reach *= 2.0;
        if reach > t.cell {
            return;
        }
    }
    // lo keeps the midpoint's verdict, hi the other
    let (mut lo, mut hi, s_lo) = (0.0, dir * reach, s_m);
    while (hi - lo).abs() > tol {
        let mid = 0.5 * (lo + hi);
        let p = at(mid);
        if t.stable(p.0, p.1) == s_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s = 0.5 * (lo + hi);
    if s.abs() <= tol {
        return;
    }
    let p = at(s);
    let on_edge = |r: Option<(f64, f64)>, v: f64| {
        r.is_some_and(|(l, h)| (v - l).abs() <= tol || (v - h).abs() <= tol)
    };
    let c = Vertex {
        x: p.0,
        y: p.1,
        piece: if on_edge(xr, p.0) || on_edge(yr, p.1) {
            Piece::Clipped
        } else {
            Piece::Bisection
        },
    };
    refine_chord(t, a, c, tol, depth + 1, xr, yr, out);
    out.push(c);
    refine_chord(t, c, b, tol, depth + 1, xr, yr, out);
}
