//! Reading Gmsh MSH 4.1 files (ASCII and binary) into a [`Mesh`].
//!
//! Format: Gmsh reference manual, section "MSH file format" (version 4.1). The parts we use:
//!
//! ```text
//!   $MeshFormat       4.1 <0 ascii | 1 binary> <sizeof(size_t)>   [binary: int 1, endianness]
//!   $PhysicalNames    <n>, then n lines: <dim> <tag> "<name>"      (text, also in binary files)
//!   $Entities         points, curves, surfaces, volumes; each lists its physical group tags
//!   $Nodes            blocks per entity: <dim> <entity> <parametric> <n>, n tags, n (x, y, z)
//!   $Elements         blocks per entity: <dim> <entity> <type> <n>, n x (tag, node tags...)
//! ```
//!
//! Element types used (node order as in [`super`]: vertices, then mid nodes of sides 01, 12, 20):
//!
//! ```text
//!   type 2  triangle, 3 nodes     type 9  triangle, 6 nodes
//!   type 1  line, 2 nodes         type 8  line, 3 nodes (ends, then mid)
//!   type 15 point (ignored)
//! ```
//!
//! The `mshio` crate parses entities, nodes and elements. It skips `$PhysicalNames`, which we
//! read ourselves (text even in binary files), and it keeps node tags only when they are
//! sparse, so we also read the node tags of each block (in file order) ourselves; that scan
//! also rejects the headers `mshio` cannot handle (an empty `$Nodes` section).
//!
//! Mapping to [`Mesh`]:
//! - triangles on a surface in a physical surface get that group; if the file has no physical
//!   surface at all, every triangle is kept with [`NO_GROUP`], otherwise triangles outside the
//!   physical surfaces are dropped (as Gmsh does when saving);
//! - lines on a curve in physical curves become boundary edges, one per (line, group) pair;
//!   lines outside physical curves are ignored;
//! - physical groups without a name in `$PhysicalNames` are named by their tag ("7");
//! - nodes are renumbered `0..n` in file order, keeping only those used by kept elements;
//! - the result goes through [`Mesh::validate`]; mesh errors carry the file name.
//!
//! Node numbers in validation messages are these compact 0-based numbers (for a Gmsh file with
//! tags `1..n`, all used, that is the tag minus one); errors found while reading name Gmsh tags.
use std::collections::HashMap;
use std::path::Path;

use mshio::{ElementType, MshParserError};

use super::{Mesh, Order, PhysicalGroup, NO_GROUP};
use crate::error::{Error, Result};

/// Read a Gmsh MSH 4.1 file (ASCII or binary) and validate the mesh.
pub fn read_msh(path: &Path) -> Result<Mesh> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, "reading the mesh file", e))?;
    MshReader { bytes: &bytes, file: path }.read()
}

struct MshReader<'a> {
    bytes: &'a [u8],
    file: &'a Path,
}

/// What the `$MeshFormat` header says.
#[derive(Clone, Copy)]
struct Format {
    binary: bool,
    size_t_bytes: usize,
    little_endian: bool,
}

impl<'a> MshReader<'a> {
    /// A parse error at `line`; without a line (a section that is missing, a check over a whole
    /// section) it points at the section it concerns, or at the end of the file, so that every
    /// parse error carries a location.
    fn error(&self, line: Option<usize>, message: impl Into<String>) -> Error {
        let message = message.into();
        let line = line.or_else(|| {
            let section = if message.contains("$Elements") || message.contains("element") {
                "$Elements"
            } else if message.contains("$Nodes") || message.contains("node") {
                "$Nodes"
            } else {
                ""
            };
            self.section_line(section)
        });
        let line = Some(line.unwrap_or_else(|| self.line_at(self.bytes.len())));
        Error::MeshFile { file: self.file.to_path_buf(), line, message }
    }

