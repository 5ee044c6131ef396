//! VTK XML UnstructuredGrid (`.vtu`) writer, for ParaView and Python meshio.
//!
//! Format: "VTK File Formats", VTK User's Guide, Kitware, 11th ed., ch. 19, and
//! <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>. We write version 1.0
//! (64-bit offsets) with every array inline as `format="binary"`, no compressor:
//!
//! ```text
//!   <DataArray type="Float64" Name="displacement" NumberOfComponents="3" format="binary">
//!     base64( N as UInt64 little-endian  ||  N bytes of little-endian values )
//!   </DataArray>
//! ```
//!
//! The header and the values are encoded as one base64 stream (what VTK itself writes for
//! uncompressed data; meshio reads it too). Values are little-endian on every platform, as the
//! file declares `byte_order="LittleEndian"`.
//!
//! Cells are the triangles, then (optionally) the boundary edges. VTK numbers the nodes of these
//! cells exactly as [`crate::mesh`] does, so connectivity is copied unchanged:
//!
//! ```text
//!   VTK_TRIANGLE (5)   VTK_QUADRATIC_TRIANGLE (22)   VTK_LINE (3)   VTK_QUADRATIC_EDGE (21)
//!
//!   2                  2
//!   |\                 |\
//!   | \                5  4                          0 ----- 1      0 --- 2 --- 1
//!   |  \               |    \
//!   0---1              0--3--1
//! ```
//!
//! Points are written as `(x, y, 0)`. Every file also carries the cell array `part_id` (Int32):
//! the physical tag of the triangle's region or of the edge's boundary part, −1 for none, so a
//! reader can select parts without the group names.
use std::io::{self, Write};
use std::path::Path;

use base64::Engine;

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Order, NO_GROUP};
use crate::output::write_atomically;

/// A named array of values attached to the points or cells; `values.len()` must be
/// `components ×` (number of points, or of cells written).
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    /// The array's name in the file (what ParaView shows).
    pub name: &'a str,
    /// Values per point or cell: 1 (scalar), 2 or 3 (vector), ...
    pub components: usize,
    /// The values, point by point (or cell by cell), components together.
    pub values: &'a [f64],
}

/// Name of the cell array holding physical tags; reserved.
pub const PART_ID: &str = "part_id";

const VTK_LINE: u8 = 3;
const VTK_TRIANGLE: u8 = 5;
const VTK_QUADRATIC_EDGE: u8 = 21;
const VTK_QUADRATIC_TRIANGLE: u8 = 22;

