//! The contact answer along the contact part, point by point: what `contact.csv` holds and
//! `contact.svg` draws. One row per contact point, in order of arc length `s` along the part
//! (the arc length of [`super::contact_zones`]: along the boundary edges in their mesh
//! direction, the domain on the left, from the first node of each chain of edges).
use std::io::{self, Write};
use std::path::Path;

use super::contact::ContactState;
use crate::contact::boundary::ContactBoundary;
use crate::contact::PointStatus;
use crate::error::Result;
use crate::mesh::Mesh;

/// The columns of `contact.csv`, in order.
pub const CONTACT_CSV_HEADER: &str =
    "s,x,y,pressure,tangential_traction,gap,normal_displacement,tangential_slip,status";

/// One contact point of the answer.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactCurvePoint {
    /// Arc length along the contact part.
    pub s: f64,
    /// The point's position in the undeformed configuration.
    pub position: [f64; 2],
    /// Normal contact pressure `−rN / w` (Pa: the nodal force per unit thickness, N/m, over the
    /// point's boundary length w, m; ≥ 0 in contact); the `peak_pressure` of the report is the
    /// largest of these.
    pub pressure: f64,
    /// Tangential traction `rT / w` (Pa) along the point's tangent `t` (the domain on the left).
    pub tangential_traction: f64,
    /// Gap to the obstacle after deformation, `g0 − uN` (0 where closed, > 0 where open).
    pub gap: f64,
    /// Normal displacement `uN = n·u` towards the obstacle.
    pub normal_displacement: f64,
    /// Tangential displacement `uT = t·u` against the (fixed) obstacle: the slip of a
    /// slipping point.
    pub tangential_slip: f64,
    /// Open, stick or slip; closed without friction.
    pub status: ContactState,
}

/// The points of the contact part in order of arc length. `force` holds `(rN, rT)` per point
/// and `u` the whole displacement vector; `frictional[i]`: has point `i` friction (else a closed
/// point is `closed`, not stick or slip).
pub fn contact_curve(
    mesh: &Mesh,
    b: &ContactBoundary,
    force: &[f64],
    status: &[PointStatus],
    u: &[f64],
    frictional: &[bool],
) -> Vec<ContactCurvePoint> {
    let (pressure, traction) = b.tractions(force);
    let bu = b.gather(u);
    super::contact_zones::chains(mesh, b)
        .into_iter()
        .flatten()
        .map(|(i, s)| ContactCurvePoint {
            s,
            position: mesh.nodes[b.nodes[i]],
            pressure: pressure[i] + 0.0, // never -0
            tangential_traction: traction[i] + 0.0,
            gap: b.gap[i] - bu[2 * i],
            normal_displacement: bu[2 * i],
            tangential_slip: bu[2 * i + 1],
            status: ContactState::of(status[i], frictional[i]),
        })
        .collect()
}

/// Write `contact.csv` (comma-separated, a header line, full precision), atomically.
pub fn write_contact_csv(path: &Path, points: &[ContactCurvePoint]) -> Result<()> {
    crate::output::write_atomically(path, |w| write_rows(w, points))
}

fn write_rows(w: &mut dyn Write, points: &[ContactCurvePoint]) -> io::Result<()> {
    writeln!(w, "{CONTACT_CSV_HEADER}")?;
    for p in points {
        writeln!(
            w,
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}",
            p.s,
            p.position[0],
            p.position[1],
            p.pressure,
            p.tangential_traction,
            p.gap,
            p.normal_displacement,
            p.tangential_slip,
            p.status.name()
        )?;
    }
    Ok(())
}
