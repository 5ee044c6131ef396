//! Mortar coupling of two bodies on non-matching meshes (src/contact/mortar): transfer of
//! constant and linear fields, the contact patch test, matching meshes, gaps, coverage, curved
//! P2 interfaces, sides from mesh parts. Run with `cargo test --release --test mortar`
//! (`-- --nocapture` prints the measured errors).
use signorini::contact::mortar::{MortarCoupling, MortarOptions, MortarSide, UncoveredNodes};
use signorini::mesh::structured::rectangle;
use signorini::mesh::Order;
use signorini::Error;

/// A small deterministic generator (xorshift64*), for irregular node positions.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `edges + 1` increasing parameters from `0` to `length` exactly, spacings random in
/// `[0.4, 1.6]` times the mean.
fn irregular(edges: usize, length: f64, seed: u64) -> Vec<f64> {
    let mut rng = Rng(seed);
    let steps: Vec<f64> = (0..edges).map(|_| 0.4 + 1.2 * rng.uniform()).collect();
    let total: f64 = steps.iter().sum();
    let mut t = vec![0.0];
    let mut acc = 0.0;
    for s in &steps[..edges - 1] {
        acc += s;
        t.push(length * acc / total);
    }
    t.push(length);
    t
}

/// The straight interface: points `O + t d`. The slave body lies on the right of `d`, so its
/// outward normal is `d` rotated by +90°; the master body on the left.
const ORIGIN: [f64; 2] = [0.3, -0.2];
const ANGLE: f64 = 0.4;
fn direction() -> [f64; 2] {
    [ANGLE.cos(), ANGLE.sin()]
}
fn slave_normal() -> [f64; 2] {
    let d = direction();
    [-d[1], d[0]]
}
fn on_line(t: f64, offset: f64) -> [f64; 2] {
    let (d, n) = (direction(), slave_normal());
    [ORIGIN[0] + t * d[0] + offset * n[0], ORIGIN[1] + t * d[1] + offset * n[1]]
}

/// A straight side through the points at parameters `ts` (shifted by `offset` along the slave
/// normal), appended to `positions`. `slave`: edges run against `d` (body on the right of `d`);
/// master: along `d`. P2 mid nodes at the middle of the edges.
fn straight_side(positions: &mut Vec<[f64; 2]>, ts: &[f64], order: Order, slave: bool, offset: f64) -> MortarSide {
    let first = positions.len();
    positions.extend(ts.iter().map(|&t| on_line(t, offset)));
    let mut edges = Vec::new();
    for k in 0..ts.len() - 1 {
        let (a, b) = (first + k, first + k + 1);
        let mut edge = if slave { vec![b, a] } else { vec![a, b] };
        if order == Order::P2 {
            edge.push(positions.len());
            positions.push(on_line(0.5 * (ts[k] + ts[k + 1]), offset));
        }
        edges.push(edge);
    }
    MortarSide::new(if slave { "slave" } else { "master" }, order, edges, positions).unwrap()
}

/// `∫ φ_k ds` of every node of a straight side: `L/2, L/2` per P1 edge, `L/6, L/6, 2L/3` per P2 edge.
fn consistent_weights(side: &MortarSide, positions: &[[f64; 2]]) -> Vec<(usize, f64)> {
    let mut w: Vec<(usize, f64)> = side.nodes().iter().map(|&k| (k, 0.0)).collect();
    for edge in side.edges() {
        let (a, b) = (positions[edge[0]], positions[edge[1]]);
        let l = (b[0] - a[0]).hypot(b[1] - a[1]);
        let share: &[f64] = if edge.len() == 2 { &[0.5, 0.5] } else { &[1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0] };
        for (&k, s) in edge.iter().zip(share) {
            w.iter_mut().find(|e| e.0 == k).unwrap().1 += s * l;
        }
    }
    w
}

const ORDERS: [(Order, Order); 4] =
    [(Order::P1, Order::P1), (Order::P1, Order::P2), (Order::P2, Order::P1), (Order::P2, Order::P2)];

/// Slave and master edge counts: master finer, slave finer, nearly equal, and edges of one
/// side 20 times longer than the other's.
const COUNTS: [(usize, usize); 5] = [(7, 11), (13, 5), (9, 8), (60, 3), (3, 60)];

/// The two sides of a straight interface of length 1.7, irregular, at distance `offset`.
fn straight_pair(so: Order, mo: Order, ns: usize, nm: usize, offset: f64) -> (Vec<[f64; 2]>, MortarSide, MortarSide) {
    let mut positions = Vec::new();
    let slave = straight_side(&mut positions, &irregular(ns, 1.7, 17 + ns as u64), so, true, 0.0);
    let master = straight_side(&mut positions, &irregular(nm, 1.7, 91 + nm as u64), mo, false, offset);
    (positions, slave, master)
}

fn couple(slave: &MortarSide, master: &MortarSide) -> MortarCoupling {
    let c = MortarCoupling::new(slave, master, &MortarOptions::default()).unwrap();
    assert!(c.uncovered.is_empty() && c.partly_covered.is_empty(), "{:?} {:?}", c.uncovered, c.partly_covered);
    assert_eq!(c.nodes, slave.nodes(), "every slave node is a contact point");
    c
}

