//! Remeshing from a size map with Gmsh (no PETSc): the new mesh follows the map — finer where
//! the sizes are small, coarser where they are large — and curved boundaries stay exact.
use signorini::adapt::{element_sizes, nodal_sizes, optimal_size_map, remesh, SizeMapLimits};
use signorini::mesh::gmsh::{generate, MeshRequest, Shape};
use signorini::mesh::{Mesh, Order};

fn disc(cell_size: f64, order: Order) -> (MeshRequest, Mesh) {
    let request =
        MeshRequest { shape: Shape::Disc { center: [0.3, -0.2], radius: 0.5 }, cell_size, refinement: None, order };
    let mesh = generate(&request).expect("gmsh (./setup.sh installs it)");
    (request, mesh)
}

fn centroid(mesh: &Mesh, c: usize) -> [f64; 2] {
    let v = mesh.cell(c);
    let x: Vec<[f64; 2]> = v[..3].iter().map(|&n| mesh.nodes[n]).collect();
    [(x[0][0] + x[1][0] + x[2][0]) / 3.0, (x[0][1] + x[1][1] + x[2][1]) / 3.0]
}

#[test]
fn element_sizes_of_a_uniform_mesh_match_the_requested_size() {
    let (_, mesh) = disc(0.05, Order::P1);
    let h = element_sizes(&mesh);
    let mean = h.iter().sum::<f64>() / h.len() as f64;
    assert!((mean / 0.05 - 1.0).abs() < 0.15, "mean size {mean} for cell_size 0.05");
    let nodal = nodal_sizes(&mesh, &h);
    assert!(nodal.iter().all(|&s| s > 0.0));
}

#[test]
fn remeshing_refines_and_coarsens_and_keeps_the_circle() {
    let (request, mesh) = disc(0.05, Order::P2);
    let h = element_sizes(&mesh);
    // An error concentrated near one boundary point: the optimal map refines there and
    // coarsens everywhere else, so the element count can drop.
    let hot = [0.3, -0.7];
    let errors: Vec<f64> = (0..mesh.num_cells())
        .map(|c| {
            let x = centroid(&mesh, c);
            let d = ((x[0] - hot[0]).powi(2) + (x[1] - hot[1]).powi(2)).sqrt();
            1e-3 / (d + 0.01).powi(2)
        })
        .collect();
    let total = errors.iter().map(|e| e * e).sum::<f64>().sqrt();
    let map = optimal_size_map(&errors, &vec![1.0; errors.len()], 0.5 * total, SizeMapLimits::default()).unwrap();
    assert!(map.ratios.iter().any(|&r| r > 1.5) && map.ratios.iter().any(|&r| r < 0.7));
    let targets: Vec<f64> = h.iter().zip(&map.ratios).map(|(h, r)| h * r).collect();
    let new = remesh(&mesh, &request, &targets).unwrap();
    assert!(new.num_cells() < mesh.num_cells(), "coarsening: {} -> {} cells", mesh.num_cells(), new.num_cells());
    // Finer near the hot spot, coarser far from it.
    let new_h = element_sizes(&new);
    let near = |m: &Mesh, hs: &[f64], far: bool| {
        let mut v: Vec<f64> = (0..m.num_cells())
            .filter(|&c| {
                let x = centroid(m, c);
                let d = ((x[0] - hot[0]).powi(2) + (x[1] - hot[1]).powi(2)).sqrt();
                if far {
                    d > 0.6
                } else {
                    d < 0.08
                }
            })
            .map(|c| hs[c])
            .collect();
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v[v.len() / 2]
    };
    assert!(near(&new, &new_h, false) < 0.7 * near(&mesh, &h, false), "not refined near the hot spot");
    assert!(near(&new, &new_h, true) > 1.5 * near(&mesh, &h, true), "not coarsened far from it");
    // Every boundary node (vertices and P2 mid nodes) on the circle.
    let mut on_boundary = 0;
    for e in 0..new.num_edges() {
        for &n in new.edge(e) {
            let x = new.nodes[n];
            let r = ((x[0] - 0.3).powi(2) + (x[1] + 0.2).powi(2)).sqrt();
            assert!((r - 0.5).abs() <= 1e-12 * 0.5, "boundary node {n} at radius {r}");
            on_boundary += 1;
        }
    }
    assert!(on_boundary > 0);
    assert!(new.group_index("circle", 1).is_some(), "physical groups survive remeshing");
}

