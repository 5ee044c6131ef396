//! Constraints, the rigid-motion check, assembly with Dirichlet elimination and load vectors.

use crate::{all_dofs, dirichlet, steel, to_dense, Distortion, Grid, Random, BOTTOM, LEFT, RIGHT, TOP};
use nalgebra::{DMatrix, DVector};
use signorini::error::Error;
use signorini::fem::{
    assemble, element_stiffness, lagrange, load_vector, quadrature, residual_forces, Constraints, EdgeLoad, Loads,
    Material, PlaneModel, Traction,
};
use signorini::mesh::{Mesh, Order};
use std::collections::HashSet;

// ---------------------------------------------------------------------------------------------
// Constraints and the rigid-motion check.
// ---------------------------------------------------------------------------------------------

fn unconstrained_message(mesh: &Mesh, c: &Constraints) -> String {
    match c.check_rigid_motions(mesh) {
        Err(Error::Unconstrained(msg)) => msg,
        other => panic!("expected Error::Unconstrained, got {other:?}"),
    }
}

#[test]
fn rigid_motion_check_names_the_free_motions() {
    let mesh = Grid::new(4, Order::P1).build();
    let ndof = 2 * mesh.num_nodes();
    let none = Constraints::new(ndof);
    let msg = unconstrained_message(&mesh, &none);
    for m in ["translation in x", "translation in y", "rotation about z", "3 rigid motions"] {
        assert!(msg.contains(m), "{msg}");
    }
    // One x-fixed node: translation in y and a rotation remain.
    let mut one = Constraints::new(ndof);
    one.fix(0, 0.0);
    let msg = unconstrained_message(&mesh, &one);
    assert!(
        msg.contains("translation in y") && msg.contains("rotation about z") && !msg.contains("translation in x"),
        "{msg}"
    );
    assert!(msg.contains("2 rigid motions"), "{msg}");
    // One node fully fixed: rotation about that node.
    let node = 7; // (2h, h) on the 5 × 5 vertex grid
    let mut pin = Constraints::new(ndof);
    pin.fix(2 * node, 0.0);
    pin.fix(2 * node + 1, 0.0);
    let msg = unconstrained_message(&mesh, &pin);
    assert!(
        msg.contains("1 rigid motion free: rotation about z (about the point (5.000000e-1, 2.500000e-1))"),
        "{msg}"
    );
    // x fixed along the bottom, y at one bottom node: rotation about that node is still free.
    let mut rollers = Constraints::new(ndof);
    rollers.fix_group(&mesh, BOTTOM, 0, |_| 0.0);
    let node = 1; // (h, 0)
    rollers.fix(2 * node + 1, 0.0);
    let msg = unconstrained_message(&mesh, &rollers);
    assert!(msg.contains("rotation about z (about the point (2.500000e-1, 0.000000e0))"), "{msg}");
    // Rollers on two sides, or a clamped side: all blocked.
    let mut sym = Constraints::new(ndof);
    sym.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
    sym.fix_group(&mesh, LEFT, 0, |_| 0.0);
    assert!(sym.check_rigid_motions(&mesh).is_ok());
    let clamped = dirichlet(&mesh, &[LEFT], &|_| [0.0, 0.0]);
    assert!(clamped.check_rigid_motions(&mesh).is_ok());
    // Also far from the origin and at a small scale.
    let mut far = mesh.clone();
    for p in &mut far.nodes {
        *p = [1e6 + 1e-3 * p[0], -3e5 + 1e-3 * p[1]];
    }
    let clamped = dirichlet(&far, &[LEFT], &|_| [0.0, 0.0]);
    assert!(clamped.check_rigid_motions(&far).is_ok());
    let mut line = Constraints::new(ndof);
    line.fix_group(&far, BOTTOM, 1, |_| 0.0);
    let msg = unconstrained_message(&far, &line);
    assert!(
        msg.contains("translation in x") && !msg.contains("translation in y") && !msg.contains("rotation"),
        "{msg}"
    );
}

#[test]
fn constraints_bookkeeping_and_fix_group_includes_mid_nodes() {
    let mesh = Grid::new(3, Order::P2).build();
    let mut c = Constraints::new(2 * mesh.num_nodes());
    assert_eq!(c.num_fixed(), 0);
    c.fix_group(&mesh, TOP, 1, |x| x[0] * 2.0);
    // 3 edges on the top: 4 vertices + 3 mid nodes.
    assert_eq!(c.num_fixed(), 7);
    for (dof, v) in c.fixed() {
        assert_eq!(dof % 2, 1);
        let x = mesh.nodes[dof / 2];
        assert!((x[1] - 1.0).abs() < 1e-15);
        assert_eq!(v, 2.0 * x[0]);
    }
    let mids = c.fixed().filter(|(d, _)| d / 2 >= 16).count();
    assert_eq!(mids, 3);
    c.fix(0, 1.5);
    assert_eq!(c.value(0), Some(1.5));
    assert_eq!(c.value(1), None);
    assert_eq!(c.value(10_000_000), None);
}