    /// The 1-based line where section `name` (e.g. "$Nodes") starts, if it does.
    fn section_line(&self, name: &str) -> Option<usize> {
        if name.is_empty() {
            return None;
        }
        let needle = format!("\n{name}");
        self.bytes.windows(needle.len()).position(|w| w == needle.as_bytes()).map(|at| self.line_at(at + 1))
    }

    /// 1-based line of byte `offset`.
    fn line_at(&self, offset: usize) -> usize {
        1 + self.bytes[..offset.min(self.bytes.len())].iter().filter(|&&b| b == b'\n').count()
    }

    fn read(&self) -> Result<Mesh> {
        let format = self.read_format()?;
        let names = self.read_physical_names()?;
        let node_tags = self.read_node_tags(format)?;
        self.check_element_header(format)?;
        let msh = mshio::parse_msh_bytes(self.bytes).map_err(|e| self.parser_error(e, format))?;
        let mut mesh = self.build(&msh, &names, &node_tags)?;
        mesh.validate().map_err(|e| e.in_mesh_file(self.file))?;
        Ok(mesh)
    }

    /// `$MeshFormat`: version 4.1 only, with a size_t size `mshio` supports.
    fn read_format(&self) -> Result<Format> {
        let mut lines = Lines::new(self.bytes, 0, 1);
        let first = loop {
            match lines.next() {
                Some((_, l)) if l.trim().is_empty() => continue,
                Some((n, l)) => break (n, l),
                None => return Err(self.error(None, "the file is empty")),
            }
        };
        if first.1.trim() != "$MeshFormat" {
            return Err(self.error(Some(first.0), "not a Gmsh MSH file: it does not start with $MeshFormat"));
        }
        let Some((n, line)) = lines.next() else {
            return Err(self.error(Some(first.0), "the file ends inside $MeshFormat"));
        };
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.len() < 3 {
            return Err(self.error(
                Some(n),
                format!("expected '<version> <file-type> <data-size>' in $MeshFormat, found '{}'", line.trim()),
            ));
        }
        let version = fields[0];
        if version != "4.1" {
            return Err(self.error(
                Some(n),
                format!(
                    "MSH {version} is not supported: re-export as MSH 4.1 (gmsh -format msh41, or Mesh.MshFileVersion = 4.1)"
                ),
            ));
        }
        let binary = match fields[1] {
            "0" => false,
            "1" => true,
            other => {
                return Err(self
                    .error(Some(n), format!("file type '{other}' in $MeshFormat is neither 0 (ASCII) nor 1 (binary)")))
            }
        };
        let size_t_bytes = match fields[2].parse::<usize>() {
            Ok(s @ (4 | 8)) => s,
            _ => {
                return Err(self.error(
                    Some(n),
                    format!("data size '{}' in $MeshFormat is not supported (4 or 8 bytes)", fields[2]),
                ))
            }
        };
        let mut little_endian = true;
        if binary {
            // The integer 1 follows the header line, in the writer's byte order.
            let at = lines.pos;
            let Some(word) = self.bytes.get(at..at + 4) else {
                return Err(self.error(Some(n), "the file ends inside $MeshFormat"));
            };
            let word: [u8; 4] = [word[0], word[1], word[2], word[3]];
            little_endian = if i32::from_le_bytes(word) == 1 {
                true
            } else if i32::from_be_bytes(word) == 1 {
                false
            } else {
                return Err(
                    self.error(Some(n + 1), "cannot tell the byte order: the integer 1 after the header is missing")
                );
            };
        }
        Ok(Format { binary, size_t_bytes, little_endian })
    }

    /// Offset just after the line `$name` (at a line start), if the file has that section.
    fn find_section(&self, name: &str) -> Option<usize> {
        let tag = format!("${name}");
        let tag = tag.as_bytes();
        let mut start = 0;
        while start < self.bytes.len() {
            let end = self.bytes[start..].iter().position(|&b| b == b'\n').map_or(self.bytes.len(), |p| start + p);
            let line = &self.bytes[start..end];
            let trimmed = trim_ascii(line);
            if trimmed == tag {
                return Some((end + 1).min(self.bytes.len()));
            }
            start = end + 1;
        }
        None
    }

