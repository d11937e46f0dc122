//! Scenes: which degrees of freedom the model keeps, fixed at compile time.
//!
//! A scene is a zero-sized type implementing [`Scene`]. Its drive kind ([`DriveKind`]:
//! the ideal drives remove rotational DOFs) and its translational DOFs ([`DofSet`]: the
//! horizontal motion can be dropped) are associated consts, and [`Layout`] places every
//! state quantity ([`StateVar`]) from them in a `const fn`. The model
//! [`CamModel<T, S, N>`](crate::CamModel) and the state views [`StateRef`] / [`StateMut`]
//! assert `N == S::N` when they are monomorphised, so a state of the wrong size does not
//! compile; every branch on the drive or the DOFs is on a constant the compiler folds,
//! and a quantity is reached by name, never by a raw index.
//!
//! State layout of `N` components:
//! 1. rotational block, by drive: regulated: `[θ_c, θ_cp - θ_c, θ_m - θ_cp, θ̇_c, θ̇_cp, θ̇_m]`;
//!    constant motor speed: `[θ_c, θ_cp - θ_c, θ_m - θ_cp, θ̇_c, θ̇_cp]`; constant cam
//!    speed: nothing (θ_c = ω0 t). Shaft twists are states, not absolute angles, so the
//!    small twist is not lost to cancellation (this matters in `f32`).
//! 2. the kept translational displacements in the order y1, x1, y2, x2, y3, x3, y4, y5;
//!    the follower chain's vertical ones (y2, y3, y4, y5) are stored relative to the
//!    cam's commanded lift, `q_i = y_i - s(θ_c)` ([`RELATIVE_TO_LIFT`]), for the same
//!    reason: in `f32` an absolute y2 near the 1.5 in lift resolves only 1.2e-7 in, i.e.
//!    0.8 lb of Hertz force (K_h ≈ 6.5e6 lb/in), and θ_c's own rounding moves s(θ_c) by
//!    microinches; the spring and contact deflections are formed from the q's instead.
//!    Same physics, different coordinates;
//! 3. their (absolute) velocities in the same order.
//!
//! A new scene is one entry of the `scenes!` invocation at the end of this file (for
//! example `DofSet::VERTICAL.without(TransDof::CamY)` for a rigid cam shaft); the host
//! lists the scenes it dispatches over once, in `host-sim/src/sim.rs`.

use core::marker::PhantomData;

use crate::{CamModel, DriveKind, QuasiStatic, Real};

/// The translational degrees of freedom, in state order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum TransDof {
    /// y1: cam (and shaft) vertical.
    CamY = 0,
    /// x1: cam horizontal.
    CamX = 1,
    /// y2: roller vertical.
    RollerY = 2,
    /// x2: roller horizontal.
    RollerX = 3,
    /// y3: cantilever portion of the follower, vertical.
    CantileverY = 4,
    /// x3: cantilever portion of the follower, horizontal.
    CantileverX = 5,
    /// y4: follower between slide bearing and load.
    Follower = 6,
    /// y5: load (the follower output).
    Load = 7,
}

/// Number of translational DOFs of the full model.
pub const TRANS_DOFS: usize = 8;

impl TransDof {
    /// Every translational DOF, in state order.
    pub const ALL: [TransDof; TRANS_DOFS] = [
        TransDof::CamY,
        TransDof::CamX,
        TransDof::RollerY,
        TransDof::RollerX,
        TransDof::CantileverY,
        TransDof::CantileverX,
        TransDof::Follower,
        TransDof::Load,
    ];

    /// The entry for this DOF of an array in [`TransDof`] order.
    #[inline(always)]
    pub fn of<T: Copy>(self, a: &[T; TRANS_DOFS]) -> T {
        let [y1, x1, y2, x2, y3, x3, y4, y5] = *a;
        match self {
            TransDof::CamY => y1,
            TransDof::CamX => x1,
            TransDof::RollerY => y2,
            TransDof::RollerX => x2,
            TransDof::CantileverY => y3,
            TransDof::CantileverX => x3,
            TransDof::Follower => y4,
            TransDof::Load => y5,
        }
    }
}

