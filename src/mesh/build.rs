//! Building the mesh a scene describes: the description ([`MeshSpec`]: a rectangle, structured
//! or meshed by Gmsh, a disc, a half disc, or a mesh file) and [`build`], which turns it into a
//! [`Mesh`] at an order. It sits below both the scene reader (which meshes the bodies of a scene
//! with several bodies to place them) and the problem driver.
use std::path::{Path, PathBuf};

use super::cache::{CacheReport, MeshCache};
use super::{Mesh, Order};
use crate::error::{Error, Result};

/// The geometry and how to mesh it.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSpec {
    /// `[origin, origin + size]`; boundary parts `bottom`, `right`, `top`, `left`.
    Rectangle {
        /// Lower-left corner (m).
        origin: [f64; 2],
        /// Width and height (m), > 0.
        size: [f64; 2],
        /// Target edge length (m), > 0.
        cell_size: f64,
        /// Structured grid or Gmsh.
        mesher: Mesher,
        /// Local refinement (Gmsh meshes only).
        refine: Option<RefineSpec>,
    },
    /// Full disc; boundary part `circle`. Always meshed by gmsh.
    Disc {
        /// Centre (m).
        center: [f64; 2],
        /// Radius (m), > 0.
        radius: f64,
        /// Target edge length (m), > 0.
        cell_size: f64,
        /// Local refinement (Gmsh meshes only).
        refine: Option<RefineSpec>,
    },
    /// Lower half disc (flat side on top, at `center.y`); boundary parts `arc` and `flat`.
    /// Always meshed by gmsh.
    HalfDisc {
        /// Centre of the full disc (m); the flat side is at `center[1]`.
        center: [f64; 2],
        /// Radius (m), > 0.
        radius: f64,
        /// Target edge length (m), > 0.
        cell_size: f64,
        /// Local refinement (Gmsh meshes only).
        refine: Option<RefineSpec>,
    },
    /// Lower-right quarter disc (`x >= center.x`, `y <= center.y`): the meridian section of
    /// the lower half of a sphere when `center[0] = 0`; boundary parts `arc`, `flat` (top) and
    /// `axis` (left, `x = center[0]`). Always meshed by gmsh.
    QuarterDisc {
        /// Centre of the full disc (m): the corner between `flat` and `axis`.
        center: [f64; 2],
        /// Radius (m), > 0.
        radius: f64,
        /// Target edge length (m), > 0.
        cell_size: f64,
        /// Local refinement (Gmsh meshes only).
        refine: Option<RefineSpec>,
    },
    /// A Gmsh MSH 4.1 file; the path is already resolved against the scene's directory.
    /// `geometry`: the Gmsh `.geo` script the file was meshed from (`geometry = "part.geo"`),
    /// which `signorini adapt` remeshes with its size map.
    File {
        /// The MSH 4.1 file.
        path: PathBuf,
        /// The `.geo` script it was meshed from, if given.
        geometry: Option<PathBuf>,
    },
}

/// Who meshes a rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mesher {
    /// A uniform grid of right triangles (no gmsh needed).
    Structured,
    /// An unstructured gmsh mesh.
    Gmsh,
}

/// Local refinement for gmsh: cells of size about `cell_size` within `radius` of `point`,
/// growing back to the mesh's `cell_size` away from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefineSpec {
    /// Centre of the refined zone (m).
    pub point: [f64; 2],
    /// Target edge length near `point` (m), > 0 and not above the mesh's `cell_size`.
    pub cell_size: f64,
    /// Radius of the zone meshed at `cell_size` (m), > 0.
    pub radius: f64,
}

/// The mesh a description gives, at an order: generated (structured or Gmsh) or read from a
/// file; the order of the file's triangles when it was read from one; and for a Gmsh mesh what
/// the mesh cache did ([`MeshCache::from_env`]: on unless `SIGNORINI_NO_MESH_CACHE` is set).
/// One body's mesh before its placement, for a scene with several bodies.
pub fn build(spec: &MeshSpec, order: Order) -> Result<(Mesh, Option<Order>, Option<CacheReport>)> {
    let (shape, cell_size, refine) = match spec {
        MeshSpec::Rectangle { origin, size, cell_size, mesher: Mesher::Structured, .. } => {
            let (nx, ny) = super::structured::cells_for_size(*size, *cell_size);
            return Ok((super::structured::rectangle(*origin, *size, nx, ny, order)?, None, None));
        }
        MeshSpec::File { path, .. } => return mesh_file(path, order).map(|(m, o)| (m, o, None)),
        MeshSpec::Rectangle { origin, size, cell_size, mesher: Mesher::Gmsh, refine } => {
            (super::gmsh::Shape::Rectangle { origin: *origin, size: *size }, *cell_size, refine)
        }
        MeshSpec::Disc { center, radius, cell_size, refine } => {
            (super::gmsh::Shape::Disc { center: *center, radius: *radius }, *cell_size, refine)
        }
        MeshSpec::HalfDisc { center, radius, cell_size, refine } => {
            (super::gmsh::Shape::HalfDisc { center: *center, radius: *radius }, *cell_size, refine)
        }
        MeshSpec::QuarterDisc { center, radius, cell_size, refine } => {
            (super::gmsh::Shape::QuarterDisc { center: *center, radius: *radius }, *cell_size, refine)
        }
    };
    let request = super::gmsh::MeshRequest {
        shape,
        cell_size,
        refinement: refine.as_ref().map(|r| super::gmsh::Refinement {
            point: r.point,
            cell_size: r.cell_size,
            radius: r.radius,
        }),
        order,
    };
    let (mesh, report) = super::gmsh::generate_cached(&request, MeshCache::from_env().as_ref())?;
    Ok((mesh, None, Some(report)))
}

/// A mesh file at the scene's order, and the order of its triangles.
fn mesh_file(path: &Path, order: Order) -> Result<(Mesh, Option<Order>)> {
    let m = super::msh::read_msh(path)?;
    let file_order = Some(m.order);
    match (m.order, order) {
        (Order::P1, Order::P2) => Ok((m.to_quadratic(), file_order)),
        (Order::P2, Order::P1) => Err(Error::Mesh {
            source_file: Some(path.to_path_buf()),
            entity: "elements".into(),
            message: "the file has quadratic (6-node) triangles but the scene asks for order = 1: set \
                      [discretization] order = 2, or export a linear mesh"
                .into(),
        }),
        _ => Ok((m, file_order)),
    }
}