#[test]
fn constants_and_linear_fields_transfer_exactly_on_irregular_straight_interfaces() {
    let mut worst = (0.0f64, 0.0f64);
    for (so, mo) in ORDERS {
        for (ns, nm) in COUNTS {
            let (x, slave, master) = straight_pair(so, mo, ns, nm, 0.0);
            let c = couple(&slave, &master);
            for i in 0..c.points() {
                let constant = (c.coverage(i) - 1.0).abs();
                let mut image = [0.0; 2];
                for (j, m) in c.transfer(i) {
                    image[0] += m * x[j][0];
                    image[1] += m * x[j][1];
                }
                let xi = x[c.nodes[i]];
                let linear = (image[0] - xi[0]).hypot(image[1] - xi[1]);
                assert!(constant <= 1e-12, "{so:?}-{mo:?} {ns}/{nm}: point {i}: Σ M/D − 1 = {constant:e}");
                assert!(linear <= 1e-12, "{so:?}-{mo:?} {ns}/{nm}: point {i}: |Σ (M/D) x_m − x_s| = {linear:e}");
                worst = (worst.0.max(constant), worst.1.max(linear));
                // The slave frame is the straight line's.
                let n = slave_normal();
                assert!((c.normal[i][0] - n[0]).abs() <= 1e-14 && (c.normal[i][1] - n[1]).abs() <= 1e-14);
                assert_eq!(c.tangent[i], [-c.normal[i][1], c.normal[i][0]]);
            }
        }
    }
    println!("straight interfaces: max |Σ M/D − 1| = {:.2e}, max |Σ (M/D) x_m − x_s| = {:.2e}", worst.0, worst.1);
}

#[test]
fn uniform_pressure_is_transmitted_exactly() {
    let p = 3.7;
    let n = slave_normal();
    let mut worst = 0.0f64;
    for (so, mo) in ORDERS {
        for (ns, nm) in COUNTS {
            let (x, slave, master) = straight_pair(so, mo, ns, nm, 0.0);
            let c = couple(&slave, &master);
            // rN_i = −p D_i: compression, nodal forces.
            let r: Vec<f64> = c.weight.iter().flat_map(|d| [-p * d, 0.0]).collect();
            let mut f = vec![0.0; 2 * x.len()];
            c.scatter_add(&r, &mut f);
            let scale = p * 1.7;
            // Slave: −p ∫φ_i ds n (pressing the slave body inwards); master: +p ∫φ_j ds n.
            for (side, sign) in [(&slave, -1.0), (&master, 1.0)] {
                for (k, w) in consistent_weights(side, &x) {
                    for comp in 0..2 {
                        let err = (f[2 * k + comp] - sign * p * w * n[comp]).abs() / scale;
                        assert!(err <= 1e-12, "{so:?}-{mo:?} {ns}/{nm}: node {k} of {}: error {err:e}", side.name());
                        worst = worst.max(err);
                    }
                }
            }
            // D_i is the consistent weight itself.
            for (k, w) in consistent_weights(&slave, &x) {
                let i = c.nodes.binary_search(&k).unwrap();
                assert!((c.weight[i] - w).abs() <= 1e-14 * 1.7, "D_{k} = {} != {w}", c.weight[i]);
            }
        }
    }
    println!("patch test: max nodal force error / (p L) = {worst:.2e}");
}

#[test]
fn rows_gather_and_scatter_are_b_and_its_transpose() {
    let (x, slave, master) = straight_pair(Order::P2, Order::P1, 6, 9, 0.05);
    let c = couple(&slave, &master);
    let mut rng = Rng(5);
    let u: Vec<f64> = (0..2 * x.len()).map(|_| rng.uniform() - 0.5).collect();
    let r: Vec<f64> = (0..2 * c.points()).map(|_| rng.uniform() - 0.5).collect();
    let bu = c.gather(&u);
    let mut btr = vec![0.0; u.len()];
    c.scatter_add(&r, &mut btr);
    let mut from_rows = vec![0.0; u.len()];
    for (j, rj) in r.iter().enumerate() {
        let row = c.b_row(j);
        assert!(row.windows(2).all(|w| w[0].0 < w[1].0), "row {j} not sorted by dof: {row:?}");
        let value: f64 = row.iter().map(|&(dof, v)| v * u[dof]).sum();
        assert!((value - bu[j]).abs() <= 1e-14, "row {j}: {value} != {}", bu[j]);
        row.iter().for_each(|&(dof, v)| from_rows[dof] += v * rj);
    }
    for (a, b) in btr.iter().zip(&from_rows) {
        assert!((a - b).abs() <= 1e-14);
    }
    // A rigid translation of both bodies has no relative displacement.
    let shift: Vec<f64> = (0..2 * x.len()).map(|d| if d % 2 == 0 { 0.3 } else { -1.1 }).collect();
    assert!(c.gather(&shift).iter().all(|v| v.abs() <= 1e-13));
}