#[test]
fn bad_size_maps_are_refused() {
    let (request, mesh) = disc(0.1, Order::P1);
    assert!(remesh(&mesh, &request, &[0.1]).is_err());
    let mut sizes = vec![0.1; mesh.num_cells()];
    sizes[3] = f64::NAN;
    assert!(remesh(&mesh, &request, &sizes).is_err());
    let tiny = vec![1e-6; mesh.num_cells()];
    let message = remesh(&mesh, &request, &tiny).unwrap_err().to_string();
    assert!(message.contains("triangles"), "{message}");
}

/// The a priori rates per cell: the volume rate everywhere, a part's rate on exactly the cells
/// with an edge on that part (the hook for contact edges: 1/2 or 2/3 there).
#[test]
fn rate_model_gives_a_part_its_rate_on_the_cells_that_touch_it() {
    use signorini::adapt::RateModel;
    use signorini::mesh::structured;
    let mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 8, 4, Order::P1).unwrap();
    assert_eq!(RateModel::uniform(1.0).cell_rates(&mesh).unwrap(), vec![1.0; mesh.num_cells()]);
    let model = RateModel { volume: 1.0, parts: vec![("bottom".into(), 0.5), ("left".into(), 2.0 / 3.0)] };
    let rates = model.cell_rates(&mesh).unwrap();
    let on = |c: usize, test: &dyn Fn([f64; 2]) -> bool| {
        let v = mesh.cell(c);
        (0..3).any(|k| test(mesh.nodes[v[k]]) && test(mesh.nodes[v[(k + 1) % 3]]))
    };
    for (c, &r) in rates.iter().enumerate() {
        let bottom = on(c, &|x| x[1].abs() < 1e-12);
        let left = on(c, &|x| x[0].abs() < 1e-12);
        let expected = if bottom {
            0.5
        } else if left {
            2.0 / 3.0
        } else {
            1.0
        };
        assert_eq!(r, expected, "cell {c}");
    }
    assert_eq!(rates.iter().filter(|&&r| r == 0.5).count(), 8, "one cell per bottom edge");
    // An unknown part and a non-positive rate are errors.
    assert!(RateModel { volume: 1.0, parts: vec![("nowhere".into(), 0.5)] }.cell_rates(&mesh).is_err());
    assert!(RateModel::uniform(0.0).cell_rates(&mesh).is_err());
}

/// The Gmsh request of a scene is its geometry; a mesh file has none, and says so (typed).
#[test]
fn mesh_request_follows_the_scene_geometry_and_refuses_mesh_files() {
    use signorini::adapt::driver::mesh_request;
    use signorini::mesh::gmsh::Shape;
    use signorini::scene::Scene;
    use signorini::Error;
    let text = "[mesh]\nshape = \"half_disc\"\ncenter = [0.0, 1.0]\nradius = 1.0\ncell_size = 0.1\n\
                refine = { point = [0.0, 0.0], cell_size = 0.01, radius = 0.1 }\n\n[discretization]\norder = 2\n\n\
                [material]\nyoung = 1e9\npoisson = 0.3\n";
    let scene = Scene::from_str(text, std::path::Path::new("inline.toml")).unwrap();
    let r = mesh_request(&scene, "adapt").unwrap();
    assert_eq!(r.shape, Shape::HalfDisc { center: [0.0, 1.0], radius: 1.0 });
    assert_eq!((r.cell_size, r.order), (0.1, Order::P2));
    assert_eq!(r.refinement.unwrap().cell_size, 0.01);
    let dir = std::env::temp_dir().join(format!("signorini-adapt-file-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("m.msh"), "not read here").unwrap();
    let text = "[mesh]\nshape = \"file\"\nfile = \"m.msh\"\n\n[material]\nyoung = 1e9\npoisson = 0.3\n";
    let scene = Scene::from_str(text, &dir.join("s.toml")).unwrap();
    let e = mesh_request(&scene, "study").unwrap_err();
    assert!(matches!(&e, Error::NeedsGeometry { command: "study", file, .. } if file.ends_with("m.msh")), "{e:?}");
    let m = e.to_string();
    assert!(m.contains("signorini study") && m.contains("m.msh") && m.contains("hint:"), "{m}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The default rates of a scene: its element degree in the volume, 1/2 on its contact part.
#[test]
fn default_rates_follow_the_element_degree_and_the_contact_part() {
    use signorini::adapt::RateModel;
    use signorini::scene::Scene;
    let read = |rel: &str| Scene::from_file(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap();
    assert_eq!(RateModel::for_scene(&read("examples/scenes/clamped_block.toml")), RateModel::uniform(1.0));
    assert_eq!(RateModel::for_scene(&read("examples/scenes/block.toml")), RateModel::uniform(2.0));
    let hertz = RateModel::for_scene(&read("examples/scenes/hertz.toml"));
    assert_eq!(hertz, RateModel { volume: 2.0, parts: vec![("arc".into(), 0.5)] });
}