    /// `$PhysicalNames`: (dim, tag) -> name.
    fn read_physical_names(&self) -> Result<Vec<(u8, i32, String)>> {
        let Some(at) = self.find_section("PhysicalNames") else {
            return Ok(Vec::new());
        };
        let mut lines = Lines::new(self.bytes, at, self.line_at(at));
        let truncated = |lines: &Lines| self.error(Some(lines.line), "the file ends inside $PhysicalNames");
        let (n, count_line) = lines.next().ok_or_else(|| truncated(&lines))?;
        let count: usize = count_line.trim().parse().map_err(|_| {
            self.error(Some(n), format!("expected the number of physical names, found '{}'", count_line.trim()))
        })?;
        let mut names = Vec::with_capacity(count.min(1 << 16));
        for _ in 0..count {
            let (n, line) = lines.next().ok_or_else(|| truncated(&lines))?;
            let bad = |what: &str| {
                self.error(
                    Some(n),
                    format!("{what} in $PhysicalNames: expected '<dim> <tag> \"<name>\"', found '{}'", line.trim()),
                )
            };
            let line = line.trim();
            let (dim, rest) = split_token(line);
            let (tag, rest) = split_token(rest);
            let dim: u8 = dim.parse().map_err(|_| bad("bad dimension"))?;
            let tag: i32 = tag.parse().map_err(|_| bad("bad tag"))?;
            let rest = rest.trim();
            let name = if let Some(quoted) = rest.strip_prefix('"') {
                let close = quoted.rfind('"').ok_or_else(|| bad("unterminated name"))?;
                &quoted[..close]
            } else {
                rest
            };
            if name.is_empty() {
                return Err(bad("empty name"));
            }
            names.push((dim, tag, name.to_string()));
        }
        match lines.next() {
            Some((_, l)) if l.trim() == "$EndPhysicalNames" => Ok(names),
            Some((n, l)) => {
                Err(self
                    .error(Some(n), format!("expected $EndPhysicalNames after {count} names, found '{}'", l.trim())))
            }
            None => Err(truncated(&lines)),
        }
    }

    /// The node tags of `$Nodes`, in file order (`mshio` drops them when they are contiguous).
    fn read_node_tags(&self, format: Format) -> Result<Vec<u64>> {
        let Some(at) = self.find_section("Nodes") else {
            return Err(self.error(None, "the file has no $Nodes section"));
        };
        let mut r = NumberReader::new(self, format, at);
        let num_blocks = r.size_t("number of node blocks")?;
        let num_nodes = r.size_t("number of nodes")?;
        r.size_t("minimum node tag")?;
        r.size_t("maximum node tag")?;
        if num_nodes == 0 {
            return Err(self.error(r.line(), "the $Nodes section is empty"));
        }
        let mut tags = Vec::with_capacity((num_nodes as usize).min(self.bytes.len() / 8 + 1));
        for _ in 0..num_blocks {
            r.int("node block dimension")?;
            r.int("node block entity tag")?;
            let parametric = r.int("node block parametric flag")?;
            if parametric != 0 {
                return Err(self.error(
                    r.line(),
                    "parametric node coordinates are not supported; save without them (Mesh.SaveParametric = 0)",
                ));
            }
            let n = r.size_t("number of nodes in the block")?;
            for _ in 0..n {
                tags.push(r.size_t("node tag")?);
            }
            r.skip_doubles(3 * n, "node coordinates")?;
        }
        if tags.len() as u64 != num_nodes {
            return Err(
                self.error(r.line(), format!("$Nodes announces {num_nodes} nodes but its blocks hold {}", tags.len()))
            );
        }
        Ok(tags)
    }

    /// `mshio` cannot handle an empty `$Elements` section.
    fn check_element_header(&self, format: Format) -> Result<()> {
        let Some(at) = self.find_section("Elements") else {
            return Err(self.error(None, "the file has no $Elements section"));
        };
        let mut r = NumberReader::new(self, format, at);
        r.size_t("number of element blocks")?;
        if r.size_t("number of elements")? == 0 {
            return Err(self.error(r.line(), "the $Elements section is empty"));
        }
        Ok(())
    }