/// Translational DOFs whose displacement state is stored relative to the commanded lift
/// s(θ_c) (the follower chain y2, y3, y4, y5; see the module docs), in [`TransDof`] order.
pub const RELATIVE_TO_LIFT: [bool; TRANS_DOFS] =
    [false, false, true, false, true, false, true, true];

/// Which translational DOFs a scene keeps (a set over [`TransDof`]); a dropped DOF is
/// held at zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DofSet(u8);

impl DofSet {
    /// No translational DOF.
    pub const NONE: DofSet = DofSet(0);
    /// All eight translational DOFs.
    pub const ALL: DofSet = DofSet(0xFF);
    /// Vertical motion only: x1, x2, x3 dropped (held at zero).
    pub const VERTICAL: DofSet = DofSet::ALL
        .without(TransDof::CamX)
        .without(TransDof::RollerX)
        .without(TransDof::CantileverX);

    /// Whether `dof` is kept.
    pub const fn contains(self, dof: TransDof) -> bool {
        self.0 & (1 << dof as u8) != 0
    }
    /// This set without `dof`.
    pub const fn without(self, dof: TransDof) -> DofSet {
        DofSet(self.0 & !(1 << dof as u8))
    }
    /// This set with `dof`.
    pub const fn with(self, dof: TransDof) -> DofSet {
        DofSet(self.0 | (1 << dof as u8))
    }
    /// This set without every DOF of `other`.
    pub const fn minus(self, other: DofSet) -> DofSet {
        DofSet(self.0 & !other.0)
    }
    /// Whether every DOF of `other` is in this set.
    pub const fn includes(self, other: DofSet) -> bool {
        self.0 & other.0 == other.0
    }
    /// Whether the set is empty.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Number of kept DOFs.
    pub const fn count(self) -> usize {
        self.0.count_ones() as usize
    }
    /// Number of kept DOFs that come before `dof` in state order.
    const fn count_before(self, dof: TransDof) -> usize {
        (self.0 & ((1u8 << dof as u8) - 1)).count_ones() as usize
    }
    /// "all", "vertical", or "custom" for any other set.
    pub const fn name(self) -> &'static str {
        if self.0 == DofSet::ALL.0 {
            "all"
        } else if self.0 == DofSet::VERTICAL.0 {
            "vertical"
        } else {
            "custom"
        }
    }
}

/// One quantity a state vector may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StateVar {
    /// Cam angle θ_c, rad.
    CamAngle,
    /// θ_cp - θ_c: twist of the shaft between coupling and cam (K_s2), rad.
    CouplingCamTwist,
    /// θ_m - θ_cp: twist of the shaft between motor and coupling (K_s1), rad.
    MotorCouplingTwist,
    /// θ̇_c, rad/s.
    CamSpeed,
    /// θ̇_cp, rad/s.
    CouplingSpeed,
    /// θ̇_m, rad/s.
    MotorSpeed,
    /// A translational displacement, in: relative to the commanded lift for the
    /// follower chain ([`RELATIVE_TO_LIFT`]), absolute otherwise.
    Position(TransDof),
    /// A translational velocity (absolute), in/s.
    Velocity(TransDof),
}

impl StateVar {
    /// The rotational quantities, in state order.
    pub const ROTATIONAL: [StateVar; 6] = [
        StateVar::CamAngle,
        StateVar::CouplingCamTwist,
        StateVar::MotorCouplingTwist,
        StateVar::CamSpeed,
        StateVar::CouplingSpeed,
        StateVar::MotorSpeed,
    ];
}

/// Where every [`StateVar`] of a scene lives in its state vector, computed at compile
/// time from the drive kind and the kept translational DOFs (see the module docs).
///
/// Only [`Layout::try_new`] builds one, and it numbers the quantities it keeps
/// consecutively from 0: every index it reports is below [`Layout::states`], and no two
/// quantities share one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Layout {
    drive: DriveKind,
    dofs: DofSet,
    quasi: DofSet,
    rotational: usize,
    states: usize,
}