/// Write `mesh` with its fields as a `.vtu` file, atomically.
///
/// `point_data` fields have `components × mesh.num_nodes()` values; `cell_data` fields cover
/// the triangles and then, if `with_boundary_edges`, the boundary edges, so they have
/// `components × (num_cells + num_edges)` values (`components × num_cells` without edges).
/// A length mismatch, a zero component count, a duplicate name or the reserved name `part_id`
/// is an [`Error::Output`] naming the field; an inconsistent mesh (node index or group index
/// out of range) is an [`Error::Output`] naming the triangle or edge. Nothing is written then.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    point_data: &[Field],
    cell_data: &[Field],
    with_boundary_edges: bool,
) -> Result<()> {
    let fail = |message: String| Error::Output { path: path.to_path_buf(), message };
    check_mesh(mesh).map_err(fail)?;
    let num_points = mesh.num_nodes();
    let num_cells = mesh.num_cells();
    let num_edges = if with_boundary_edges { mesh.num_edges() } else { 0 };
    let cells_desc = if with_boundary_edges {
        format!("{num_cells} triangles + {num_edges} boundary edges")
    } else {
        format!("{num_cells} triangles")
    };
    check_fields("point", point_data, num_points, &format!("{num_points} points")).map_err(fail)?;
    check_fields("cell", cell_data, num_cells + num_edges, &cells_desc).map_err(fail)?;
    if let Some(f) = cell_data.iter().find(|f| f.name == PART_ID) {
        return Err(fail(format!(
            "cell field '{}': the name is reserved for the physical tags written with every mesh; rename the field",
            f.name
        )));
    }

    let part_id: Vec<i32> = mesh.cell_group[..num_cells]
        .iter()
        .chain(mesh.edge_group[..num_edges].iter())
        .map(|&g| if g == NO_GROUP { -1 } else { mesh.groups[g].tag })
        .collect();

    write_atomically(path, |w| {
        begin_piece(w, num_points, num_cells + num_edges)?;

        writeln!(w, "      <PointData>")?;
        for f in point_data {
            write_f64_array(w, Some(f.name), f.components, f.values.len(), f.values.iter().copied())?;
        }
        writeln!(w, "      </PointData>")?;

        writeln!(w, "      <CellData>")?;
        write_array(w, "Int32", Some(PART_ID), 1, part_id.len(), part_id.iter().map(|v| v.to_le_bytes()))?;
        for f in cell_data {
            write_f64_array(w, Some(f.name), f.components, f.values.len(), f.values.iter().copied())?;
        }
        writeln!(w, "      </CellData>")?;

        writeln!(w, "      <Points>")?;
        write_f64_array(w, None, 3, 3 * num_points, mesh.nodes.iter().flat_map(|p| [p[0], p[1], 0.0]))?;
        writeln!(w, "      </Points>")?;

        let cell_len = mesh.order.nodes_per_cell();
        let edge_len = mesh.order.nodes_per_edge();
        let (cell_type, edge_type) = match mesh.order {
            Order::P1 => (VTK_TRIANGLE, VTK_LINE),
            Order::P2 => (VTK_QUADRATIC_TRIANGLE, VTK_QUADRATIC_EDGE),
        };
        let connectivity = mesh.cells[..num_cells * cell_len].iter().chain(mesh.edges[..num_edges * edge_len].iter());
        let offsets =
            (1..=num_cells).map(|c| c * cell_len).chain((1..=num_edges).map(|e| num_cells * cell_len + e * edge_len));
        let types = std::iter::repeat_n(cell_type, num_cells).chain(std::iter::repeat_n(edge_type, num_edges));
        let num_connectivity = num_cells * cell_len + num_edges * edge_len;
        writeln!(w, "      <Cells>")?;
        write_array(
            w,
            "Int64",
            Some("connectivity"),
            1,
            num_connectivity,
            connectivity.map(|&n| (n as i64).to_le_bytes()),
        )?;
        write_array(w, "Int64", Some("offsets"), 1, num_cells + num_edges, offsets.map(|o| (o as i64).to_le_bytes()))?;
        write_array(w, "UInt8", Some("types"), 1, num_cells + num_edges, types.map(|t| [t]))?;
        writeln!(w, "      </Cells>")?;
        end_piece(w)
    })
}

/// The opening lines of an unstructured-grid file of one piece (binary base64 arrays with
/// 64-bit headers), up to `<Piece>`.
pub(crate) fn begin_piece(w: &mut dyn Write, points: usize, cells: usize) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(w, "    <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">")
}

/// The closing lines matching [`begin_piece`].
pub(crate) fn end_piece(w: &mut dyn Write) -> io::Result<()> {
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}

/// Checks that the writer cannot index out of bounds or write a file with dangling nodes.
fn check_mesh(mesh: &Mesh) -> std::result::Result<(), String> {
    let (cell_len, edge_len) = (mesh.order.nodes_per_cell(), mesh.order.nodes_per_edge());
    let n = mesh.num_nodes();
    if !mesh.cells.len().is_multiple_of(cell_len) {
        return Err(format!(
            "mesh: {} triangle connectivity entries is not a multiple of {cell_len} ({:?} triangles)",
            mesh.cells.len(),
            mesh.order
        ));
    }
    if !mesh.edges.len().is_multiple_of(edge_len) {
        return Err(format!(
            "mesh: {} edge connectivity entries is not a multiple of {edge_len} ({:?} edges)",
            mesh.edges.len(),
            mesh.order
        ));
    }
    if mesh.cell_group.len() != mesh.num_cells() {
        return Err(format!(
            "mesh: {} triangle group entries for {} triangles",
            mesh.cell_group.len(),
            mesh.num_cells()
        ));
    }
    if mesh.edge_group.len() != mesh.num_edges() {
        return Err(format!("mesh: {} edge group entries for {} edges", mesh.edge_group.len(), mesh.num_edges()));
    }
    let groups = mesh.groups.len();
    for c in 0..mesh.num_cells() {
        if let Some(&v) = mesh.cell(c).iter().find(|&&v| v >= n) {
            return Err(format!("mesh: triangle {c} uses node {v}, but the mesh has {n} nodes"));
        }
        let g = mesh.cell_group[c];
        if g != NO_GROUP && g >= groups {
            return Err(format!("mesh: triangle {c} is in group {g}, but the mesh has {groups} groups"));
        }
    }
    for e in 0..mesh.num_edges() {
        if let Some(&v) = mesh.edge(e).iter().find(|&&v| v >= n) {
            return Err(format!("mesh: boundary edge {e} uses node {v}, but the mesh has {n} nodes"));
        }
        let g = mesh.edge_group[e];
        if g != NO_GROUP && g >= groups {
            return Err(format!("mesh: boundary edge {e} is in group {g}, but the mesh has {groups} groups"));
        }
    }
    Ok(())
}

