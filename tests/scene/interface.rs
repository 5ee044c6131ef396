//! `[contact.interface]`, `[contact_pair.interface]`: interface laws. The oracle of every good
//! scene is the values written in its text (and the defaults of docs/scene-format.md); every
//! mistake is an `Error::Scene` at the line of the offending value (or of the table's header
//! for a missing key), saying what to do.

use crate::edit::Edit;
use crate::{line_of, parse, scene_error, BASE, LINE};
use signorini::error::Error;
use signorini::scene::{
    BodiesBuilder, CohesiveJointSpec, FrictionSpec, InterfaceLawSpec, InterfaceSpec, RccmSpec, Scene, SceneBuilder,
    ThinLayerSpec, BUILT_IN_RUST,
};
use std::path::Path;

const THIN: &str = "[contact.interface]\nlaw = \"thin_layer\"\nyoung = 1e7\npoisson = 0.3\nthickness = 1e-3\n";
const RCCM: &str = "[contact.interface]\nlaw = \"rccm\"\nnormal_stiffness = 1e12\ntangential_stiffness = 5e11\n\
                    adhesion_energy = 2.0\n";
const JOINT: &str = "[contact.interface]\nlaw = \"cohesive_joint\"\ncohesion = 0.3e6\ntensile_strength = 0.1e6\n\
                     mu = 0.6\nfracture_energy_tension = 20.0\nfracture_energy_shear = 200.0\n";
const EVOLUTION: &str = "[evolution]\nsteps = 2\n";

/// BASE with a line obstacle on `bottom`, `contact_extra` keys in `[contact]`, then `tail`.
fn scene(contact_extra: &str, tail: &str) -> String {
    format!("{BASE}\n[contact]\n{LINE}{contact_extra}{tail}")
}

