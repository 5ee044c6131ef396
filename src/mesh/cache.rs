//! A cache of generated meshes on disk, so that a scene whose geometry and sizes have not
//! changed since the last run is not meshed again.
//!
//! An entry is found by a key: a text naming everything that defines the mesh (for Gmsh
//! meshes, [`super::gmsh`] writes the `.geo` script, the Gmsh binary and its version, the
//! arguments, the order and how the P2 nodes are placed). Its file is
//! `DIR/meshes/<FNV-1a-128 of the key, hex>.mesh`:
//!
//! ```text
//!   magic "signorini-mesh\n", u32 format version
//!   u64 key length, key bytes                      the whole key: compared on reading, so a
//!                                                  file-name collision is a miss, never a hit
//!   u64 payload length, payload                    the mesh, below
//!   u128 FNV-1a-128 of everything before it        detects truncation and corruption
//!
//!   payload: u8 order (1, 2); u64 n, 2n f64 node coordinates; u64 n, n u32 cell nodes;
//!   u64 n, n u32 cell groups; u64 n, n u32 edge nodes; u64 n, n u32 edge groups;
//!   u64 n, then n groups: u8 dim, i32 tag, u64 length, UTF-8 name
//! ```
//!
//! All numbers are little-endian; `u32::MAX` stands for [`NO_GROUP`].
//!
//! Safety against stale and broken entries: an entry is used only if its magic, version,
//! key, lengths and checksum all match and the decoded mesh passes [`Mesh::validate`];
//! anything else (a truncated or corrupt file, an entry of another key, a read error) is
//! reported in [`CacheReport::problem`], the mesh is made again and the entry replaced.
//! Entries are written to a temporary file in the same directory and renamed into place,
//! so a reader (another rank of an MPI run, a concurrent run) sees the old entry, the new one
//! or none, never a half-written one. No fsync: after a crash an entry may be lost or
//! damaged, which the checksum catches.
//!
//! Size: after each store the oldest entries (by modification time, refreshed on every hit)
//! are removed until the cache holds at most [`MeshCache::max_bytes`] (default
//! [`DEFAULT_MAX_BYTES`], `SIGNORINI_MESH_CACHE_MAX_MB` overrides it). Temporary files left
//! by a killed writer are removed after an hour.
//!
//! The library never prints: what happened is returned as a [`CacheReport`].
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, SystemTime};

use super::{Measure, Mesh, Order, PhysicalGroup, NO_GROUP};
use crate::error::{Error, Result};

/// Version of the entry layout above; part of every key too.
pub const FORMAT_VERSION: u32 = 1;

const MAGIC: &[u8] = b"signorini-mesh\n";

/// Default bound on the total size of the entries: 256 MB, about 200 meshes of 1e5 dofs (P2).
pub const DEFAULT_MAX_BYTES: u64 = 256 << 20;

/// Temporary files older than this are a killed writer's leftovers.
const STALE_TEMPORARY: Duration = Duration::from_secs(3600);

/// What the cache did for one mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CacheStatus {
    /// The mesh came from the cache.
    Hit,
    /// The mesh was made (and stored, unless [`CacheReport::problem`] says otherwise).
    Miss,
    /// No cache was used (disabled, or no cache directory).
    Disabled,
}

/// The cache's part in getting one mesh.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct CacheReport {
    /// Whether the mesh came from the cache, was stored in it, or the cache was off.
    pub status: CacheStatus,
    /// Something that went wrong without stopping the run: an unusable entry that was
    /// replaced ("corrupt entry ...: checksum mismatch; replaced"), or a mesh that could not
    /// be stored.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub problem: Option<String>,
}

impl CacheReport {
    /// The report of a run with the cache switched off.
    pub fn disabled() -> Self {
        CacheReport { status: CacheStatus::Disabled, problem: None }
    }
}

/// A mesh cache rooted at a directory (entries in its `meshes/` subdirectory).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshCache {
    root: PathBuf,
    max_bytes: u64,
}

/// Is this environment variable set to a true value (anything but empty, `0`, `false`, `no`)?
fn env_flag(name: &str) -> bool {
    std::env::var(name)
        .map(|v| !matches!(v.trim().to_ascii_lowercase().as_str(), "" | "0" | "false" | "no"))
        .unwrap_or(false)
}

impl MeshCache {
    /// A cache in `root` (created when first written), bounded to [`DEFAULT_MAX_BYTES`].
    pub fn at(root: impl Into<PathBuf>) -> Self {
        MeshCache { root: root.into(), max_bytes: DEFAULT_MAX_BYTES }
    }

