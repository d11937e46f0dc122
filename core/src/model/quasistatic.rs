//! Quasi-static follower chains: static condensation of the stiff vertical DOFs
//! (docs/MODEL.md §10).
//!
//! The vertical chain runs from the cam shaft to the load (y1, y2, y3, y4, y5): the cam
//! on its shaft spring K_vs, the Hertz contact K_h cos²φ with its preload offset, the
//! roller bearing K_rb, the cantilever portion K_vc with the return spring K_rs at y3,
//! the follower rod K_f with its damper C_f1, the load. A reduced scene drops the masses
//! of a run of that chain ([`QuasiStatic`]): their nodes carry no inertia, so the forces
//! on each balance at every instant and their displacements follow from the dynamic
//! nodes' by one tridiagonal solve ([`ChainSolve`]). That removes the chain's stiff
//! modes (the roller's 2.5e5-3.6e5 rad/s on the contact and K_rb, the cantilever's
//! ~1e5) from the step-size limit.
//!
//! What goes with the masses: the contact and roller-bearing dampers, C = 2ξ√(K M_r),
//! vanish with M_r (so the massless roller's series spring is undamped, the exact limit);
//! the dropped follower masses ride on the first dynamic node beyond the run (lumped:
//! the train's inertia still loads the contact, so the jump criterion keeps it), and
//! their momentum-exchange terms (ρA ẏ3 ẏ4, ρA ẏ3²) go when y3 is quasi-static.

use crate::{DofSet, Real, TransDof, QUASI_STATIC_CHAIN};

/// The quasi-static runs a reduced scene may drop (each a [`DofSet`] of the vertical
/// chain, `Scene::QUASI_STATIC`).
#[derive(Clone, Copy, Debug)]
pub struct QuasiStatic;

impl QuasiStatic {
    /// A massless roller: y2, the contact and K_rb in series.
    pub const ROLLER: DofSet = DofSet::NONE.with(TransDof::RollerY);
    /// The roller and the cantilever portion y3.
    pub const CANTILEVER: DofSet = Self::ROLLER.with(TransDof::CantileverY);
    /// The roller, the cantilever and the follower rod y4: the load carries the train.
    pub const ROD: DofSet = Self::CANTILEVER.with(TransDof::Follower);
    /// The whole chain up to the load, the cam shaft y1 too.
    pub const SHAFT: DofSet = Self::ROD.with(TransDof::CamY);
}

/// The follower's model: the full chain, or which run of it is quasi-static (a reduced
/// scene; the host and scene files name it, `run.follower`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum FollowerModel {
    /// Every mass of the chain (Eqs. IV.2-IV.3).
    #[default]
    Full,
    /// [`QuasiStatic::ROLLER`].
    MasslessRoller,
    /// [`QuasiStatic::CANTILEVER`].
    QuasiStaticCantilever,
    /// [`QuasiStatic::ROD`].
    QuasiStaticRod,
    /// [`QuasiStatic::SHAFT`].
    QuasiStaticShaft,
}

impl FollowerModel {
    /// Every follower model, fullest first.
    pub const ALL: [FollowerModel; 5] = [
        FollowerModel::Full,
        FollowerModel::MasslessRoller,
        FollowerModel::QuasiStaticCantilever,
        FollowerModel::QuasiStaticRod,
        FollowerModel::QuasiStaticShaft,
    ];

    /// The DOFs it solves quasi-statically (`Scene::QUASI_STATIC`).
    pub const fn quasi_static(self) -> DofSet {
        match self {
            FollowerModel::Full => DofSet::NONE,
            FollowerModel::MasslessRoller => QuasiStatic::ROLLER,
            FollowerModel::QuasiStaticCantilever => QuasiStatic::CANTILEVER,
            FollowerModel::QuasiStaticRod => QuasiStatic::ROD,
            FollowerModel::QuasiStaticShaft => QuasiStatic::SHAFT,
        }
    }

    /// Its name in scene files and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            FollowerModel::Full => "full",
            FollowerModel::MasslessRoller => "massless-roller",
            FollowerModel::QuasiStaticCantilever => "quasi-static-cantilever",
            FollowerModel::QuasiStaticRod => "quasi-static-rod",
            FollowerModel::QuasiStaticShaft => "quasi-static-shaft",
        }
    }
}

/// Nodes of the vertical chain that can be quasi-static (y1..y4; the load never is).
pub const CHAIN_NODES: usize = 4;

