//! Root finding below the stability tests and the engines: one-dimensional (Brent) for the
//! searches, and a polynomial's roots by eigenvalues ([`eigen`], with the Hessenberg QR of
//! [`hqr`]) for the scan refinement of the loop curve and the stability tests.

pub(crate) mod eigen;
pub(crate) mod hqr;

/// A complex number (the type [`crate::poly::Complex`] names for the crate's users).
pub(crate) type Complex = nalgebra::Complex<f64>;

/// Brent's root finder (zeroin; Brent 1973, ch. 4) for `f` on `[a, b]` with `f(a) f(b) <= 0`.
pub(crate) fn brent(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let (fa, fb) = (f(a), f(b));
    brent_from(f, (a, fa), (b, fb), tol)
}

/// [`brent`] with the values at the ends already known, `fa = f(a)` and `fb = f(b)`: the
/// same iterates, without evaluating `f` at the ends again (where each value is a costly
/// solve of its own).
pub(crate) fn brent_from(
    mut f: impl FnMut(f64) -> f64,
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    tol: f64,
) -> f64 {
    // Exact zeros on purpose (as in zeroin): an end point that is a root to the last bit ends
    // the search; anything else is bracketed and refined to `tol`.
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    b
}
