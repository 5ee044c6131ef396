//! A contact problem built in Rust, without writing TOML: a block pressed on a rigid plane with
//! Coulomb friction, sheared on top. The builder checks the scene exactly as a scene file is
//! checked; a mistake (try `.material(210e9, 0.6)`) is reported as in a file.
//!
//! `cargo run --release --example contact_builder [PETSc options...]`
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::SceneBuilder;

fn main() -> Result<(), signorini::Error> {
    let args: Vec<String> = std::env::args().collect();
    let scene = SceneBuilder::rectangle([0.0, 0.0], [2.0, 1.0], 0.1)
        .title("block on a plane, built in Rust")
        .material(210e9, 0.3)
        .traction("top", [2e5, -1e6])
        .contact_line("bottom", [0.0, 0.0], [0.0, 1.0])
        .coulomb(0.5)
        .build()?;
    let session = Session::init(&args)?;
    let mut problem = ElasticityProblem::setup_system(&session, scene)?;
    problem.assemble()?;
    problem.solve()?;
    problem.postprocess()?;
    let report = problem.report()?;
    if let (Some(c), Some(r)) = (&report.contact, &report.results) {
        println!(
            "contact: {} points ({} stick, {} slip, {} open), normal force {:.4e}, tangential {:.4e}; max |u| {:.4e}",
            c.points, c.stick, c.slip, c.open, c.normal_resultant, c.tangential_resultant, r.max_displacement
        );
    }
    Ok(())
}
