//! Interface laws of a contact (`[contact.interface]`, `[contact_pair.interface]`): what the
//! interface transmits beyond Signorini and Coulomb. The laws themselves are in
//! [`crate::interface_law`]; this module holds what the scene says of them.
use super::convert::Table;
use super::diagnostic::Source;
use super::raw::{Leaf, RawInterface};
use crate::error::{Location, Result};
use toml::{Spanned, Value};

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

impl InterfaceLawSpec {
    /// The law's name in a scene (`law = "..."`).
    pub fn name(&self) -> &'static str {
        match self {
            InterfaceLawSpec::ThinLayer(_) => "thin_layer",
            InterfaceLawSpec::Rccm(_) => "rccm",
            InterfaceLawSpec::CohesiveJoint(_) => "cohesive_joint",
        }
    }

    /// Whether the law has internal variables that evolve along a load path (RCCM's adhesion,
    /// the joint's softening): such a law needs `[evolution]`.
    pub fn has_memory(&self) -> bool {
        !matches!(self, InterfaceLawSpec::ThinLayer(_))
    }

    /// Whether the contact's own friction (`friction`, `mu`, `threshold` of `[contact]` or
    /// `[[contact_pair]]`) applies: only for a cut thin layer (`bonded = false`). RCCM and the
    /// joint carry their friction coefficient in the law (`mu`), a bonded layer has none.
    pub fn takes_contact_friction(&self) -> bool {
        matches!(self, InterfaceLawSpec::ThinLayer(ThinLayerSpec { bonded: false, .. }))
    }
}

// ---- conversion -------------------------------------------------------------------------------

/// The laws a scene may name.
pub(super) const LAWS: &[&str] = &["thin_layer", "rccm", "cohesive_joint"];
const THIN_LAYER_KEYS: &[&str] = &["young", "poisson", "thickness", "bonded"];
const RCCM_KEYS: &[&str] =
    &["normal_stiffness", "tangential_stiffness", "adhesion_energy", "viscosity", "mu", "initial_adhesion"];
const JOINT_KEYS: &[&str] = &["cohesion", "tensile_strength", "mu", "fracture_energy_tension", "fracture_energy_shear"];

/// The parameter keys of `law` (besides `law` and `trace`, which every law takes).
fn law_keys(law: &str) -> &'static [&'static str] {
    match law {
        "thin_layer" => THIN_LAYER_KEYS,
        "rccm" => RCCM_KEYS,
        _ => JOINT_KEYS,
    }
}

/// The contact's own friction keys (`friction`, `mu`, `threshold` of the `[contact]` or
/// `[[contact_pair]]` table that holds the interface), checked against the law.
pub(super) struct ContactFrictionKeys<'r> {
    pub friction: &'r Leaf,
    pub mu: &'r Leaf,
    pub threshold: &'r Leaf,
    /// How messages name the contact table: `[contact]`, `this [[contact_pair]]`.
    pub table: String,
}