#[test]
fn matching_meshes_reduce_to_node_to_node() {
    let mut worst = 0.0f64;
    for order in [Order::P1, Order::P2] {
        let ts = irregular(10, 1.7, 3);
        let mut x = Vec::new();
        let slave = straight_side(&mut x, &ts, order, true, 0.0);
        let master = straight_side(&mut x, &ts, order, false, 0.0);
        let c = couple(&slave, &master);
        for i in 0..c.points() {
            let xi = x[c.nodes[i]];
            // The partner: the master node at the same position.
            let partner = *master.nodes().iter().find(|&&j| x[j] == xi).expect("a master node at the same place");
            for (j, m) in c.transfer(i) {
                let expected = if j == partner { 1.0 } else { 0.0 };
                assert!((m - expected).abs() <= 1e-13, "{order:?}: M_{i}{j}/D_{i} = {m:e}, expected {expected}");
                worst = worst.max((m - expected).abs());
            }
            assert!(c.transfer(i).any(|(j, _)| j == partner));
            assert!(c.gap[i].abs() <= 1e-13, "{order:?}: g0_{i} = {:e}", c.gap[i]);
        }
    }
    println!("matching meshes: max |M_ij/D_i − δ| = {worst:.2e}");
}

#[test]
fn parallel_sides_have_the_distance_as_gap() {
    let mut worst = 0.0f64;
    for (so, mo) in ORDERS {
        for d in [0.37, 0.0, -0.02] {
            let (x, slave, master) = straight_pair(so, mo, 8, 13, d);
            let c = couple(&slave, &master);
            for (i, g) in c.gap.iter().enumerate() {
                assert!((g - d).abs() <= 1e-12, "{so:?}-{mo:?} d = {d}: g0_{i} = {g}");
                worst = worst.max((g - d).abs());
            }
            // The constraint row of the positions themselves gives the same gap: Σ (M/D) x_m − x_s = d n.
            let u: Vec<f64> = x.iter().flat_map(|p| [-p[0], -p[1]]).collect();
            for (i, un) in c.gather(&u).chunks(2).enumerate() {
                assert!((un[0] - c.gap[i]).abs() <= 1e-12 && un[1].abs() <= 1e-12, "point {i}: {un:?}");
            }
        }
    }
    // Touching sides far from the origin (round-off relative to the coordinates).
    println!("parallel sides: max |g0 − d| = {worst:.2e}");
}

#[test]
fn uncovered_slave_nodes_are_reported() {
    // Slave side from t = 0 to 2.2, master from t = 0.5 to 1.7: slave nodes with t < 0.5 or
    // t > 1.7 are uncovered.
    for (so, mo) in ORDERS {
        let mut x = Vec::new();
        let ts = irregular(12, 2.2, 8);
        let slave = straight_side(&mut x, &ts, so, true, 0.0);
        let tm: Vec<f64> = irregular(7, 1.2, 4).iter().map(|t| t + 0.5).collect();
        let master = straight_side(&mut x, &tm, mo, false, 0.1);
        let parameter = |k: usize| {
            let d = direction();
            (x[k][0] - ORIGIN[0]) * d[0] + (x[k][1] - ORIGIN[1]) * d[1]
        };
        let outside: Vec<usize> =
            slave.nodes().iter().copied().filter(|&k| parameter(k) < 0.5 || parameter(k) > 1.7).collect();
        assert!(outside.len() >= 4);

        let err = MortarCoupling::new(&slave, &master, &MortarOptions::default()).unwrap_err();
        let Error::Formulation { message, .. } = err else { panic!("expected Error::Formulation, got {err:?}") };
        let first = outside[0];
        assert!(
            message.contains(&format!("slave node {first} at ({:?}, {:?})", x[first][0], x[first][1])),
            "{message}"
        );
        assert!(message.contains(&format!("and {} more", outside.len() - 1)), "{message}");

        let options = MortarOptions { uncovered: UncoveredNodes::LeaveOut, ..Default::default() };
        let c = MortarCoupling::new(&slave, &master, &options).unwrap();
        let listed: Vec<usize> = c.uncovered.iter().map(|u| u.node).collect();
        assert_eq!(listed, outside, "{so:?}-{mo:?}");
        for u in &c.uncovered {
            assert_eq!(u.position, x[u.node]);
        }
        assert_eq!(c.points() + outside.len(), slave.nodes().len());
        // The covered nodes next to the master's ends have partly covered supports (ψ_i changes
        // sign, so the faced part of ∫ψ_i may exceed ∫φ_i as well); weighed by that faced part,
        // they transfer constants exactly and have the gap 0.1 like every other point: a rigid
        // translation of both sides moves no point's uN, so a master end cannot sink into the
        // slave side by a share of its displacement.
        assert!(!c.partly_covered.is_empty());
        for pc in &c.partly_covered {
            assert!((pc.coverage - 1.0).abs() > 1e-6 && pc.coverage > 0.0, "{pc:?}");
            let i = c.nodes.iter().position(|&k| k == pc.node).unwrap();
            let full: f64 = slave_weight(&slave, &x, pc.node);
            assert!((c.weight[i] - pc.coverage * full).abs() <= 1e-12 * full, "{pc:?}: {}", c.weight[i]);
        }
        let shift = [0.37, -1.3];
        let u: Vec<f64> = (0..x.len()).flat_map(|_| shift).collect();
        for i in 0..c.points() {
            assert!((c.coverage(i) - 1.0).abs() <= 1e-12, "{so:?}-{mo:?} point {i}: {}", c.coverage(i));
            assert!((c.gap[i] - 0.1).abs() <= 1e-12, "{so:?}-{mo:?} point {i}: {}", c.gap[i]);
        }
        assert!(c.gather(&u).iter().all(|v| v.abs() <= 1e-12), "{:?}", c.gather(&u));
    }
}

