//! Hertz line contact through the library API: a half cylinder pressed on a rigid plane,
//! force-driven, frictionless; compares the contact half-width and peak pressure with Hertz's
//! formulas (K. L. Johnson, Contact Mechanics, 1985, §4.2): E* = E/(1−ν²), a = √(4PR/(πE*)), p0 = 2P/(πa).
//!
//! ```text
//! cargo run --release --example hertz_contact             # fine mesh (a/20 at the contact)
//! cargo run --release --example hertz_contact -- --small  # coarse, a few seconds
//! cargo run --release --example hertz_contact -- --plot hertz.svg   # also plot p(x) vs Hertz
//! ```
//! PETSc options work as usual after the flags, e.g. `-- -ksp_view`.
use std::f64::consts::PI;
use std::path::Path;

use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::SceneBuilder;

fn main() -> Result<(), signorini::Error> {
    let args: Vec<String> = std::env::args().collect();
    let small = args.iter().any(|a| a == "--small");
    let plot = args.iter().position(|a| a == "--plot").and_then(|i| args.get(i + 1)).cloned();
    let petsc_args: Vec<String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| *a != "--small" && *a != "--plot" && !(*i > 0 && args[i - 1] == "--plot"))
        .map(|(_, a)| a.clone())
        .collect();
    let session = Session::init(&petsc_args)?;

    // The problem, in SI units.
    let (radius, young, poisson) = (0.1_f64, 210e9_f64, 0.3_f64);
    let load = 4.5e7; // N per metre of thickness
    let estar = young / (1.0 - poisson * poisson);
    let a = (4.0 * load * radius / (PI * estar)).sqrt();
    let p0 = 2.0 * load / (PI * a);
    let fine = if small { a / 5.0 } else { a / 20.0 };

    // A half cylinder (flat side on top), quadratic, its mesh refined where it touches the plane.
    let scene = SceneBuilder::half_disc([0.0, radius], radius, radius / 10.0)
        .title("Hertz line contact (example)")
        .refine([0.0, 0.0], fine, 3.0 * a)
        .quadratic()
        .material(young, poisson)
        .pressure("flat", load / (2.0 * radius))
        .dirichlet_point([0.0, radius], Some(0.0), None)
        .contact_line("arc", [0.0, 0.0], [0.0, 1.0])
        .build()?;

    let mut problem = ElasticityProblem::setup_system(&session, scene)?;
    problem.assemble()?;
    problem.solve()?;
    problem.postprocess()?;

    let contact = problem.contact.as_ref().expect("the scene has contact");
    let outcome = problem.contact_outcome.as_ref().expect("solved");
    let pressure = contact.boundary.recovered_pressure(&problem.mesh, &outcome.force);
    let peak = pressure.iter().cloned().fold(0.0, f64::max);
    // The closed zone as an interval of arc length along the flat contact part (= x there).
    let zone = outcome.report.zones.first().map(|z| z.extent).expect("the cylinder touches the plane");
    if session.rank() == 0 {
        println!("Hertz line contact, {} dofs, {} contact points", problem.num_dofs(), outcome.report.points);
        println!("  half-width  a : computed {:.4e} (closed nodes), Hertz {:.4e}", 0.5 * (zone[1] - zone[0]), a);
        println!("  peak pressure : computed {:.4e}, Hertz {:.4e} ({:+.2} %)", peak, p0, 100.0 * (peak - p0) / p0);
        let r = &outcome.report.residuals;
        println!(
            "  independent check: penetration {:.1e}, complementarity {:.1e}; {} Newton iterations",
            r.max_penetration, r.normal_complementarity, outcome.report.iterations
        );
    }
    if let (Some(path), 0) = (plot, session.rank()) {
        // Nodal pressures (vertex and mid-edge nodes alike, −rN/w) against Hertz's curve.
        let (nodal, _) = contact.boundary.tractions(&outcome.force);
        let mut computed: Vec<(f64, f64)> = contact
            .boundary
            .nodes
            .iter()
            .zip(&nodal)
            .map(|(&n, &p)| (problem.mesh.nodes[n][0], p))
            .filter(|(x, _)| x.abs() <= 1.5 * a)
            .collect();
        computed.sort_by(|p, q| p.0.total_cmp(&q.0));
        let theory: Vec<(f64, f64)> = (0..=400)
            .map(|k| {
                let x = -1.5 * a + 3.0 * a * k as f64 / 400.0;
                (x, if x.abs() < a { p0 * (1.0 - (x / a).powi(2)).sqrt() } else { 0.0 })
            })
            .collect();
        signorini::output::plot::write_linear_svg(
            Path::new(&path),
            "Hertz line contact: contact pressure",
            "x (m)",
            "pressure (Pa)",
            &[
                signorini::output::plot::Series { label: "Hertz".into(), points: theory },
                signorini::output::plot::Series { label: "signorini, P2 nodes".into(), points: computed },
            ],
            &[true, false],
        )?;
        println!("  wrote {path}");
    }
    Ok(())
}
