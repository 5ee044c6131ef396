//! MSH 4.1 files written inline: what is read, and every error at its place.

use crate::edit::Edit;

use crate::{assert_counter_clockwise, close, inline_path, mesh_error_text, read_inline, total_area, Scratch};
use signorini::mesh::msh::read_msh;
use signorini::mesh::{Order, NO_GROUP};
use signorini::Error;

// ---------------------------------------------------------------------------------------------
// MSH 4.1 files written inline
// ---------------------------------------------------------------------------------------------

/// An element block: (entity dim, entity tag, element type, [(element tag, node tags)]).
type Block = (i32, i32, i32, Vec<(u64, Vec<u64>)>);

/// A small MSH 4.1 ASCII file.
struct MshText {
    format: &'static str,
    names: Vec<(u8, i32, &'static str)>,
    /// (tag, physical tags) of curves and surfaces.
    curves: Vec<(i32, Vec<i32>)>,
    surfaces: Vec<(i32, Vec<i32>)>,
    nodes: Vec<(u64, [f64; 3])>,
    blocks: Vec<Block>,
}

impl MshText {
    /// Unit square with node tags 10, 20, 30, 40 (+ unused 99), triangles (10,20,30), (10,30,40),
    /// boundary lines on curve 1 (group "bottom side") and curve 2 (group 7, unnamed).
    fn square() -> Self {
        MshText {
            format: "4.1 0 8",
            names: vec![(1, 5, "bottom side"), (2, 6, "domain"), (1, 8, "unused \"quoted\" name")],
            curves: vec![(1, vec![5]), (2, vec![7]), (3, vec![])],
            surfaces: vec![(1, vec![6])],
            nodes: vec![
                (10, [0.0, 0.0, 0.0]),
                (20, [1.0, 0.0, 0.0]),
                (99, [5.0, 5.0, 0.0]),
                (30, [1.0, 1.0, 0.0]),
                (40, [0.0, 1.0, 0.0]),
            ],
            blocks: vec![
                (2, 1, 2, vec![(1, vec![10, 20, 30]), (2, vec![10, 30, 40])]),
                (1, 1, 1, vec![(3, vec![10, 20])]),
                (1, 2, 1, vec![(4, vec![30, 20])]),
                (1, 3, 1, vec![(5, vec![30, 40])]),
            ],
        }
    }

