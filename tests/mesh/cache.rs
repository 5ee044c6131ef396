//! The mesh cache: hits, corrupt entries, misses on any change, its size bound.

use crate::{assert_identical, half_disc_request, Scratch};
use signorini::mesh::cache::{CacheStatus, MeshCache};
use signorini::mesh::gmsh::{generate, generate_cached, MeshRequest, Refinement, Shape};
use signorini::mesh::Order;
use std::path::PathBuf;

fn entries(cache: &MeshCache) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(cache.entries_dir())
        .map(|d| d.map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|x| x == "mesh")).collect())
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn a_hit_is_the_same_mesh_to_the_bit_and_disabled_meshes_alike() {
    let scratch = Scratch::new("cache-hit");
    let cache = MeshCache::at(&scratch.0);
    let request = half_disc_request(0.02, Order::P2);
    let (made, first) = generate_cached(&request, Some(&cache)).unwrap();
    assert_eq!((first.status, first.problem.as_deref()), (CacheStatus::Miss, None));
    assert_eq!(entries(&cache).len(), 1);
    let (cached, second) = generate_cached(&request, Some(&cache)).unwrap();
    assert_eq!((second.status, second.problem.as_deref()), (CacheStatus::Hit, None));
    assert_identical(&made, &cached);
    // Without a cache: made by Gmsh again, the same mesh (Gmsh is deterministic), nothing
    // stored.
    let (fresh, off) = generate_cached(&request, None).unwrap();
    assert_eq!(off.status, CacheStatus::Disabled);
    assert_identical(&made, &fresh);
    assert_identical(&made, &generate(&request).unwrap());
    assert_eq!(entries(&cache).len(), 1);
}

#[test]
fn corrupt_or_truncated_entries_are_detected_remeshed_and_replaced() {
    let scratch = Scratch::new("cache-corrupt");
    let cache = MeshCache::at(&scratch.0);
    let request = half_disc_request(0.03, Order::P2);
    let (made, _) = generate_cached(&request, Some(&cache)).unwrap();
    let path = entries(&cache).pop().unwrap();
    let good = std::fs::read(&path).unwrap();
    let mut flipped = good.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x10; // one bit of a node coordinate or an index
    let damages: [(&str, Vec<u8>); 4] = [
        ("a flipped bit", flipped),
        ("truncation", good[..good.len() - 100].to_vec()),
        ("an empty file", Vec::new()),
        ("another file", b"not a mesh at all".to_vec()),
    ];
    for (what, bytes) in damages {
        std::fs::write(&path, &bytes).unwrap();
        let (mesh, report) = generate_cached(&request, Some(&cache)).unwrap();
        assert_eq!(report.status, CacheStatus::Miss, "{what}");
        let problem = report.problem.unwrap_or_else(|| panic!("{what}: not reported"));
        assert!(problem.contains("unusable entry") && problem.contains("replaced"), "{what}: {problem}");
        assert_identical(&made, &mesh);
        // Replaced: the entry is whole again and the next run hits.
        assert_eq!(std::fs::read(&path).unwrap(), good, "{what}");
        assert_eq!(generate_cached(&request, Some(&cache)).unwrap().1.status, CacheStatus::Hit, "{what}");
    }
}

#[test]
fn any_change_of_the_input_misses() {
    let scratch = Scratch::new("cache-inputs");
    let cache = MeshCache::at(&scratch.0);
    let base = half_disc_request(0.03, Order::P1);
    let variants = [
        base.clone(),
        MeshRequest { cell_size: 0.029, ..base.clone() },
        MeshRequest { order: Order::P2, ..base.clone() },
        MeshRequest { shape: Shape::HalfDisc { center: [0.0, 0.1], radius: 0.11 }, ..base.clone() },
        MeshRequest { shape: Shape::HalfDisc { center: [0.001, 0.1], radius: 0.1 }, ..base.clone() },
        MeshRequest { shape: Shape::Disc { center: [0.0, 0.1], radius: 0.1 }, ..base.clone() },
        MeshRequest { refinement: None, ..base.clone() },
        MeshRequest {
            refinement: Some(Refinement { point: [0.0, 0.0], cell_size: 0.03 / 8.0, radius: 0.016 }),
            ..base.clone()
        },
    ];
    for (k, request) in variants.iter().enumerate() {
        let (_, report) = generate_cached(request, Some(&cache)).unwrap();
        assert_eq!(report.status, CacheStatus::Miss, "variant {k}: {request:?}");
        assert_eq!(entries(&cache).len(), k + 1);
    }
    for (k, request) in variants.iter().enumerate() {
        let (mesh, report) = generate_cached(request, Some(&cache)).unwrap();
        assert_eq!(report.status, CacheStatus::Hit, "variant {k}");
        assert_eq!(mesh.order, request.order);
    }
}

#[test]
fn the_cache_keeps_to_its_size_bound_newest_first() {
    let scratch = Scratch::new("cache-bound");
    // Room for about one entry: each store removes the older ones, never itself.
    let cache = MeshCache::at(&scratch.0).with_max_bytes(1);
    for h in [0.05, 0.04] {
        let (_, report) = generate_cached(&half_disc_request(h, Order::P1), Some(&cache)).unwrap();
        assert_eq!(report.status, CacheStatus::Miss);
        assert_eq!(entries(&cache).len(), 1);
    }
    assert_eq!(generate_cached(&half_disc_request(0.04, Order::P1), Some(&cache)).unwrap().1.status, CacheStatus::Hit);
    assert_eq!(generate_cached(&half_disc_request(0.05, Order::P1), Some(&cache)).unwrap().1.status, CacheStatus::Miss);
}

#[test]
fn an_unwritable_cache_still_meshes_and_says_so() {
    let scratch = Scratch::new("cache-unwritable");
    let file = scratch.path("not-a-directory");
    std::fs::write(&file, b"x").unwrap();
    let cache = MeshCache::at(&file);
    let request = half_disc_request(0.05, Order::P1);
    let (mesh, report) = generate_cached(&request, Some(&cache)).unwrap();
    assert_eq!(report.status, CacheStatus::Miss);
    assert!(report.problem.is_some_and(|p| p.contains("not stored")));
    // The fallback's mesh is the uncached one, nodes, cells and parts to the bit.
    assert!(mesh.num_cells() > 0);
    assert_identical(&generate(&request).unwrap(), &mesh);
}
