//! Unstructured triangle meshes made by the Gmsh binary (`gmsh`, Debian package `gmsh`).
//!
//! We write a `.geo` script for the requested shape, run
//! `gmsh in.geo -2 -nt 1 -format msh41 -bin -v 1 -o out.msh` in a fresh temporary directory and read
//! the result with [`super::msh::read_msh`]. Driving the binary (instead of linking the Gmsh
//! library) keeps this crate free of the GPL.
//!
//! Shapes, their geometry points and physical groups (curves run counter-clockwise, so the
//! region is on their left):
//!
//! ```text
//!   Rectangle                   Disc (4 quarter arcs,          HalfDisc (lower half,
//!                               one group "circle")            y <= cy)
//!   4 ---- top ---- 3
//!   |               |                 3                        1 ------ flat ------ 3
//!  left   domain  right          /         \                    \                 /
//!   |               |           4     c     2                   arc    domain   arc
//!   1 --- bottom -- 2            \         /                       \           /
//!                                     5                                  2
//!                                                                  2 = (cx, cy - R)
//! ```
//!
//! QuarterDisc (lower-right quarter, x >= cx, y <= cy; the meridian section of the lower half of
//! a sphere when cx = 0): points 1 = (cx, cy - R), 2 = (cx + R, cy), 3 = c; groups "arc" (1 to
//! 2), "flat" (2 to 3), "axis" (3 to 1).
//!
//! Circle arcs are kept below 180 degrees, as Gmsh requires. The bottom point of the half disc
//! is a geometry point, so it is a mesh node (the initial contact point of the Hertz problem);
//! so is the centre, which splits the flat side in two lines (the point support of the Hertz
//! scene sits there, and a remeshed size map need not put a node at the middle otherwise).
//!
//! Mesh size: the points carry `cell_size`. With a [`Refinement`] the size is instead given by a
//! background field: a `Distance` field `d` from the refinement point feeding a `Threshold`
//! field, size `refinement.cell_size` for `d <= radius`, growing linearly to `cell_size` at
//! `d = 2 radius` and constant beyond; sizes from points, curvature and boundary extension are
//! switched off so the field alone decides (Gmsh reference manual, "Specifying mesh element
//! sizes").
//!
//! Algorithm: the script sets `Mesh.Algorithm = 6` (Frontal-Delaunay, Gmsh's default, written
//! out so that a user's Gmsh option file cannot change it). On the 8.6e4-dof P2 half disc
//! (`examples/scenes/half_disc_86k.toml`, Gmsh 4.8.4) it was the fastest of the algorithms
//! that keep the quality: Delaunay (5) spends about 15 % less CPU in 2D meshing but makes 12 %
//! more nodes (more dofs to solve) of a lower mean quality (mean smallest angle 49° against
//! 58°); MeshAdapt (1) is 30 times slower, BAMG (7) and packing of parallelograms (9) 5 and 25
//! times, Frontal quads (8) crashes. `Mesh.Smoothing = 0` would save 25 % of the 2D time but
//! lowers the worst angles (1 % quantile 32° instead of 39°), so it stays on. What Gmsh's run
//! of 1.0–1.5 s wall (0.75 s CPU) is made of: 0.2 s starting the program, 0.45 s CPU of 2D
//! meshing, 0.15 s of second-order nodes (now ours, 2 ms); reading its binary MSH takes us
//! 13 ms (ASCII: 16 ms).
//!
//! P2: Gmsh makes the linear mesh and we add the mid nodes ([`Mesh::to_quadratic_with`]):
//! straight sides get their midpoint, boundary edges on a circle arc the projection of their
//! midpoint on the circle (the point of the arc halfway in angle; Gmsh's `-order 2` with
//! `Mesh.SecondOrderLinear = 0` puts it on the circle too, within 1e-10 rad of that angle).
//! This saves Gmsh's second-order pass (a fifth of its time) and halves the file to
//! read.
//!
//! Cache: [`generate_cached`] keeps meshes in a [`MeshCache`] keyed by the `.geo` script, the
//! Gmsh binary (path, size, modification time) and its version, the arguments, the order and
//! the P2 construction ([`MESH_GENERATOR`]): the same scene meshes once.
//!
//! Numbers are written into the script literally with full precision (Rust's shortest
//! round-trip formatting), never through `DefineNumber` (which `-setnumber` does not override).
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::cache::{CacheReport, CacheStatus, MeshCache};
use super::{msh::read_msh, Mesh, Order};
use crate::error::{Error, Result};