/// `∫ φ_k ds` over the slave side's straight edges (exact: `L/2` at a P1 node, `L/6` at a P2
/// vertex, `2L/3` at a P2 mid node).
fn slave_weight(side: &MortarSide, x: &[[f64; 2]], k: usize) -> f64 {
    let mut w = 0.0;
    for e in side.edges() {
        let l = (x[e[1]][0] - x[e[0]][0]).hypot(x[e[1]][1] - x[e[0]][1]);
        match e.iter().position(|&n| n == k) {
            Some(2) => w += 2.0 * l / 3.0,
            Some(_) if e.len() == 3 => w += l / 6.0,
            Some(_) => w += l / 2.0,
            None => {}
        }
    }
    w
}

#[test]
fn max_distance_and_facing_decide_the_pairing() {
    // Two master sides at 0.1 and 0.6 above the slave: the nearest is paired. A master side
    // facing away (edges reversed) is never paired.
    let (mut x, slave, near) = straight_pair(Order::P1, Order::P2, 6, 5, 0.1);
    let far = straight_side(&mut x, &irregular(4, 1.7, 77), Order::P2, false, 0.6);
    let mut edges = near.edges().to_vec();
    edges.extend(far.edges().iter().cloned());
    let both = MortarSide::new("both", Order::P2, edges, &x).unwrap();
    let c = couple(&slave, &both);
    assert!(c.gap.iter().all(|g| (g - 0.1).abs() <= 1e-12), "{:?}", c.gap);
    assert!(c.mortar.iter().flatten().all(|(j, _)| near.nodes().contains(j)));

    let away: Vec<Vec<usize>> = near.edges().iter().map(|e| vec![e[1], e[0], e[2]]).collect();
    let away = MortarSide::new("away", Order::P2, away, &x).unwrap();
    assert!(matches!(MortarCoupling::new(&slave, &away, &MortarOptions::default()), Err(Error::Formulation { .. })));

    // Within 0.3 only the near side is a candidate; within 0.05 none is.
    let within = |d: f64| MortarOptions { max_distance: d, uncovered: UncoveredNodes::LeaveOut };
    let c3 = MortarCoupling::new(&slave, &both, &within(0.3)).unwrap();
    assert_eq!((&c3.nodes, c3.mortar.len()), (&c.nodes, c.mortar.len()));
    for i in 0..c.points() {
        assert!((c3.gap[i] - c.gap[i]).abs() <= 1e-14);
        assert_eq!(c3.mortar[i].len(), c.mortar[i].len());
        for (a, b) in c3.mortar[i].iter().zip(&c.mortar[i]) {
            assert!(a.0 == b.0 && (a.1 - b.1).abs() <= 1e-14, "{a:?} != {b:?}");
        }
    }
    // Within 0.05 no slave node is paired: every one is left out, listed as uncovered (the
    // caller decides what a pair without points means).
    let none = MortarCoupling::new(&slave, &both, &within(0.05)).unwrap();
    assert_eq!(none.points(), 0);
    assert_eq!(none.uncovered.iter().map(|u| u.node).collect::<Vec<_>>(), slave.nodes());
    assert!(matches!(MortarCoupling::new(&slave, &both, &within(0.0)), Err(Error::Usage(_))));
}

/// An arc of the circle of radius `r` around the origin from angle `a0` to `a1`, `edges`
/// edges with irregular angles, every node (P2 mid nodes included, at the middle angle) on the
/// circle. The slave body is inside the disc (edges counter-clockwise), the master outside
/// (clockwise).
#[allow(clippy::too_many_arguments)]
fn arc_side(
    x: &mut Vec<[f64; 2]>,
    order: Order,
    r: f64,
    a0: f64,
    a1: f64,
    edges: usize,
    seed: u64,
    slave: bool,
) -> MortarSide {
    let angles: Vec<f64> = irregular(edges, a1 - a0, seed).iter().map(|t| a0 + t).collect();
    let first = x.len();
    x.extend(angles.iter().map(|a| [r * a.cos(), r * a.sin()]));
    let mut list = Vec::new();
    for k in 0..edges {
        let (a, b) = (first + k, first + k + 1);
        let mut edge = if slave { vec![a, b] } else { vec![b, a] };
        if order == Order::P2 {
            let mid = 0.5 * (angles[k] + angles[k + 1]);
            edge.push(x.len());
            x.push([r * mid.cos(), r * mid.sin()]);
        }
        list.push(edge);
    }
    MortarSide::new(if slave { "inner arc" } else { "outer arc" }, order, list, x).unwrap()
}

