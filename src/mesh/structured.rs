//! Structured triangle meshes of a rectangle, built without Gmsh.
//!
//! The rectangle `[x0, x0 + Lx] x [y0, y0 + Ly]` is cut into `nx x ny` equal cells; grid vertex
//! `(i, j)` sits at `(x0 + Lx i / nx, y0 + Ly j / ny)` and has number `j (nx + 1) + i`. Each cell
//! is split along one diagonal, alternating like a checkerboard so that no direction is favoured
//! (a single diagonal direction makes P1 solutions slightly anisotropic):
//!
//! ```text
//!   (i+j) even                 (i+j) odd
//!
//!   d ------- c                d ------- c
//!   |       / |                | \       |
//!   |  T1 /   |                |   \ T1  |
//!   |   /  T0 |                | T0  \   |
//!   | /       |                |       \ |
//!   a ------- b                a ------- b
//!
//!   T0 = (a, b, c), T1 = (a, c, d)   T0 = (a, b, d), T1 = (b, c, d)
//! ```
//!
//! All triangles are counter-clockwise. Boundary edges run with the domain on their left:
//! "bottom" left to right, "right" upwards, "top" right to left, "left" downwards; the region is
//! "domain".
//!
//! For P2 the nodes are the points of the grid refined twice in each direction; vertices keep
//! their P1 numbers and the mid nodes follow: first those of the horizontal sides
//! (`nx (ny + 1)` of them, row by row), then the vertical sides (`(nx + 1) ny`), then the cell
//! diagonals (`nx ny`, one per cell, at the cell centre).
use super::{Measure, Mesh, Order, PhysicalGroup};
use crate::error::{Error, Result};

/// Numbers of cells `(nx, ny)` so that cells are at most `cell_size` wide and high:
/// `ceil(size / cell_size)`, at least 1 (also for a nonpositive or non-finite `cell_size`, which
/// callers should reject first). The quotient is lowered by a relative `1e-9` before rounding
/// up, so that a size that is a whole number of cells gives that number despite round-off
/// (`0.07 / 0.01 = 7.000000000000001` in floating point: 7 cells, not 8).
pub fn cells_for_size(size: [f64; 2], cell_size: f64) -> (usize, usize) {
    let count = |l: f64| {
        let n = (l / cell_size * (1.0 - 1e-9)).ceil();
        // `as` saturates: NaN -> 0, +inf -> usize::MAX (rejected by `rectangle` as too many cells).
        (n as usize).max(1)
    };
    (count(size[0]), count(size[1]))
}

/// Most triangles a structured mesh may have: 1e8 triangles already take about 5 GB (P1
/// connectivity and edge tables), far beyond what the solver handles; the limit turns an absurd
/// cell size into an error instead of an allocation failure.
const MAX_TRIANGLES: usize = 100_000_000;

