//! Two deformable bodies in frictional contact, built in Rust without writing TOML: a block
//! pressed and sheared on an elastic base, the meshes not matching across the interface. Each
//! body is a single-body scene from `SceneBuilder`; `BodiesBuilder` names them and adds the
//! contact pair, checked as a scene file is. The run reports each body's equilibrium and the
//! pair's action and reaction, independently of the solver.
//!
//! `cargo run --release --example two_bodies [PETSc options...]`
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::{BodiesBuilder, FrictionSpec, SceneBuilder};

fn main() -> Result<(), signorini::Error> {
    let args: Vec<String> = std::env::args().collect();
    // The block: 1 m × 0.5 m, pressed and pushed sideways on its top, held sideways at one
    // corner of its top (vertically it rests on the base: held by the contact alone).
    let block = SceneBuilder::rectangle([0.0, 0.0], [1.0, 0.5], 0.05)
        .material(70e9, 0.3)
        .traction("top", [1e6, -5e6])
        .dirichlet_point([0.0, 0.5], Some(0.0), None)
        .build()?;
    // The base: wider, a coarser mesh, clamped at its bottom.
    let base = SceneBuilder::rectangle([-0.5, -0.6], [2.0, 0.6], 0.08)
        .material(210e9, 0.3)
        .dirichlet("bottom", Some(0.0), Some(0.0))
        .build()?;
    let scene = BodiesBuilder::new("block on an elastic base, built in Rust")
        .body("block", block)
        .body("base", base)
        .pair("block.bottom", "base.top", FrictionSpec::Coulomb { mu: 0.3 })
        .build()?;
    let session = Session::init(&args)?;
    let mut problem = ElasticityProblem::setup_system(&session, scene)?;
    problem.assemble()?;
    problem.solve()?;
    problem.postprocess()?;
    let report = problem.report()?;
    if let Some(bodies) = &report.bodies {
        for b in &bodies.bodies {
            println!(
                "body {}: {} nodes, contact force ({:.4e}, {:.4e}), equilibrium residual {:.1e}",
                b.name, b.nodes, b.contact_force[0], b.contact_force[1], b.equilibrium_residual
            );
        }
        for c in &bodies.contacts {
            println!(
                "contact {}: {} points ({} stick, {} slip, {} open), action-reaction residual {:.1e}",
                c.name,
                c.points,
                c.stick,
                c.slip,
                c.open,
                c.action_reaction_residual.unwrap_or(0.0)
            );
        }
    }
    Ok(())
}