fn check_fields(kind: &str, fields: &[Field], count: usize, count_desc: &str) -> std::result::Result<(), String> {
    for (i, f) in fields.iter().enumerate() {
        if f.components == 0 {
            return Err(format!("{kind} field '{}': 0 components; a field needs at least one", f.name));
        }
        let expected = f.components * count;
        if f.values.len() != expected {
            return Err(format!(
                "{kind} field '{}': {} values, expected {expected} ({} components × {count_desc})",
                f.name,
                f.values.len(),
                f.components
            ));
        }
        if fields[..i].iter().any(|g| g.name == f.name) {
            return Err(format!("{kind} field '{}': given twice; field names must be unique", f.name));
        }
    }
    Ok(())
}

pub(crate) fn write_f64_array(
    w: &mut dyn Write,
    name: Option<&str>,
    components: usize,
    count: usize,
    values: impl Iterator<Item = f64>,
) -> io::Result<()> {
    write_array(w, "Float64", name, components, count, values.map(f64::to_le_bytes))
}

/// One `<DataArray>` of `count` items of `N` bytes each (already little-endian).
pub(crate) fn write_array<const N: usize>(
    w: &mut dyn Write,
    vtk_type: &str,
    name: Option<&str>,
    components: usize,
    count: usize,
    items: impl Iterator<Item = [u8; N]>,
) -> io::Result<()> {
    write!(w, "        <DataArray type=\"{vtk_type}\"")?;
    if let Some(name) = name {
        write!(w, " Name=\"{}\"", escape_attribute(name))?;
    }
    if components != 1 {
        write!(w, " NumberOfComponents=\"{components}\"")?;
    }
    write!(w, " format=\"binary\">\n          ")?;
    let mut stream = Base64Stream::new(w);
    stream.push(&((count * N) as u64).to_le_bytes())?;
    let mut written = 0usize;
    for item in items {
        stream.push(&item)?;
        written += 1;
    }
    if written != count {
        // Only reachable through a bug in this module; never leave a file with a wrong header.
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("internal error: array '{}' has {written} items, header says {count}", name.unwrap_or("")),
        ));
    }
    stream.finish()?;
    writeln!(w, "\n        </DataArray>")
}

/// Escape a string for a double-quoted XML attribute value.
pub(crate) fn escape_attribute(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 (RFC 4648 §4) of a byte stream, encoded in chunks of a multiple of 3 bytes
/// so that padding only appears at the very end.
struct Base64Stream<'w> {
    out: &'w mut dyn Write,
    pending: Vec<u8>,
    encoded: Vec<u8>,
}

/// Input bytes per encoded chunk (a multiple of 3).
const BASE64_CHUNK: usize = 3 * 16 * 1024;

impl<'w> Base64Stream<'w> {
    fn new(out: &'w mut dyn Write) -> Self {
        Base64Stream { out, pending: Vec::with_capacity(BASE64_CHUNK + 16), encoded: vec![0; BASE64_CHUNK / 3 * 4 + 8] }
    }

    fn push(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.pending.extend_from_slice(bytes);
        if self.pending.len() >= BASE64_CHUNK {
            let whole = self.pending.len() / 3 * 3;
            self.encode(whole)?;
        }
        Ok(())
    }

    /// Encode and write the first `n` pending bytes.
    fn encode(&mut self, n: usize) -> io::Result<()> {
        let needed = n.div_ceil(3) * 4;
        if self.encoded.len() < needed {
            self.encoded.resize(needed, 0);
        }
        let written = base64::engine::general_purpose::STANDARD
            .encode_slice(&self.pending[..n], &mut self.encoded)
            .map_err(|e| io::Error::other(format!("base64 encoding: {e}")))?;
        self.out.write_all(&self.encoded[..written])?;
        self.pending.drain(..n);
        Ok(())
    }

    fn finish(mut self) -> io::Result<()> {
        let n = self.pending.len();
        self.encode(n)
    }
}
