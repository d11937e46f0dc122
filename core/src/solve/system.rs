//! The systems the solvers integrate ([`OdeSystem`]) and their error tolerances.

use crate::Real;

/// A system of first-order ordinary differential equations `dy/dt = f(t, y)` with
/// `N` components, as integrated by [`England`](crate::England) and [`rk4_integrate`](crate::rk4_integrate).
pub trait OdeSystem<T: Real, const N: usize> {
    /// dy/dt = f(t, y): writes the derivative of every component into `dydt`.
    fn rhs(&self, t: T, y: &[T; N], dydt: &mut [T; N]);

    /// An estimate of the spectral radius of the Jacobian `∂f/∂y` at `(t, y)` (the
    /// modulus of the stiffest eigenvalue, 1/s), if the system knows one; used only by
    /// [`StiffnessCap`](crate::StiffnessCap) (which otherwise estimates it by power
    /// iteration). The default knows none.
    fn spectral_radius(&self, t: T, y: &[T; N]) -> Option<T> {
        let _ = (t, y);
        None
    }
}

/// Error tolerance of [`England`](crate::England): component `i` of a double step is accepted when
/// `|E_i| <= atol_i + rtol · max(|y_i(t0)|, |ŷ2_i|)`, ŷ2 England's auxiliary end-point
/// estimate (Appendix D's "absolute error + relative error · y"; docs/MODEL.md §3.16).
#[derive(Clone, Copy, Debug)]
pub struct Tolerance<T, const N: usize> {
    /// Relative tolerance (dimensionless), shared by all components.
    pub rtol: T,
    /// Absolute tolerance per component, in that component's units.
    pub atol: [T; N],
}

impl<T: Real, const N: usize> Tolerance<T, N> {
    /// The same absolute tolerance for every component.
    pub fn scalar(rtol: T, atol: T) -> Self {
        Self {
            rtol,
            atol: [atol; N],
        }
    }

    /// One absolute tolerance per component (for states of different units).
    pub fn per_component(rtol: T, atol: [T; N]) -> Self {
        Self { rtol, atol }
    }

    /// Weighted-norm scale of component `i` at value `yi`: `atol_i + rtol · |yi|`.
    #[inline]
    pub(crate) fn scale(&self, i: usize, yi: T) -> T {
        self.atol.get(i).copied().unwrap_or(T::ZERO) + self.rtol * yi.abs()
    }
}