impl Layout {
    /// No layout: no state at all (what [`Scene::LAYOUT`] falls back to for a set
    /// [`Layout::try_reduced`] refuses; the `scenes!` definitions assert that none does).
    pub const NONE: Layout = Layout {
        drive: DriveKind::ConstantCamSpeed,
        dofs: DofSet::NONE,
        quasi: DofSet::NONE,
        rotational: 0,
        states: 0,
    };

    /// The layout for a drive kind and a DOF set, all of it dynamic; `None` if the set
    /// lacks a DOF the contact, the return spring or the output needs (y2, y3, y5).
    pub const fn try_new(drive: DriveKind, dofs: DofSet) -> Option<Layout> {
        Self::try_reduced(drive, dofs, DofSet::NONE)
    }

    /// The layout for a drive kind, the DOFs the model represents (`dofs`) and those of
    /// them it solves quasi-statically (`quasi`, [`crate::QuasiStatic`]: no state, no
    /// mass of their own). `None` unless `dofs` holds y2, y3 and y5, and a non-empty
    /// `quasi` is a run of the vertical chain [`QUASI_STATIC_CHAIN`] that starts at
    /// y1 or y2 and holds the roller y2, in a vertical scene (x1, x2, x3 dropped: their
    /// roller and cantilever would lose their masses too).
    pub const fn try_reduced(drive: DriveKind, dofs: DofSet, quasi: DofSet) -> Option<Layout> {
        if !(dofs.contains(TransDof::RollerY)
            && dofs.contains(TransDof::CantileverY)
            && dofs.contains(TransDof::Load))
        {
            return None;
        }
        if !quasi.is_empty() && !quasi_static_run_ok(dofs, quasi) {
            return None;
        }
        let dynamic = dofs.minus(quasi);
        let rotational = match drive {
            DriveKind::Regulated => 6,
            DriveKind::ConstantMotorSpeed => 5,
            DriveKind::ConstantCamSpeed => 0,
        };
        Some(Layout {
            drive,
            dofs: dynamic,
            quasi,
            rotational,
            states: rotational + 2 * dynamic.count(),
        })
    }

    /// The state length N.
    pub const fn states(&self) -> usize {
        self.states
    }
    /// The drive kind.
    pub const fn drive(&self) -> DriveKind {
        self.drive
    }
    /// The translational DOFs kept as states (dynamic: with their mass).
    pub const fn dofs(&self) -> DofSet {
        self.dofs
    }
    /// The translational DOFs solved quasi-statically (no state, no mass of their own).
    pub const fn quasi_static(&self) -> DofSet {
        self.quasi
    }
    /// Number of rotational state components (6, 5 or 0).
    pub const fn rotational_states(&self) -> usize {
        self.rotational
    }
    /// Degrees of freedom of the scene: the drive's free rotations plus the translations
    /// kept as states (11 for the full model; a quasi-static DOF is not one).
    pub const fn degrees_of_freedom(&self) -> usize {
        self.drive.rotational_dofs() + self.dofs.count()
    }

    /// The state index of `var`, or `None` when the scene does not carry it (a dropped
    /// DOF, or a quantity an ideal drive imposes).
    #[inline(always)]
    pub const fn index(&self, var: StateVar) -> Option<usize> {
        let r = self.rotational;
        // The regulated block extends the constant-motor-speed one by θ̇_m.
        match var {
            StateVar::CamAngle => Self::rot(0, r >= 5),
            StateVar::CouplingCamTwist => Self::rot(1, r >= 5),
            StateVar::MotorCouplingTwist => Self::rot(2, r >= 5),
            StateVar::CamSpeed => Self::rot(3, r >= 5),
            StateVar::CouplingSpeed => Self::rot(4, r >= 5),
            StateVar::MotorSpeed => Self::rot(5, r >= 6),
            StateVar::Position(dof) => self.trans(dof, r),
            StateVar::Velocity(dof) => self.trans(dof, r + self.dofs.count()),
        }
    }