    /// The same cache bounded to `max_bytes` of entries.
    pub fn with_max_bytes(mut self, max_bytes: u64) -> Self {
        self.max_bytes = max_bytes;
        self
    }

    /// The cache the environment asks for: none if `SIGNORINI_NO_MESH_CACHE` is set (to
    /// anything but `0`, `false`, `no` or nothing); else `SIGNORINI_CACHE_DIR`, else
    /// `$XDG_CACHE_HOME/signorini` (an absolute `XDG_CACHE_HOME`), else
    /// `$HOME/.cache/signorini`; none if neither can be found. `SIGNORINI_MESH_CACHE_MAX_MB`
    /// sets the size bound.
    pub fn from_env() -> Option<MeshCache> {
        if env_flag("SIGNORINI_NO_MESH_CACHE") {
            return None;
        }
        let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
        let root = var("SIGNORINI_CACHE_DIR")
            .or_else(|| var("XDG_CACHE_HOME").filter(|p| p.is_absolute()).map(|p| p.join("signorini")))
            .or_else(|| var("HOME").map(|h| h.join(".cache").join("signorini")))?;
        let mut cache = MeshCache::at(root);
        if let Some(mb) = std::env::var("SIGNORINI_MESH_CACHE_MAX_MB").ok().and_then(|v| v.trim().parse::<u64>().ok()) {
            cache.max_bytes = mb.saturating_mul(1 << 20);
        }
        Some(cache)
    }

    /// The cache's directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The size limit of the cache (bytes); the oldest entries are removed beyond it.
    pub fn max_bytes(&self) -> u64 {
        self.max_bytes
    }

    /// The directory of the entries.
    pub fn entries_dir(&self) -> PathBuf {
        self.root.join("meshes")
    }

    /// The file of the entry for `key` (whether or not it exists).
    pub fn entry_path(&self, key: &str) -> PathBuf {
        self.entries_dir().join(format!("{:032x}.mesh", fnv1a_128(key.as_bytes())))
    }

    /// The mesh for `key`: from the cache if a valid entry is there, else `make()`'s, stored
    /// for next time. Errors of `make` are returned; the cache's own failures never are (they
    /// go to [`CacheReport::problem`]).
    pub fn get_or_make(&self, key: &str, make: impl FnOnce() -> Result<Mesh>) -> Result<(Mesh, CacheReport)> {
        let path = self.entry_path(key);
        let mut problem = None;
        match fs::read(&path) {
            Ok(bytes) => match decode_entry(&bytes, key) {
                Ok(mesh) => {
                    touch(&path);
                    return Ok((mesh, CacheReport { status: CacheStatus::Hit, problem: None }));
                }
                Err(why) => problem = Some(format!("unusable entry {}: {why}; replaced", path.display())),
            },
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => problem = Some(format!("cannot read entry {}: {e}; replaced", path.display())),
        }
        let mesh = make()?;
        if let Some(note) = self.insert(key, &mesh) {
            problem = Some(match problem {
                Some(p) => format!("{p}; {note}"),
                None => note,
            });
        }
        Ok((mesh, CacheReport { status: CacheStatus::Miss, problem }))
    }

    /// A line of text the cache remembers under `name` (e.g. the version of a program, by
    /// the identity of its binary), if it does.
    pub fn recall(&self, name: &str) -> Option<String> {
        let text = fs::read_to_string(self.root.join(format!("{name}.txt"))).ok()?;
        text.strip_suffix('\n').filter(|v| !v.is_empty() && !v.contains('\n')).map(str::to_string)
    }

    /// Remember a line of text under `name` (best effort: a cache that cannot be written
    /// only forgets).
    pub fn remember(&self, name: &str, value: &str) {
        if !value.is_empty() && !value.contains('\n') {
            let _ = write_atomically(&self.root.join(format!("{name}.txt")), format!("{value}\n").as_bytes());
        }
    }

    /// Store `mesh` under `key` (replacing any entry), then keep to the size bound; what went
    /// wrong, if anything.
    pub fn insert(&self, key: &str, mesh: &Mesh) -> Option<String> {
        self.store(&self.entry_path(key), key, mesh).err().map(|e| format!("mesh not stored in the cache: {e}"))
    }

    fn store(&self, path: &Path, key: &str, mesh: &Mesh) -> std::result::Result<(), String> {
        let bytes = encode_entry(key, mesh)?;
        write_atomically(path, &bytes).map_err(|e| e.to_string())?;
        self.evict(path);
        Ok(())
    }

