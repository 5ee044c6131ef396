//! # The thin elastic layer (an imperfect interface)
//!
//! A layer of thickness `e` of an isotropic elastic material (E, ν; Lamé constants λ, μ_L)
//! between the body and the obstacle (or the other body), soft compared with its neighbours or
//! thin compared with the bodies, is replaced by the surface between the two faces with the
//! law of springs
//!
//! ```text
//!   t_N = K_N [u_N],   t_T = K_T [u_T]
//!   K_N = (λ + 2 μ_L) / e = E (1 − ν) / ((1 + ν)(1 − 2ν) e)     (plane strain)
//!   K_N = E / ((1 − ν²) e)                                      (plane stress: σ_zz = 0 in the layer)
//!   K_T = μ_L / e = E / (2 (1 + ν) e)
//! ```
//!
//! `[u]` the jump of the displacement across the layer (the body's relative to the other side)
//! and `t` the traction the layer exerts on the body (`t = −K [u]`: pulled back when the jump
//! opens). This is the leading term of the asymptotic expansion in `e` of the layer's
//! equilibrium, the through-thickness strain being `[u]/e` and the in-plane one negligible:
//! M. Goland and E. Reissner, "The stresses in cemented joints", J. Appl. Mech. 11 (1944)
//! A17–A27 (the springs of the adhesive in a lap joint); A. Klarbring, "Derivation of a model of
//! adhesively bonded joints by the asymptotic expansion method", Int. J. Engng Sci. 29 (1991)
//! 493–512 (the limit of a layer of thickness e with moduli of order e: `σ_{i3} = K_{ij} [u_j]`
//! with the constants above); F. Lebon and R. Rizzoni, "Asymptotic analysis of a thin
//! interface: the case involving similar rigidity", Int. J. Engng Sci. 48 (2010) 473–486 (the
//! same springs for a layer as stiff as the bodies, the next order's corrections, and the
//! error `O(e)` of the soft model measured by the layer lane against the layer meshed in
//! full). In plane stress the layer's normal modulus is the plane-stress one, `E/(1−ν²)`,
//! the stiffness of a fibre across the layer free to contract out of plane.
//!
//! ## Bonded and cut layers
//!
//! - **bonded** (`bonded = true`, the default): glued on both faces, it transmits tension and
//!   compression; at a point of weight `w` it is two parallel springs `k = K w`
//!   (`PointModification::stiffness`), with no unilateral contact (`contact = false`) and no
//!   friction. The springs' rest state is the initial configuration: `spring_offset =
//!   (g0, slip_before)`, so that the normal spring force is `−k_N (u_N − d_N)` (the layer fills
//!   the initial gap `g0` unstressed) and the tangential one `−k_T` times the whole tangential
//!   jump since the start of the path.
//! - **cut** (`bonded = false`): the layer sticks to the body and touches the other face, in
//!   unilateral contact with the contact's friction law: the series compliance
//!   `c = 1/(K w)` (`PointModification::compliance`), the unilateral law acting on
//!   `u' = u + c r` (the jump minus the layer's elastic deformation). As `K → ∞` it is Signorini
//!   and Coulomb (tested to 1e-8); in compression and sticking everywhere it equals the bonded
//!   layer.
//!
//! The law has no internal variables (no memory): a static run solves it in one solve.
//!
//! ## Its own residual
//!
//! Bonded: `|r − (k_N (opening − g0), −k_T slip)|` relative to the larger of `|r|` and
//! `k |jump|`. Cut: the layer in series transmits the contact force whole and in compression
//! (`r = r'`, `rN ≤ 0`), relative to `|r|`; Signorini and friction on `(r', u' = u + c r)` are
//! checked by the contact check of the modified problem ([`super::condensed`]) on the scales
//! of the whole contact (a point alone has no displacement scale).
use super::{InterfaceLaw, InterfaceOutputs, InterfacePoint, PointFriction, PointModification, PointSolution};
use crate::fem::material::PlaneModel;
use crate::scene::ThinLayerSpec;

/// A thin elastic layer: its stiffnesses per unit area and whether it is bonded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinLayer {
    /// The scene's parameters.
    pub spec: ThinLayerSpec,
    /// `K_N` (Pa/m).
    pub normal_stiffness: f64,
    /// `K_T` (Pa/m).
    pub tangential_stiffness: f64,
}

impl ThinLayer {
    /// The layer of `spec` in the plane model `plane` (module documentation).
    pub fn new(spec: &ThinLayerSpec, plane: PlaneModel) -> Self {
        let (e, nu, h) = (spec.young, spec.poisson, spec.thickness);
        let shear = e / (2.0 * (1.0 + nu));
        let normal_modulus = match plane {
            PlaneModel::Strain | PlaneModel::Axisymmetric => e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            PlaneModel::Stress => e / (1.0 - nu * nu),
        };
        ThinLayer { spec: *spec, normal_stiffness: normal_modulus / h, tangential_stiffness: shear / h }
    }
}

impl InterfaceLaw for ThinLayer {
    fn name(&self) -> &'static str {
        "thin_layer"
    }

    fn has_memory(&self) -> bool {
        false
    }

    fn initial(&self) -> Vec<f64> {
        Vec::new()
    }

    fn modification(
        &self,
        point: &InterfacePoint,
        friction: PointFriction,
        _trial: &[f64],
        _last: Option<&PointSolution>,
    ) -> PointModification {
        let k = [self.normal_stiffness * point.weight, self.tangential_stiffness * point.weight];
        if self.spec.bonded {
            PointModification {
                compliance: [0.0; 2],
                stiffness: k,
                spring_offset: [point.gap, point.slip_before],
                force_offset: [0.0; 2],
                contact: false,
                friction: PointFriction::None,
            }
        } else {
            PointModification { compliance: [1.0 / k[0], 1.0 / k[1]], ..PointModification::plain(friction) }
        }
    }

    fn update(&self, _point: &InterfacePoint, committed: &[f64], _solution: &PointSolution, _dt: f64) -> Vec<f64> {
        committed.to_vec()
    }

    fn residual(
        &self,
        point: &InterfacePoint,
        _committed: &[f64],
        _state: &[f64],
        solution: &PointSolution,
        _dt: f64,
    ) -> f64 {
        let k = [self.normal_stiffness * point.weight, self.tangential_stiffness * point.weight];
        let [rn, rt] = solution.force;
        if self.spec.bonded {
            let expected = [k[0] * (solution.opening - point.gap), -k[1] * solution.slip];
            let scale = rn.abs().max(rt.abs()).max(expected[0].abs()).max(expected[1].abs());
            if scale == 0.0 {
                return 0.0;
            }
            ((rn - expected[0]).abs().max((rt - expected[1]).abs())) / scale
        } else {
            // In series the layer transmits the contact force whole (r = r'), compressive.
            let [cn, ct] = solution.contact_force;
            let scale = rn.abs().max(rt.abs()).max(cn.abs()).max(ct.abs());
            if scale == 0.0 {
                return 0.0;
            }
            (rn.max(0.0).max((rn - cn).abs()).max((rt - ct).abs())) / scale
        }
    }

    fn outputs(&self, _state: &[f64]) -> InterfaceOutputs {
        InterfaceOutputs::default()
    }
}
