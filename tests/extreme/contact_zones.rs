//! Contact zones and the peak pressure: two zones under a dip, the Hertz width along the arc.

use crate::edit::Edit;

use crate::{answer, Block};
use std::path::Path;

#[test]
fn contact_closed_in_two_places_gives_two_zones_and_the_peak() {
    // The block on a plane with a 2 cm deep dip under its middle: it touches on both sides.
    let b = Block { contact: "friction = \"none\"".into(), mesher: "structured", cell: 0.1, ..Default::default() };
    let scene = b.toml().edit(
        "obstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]",
        "obstacle = \"polyline\"\npoints = [[-1.0, 0.0], [0.75, 0.0], [0.85, -0.02], [1.15, -0.02], [1.25, 0.0], [3.0, 0.0]]",
    );
    let (_, r) = answer("two_zones", &scene, &[]);
    let zones = r["contact"]["zones"].as_array().unwrap();
    assert_eq!(zones.len(), 2, "{}", r["contact"]["zones"]);
    let (a, c) = (&zones[0], &zones[1]);
    assert!(a["end"][0].as_f64().unwrap() <= 0.8 && c["start"][0].as_f64().unwrap() >= 1.2, "{zones:?}");
    assert!(a["extent"][1].as_f64().unwrap() < c["extent"][0].as_f64().unwrap());
    let peak = &r["contact"]["peak_pressure"];
    assert!(peak["pressure"].as_f64().unwrap() > 1e6, "the supports beside the dip carry more: {peak}");
}

#[test]
fn hertz_zone_is_the_contact_width_along_the_arc() {
    let scene =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/hertz.toml")).unwrap();
    let (_, r) = answer("hertz_zone", &scene, &[]);
    let (radius, young, nu, load) = (0.1f64, 210e9f64, 0.3f64, 4.5e7f64);
    let a = (4.0 * load * radius / (std::f64::consts::PI * young / (1.0 - nu * nu))).sqrt();
    let zones = r["contact"]["zones"].as_array().unwrap();
    assert_eq!(zones.len(), 1);
    let width = zones[0]["extent"][1].as_f64().unwrap() - zones[0]["extent"][0].as_f64().unwrap();
    assert!((width - 2.0 * a).abs() < 0.03 * 2.0 * a, "zone width {width} vs 2a = {}", 2.0 * a);
    let peak = &r["contact"]["peak_pressure"];
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    assert!(
        (peak["pressure"].as_f64().unwrap() - p0).abs() < 0.01 * p0
            && peak["position"][0].as_f64().unwrap().abs() < 0.1 * a
    );
}