    /// Remove the oldest entries beyond the size bound (never `keep`, the entry just
    /// written) and stale temporary files. Best effort.
    fn evict(&self, keep: &Path) {
        let Ok(dir) = fs::read_dir(self.entries_dir()) else { return };
        let now = SystemTime::now();
        let mut entries = Vec::new();
        for entry in dir.flatten() {
            let path = entry.path();
            let Ok(meta) = entry.metadata() else { continue };
            let modified = meta.modified().unwrap_or(now);
            let name = entry.file_name().to_string_lossy().to_string();
            if name.ends_with(".tmp") {
                if now.duration_since(modified).is_ok_and(|age| age > STALE_TEMPORARY) {
                    let _ = fs::remove_file(&path);
                }
            } else if name.ends_with(".mesh") {
                entries.push((modified, meta.len(), path));
            }
        }
        let mut total: u64 = entries.iter().map(|e| e.1).sum();
        entries.sort();
        for (_, size, path) in entries {
            if total <= self.max_bytes {
                break;
            }
            if path != keep && fs::remove_file(&path).is_ok() {
                total -= size;
            }
        }
    }
}

/// Mark an entry as just used (its modification time orders the eviction).
fn touch(path: &Path) {
    if let Ok(file) = fs::OpenOptions::new().append(true).open(path) {
        let _ = file.set_modified(SystemTime::now());
    }
}

/// Write `bytes` to `path` through a temporary file in the same directory and a rename.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let io = |e| Error::io(path, "writing a mesh cache entry", e);
    let dir = path.parent().unwrap_or(Path::new("."));
    fs::create_dir_all(dir).map_err(io)?;
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary = dir.join(format!(".{name}.{}.{n}.tmp", std::process::id()));
    let result = (|| {
        let mut file = fs::OpenOptions::new().write(true).create_new(true).open(&temporary)?;
        file.write_all(bytes)?;
        drop(file);
        fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&temporary);
    }
    result.map_err(io)
}

/// FNV-1a with 128-bit state (offset basis and prime from the FNV specification,
/// draft-eastlake-fnv).
pub fn fnv1a_128(bytes: &[u8]) -> u128 {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013b;
    bytes.iter().fold(OFFSET, |h, &b| (h ^ b as u128).wrapping_mul(PRIME))
}

fn put_u64(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_indices(out: &mut Vec<u8>, values: &[usize]) -> std::result::Result<(), String> {
    put_u64(out, values.len() as u64);
    for &v in values {
        let v = if v == NO_GROUP {
            u32::MAX
        } else {
            u32::try_from(v).ok().filter(|&v| v != u32::MAX).ok_or("a mesh this large is not cached")?
        };
        out.extend_from_slice(&v.to_le_bytes());
    }
    Ok(())
}

/// The bytes of a cache entry.
pub fn encode_entry(key: &str, mesh: &Mesh) -> std::result::Result<Vec<u8>, String> {
    let mut payload = Vec::with_capacity(16 * mesh.nodes.len() + 4 * (mesh.cells.len() + mesh.edges.len()) + 1024);
    payload.push(match mesh.order {
        Order::P1 => 1,
        Order::P2 => 2,
    });
    put_u64(&mut payload, mesh.nodes.len() as u64);
    for p in &mesh.nodes {
        payload.extend_from_slice(&p[0].to_le_bytes());
        payload.extend_from_slice(&p[1].to_le_bytes());
    }
    put_indices(&mut payload, &mesh.cells)?;
    put_indices(&mut payload, &mesh.cell_group)?;
    put_indices(&mut payload, &mesh.edges)?;
    put_indices(&mut payload, &mesh.edge_group)?;
    put_u64(&mut payload, mesh.groups.len() as u64);
    for g in &mesh.groups {
        payload.push(g.dim);
        payload.extend_from_slice(&g.tag.to_le_bytes());
        put_u64(&mut payload, g.name.len() as u64);
        payload.extend_from_slice(g.name.as_bytes());
    }
    let mut out = Vec::with_capacity(payload.len() + key.len() + 64);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    put_u64(&mut out, key.len() as u64);
    out.extend_from_slice(key.as_bytes());
    put_u64(&mut out, payload.len() as u64);
    out.extend_from_slice(&payload);
    let sum = fnv1a_128(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    Ok(out)
}

/// Reads little-endian values, every length checked against what is left.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> std::result::Result<&'a [u8], String> {
        if n > self.bytes.len() {
            return Err(format!("truncated in {what}"));
        }
        let (head, tail) = self.bytes.split_at(n);
        self.bytes = tail;
        Ok(head)
    }
    fn u64(&mut self, what: &str) -> std::result::Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().expect("8 bytes")))
    }
    /// A count of items of `size` bytes each that must fit in what is left.
    fn count(&mut self, size: usize, what: &str) -> std::result::Result<usize, String> {
        let n = self.u64(what)?;
        if n.checked_mul(size as u64).is_none_or(|b| b > self.bytes.len() as u64) {
            return Err(format!("{what}: length {n} beyond the end of the entry"));
        }
        Ok(n as usize)
    }
    fn indices(&mut self, what: &str) -> std::result::Result<Vec<usize>, String> {
        let n = self.count(4, what)?;
        let raw = self.take(4 * n, what)?;
        Ok(raw
            .chunks_exact(4)
            .map(|c| match u32::from_le_bytes(c.try_into().expect("4 bytes")) {
                u32::MAX => NO_GROUP,
                v => v as usize,
            })
            .collect())
    }
}