/// A domain Gmsh can mesh for us.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Axis-aligned rectangle with lower-left corner `origin`. Groups "bottom", "right", "top",
    /// "left", "domain".
    Rectangle {
        /// Lower-left corner.
        origin: [f64; 2],
        /// Width and height.
        size: [f64; 2],
    },
    /// Full disc. Groups "circle", "domain".
    Disc {
        /// Centre.
        center: [f64; 2],
        /// Radius.
        radius: f64,
    },
    /// Lower half disc `{|x - c| <= R, y <= cy}`. Groups "arc" (curved side), "flat" (top),
    /// "domain".
    HalfDisc {
        /// Centre of the full disc.
        center: [f64; 2],
        /// Radius.
        radius: f64,
    },
    /// Lower-right quarter disc `{x >= cx, y <= cy, |x - c| <= R}`: the meridian section of
    /// the lower half of a sphere when `cx = 0` (axisymmetric scenes). Groups "arc" (curved
    /// side), "flat" (top, `y = cy`), "axis" (left, `x = cx`), "domain".
    QuarterDisc {
        /// Centre of the full disc (the corner between "flat" and "axis").
        center: [f64; 2],
        /// Radius.
        radius: f64,
    },
    /// A user's Gmsh script (built-in or OpenCASCADE kernel), read from `file`, with its own
    /// physical groups; only meshed with a background size map ([`generate_with_background`]).
    /// P2 by Gmsh's `-order 2`, which puts the mid nodes of boundary edges on the script's
    /// curves.
    Geometry {
        /// The script's text.
        script: String,
        /// The script's file (Gmsh resolves its includes and merges against it).
        file: PathBuf,
    },
}

/// Smaller cells around a point: `cell_size` within `radius`, growing to the request's size at
/// `2 radius`.
#[derive(Debug, Clone, PartialEq)]
pub struct Refinement {
    /// Centre of the refined zone (m).
    pub point: [f64; 2],
    /// Cell size within `radius` of `point` (m).
    pub cell_size: f64,
    /// Radius of the refined zone (m).
    pub radius: f64,
}

#[derive(Debug, Clone, PartialEq)]
/// What to ask Gmsh for: a shape, its cell size, a refinement and the order.
pub struct MeshRequest {
    /// The geometry.
    pub shape: Shape,
    /// Target side length of the triangles away from the refinement.
    pub cell_size: f64,
    /// Local refinement, if any.
    pub refinement: Option<Refinement>,
    /// Linear or quadratic triangles.
    pub order: Order,
}

/// Estimated triangle count above which a request is refused (Gmsh needs about a minute per
/// million triangles; this limit is far beyond what the solver handles).
const MAX_ESTIMATED_TRIANGLES: f64 = 5e7;

/// Gmsh's 2D meshing algorithm (6: Frontal-Delaunay; see the module documentation).
pub const ALGORITHM: u32 = 6;

/// The arguments of every Gmsh run, before `-o FILE` (part of the cache key). One thread:
/// with more, Gmsh 4.8's 2D mesh of one surface is no faster and no longer the same from run
/// to run (the cache and the ranks of an MPI run rely on that).
const GMSH_ARGS: [&str; 8] = ["-2", "-nt", "1", "-format", "msh41", "-bin", "-v", "1"];

/// Version of how a [`MeshRequest`] becomes a mesh beyond the `.geo` script (the P2 mid nodes,
/// the reading): part of the cache key, raised whenever that changes so that old entries miss.
pub const MESH_GENERATOR: u32 = 1;

