//! Illegal scenes give typed errors whose messages say what is wrong.

use crate::edit::Edit;

use crate::{answer, error, scratch, square_block, Block, SQUARE_BLOCK};
use std::process::Command;

// ---------------------------------------------------------------- illegal scenes: typed errors

#[test]
fn body_inside_a_circle_obstacle() {
    let scene = r#"[mesh]
shape = "half_disc"
center = [0.0, 0.0]
radius = 0.1
cell_size = 0.02

[material]
young = 210e9
poisson = 0.3

[[dirichlet]]
part = "flat"
ux = 0.0
uy = 0.0

[contact]
part = "arc"
obstacle = "circle"      # a rigid disc of radius 0.2 around the whole body
center = [0.0, 0.0]
radius = 0.2
friction = "none"
"#;
    error("inside_circle", scene, &[], &["node", "inside the obstacle", "arc"]);
}

#[test]
fn body_on_the_wrong_side_of_a_line() {
    let b = Block::default();
    // The obstacle is the half-plane y >= -0.5 (normal pointing down): the body is inside it.
    let scene = b.toml().edit("point = [0.0, 0.0]\nnormal = [0.0, 1.0]", "point = [0.0, -0.5]\nnormal = [0.0, -1.0]");
    error("wrong_side", &scene, &[], &["node", "inside the obstacle", "bottom"]);
}

#[test]
fn sliding_square_block_without_friction_support() {
    // The square block without friction and without its supports: the left pressure pushes it
    // along the plane and nothing holds it sideways.
    let scene = square_block("friction = \"none\"")
        .edit("[[dirichlet]]\npart = \"right\"\nux = 0.0\n", "")
        .edit("[[dirichlet]]\npoint = [0.04, 0.0]      # the lower-right corner\nux = 0.0\nuy = 0.0\n", "");
    error("sliding", &scene, &[], &["slide"]);
}

#[test]
fn overflowing_load() {
    let b = Block { p: 1e300, ..Default::default() };
    let msg = error("overflow", &b.toml(), &[], &["pressure", "overflow", "units"]);
    assert!(msg.contains("scene.toml:"), "the message names the file and line: {msg}");
}

#[test]
fn coulomb_negative_mu() {
    let b = Block { contact: "friction = \"coulomb\"\nmu = -0.5".into(), ..Default::default() };
    error("mu_negative", &b.toml(), &[], &["mu"]);
}

#[test]
fn poisson_at_the_incompressible_limit() {
    let b = Block { poisson: 0.5, ..Default::default() };
    error("nu_half", &b.toml(), &[], &["poisson"]);
}

#[test]
fn loose_contact_tolerance() {
    let b = Block { contact: "friction = \"none\"\ntolerance = 0.9".into(), ..Default::default() };
    error("tolerance", &b.toml(), &[], &["tolerance"]);
}

#[test]
fn square_block_reactions_per_prescribed_component() {
    // `right` prescribes ux only: its reaction has no y component; the corner point prescribes
    // both and carries the vertical force the old attribution gave to `right`.
    let (_, r) = answer("sb_reactions", SQUARE_BLOCK, &[]);
    let reactions = &r["results"]["reactions"];
    assert_eq!(reactions["right"][1].as_f64(), Some(0.0), "{reactions}");
    let corner = &reactions["point [0.04, 0]"];
    assert!(corner[1].as_f64().unwrap().abs() > 1e3, "the corner carries a vertical force: {reactions}");
    assert!(r["results"]["equilibrium_residual"].as_f64().unwrap() < 1e-12);
}

#[test]
fn disconnected_piece_held_by_nothing() {
    // Two squares, the second touching nothing; only the first is held.
    let dir = scratch("pieces-mesh");
    let geo = dir.join("two.geo");
    std::fs::write(
        &geo,
        "Point(1)={0,0,0,0.25};Point(2)={1,0,0,0.25};Point(3)={1,1,0,0.25};Point(4)={0,1,0,0.25};\n\
         Point(5)={3,0,0,0.25};Point(6)={4,0,0,0.25};Point(7)={4,1,0,0.25};Point(8)={3,1,0,0.25};\n\
         Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};\n\
         Line(5)={5,6};Line(6)={6,7};Line(7)={7,8};Line(8)={8,5};\n\
         Curve Loop(1)={1,2,3,4};Plane Surface(1)={1};Curve Loop(2)={5,6,7,8};Plane Surface(2)={2};\n\
         Physical Curve(\"bottom\")={1};Physical Curve(\"top\")={3,7};Physical Curve(\"other\")={2,4,5,6,8};\n\
         Physical Surface(\"domain\")={1,2};\n",
    )
    .unwrap();
    let msh = dir.join("two.msh");
    let status = Command::new("gmsh").arg(&geo).args(["-2", "-format", "msh41", "-v", "0", "-o"]).arg(&msh).status();
    assert!(status.expect("gmsh (./setup.sh installs it)").success());
    let scene = format!(
        "[mesh]\nshape = \"file\"\nfile = \"{}\"\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n[[traction]]\npart = \"top\"\npressure = 1e5\n\n[[dirichlet]]\npart = \"bottom\"\nux = 0.0\nuy = 0.0\n",
        msh.display()
    );
    error("pieces", &scene, &[], &["2 separate pieces", "held", "float"]);
}