/// Convert and check an interface table. `table` locates and names it (`[contact.interface]`,
/// found by its header or its first key); `friction` are the keys of the contact holding it (a
/// friction there is refused with a law that has its own, or none).
pub(super) fn interface_spec(
    src: &Source,
    table: &Table,
    raw: &RawInterface,
    friction: &ContactFrictionKeys,
) -> Result<InterfaceSpec> {
    let at = src.location(table.span.start);
    let law_v = table.require(
        &raw.law,
        "law",
        "law = \"thin_layer\" (or \"rccm\", \"cohesive_joint\"; see \"Interface laws\" in docs/scene-format.md)",
    )?;
    let law = src.choice(law_v, "law", LAWS)?;
    let allowed = law_keys(law);
    let misplaced = raw.present_keys().into_iter().find(|(k, _)| *k != "law" && *k != "trace" && !allowed.contains(k));
    if let Some((key, span)) = misplaced {
        let owners: Vec<String> =
            LAWS.iter().filter(|l| law_keys(l).contains(&key)).map(|l| format!("law = \"{l}\"")).collect();
        return Err(src.error(
            &span,
            format!("`{key}` does not apply to law = \"{law}\""),
            format!(
                "`{key}` is a parameter of {}; law = \"{law}\" takes {} (and `trace`): remove `{key}`, or change the law",
                owners.join(" and "),
                allowed.join(", ")
            ),
        ));
    }
    let table =
        Table { src: table.src, name: format!("{} with law = \"{law}\"", table.name), span: table.span.clone() };
    let spec = match law {
        "thin_layer" => InterfaceLawSpec::ThinLayer(thin_layer(src, &table, raw)?),
        "rccm" => InterfaceLawSpec::Rccm(rccm(src, &table, raw)?),
        _ => InterfaceLawSpec::CohesiveJoint(cohesive_joint(src, &table, raw)?),
    };
    let trace = match &raw.trace {
        Some(v) => {
            let points = src.points(v, "trace")?;
            if points.is_empty() {
                return Err(src.error(
                    &v.span(),
                    "`trace` holds no point",
                    "give the points whose τ–δ curves are plotted, e.g. trace = [[0.0, 0.0], [0.5, 0.0]] (the \
                     contact point nearest each), or remove `trace` for the default (the first, middle and last \
                     contact points)",
                ));
            }
            points
        }
        None => Vec::new(),
    };
    check_contact_friction(src, &spec, friction)?;
    Ok(InterfaceSpec { law: spec, trace, at })
}

/// A friction on the contact is refused with RCCM and the joint (their `mu` is the law's) and
/// with a bonded thin layer (glued: no slip, no friction).
fn check_contact_friction(src: &Source, law: &InterfaceLawSpec, keys: &ContactFrictionKeys) -> Result<()> {
    if law.takes_contact_friction() {
        return Ok(());
    }
    let written = [("friction", keys.friction), ("mu", keys.mu), ("threshold", keys.threshold)]
        .into_iter()
        .filter_map(|(k, leaf)| leaf.as_ref().map(|v| (k, v.span())))
        .min_by_key(|(_, s)| s.start);
    let Some((key, span)) = written else { return Ok(()) };
    let name = law.name();
    let hint = match law {
        InterfaceLawSpec::ThinLayer(_) => {
            "a bonded layer is glued to both faces: it has no friction (and no contact condition); remove the \
             friction keys from the contact, or write bonded = false in the interface table for a cut layer in \
             contact with the other face, with the contact's friction"
                .to_string()
        }
        _ => format!(
            "law = \"{name}\" has its own Coulomb friction coefficient, `mu` in the interface table: move it there \
             (e.g. mu = 0.3) and remove `friction`, `mu` and `threshold` from {}",
            keys.table
        ),
    };
    let what = match law {
        InterfaceLawSpec::ThinLayer(_) => "a bonded thin layer (law = \"thin_layer\", bonded = true)".to_string(),
        _ => format!("law = \"{name}\""),
    };
    Err(src.error(&span, format!("`{key}` of {} does not apply with {what}", keys.table), hint))
}

/// A number > 0 (a stiffness, an energy, a modulus, a thickness).
fn positive(src: &Source, table: &Table, leaf: &Leaf, key: &str, example: &str, what: &str) -> Result<f64> {
    let v = table.require(leaf, key, example)?;
    src.positive(v, key, what)
}

/// A number ≥ 0, or `default` when the key is absent.
fn non_negative(src: &Source, leaf: &Leaf, key: &str, default: Option<f64>, hint: &str) -> Result<Option<f64>> {
    let Some(v) = leaf else { return Ok(default) };
    let x = src.number(v, key)?;
    if x < 0.0 {
        return Err(src.error(&v.span(), format!("`{key}` must not be negative, found {}", src.written(v)), hint));
    }
    Ok(Some(x))
}

fn required_non_negative(src: &Source, v: &Spanned<Value>, key: &str, hint: &str) -> Result<f64> {
    let x = src.number(v, key)?;
    if x < 0.0 {
        return Err(src.error(&v.span(), format!("`{key}` must not be negative, found {}", src.written(v)), hint));
    }
    Ok(x)
}