    fn parser_error(&self, e: MshParserError<&[u8]>, format: Format) -> Error {
        let trace = e.filtered_backtrace();
        let Some((rest, kind)) = trace.first() else {
            return self.error(None, "cannot parse the file (no details from the MSH parser)");
        };
        let mut offset = self.bytes.len() - rest.len();
        let at_end = self.bytes[offset..].iter().all(|b| b.is_ascii_whitespace());
        while offset < self.bytes.len() && self.bytes[offset].is_ascii_whitespace() && !format.binary {
            offset += 1;
        }
        let line = if format.binary { None } else { Some(self.line_at(offset)) };
        // Innermost first: the failures (error kinds), then where the parser was (contexts).
        let problems: Vec<String> =
            trace.iter().filter(|(_, k)| k.context().is_none()).map(|(_, k)| k.to_string()).collect();
        let contexts: Vec<&str> = trace.iter().rev().filter_map(|(_, k)| k.context()).collect();
        let mut message =
            format!("cannot parse: {}", if problems.is_empty() { format!("{kind}") } else { problems.join("; ") });
        if !contexts.is_empty() {
            message += &format!(" (while reading {})", contexts.join(" > "));
        }
        let last_line = trim_ascii(self.bytes).rsplit(|&b| b == b'\n').next().unwrap_or_default();
        if at_end {
            message += "; the file ends early (truncated?)";
        } else if !trim_ascii(last_line).starts_with(b"$End") {
            message += "; the file does not end with an $End... line (truncated?)";
        }
        self.error(line, message)
    }