const NOT_FOUND: &str =
    "the gmsh binary was not found on PATH: install it with `apt-get install -y --no-install-recommends gmsh`";

/// Mesh a shape with Gmsh (no cache).
pub fn generate(request: &MeshRequest) -> Result<Mesh> {
    let geo = geo_script(request)?;
    mesh_shape(request, &geo, None)
}

/// Mesh a shape with Gmsh, through `cache` if there is one: a mesh made before from the same
/// script, by the same Gmsh, comes from the cache (bit for bit the mesh made then). The report
/// says whether it did, and what went wrong with the cache, if anything (never an error: the
/// mesh is then made as without a cache).
pub fn generate_cached(request: &MeshRequest, cache: Option<&MeshCache>) -> Result<(Mesh, CacheReport)> {
    let geo = geo_script(request)?;
    let Some(cache) = cache else {
        return Ok((mesh_shape(request, &geo, None)?, CacheReport::disabled()));
    };
    let Some((binary, memo)) = gmsh_binary() else {
        // No gmsh to key on: mesh without the cache (which reports the missing gmsh).
        return Ok((mesh_shape(request, &geo, None)?, CacheReport::disabled()));
    };
    if let Some(version) = cache.recall(&memo) {
        let key = cache_key(request, &geo, &binary, &version);
        return cache.get_or_make(&key, || mesh_shape(request, &geo, None));
    }
    // The first mesh by this Gmsh binary: ask its version (a fifth of a second) while it
    // meshes, then remember the version and store the mesh.
    let asking = Command::new("gmsh")
        .arg("--version")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn();
    let mesh = mesh_shape(request, &geo, None)?;
    let version = asking.and_then(|child| child.wait_with_output());
    let version = version_of(version);
    let problem = match version {
        Ok(version) => {
            cache.remember(&memo, &version);
            cache.insert(&cache_key(request, &geo, &binary, &version), &mesh)
        }
        Err(e) => Some(format!("mesh not stored in the cache: {e}")),
    };
    Ok((mesh, CacheReport { status: CacheStatus::Miss, problem }))
}

/// Everything that defines the mesh of `request`, as text: the cache key.
fn cache_key(request: &MeshRequest, geo: &str, binary: &str, version: &str) -> String {
    format!(
        "signorini mesh: cache format {}, generator {MESH_GENERATOR}\ngmsh {binary}, version {version}\n\
         arguments: {}\norder: {:?} (P2 mid nodes by signorini, on the arcs)\n--- geo\n{geo}",
        super::cache::FORMAT_VERSION,
        GMSH_ARGS.join(" "),
        request.order
    )
}

/// The gmsh binary that PATH gives, as its canonical path, size and modification time (ns),
/// and the name under which the cache remembers its version; `None` without one.
fn gmsh_binary() -> Option<(String, String)> {
    use std::os::unix::fs::PermissionsExt as _;
    let runnable = |p: &std::path::Path| p.metadata().is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0);
    let path = std::env::split_paths(&std::env::var_os("PATH")?).map(|d| d.join("gmsh")).find(|p| runnable(p))?;
    let path = std::fs::canonicalize(&path).unwrap_or(path);
    let meta = std::fs::metadata(&path).ok()?;
    let modified =
        meta.modified().ok().and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok()).map_or(0, |d| d.as_nanos());
    let binary = format!("{} ({} bytes, modified {modified} ns)", path.display(), meta.len());
    let memo = format!("gmsh-version-{:032x}", super::cache::fnv1a_128(binary.as_bytes()));
    Some((binary, memo))
}

/// The mesh of `request` from its script: Gmsh's linear mesh, made quadratic by us for P2.
fn mesh_shape(request: &MeshRequest, geo: &str, background_pos: Option<&str>) -> Result<Mesh> {
    if let Shape::Geometry { file, .. } = &request.shape {
        return run_gmsh(geo, request.order, background_pos).map_err(|e| match e {
            Error::Gmsh { message, stderr } => {
                Error::Gmsh { message: format!("{message} (meshing the geometry script {})", file.display()), stderr }
            }
            other => other,
        });
    }
    let linear = run_gmsh(geo, Order::P1, background_pos)?;
    match request.order {
        Order::P1 => Ok(linear),
        Order::P2 => quadratic_on_shape(&linear, &request.shape),
    }
}