// ---------------------------------------------------------------------------------------------
// Assembly: pattern, elimination, row blocks.
// ---------------------------------------------------------------------------------------------

/// The unconstrained global stiffness, dense, from the element matrices.
fn dense_stiffness(mesh: &Mesh, m: &Material) -> DMatrix<f64> {
    let n = 2 * mesh.num_nodes();
    let npc = mesh.order.nodes_per_cell();
    let mut k = DMatrix::zeros(n, n);
    for c in 0..mesh.num_cells() {
        let nodes = mesh.cell(c);
        let x: Vec<[f64; 2]> = nodes.iter().map(|&i| mesh.nodes[i]).collect();
        let ke = element_stiffness(mesh.order, &x, m);
        for a in 0..2 * npc {
            for b in 0..2 * npc {
                k[(2 * nodes[a / 2] + a % 2, 2 * nodes[b / 2] + b % 2)] += ke[a * 2 * npc + b];
            }
        }
    }
    k
}

#[test]
fn assembly_eliminates_dirichlet_symmetrically_with_an_exact_pattern() {
    for (order, grid) in [(Order::P1, 4), (Order::P2, 3)] {
        let mesh = Grid::new(grid, order).distorted(Distortion::Random(0.2)).curved(0.1, 0.0).build();
        let m = steel(PlaneModel::Strain);
        let ndof = 2 * mesh.num_nodes();
        let mut c = Constraints::new(ndof);
        c.fix_group(&mesh, LEFT, 0, |x| 1e-3 * x[1]);
        c.fix_group(&mesh, LEFT, 1, |x| -2e-3 * x[1]);
        c.fix_group(&mesh, BOTTOM, 1, |x| 5e-4 * x[0]);
        let force = |x: [f64; 2]| [1e6 * x[1], -2e6];
        let loads = Loads {
            body_force: Some(&force),
            edge_loads: vec![EdgeLoad { group: TOP, traction: Traction::Pressure(3e7) }],
        };
        let system = assemble(&mesh, &m, &c, &loads, all_dofs(&mesh));
        let k = dense_stiffness(&mesh, &m);
        let f = load_vector(&mesh, &loads);
        // Expected pattern: free rows hold the free dofs of the neighbouring nodes.
        let mut neighbours = vec![HashSet::new(); mesh.num_nodes()];
        for cell in mesh.cells.chunks(order.nodes_per_cell()) {
            for &a in cell {
                neighbours[a].extend(cell.iter().copied());
            }
        }
        let a = &system.matrix;
        assert_eq!((a.first_row, a.num_rows(), a.num_cols), (0, ndof, ndof));
        for i in 0..ndof {
            let (cols, vals) = a.row(i);
            assert!(cols.windows(2).all(|w| w[0] < w[1]), "row {i}: columns not sorted");
            match c.value(i) {
                Some(g) => {
                    assert_eq!(cols, &[i]);
                    assert_eq!(vals, &[m.young]);
                    assert_eq!(system.rhs[i], m.young * g);
                }
                None => {
                    let mut expect: Vec<usize> = neighbours[i / 2]
                        .iter()
                        .flat_map(|&nb| [2 * nb, 2 * nb + 1])
                        .filter(|&j| !c.is_fixed(j))
                        .collect();
                    expect.sort();
                    assert_eq!(cols, &expect[..], "row {i}: pattern");
                    for (&j, &v) in cols.iter().zip(vals) {
                        assert!((v - k[(i, j)]).abs() <= 1e-12 * k[(i, i)].abs(), "row {i} col {j}");
                    }
                    let lifted: f64 = c.fixed().map(|(j, g)| k[(i, j)] * g).sum();
                    let expect_rhs = f[i] - lifted;
                    assert!((system.rhs[i] - expect_rhs).abs() <= 1e-10 * (f[i].abs() + lifted.abs() + 1.0), "rhs {i}");
                }
            }
        }
        // Symmetric and, with the rigid motions removed, positive definite.
        let dense = to_dense(&system);
        assert!((&dense - dense.transpose()).amax() <= 1e-14 * dense.amax());
        assert!(dense.clone().cholesky().is_some());
        // residual_forces is K u.
        let mut rng = Random(3);
        let u: Vec<f64> = (0..ndof).map(|_| rng.next()).collect();
        let ku = &k * DVector::from_column_slice(&u);
        let r = residual_forces(&mesh, &m, &u);
        for i in 0..ndof {
            assert!((r[i] - ku[i]).abs() <= 1e-12 * k.amax() * 10.0, "K u at {i}");
        }
    }
}