    fn build(
        &self,
        msh: &mshio::MshFile<u64, i32, f64>,
        names: &[(u8, i32, String)],
        node_tags: &[u64],
    ) -> Result<Mesh> {
        // Physical groups of dimension 1 and 2: named ones in file order, then unnamed by tag.
        let mut groups: Vec<PhysicalGroup> = Vec::new();
        let mut group_of: HashMap<(u8, i32), usize> = HashMap::new();
        let add_group = |groups: &mut Vec<PhysicalGroup>,
                         group_of: &mut HashMap<(u8, i32), usize>,
                         dim: u8,
                         tag: i32,
                         name: String| {
            group_of.entry((dim, tag)).or_insert_with(|| {
                groups.push(PhysicalGroup { name, tag, dim });
                groups.len() - 1
            });
        };
        for (dim, tag, name) in names.iter().filter(|(d, ..)| *d == 1 || *d == 2) {
            add_group(&mut groups, &mut group_of, *dim, *tag, name.clone());
        }
        let mut entity_groups: HashMap<(u8, i32), Vec<i32>> = HashMap::new();
        if let Some(entities) = &msh.data.entities {
            for c in &entities.curves {
                entity_groups.insert((1, c.tag), c.physical_tags.clone());
            }
            for s in &entities.surfaces {
                entity_groups.insert((2, s.tag), s.physical_tags.clone());
            }
        }
        let mut unnamed: Vec<(u8, i32)> = entity_groups
            .iter()
            .flat_map(|(&(dim, _), tags)| tags.iter().map(move |&t| (dim, t)))
            .filter(|key| !group_of.contains_key(key))
            .collect();
        unnamed.sort_unstable();
        unnamed.dedup();
        for (dim, tag) in unnamed {
            add_group(&mut groups, &mut group_of, dim, tag, tag.to_string());
        }
        let has_physical_surface = entity_groups.iter().any(|(&(dim, _), tags)| dim == 2 && !tags.is_empty());
        let groups_of_entity = |dim: u8, entity: i32| -> Result<Vec<usize>> {
            if msh.data.entities.is_none() {
                return Ok(Vec::new());
            }
            let tags = entity_groups.get(&(dim, entity)).ok_or_else(|| {
                self.error(
                    None,
                    format!(
                        "elements refer to {} entity {entity}, which is not in the $Entities section",
                        if dim == 1 { "curve" } else { "surface" }
                    ),
                )
            })?;
            Ok(tags.iter().map(|t| group_of[&(dim, *t)]).collect())
        };

        let Some(elements) = &msh.data.elements else {
            return Err(self.error(None, "the file has no $Elements section"));
        };
        // Order of the mesh, and rejection of unsupported element types.
        let mut first_of_order: [Option<(u64, ElementType)>; 2] = [None, None];
        for block in &elements.element_blocks {
            let first_tag = block.elements.first().map_or(0, |e| e.element_tag);
            let slot = match block.element_type {
                ElementType::Tri3 | ElementType::Lin2 => 0,
                ElementType::Tri6 | ElementType::Lin3 => 1,
                ElementType::Pnt => continue,
                other => {
                    return Err(self.error(
                        None,
                        format!(
                            "element {first_tag} is {}; only triangles (Gmsh types 2, 9), lines (1, 8) and \
                             points (15) are supported: mesh the 2D domain with triangles (no recombination into quads)",
                            describe_type(other)
                        ),
                    ))
                }
            };
            if first_of_order[slot].is_none() && !block.elements.is_empty() {
                first_of_order[slot] = Some((first_tag, block.element_type));
            }
        }
        let order = match first_of_order {
            [Some((t1, k1)), Some((t2, k2))] => {
                return Err(self.error(
                    None,
                    format!(
                        "the file mixes linear and quadratic elements: element {t1} is {} and element {t2} is {}; \
                         export all elements with the same order",
                        describe_type(k1),
                        describe_type(k2)
                    ),
                ))
            }
            [_, Some(_)] => Order::P2,
            _ => Order::P1,
        };

        let index = NodeIndex::new(node_tags)
            .map_err(|tag| self.error(None, format!("node tag {tag} appears twice in $Nodes")))?;
        let lookup = |element: u64, tag: u64| {
            index.get(tag).ok_or_else(|| {
                self.error(None, format!("element {element} refers to node {tag}, which is not in the $Nodes section"))
            })
        };

        let mut cells = Vec::new();
        let mut cell_group = Vec::new();
        let mut edges = Vec::new();
        let mut edge_group = Vec::new();
        for block in &elements.element_blocks {
            match block.element_type {
                ElementType::Tri3 | ElementType::Tri6 => {
                    let groups_here = groups_of_entity(2, block.entity_tag)?;
                    let group = match groups_here.as_slice() {
                        [] if has_physical_surface => continue,
                        [] => NO_GROUP,
                        [g] => *g,
                        several => {
                            let list: Vec<String> = several.iter().map(|&g| format!("'{}'", groups[g].name)).collect();
                            return Err(self.error(
                                None,
                                format!(
                                    "surface {} belongs to several physical surfaces ({}); a triangle can have one region: \
                                     put each surface in one physical surface",
                                    block.entity_tag,
                                    list.join(", ")
                                ),
                            ));
                        }
                    };
                    for element in &block.elements {
                        for &tag in &element.nodes {
                            cells.push(lookup(element.element_tag, tag)?);
                        }
                        cell_group.push(group);
                    }
                }
                ElementType::Lin2 | ElementType::Lin3 => {
                    let groups_here = groups_of_entity(1, block.entity_tag)?;
                    for element in &block.elements {
                        for &g in &groups_here {
                            for &tag in &element.nodes {
                                edges.push(lookup(element.element_tag, tag)?);
                            }
                            edge_group.push(g);
                        }
                    }
                }
                _ => {}
            }
        }

        // Compact the nodes: keep those used by kept elements, in file order.
        let mut new_index = vec![usize::MAX; node_tags.len()];
        for &v in cells.iter().chain(edges.iter()) {
            new_index[v] = 0;
        }
        let mut kept = 0;
        for slot in new_index.iter_mut().filter(|s| **s == 0) {
            *slot = kept;
            kept += 1;
        }
        let mut nodes = vec![[0.0; 2]; kept];
        let mut z_values = Vec::new();
        let mut file_index = 0;
        if let Some(node_data) = &msh.data.nodes {
            for block in &node_data.node_blocks {
                for node in &block.nodes {
                    if let Some(&k) = new_index.get(file_index).filter(|&&k| k != usize::MAX) {
                        nodes[k] = [node.x, node.y];
                        if node.z != 0.0 {
                            z_values.push((file_index, node.x, node.y, node.z));
                        }
                    }
                    file_index += 1;
                }
            }
        }
        if file_index != node_tags.len() {
            return Err(self.error(
                None,
                format!("the MSH parser found {file_index} nodes, the $Nodes blocks list {} tags", node_tags.len()),
            ));
        }
        let scale = nodes.iter().fold(0.0f64, |s, p| s.max(p[0].abs()).max(p[1].abs()));
        if let Some(&(i, x, y, z)) = z_values.iter().find(|v| v.3.is_nan() || v.3.abs() > 1e-12 * scale) {
            return Err(Error::Mesh {
                source_file: Some(self.file.to_path_buf()),
                entity: format!("node tag {} at ({x}, {y}, {z})", node_tags[i]),
                message: "not a planar mesh: z must be 0 (mesh the geometry in the xy-plane)".to_string(),
            });
        }
        for v in cells.iter_mut().chain(edges.iter_mut()) {
            *v = new_index[*v];
        }
        Ok(Mesh { order, nodes, cells, cell_group, edges, edge_group, groups, measure: super::Measure::Plane })
    }
}