/// The P2 mesh of a linear mesh of `shape`: mid nodes of edges on circle arcs projected on the
/// circle, all others at the midpoint; validated (a projection can fold a coarse cell).
fn quadratic_on_shape(linear: &Mesh, shape: &Shape) -> Result<Mesh> {
    let (arcs, center, radius) = match *shape {
        Shape::Rectangle { .. } | Shape::Geometry { .. } => (None, [0.0; 2], 0.0),
        Shape::Disc { center, radius } => (linear.group_index("circle", 1), center, radius),
        Shape::HalfDisc { center, radius } | Shape::QuarterDisc { center, radius } => {
            (linear.group_index("arc", 1), center, radius)
        }
    };
    let mut mesh = linear.to_quadratic_with(|group, p| {
        if Some(group) != arcs {
            return p;
        }
        let (dx, dy) = (p[0] - center[0], p[1] - center[1]);
        let r = dx.hypot(dy);
        if r > 0.0 {
            [center[0] + radius * dx / r, center[1] + radius * dy / r]
        } else {
            p
        }
    });
    mesh.validate().map_err(|e| match e {
        Error::Mesh { entity, message, .. } => Error::Mesh {
            source_file: None,
            entity,
            message: format!("{message} (in the mesh gmsh generated; a smaller cell size may help)"),
        },
        other => other,
    })?;
    Ok(mesh)
}

/// Mesh a shape with Gmsh, the element sizes given by a background mesh instead of
/// `request.cell_size`: `background_pos` is a Gmsh post-processing view in the list-based
/// `.pos` format (`View "sizes" { ST(x1,y1,0,x2,y2,0,x3,y3,0){h1,h2,h3}; ... };`), used with
/// `-bgm`, and sizes from points, curvature and boundary extension are switched off, so the
/// view alone decides: the new mesh both refines and coarsens (Gmsh reference manual,
/// "Specifying mesh element sizes"). Boundary nodes are placed on the true curves (circle
/// arcs stay circles). Not cached (a size map rarely repeats).
pub fn generate_with_background(request: &MeshRequest, background_pos: &str) -> Result<Mesh> {
    let mut geo = geo_script(request)?;
    geo.push_str(
        "Mesh.MeshSizeExtendFromBoundary = 0;\nMesh.MeshSizeFromPoints = 0;\nMesh.MeshSizeFromCurvature = 0;\n",
    );
    mesh_shape(request, &geo, Some(background_pos))
}

/// Mesh a `.geo` script (built-in kernel syntax) with Gmsh: 2D mesh, MSH 4.1, `order` (P2 by
/// Gmsh's `-order 2`; the script sets `Mesh.SecondOrderLinear` as it wants). The script must
/// define the physical groups it wants to keep.
pub fn generate_from_geo(geo: &str, order: Order) -> Result<Mesh> {
    run_gmsh(geo, order, None)
}