/// The mesh of a cache entry, if the entry is whole, of this format, of this key, and its mesh
/// is valid; else why not.
pub fn decode_entry(bytes: &[u8], key: &str) -> std::result::Result<Mesh, String> {
    let body_len = bytes.len().checked_sub(16).ok_or("truncated (shorter than its checksum)")?;
    let (body, sum) = bytes.split_at(body_len);
    if !body.starts_with(MAGIC) {
        return Err("not a signorini mesh cache entry".into());
    }
    if fnv1a_128(body) != u128::from_le_bytes(sum.try_into().expect("16 bytes")) {
        return Err("checksum mismatch (truncated or corrupt)".into());
    }
    let mut r = Reader { bytes: &body[MAGIC.len()..] };
    let version = u32::from_le_bytes(r.take(4, "version")?.try_into().expect("4 bytes"));
    if version != FORMAT_VERSION {
        return Err(format!("format version {version}, expected {FORMAT_VERSION}"));
    }
    let n = r.count(1, "key")?;
    if r.take(n, "key")? != key.as_bytes() {
        return Err("made for another key".into());
    }
    let n = r.count(1, "payload")?;
    let mut r = Reader { bytes: r.take(n, "payload")? };
    let order = match r.take(1, "order")?[0] {
        1 => Order::P1,
        2 => Order::P2,
        o => return Err(format!("order {o}")),
    };
    let n = r.count(16, "nodes")?;
    let nodes = r
        .take(16 * n, "nodes")?
        .chunks_exact(16)
        .map(|c| {
            let x = f64::from_le_bytes(c[..8].try_into().expect("8 bytes"));
            let y = f64::from_le_bytes(c[8..].try_into().expect("8 bytes"));
            [x, y]
        })
        .collect();
    let cells = r.indices("cells")?;
    let cell_group = r.indices("cell groups")?;
    let edges = r.indices("edges")?;
    let edge_group = r.indices("edge groups")?;
    let n = r.count(13, "groups")?;
    let mut groups = Vec::with_capacity(n);
    for _ in 0..n {
        let dim = r.take(1, "group")?[0];
        let tag = i32::from_le_bytes(r.take(4, "group")?.try_into().expect("4 bytes"));
        let len = r.count(1, "group name")?;
        let name = String::from_utf8(r.take(len, "group name")?.to_vec()).map_err(|_| "group name not UTF-8")?;
        groups.push(PhysicalGroup { name, tag, dim });
    }
    if !r.bytes.is_empty() {
        return Err(format!("{} bytes after the mesh", r.bytes.len()));
    }
    let mut mesh = Mesh { order, nodes, cells, cell_group, edges, edge_group, groups, measure: Measure::Plane };
    mesh.validate().map_err(|e| format!("invalid mesh: {e}"))?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_128_matches_the_reference_values() {
        // FNV-1a 128 of "" is the offset basis; of "a" from the reference implementation.
        assert_eq!(fnv1a_128(b""), 0x6c62272e07bb014262b821756295c58d);
        assert_eq!(fnv1a_128(b"a"), 0xd228cb696f1a8caf78912b704e4a8964);
    }

    #[test]
    fn entries_round_trip_and_every_truncation_is_refused() {
        let mesh = crate::mesh::structured::rectangle([0.0, 0.0], [1.0, 1.0], 2, 1, Order::P2).unwrap();
        let bytes = encode_entry("key", &mesh).unwrap();
        let back = decode_entry(&bytes, "key").unwrap();
        assert_eq!((back.nodes, back.cells, back.edges), (mesh.nodes, mesh.cells, mesh.edges));
        assert!(decode_entry(&bytes, "other key").unwrap_err().contains("another key"));
        for n in 0..bytes.len() {
            assert!(decode_entry(&bytes[..n], "key").is_err(), "truncated to {n} bytes");
        }
    }
}
