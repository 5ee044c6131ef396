//! Interface laws of a contact (`[contact.interface]`, `[contact_pair.interface]`): what the
//! interface transmits beyond Signorini and Coulomb. The laws themselves are in
//! [`crate::interface_law`]; this module holds what the scene says of them.
use crate::error::Location;

/// The interface law of one contact (a body on a rigid obstacle, or a pair of bodies).
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceSpec {
    /// The law and its parameters.
    pub law: InterfaceLawSpec,
    /// `trace = [[x, y], ...]`: the points whose τ–δ history is plotted (the contact point
    /// nearest to each); empty: the default (the first, middle and last contact points).
    pub trace: Vec<[f64; 2]>,
    /// Where the interface table starts (for errors found later).
    pub at: Location,
}

/// The interface laws (`law = "thin_layer" | "rccm" | "cohesive_joint"`).
#[derive(Debug, Clone, PartialEq)]
pub enum InterfaceLawSpec {
    /// A thin elastic layer between the faces (an imperfect interface).
    ThinLayer(ThinLayerSpec),
    /// Adhesion with unilateral contact and friction (Raous, Cangémi, Cocou 1999).
    Rccm(RccmSpec),
    /// A cohesive–frictional joint (masonry): Mohr–Coulomb with a tensile cut-off, cohesion and
    /// tensile strength softening to pure Coulomb friction.
    CohesiveJoint(CohesiveJointSpec),
}

/// `law = "thin_layer"`: a layer of thickness `e` of an elastic material (E, ν) between the two
/// faces, modelled by springs: `t_N = K_N [u_N]`, `t_T = K_T [u_T]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinLayerSpec {
    /// `young`: the layer's Young's modulus (Pa), > 0.
    pub young: f64,
    /// `poisson`: the layer's Poisson's ratio, in (−1, 0.5).
    pub poisson: f64,
    /// `thickness`: the layer's thickness e (m), > 0.
    pub thickness: f64,
    /// `bonded`: glued on both faces (springs in tension and compression, no friction; the
    /// default `true`); `false`: a cut layer, in unilateral contact with the other face, with the
    /// contact's friction law.
    pub bonded: bool,
}

/// `law = "rccm"`: the Raous–Cangémi–Cocou–Monerie adhesion model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RccmSpec {
    /// `normal_stiffness` C_N (Pa/m), > 0: the adhesive's normal stiffness at β = 1.
    pub normal_stiffness: f64,
    /// `tangential_stiffness` C_T (Pa/m), > 0.
    pub tangential_stiffness: f64,
    /// `adhesion_energy` w (J/m²), > 0: the Dupré energy, the decohesion threshold.
    pub adhesion_energy: f64,
    /// `viscosity` b (J·s/m²), ≥ 0: 0 is the rate-independent limit.
    pub viscosity: f64,
    /// `mu`: the friction coefficient μ ≥ 0 (acting on the debonded fraction, `μ (1 − β)`).
    pub mu: f64,
    /// `initial_adhesion` β0 in [0, 1] (the default 1: fully glued).
    pub initial_adhesion: f64,
}

/// `law = "cohesive_joint"`: Mohr–Coulomb `|τ| ≤ c + μ σ` with a tensile strength, both softening
/// exponentially with the fracture energies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveJointSpec {
    /// `cohesion` c0 (Pa), ≥ 0.
    pub cohesion: f64,
    /// `tensile_strength` f_t0 (Pa), ≥ 0, at most `cohesion / mu`.
    pub tensile_strength: f64,
    /// `mu`: the friction coefficient μ ≥ 0.
    pub mu: f64,
    /// `fracture_energy_tension` G_I (J/m²), > 0.
    pub fracture_energy_tension: f64,
    /// `fracture_energy_shear` G_II (J/m²), > 0.
    pub fracture_energy_shear: f64,
}
