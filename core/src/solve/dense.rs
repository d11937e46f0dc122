//! The continuous extension of England's double step ([`Dense`]): a quintic Hermite
//! interpolant of the step's three nodes and their derivatives.

use crate::{Error, Real, Result};

/// The continuous extension of one accepted double step of [`England`](crate::England) (its dense
/// output, passed by [`England::integrate_dense`](crate::England::integrate_dense)): the quintic Hermite interpolant of the
/// start `(t0, y0)`, midpoint `(t1, y1)` and end `(t2, y2)` of the step and of the
/// derivatives `f(t_j, y_j)` at all three.
///
/// Why quintic: it uses only what the solver has anyway (`f(t0, y0)` is `k1/s`,
/// `f(t1, y1)` is `k5/s`, `f(t2, y2)` is the next step's first stage), its interpolation
/// error `y⁽⁶⁾(ξ) ((t-t0)(t-t1)(t-t2))² / 720` is `O(h⁶)`, one order below the
/// `O(h⁵)` local error of the nodes themselves, so between the nodes the output is as
/// accurate as at them (globally fourth order, like the solver); and it matches `f` at
/// every node, so it is continuously differentiable across steps. A quartic from
/// `y0, y1, y2, f0, f1` would save only the one final evaluation, with an `O(h⁵)`
/// interpolation error and a kink at every step end.
///
/// It reproduces `y0`, `y1`, `y2` exactly (bit for bit) at `t0`, `t1`, `t2`. Outside
/// `[t0, t2]` it extrapolates (no error; accuracy degrades quickly).
#[derive(Clone, Copy, Debug)]
pub struct Dense<'a, T, const N: usize> {
    t: [T; 3],
    y: [&'a [T; N]; 3],
    f: [&'a [T; N]; 3],
    /// L_j'(t_j) of the quadratic Lagrange basis.
    c: [T; 3],
    /// Two nodes only ([`Dense::cubic`]): the last two entries of `t`, `y`, `f` repeat
    /// the end.
    cubic: bool,
}

impl<'a, T: Real, const N: usize> Dense<'a, T, N> {
    /// The interpolant of `y[j]` with derivative `f[j]` at times `t[j]`; the times must
    /// be finite and strictly increasing (they need not be equally spaced).
    pub fn new(t: [T; 3], y: [&'a [T; N]; 3], f: [&'a [T; N]; 3]) -> Result<Self> {
        let [t0, t1, t2] = t;
        if !(t0.is_finite() && t1.is_finite() && t2.is_finite() && t0 < t1 && t1 < t2) {
            return Err(Error::InvalidParameter {
                field: "t",
                rule: "dense-output nodes must be finite and strictly increasing (a step below the resolution of t?)",
                value: t1.to_f64(),
            });
        }
        let c = [
            T::ONE / (t0 - t1) + T::ONE / (t0 - t2),
            T::ONE / (t1 - t0) + T::ONE / (t1 - t2),
            T::ONE / (t2 - t0) + T::ONE / (t2 - t1),
        ];
        Ok(Self {
            t,
            y,
            f,
            c,
            cubic: false,
        })
    }

    /// The cubic Hermite interpolant of one step of an embedded pair
    /// ([`Pair::integrate_dense`](crate::Pair::integrate_dense)) from its two ends `y[j]`
    /// with derivatives `f[j]` at times `t[j]`: third order between the nodes
    /// (`y⁽⁴⁾(ξ) ((t-t0)(t-t1))² / 24`), exact at them. The times must be finite and
    /// strictly increasing. [`Dense::t_mid`] is then the end.
    pub fn cubic(t: [T; 2], y: [&'a [T; N]; 2], f: [&'a [T; N]; 2]) -> Result<Self> {
        let [t0, t1] = t;
        if !(t0.is_finite() && t1.is_finite() && t0 < t1) {
            return Err(Error::InvalidParameter {
                field: "t",
                rule: "dense-output nodes must be finite and strictly increasing (a step below the resolution of t?)",
                value: t1.to_f64(),
            });
        }
        let [y0, y1] = y;
        let [f0, f1] = f;
        Ok(Self {
            t: [t0, t1, t1],
            y: [y0, y1, y1],
            f: [f0, f1, f1],
            c: [T::ZERO; 3],
            cubic: true,
        })
    }

    /// The nodes after the start, with their times: the midpoint and the end of England's
    /// double step, or the end alone of a pair's step ([`Dense::cubic`]).
    pub fn inner_nodes(&self) -> impl Iterator<Item = (T, &'a [T; N])> + '_ {
        let skip = if self.cubic { 2 } else { 1 };
        self.t.into_iter().zip(self.y).skip(skip)
    }

    /// Start time of the step.
    pub fn t_start(&self) -> T {
        self.t[0]
    }

    /// Midpoint time of the step.
    pub fn t_mid(&self) -> T {
        self.t[1]
    }

    /// End time of the step.
    pub fn t_end(&self) -> T {
        self.t[2]
    }

    /// State at the start, midpoint and end.
    pub fn nodes(&self) -> [&'a [T; N]; 3] {
        self.y
    }

    /// Derivative `f(t_j, y_j)` at the start, midpoint and end.
    pub fn derivatives(&self) -> [&'a [T; N]; 3] {
        self.f
    }

    /// The step's length and `t`'s fraction of it (a cubic extension's).
    fn unit(&self, t: T) -> (T, T) {
        let [t0, t1, _] = self.t;
        let h = t1 - t0;
        (h, (t - t0) / h)
    }

    /// Weights `[H0, H1, H2, K0, K1, K2]` of the values and derivatives at `t`:
    /// `L_j` the quadratic Lagrange basis, `H_j = (1 - 2 L_j'(t_j)(t - t_j)) L_j²`,
    /// `K_j = (t - t_j) L_j²`. Each `L_j` is a product of ratios that is exactly 1 at
    /// `t_j` and exactly 0 at the other nodes, so the nodes are reproduced exactly.
    fn weights(&self, t: T) -> [T; 6] {
        let [t0, t1, t2] = self.t;
        let a = [t - t0, t - t1, t - t2];
        let [a0, a1, a2] = a;
        let l = [
            (a1 / (t0 - t1)) * (a2 / (t0 - t2)),
            (a0 / (t1 - t0)) * (a2 / (t1 - t2)),
            (a0 / (t2 - t0)) * (a1 / (t2 - t1)),
        ];
        // (H_j, K_j) of node j.
        let hk = |lj: T, aj: T, cj: T| {
            let l2 = lj * lj;
            ((T::ONE - T::TWO * cj * aj) * l2, aj * l2)
        };
        let [l0, l1, l2] = l;
        let [c0, c1, c2] = self.c;
        let (h0, k0) = hk(l0, a0, c0);
        let (h1, k1) = hk(l1, a1, c1);
        let (h2, k2) = hk(l2, a2, c2);
        [h0, h1, h2, k0, k1, k2]
    }

    /// The interpolated state at `t`.
    pub fn eval(&self, t: T, out: &mut [T; N]) {
        if self.cubic {
            let (h, u) = self.unit(t);
            let (u2, three) = (u * u, T::from_f64(3.0));
            let u3 = u2 * u;
            let w = [
                T::TWO * u3 - three * u2 + T::ONE,
                three * u2 - T::TWO * u3,
                T::ZERO,
                h * (u3 - T::TWO * u2 + u),
                h * (u3 - u2),
                T::ZERO,
            ];
            combine(w, self.y, self.f, out);
            return;
        }
        combine(self.weights(t), self.y, self.f, out);
    }

    /// The interpolated derivative `dy/dt` at `t` (continuous across steps; equal to
    /// `f(t_j, y_j)` at the nodes up to rounding).
    pub fn eval_derivative(&self, t: T, out: &mut [T; N]) {
        if self.cubic {
            let (h, u) = self.unit(t);
            let (u2, three, six) = (u * u, T::from_f64(3.0), T::from_f64(6.0));
            let w = [
                six * (u2 - u) / h,
                six * (u - u2) / h,
                T::ZERO,
                three * u2 - T::from_f64(4.0) * u + T::ONE,
                three * u2 - T::TWO * u,
                T::ZERO,
            ];
            combine(w, self.y, self.f, out);
            return;
        }
        // d/dt of the weights: with a_j = t - t_j, L_j = (a_k/(t_j-t_k))(a_m/(t_j-t_m)),
        // L_j' = a_m/((t_j-t_k)(t_j-t_m)) + a_k/((t_j-t_k)(t_j-t_m)).
        let [t0, t1, t2] = self.t;
        let a = [t - t0, t - t1, t - t2];
        let den = [
            (t0 - t1) * (t0 - t2),
            (t1 - t0) * (t1 - t2),
            (t2 - t0) * (t2 - t1),
        ];
        // (H_j', K_j') of node j, whose other two nodes are k and m.
        let dhk = |aj: T, ak: T, am: T, den_j: T, cj: T| {
            let l = ak * am / den_j;
            let dl = (ak + am) / den_j;
            // H_j' = -2 c_j L² + (1 - 2 c_j a_j) 2 L L';  K_j' = L² + a_j 2 L L'.
            (
                -T::TWO * cj * l * l + (T::ONE - T::TWO * cj * aj) * T::TWO * l * dl,
                l * l + aj * T::TWO * l * dl,
            )
        };
        let [a0, a1, a2] = a;
        let [den0, den1, den2] = den;
        let [c0, c1, c2] = self.c;
        let (dh0, dk0) = dhk(a0, a1, a2, den0, c0);
        let (dh1, dk1) = dhk(a1, a0, a2, den1, c1);
        let (dh2, dk2) = dhk(a2, a0, a1, den2, c2);
        combine([dh0, dh1, dh2, dk0, dk1, dk2], self.y, self.f, out);
    }
}

/// `out = w0 y0 + w1 y1 + w2 y2 + (w3 f0 + w4 f1 + w5 f2)`, component by component: the
/// value or derivative of [`Dense`] from its weights.
fn combine<T: Real, const N: usize>(w: [T; 6], y: [&[T; N]; 3], f: [&[T; N]; 3], out: &mut [T; N]) {
    let [w0, w1, w2, w3, w4, w5] = w;
    let [y0, y1, y2] = y;
    let [f0, f1, f2] = f;
    for ((((((o, y0), y1), y2), f0), f1), f2) in out
        .iter_mut()
        .zip(y0.iter())
        .zip(y1.iter())
        .zip(y2.iter())
        .zip(f0.iter())
        .zip(f1.iter())
        .zip(f2.iter())
    {
        *o = w0 * *y0 + w1 * *y1 + w2 * *y2 + (w3 * *f0 + w4 * *f1 + w5 * *f2);
    }
}