fn describe_type(t: ElementType) -> String {
    let what = match t {
        ElementType::Lin2 => "a 2-node line",
        ElementType::Lin3 => "a 3-node line",
        ElementType::Tri3 => "a 3-node triangle",
        ElementType::Tri6 => "a 6-node triangle",
        ElementType::Qua4 | ElementType::Qua8 | ElementType::Qua9 => "a quadrangle",
        ElementType::Tet4 | ElementType::Tet10 => "a tetrahedron",
        ElementType::Hex8 | ElementType::Hex20 | ElementType::Hex27 => "a hexahedron",
        ElementType::Pri6 | ElementType::Pri15 | ElementType::Pri18 => "a prism",
        ElementType::Pyr5 | ElementType::Pyr13 | ElementType::Pyr14 => "a pyramid",
        _ => "an element",
    };
    format!("{what} (Gmsh type {}, {t:?})", t as i32)
}

fn trim_ascii(mut s: &[u8]) -> &[u8] {
    while let [first, rest @ ..] = s {
        if first.is_ascii_whitespace() {
            s = rest;
        } else {
            break;
        }
    }
    while let [rest @ .., last] = s {
        if last.is_ascii_whitespace() {
            s = rest;
        } else {
            break;
        }
    }
    s
}

fn split_token(s: &str) -> (&str, &str) {
    let s = s.trim_start();
    match s.find(char::is_whitespace) {
        Some(p) => (&s[..p], &s[p..]),
        None => (s, ""),
    }
}

/// Text lines with their 1-based numbers (lossy UTF-8).
struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    fn new(bytes: &'a [u8], pos: usize, line: usize) -> Self {
        Lines { bytes, pos, line }
    }
    fn next(&mut self) -> Option<(usize, String)> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        let text = String::from_utf8_lossy(&rest[..len]).into_owned();
        let number = self.line;
        self.pos += len + 1;
        self.line += 1;
        Some((number, text))
    }
}

/// Numbers of a section, as whitespace-separated text or as raw binary.
struct NumberReader<'r, 'a> {
    reader: &'r MshReader<'a>,
    format: Format,
    pos: usize,
    /// Current line (ASCII only).
    line: usize,
}

impl<'r, 'a> NumberReader<'r, 'a> {
    fn new(reader: &'r MshReader<'a>, format: Format, pos: usize) -> Self {
        let line = if format.binary { 0 } else { reader.line_at(pos) };
        NumberReader { reader, format, pos, line }
    }