fn run_gmsh(geo: &str, order: Order, background_pos: Option<&str>) -> Result<Mesh> {
    let dir = TempDir::new()?;
    let geo_path = dir.path.join("in.geo");
    let msh_path = dir.path.join("out.msh");
    // Gmsh ignores a last statement that no newline ends: end the script with one.
    let geo = if geo.ends_with('\n') { geo.to_string() } else { format!("{geo}\n") };
    std::fs::write(&geo_path, geo).map_err(|e| Error::io(&geo_path, "writing the Gmsh script", e))?;
    let mut command = Command::new("gmsh");
    command.arg(&geo_path).args(GMSH_ARGS).arg("-o").arg(&msh_path);
    if let Some(pos) = background_pos {
        let pos_path = dir.path.join("sizes.pos");
        std::fs::write(&pos_path, pos).map_err(|e| Error::io(&pos_path, "writing the Gmsh size map", e))?;
        command.arg("-bgm").arg(&pos_path);
    }
    if order == Order::P2 {
        command.args(["-order", "2"]);
    }
    command.current_dir(&dir.path);
    let output = command.output().map_err(spawn_error)?;
    let stderr = String::from_utf8_lossy(&output.stderr).trim().to_string();
    if !output.status.success() {
        let first = stderr.lines().find(|l| l.contains("Error")).unwrap_or("no error message");
        let first = first.trim_start_matches("Error").trim_start_matches([' ', ':']);
        let code = output.status.code().map_or("a signal".to_string(), |c| format!("exit code {c}"));
        return Err(Error::Gmsh { message: format!("{first} ({code})"), stderr });
    }
    if !msh_path.is_file() {
        return Err(Error::Gmsh { message: "gmsh wrote no mesh file".to_string(), stderr });
    }
    read_msh(&msh_path).map_err(|e| match e {
        // The temporary file name means nothing to the user: say where the mesh came from.
        Error::Mesh { entity, message, .. } => Error::Mesh {
            source_file: None,
            entity,
            message: format!("{message} (in the mesh gmsh generated; a smaller cell size may help)"),
        },
        Error::MeshFile { message, .. } => {
            Error::Gmsh { message: format!("cannot read the mesh gmsh produced: {message}"), stderr: stderr.clone() }
        }
        other => other,
    })
}

/// The version Gmsh reports (`gmsh --version`), e.g. "4.8.4".
pub fn gmsh_version() -> Result<String> {
    version_of(Command::new("gmsh").arg("--version").output())
}

/// The version in the output of `gmsh --version` (which Gmsh prints on stderr).
fn version_of(output: std::io::Result<std::process::Output>) -> Result<String> {
    let output = output.map_err(spawn_error)?;
    let text = format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    let version = text.trim().to_string();
    if !output.status.success() || version.is_empty() || version.contains('\n') {
        return Err(Error::Gmsh { message: format!("gmsh --version failed ({})", output.status), stderr: version });
    }
    Ok(version)
}

fn spawn_error(e: std::io::Error) -> Error {
    if e.kind() == std::io::ErrorKind::NotFound {
        Error::Gmsh { message: NOT_FOUND.to_string(), stderr: String::new() }
    } else {
        Error::Gmsh { message: format!("cannot run gmsh: {e}"), stderr: String::new() }
    }
}

/// A directory under the system temp dir, removed when dropped.
struct TempDir {
    path: PathBuf,
}

impl TempDir {
    fn new() -> Result<Self> {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let base = std::env::temp_dir();
        loop {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = base.join(format!("signorini-gmsh-{}-{n}", std::process::id()));
            match std::fs::create_dir(&path) {
                Ok(()) => return Ok(TempDir { path }),
                // Left over from an earlier process with the same id: try the next number.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(Error::io(path, "creating a temporary directory", e)),
            }
        }
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        // Best effort: a leftover directory in /tmp is harmless.
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

fn request_error(entity: String, message: String) -> Error {
    Error::mesh(entity, message)
}

fn positive(value: f64, name: &str, entity: &dyn Fn() -> String) -> Result<()> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(request_error(entity(), format!("{name} = {value} must be positive and finite")))
    }
}

fn finite_point(p: [f64; 2], name: &str, entity: &dyn Fn() -> String) -> Result<()> {
    if p[0].is_finite() && p[1].is_finite() {
        Ok(())
    } else {
        Err(request_error(entity(), format!("{name} ({}, {}) must be finite", p[0], p[1])))
    }
}