    #[inline(always)]
    const fn rot(slot: usize, kept: bool) -> Option<usize> {
        if kept {
            Some(slot)
        } else {
            None
        }
    }

    #[inline(always)]
    const fn trans(&self, dof: TransDof, base: usize) -> Option<usize> {
        if self.dofs.contains(dof) {
            Some(base + self.dofs.count_before(dof))
        } else {
            None
        }
    }
}

/// The vertical chain from the cam to the load, in order: the quasi-static DOFs of a
/// reduced scene are a run of it (docs/MODEL.md §10).
pub const QUASI_STATIC_CHAIN: [TransDof; 5] = [
    TransDof::CamY,
    TransDof::RollerY,
    TransDof::CantileverY,
    TransDof::Follower,
    TransDof::Load,
];

/// Whether `quasi` is a run of [`QUASI_STATIC_CHAIN`] starting at y1 or y2, holding y2,
/// never the load y5, within a vertical `dofs` that holds the whole chain.
const fn quasi_static_run_ok(dofs: DofSet, quasi: DofSet) -> bool {
    if !(dofs.0 == DofSet::VERTICAL.0 && quasi.contains(TransDof::RollerY)) {
        return false;
    }
    if quasi.contains(TransDof::Load) || !dofs.includes(quasi) {
        return false;
    }
    // A run: once a DOF after y2 is dynamic, none further along is quasi-static.
    let cantilever = quasi.contains(TransDof::CantileverY);
    let follower = quasi.contains(TransDof::Follower);
    if follower && !cantilever {
        return false;
    }
    true
}

mod sealed {
    /// Scenes are defined in camsim-core only (the `scenes!` invocation), so their
    /// layout is the one [`super::Layout::try_new`] computes.
    pub trait Sealed {}
}

/// A model configuration fixed at compile time: which drive and which translational
/// DOFs, hence the state layout and its length. Implemented by the zero-sized scene
/// types of this module (sealed: a scene is defined in camsim-core).
pub trait Scene:
    sealed::Sealed + Copy + Default + core::fmt::Debug + Send + Sync + 'static
{
    /// The drive kind (a design's [`DriveLaw`](crate::DriveLaw) must be of this kind).
    const DRIVE: DriveKind;
    /// The translational DOFs the model represents (as states or quasi-statically).
    const DOFS: DofSet;
    /// Of [`Scene::DOFS`], those solved quasi-statically ([`crate::QuasiStatic`]): none
    /// for the full follower.
    const QUASI_STATIC: DofSet = DofSet::NONE;
    /// The state layout ([`Layout::try_reduced`]). A scene lacking y2, y3 or y5, or with a
    /// quasi-static set that is not a run of the vertical chain, does not compile: the
    /// `scenes!` definition asserts its layout at compile time (the trait is sealed, so
    /// every scene is one of those), and [`Layout::NONE`] here is never a scene's.
    const LAYOUT: Layout = match Layout::try_reduced(Self::DRIVE, Self::DOFS, Self::QUASI_STATIC) {
        Some(l) => l,
        None => Layout::NONE,
    };
    /// The state length N.
    const N: usize = Self::LAYOUT.states();
}

/// Compile-time proof that an `N`-component array holds a state of scene `S`.
struct Fits<S, const N: usize>(PhantomData<S>);

impl<S: Scene, const N: usize> Fits<S, N> {
    /// Evaluated when a view or model of (S, N) is monomorphised: a mismatch does not compile.
    const OK: () = assert!(
        N == S::LAYOUT.states(),
        "the state length N must equal the scene's S::N"
    );
}

/// Proves at compile time that `N` is scene `S`'s state length (used by every type that
/// indexes an `[T; N]` through `S::LAYOUT`).
#[inline(always)]
pub(crate) fn assert_fits<S: Scene, const N: usize>() {
    #[allow(clippy::let_unit_value)]
    let () = Fits::<S, N>::OK;
}

