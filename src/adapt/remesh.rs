//! Remeshing from a size map through Gmsh.
//!
//! The size of an element is measured as the side of the equilateral triangle of the same area,
//!
//! ```text
//!   h_E = (4 |E| / √3)^½,
//! ```
//!
//! which is what Gmsh's target sizes mean (edge lengths of near-equilateral triangles). The
//! optimal size map ([`super::size_map`]) gives `h*_E = r_E h_E` per element; Gmsh wants sizes at
//! points, so each vertex takes the mean of `h*_E` over the elements around it (a node between
//! a strongly refined element and a coarsened one gets a size between the two, and Gmsh grades
//! the transition). The nodal sizes become a list-based post-processing view (`ST` lines, one
//! triangle of the current mesh each) that Gmsh uses as background mesh with every other size
//! source switched off ([`crate::mesh::gmsh::generate_with_background`]), so the new mesh
//! follows the map, coarser or finer, and its boundary nodes lie on the true curves.
use std::fmt::Write as _;

use crate::error::{Error, Result};
use crate::mesh::gmsh::{generate_with_background, MeshRequest};
use crate::mesh::Mesh;

/// Estimated triangle count above which a size map is refused.
const MAX_TRIANGLES: f64 = 2e7;

fn vertices(mesh: &Mesh, cell: usize) -> [[f64; 2]; 3] {
    let v = mesh.cell(cell);
    [mesh.nodes[v[0]], mesh.nodes[v[1]], mesh.nodes[v[2]]]
}

fn area(t: &[[f64; 2]; 3]) -> f64 {
    0.5 * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1])).abs()
}

/// `h_E` of every cell (vertex triangle).
pub fn element_sizes(mesh: &Mesh) -> Vec<f64> {
    (0..mesh.num_cells()).map(|c| (4.0 * area(&vertices(mesh, c)) / 3f64.sqrt()).sqrt()).collect()
}

/// The mean of the element sizes `sizes` around each vertex (0 for mid-edge nodes, which no
/// view uses).
pub fn nodal_sizes(mesh: &Mesh, sizes: &[f64]) -> Vec<f64> {
    let mut sum = vec![0.0; mesh.num_nodes()];
    let mut count = vec![0usize; mesh.num_nodes()];
    for (c, &h) in sizes.iter().enumerate() {
        for &n in &mesh.cell(c)[..3] {
            sum[n] += h;
            count[n] += 1;
        }
    }
    sum.iter().zip(&count).map(|(s, &k)| if k > 0 { s / k as f64 } else { 0.0 }).collect()
}

/// The Gmsh list-based view of nodal sizes on the vertex triangles of `mesh`.
pub fn size_view(mesh: &Mesh, nodal: &[f64]) -> String {
    let mut pos = String::with_capacity(mesh.num_cells() * 120);
    pos.push_str("View \"sizes\" {\n");
    for c in 0..mesh.num_cells() {
        let v = &mesh.cell(c)[..3];
        let x: Vec<[f64; 2]> = v.iter().map(|&n| mesh.nodes[n]).collect();
        let _ = writeln!(
            pos,
            "ST({:?},{:?},0,{:?},{:?},0,{:?},{:?},0){{{:?},{:?},{:?}}};",
            x[0][0], x[0][1], x[1][0], x[1][1], x[2][0], x[2][1], nodal[v[0]], nodal[v[1]], nodal[v[2]]
        );
    }
    pos.push_str("};\n");
    pos
}

/// A new mesh of `request`'s shape with the target sizes `targets` (`h*_E`, one per cell of
/// `mesh`, which must mesh the same shape).
pub fn remesh(mesh: &Mesh, request: &MeshRequest, targets: &[f64]) -> Result<Mesh> {
    if targets.len() != mesh.num_cells() {
        return Err(Error::Usage(format!(
            "remesh: {} target sizes for {} cells; give one per cell",
            targets.len(),
            mesh.num_cells()
        )));
    }
    if let Some(c) = targets.iter().position(|h| !(h.is_finite() && *h > 0.0)) {
        return Err(Error::Usage(format!("remesh: cell {c} has target size {}; sizes must be positive", targets[c])));
    }
    // Each cell E becomes about |E| / (√3/4 h*²) triangles.
    let estimate: f64 =
        (0..mesh.num_cells()).map(|c| area(&vertices(mesh, c)) / (3f64.sqrt() / 4.0 * targets[c] * targets[c])).sum();
    if estimate > MAX_TRIANGLES {
        return Err(Error::Usage(format!(
            "remesh: the size map asks for about {estimate:.2e} triangles (limit {MAX_TRIANGLES:.0e}); aim at a larger target error"
        )));
    }
    let nodal = nodal_sizes(mesh, targets);
    generate_with_background(request, &size_view(mesh, &nodal))
}
