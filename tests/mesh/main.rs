//! Tests of the mesh module: structured rectangles, P1 -> P2, validation, MSH 4.1 input and
//! Gmsh-generated meshes (the `gmsh` binary must be installed).
#[path = "../common/edit.rs"]
mod edit;

mod cache;
mod gmsh;
mod msh_inline;
mod p2_arcs;
mod structured;
mod validation;

use signorini::mesh::gmsh::{MeshRequest, Refinement, Shape};
use signorini::mesh::msh::read_msh;
use signorini::mesh::{Mesh, Order};
use signorini::Error;
use std::path::PathBuf;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// A directory of its own for one test, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("signorini-mesh-tests-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
    fn path(&self, file: &str) -> PathBuf {
        self.0.join(file)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The path an inline file `name` is written to by [`read_inline`].
fn inline_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("signorini-mesh-tests-{}-{name}", std::process::id())).join(format!("{name}.msh"))
}

/// Write `text` to `<name>.msh` in a scratch directory, read it, remove it.
fn read_inline(name: &str, text: &str) -> signorini::Result<Mesh> {
    let dir = Scratch::new(name);
    let path = dir.path(&format!("{name}.msh"));
    assert_eq!(path, inline_path(name));
    std::fs::write(&path, text).unwrap();
    read_msh(&path)
}

fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

fn vertex_area(mesh: &Mesh, c: usize) -> f64 {
    let v = mesh.cell(c);
    signed_area(mesh.nodes[v[0]], mesh.nodes[v[1]], mesh.nodes[v[2]])
}

/// Area of the (possibly curved) cell: integral of det J of the isoparametric map. For P2,
/// det J is quadratic and the edge-midpoint rule (weights 1/6) integrates it exactly.
fn cell_area(mesh: &Mesh, c: usize) -> f64 {
    match mesh.order {
        Order::P1 => vertex_area(mesh, c),
        Order::P2 => {
            let v = mesh.cell(c);
            let x: Vec<[f64; 2]> = v.iter().map(|&n| mesh.nodes[n]).collect();
            let det = |xi: f64, eta: f64| {
                let l0 = 1.0 - xi - eta;
                let dxi = [1.0 - 4.0 * l0, 4.0 * xi - 1.0, 0.0, 4.0 * (l0 - xi), 4.0 * eta, -4.0 * eta];
                let deta = [1.0 - 4.0 * l0, 0.0, 4.0 * eta - 1.0, -4.0 * xi, 4.0 * xi, 4.0 * (l0 - eta)];
                let mut j = [0.0; 4];
                for i in 0..6 {
                    j[0] += dxi[i] * x[i][0];
                    j[1] += deta[i] * x[i][0];
                    j[2] += dxi[i] * x[i][1];
                    j[3] += deta[i] * x[i][1];
                }
                j[0] * j[3] - j[1] * j[2]
            };
            (det(0.5, 0.0) + det(0.5, 0.5) + det(0.0, 0.5)) / 6.0
        }
    }
}

fn total_area(mesh: &Mesh) -> f64 {
    (0..mesh.num_cells()).map(|c| cell_area(mesh, c)).sum()
}

fn group_length(mesh: &Mesh, name: &str) -> f64 {
    let g = mesh.require_group(name, 1).unwrap();
    mesh.edges_in_group(g).map(|e| mesh.edge_normal(e).1).sum()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
}

/// Every boundary edge's outward normal points away from the cell it bounds.
fn assert_outward_normals(mesh: &Mesh) {
    for e in 0..mesh.num_edges() {
        let ed = mesh.edge(e);
        let (n, _) = mesh.edge_normal(e);
        let c = (0..mesh.num_cells())
            .find(|&c| {
                let v = mesh.cell(c);
                v[..3].contains(&ed[0]) && v[..3].contains(&ed[1])
            })
            .expect("boundary edge on a triangle");
        let v = mesh.cell(c);
        let opposite = *v[..3].iter().find(|&&x| x != ed[0] && x != ed[1]).unwrap();
        let (a, o) = (mesh.nodes[ed[0]], mesh.nodes[opposite]);
        let inward = [o[0] - a[0], o[1] - a[1]];
        assert!(n[0] * inward[0] + n[1] * inward[1] < 0.0, "edge {e} normal {n:?} points inwards");
    }
}

fn assert_counter_clockwise(mesh: &Mesh) {
    for c in 0..mesh.num_cells() {
        assert!(vertex_area(mesh, c) > 0.0, "triangle {c} is not counter-clockwise");
    }
}

fn mesh_error_text(result: signorini::Result<Mesh>) -> (Error, String) {
    let e = result.expect_err("expected an error");
    let text = e.to_string();
    (e, text)
}

fn half_disc_request(cell_size: f64, order: Order) -> MeshRequest {
    MeshRequest {
        shape: Shape::HalfDisc { center: [0.0, 0.1], radius: 0.1 },
        cell_size,
        refinement: Some(Refinement { point: [0.0, 0.0], cell_size: cell_size / 8.0, radius: 0.015 }),
        order,
    }
}

/// The same mesh to the bit: every array and group.
fn assert_identical(a: &Mesh, b: &Mesh) {
    assert_eq!(a.order, b.order);
    let bits = |m: &Mesh| m.nodes.iter().flat_map(|p| [p[0].to_bits(), p[1].to_bits()]).collect::<Vec<u64>>();
    assert!(bits(a) == bits(b), "node coordinates differ");
    assert_eq!(a.cells, b.cells);
    assert_eq!(a.cell_group, b.cell_group);
    assert_eq!(a.edges, b.edges);
    assert_eq!(a.edge_group, b.edge_group);
    assert_eq!(a.groups, b.groups);
}