#[track_caller]
fn interface_of(text: &str) -> InterfaceSpec {
    let s = parse(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    s.contact.expect("[contact]").interface.expect("an interface")
}

/// 1-based line of the last line of `text` containing `needle` (the interface tables come after
/// the base scene's, whose keys may share a name: `young`, `poisson`).
fn last_line_of(text: &str, needle: &str) -> usize {
    text.lines().collect::<Vec<_>>().iter().rposition(|l| l.contains(needle)).expect("needle in text") + 1
}

/// The error of `text`: at the last line containing `needle`, its message containing every
/// one of `message`, its hint every one of `hint`.
#[track_caller]
fn refused(text: &str, needle: &str, message: &[&str], hint: &[&str]) {
    let e = scene_error(text);
    assert_eq!(e.line, last_line_of(text, needle), "{}\n{text}", e.message);
    for m in message {
        assert!(e.message.contains(m), "message {:?} lacks {m:?}", e.message);
    }
    for h in hint {
        assert!(e.hint.contains(h), "hint {:?} lacks {h:?}", e.hint);
    }
}

// ---- good scenes ------------------------------------------------------------------------------

#[test]
fn a_thin_layer_parses_with_its_default_bonded() {
    let text = scene("", THIN);
    let i = interface_of(&text);
    assert_eq!(
        i.law,
        InterfaceLawSpec::ThinLayer(ThinLayerSpec { young: 1e7, poisson: 0.3, thickness: 1e-3, bonded: true })
    );
    assert!(i.trace.is_empty());
    assert_eq!(i.at.line, line_of(&text, "[contact.interface]"));
    assert_eq!(i.at.file, Path::new("test.toml"));
    // a cut layer keeps the contact's friction
    let text = scene("friction = \"coulomb\"\nmu = 0.4\n", &format!("{THIN}bonded = false\n"));
    let s = parse(&text).unwrap();
    let c = s.contact.unwrap();
    assert_eq!(c.friction, FrictionSpec::Coulomb { mu: 0.4 });
    assert!(matches!(c.interface.unwrap().law, InterfaceLawSpec::ThinLayer(ThinLayerSpec { bonded: false, .. })));
}

#[test]
fn rccm_parses_with_its_defaults_and_every_key() {
    let i = interface_of(&scene("", &format!("{RCCM}{EVOLUTION}")));
    assert_eq!(
        i.law,
        InterfaceLawSpec::Rccm(RccmSpec {
            normal_stiffness: 1e12,
            tangential_stiffness: 5e11,
            adhesion_energy: 2.0,
            viscosity: 0.0,
            mu: 0.0,
            initial_adhesion: 1.0,
        })
    );
    let text = scene("", &format!("{RCCM}viscosity = 0.5\nmu = 0.3\ninitial_adhesion = 0.25\n{EVOLUTION}"));
    assert_eq!(
        interface_of(&text).law,
        InterfaceLawSpec::Rccm(RccmSpec {
            normal_stiffness: 1e12,
            tangential_stiffness: 5e11,
            adhesion_energy: 2.0,
            viscosity: 0.5,
            mu: 0.3,
            initial_adhesion: 0.25,
        })
    );
    // the ends of [0, 1] are accepted
    for beta in ["0", "1.0"] {
        let text = scene("", &format!("{RCCM}initial_adhesion = {beta}\n{EVOLUTION}"));
        assert!(parse(&text).is_ok(), "{beta}");
    }
}

#[test]
fn a_cohesive_joint_parses_with_its_trace() {
    let text = scene("", &format!("{JOINT}trace = [[0.0, 0.0], [0.5, 0]]\n{EVOLUTION}"));
    let i = interface_of(&text);
    assert_eq!(
        i.law,
        InterfaceLawSpec::CohesiveJoint(CohesiveJointSpec {
            cohesion: 0.3e6,
            tensile_strength: 0.1e6,
            mu: 0.6,
            fracture_energy_tension: 20.0,
            fracture_energy_shear: 200.0,
        })
    );
    assert_eq!(i.trace, vec![[0.0, 0.0], [0.5, 0.0]]);
    // the apex itself (f_t = c/μ) is accepted, and so is any f_t without friction
    let apex = text.edit("tensile_strength = 0.1e6", "tensile_strength = 0.5e6");
    assert!(parse(&apex).is_ok());
    let band = text.edit("tensile_strength = 0.1e6", "tensile_strength = 9e6").edit("mu = 0.6", "mu = 0");
    assert!(parse(&band).is_ok());
}

#[test]
fn the_interface_may_be_written_inline() {
    let text = scene(
        "interface = { law = \"thin_layer\", young = 2e7, poisson = 0.25, thickness = 2e-3, trace = [[1, 0]] }\n",
        "",
    );
    let i = interface_of(&text);
    assert_eq!(
        i.law,
        InterfaceLawSpec::ThinLayer(ThinLayerSpec { young: 2e7, poisson: 0.25, thickness: 2e-3, bonded: true })
    );
    assert_eq!(i.trace, vec![[1.0, 0.0]]);
    // a missing key of an inline table points at its first key
    let text = scene("interface = { law = \"thin_layer\", young = 2e7, poisson = 0.25 }\n", "");
    refused(&text, "interface = {", &["missing `thickness`"], &["thickness = "]);
}

#[test]
fn without_an_interface_table_there_is_none() {
    let s = parse(&scene("", "")).unwrap();
    assert_eq!(s.contact.unwrap().interface, None);
}

// ---- mistakes ---------------------------------------------------------------------------------

#[test]
fn an_unknown_law_lists_the_three() {
    let text = scene("", &THIN.edit("\"thin_layer\"", "\"glue\""));
    refused(&text, "law = ", &["unknown law \"glue\""], &["\"thin_layer\", \"rccm\", \"cohesive_joint\""]);
    let text = scene("", &THIN.edit("\"thin_layer\"", "\"thin_layr\""));
    refused(&text, "law = ", &["unknown law"], &["did you mean \"thin_layer\"?"]);
}

#[test]
fn a_missing_key_points_at_the_header() {
    let cases: &[(&str, &str, &str)] = &[
        (THIN, "law = \"thin_layer\"\n", "law"),
        (THIN, "young = 1e7\n", "young"),
        (THIN, "poisson = 0.3\n", "poisson"),
        (THIN, "thickness = 1e-3\n", "thickness"),
        (RCCM, "normal_stiffness = 1e12\n", "normal_stiffness"),
        (RCCM, "tangential_stiffness = 5e11\n", "tangential_stiffness"),
        (RCCM, "adhesion_energy = 2.0\n", "adhesion_energy"),
        (JOINT, "cohesion = 0.3e6\n", "cohesion"),
        (JOINT, "tensile_strength = 0.1e6\n", "tensile_strength"),
        (JOINT, "mu = 0.6\n", "mu"),
        (JOINT, "fracture_energy_tension = 20.0\n", "fracture_energy_tension"),
        (JOINT, "fracture_energy_shear = 200.0\n", "fracture_energy_shear"),
    ];
    for (table, line, key) in cases {
        let text = scene("", &format!("{}{EVOLUTION}", table.edit(line, "")));
        refused(&text, "[contact.interface]", &["[contact.interface]", &format!("is missing `{key}`")], &[key]);
    }
}

#[test]
fn a_key_of_another_law_names_the_law_that_takes_it() {
    let text = scene("", &format!("{THIN}cohesion = 1e5\n"));
    refused(
        &text,
        "cohesion = ",
        &["`cohesion` does not apply to law = \"thin_layer\""],
        &["law = \"cohesive_joint\"", "young, poisson, thickness, bonded"],
    );
    let text = scene("", &format!("{JOINT}young = 1e7\n{EVOLUTION}"));
    refused(&text, "young = ", &["`young` does not apply to law = \"cohesive_joint\""], &["law = \"thin_layer\""]);
    // `mu` is taken by two laws
    let text = scene("", &format!("{THIN}mu = 0.3\n"));
    refused(&text, "mu = ", &["`mu` does not apply"], &["law = \"rccm\" and law = \"cohesive_joint\""]);
    let text = scene("", &format!("{RCCM}bonded = true\n{EVOLUTION}"));
    refused(&text, "bonded = ", &["`bonded` does not apply to law = \"rccm\""], &["law = \"thin_layer\""]);
}

#[test]
fn a_key_no_law_takes_is_unknown() {
    let text = scene("", &format!("{THIN}stifness = 1\n"));
    refused(&text, "stifness", &["unknown key `stifness`", "interface table"], &["law, young"]);
    let text = scene("", &format!("{THIN}thicknes = 1\n"));
    refused(&text, "thicknes = 1", &["unknown key `thicknes`"], &["did you mean `thickness`?"]);
}

#[test]
fn non_positive_moduli_stiffnesses_energies_and_thicknesses_are_refused() {
    let cases: &[(&str, &str, &str)] = &[
        (THIN, "young = 1e7", "young"),
        (THIN, "thickness = 1e-3", "thickness"),
        (RCCM, "normal_stiffness = 1e12", "normal_stiffness"),
        (RCCM, "tangential_stiffness = 5e11", "tangential_stiffness"),
        (RCCM, "adhesion_energy = 2.0", "adhesion_energy"),
        (JOINT, "fracture_energy_tension = 20.0", "fracture_energy_tension"),
        (JOINT, "fracture_energy_shear = 200.0", "fracture_energy_shear"),
    ];
    for (table, line, key) in cases {
        for bad in ["0", "-1.5", "0.0"] {
            let text = scene("", &format!("{}{EVOLUTION}", table.edit(line, &format!("{key} = {bad}"))));
            refused(&text, &format!("{key} = {bad}"), &[&format!("`{key}`"), "must be positive", bad], &[]);
        }
    }
}

#[test]
fn fracture_energies_say_what_zero_would_mean() {
    let text = scene(
        "",
        &format!("{}{EVOLUTION}", JOINT.edit("fracture_energy_tension = 20.0", "fracture_energy_tension = 0")),
    );
    refused(
        &text,
        "fracture_energy_tension",
        &["`fracture_energy_tension` (G_I) must be positive, found 0"],
        &["perfectly brittle"],
    );
    let text =
        scene("", &format!("{}{EVOLUTION}", JOINT.edit("fracture_energy_shear = 200.0", "fracture_energy_shear = 0")));
    refused(&text, "fracture_energy_shear", &["(G_II) must be positive"], &["slip (mode II)"]);
}

#[test]
fn poisson_outside_its_open_interval_is_refused() {
    for bad in ["0.5", "0.6", "-1", "-1.2"] {
        let text = scene("", &THIN.edit("poisson = 0.3", &format!("poisson = {bad}")));
        refused(&text, "poisson = ", &["`poisson` must be in (-1, 0.5)", bad], &["-1 < poisson < 0.5"]);
    }
    let text = scene("", &THIN.edit("poisson = 0.3", "poisson = -0.99"));
    assert!(parse(&text).is_ok());
}

#[test]
fn initial_adhesion_outside_zero_one_is_refused() {
    for bad in ["-0.1", "1.5"] {
        let text = scene("", &format!("{RCCM}initial_adhesion = {bad}\n{EVOLUTION}"));
        refused(
            &text,
            "initial_adhesion",
            &["`initial_adhesion` must be in [0, 1]", bad],
            &["fraction of active bonds"],
        );
    }
}

#[test]
fn negative_viscosity_mu_cohesion_and_tensile_strength_are_refused() {
    let cases: &[(String, &str, &str)] = &[
        (format!("{RCCM}viscosity = -1\n"), "viscosity", "rate-independent"),
        (format!("{RCCM}mu = -0.2\n"), "mu", "friction coefficient"),
        (JOINT.edit("cohesion = 0.3e6", "cohesion = -1"), "cohesion", "shear strength"),
        (JOINT.edit("tensile_strength = 0.1e6", "tensile_strength = -1"), "tensile_strength", "tensile strength"),
        (JOINT.edit("mu = 0.6", "mu = -0.6"), "mu", "friction coefficient"),
    ];
    for (table, key, hint) in cases {
        let text = scene("", &format!("{table}{EVOLUTION}"));
        refused(&text, &format!("{key} = -"), &[&format!("`{key}` must not be negative")], &[hint]);
    }
    // zero is allowed for each
    for table in [
        format!("{RCCM}viscosity = 0\nmu = 0\n"),
        JOINT.edit("cohesion = 0.3e6", "cohesion = 0").edit("tensile_strength = 0.1e6", "tensile_strength = 0"),
    ] {
        assert!(parse(&scene("", &format!("{table}{EVOLUTION}"))).is_ok(), "{table}");
    }
}

#[test]
fn a_tensile_strength_beyond_the_cone_apex_is_refused() {
    // c/μ = 0.3e6 / 0.6 = 5e5
    let text = scene("", &format!("{}{EVOLUTION}", JOINT.edit("tensile_strength = 0.1e6", "tensile_strength = 0.6e6")));
    refused(
        &text,
        "tensile_strength",
        &["`tensile_strength` 0.6e6 is above cohesion / mu = 0.3e6 / 0.6 = 5e5", "apex of the Mohr–Coulomb cone"],
        &["vanishes at the tension", "at most cohesion / mu"],
    );
    // no cohesion, some tension: the apex is at 0
    let text = scene(
        "",
        &format!(
            "{}{EVOLUTION}",
            JOINT.edit("cohesion = 0.3e6", "cohesion = 0").edit("tensile_strength = 0.1e6", "tensile_strength = 1")
        ),
    );
    refused(&text, "tensile_strength", &["above cohesion / mu"], &[]);
}

#[test]
fn a_friction_beside_a_law_with_its_own_is_refused() {
    for (law, tail) in [("rccm", RCCM), ("cohesive_joint", JOINT)] {
        for (keys, first) in [
            ("friction = \"coulomb\"\nmu = 0.3\n", "friction = "),
            ("friction = \"none\"\n", "friction = "),
            ("friction = \"tresca\"\nthreshold = 1e5\n", "friction = "),
            ("mu = 0.3\n", "mu = 0.3"),
        ] {
            let text = scene(keys, &format!("{tail}{EVOLUTION}"));
            refused(
                &text,
                first,
                &["of [contact] does not apply with", &format!("law = \"{law}\"")],
                &["own Coulomb friction coefficient", "move it there", "[contact]"],
            );
        }
    }
    // a bonded layer has no friction (bonded written or by default)
    for tail in [THIN.to_string(), format!("{THIN}bonded = true\n")] {
        let text = scene("friction = \"coulomb\"\nmu = 0.3\n", &tail);
        refused(&text, "friction = ", &["a bonded thin layer"], &["glued to both faces", "bonded = false"]);
    }
}

#[test]
fn laws_with_memory_need_a_load_path() {
    for (law, tail) in [("rccm", RCCM), ("cohesive_joint", JOINT)] {
        let text = scene("", tail);
        refused(
            &text,
            "law = ",
            &[&format!("law = \"{law}\" has memory"), "no [evolution]"],
            &["[evolution] steps = 10"],
        );
    }
    // a thin layer is memoryless: a static run
    assert!(parse(&scene("", THIN)).is_ok());
}

#[test]
fn bonded_and_trace_are_checked() {
    let text = scene("", &format!("{THIN}bonded = \"yes\"\n"));
    refused(&text, "bonded = ", &["`bonded` must be true or false"], &["bonded = false"]);
    let text = scene("", &format!("{THIN}trace = []\n"));
    refused(&text, "trace = ", &["`trace` holds no point"], &["remove `trace` for the default"]);
    let text = scene("", &format!("{THIN}trace = [[0.0, 0.0], [1.0]]\n"));
    refused(&text, "trace = ", &["`trace[1]` must be a point"], &[]);
}

// ---- several bodies ---------------------------------------------------------------------------

const TWO_BODIES: &str = r#"
[[body]]
name = "punch"
[body.mesh]
shape = "rectangle"
origin = [0.0, 1.0]
size = [1.0, 1.0]
cell_size = 0.5
[body.material]
young = 1e9
poisson = 0.3
[[body]]
name = "base"
[body.mesh]
shape = "rectangle"
size = [1.0, 1.0]
cell_size = 0.5
[body.material]
young = 1e9
poisson = 0.3
[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0
[[contact_pair]]
slave = "punch.bottom"
master = "base.top"
"#;

const THIN_LAW: ThinLayerSpec = ThinLayerSpec { young: 1e7, poisson: 0.3, thickness: 1e-3, bonded: true };

#[test]
fn a_pair_takes_an_interface_as_a_sub_table_or_inline() {
    let sub = format!("{TWO_BODIES}{}", THIN.edit("[contact.interface]", "[contact_pair.interface]"));
    let s = parse(&sub).unwrap_or_else(|e| panic!("{e}"));
    let i = s.contact_pairs[0].interface.as_ref().unwrap();
    assert_eq!(i.law, InterfaceLawSpec::ThinLayer(THIN_LAW));
    assert_eq!(i.at.line, line_of(&sub, "[contact_pair.interface]"));

    let inline = TWO_BODIES.edit(
        "master = \"base.top\"\n",
        "master = \"base.top\"\ninterface = { law = \"thin_layer\", young = 1e7, poisson = 0.3, thickness = 1e-3 }\n",
    );
    let s = parse(&inline).unwrap();
    assert_eq!(s.contact_pairs[0].interface.as_ref().unwrap().law, InterfaceLawSpec::ThinLayer(THIN_LAW));

    // the second of two pairs: its own sub-table, located between its header and the end
    let two_pairs = format!(
        "{TWO_BODIES}[[contact_pair]]\nslave = \"punch.left\"\nmaster = \"base.left\"\n{}",
        THIN.edit("[contact.interface]", "[contact_pair.interface]").edit("young = 1e7\n", "")
    );
    let text = two_pairs.replace("slave = \"punch.left\"", "slave = \"punch.right\"");
    refused(&text, "[contact_pair.interface]", &["[contact_pair.interface] with law", "missing `young`"], &[]);
}

#[test]
fn a_pair_s_interface_is_checked_as_a_contact_s() {
    let rccm = RCCM.edit("[contact.interface]", "[contact_pair.interface]");
    // friction on the pair with rccm
    let text = format!(
        "{}{rccm}{EVOLUTION}",
        TWO_BODIES.edit("master = \"base.top\"\n", "master = \"base.top\"\nfriction = \"coulomb\"\nmu = 0.2\n")
    );
    refused(&text, "friction = ", &["of this [[contact_pair]] does not apply with law = \"rccm\""], &["move it there"]);
    // memory without a load path
    let text = format!("{TWO_BODIES}{rccm}");
    refused(&text, "law = ", &["law = \"rccm\" has memory"], &["[evolution]"]);
    // a bad value
    let text = format!("{TWO_BODIES}{}{EVOLUTION}", rccm.edit("adhesion_energy = 2.0", "adhesion_energy = -2"));
    refused(&text, "adhesion_energy", &["`adhesion_energy` must be positive"], &[]);
}

#[test]
fn a_body_s_rigid_contact_takes_an_interface() {
    let text = TWO_BODIES.edit(
        "[[body.dirichlet]]",
        "[body.contact]\npart = \"left\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
         [body.contact.interface]\nlaw = \"cohesive_joint\"\ncohesion = 1e5\ntensile_strength = 1e4\nmu = 0.5\n\
         fracture_energy_tension = 10\nfracture_energy_shear = 100\n[[body.dirichlet]]",
    );
    let with_path = format!("{text}{EVOLUTION}");
    let s = parse(&with_path).unwrap_or_else(|e| panic!("{e}"));
    let i = s.bodies[1].contact.as_ref().unwrap().interface.as_ref().unwrap();
    assert!(matches!(i.law, InterfaceLawSpec::CohesiveJoint(CohesiveJointSpec { cohesion, .. }) if cohesion == 1e5));
    assert_eq!(i.at.line, line_of(&with_path, "[body.contact.interface]"));
    refused(&text, "law = \"cohesive_joint\"", &["has memory"], &[]);
    let missing = with_path.edit("mu = 0.5\n", "");
    refused(&missing, "[body.contact.interface]", &["[body.contact.interface] of body `base`", "missing `mu`"], &[]);
}

// ---- built in Rust ------------------------------------------------------------------------------

#[track_caller]
fn builder_error(built: signorini::Result<Scene>) -> (String, String) {
    match built {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!(location.file, Path::new(BUILT_IN_RUST));
            (message, hint)
        }
        other => panic!("expected Error::Scene, got {other:?}"),
    }
}

fn block() -> SceneBuilder {
    SceneBuilder::rectangle([0.0, 0.0], [1.0, 0.2], 0.1)
        .material(210e9, 0.3)
        .dirichlet("left", Some(0.0), Some(0.0))
        .contact_line("bottom", [0.0, 0.0], [0.0, 1.0])
}

const RCCM_LAW: RccmSpec = RccmSpec {
    normal_stiffness: 1e12,
    tangential_stiffness: 5e11,
    adhesion_energy: 2.0,
    viscosity: 0.0,
    mu: 0.3,
    initial_adhesion: 1.0,
};

#[test]
fn the_builder_gives_the_interface_of_a_file() {
    let built =
        block().interface(InterfaceLawSpec::ThinLayer(THIN_LAW)).interface_trace(&[[0.5, 0.0]]).build().unwrap();
    let i = built.contact.as_ref().unwrap().interface.as_ref().unwrap();
    assert_eq!(i.law, InterfaceLawSpec::ThinLayer(THIN_LAW));
    assert_eq!(i.trace, vec![[0.5, 0.0]]);
    // written as a file and read back: the same interface
    let read = Scene::from_str(&built.to_toml(), Path::new("t.toml")).unwrap();
    let r = read.contact.unwrap().interface.unwrap();
    assert_eq!((r.law, r.trace), (i.law.clone(), i.trace.clone()));

    let rccm = block().interface(InterfaceLawSpec::Rccm(RCCM_LAW)).evolution_steps(3).build().unwrap();
    assert_eq!(rccm.contact.unwrap().interface.unwrap().law, InterfaceLawSpec::Rccm(RCCM_LAW));
}

#[test]
fn the_builder_refuses_what_a_file_refuses() {
    let (m, h) = builder_error(block().interface(InterfaceLawSpec::Rccm(RCCM_LAW)).build());
    assert!(m.starts_with("SceneBuilder::interface (`law = \"rccm\"`)") && m.contains("has memory"), "{m}");
    assert!(h.contains("[evolution]"), "{h}");
    let (m, _) =
        builder_error(block().interface(InterfaceLawSpec::Rccm(RCCM_LAW)).coulomb(0.3).evolution_steps(2).build());
    assert!(m.starts_with("SceneBuilder::coulomb") && m.contains("does not apply with law = \"rccm\""), "{m}");
    let bad = RccmSpec { initial_adhesion: 1.5, ..RCCM_LAW };
    let (m, _) = builder_error(block().interface(InterfaceLawSpec::Rccm(bad)).evolution_steps(2).build());
    assert!(m.starts_with("SceneBuilder::interface (`initial_adhesion = 1.5`)"), "{m}");
    let bad = ThinLayerSpec { poisson: 0.5, ..THIN_LAW };
    let (m, _) = builder_error(block().interface(InterfaceLawSpec::ThinLayer(bad)).build());
    assert!(m.contains("`poisson` must be in (-1, 0.5)"), "{m}");
    let (m, _) = builder_error(block().interface(InterfaceLawSpec::ThinLayer(THIN_LAW)).interface_trace(&[]).build());
    assert!(m.starts_with("SceneBuilder::interface_trace") && m.contains("no point"), "{m}");
    // a frictionless cut layer: no friction line written, none refused
    let cut = ThinLayerSpec { bonded: false, ..THIN_LAW };
    assert!(block().interface(InterfaceLawSpec::ThinLayer(cut)).build().is_ok());
}

#[test]
fn the_builder_refuses_an_interface_it_would_ignore() {
    let no_contact = SceneBuilder::rectangle([0.0, 0.0], [1.0, 0.2], 0.1).material(210e9, 0.3);
    let (m, _) = builder_error(no_contact.interface(InterfaceLawSpec::ThinLayer(THIN_LAW)).build());
    assert!(m.starts_with("SceneBuilder::interface") && m.contains("there is no contact"), "{m}");
    let (m, _) = builder_error(block().interface_trace(&[[0.0, 0.0]]).build());
    assert!(m.starts_with("SceneBuilder::interface_trace") && m.contains("no interface law"), "{m}");
    let law = InterfaceLawSpec::ThinLayer(THIN_LAW);
    let (m, _) = builder_error(block().interface(law.clone()).interface(law).build());
    assert!(m.contains("set twice"), "{m}");
}

#[test]
fn the_bodies_builder_gives_a_pair_its_interface() {
    let punch = SceneBuilder::rectangle([0.0, 1.0], [1.0, 1.0], 0.5).material(1e9, 0.3).build().unwrap();
    let base = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.5)
        .material(1e9, 0.3)
        .dirichlet("bottom", Some(0.0), Some(0.0))
        .build()
        .unwrap();
    let two = || BodiesBuilder::new("two").body("punch", punch.clone()).body("base", base.clone());
    let s = two()
        .pair("punch.bottom", "base.top", FrictionSpec::None)
        .pair_interface(InterfaceLawSpec::Rccm(RCCM_LAW))
        .pair_interface_trace(&[[0.5, 1.0]])
        .evolution_steps(2)
        .build()
        .unwrap();
    let i = s.contact_pairs[0].interface.as_ref().unwrap();
    assert_eq!((i.law.clone(), i.trace.clone()), (InterfaceLawSpec::Rccm(RCCM_LAW), vec![[0.5, 1.0]]));
    // the same as the file
    let file = format!(
        "{TWO_BODIES}{}mu = 0.3\ntrace = [[0.5, 1.0]]\n{EVOLUTION}",
        RCCM.edit("[contact.interface]", "[contact_pair.interface]")
    );
    assert_eq!(parse(&file).unwrap().contact_pairs[0].interface.as_ref().unwrap().law, i.law);

    let (m, h) = builder_error(
        two()
            .pair("punch.bottom", "base.top", FrictionSpec::None)
            .pair_interface(InterfaceLawSpec::Rccm(RCCM_LAW))
            .build(),
    );
    assert!(m.starts_with("BodiesBuilder::pair_interface") && m.contains("has memory"), "{m}");
    assert!(h.contains("[evolution]"), "{h}");
    let (m, _) = builder_error(
        two()
            .pair("punch.bottom", "base.top", FrictionSpec::Coulomb { mu: 0.3 })
            .pair_interface(InterfaceLawSpec::Rccm(RCCM_LAW))
            .evolution_steps(2)
            .build(),
    );
    assert!(m.starts_with("BodiesBuilder::pair") && m.contains("does not apply with law = \"rccm\""), "{m}");
    let (m, _) = builder_error(two().pair_interface(InterfaceLawSpec::ThinLayer(THIN_LAW)).build());
    assert!(m.starts_with("BodiesBuilder::pair_interface") && m.contains("no pair was added"), "{m}");
    let (m, _) = builder_error(
        two()
            .pair("punch.bottom", "base.top", FrictionSpec::None)
            .pair_interface(InterfaceLawSpec::ThinLayer(THIN_LAW))
            .pair_interface(InterfaceLawSpec::ThinLayer(THIN_LAW))
            .build(),
    );
    assert!(m.contains("set twice"), "{m}");
    let (m, _) = builder_error(
        two().pair("punch.bottom", "base.top", FrictionSpec::None).pair_interface_trace(&[[0.0, 1.0]]).build(),
    );
    assert!(m.contains("no interface law"), "{m}");
}