    fn text(&self) -> String {
        let mut s = format!("$MeshFormat\n{}\n$EndMeshFormat\n", self.format);
        if !self.names.is_empty() {
            s += &format!("$PhysicalNames\n{}\n", self.names.len());
            for (d, t, n) in &self.names {
                s += &format!("{d} {t} \"{n}\"\n");
            }
            s += "$EndPhysicalNames\n";
        }
        s += &format!("$Entities\n0 {} {} 0\n", self.curves.len(), self.surfaces.len());
        let tags = |t: &Vec<i32>| {
            let mut s = t.len().to_string();
            for x in t {
                s += &format!(" {x}");
            }
            s
        };
        for (tag, phys) in self.curves.iter().chain(self.surfaces.iter()) {
            s += &format!("{tag} 0 0 0 1 1 0 {} 0\n", tags(phys));
        }
        s += "$EndEntities\n";
        let (min, max) = self.nodes.iter().fold((u64::MAX, 0), |(a, b), n| (a.min(n.0), b.max(n.0)));
        s += &format!("$Nodes\n1 {} {min} {max}\n2 1 0 {}\n", self.nodes.len(), self.nodes.len());
        for (t, _) in &self.nodes {
            s += &format!("{t}\n");
        }
        for (_, p) in &self.nodes {
            s += &format!("{:?} {:?} {:?}\n", p[0], p[1], p[2]);
        }
        s += "$EndNodes\n";
        let all: Vec<u64> = self.blocks.iter().flat_map(|b| b.3.iter().map(|e| e.0)).collect();
        s += &format!(
            "$Elements\n{} {} {} {}\n",
            self.blocks.len(),
            all.len(),
            all.iter().min().unwrap(),
            all.iter().max().unwrap()
        );
        for (dim, ent, ty, elements) in &self.blocks {
            s += &format!("{dim} {ent} {ty} {}\n", elements.len());
            for (tag, nodes) in elements {
                s += &tag.to_string();
                for n in nodes {
                    s += &format!(" {n}");
                }
                s += "\n";
            }
        }
        s += "$EndElements\n";
        s
    }
}

#[test]
fn msh_inline_square_is_read_compacted_and_oriented() {
    let mesh = read_inline("square", &MshText::square().text()).unwrap();
    assert_eq!(mesh.order, Order::P1);
    assert_eq!(mesh.num_nodes(), 4, "the unused node 99 is dropped");
    assert_eq!(mesh.nodes, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    assert_eq!(mesh.cells, vec![0, 1, 2, 0, 2, 3]);
    assert_eq!(mesh.num_edges(), 2, "lines without a physical group are ignored");
    let bottom = mesh.require_group("bottom side", 1).unwrap();
    let unnamed = mesh.require_group("7", 1).unwrap();
    assert!(mesh.group_index("unused \"quoted\" name", 1).is_some());
    assert_eq!(mesh.groups[bottom].tag, 5);
    assert_eq!(mesh.edges_in_group(bottom).collect::<Vec<_>>(), vec![0]);
    // The line 30 -> 20 was reversed so the domain is on its left.
    let e = mesh.edges_in_group(unnamed).next().unwrap();
    assert_eq!(mesh.edge(e), &[1, 2]);
    assert_eq!(mesh.edge_normal(e).0, [1.0, 0.0]);
    let domain = mesh.require_group("domain", 2).unwrap();
    assert_eq!(mesh.cell_group, vec![domain, domain]);
}

#[test]
fn msh_inline_variants() {
    // Clockwise triangles are flipped; no physical surface: triangles kept with NO_GROUP;
    // a line in two physical curves gives two edges.
    let mut m = MshText::square();
    m.blocks[0].3 = vec![(1, vec![10, 30, 20]), (2, vec![10, 40, 30])];
    m.surfaces = vec![(1, vec![])];
    m.curves[0].1 = vec![5, 7];
    let mesh = read_inline("variants", &m.text()).unwrap();
    assert_eq!(mesh.cell_group, vec![NO_GROUP; 2]);
    assert_counter_clockwise(&mesh);
    assert_eq!(mesh.num_edges(), 3);
    assert_eq!(mesh.edge(0), mesh.edge(1));
    assert_ne!(mesh.edge_group[0], mesh.edge_group[1]);
    // Triangles outside physical surfaces are dropped when there are physical surfaces.
    let mut m = MshText::square();
    m.surfaces = vec![(1, vec![6]), (2, vec![])];
    m.nodes.push((50, [2.0, 0.0, 0.0]));
    m.blocks.push((2, 2, 2, vec![(9, vec![20, 50, 30])]));
    let mesh = read_inline("dropped", &m.text()).unwrap();
    assert_eq!((mesh.num_cells(), mesh.num_nodes()), (2, 4));
}

#[test]
fn msh_p2_inline() {
    let mut m = MshText::square();
    m.nodes.extend([
        (11, [0.5, 0.0, 0.0]),
        (12, [1.0, 0.5, 0.0]),
        (13, [0.5, 1.0, 0.0]),
        (14, [0.0, 0.5, 0.0]),
        (15, [0.5, 0.5, 0.0]),
    ]);
    m.blocks = vec![
        (2, 1, 9, vec![(1, vec![10, 20, 30, 11, 12, 15]), (2, vec![10, 30, 40, 15, 13, 14])]),
        (1, 1, 8, vec![(3, vec![10, 20, 11])]),
        (1, 2, 8, vec![(4, vec![30, 20, 12])]),
    ];
    let mesh = read_inline("p2", &m.text()).unwrap();
    assert_eq!(mesh.order, Order::P2);
    assert_eq!(mesh.num_nodes(), 9);
    assert_eq!(mesh.num_edges(), 2);
    assert!(close(total_area(&mesh), 1.0, 1e-15));
    // Mixed orders are refused.
    m.blocks.push((1, 3, 1, vec![(5, vec![30, 40])]));
    let (e, text) = mesh_error_text(read_inline("mixed", &m.text()));
    assert!(matches!(e, Error::MeshFile { .. }));
    assert!(text.contains("mixes linear and quadratic") && text.contains("element 5"), "{text}");
}

#[test]
fn msh_error_version_2() {
    let mut m = MshText::square();
    m.format = "2.2 0 8";
    let (e, text) = mesh_error_text(read_inline("v22", &m.text()));
    let path = inline_path("v22");
    assert!(matches!(e, Error::MeshFile { line: Some(2), .. }), "{e:?}");
    assert!(text.contains(&path.display().to_string()), "{text}");
    assert!(
        text.contains(
            "MSH 2.2 is not supported: re-export as MSH 4.1 (gmsh -format msh41, or Mesh.MshFileVersion = 4.1)"
        ),
        "{text}"
    );
}

#[test]
fn msh_error_unsupported_element() {
    let mut m = MshText::square();
    m.blocks[0] = (2, 1, 3, vec![(17, vec![10, 20, 30, 40])]);
    let (e, text) = mesh_error_text(read_inline("quad", &m.text()));
    assert!(matches!(e, Error::MeshFile { .. }));
    assert!(text.contains("element 17") && text.contains("type 3") && text.contains("quadrangle"), "{text}");
    assert!(text.contains("quad.msh"), "{text}");
}

#[test]
fn msh_error_truncated() {
    let text = MshText::square().text();
    let cut = text.find("$EndNodes").unwrap() - 12;
    let (e, msg) = mesh_error_text(read_inline("truncated", &text[..cut]));
    let Error::MeshFile { line, .. } = &e else { panic!("{e:?}") };
    assert!(line.is_some(), "{e:?}");
    assert!(msg.contains("truncated.msh") && msg.contains("ends early"), "{msg}");
    // Truncated in the elements: mshio's error, with a line.
    let cut = text.find("$EndElements").unwrap() - 4;
    let (e, msg) = mesh_error_text(read_inline("truncated2", &text[..cut]));
    assert!(matches!(e, Error::MeshFile { line: Some(_), .. }), "{e:?}");
    assert!(msg.contains("truncated2.msh") && msg.contains("truncated?"), "{msg}");
    // Garbage in place of a number.
    let bad = text.replacen("0.0 1.0 0.0", "0.0 x1.0 0.0", 1);
    let (e, msg) = mesh_error_text(read_inline("garbage", &bad));
    let expected_line = bad[..bad.find("x1.0").unwrap()].lines().count();
    assert!(matches!(e, Error::MeshFile { line: Some(l), .. } if l == expected_line), "{e:?} (line {expected_line})");
    assert!(msg.contains("garbage.msh"), "{msg}");
}

#[test]
fn msh_error_non_planar() {
    let mut m = MshText::square();
    m.nodes[3].1[2] = 0.5;
    let (e, text) = mesh_error_text(read_inline("nonplanar", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(text.contains("node tag 30 at (1, 1, 0.5)") && text.contains("not a planar mesh"), "{text}");
    assert!(text.contains("nonplanar.msh"), "{text}");
    // Rounding noise in z is accepted.
    let mut m = MshText::square();
    m.nodes[3].1[2] = 1e-14;
    read_inline("almost_planar", &m.text()).unwrap();
}

#[test]
fn msh_error_degenerate_triangle() {
    let mut m = MshText::square();
    m.nodes[3].1 = [2.0, 0.0, 0.0]; // node 30 on the line through 10 and 20
    let (e, text) = mesh_error_text(read_inline("degenerate", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(
        text.contains("degenerate.msh") && text.contains("triangle 0 (nodes 0, 1, 2)") && text.contains("degenerate"),
        "{text}"
    );
}

#[test]
fn msh_error_inverted_triangle() {
    let mut m = MshText::square();
    m.nodes.push((50, [2.0, 0.0, 0.0]));
    m.blocks[0].3.push((3, vec![20, 30, 50])); // clockwise, the other two counter-clockwise
    let (e, text) = mesh_error_text(read_inline("inverted", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(text.contains("triangle 2 (nodes 1, 2, 4)") && text.contains("inverted"), "{text}");
}

#[test]
fn msh_error_boundary_edge_off_the_mesh() {
    let mut m = MshText::square();
    m.blocks[1].3.push((6, vec![20, 40])); // the diagonal not used by the triangles
    let (e, text) = mesh_error_text(read_inline("offedge", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(
        text.contains("boundary edge 1 of group 'bottom side'") && text.contains("not a side of any triangle"),
        "{text}"
    );
}

#[test]
fn msh_error_unknown_node_and_missing_file() {
    let mut m = MshText::square();
    m.blocks[0].3[1].1[2] = 77;
    let (e, text) = mesh_error_text(read_inline("unknown_node", &m.text()));
    assert!(matches!(e, Error::MeshFile { .. }));
    assert!(text.contains("element 2 refers to node 77"), "{text}");

    let dir = Scratch::new("missing");
    let path = dir.path("does-not-exist.msh");
    let (e, text) = mesh_error_text(read_msh(&path));
    assert!(matches!(e, Error::Io { .. }), "{e:?}");
    assert!(text.contains("does-not-exist.msh"), "{text}");
}

#[test]
fn msh_error_not_an_msh_file() {
    let (e, text) = mesh_error_text(read_inline("notmsh", "hello\n"));
    assert!(matches!(e, Error::MeshFile { line: Some(1), .. }));
    assert!(text.contains("$MeshFormat"), "{text}");
    let bad_names = MshText::square().text().edit("2 6 \"domain\"", "2 six \"domain\"");
    let (e, text) = mesh_error_text(read_inline("badnames", &bad_names));
    assert!(matches!(e, Error::MeshFile { line: Some(7), .. }), "{e:?}");
    assert!(text.contains("PhysicalNames"), "{text}");
}
