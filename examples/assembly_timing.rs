//! Times the assembly of a ~1e6-dof P1 system (707 × 707 structured grid, ~1e6 triangles) on
//! one core: pattern + values + rhs, clamped left side, a body force and a pressure on the top.
//!
//! Reports wall-clock time and the CPU time of this thread (from `/proc/thread-self/schedstat`,
//! Linux): on a shared machine the wall-clock time includes waiting for a core.
//!
//! `cargo run --release --example assembly_timing [nodes_per_side]`
use signorini::fem::{assemble, Constraints, EdgeLoad, Loads, Material, PlaneModel, Traction};
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use std::time::Instant;

fn grid(m: usize) -> Mesh {
    let h = 1.0 / (m - 1) as f64;
    let mut nodes = Vec::with_capacity(m * m);
    for j in 0..m {
        for i in 0..m {
            nodes.push([i as f64 * h, j as f64 * h]);
        }
    }
    let id = |i: usize, j: usize| j * m + i;
    let mut cells = Vec::with_capacity(6 * (m - 1) * (m - 1));
    for j in 0..m - 1 {
        for i in 0..m - 1 {
            cells.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            cells.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut edges = Vec::new();
    let mut edge_group = Vec::new();
    for i in 0..m - 1 {
        edges.extend([id(m - 1 - i, m - 1), id(m - 2 - i, m - 1)]);
        edge_group.push(0);
        edges.extend([id(0, m - 1 - i), id(0, m - 2 - i)]);
        edge_group.push(1);
    }
    let ncells = cells.len() / 3;
    Mesh {
        order: Order::P1,
        nodes,
        cells,
        cell_group: vec![NO_GROUP; ncells],
        edges,
        edge_group,
        groups: vec![
            PhysicalGroup { name: "top".into(), tag: 1, dim: 1 },
            PhysicalGroup { name: "left".into(), tag: 2, dim: 1 },
        ],
        measure: Default::default(),
    }
}

/// CPU time of the calling thread in seconds (0 where `/proc` is unavailable).
fn thread_cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|ns| ns.parse::<f64>().ok()))
        .map_or(0.0, |ns| ns * 1e-9)
}

fn main() {
    let m: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(707);
    let mesh = grid(m);
    let material = Material { young: 2.0e11, poisson: 0.3, plane: PlaneModel::Strain };
    let ndof = 2 * mesh.num_nodes();
    let mut constraints = Constraints::new(ndof);
    constraints.fix_group(&mesh, 1, 0, |_| 0.0);
    constraints.fix_group(&mesh, 1, 1, |_| 0.0);
    let gravity = |_: [f64; 2]| [0.0, -7.8e4];
    let with_loads = Loads {
        body_force: Some(&gravity),
        edge_loads: vec![EdgeLoad { group: 0, traction: Traction::Pressure(1e6) }],
    };
    println!("{} nodes, {} triangles, {} dofs", mesh.num_nodes(), mesh.num_cells(), ndof);
    for (name, loads) in [("no loads", Loads::default()), ("body force + pressure", with_loads)] {
        let (mut best_wall, mut best_cpu) = (f64::INFINITY, f64::INFINITY);
        let mut nnz = 0;
        for _ in 0..3 {
            let (t, c) = (Instant::now(), thread_cpu_seconds());
            let system = assemble(&mesh, &material, &constraints, &loads, 0..ndof);
            best_cpu = best_cpu.min(thread_cpu_seconds() - c);
            best_wall = best_wall.min(t.elapsed().as_secs_f64());
            nnz = system.matrix.nnz();
        }
        println!("assemble ({name}): wall {best_wall:.3} s, cpu {best_cpu:.3} s (best of 3), nnz = {nnz}");
    }
    let (t, c) = (Instant::now(), thread_cpu_seconds());
    let half = ndof / 2 + 1;
    let a = assemble(&mesh, &material, &constraints, &Loads::default(), 0..half);
    let b = assemble(&mesh, &material, &constraints, &Loads::default(), half..ndof);
    println!(
        "two row blocks: wall {:.3} s, cpu {:.3} s, nnz = {} + {}",
        t.elapsed().as_secs_f64(),
        thread_cpu_seconds() - c,
        a.matrix.nnz(),
        b.matrix.nnz()
    );
}