#[test]
fn row_blocks_match_the_full_assembly() {
    for order in [Order::P1, Order::P2] {
        let mesh = Grid::new(4, order).distorted(Distortion::Random(0.2)).build();
        let m = steel(PlaneModel::Stress);
        let ndof = 2 * mesh.num_nodes();
        let mut c = dirichlet(&mesh, &[LEFT], &|x| [0.0, 1e-3 * x[1]]);
        c.fix(2 * 13, 0.0);
        let force = |x: [f64; 2]| [x[0], 1.0 - x[1]];
        let field = |_x: [f64; 2], n: [f64; 2]| [n[1], -n[0]];
        let loads = Loads {
            body_force: Some(&force),
            edge_loads: vec![
                EdgeLoad { group: RIGHT, traction: Traction::Constant([1e5, -3e4]) },
                EdgeLoad { group: TOP, traction: Traction::Field(&field) },
            ],
        };
        let full = assemble(&mesh, &m, &c, &loads, 0..ndof);
        // Split inside a node (odd boundary), into three blocks, one of them a single row.
        let cuts = [0, ndof / 2 + 1, ndof / 2 + 2, ndof];
        let mut total_nnz = 0;
        for w in cuts.windows(2) {
            let part = assemble(&mesh, &m, &c, &loads, w[0]..w[1]);
            assert_eq!(part.matrix.first_row, w[0]);
            assert_eq!(part.matrix.num_rows(), w[1] - w[0]);
            assert_eq!(part.rhs.len(), w[1] - w[0]);
            total_nnz += part.matrix.nnz();
            for i in w[0]..w[1] {
                assert_eq!(part.matrix.row(i), full.matrix.row(i), "{order:?} row {i}");
                assert_eq!(part.rhs[i - w[0]], full.rhs[i], "{order:?} rhs {i}");
            }
        }
        assert_eq!(total_nnz, full.matrix.nnz());
        // Out-of-range and empty ranges are clamped.
        let empty = assemble(&mesh, &m, &c, &loads, ndof..ndof + 10);
        assert_eq!(empty.matrix.num_rows(), 0);
        assert_eq!(empty.matrix.indptr, vec![0]);
        let tail = assemble(&mesh, &m, &c, &loads, ndof - 3..ndof + 10);
        assert_eq!(tail.matrix.num_rows(), 3);
    }
}

#[test]
fn load_vector_resultants() {
    let mesh = Grid::new(5, Order::P2).distorted(Distortion::Random(0.2)).curved(0.06, 0.1).build();
    let force = |_: [f64; 2]| [2.0, -3.0];
    let p = 7.0;
    let loads = Loads {
        body_force: Some(&force),
        edge_loads: vec![
            EdgeLoad { group: BOTTOM, traction: Traction::Pressure(p) },
            EdgeLoad { group: LEFT, traction: Traction::Constant([0.5, 0.25]) },
        ],
    };
    let f = load_vector(&mesh, &loads);
    let fx: f64 = f.iter().step_by(2).sum();
    let fy: f64 = f.iter().skip(1).step_by(2).sum();
    // Area: the curved right and top sides change it; compute it by quadrature of det J.
    let mut area = 0.0;
    let rule = quadrature::triangle(2);
    for c in 0..mesh.num_cells() {
        let x: Vec<[f64; 2]> = mesh.cell(c).iter().map(|&k| mesh.nodes[k]).collect();
        for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
            area += w * lagrange::map_cell_point(Order::P2, &x, xi).det;
        }
    }
    // Pressure on the bottom (n = (0, −1)): t = (0, p); constant traction on the left (length 1).
    let ex = 2.0 * area + 0.5;
    let ey = -3.0 * area + p + 0.25;
    assert!((fx - ex).abs() < 1e-13 && (fy - ey).abs() < 1e-13, "({fx}, {fy}) vs ({ex}, {ey})");
    assert!((area - 1.0).abs() > 1e-4, "the curved boundary should change the area");
}
