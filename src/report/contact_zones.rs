//! The quantities a contact engineer looks at first: the peak contact pressure and where it
//! is, and the closed zones as intervals of arc length along the contact part.
//!
//! Arc length `s` runs along the part's boundary edges in their mesh direction (the domain on
//! the left), from the first node of each chain of edges; a part made of several chains (or a
//! closed curve, cut at its lowest-numbered node) gets one `s` per chain, continued across
//! chains. A closed zone is a maximal run of consecutive closed points (stick or slip) along a
//! chain; its extent is `[s_start, s_end]` with the positions of its end points. This is right
//! for every obstacle (a circle, a punch closed in several places), unlike a projection on one
//! tangent.
use crate::contact::boundary::ContactBoundary;
use crate::contact::PointStatus;
use crate::mesh::Mesh;

/// The largest nodal contact pressure and where it is.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PeakPressure {
    /// The pressure (N/m²): the normal contact force divided by the point's boundary weight.
    pub pressure: f64,
    /// The mesh node.
    pub node: usize,
    /// Its coordinates (m).
    pub position: [f64; 2],
    /// Arc length along the contact part.
    pub s: f64,
}

/// One connected run of closed contact points.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ClosedZone {
    /// `[s_start, s_end]`: arc length along the contact part.
    pub extent: [f64; 2],
    /// Coordinates of the zone's first point (m).
    pub start: [f64; 2],
    /// Coordinates of its last point (m).
    pub end: [f64; 2],
    /// Closed points in the zone.
    pub points: usize,
}

/// The contact points in chain order with their arc length, and where each chain starts.
pub(crate) fn chains(mesh: &Mesh, b: &ContactBoundary) -> Vec<Vec<(usize, f64)>> {
    // Each edge's nodes in order along the edge: v0, [mid], v1.
    let mut next: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut has_previous = std::collections::HashSet::new();
    for &e in &b.edges {
        let ed = mesh.edge(e);
        next.insert(ed[0], e);
        has_previous.insert(ed[1]);
    }
    let mut starts: Vec<usize> = next.keys().copied().filter(|n| !has_previous.contains(n)).collect();
    starts.sort_unstable();
    if starts.is_empty() {
        // A closed curve: cut it at its lowest-numbered node.
        starts.extend(next.keys().copied().min());
    }
    let point_of = |node: usize| b.nodes.binary_search(&node).ok();
    let (mut out, mut s, mut visited) = (Vec::new(), 0.0, std::collections::HashSet::new());
    for start in starts {
        let mut chain = Vec::new();
        let mut node = start;
        if let Some(i) = point_of(node) {
            chain.push((i, s));
        }
        while let Some(&e) = next.get(&node) {
            if !visited.insert(e) {
                break;
            }
            let ed = mesh.edge(e);
            let (a, c) = (mesh.nodes[ed[0]], mesh.nodes[ed[1]]);
            let len = (c[0] - a[0]).hypot(c[1] - a[1]);
            if ed.len() == 3 {
                if let Some(i) = point_of(ed[2]) {
                    chain.push((i, s + 0.5 * len));
                }
            }
            s += len;
            node = ed[1];
            if let Some(i) = point_of(node) {
                if node != start {
                    chain.push((i, s));
                }
            }
        }
        out.push(chain);
    }
    out
}

/// The peak pressure and the closed zones of a contact answer (`pressure[i]` nodal pressures).
pub fn zones(
    mesh: &Mesh,
    b: &ContactBoundary,
    pressure: &[f64],
    status: &[PointStatus],
) -> (Option<PeakPressure>, Vec<ClosedZone>) {
    let chains = chains(mesh, b);
    let mut peak: Option<PeakPressure> = None;
    let mut zones = Vec::new();
    for chain in &chains {
        let mut current: Option<ClosedZone> = None;
        for &(i, s) in chain {
            let x = mesh.nodes[b.nodes[i]];
            if peak.as_ref().is_none_or(|p| pressure[i] > p.pressure) {
                peak = Some(PeakPressure { pressure: pressure[i], node: b.nodes[i], position: x, s });
            }
            if status[i] != PointStatus::Open {
                match current.as_mut() {
                    Some(z) => {
                        z.extent[1] = s;
                        z.end = x;
                        z.points += 1;
                    }
                    None => current = Some(ClosedZone { extent: [s, s], start: x, end: x, points: 1 }),
                }
            } else if let Some(z) = current.take() {
                zones.push(z);
            }
        }
        zones.extend(current);
    }
    (peak, zones)
}