/// Check the request and write its `.geo` script.
fn geo_script(request: &MeshRequest) -> Result<String> {
    let entity = || format!("mesh request {:?}", request.shape);
    let (area, mut geo) = match request.shape {
        Shape::Rectangle { origin, size } => {
            finite_point(origin, "origin", &entity)?;
            positive(size[0], "width", &entity)?;
            positive(size[1], "height", &entity)?;
            (size[0] * size[1], rectangle_geo(origin, size, request.cell_size))
        }
        Shape::Disc { center, radius } => {
            finite_point(center, "center", &entity)?;
            positive(radius, "radius", &entity)?;
            (std::f64::consts::PI * radius * radius, disc_geo(center, radius, request.cell_size))
        }
        Shape::HalfDisc { center, radius } => {
            finite_point(center, "center", &entity)?;
            positive(radius, "radius", &entity)?;
            (0.5 * std::f64::consts::PI * radius * radius, half_disc_geo(center, radius, request.cell_size))
        }
        Shape::QuarterDisc { center, radius } => {
            finite_point(center, "center", &entity)?;
            positive(radius, "radius", &entity)?;
            (0.25 * std::f64::consts::PI * radius * radius, quarter_disc_geo(center, radius, request.cell_size))
        }
        Shape::Geometry { ref script, .. } => {
            // The sizes come from the background map, whose triangle count the caller checks.
            let mut geo = script.clone();
            if !geo.ends_with('\n') {
                geo.push('\n');
            }
            let _ = writeln!(geo, "Mesh.Algorithm = {ALGORITHM};");
            return Ok(geo);
        }
    };
    positive(request.cell_size, "cell_size", &entity)?;
    // Equilateral triangles of side h have area h^2 sqrt(3) / 4.
    let per_triangle = |h: f64| h * h * 3f64.sqrt() / 4.0;
    let mut estimate = area / per_triangle(request.cell_size);
    if let Some(r) = &request.refinement {
        let entity = || format!("refinement {r:?}");
        finite_point(r.point, "point", &entity)?;
        positive(r.cell_size, "cell_size", &entity)?;
        positive(r.radius, "radius", &entity)?;
        let refined_area = std::f64::consts::PI * 4.0 * r.radius * r.radius;
        estimate += refined_area.min(area) / per_triangle(r.cell_size);
        refinement_geo(&mut geo, r, request.cell_size);
    }
    if estimate > MAX_ESTIMATED_TRIANGLES {
        return Err(request_error(
            entity(),
            format!(
                "would make about {estimate:.2e} triangles (limit {MAX_ESTIMATED_TRIANGLES:.0e}); use a larger cell size"
            ),
        ));
    }
    let _ = writeln!(geo, "Mesh.Algorithm = {ALGORITHM};");
    Ok(geo)
}

/// `Point(tag) = {x, y, 0, size};`
fn point(geo: &mut String, tag: usize, p: [f64; 2], size: f64) {
    let _ = writeln!(geo, "Point({tag}) = {{{:?}, {:?}, 0, {:?}}};", p[0], p[1], size);
}

fn rectangle_geo(o: [f64; 2], s: [f64; 2], h: f64) -> String {
    let mut geo = String::from("// rectangle, written by signorini\n");
    point(&mut geo, 1, o, h);
    point(&mut geo, 2, [o[0] + s[0], o[1]], h);
    point(&mut geo, 3, [o[0] + s[0], o[1] + s[1]], h);
    point(&mut geo, 4, [o[0], o[1] + s[1]], h);
    geo.push_str(
        "Line(1) = {1, 2};\nLine(2) = {2, 3};\nLine(3) = {3, 4};\nLine(4) = {4, 1};\n\
         Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n\
         Physical Curve(\"bottom\") = {1};\nPhysical Curve(\"right\") = {2};\n\
         Physical Curve(\"top\") = {3};\nPhysical Curve(\"left\") = {4};\n\
         Physical Surface(\"domain\") = {1};\n",
    );
    geo
}