/// A structured triangle mesh of the rectangle with lower-left corner `origin` and extent `size`,
/// `nx x ny` cells, two triangles each. Groups: curves "bottom", "right", "top", "left" (tags
/// 1-4) and surface "domain" (tag 5).
pub fn rectangle(origin: [f64; 2], size: [f64; 2], nx: usize, ny: usize, order: Order) -> Result<Mesh> {
    let entity = || {
        format!("rectangle (origin ({}, {}), size ({}, {}), {nx} x {ny} cells)", origin[0], origin[1], size[0], size[1])
    };
    if nx == 0 || ny == 0 {
        return Err(Error::mesh(entity(), format!("nx = {nx}, ny = {ny}: need at least one cell in each direction")));
    }
    if !(size[0] > 0.0 && size[1] > 0.0 && size[0].is_finite() && size[1].is_finite()) {
        return Err(Error::mesh(
            entity(),
            format!("size ({}, {}): both sides must be positive and finite", size[0], size[1]),
        ));
    }
    if !(origin[0].is_finite() && origin[1].is_finite()) {
        return Err(Error::mesh(entity(), "the origin must be finite"));
    }
    match nx.checked_mul(ny).and_then(|n| n.checked_mul(2)) {
        Some(n) if n <= MAX_TRIANGLES => {}
        _ => {
            return Err(Error::mesh(
                entity(),
                format!("{nx} x {ny} cells is more than {MAX_TRIANGLES} triangles; use a larger cell size"),
            ))
        }
    }

    let row = nx + 1;
    let nv = row * (ny + 1);
    let vertex = |i: usize, j: usize| j * row + i;
    // Mid node numbering (P2).
    let horizontal = |i: usize, j: usize| nv + j * nx + i; // side (i, j) - (i + 1, j)
    let nh = nx * (ny + 1);
    let vertical = |i: usize, j: usize| nv + nh + j * row + i; // side (i, j) - (i, j + 1)
    let nvert = row * ny;
    let diagonal = |i: usize, j: usize| nv + nh + nvert + j * nx + i; // centre of cell (i, j)

    // k / n is exact at both ends, so the corners are exactly origin and origin + size.
    let coordinate = |k: usize, n: usize, axis: usize| origin[axis] + size[axis] * (k as f64 / n as f64);
    let p2 = order == Order::P2;
    let num_nodes = if p2 { (2 * nx + 1) * (2 * ny + 1) } else { nv };
    let mut nodes = Vec::with_capacity(num_nodes);
    for j in 0..=ny {
        let y = coordinate(j, ny, 1);
        nodes.extend((0..=nx).map(|i| [coordinate(i, nx, 0), y]));
    }
    if p2 {
        for j in 0..=ny {
            let y = coordinate(j, ny, 1);
            nodes.extend((0..nx).map(|i| [coordinate(2 * i + 1, 2 * nx, 0), y]));
        }
        for j in 0..ny {
            let y = coordinate(2 * j + 1, 2 * ny, 1);
            nodes.extend((0..=nx).map(|i| [coordinate(i, nx, 0), y]));
        }
        for j in 0..ny {
            let y = coordinate(2 * j + 1, 2 * ny, 1);
            nodes.extend((0..nx).map(|i| [coordinate(2 * i + 1, 2 * nx, 0), y]));
        }
    }
    debug_assert_eq!(nodes.len(), num_nodes);

    let npc = order.nodes_per_cell();
    let mut cells = Vec::with_capacity(2 * nx * ny * npc);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            let (ab, bc, dc, ad) = (horizontal(i, j), vertical(i + 1, j), horizontal(i, j + 1), vertical(i, j));
            let diag = diagonal(i, j);
            if (i + j) % 2 == 0 {
                // Diagonal a-c.
                cells.extend_from_slice(&[a, b, c]);
                if p2 {
                    cells.extend_from_slice(&[ab, bc, diag]);
                }
                cells.extend_from_slice(&[a, c, d]);
                if p2 {
                    cells.extend_from_slice(&[diag, dc, ad]);
                }
            } else {
                // Diagonal b-d.
                cells.extend_from_slice(&[a, b, d]);
                if p2 {
                    cells.extend_from_slice(&[ab, diag, ad]);
                }
                cells.extend_from_slice(&[b, c, d]);
                if p2 {
                    cells.extend_from_slice(&[bc, dc, diag]);
                }
            }
        }
    }

    let mut edges = Vec::with_capacity(2 * (nx + ny) * order.nodes_per_edge());
    let mut edge_group = Vec::with_capacity(2 * (nx + ny));
    let mut push_edge = |v0: usize, v1: usize, mid: usize, group: usize| {
        edges.extend_from_slice(&[v0, v1]);
        if p2 {
            edges.push(mid);
        }
        edge_group.push(group);
    };
    for i in 0..nx {
        push_edge(vertex(i, 0), vertex(i + 1, 0), horizontal(i, 0), 0);
    }
    for j in 0..ny {
        push_edge(vertex(nx, j), vertex(nx, j + 1), vertical(nx, j), 1);
    }
    for i in (0..nx).rev() {
        push_edge(vertex(i + 1, ny), vertex(i, ny), horizontal(i, ny), 2);
    }
    for j in (0..ny).rev() {
        push_edge(vertex(0, j + 1), vertex(0, j), vertical(0, j), 3);
    }

    let group = |name: &str, tag: i32, dim: u8| PhysicalGroup { name: name.to_string(), tag, dim };
    let groups = vec![
        group("bottom", 1, 1),
        group("right", 2, 1),
        group("top", 3, 1),
        group("left", 4, 1),
        group("domain", 5, 2),
    ];
    let mut mesh = Mesh {
        order,
        nodes,
        cell_group: vec![4; 2 * nx * ny],
        cells,
        edges,
        edge_group,
        groups,
        measure: Measure::Plane,
    };
    // Correct by construction; validation costs a fraction of the build and keeps the promise
    // every constructor makes.
    mesh.validate()?;
    Ok(mesh)
}