/// Both sides on the unit circle from 0.2 to 1.9 rad, `6·2^level` slave and `10·2^level`
/// master edges: `(max |Σ M/D − 1|, max |Σ (M/D) x_m − x_s|, max |g0|, largest edge angle h)`.
fn circle_errors(so: Order, mo: Order, level: usize) -> (f64, f64, f64, f64) {
    let (ns, nm) = (6 << level, 10 << level);
    let mut x = Vec::new();
    let slave = arc_side(&mut x, so, 1.0, 0.2, 1.9, ns, 11, true);
    let master = arc_side(&mut x, mo, 1.0, 0.2, 1.9, nm, 29, false);
    let c = couple(&slave, &master);
    // The largest edge angle of either side.
    let largest = |n: usize, seed: u64| irregular(n, 1.7, seed).windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    let h = largest(ns, 11).max(largest(nm, 29));
    let (mut constant, mut linear, mut gap) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..c.points() {
        constant = constant.max((c.coverage(i) - 1.0).abs());
        let mut image = [0.0; 2];
        for (j, m) in c.transfer(i) {
            image[0] += m * x[j][0];
            image[1] += m * x[j][1];
        }
        let xi = x[c.nodes[i]];
        linear = linear.max((image[0] - xi[0]).hypot(image[1] - xi[1]));
        gap = gap.max(c.gap[i].abs());
        // The nodal normal is radial up to the discretization of the circle (at the end node
        // of a P1 side, the chord's normal: half the edge angle off).
        let radial = [xi[0] / xi[0].hypot(xi[1]), xi[1] / xi[0].hypot(xi[1])];
        assert!((c.normal[i][0] - radial[0]).hypot(c.normal[i][1] - radial[1]) <= 0.5 * h);
    }
    (constant, linear, gap, h)
}

#[test]
fn curved_interfaces_transfer_constants_exactly_and_linear_fields_to_the_geometric_error() {
    // Constants: exact (1e-12) for every pair of orders, since Σ ψ_i = 1 and Σ φ_j^m = 1
    // pointwise and the dual basis is built with the mortar quadrature. Linear fields: the
    // transfer error of node i is (1/D_i) ∫ ψ_i (x_m − x_s) ds, the weighted distance between
    // the two discrete curves along the normal, i.e. the geometric error: P2–P2, both curves
    // parabolic arcs through three points of the circle (mid node at the middle angle), whose
    // normal distance to the circle is O(h⁴) (measured 1.5e-3 h⁴), asserted ≤ 3e-3 h⁴; a P1
    // side, a polygon inscribed in the circle (sagitta h²/8), asserted ≤ h²/8 (measured
    // 0.03–0.08 h²); h the largest edge angle of the two sides, and the order checked over
    // two halvings of h. The gap g0 is of the same size.
    for (so, mo) in ORDERS {
        let quadratic = so == Order::P2 && mo == Order::P2;
        let mut errors = Vec::new();
        for level in 0..3 {
            let (constant, linear, gap, h) = circle_errors(so, mo, level);
            println!(
                "circle {so:?}-{mo:?}, level {level} (h ≤ {h:.3}): max |Σ M/D − 1| = {constant:.2e}, \
                 max |Σ (M/D) x_m − x_s| = {linear:.2e} = {:.2e} h^{}, max |g0| = {gap:.2e}",
                linear / h.powi(if quadratic { 4 } else { 2 }),
                if quadratic { 4 } else { 2 }
            );
            let bound = if quadratic { 3e-3 * h.powi(4) } else { h * h / 8.0 };
            assert!(constant <= 1e-12, "{so:?}-{mo:?} level {level}: {constant:e}");
            assert!(linear <= bound, "{so:?}-{mo:?} level {level}: {linear:e} > {bound:e}");
            assert!(gap <= bound, "{so:?}-{mo:?} level {level}: {gap:e} > {bound:e}");
            errors.push(linear / h.powi(if quadratic { 4 } else { 2 }));
        }
        // The order: e / h^p stays within a factor 2 over a fourfold refinement (one order
        // less would multiply it by about 4).
        let (lo, hi) = errors.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &e| (lo.min(e), hi.max(e)));
        assert!(hi <= 2.0 * lo, "{so:?}-{mo:?}: e / h^p = {errors:?} is not bounded");
    }
}

