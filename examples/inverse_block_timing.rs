//! Times a MUMPS Cholesky of a ~n-dof P1 stiffness with the block of its inverse on the bottom
//! side's dofs (the contact dofs of the square block), on any number of ranks: the work the
//! dense Schur contact route does before its Newton steps.
//!
//! `mpirun -n 2 target/release/examples/inverse_block_timing [nodes_per_side] [schur]`: with
//! `schur` (one rank) the Schur complement route of `petsc/schur.rs` is timed too and the two
//! blocks compared.
use signorini::fem::{assemble, Constraints, Loads, Material, PlaneModel};
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use signorini::petsc::inverse_block::InverseBlockFactor;
use signorini::petsc::schur::SchurFactor;
use signorini::petsc::{Matrix, Session};
use std::time::Instant;

fn grid(m: usize) -> Mesh {
    let h = 1.0 / (m - 1) as f64;
    let nodes = (0..m * m).map(|k| [(k % m) as f64 * h, (k / m) as f64 * h]).collect();
    let id = |i: usize, j: usize| j * m + i;
    let mut cells = Vec::new();
    for j in 0..m - 1 {
        for i in 0..m - 1 {
            cells.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            cells.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut edges = Vec::new();
    for i in 0..m - 1 {
        edges.extend([id(m - 1 - i, m - 1), id(m - 2 - i, m - 1)]);
    }
    let ncells = cells.len() / 3;
    Mesh {
        order: Order::P1,
        nodes,
        cells,
        cell_group: vec![NO_GROUP; ncells],
        edge_group: vec![0; edges.len() / 2],
        edges,
        groups: vec![PhysicalGroup { name: "top".into(), tag: 1, dim: 1 }],
        measure: Default::default(),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let m: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(709);
    let schur = args.iter().any(|a| a == "schur");
    let session = Session::init(&args[..1]).unwrap();
    let (rank, size) = (session.rank(), session.size());
    let mesh = grid(m);
    let material = Material { young: 1.3e11, poisson: 0.2, plane: PlaneModel::Strain };
    let n = 2 * mesh.num_nodes();
    let mut constraints = Constraints::new(n);
    constraints.fix_group(&mesh, 0, 0, |_| 0.0);
    constraints.fix_group(&mesh, 0, 1, |_| 0.0);
    let nn = mesh.num_nodes();
    let owned = 2 * (nn * rank / size)..2 * (nn * (rank + 1) / size);
    let system = assemble(&mesh, &material, &constraints, &Loads::default(), owned.clone());
    let k = &system.matrix;
    let matrix =
        Matrix::from_csr_rows(&session, session.world(), n, k.first_row, &k.indptr, &k.indices, &k.values, 2, true)
            .unwrap();
    let contact_rows: Vec<usize> = (1..m).flat_map(|i| [2 * i, 2 * i + 1]).collect();
    let mut rows = contact_rows.clone();
    if args.iter().any(|a| a == "factor_only") {
        rows.clear();
    }
    let t = Instant::now();
    let factor = InverseBlockFactor::new(&session, &matrix, &rows).unwrap();
    let t_inverse = t.elapsed().as_secs_f64();
    let [t_analysis, t_numeric, t_selected] = factor.seconds();
    // One solve, and a check of column 0 of the block against it.
    let mut b = matrix.create_vector().unwrap();
    let mut x = matrix.create_vector().unwrap();
    let mut e = vec![0.0; owned.len()];
    if owned.contains(&2) {
        e[2 - owned.start] = 1.0;
    }
    b.set_owned(&e).unwrap();
    let t = Instant::now();
    factor.solve(&b, &mut x).unwrap();
    let t_solve = t.elapsed().as_secs_f64();
    let column = x.gather_all().unwrap();
    let s = rows.len();
    let block = factor.inverse_block().to_vec();
    let scale = block.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(f64::MIN_POSITIVE);
    let err = (0..s).map(|i| (block[i * s] - column[rows[i]]).abs()).fold(0.0, f64::max) / scale;
    if rank == 0 {
        println!(
            "{size} rank(s), {n} dofs, block {s}: factor + selected inverse {t_inverse:.2} s ({t_analysis:.2} analysis + {t_numeric:.2} numeric + {t_selected:.2} inverse), one solve {t_solve:.3} s, \
             column 0 against a solve {err:.1e}"
        );
    }
    drop(factor);
    if args.iter().any(|a| a == "parallel_schur") {
        let t = Instant::now();
        let f = InverseBlockFactor::with_schur_complement(&session, &matrix, &contact_rows).unwrap();
        let [t_analysis, t_numeric, t_inverse] = f.seconds();
        let diff = f.inverse_block().iter().zip(&block).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
        if rank == 0 {
            println!(
                "distributed Schur: {:.2} s ({t_analysis:.2} analysis + {t_numeric:.2} numeric + {t_inverse:.2} S⁻¹); blocks differ by {diff:.1e}",
                t.elapsed().as_secs_f64()
            );
        }
    }
    if schur && size == 1 {
        let t = Instant::now();
        let f = SchurFactor::new(&session, &matrix, &rows).unwrap();
        let t_schur = t.elapsed().as_secs_f64();
        let diff = f.inverse_block().iter().zip(&block).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
        println!("Schur route: factor + S + S⁻¹ {t_schur:.2} s; blocks differ by {diff:.1e}");
    }
}