fn disc_geo(c: [f64; 2], r: f64, h: f64) -> String {
    let mut geo = String::from("// disc, written by signorini\n");
    point(&mut geo, 1, c, h);
    point(&mut geo, 2, [c[0] + r, c[1]], h);
    point(&mut geo, 3, [c[0], c[1] + r], h);
    point(&mut geo, 4, [c[0] - r, c[1]], h);
    point(&mut geo, 5, [c[0], c[1] - r], h);
    geo.push_str(
        "Circle(1) = {2, 1, 3};\nCircle(2) = {3, 1, 4};\nCircle(3) = {4, 1, 5};\nCircle(4) = {5, 1, 2};\n\
         Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n\
         Physical Curve(\"circle\") = {1, 2, 3, 4};\nPhysical Surface(\"domain\") = {1};\n",
    );
    geo
}

fn half_disc_geo(c: [f64; 2], r: f64, h: f64) -> String {
    let mut geo = String::from("// lower half disc, written by signorini\n");
    point(&mut geo, 1, [c[0] - r, c[1]], h);
    point(&mut geo, 2, [c[0], c[1] - r], h);
    point(&mut geo, 3, [c[0] + r, c[1]], h);
    point(&mut geo, 4, c, h);
    geo.push_str(
        "Circle(1) = {1, 4, 2};\nCircle(2) = {2, 4, 3};\nLine(3) = {3, 4};\nLine(4) = {4, 1};\n\
         Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n\
         Physical Curve(\"arc\") = {1, 2};\nPhysical Curve(\"flat\") = {3, 4};\n\
         Physical Surface(\"domain\") = {1};\n",
    );
    geo
}

fn quarter_disc_geo(c: [f64; 2], r: f64, h: f64) -> String {
    let mut geo = String::from("// lower-right quarter disc, written by signorini\n");
    point(&mut geo, 1, [c[0], c[1] - r], h);
    point(&mut geo, 2, [c[0] + r, c[1]], h);
    point(&mut geo, 3, c, h);
    geo.push_str(
        "Circle(1) = {1, 3, 2};\nLine(2) = {2, 3};\nLine(3) = {3, 1};\n\
         Curve Loop(1) = {1, 2, 3};\nPlane Surface(1) = {1};\n\
         Physical Curve(\"arc\") = {1};\nPhysical Curve(\"flat\") = {2};\n\
         Physical Curve(\"axis\") = {3};\nPhysical Surface(\"domain\") = {1};\n",
    );
    geo
}

fn refinement_geo(geo: &mut String, r: &Refinement, h: f64) {
    // A free point (not on any curve, not in a physical group) for the distance field.
    point(geo, 100, r.point, r.cell_size);
    let _ = write!(
        geo,
        "Field[1] = Distance;\nField[1].PointsList = {{100}};\n\
         Field[2] = Threshold;\nField[2].InField = 1;\n\
         Field[2].SizeMin = {:?};\nField[2].SizeMax = {:?};\n\
         Field[2].DistMin = {:?};\nField[2].DistMax = {:?};\n\
         Background Field = 2;\n\
         Mesh.MeshSizeExtendFromBoundary = 0;\nMesh.MeshSizeFromPoints = 0;\nMesh.MeshSizeFromCurvature = 0;\n",
        r.cell_size,
        h,
        r.radius,
        2.0 * r.radius
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_binary_is_reported_with_the_install_command() {
        let e = spawn_error(std::io::Error::from(std::io::ErrorKind::NotFound));
        assert!(e.to_string().contains("apt-get install -y --no-install-recommends gmsh"), "{e}");
    }

    #[test]
    fn numbers_are_written_with_full_precision() {
        let geo = geo_script(&MeshRequest {
            shape: Shape::Disc { center: [0.1, 1.0 / 3.0], radius: 2.0 / 3.0 },
            cell_size: 0.1,
            refinement: None,
            order: Order::P2,
        })
        .unwrap();
        assert!(geo.contains("0.3333333333333333"), "{geo}");
        assert!(geo.contains("Mesh.Algorithm = 6;"), "{geo}");
        assert!(!geo.contains("DefineNumber"));
    }

    #[test]
    fn temporary_directories_are_unique_and_removed() {
        let (a, b) = (TempDir::new().unwrap(), TempDir::new().unwrap());
        assert_ne!(a.path, b.path);
        let path = a.path.clone();
        drop(a);
        assert!(!path.exists());
    }
}