#[test]
fn sides_from_mesh_parts_of_two_rectangles() {
    // Lower body [0, 1] × [0, 1] P1 with 5 cells across, upper body [0, 1] × [1, 1.6] P2 with 3:
    // the lower body's "top" is the slave side, the upper body's "bottom" the master side, its
    // nodes numbered after the lower body's.
    let lower = rectangle([0.0, 0.0], [1.0, 1.0], 5, 4, Order::P1).unwrap();
    let upper = rectangle([0.0, 1.0], [1.0, 0.6], 3, 2, Order::P2).unwrap();
    let offset = lower.num_nodes();
    let slave = MortarSide::from_mesh(&lower, lower.require_group("top", 1).unwrap()).unwrap();
    let master =
        MortarSide::from_mesh(&upper, upper.require_group("bottom", 1).unwrap()).unwrap().with_node_offset(offset);
    let c = couple(&slave, &master);
    assert_eq!(c.points(), 6);
    let mut x = lower.nodes.clone();
    x.extend(&upper.nodes);
    for i in 0..c.points() {
        assert!((c.normal[i][0]).abs() <= 1e-15 && (c.normal[i][1] - 1.0).abs() <= 1e-15);
        assert!((c.coverage(i) - 1.0).abs() <= 1e-12);
        assert!(c.gap[i].abs() <= 1e-13);
        assert!(c.transfer(i).all(|(j, _)| j >= offset && upper.nodes[j - offset][1] == 1.0));
        let xi = x[c.nodes[i]];
        let image: f64 = c.transfer(i).map(|(j, m)| m * x[j][0]).sum();
        assert!((image - xi[0]).abs() <= 1e-13, "point {i}: {image} != {}", xi[0]);
        // D_i: 0.1 at the ends, 0.2 inside.
        let expected = if xi[0] == 0.0 || xi[0] == 1.0 { 0.1 } else { 0.2 };
        assert!((c.weight[i] - expected).abs() <= 1e-15);
    }
    assert!(matches!(MortarSide::from_mesh(&lower, lower.require_group("domain", 2).unwrap()), Err(Error::Usage(_))));
}

#[test]
fn malformed_sides_are_rejected() {
    let x = vec![[0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [f64::NAN, 0.0]];
    let usage = |r: signorini::Result<MortarSide>| match r {
        Err(Error::Usage(m)) => m,
        other => panic!("expected Error::Usage, got {other:?}"),
    };
    assert!(usage(MortarSide::new("s", Order::P2, vec![vec![0, 1]], &x)).contains("edge 0 has 2 nodes"));
    assert!(usage(MortarSide::new("s", Order::P1, vec![vec![0, 7]], &x)).contains("node 7 has no position"));
    assert!(usage(MortarSide::new("s", Order::P1, vec![vec![0, 0]], &x)).contains("repeats a node"));
    assert!(usage(MortarSide::new("s", Order::P1, vec![vec![0, 3]], &x)).contains("non-finite"));
    assert!(usage(MortarSide::new("s", Order::P1, vec![], &x)).contains("no edges"));
    // A P2 edge whose mid node sits on an end vertex folds on itself.
    let folded = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]];
    assert!(matches!(MortarSide::new("s", Order::P2, vec![vec![0, 1, 2]], &folded), Err(Error::Mesh { .. })));
    // Edges of opposite orientations through a node: its normal is undefined.
    let y = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let side = MortarSide::new("s", Order::P1, vec![vec![0, 1], vec![2, 1]], &y).unwrap();
    assert!(matches!(side.nodal_normals(), Err(Error::Mesh { .. })));
}

#[test]
fn long_interfaces_stay_exact() {
    // 1500 slave P2 edges against 2300 master P1 edges (every pair is examined: the search is
    // quadratic in the number of edges, without a spatial index).
    let start = std::time::Instant::now();
    let (x, slave, master) = straight_pair(Order::P2, Order::P1, 1500, 2300, 0.01);
    let c = couple(&slave, &master);
    let elapsed = start.elapsed();
    let (mut constant, mut gap, mut linear) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..c.points() {
        constant = constant.max((c.coverage(i) - 1.0).abs());
        gap = gap.max((c.gap[i] - 0.01).abs());
        let image: f64 = c.transfer(i).map(|(j, m)| m * x[j][0]).sum();
        linear = linear.max((image - x[c.nodes[i]][0] - 0.01 * slave_normal()[0]).abs());
    }
    println!(
        "long interface: {} points in {elapsed:.2?}, max |Σ M/D − 1| = {constant:.2e}, max |g0 − d| = {gap:.2e}, \
         max |Σ (M/D) x_m − x_s − d n| = {linear:.2e}",
        c.points()
    );
    assert!(constant <= 1e-12 && gap <= 1e-12 && linear <= 1e-12);
}

/// A side along the polyline `corners`, with irregular edges on each straight piece (a node at
/// every corner); slave edges run against the polyline, master edges along it.
fn polyline_side(
    x: &mut Vec<[f64; 2]>,
    corners: &[[f64; 2]],
    per_piece: usize,
    order: Order,
    seed: u64,
    slave: bool,
) -> MortarSide {
    let mut chain = vec![x.len()];
    x.push(corners[0]);
    for (p, w) in corners.windows(2).enumerate() {
        let ts = irregular(per_piece + p, 1.0, seed + p as u64);
        for &t in &ts[1..ts.len() - 1] {
            chain.push(x.len());
            x.push([w[0][0] + t * (w[1][0] - w[0][0]), w[0][1] + t * (w[1][1] - w[0][1])]);
        }
        chain.push(x.len());
        x.push(w[1]);
    }
    let mut edges = Vec::new();
    for k in chain.windows(2) {
        let mut edge = if slave { vec![k[1], k[0]] } else { vec![k[0], k[1]] };
        if order == Order::P2 {
            edge.push(x.len());
            x.push([0.5 * (x[k[0]][0] + x[k[1]][0]), 0.5 * (x[k[0]][1] + x[k[1]][1])]);
        }
        edges.push(edge);
    }
    MortarSide::new(if slave { "slave" } else { "master" }, order, edges, x).unwrap()
}