fn thin_layer(src: &Source, table: &Table, raw: &RawInterface) -> Result<ThinLayerSpec> {
    let young = positive(
        src,
        table,
        &raw.young,
        "young",
        "young = 1e7 (the layer's Young's modulus, Pa)",
        "a Young's modulus (Pa)",
    )?;
    let poisson_v =
        table.require(&raw.poisson, "poisson", "poisson = 0.3 (the layer's Poisson's ratio, in (-1, 0.5))")?;
    let poisson = src.number(poisson_v, "poisson")?;
    if !(poisson > -1.0 && poisson < 0.5) {
        return Err(src.error(
            &poisson_v.span(),
            format!("`poisson` must be in (-1, 0.5), found {}", src.written(poisson_v)),
            "a stable isotropic layer has -1 < poisson < 0.5 (its normal stiffness (λ + 2μ)/e blows up at 0.5: \
             an incompressible layer; rubber-like adhesives: about 0.45-0.49)",
        ));
    }
    let thickness = positive(
        src,
        table,
        &raw.thickness,
        "thickness",
        "thickness = 1e-3 (the layer's thickness e, m)",
        "the layer's thickness (m)",
    )?;
    let bonded = match &raw.bonded {
        None => true,
        Some(v) => match v.get_ref() {
            Value::Boolean(b) => *b,
            _ => {
                return Err(src.error(
                    &v.span(),
                    format!("`bonded` must be true or false, found {}", src.written(v)),
                    "write bonded = true (glued to both faces, the default) or bonded = false (a cut layer in \
                     unilateral contact)",
                ))
            }
        },
    };
    Ok(ThinLayerSpec { young, poisson, thickness, bonded })
}

fn rccm(src: &Source, table: &Table, raw: &RawInterface) -> Result<RccmSpec> {
    let normal_stiffness = positive(
        src,
        table,
        &raw.normal_stiffness,
        "normal_stiffness",
        "normal_stiffness = 1e12 (C_N, the adhesive's normal stiffness at β = 1, Pa/m)",
        "the normal stiffness C_N (Pa/m)",
    )?;
    let tangential_stiffness = positive(
        src,
        table,
        &raw.tangential_stiffness,
        "tangential_stiffness",
        "tangential_stiffness = 1e12 (C_T, Pa/m)",
        "the tangential stiffness C_T (Pa/m)",
    )?;
    let adhesion_energy = positive(
        src,
        table,
        &raw.adhesion_energy,
        "adhesion_energy",
        "adhesion_energy = 1.0 (w, the Dupré energy, J/m²)",
        "the adhesion energy w (J/m²)",
    )?;
    let viscosity = non_negative(
        src,
        &raw.viscosity,
        "viscosity",
        Some(0.0),
        "the viscosity b of the adhesion's evolution is ≥ 0 (J·s/m²); 0 is the rate-independent limit",
    )?
    .unwrap_or(0.0);
    let mu =
        non_negative(src, &raw.mu, "mu", Some(0.0), "the friction coefficient is ≥ 0 (0: frictionless once debonded)")?
            .unwrap_or(0.0);
    let initial_adhesion = match &raw.initial_adhesion {
        None => 1.0,
        Some(v) => {
            let beta = src.number(v, "initial_adhesion")?;
            if !(0.0..=1.0).contains(&beta) {
                return Err(src.error(
                    &v.span(),
                    format!("`initial_adhesion` must be in [0, 1], found {}", src.written(v)),
                    "β0 is the initial fraction of active bonds: 1 fully glued (the default), 0 no adhesion \
                     (Signorini–Coulomb), values between for a partly damaged bond",
                ));
            }
            beta
        }
    };
    Ok(RccmSpec { normal_stiffness, tangential_stiffness, adhesion_energy, viscosity, mu, initial_adhesion })
}

