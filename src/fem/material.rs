//! Isotropic Hooke's law in plane strain and plane stress (Voigt notation).
//!
//! Voigt vectors: stress `s = (σxx, σyy, σxy)`, strain `e = (εxx, εyy, γxy)` with the
//! engineering shear `γxy = 2 εxy`, so that `s · e = σ : ε`.
//!
//! Plane strain (`εzz = 0`), with `λ = Eν / ((1 + ν)(1 − 2ν))`, `μ = E / (2(1 + ν))`:
//!
//! ```text
//!         E          [ 1 − ν    ν        0      ]
//!   C = --------------[   ν    1 − ν      0      ] ,   σzz = ν (σxx + σyy)
//!     (1 + ν)(1 − 2ν) [   0      0   (1 − 2ν)/2  ]
//! ```
//!
//! Plane stress (`σzz = 0`):
//!
//! ```text
//!         E    [ 1  ν     0     ]
//!   C = ------ [ ν  1     0     ] ,   σzz = 0
//!       1 − ν² [ 0  0  (1 − ν)/2 ]
//! ```
//!
//! Both have the form `[[λ* + 2μ, λ*, 0], [λ*, λ* + 2μ, 0], [0, 0, μ]]` with the in-plane
//! `λ* = λ` (plane strain) or `λ* = 2λμ / (λ + 2μ) = Eν / (1 − ν²)` (plane stress).
//!
//! Compliance `C⁻¹` and the complementary energy density `w*(σ) = ½ s · C⁻¹ s`
//! (the compliance form of Hooke's law, as in the dual formulation of F. Lebon's talk "Modèles d'interface et formulations pour le contact frottant"):
//!
//! ```text
//!   plane strain: w* = (1 + ν)/(2E) [ (1 − ν)(σxx² + σyy²) − 2ν σxx σyy + 2 σxy² ]
//!   plane stress: w* = 1/(2E) [ σxx² + σyy² − 2ν σxx σyy + 2(1 + ν) σxy² ]
//! ```
//!
//! The von Mises stress includes σzz (nonzero in plane strain):
//! `σ_vm = √( ½[(σxx − σyy)² + (σyy − σzz)² + (σzz − σxx)²] + 3 σxy² )`.
//!
//! Axisymmetric (a body of revolution under loads without torsion, in the meridian half-plane
//! `(r, z) = (x, y)`): the strain has a fourth component, the hoop strain `εθθ = u_r / r`, and
//! Hooke's law is the 3D one on `e = (εrr, εzz, γrz, εθθ)`:
//!
//! ```text
//!       [ λ + 2μ    λ      0     λ    ]
//!   C = [   λ     λ + 2μ   0     λ    ] ,   σθθ = λ (εrr + εzz + εθθ) + 2μ εθθ
//!       [   0       0      μ     0    ]
//!       [   λ       λ      0   λ + 2μ ]
//! ```
//!
//! with the 3D `λ` of plane strain. The in-plane block `(rr, zz, rz)` equals plane strain's, so
//! [`Material::elasticity`] and [`Material::lame`] return it; the hoop row enters through
//! [`Material::axisymmetric_stress`] (Zienkiewicz, Taylor, Zhu, *The Finite Element Method: Its
//! Basis and Fundamentals*, 7th ed., Butterworth-Heinemann 2013, §6.2 "Axisymmetric stress
//! analysis"; Hughes, *The Finite Element Method*, §2.12).
//!
//! References: S. Timoshenko, J. N. Goodier, *Theory of Elasticity*, 3rd ed., McGraw-Hill 1970,
//! §§8–17 (plane stress / plane strain); T. J. R. Hughes, *The Finite Element Method*, Dover 2000,
//! §2.7 (the Voigt matrices above).

/// Which 2D reduction of 3D elasticity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PlaneModel {
    /// `εzz = 0` (thick bodies; the default of the project).
    Strain,
    /// `σzz = 0` (thin plates).
    Stress,
    /// A body of revolution in its meridian half-plane `(r, z) = (x, y)`, `r ≥ 0`: the hoop
    /// strain `u_r / r` joins the in-plane strains (see the module doc).
    Axisymmetric,
}