/// The first and last node of a quasi-static run of the chain (a `const fn`: for a
/// scene's constant set the solver's loops have constant bounds).
pub const fn run_bounds(quasi: DofSet) -> (usize, usize) {
    let mut first = CHAIN_NODES;
    let mut last = 0;
    let mut i = 0;
    while i < CHAIN_NODES {
        let d = match i {
            0 => QUASI_STATIC_CHAIN[0],
            1 => QUASI_STATIC_CHAIN[1],
            2 => QUASI_STATIC_CHAIN[2],
            _ => QUASI_STATIC_CHAIN[3],
        };
        if quasi.contains(d) {
            if i < first {
                first = i;
            }
            last = i;
        }
        i += 1;
    }
    (first, last)
}

/// The linear elements of the vertical chain at one instant, nodes in
/// [`QUASI_STATIC_CHAIN`] order (0 = y1 ... 4 = y5), in the model's stored coordinates
/// (y1 absolute, the follower chain relative to the lift).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainSolve<T> {
    /// Stiffness between node i and node i + 1, lb/in: K_h cos²φ (0 when separated),
    /// K_rb, K_vc, K_f.
    pub series: [T; CHAIN_NODES],
    /// Stiffness from node i to ground, lb/in: K_vs at y1, K_rs at y3.
    pub ground: [T; CHAIN_NODES],
    /// First quasi-static node (0 or 1).
    pub first: usize,
    /// Last quasi-static node (1 to 3).
    pub last: usize,
}

impl<T: Real> ChainSolve<T> {
    /// The chain with quasi-static run `quasi` (a valid `Scene::QUASI_STATIC`, non-empty).
    #[inline(always)]
    pub fn new(quasi: DofSet, series: [T; CHAIN_NODES], ground: [T; CHAIN_NODES]) -> Self {
        let (first, last) = run_bounds(quasi);
        Self {
            series,
            ground,
            first,
            last,
        }
    }

    /// Balances the forces on the quasi-static nodes: for each, the springs to its
    /// neighbours and to ground plus `force[i]` (every force that does not depend on the
    /// displacements: offsets, dampers, friction) sum to zero, with the dynamic nodes at
    /// `x`. Writes the quasi-static nodes' displacements into `x`. (One solve: a caller
    /// with several right-hand sides for one chain factors it once, [`Self::factor`].)
    pub fn solve(&self, x: &mut [T; CHAIN_NODES + 1], force: &[T; CHAIN_NODES]) {
        self.factor().solve(x, force);
    }

    /// The chain's tridiagonal stiffness matrix over its quasi-static run, factored (the
    /// Thomas algorithm's forward sweep of the matrix; a stiffness matrix is diagonally
    /// dominant, so no pivoting): each pivot's reciprocal and super-diagonal ratio.
    #[inline(always)]
    pub fn factor(&self) -> ChainFactor<T> {
        let (first, last) = (self.first, self.last.min(CHAIN_NODES - 1));
        let mut f = ChainFactor {
            first,
            last,
            inv_pivot: [T::ZERO; CHAIN_NODES],
            ratio: [T::ZERO; CHAIN_NODES],
            left: [T::ZERO; CHAIN_NODES],
            right: [T::ZERO; CHAIN_NODES],
        };
        let mut prev_ratio: Option<T> = None;
        // `first..last + 1`, not `first..=last`: LLVM unrolls an exclusive range with
        // constant bounds (a scene's run) to straight-line code and does not unroll the
        // inclusive one (the chip's three solves an evaluation: 486 -> about 80
        // instructions, docs/FIRMWARE.md). `last` < CHAIN_NODES, so `+ 1` cannot wrap.
        for i in first..last + 1 {
            let k_left = if i > 0 {
                self.series.get(i - 1).copied().unwrap_or(T::ZERO)
            } else {
                T::ZERO
            };
            let k_right = self.series.get(i).copied().unwrap_or(T::ZERO);
            let g = self.ground.get(i).copied().unwrap_or(T::ZERO);
            let diag = k_left + k_right + g;
            // Eliminate the sub-diagonal -k_left against the previous row.
            let pivot = match prev_ratio {
                Some(c) => diag - k_left * c,
                None => diag,
            };
            let inv = T::ONE / pivot;
            let c = k_right * inv; // the row's super-diagonal is -k_right
            if let (Some(ip), Some(r), Some(l), Some(rt)) = (
                f.inv_pivot.get_mut(i),
                f.ratio.get_mut(i),
                f.left.get_mut(i),
                f.right.get_mut(i),
            ) {
                *ip = inv;
                *r = c;
                *l = k_left;
                *rt = k_right;
            }
            prev_ratio = Some(c);
        }
        f
    }
}

/// A [`ChainSolve`]'s matrix factored: solves it for any forces in a few multiplies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainFactor<T> {
    first: usize,
    last: usize,
    inv_pivot: [T; CHAIN_NODES],
    ratio: [T; CHAIN_NODES],
    left: [T; CHAIN_NODES],
    right: [T; CHAIN_NODES],
}

