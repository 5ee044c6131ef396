//! The result files of a run with several bodies: besides `solution.vtu` (every body in one
//! file), one `<body>.vtu` per body, on the body's own mesh with its own part tags, and
//! `solution.pvd`, a ParaView collection that opens them together (each body a block, so
//! ParaView can colour, hide or threshold them one by one).
//!
//! Contact fields on both sides of a pair: the slave nodes carry the contact points' pressure
//! `−rN_i / D_i`, friction traction `rT_i / D_i` and status (0 open, 1 stick, 2 slip). A master
//! node `j` receives the force `f_j = Σ_i (Bᵀ r)_j` (the mortar-weighted reactions of the slave
//! points); its pressure is `−f_j·n_j / w_j` and its friction traction `f_j·t_j / w_j`, with
//! `n_j` the master body's outward normal at the node (the normalized sum of its edges'
//! normals), `t_j` that normal turned by +90° and `w_j = ∫ φ_j ds` over the master part, and its
//! status is that of the slave point that couples to it most strongly (−1: no slave point
//! couples to it). With the dual mortar basis a uniform pressure reads the same on both sides.
use std::io::Write;
use std::path::{Path, PathBuf};

use super::files::SolutionFields;
use crate::contact::boundary::edge_weights;
use crate::error::Result;
use crate::output::write_atomically;
use crate::problem::ElasticityProblem;

impl ElasticityProblem<'_> {
    /// Fill the master nodes' entries of the nodal contact fields (module documentation).
    pub(crate) fn add_master_contact_fields(&self, pressure: &mut [f64], friction: &mut [f64], status: &mut [f64]) {
        let (Some(c), Some(outcome)) = (&self.contact, &self.contact_outcome) else {
            return;
        };
        let Some(parts) = &c.parts else { return };
        let b = &c.boundary;
        for (p, part) in parts.parts.iter().enumerate() {
            let Some(master) = part.master else { continue };
            // Forces on the master nodes of this part, and the strongest coupling of each.
            let mut force: std::collections::BTreeMap<usize, [f64; 2]> = std::collections::BTreeMap::new();
            let mut strongest: std::collections::BTreeMap<usize, (f64, usize)> = std::collections::BTreeMap::new();
            for i in (0..b.points()).filter(|&i| parts.part_of[i] == p) {
                let whole = b.point_force(i, &outcome.force);
                for cn in b.coupled_to(i) {
                    let f = force.entry(cn.node).or_insert([0.0; 2]);
                    for (fc, w) in f.iter_mut().zip(whole) {
                        *fc -= cn.transfer * w;
                    }
                    let coupling = cn.transfer.abs();
                    let s = strongest.entry(cn.node).or_insert((0.0, i));
                    if coupling > s.0 {
                        *s = (coupling, i);
                    }
                }
            }
            // The master part's edges, its nodal normals and weights.
            let edges: Vec<usize> = self.mesh.edges_in_group(master.group).collect();
            let mut normal: std::collections::BTreeMap<usize, [f64; 2]> = std::collections::BTreeMap::new();
            for &e in &edges {
                let (n, _) = self.mesh.edge_normal(e);
                for &k in self.mesh.edge(e) {
                    let v = normal.entry(k).or_insert([0.0; 2]);
                    v[0] += n[0];
                    v[1] += n[1];
                }
            }
            for (k, w) in edge_weights(&self.mesh, &edges) {
                let Some(f) = force.get(&k) else { continue };
                let n = normal.get(&k).copied().unwrap_or([0.0, 1.0]);
                let length = n[0].hypot(n[1]);
                if !(length > 0.0 && w > 0.0) {
                    continue;
                }
                let n = [n[0] / length, n[1] / length];
                let t = [-n[1], n[0]];
                pressure[k] = -(f[0] * n[0] + f[1] * n[1]) / w;
                friction[k] = (f[0] * t[0] + f[1] * t[1]) / w;
                if let Some(&(_, i)) = strongest.get(&k) {
                    let frictional = part.friction != crate::scene::FrictionSpec::None;
                    status[k] = super::contact::ContactState::of(outcome.status[i], frictional).code();
                }
            }
        }
    }

    /// `<body>.vtu` for every body and `solution.pvd` (module documentation), with `fields`
    /// (those of `solution.vtu`) restricted to each body. Nothing for a single body.
    pub(crate) fn write_body_files(
        &self,
        dir: &Path,
        fields: &SolutionFields,
        written: &mut Vec<PathBuf>,
    ) -> Result<()> {
        let Some(model) = &self.bodies else { return Ok(()) };
        let (num_cells, num_edges) = (self.mesh.num_cells(), self.mesh.num_edges());
        let mut files = Vec::new();
        for (b, body) in model.bodies.iter().enumerate() {
            let range = &model.layout.bodies[b];
            let point = fields
                .point
                .iter()
                .map(|(name, k, v)| (name.clone(), *k, v[k * range.nodes.start..k * range.nodes.end].to_vec()))
                .collect();
            let cell = fields
                .cell
                .iter()
                .map(|(name, k, v)| {
                    let mut values = v[k * range.cells.start..k * range.cells.end].to_vec();
                    if fields.with_edges && v.len() == k * (num_cells + num_edges) {
                        let first = k * num_cells;
                        values.extend_from_slice(&v[first + k * range.edges.start..first + k * range.edges.end]);
                    }
                    (name.clone(), *k, values)
                })
                .collect();
            let name = format!("{}.vtu", body.name);
            let path = dir.join(&name);
            SolutionFields { point, cell, with_edges: fields.with_edges }.write(&path, &model.body_meshes[b])?;
            written.push(path);
            files.push((body.name.clone(), name));
        }
        let path = dir.join("solution.pvd");
        write_atomically(&path, |w| write_collection(w, &files))?;
        written.push(path);
        Ok(())
    }
}

/// A ParaView collection (`.pvd`) of one `.vtu` per body, each its own part.
fn write_collection(w: &mut dyn Write, files: &[(String, String)]) -> std::io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(w, "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">")?;
    writeln!(w, "  <Collection>")?;
    for (part, (name, file)) in files.iter().enumerate() {
        writeln!(w, "    <DataSet timestep=\"0\" part=\"{part}\" name=\"{name}\" file=\"{file}\"/>")?;
    }
    writeln!(w, "  </Collection>")?;
    writeln!(w, "</VTKFile>")
}