/// Named read access to a state vector of scene `S`.
#[derive(Clone, Copy, Debug)]
pub struct StateRef<'a, T, S, const N: usize> {
    y: &'a [T; N],
    scene: PhantomData<S>,
}

impl<'a, T: Real, S: Scene, const N: usize> StateRef<'a, T, S, N> {
    /// A view of `y`; `N` must equal `S::N` (a compile error otherwise).
    #[inline(always)]
    pub fn new(y: &'a [T; N]) -> Self {
        assert_fits::<S, N>();
        Self {
            y,
            scene: PhantomData,
        }
    }

    /// The value of `var`, or `None` when the scene does not carry it.
    #[inline(always)]
    pub fn get(&self, var: StateVar) -> Option<T> {
        // Every index the layout reports is below S::N, which `new` proved equal to N:
        // `get` cannot miss here (and with constant indices the check folds away).
        S::LAYOUT.index(var).and_then(|i| self.y.get(i).copied())
    }
    /// θ_c, rad (`None` under a constant cam speed: θ_c = ω0 t).
    #[inline(always)]
    pub fn cam_angle(&self) -> Option<T> {
        self.get(StateVar::CamAngle)
    }
    /// θ_cp - θ_c, rad.
    #[inline(always)]
    pub fn coupling_cam_twist(&self) -> Option<T> {
        self.get(StateVar::CouplingCamTwist)
    }
    /// θ_m - θ_cp, rad.
    #[inline(always)]
    pub fn motor_coupling_twist(&self) -> Option<T> {
        self.get(StateVar::MotorCouplingTwist)
    }
    /// θ̇_c, rad/s.
    #[inline(always)]
    pub fn cam_speed(&self) -> Option<T> {
        self.get(StateVar::CamSpeed)
    }
    /// θ̇_cp, rad/s.
    #[inline(always)]
    pub fn coupling_speed(&self) -> Option<T> {
        self.get(StateVar::CouplingSpeed)
    }
    /// θ̇_m, rad/s (`None` for the ideal drives, which hold it at ω0).
    #[inline(always)]
    pub fn motor_speed(&self) -> Option<T> {
        self.get(StateVar::MotorSpeed)
    }
    /// The stored displacement of `dof`, in (relative to the lift for the follower chain).
    #[inline(always)]
    pub fn position(&self, dof: TransDof) -> Option<T> {
        self.get(StateVar::Position(dof))
    }
    /// The velocity of `dof`, in/s.
    #[inline(always)]
    pub fn velocity(&self, dof: TransDof) -> Option<T> {
        self.get(StateVar::Velocity(dof))
    }
    /// Every stored displacement in [`TransDof`] order; a DOF the scene drops is held at 0.
    #[inline(always)]
    pub fn positions(&self) -> [T; TRANS_DOFS] {
        TransDof::ALL.map(|d| self.position(d).unwrap_or(T::ZERO))
    }
    /// Every velocity in [`TransDof`] order; a DOF the scene drops is held at 0.
    #[inline(always)]
    pub fn velocities(&self) -> [T; TRANS_DOFS] {
        TransDof::ALL.map(|d| self.velocity(d).unwrap_or(T::ZERO))
    }
}

/// Named write access to a state vector (or its derivative) of scene `S`.
#[derive(Debug)]
pub struct StateMut<'a, T, S, const N: usize> {
    y: &'a mut [T; N],
    scene: PhantomData<S>,
}

impl<'a, T: Real, S: Scene, const N: usize> StateMut<'a, T, S, N> {
    /// A view of `y`; `N` must equal `S::N` (a compile error otherwise).
    #[inline(always)]
    pub fn new(y: &'a mut [T; N]) -> Self {
        assert_fits::<S, N>();
        Self {
            y,
            scene: PhantomData,
        }
    }