impl<T: Real> ChainFactor<T> {
    /// [`ChainSolve::solve`] with this factorisation.
    #[inline(always)]
    pub fn solve(&self, x: &mut [T; CHAIN_NODES + 1], force: &[T; CHAIN_NODES]) {
        let (first, last) = (self.first, self.last);
        let mut dp = [T::ZERO; CHAIN_NODES];
        let mut prev: Option<T> = None;
        // Exclusive ranges, as in [`ChainSolve::factor`] (`last` < CHAIN_NODES).
        for i in first..last + 1 {
            let k_left = self.left.get(i).copied().unwrap_or(T::ZERO);
            let mut rhs = force.get(i).copied().unwrap_or(T::ZERO);
            // A dynamic neighbour's pull goes to the right-hand side.
            if i == first && i > 0 {
                rhs += k_left * x.get(i - 1).copied().unwrap_or(T::ZERO);
            }
            if i == last {
                let k_right = self.right.get(i).copied().unwrap_or(T::ZERO);
                rhs += k_right * x.get(i + 1).copied().unwrap_or(T::ZERO);
            }
            if let Some(d_prev) = prev {
                rhs += k_left * d_prev;
            }
            let d = rhs * self.inv_pivot.get(i).copied().unwrap_or(T::ZERO);
            if let Some(o) = dp.get_mut(i) {
                *o = d;
            }
            prev = Some(d);
        }
        // Back substitution: x[i] = d'[i] + c'[i] x[i+1] (x[last+1] is not an unknown).
        let mut next: Option<T> = None;
        for i in (first..last + 1).rev() {
            let d = dp.get(i).copied().unwrap_or(T::ZERO);
            let c = self.ratio.get(i).copied().unwrap_or(T::ZERO);
            let xi = match next {
                Some(xn) => d + c * xn,
                None => d,
            };
            if let Some(o) = x.get_mut(i) {
                *o = xi;
            }
            next = Some(xi);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three springs in series between two fixed ends: the classic closed form.
    #[test]
    fn series_springs_share_the_displacement_in_inverse_proportion() {
        // Nodes 1, 2 quasi-static between node 0 at 0 and node 3 at 1 (nothing to ground).
        let c = ChainSolve::<f64> {
            series: [1.0, 2.0, 4.0, 0.0],
            ground: [0.0; 4],
            first: 1,
            last: 2,
        };
        let mut x = [0.0, 9.0, 9.0, 1.0, 0.0];
        c.solve(&mut x, &[0.0; 4]);
        // Series compliance 1 + 1/2 + 1/4 = 7/4: force 4/7, stretches 4/7, 2/7, 1/7.
        assert!((x[1] - 4.0 / 7.0).abs() < 1e-15, "{x:?}");
        assert!((x[2] - 6.0 / 7.0).abs() < 1e-15, "{x:?}");
        assert_eq!((x[0], x[3]), (0.0, 1.0));
    }

    /// A node on a ground spring and a series spring, loaded by a force: the balance
    /// (g + k) x = F + k x_dyn.
    #[test]
    fn a_ground_spring_and_an_external_force_balance() {
        let c = ChainSolve::<f64>::new(
            QuasiStatic::SHAFT,
            [3.0, 5.0, 7.0, 11.0],
            [2.0, 0.0, 13.0, 0.0],
        );
        assert_eq!((c.first, c.last), (0, 3));
        let f = [1.0, -2.0, 0.5, 3.0];
        let mut x = [0.0, 0.0, 0.0, 0.0, 0.25];
        c.solve(&mut x, &f);
        // Residual of every equation: the forces on each node sum to zero.
        let r = [
            -2.0 * x[0] + 3.0 * (x[1] - x[0]) + f[0],
            3.0 * (x[0] - x[1]) + 5.0 * (x[2] - x[1]) + f[1],
            5.0 * (x[1] - x[2]) + 7.0 * (x[3] - x[2]) - 13.0 * x[2] + f[2],
            7.0 * (x[2] - x[3]) + 11.0 * (x[4] - x[3]) + f[3],
        ];
        assert!(r.iter().all(|v| v.abs() < 1e-14), "{r:?}");
        let roller = ChainSolve::<f64>::new(QuasiStatic::ROLLER, [1.0; 4], [0.0; 4]);
        assert_eq!((roller.first, roller.last), (1, 1));
        let rod = ChainSolve::<f64>::new(QuasiStatic::ROD, [1.0; 4], [0.0; 4]);
        assert_eq!((rod.first, rod.last), (1, 3));
    }
}