    fn line(&self) -> Option<usize> {
        (!self.format.binary).then_some(self.line)
    }

    fn truncated(&self, what: &str) -> Error {
        self.reader.error(self.line(), format!("the file ends early: expected {what} (truncated?)"))
    }

    /// Next whitespace-separated token (ASCII).
    fn token(&mut self, what: &str) -> Result<&'a [u8]> {
        let bytes = self.reader.bytes;
        while self.pos < bytes.len() && bytes[self.pos].is_ascii_whitespace() {
            if bytes[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < bytes.len() && !bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.truncated(what));
        }
        Ok(&bytes[start..self.pos])
    }

    fn raw<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let bytes = self.reader.bytes;
        let Some(chunk) = bytes.get(self.pos..self.pos + N) else {
            return Err(self.truncated(what));
        };
        self.pos += N;
        let mut out = [0u8; N];
        out.copy_from_slice(chunk);
        if self.format.little_endian != cfg!(target_endian = "little") {
            out.reverse();
        }
        Ok(out)
    }

    fn parse_token<T: std::str::FromStr>(&mut self, what: &str) -> Result<T> {
        let token = self.token(what)?;
        let text = String::from_utf8_lossy(token);
        text.parse().map_err(|_| self.reader.error(self.line(), format!("expected {what}, found '{text}'")))
    }

    fn size_t(&mut self, what: &str) -> Result<u64> {
        if !self.format.binary {
            return self.parse_token(what);
        }
        Ok(match self.format.size_t_bytes {
            4 => u32::from_ne_bytes(self.raw::<4>(what)?) as u64,
            _ => u64::from_ne_bytes(self.raw::<8>(what)?),
        })
    }

    fn int(&mut self, what: &str) -> Result<i32> {
        if !self.format.binary {
            return self.parse_token(what);
        }
        Ok(i32::from_ne_bytes(self.raw::<4>(what)?))
    }

    fn skip_doubles(&mut self, n: u64, what: &str) -> Result<()> {
        if self.format.binary {
            let len = usize::try_from(n).ok().and_then(|n| n.checked_mul(8));
            match len.and_then(|l| self.pos.checked_add(l)).filter(|&end| end <= self.reader.bytes.len()) {
                Some(end) => self.pos = end,
                None => return Err(self.truncated(what)),
            }
        } else {
            for _ in 0..n {
                self.token(what)?;
            }
        }
        Ok(())
    }
}

/// Gmsh node tag -> position in file order.
enum NodeIndex {
    Dense { min: u64, index: Vec<usize> },
    Sparse(HashMap<u64, usize>),
}

impl NodeIndex {
    /// Fails with the first repeated tag.
    fn new(tags: &[u64]) -> std::result::Result<Self, u64> {
        let (min, max) = tags.iter().fold((u64::MAX, 0), |(lo, hi), &t| (lo.min(t), hi.max(t)));
        let span = max.saturating_sub(min);
        if span <= 4 * tags.len() as u64 + 16 {
            let mut index = vec![usize::MAX; span as usize + 1];
            for (i, &t) in tags.iter().enumerate() {
                let slot = &mut index[(t - min) as usize];
                if *slot != usize::MAX {
                    return Err(t);
                }
                *slot = i;
            }
            Ok(NodeIndex::Dense { min, index })
        } else {
            let mut map = HashMap::with_capacity(tags.len());
            for (i, &t) in tags.iter().enumerate() {
                if map.insert(t, i).is_some() {
                    return Err(t);
                }
            }
            Ok(NodeIndex::Sparse(map))
        }
    }

    fn get(&self, tag: u64) -> Option<usize> {
        match self {
            NodeIndex::Dense { min, index } => {
                let i = *index.get(usize::try_from(tag.checked_sub(*min)?).ok()?)?;
                (i != usize::MAX).then_some(i)
            }
            NodeIndex::Sparse(map) => map.get(&tag).copied(),
        }
    }
}