#[test]
fn kinked_interfaces_transfer_exactly_through_their_corners() {
    // Both sides on the polyline (0, 0) -> (1, 0) -> (1.6, 0.7) -> (2.4, 0.5) (a left and a right
    // turn), different irregular meshes with a node at each corner. The slave normal field turns
    // continuously at the corners, and every slave point lies on the master curve, so it is
    // paired with itself: constants and linear fields transfer exactly and g0 = 0, corners
    // included.
    let corners = [[0.0, 0.0], [1.0, 0.0], [1.6, 0.7], [2.4, 0.5]];
    let mut worst = 0.0f64;
    for (so, mo) in ORDERS {
        let mut x = Vec::new();
        let slave = polyline_side(&mut x, &corners, 4, so, 3, true);
        let master = polyline_side(&mut x, &corners, 7, mo, 40, false);
        let c = couple(&slave, &master);
        for i in 0..c.points() {
            let mut image = [0.0; 2];
            for (j, m) in c.transfer(i) {
                image[0] += m * x[j][0];
                image[1] += m * x[j][1];
            }
            let xi = x[c.nodes[i]];
            let errors = [(c.coverage(i) - 1.0).abs(), (image[0] - xi[0]).hypot(image[1] - xi[1]), c.gap[i].abs()];
            assert!(errors.iter().all(|&e| e <= 1e-12), "{so:?}-{mo:?}: point {i} at {xi:?}: {errors:?}");
            worst = errors.iter().fold(worst, |w, &e| w.max(e));
        }
        // The corner nodes' normals bisect the two pieces' normals.
        let i = c.nodes.iter().position(|&k| x[k] == [1.0, 0.0]).unwrap();
        let expected = {
            let (a, b) = ([0.0, 1.0], [-0.7 / 0.85f64.sqrt(), 0.6 / 0.85f64.sqrt()]);
            let s = [a[0] + b[0], a[1] + b[1]];
            [s[0] / s[0].hypot(s[1]), s[1] / s[0].hypot(s[1])]
        };
        assert!((c.normal[i][0] - expected[0]).hypot(c.normal[i][1] - expected[1]) <= 1e-14, "{:?}", c.normal[i]);
    }
    println!("kinked interface: worst of |Σ M/D − 1|, |Σ (M/D) x_m − x_s|, |g0| = {worst:.2e}");
}

// ---- axisymmetry (issue 27) -------------------------------------------------------------------

/// A side on the line `z = offset` through the radii `rs`, measured in axisymmetry: slave edges
/// run towards the axis (body below, outward normal +z), master edges away from it (body above).
fn axisymmetric_side(positions: &mut Vec<[f64; 2]>, rs: &[f64], order: Order, slave: bool, offset: f64) -> MortarSide {
    let first = positions.len();
    positions.extend(rs.iter().map(|&r| [r, offset]));
    let mut edges = Vec::new();
    for k in 0..rs.len() - 1 {
        let (a, b) = (first + k, first + k + 1);
        let mut edge = if slave { vec![b, a] } else { vec![a, b] };
        if order == Order::P2 {
            edge.push(positions.len());
            positions.push([0.5 * (rs[k] + rs[k + 1]), offset]);
        }
        edges.push(edge);
    }
    MortarSide::new(if slave { "slave" } else { "master" }, order, edges, positions)
        .unwrap()
        .with_measure(signorini::mesh::Measure::Axisymmetric)
}

/// `∫ φ_k 2π r ds` of every node of a straight side on `z = const`, in closed form: on an edge
/// `r(s) = r0 + (r1 − r0) s`, `∫ φ_a r ds = r0 ∫ φ_a + (r1 − r0) ∫ φ_a s`, with
/// `(∫ φ, ∫ φ s)` = (1/2, 1/6), (1/2, 1/3) for P1 and (1/6, 0), (1/6, 1/6), (2/3, 1/3) for P2.
fn axisymmetric_weights(side: &MortarSide, positions: &[[f64; 2]]) -> Vec<(usize, f64)> {
    let mut w: Vec<(usize, f64)> = side.nodes().iter().map(|&k| (k, 0.0)).collect();
    for edge in side.edges() {
        let (r0, r1) = (positions[edge[0]][0], positions[edge[1]][0]);
        let l = (r1 - r0).abs();
        let moments: &[(f64, f64)] = if edge.len() == 2 {
            &[(0.5, 1.0 / 6.0), (0.5, 1.0 / 3.0)]
        } else {
            &[(1.0 / 6.0, 0.0), (1.0 / 6.0, 1.0 / 6.0), (2.0 / 3.0, 1.0 / 3.0)]
        };
        for (&k, &(m0, m1)) in edge.iter().zip(moments) {
            w.iter_mut().find(|e| e.0 == k).unwrap().1 += 2.0 * std::f64::consts::PI * l * (r0 * m0 + (r1 - r0) * m1);
        }
    }
    w
}