fn cohesive_joint(src: &Source, table: &Table, raw: &RawInterface) -> Result<CohesiveJointSpec> {
    let cohesion_v = table.require(&raw.cohesion, "cohesion", "cohesion = 0.3e6 (c0, Pa)")?;
    let cohesion = required_non_negative(
        src,
        cohesion_v,
        "cohesion",
        "the cohesion c0 is a shear strength at zero normal stress, ≥ 0 (Pa; 0: no cohesion)",
    )?;
    let tensile_v = table.require(&raw.tensile_strength, "tensile_strength", "tensile_strength = 0.1e6 (f_t0, Pa)")?;
    let tensile_strength = required_non_negative(
        src,
        tensile_v,
        "tensile_strength",
        "the tensile strength f_t0 is ≥ 0 (Pa; 0: no tension transmitted)",
    )?;
    let mu_v = table.require(&raw.mu, "mu", "mu = 0.6 (the friction coefficient)")?;
    let mu = required_non_negative(src, mu_v, "mu", "the friction coefficient is ≥ 0 (mortar joints: about 0.6-0.8)")?;
    let fracture_energy = |leaf: &Leaf, key: &str, symbol: &str, mode: &str, example: &str| -> Result<f64> {
        let v = table.require(leaf, key, example)?;
        let g = src.number(v, key)?;
        if g <= 0.0 {
            return Err(src.error(
                &v.span(),
                format!("`{key}` ({symbol}) must be positive, found {}", src.written(v)),
                format!(
                    "{symbol} is the energy per unit area dissipated in {mode} until the strength is gone (J/m²): 0 \
                     would be a perfectly brittle joint whose strength vanishes at once; give a value > 0 (mortar: \
                     about 10-100 J/m² in tension, 10 times more in shear)"
                ),
            ));
        }
        Ok(g)
    };
    let fracture_energy_tension = fracture_energy(
        &raw.fracture_energy_tension,
        "fracture_energy_tension",
        "G_I",
        "opening (mode I)",
        "fracture_energy_tension = 20.0 (G_I, J/m²)",
    )?;
    let fracture_energy_shear = fracture_energy(
        &raw.fracture_energy_shear,
        "fracture_energy_shear",
        "G_II",
        "slip (mode II)",
        "fracture_energy_shear = 200.0 (G_II, J/m²)",
    )?;
    if mu > 0.0 && tensile_strength > cohesion / mu {
        return Err(src.error(
            &tensile_v.span(),
            format!(
                "`tensile_strength` {} is above cohesion / mu = {} / {} = {:e}, the apex of the Mohr–Coulomb cone",
                src.written(tensile_v),
                src.written(cohesion_v),
                mu,
                cohesion / mu
            ),
            "the shear strength c + μσ (σ the compression) vanishes at the tension σ = −c/μ: a joint cannot carry \
             more tension than that, so the tension cut-off f_t0 must be at most cohesion / mu; lower \
             `tensile_strength`, or raise `cohesion`",
        ));
    }
    Ok(CohesiveJointSpec { cohesion, tensile_strength, mu, fracture_energy_tension, fracture_energy_shear })
}

/// `law = "rccm"` or `"cohesive_joint"` written in a scene without `[evolution]`: the value's
/// span and the law (the check of [`super::Scene::from_str`]).
pub(super) fn memory_law_without_evolution<'r>(
    src: &Source,
    interfaces: impl Iterator<Item = &'r RawInterface>,
) -> Result<()> {
    for raw in interfaces {
        let Some(v) = &raw.law else { continue };
        let Value::String(law) = v.get_ref() else { continue };
        if law == "rccm" || law == "cohesive_joint" {
            return Err(memory_error(src, v, law));
        }
    }
    Ok(())
}

fn memory_error(src: &Source, v: &Spanned<Value>, law: &str) -> crate::error::Error {
    let what = match law {
        "rccm" => "the adhesion intensity β",
        _ => "the joint's softening (its largest opening and accumulated slip)",
    };
    src.error(
        &v.span(),
        format!("law = \"{law}\" has memory ({what} evolves along the load path), but the scene has no [evolution]"),
        "a law with memory is solved increment by increment: add a load path, e.g. [evolution] steps = 10 \
         (every load ramped from 0 to its value in 10 increments; see \"Load paths: [evolution]\" in \
         docs/scene-format.md)",
    )
}