impl PlaneModel {
    /// The name the scene, the summary and `report.json` use: "strain", "stress", "axisymmetric".
    pub fn name(self) -> &'static str {
        match self {
            PlaneModel::Strain => "strain",
            PlaneModel::Stress => "stress",
            PlaneModel::Axisymmetric => "axisymmetric",
        }
    }
}

/// An isotropic linear elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E (> 0).
    pub young: f64,
    /// Poisson's ratio ν (−1 < ν < 0.5).
    pub poisson: f64,
    /// Plane strain or plane stress.
    pub plane: PlaneModel,
}

/// The material of every cell of a mesh: one for all cells (a single body), or one per body of
/// a scene with several bodies (the union mesh of [`crate::mesh::union`]).
#[derive(Debug, Clone, PartialEq)]
pub struct CellMaterials {
    materials: Vec<Material>,
    /// Index into `materials` of each cell; empty when there is one material.
    of_cell: Vec<usize>,
}

impl CellMaterials {
    /// Every cell of `material`.
    pub fn uniform(material: Material) -> Self {
        CellMaterials { materials: vec![material], of_cell: Vec::new() }
    }

    /// Cell `c` of `materials[of_cell[c]]`. Errors when an index is out of range or no
    /// material is given.
    pub fn per_cell(materials: Vec<Material>, of_cell: Vec<usize>) -> crate::error::Result<Self> {
        if materials.is_empty() {
            return Err(crate::error::Error::Usage("CellMaterials::per_cell: no material".into()));
        }
        if let Some((cell, &k)) = of_cell.iter().enumerate().find(|(_, &k)| k >= materials.len()) {
            return Err(crate::error::Error::Usage(format!(
                "CellMaterials::per_cell: cell {cell} has material {k}, but only {} are given",
                materials.len()
            )));
        }
        Ok(CellMaterials { materials, of_cell })
    }

    /// The distinct materials, in order.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The index (in [`CellMaterials::materials`]) of the material of `cell`.
    pub fn index_of(&self, cell: usize) -> usize {
        self.of_cell.get(cell).copied().unwrap_or(0)
    }

    /// The material of `cell`.
    pub fn of(&self, cell: usize) -> &Material {
        &self.materials[self.index_of(cell)]
    }

    /// The largest Young's modulus (the scale of the Dirichlet rows).
    pub fn max_young(&self) -> f64 {
        self.materials.iter().map(|m| m.young).fold(0.0, f64::max)
    }
}

impl Material {
    /// The material of Young's modulus `young` (Pa), Poisson's ratio `poisson`, under `plane`.
    pub fn new(young: f64, poisson: f64, plane: PlaneModel) -> Self {
        Material { young, poisson, plane }
    }