    /// Sets `var` to `value`; returns false (and changes nothing) when the scene does not
    /// carry `var`, which the scene's consts decide at compile time.
    #[inline(always)]
    pub fn set(&mut self, var: StateVar, value: T) -> bool {
        // As in `StateRef::get`: the index is below S::N == N, `get_mut` cannot miss.
        match S::LAYOUT.index(var).and_then(|i| self.y.get_mut(i)) {
            Some(o) => {
                *o = value;
                true
            }
            None => false,
        }
    }
}

/// What a caller does with a scene chosen at run time ([`SceneId::visit`]): the one
/// dispatch from a scene's id to its type, so that a new scene is one line of `scenes!`.
pub trait SceneVisitor {
    /// What the visit returns.
    type Output;
    /// Called with the scene's type `S` and its state length `N = S::N`.
    fn visit<S: Scene, const N: usize>(self) -> Self::Output;
}

/// Defines each scene: its type, its `Scene` impl, its model alias and its [`SceneId`],
/// from its drive kind (a [`DriveKind`] variant) and its DOF set (a const [`DofSet`]
/// expression).
macro_rules! scenes {
    ($($(#[$doc:meta])* $scene:ident => $model:ident: $drive:ident, $dofs:expr $(, quasi-static $quasi:expr)?;)+) => {
        $(
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        pub struct $scene;
        impl sealed::Sealed for $scene {}
        impl Scene for $scene {
            const DRIVE: DriveKind = DriveKind::$drive;
            const DOFS: DofSet = $dofs;
            $(const QUASI_STATIC: DofSet = $quasi;)?
        }
        // Checked here, at compile time: a scene with an impossible layout does not compile.
        const _: () = assert!(
            Layout::try_reduced(
                <$scene as Scene>::DRIVE,
                <$scene as Scene>::DOFS,
                <$scene as Scene>::QUASI_STATIC
            )
            .is_some(),
            "a scene must keep y2, y3 and y5, and solve a run of the vertical chain quasi-statically"
        );
        #[doc = concat!("The model of the [`", stringify!($scene), "`] scene.")]
        pub type $model<T> = CamModel<T, $scene, { <$scene as Scene>::N }>;
        )+

        /// Every scene by name: the run-time handle of the scene types, with their
        /// properties and the dispatch to the type ([`SceneId::visit`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum SceneId {
            $(
            $(#[$doc])*
            $scene,
            )+
        }

        impl SceneId {
            /// Every scene, in the order of their definition.
            pub const ALL: &'static [SceneId] = &[$(SceneId::$scene),+];

            /// The scene's type name (for example `"RegulatedFull"`).
            pub const fn name(self) -> &'static str {
                match self { $(SceneId::$scene => stringify!($scene),)+ }
            }

            /// The scene's drive kind.
            pub const fn drive(self) -> DriveKind {
                match self { $(SceneId::$scene => <$scene as Scene>::DRIVE,)+ }
            }

            /// The translational DOFs the scene keeps.
            pub const fn dofs(self) -> DofSet {
                match self { $(SceneId::$scene => <$scene as Scene>::DOFS,)+ }
            }

            /// The DOFs the scene solves quasi-statically.
            pub const fn quasi_static(self) -> DofSet {
                match self { $(SceneId::$scene => <$scene as Scene>::QUASI_STATIC,)+ }
            }

            /// The scene's state length.
            pub const fn states(self) -> usize {
                match self { $(SceneId::$scene => <$scene as Scene>::N,)+ }
            }

            /// Calls `visitor` with the scene's type.
            pub fn visit<V: SceneVisitor>(self, visitor: V) -> V::Output {
                match self {
                    $(SceneId::$scene => visitor.visit::<$scene, { <$scene as Scene>::N }>(),)+
                }
            }
        }
    };
}

impl SceneId {
    /// The scene with this drive, these DOFs and these quasi-static DOFs, if one is
    /// defined.
    pub fn find(drive: DriveKind, dofs: DofSet, quasi_static: DofSet) -> Option<SceneId> {
        Self::ALL
            .iter()
            .copied()
            .find(|s| s.drive() == drive && s.dofs() == dofs && s.quasi_static() == quasi_static)
    }
}

scenes! {
    /// Regulated motor, all eleven DOFs: 6 + 2·8 = 22 states (the full model).
    RegulatedFull => RegulatedFullModel: Regulated, DofSet::ALL;
    /// Regulated motor, vertical motion only: 6 + 2·5 = 16 states (the chip's scene).
    RegulatedVertical => RegulatedVerticalModel: Regulated, DofSet::VERTICAL;
    /// Motor held at ω0, all translational DOFs: 5 + 2·8 = 21 states.
    ConstMotorFull => ConstMotorFullModel: ConstantMotorSpeed, DofSet::ALL;
    /// Motor held at ω0, vertical motion only: 5 + 2·5 = 15 states.
    ConstMotorVertical => ConstMotorVerticalModel: ConstantMotorSpeed, DofSet::VERTICAL;
    /// Cam held at ω0 (rigid drive), all translational DOFs: 2·8 = 16 states.
    ConstCamFull => ConstCamFullModel: ConstantCamSpeed, DofSet::ALL;
    /// Cam held at ω0 (rigid drive), vertical motion only: 2·5 = 10 states.
    ConstCamVertical => ConstCamVerticalModel: ConstantCamSpeed, DofSet::VERTICAL;
    /// Regulated motor, vertical, massless roller: the Hertz contact and K_rb in series
    /// (docs/MODEL.md §10): 6 + 2·4 = 14 states.
    RegulatedMasslessRoller => RegulatedMasslessRollerModel: Regulated, DofSet::VERTICAL,
        quasi-static QuasiStatic::ROLLER;
    /// Regulated motor, vertical, roller and cantilever portion quasi-static: 6 + 2·3 = 12
    /// states.
    RegulatedQsCantilever => RegulatedQsCantileverModel: Regulated, DofSet::VERTICAL,
        quasi-static QuasiStatic::CANTILEVER;
    /// Regulated motor, vertical, roller, cantilever and follower rod quasi-static (the
    /// follower train's mass rides on the load): 6 + 2·2 = 10 states.
    RegulatedQsRod => RegulatedQsRodModel: Regulated, DofSet::VERTICAL,
        quasi-static QuasiStatic::ROD;
    /// Regulated motor, vertical, the whole chain from the cam shaft to the rod
    /// quasi-static: the drive and the load are left, 6 + 2·1 = 8 states.
    RegulatedQsShaft => RegulatedQsShaftModel: Regulated, DofSet::VERTICAL,
        quasi-static QuasiStatic::SHAFT;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every quantity a layout keeps has its own index, and together they fill 0..N.
    fn check<S: Scene>(n: usize, dof_count: usize) {
        let l = S::LAYOUT;
        assert_eq!(S::N, n);
        assert_eq!(l.degrees_of_freedom(), dof_count);
        let mut seen = [false; 32];
        let mut vars = StateVar::ROTATIONAL.to_vec();
        for d in TransDof::ALL {
            vars.push(StateVar::Position(d));
            vars.push(StateVar::Velocity(d));
        }
        for v in vars {
            if let Some(i) = l.index(v) {
                assert!(i < n, "{v:?} at {i}");
                assert!(!seen[i], "{v:?}: index {i} twice");
                seen[i] = true;
            }
        }
        assert!(seen[..n].iter().all(|s| *s), "{:?}", &seen[..n]);
    }

    #[test]
    fn scenes_have_the_documented_sizes_and_their_indices_fill_the_state() {
        check::<RegulatedFull>(22, 11);
        check::<RegulatedVertical>(16, 8);
        check::<ConstMotorFull>(21, 10);
        check::<ConstMotorVertical>(15, 7);
        check::<ConstCamFull>(16, 8);
        check::<ConstCamVertical>(10, 5);
    }

    #[test]
    fn layout_places_the_documented_quantities() {
        let l = RegulatedVertical::LAYOUT;
        assert_eq!(l.index(StateVar::CamAngle), Some(0));
        assert_eq!(l.index(StateVar::MotorSpeed), Some(5));
        // y1, y2, y3, y4, y5 then their velocities.
        assert_eq!(l.index(StateVar::Position(TransDof::CamY)), Some(6));
        assert_eq!(l.index(StateVar::Position(TransDof::RollerY)), Some(7));
        assert_eq!(l.index(StateVar::Position(TransDof::RollerX)), None);
        assert_eq!(l.index(StateVar::Position(TransDof::Load)), Some(10));
        assert_eq!(l.index(StateVar::Velocity(TransDof::CamY)), Some(11));
        assert_eq!(l.index(StateVar::Velocity(TransDof::Load)), Some(15));
        let m = ConstMotorFull::LAYOUT;
        assert_eq!(m.index(StateVar::MotorCouplingTwist), Some(2));
        assert_eq!(m.index(StateVar::MotorSpeed), None);
        assert_eq!(m.index(StateVar::Position(TransDof::CamX)), Some(6));
        let c = ConstCamVertical::LAYOUT;
        assert_eq!(c.index(StateVar::CamAngle), None);
        assert_eq!(c.index(StateVar::Position(TransDof::CamY)), Some(0));
        assert_eq!(DofSet::VERTICAL.count(), 5);
        assert_eq!(DofSet::VERTICAL.name(), "vertical");
    }

    #[test]
    fn a_set_without_the_contact_spring_or_output_dofs_has_no_layout() {
        for d in [TransDof::RollerY, TransDof::CantileverY, TransDof::Load] {
            assert_eq!(
                Layout::try_new(DriveKind::Regulated, DofSet::VERTICAL.without(d)),
                None
            );
        }
        assert!(Layout::try_new(
            DriveKind::Regulated,
            DofSet::VERTICAL.without(TransDof::CamY)
        )
        .is_some());
    }

    /// The ids describe their types, each (drive, DOFs, quasi-static DOFs) is one scene,
    /// and a visit reaches the id's own type.
    #[test]
    fn scene_ids_match_their_types_and_are_found_by_their_properties() {
        struct States;
        impl SceneVisitor for States {
            type Output = (usize, usize, DofSet);
            fn visit<S: Scene, const N: usize>(self) -> Self::Output {
                (S::N, N, S::DOFS)
            }
        }
        assert_eq!(SceneId::ALL.len(), 10);
        for &id in SceneId::ALL {
            assert_eq!(id.visit(States), (id.states(), id.states(), id.dofs()));
            assert_eq!(
                SceneId::find(id.drive(), id.dofs(), id.quasi_static()),
                Some(id)
            );
        }
        assert_eq!(SceneId::RegulatedFull.states(), 22);
        assert_eq!(SceneId::RegulatedQsRod.states(), 10);
        assert_eq!(SceneId::RegulatedQsRod.name(), "RegulatedQsRod");
        assert_eq!(
            SceneId::find(DriveKind::ConstantCamSpeed, DofSet::ALL, QuasiStatic::ROD),
            None
        );
    }

    #[test]
    fn views_read_and_write_by_name() {
        let mut y = [0.0f64; 16];
        let mut w = StateMut::<f64, RegulatedVertical, 16>::new(&mut y);
        assert!(w.set(StateVar::Velocity(TransDof::Load), 3.0));
        assert!(!w.set(StateVar::Velocity(TransDof::CamX), 4.0));
        assert!(w.set(StateVar::CouplingCamTwist, 1e-4));
        assert_eq!(y[15], 3.0);
        assert_eq!(y[1], 1e-4);
        assert_eq!(y.iter().filter(|v| **v != 0.0).count(), 2);
        let r = StateRef::<f64, RegulatedVertical, 16>::new(&y);
        assert_eq!(r.velocity(TransDof::Load), Some(3.0));
        assert_eq!(r.velocity(TransDof::CamX), None);
        assert_eq!(TransDof::Load.of(&r.velocities()), 3.0);
        assert_eq!(TransDof::RollerX.of(&[0, 1, 2, 3, 4, 5, 6, 7]), 3);
        assert_eq!(r.coupling_cam_twist(), Some(1e-4));
    }
}