/// On a straight interface `z = 0` of a body of revolution, from the axis (r = 0) or from
/// r = 0.4, out to r = 1.7, irregular non-matching sides of every pair of orders:
/// `D_i = ∫ φ_i 2π r ds` in closed form (0 exactly at a P2 slave vertex on the axis), constants
/// and linear fields transfer exactly (the node on the axis by its node-to-segment row), a
/// parallel offset `d` is the gap of every point, and a uniform pressure `p` (`rN_i = −p D_i`)
/// gives both sides their consistent ring loads `p ∫ φ_k 2π r ds`: the patch test.
#[test]
fn axisymmetric_weights_transfer_and_patch_test_are_exact() {
    let p = 3.7;
    let mut worst = 0.0f64;
    for r0 in [0.0, 0.4] {
        for (so, mo) in ORDERS {
            for (ns, nm) in [(7, 11), (13, 5), (9, 8)] {
                let mut x = Vec::new();
                let rs =
                    |n: usize, seed: u64| irregular(n, 1.7 - r0, seed).iter().map(|t| r0 + t).collect::<Vec<f64>>();
                let slave = axisymmetric_side(&mut x, &rs(ns, 17 + ns as u64), so, true, 0.0);
                let master = axisymmetric_side(&mut x, &rs(nm, 91 + nm as u64), mo, false, 0.0);
                let what = format!("r0 = {r0}, {so:?}-{mo:?} {ns}/{nm}");
                let c = couple(&slave, &master);
                let scale = 2.0 * std::f64::consts::PI * 1.7 * 1.7;
                let axis_vertex = r0 == 0.0 && so == Order::P2;
                for (k, w) in axisymmetric_weights(&slave, &x) {
                    let i = c.nodes.binary_search(&k).unwrap();
                    let expected = if axis_vertex && x[k][0] == 0.0 { 0.0 } else { w };
                    assert!((c.weight[i] - expected).abs() <= 1e-13 * scale, "{what}: D_{k} = {} != {w}", c.weight[i]);
                }
                assert_eq!(c.axis_pressure.len(), usize::from(axis_vertex), "{what}: {:?}", c.axis_pressure);
                if let Some(axis) = c.axis_pressure.first() {
                    // The even extrapolation from the mid node (r = L/2) and the far vertex (L).
                    assert!((axis.from[0].1 - 4.0 / 3.0).abs() < 1e-12 && (axis.from[1].1 + 1.0 / 3.0).abs() < 1e-12);
                }
                for i in 0..c.points() {
                    let mut image = [0.0; 2];
                    for (j, m) in c.transfer(i) {
                        image[0] += m * x[j][0];
                        image[1] += m * x[j][1];
                    }
                    let xi = x[c.nodes[i]];
                    let error = (c.coverage(i) - 1.0).abs().max((image[0] - xi[0]).hypot(image[1] - xi[1]));
                    assert!(error <= 1e-12, "{what}: point {i} at {xi:?}: transfer error {error:e}");
                    assert_eq!(c.normal[i], [0.0, 1.0], "{what}");
                }
                let r: Vec<f64> = c.weight.iter().flat_map(|d| [-p * d, 0.0]).collect();
                let mut f = vec![0.0; 2 * x.len()];
                c.scatter_add(&r, &mut f);
                for (side, sign) in [(&slave, -1.0), (&master, 1.0)] {
                    for (k, w) in axisymmetric_weights(side, &x) {
                        let err = (f[2 * k] - 0.0).abs().max((f[2 * k + 1] - sign * p * w).abs()) / (p * scale);
                        assert!(err <= 1e-12, "{what}: node {k} of {}: nodal force error {err:e}", side.name());
                        worst = worst.max(err);
                    }
                }
                // Parallel sides at distance d: every point's gap is d.
                let mut y = Vec::new();
                let d = 0.03;
                let slave = axisymmetric_side(&mut y, &rs(ns, 17 + ns as u64), so, true, 0.0);
                let master = axisymmetric_side(&mut y, &rs(nm, 91 + nm as u64), mo, false, d);
                let c = couple(&slave, &master);
                for (i, g) in c.gap.iter().enumerate() {
                    assert!((g - d).abs() <= 1e-13, "{what}: gap of point {i}: {g} != {d}");
                }
            }
        }
    }
    println!("axisymmetric patch test: max nodal force error / (p 2π R²) = {worst:.2e}");
}

/// A plane side against an axisymmetric one is refused by name.
#[test]
fn axisymmetric_and_plane_sides_do_not_mix() {
    let mut x = Vec::new();
    let slave = axisymmetric_side(&mut x, &[0.0, 0.5, 1.0], Order::P1, true, 0.0);
    let master = axisymmetric_side(&mut x, &[0.0, 1.0], Order::P1, false, 0.0).with_measure(Default::default());
    match MortarCoupling::new(&slave, &master, &MortarOptions::default()) {
        Err(Error::Usage(m)) => {
            assert!(m.contains("'slave'") && m.contains("'master'") && m.contains("same measure"), "{m}")
        }
        other => panic!("expected a usage error, got {other:?}"),
    }
}