    /// `Ok` when `E > 0` is finite and `−1 < ν < 0.5`; otherwise what is wrong and what to do.
    pub fn check(&self) -> std::result::Result<(), String> {
        if !(self.young.is_finite() && self.young > 0.0) {
            return Err(format!(
                "Young's modulus must be a finite positive number, got {}; give E in Pa (e.g. 2.1e11 for steel)",
                self.young
            ));
        }
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(format!(
                "Poisson's ratio must satisfy -1 < nu < 0.5, got {}; nu = 0.5 (incompressible) is not supported by the displacement formulation",
                self.poisson
            ));
        }
        Ok(())
    }

    /// Shear modulus `μ = E / (2(1 + ν))`.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// The plane modulus `E' = E / (1 − ν²)` (plane strain) or `E` (plane stress): the
    /// stiffness of the model against a uniaxial in-plane strain with the other in-plane
    /// component free.
    pub fn plane_modulus(&self) -> f64 {
        match self.plane {
            PlaneModel::Strain | PlaneModel::Axisymmetric => self.young / (1.0 - self.poisson * self.poisson),
            PlaneModel::Stress => self.young,
        }
    }

    /// In-plane Lamé parameters `(λ*, μ)` of the model (see the module doc; the 3D `λ` in plane
    /// strain and in axisymmetry).
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        let mu = self.shear_modulus();
        let lambda = match self.plane {
            PlaneModel::Strain | PlaneModel::Axisymmetric => e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            PlaneModel::Stress => e * nu / (1.0 - nu * nu),
        };
        (lambda, mu)
    }

    /// Elasticity matrix `C` (σ = C e in Voigt notation, engineering shear strain).
    pub fn elasticity(&self) -> [[f64; 3]; 3] {
        let (lambda, mu) = self.lame();
        [[lambda + 2.0 * mu, lambda, 0.0], [lambda, lambda + 2.0 * mu, 0.0], [0.0, 0.0, mu]]
    }

    /// Compliance matrix `C⁻¹` (e = C⁻¹ σ).
    pub fn compliance(&self) -> [[f64; 3]; 3] {
        let (e, nu) = (self.young, self.poisson);
        match self.plane {
            PlaneModel::Strain | PlaneModel::Axisymmetric => {
                let f = (1.0 + nu) / e;
                [[f * (1.0 - nu), -f * nu, 0.0], [-f * nu, f * (1.0 - nu), 0.0], [0.0, 0.0, 2.0 * f]]
            }
            PlaneModel::Stress => [[1.0 / e, -nu / e, 0.0], [-nu / e, 1.0 / e, 0.0], [0.0, 0.0, 2.0 * (1.0 + nu) / e]],
        }
    }

    /// Stress `(σxx, σyy, σxy)` from the strain `(εxx, εyy, γxy)`.
    pub fn stress(&self, strain: [f64; 3]) -> [f64; 3] {
        let c = self.elasticity();
        [
            c[0][0] * strain[0] + c[0][1] * strain[1] + c[0][2] * strain[2],
            c[1][0] * strain[0] + c[1][1] * strain[1] + c[1][2] * strain[2],
            c[2][0] * strain[0] + c[2][1] * strain[1] + c[2][2] * strain[2],
        ]
    }

    /// Out-of-plane stress: `ν (σxx + σyy)` in plane strain, 0 in plane stress. In axisymmetry
    /// the out-of-plane stress is the hoop stress, which needs the hoop strain: use
    /// [`Material::axisymmetric_stress`]; this returns the plane strain value (`εθθ = 0`).
    pub fn sigma_zz(&self, s: [f64; 3]) -> f64 {
        match self.plane {
            PlaneModel::Strain | PlaneModel::Axisymmetric => self.poisson * (s[0] + s[1]),
            PlaneModel::Stress => 0.0,
        }
    }

    /// Axisymmetric stress `((σrr, σzz, σrz), σθθ)` from the strain `(εrr, εzz, γrz)` and the hoop
    /// strain `εθθ = u_r / r` (module doc).
    pub fn axisymmetric_stress(&self, strain: [f64; 3], hoop: f64) -> ([f64; 3], f64) {
        let (lambda, mu) = self.lame();
        let trace = strain[0] + strain[1] + hoop;
        (
            [lambda * trace + 2.0 * mu * strain[0], lambda * trace + 2.0 * mu * strain[1], mu * strain[2]],
            lambda * trace + 2.0 * mu * hoop,
        )
    }

    /// Von Mises equivalent stress, including σzz.
    pub fn von_mises(&self, s: [f64; 3]) -> f64 {
        let szz = self.sigma_zz(s);
        let (sxx, syy, sxy) = (s[0], s[1], s[2]);
        (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2)) + 3.0 * sxy * sxy).sqrt()
    }

    /// Complementary (compliance) energy density `w*(σ) = ½ σ : C⁻¹ σ` (the complementary energy of the dual formulation).
    pub fn complementary_energy_density(&self, s: [f64; 3]) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        let (sxx, syy, sxy) = (s[0], s[1], s[2]);
        match self.plane {
            PlaneModel::Strain | PlaneModel::Axisymmetric => {
                (1.0 + nu) / (2.0 * e) * ((1.0 - nu) * (sxx * sxx + syy * syy) - 2.0 * nu * sxx * syy + 2.0 * sxy * sxy)
            }
            PlaneModel::Stress => {
                (sxx * sxx + syy * syy - 2.0 * nu * sxx * syy + 2.0 * (1.0 + nu) * sxy * sxy) / (2.0 * e)
            }
        }
    }

    /// Strain energy density `w(ε) = ½ e · C e`.
    pub fn strain_energy_density(&self, strain: [f64; 3]) -> f64 {
        let s = self.stress(strain);
        0.5 * (s[0] * strain[0] + s[1] * strain[1] + s[2] * strain[2])
    }
}
