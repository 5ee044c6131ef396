//! The condensed problem modified by interface laws (`interface_law::condensed`), against the
//! original equations solved independently: closed forms at one point, and on random SPD `W`
//! with 3–4 points an enumeration of every point's state (open/closed × stick/slip±), each a
//! linear system in `(u, r')` checked for its inequalities.
use nalgebra::{DMatrix, DVector};
use signorini::contact::{solve, CondensedProblem, ContactSolver, Delassus, FrictionLaw, SolverSettings};
use signorini::interface_law::condensed::{unify_friction, ModifiedProblem};
use signorini::interface_law::{PointFriction, PointModification};

fn tight() -> SolverSettings {
    SolverSettings { tolerance: 1e-12, max_iterations: 10_000, ..SolverSettings::default() }
}

/// Solve the modified problem: `(r, r', u)`.
fn solve_modified(base: &CondensedProblem, mods: &[PointModification]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let md = ModifiedProblem::new(base, mods, None).expect("modified problem");
    let contact_force = match md.problem() {
        Some(p) => md.expand(&solve(p, &ContactSolver::SemismoothNewton, &tight()).expect("solve").force),
        None => vec![0.0; 2 * base.points()],
    };
    let answer = md.answer(&contact_force);
    // The independent check on the answer's own displacement passes.
    let check = md.residuals_at(&answer.force, &answer.displacement).unwrap();
    assert!(check.is_acceptable(1e-9), "{check}");
    (answer.force, answer.contact_force, answer.displacement)
}

fn close(a: &[f64], b: &[f64], tol: f64, what: &str) {
    let scale = a.iter().chain(b).fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!((x - y).abs() <= tol * scale, "{what}: entry {k}: {x} vs {y} ({a:?} vs {b:?})");
    }
}

fn w2() -> DMatrix<f64> {
    DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0])
}

#[test]
fn one_point_series_compliance_closed_form() {
    // Frictionless, c_N = 0.5: closed on u' = u + c r: rN = −(uN_free − g0)/(W_NN + c_N).
    let base =
        CondensedProblem::new(Delassus::Dense(w2()), vec![0.3, 0.1], vec![0.1], FrictionLaw::None, None).unwrap();
    let md = PointModification { compliance: [0.5, 0.25], ..PointModification::plain(PointFriction::None) };
    let (r, rc, u) = solve_modified(&base, &[md]);
    let rn = -(0.3 - 0.1) / (2.0 + 0.5);
    close(&r, &[rn, 0.0], 1e-12, "force");
    close(&rc, &r, 1e-15, "r' = r in series");
    // u = W r + u_free penetrates by c |rN|: u' = g0.
    close(&u, &[2.0 * rn + 0.3, 0.5 * rn + 0.1], 1e-12, "displacement");
    assert!((u[0] + 0.5 * rn - 0.1).abs() < 1e-14);
}

#[test]
fn one_point_bonded_springs_closed_form() {
    // No unilateral contact: r = o − D (v + a), v = W r + z  ⇒  r = (I + D W)⁻¹ (o − D (z + a)).
    let (uf, g0) = ([0.3, -0.2], 0.05);
    let base = CondensedProblem::new(Delassus::Dense(w2()), uf.to_vec(), vec![g0], FrictionLaw::None, None).unwrap();
    let md = PointModification {
        compliance: [0.0; 2],
        stiffness: [3.0, 2.0],
        spring_offset: [0.02, 0.05],
        force_offset: [0.1, 0.0],
        contact: false,
        friction: PointFriction::None,
    };
    let (r, rc, u) = solve_modified(&base, &[md]);
    let d = DMatrix::from_diagonal(&DVector::from_vec(vec![3.0, 2.0]));
    let z = DVector::from_vec(vec![uf[0] - g0, uf[1]]);
    let a = DVector::from_vec(vec![0.02, 0.05]);
    let o = DVector::from_vec(vec![0.1, 0.0]);
    let rhs = &o - &d * (&z + &a);
    let expected = (DMatrix::identity(2, 2) + &d * w2()).lu().solve(&rhs).unwrap();
    close(&r, expected.as_slice(), 1e-13, "force");
    assert_eq!(rc, vec![0.0, 0.0]);
    let expected_u = w2() * &expected + DVector::from_vec(uf.to_vec());
    close(&u, expected_u.as_slice(), 1e-13, "displacement");
}

#[test]
fn a_wrong_displacement_fails_the_springs_check() {
    let base =
        CondensedProblem::new(Delassus::Dense(w2()), vec![0.3, -0.2], vec![0.0], FrictionLaw::None, None).unwrap();
    let md =
        PointModification { stiffness: [3.0, 2.0], contact: false, ..PointModification::plain(PointFriction::None) };
    let problem = ModifiedProblem::new(&base, &[md], None).unwrap();
    let answer = problem.answer(&[0.0, 0.0]);
    assert!(problem.residuals_at(&answer.force, &answer.displacement).unwrap().is_acceptable(1e-12));
    let mut wrong = answer.displacement.clone();
    wrong[1] += 1e-3;
    let check = problem.residuals_at(&answer.force, &wrong).unwrap();
    assert!(check.springs > 1e-4, "{check}");
}

#[test]
fn series_and_springs_on_one_component_are_refused() {
    let base =
        CondensedProblem::new(Delassus::Dense(w2()), vec![0.3, -0.2], vec![0.0], FrictionLaw::None, None).unwrap();
    let md = PointModification {
        compliance: [0.1, 0.0],
        stiffness: [3.0, 0.0],
        ..PointModification::plain(PointFriction::None)
    };
    let err = ModifiedProblem::new(&base, &[md], None).unwrap_err().to_string();
    assert!(err.contains("contact point 0") && err.contains("both a series compliance"), "{err}");
}

#[test]
fn mixed_tresca_and_coulomb_take_thresholds_from_the_last_contact_force() {
    let frictions = [PointFriction::Tresca(0.2), PointFriction::Coulomb(0.5), PointFriction::None];
    let last = [-1.0, 0.1, -3.0, 0.2, -2.0, 0.0];
    assert_eq!(unify_friction(&frictions, Some(&last)), FrictionLaw::Tresca { threshold: vec![0.2, 1.5, 0.0] });
    assert_eq!(unify_friction(&frictions, None), FrictionLaw::Tresca { threshold: vec![0.2, 0.0, 0.0] });
    assert_eq!(
        unify_friction(&[PointFriction::Coulomb(0.5), PointFriction::None], None),
        FrictionLaw::Coulomb { mu: vec![0.5, 0.0] }
    );
}

// ---------------------------------------------------------------------------------------------
// Random SPD W against an enumeration of the original equations
// ---------------------------------------------------------------------------------------------

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn random_w(m: usize, rng: &mut Lcg) -> DMatrix<f64> {
    let n = 2 * m;
    let a = DMatrix::from_fn(n, n, |_, _| rng.next());
    &a * a.transpose() / n as f64 + DMatrix::identity(n, n) * 0.3
}

/// The solution of the original equations (unknowns u and r', r eliminated) by enumerating the
/// points' states; panics unless exactly one state combination (up to equal answers) is
/// admissible. Returns `(r, r', u)`.
fn brute_force(
    w: &DMatrix<f64>,
    uf: &[f64],
    gap: &[f64],
    mods: &[PointModification],
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let m = gap.len();
    let n = 2 * m;
    let c: Vec<f64> = mods.iter().flat_map(|md| md.compliance).collect();
    let k: Vec<f64> = mods.iter().flat_map(|md| md.stiffness).collect();
    let a: Vec<f64> = mods.iter().flat_map(|md| md.spring_offset).collect();
    let o: Vec<f64> = mods.iter().flat_map(|md| md.force_offset).collect();
    let gt: Vec<f64> = (0..n).map(|j| if j % 2 == 0 { gap[j / 2] } else { 0.0 }).collect();
    let d = DMatrix::from_diagonal(&DVector::from_vec(k.clone()));
    // (I + W D) u − W r' = u_free + W (o + D g̃ − D a)
    let top = DMatrix::identity(n, n) + w * &d;
    let extra: DVector<f64> = DVector::from_fn(n, |j, _| o[j] + k[j] * (gt[j] - a[j]));
    let top_rhs = DVector::from_vec(uf.to_vec()) + w * extra;
    let combos = 6usize.pow(m as u32);
    let mut found: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = Vec::new();
    for combo in 0..combos {
        let mut mat = DMatrix::<f64>::zeros(2 * n, 2 * n);
        let mut rhs = DVector::<f64>::zeros(2 * n);
        mat.view_mut((0, 0), (n, n)).copy_from(&top);
        mat.view_mut((0, n), (n, n)).copy_from(&(-w));
        rhs.rows_mut(0, n).copy_from(&top_rhs);
        let state = |i: usize| (combo / 6usize.pow(i as u32)) % 6;
        let mut skip = false;
        for i in 0..m {
            let (rn, rt, un, ut) = (n + 2 * i, n + 2 * i + 1, 2 * i, 2 * i + 1);
            let (row_n, row_t) = (n + 2 * i, n + 2 * i + 1);
            let (closed, tangential) = (state(i) / 3 == 1, state(i) % 3); // 0 stick, 1 slip+, 2 slip−
            let md = &mods[i];
            let (coulomb, tresca) = match md.friction {
                PointFriction::Coulomb(mu) if mu > 0.0 => (Some(mu), None),
                PointFriction::Tresca(s) if s > 0.0 => (None, Some(s)),
                _ => (None, None),
            };
            if !md.contact {
                if closed || tangential != 0 {
                    skip = true;
                }
                mat[(row_n, rn)] = 1.0;
                mat[(row_t, rt)] = 1.0;
                continue;
            }
            // normal: open r'N = 0; closed u'N = uN + cN r'N + cN oN = g0
            if closed {
                mat[(row_n, un)] = 1.0;
                mat[(row_n, rn)] = c[2 * i];
                rhs[row_n] = gap[i] - c[2 * i] * o[2 * i];
            } else {
                mat[(row_n, rn)] = 1.0;
            }
            let frictionless = coulomb.is_none() && tresca.is_none();
            if frictionless || (coulomb.is_some() && !closed) {
                if tangential != 0 {
                    skip = true;
                }
                mat[(row_t, rt)] = 1.0;
                continue;
            }
            match tangential {
                0 => {
                    // u'T = uT + cT r'T + cT oT = 0
                    mat[(row_t, ut)] = 1.0;
                    mat[(row_t, rt)] = c[2 * i + 1];
                    rhs[row_t] = -c[2 * i + 1] * o[2 * i + 1];
                }
                _ => {
                    let sign = if tangential == 1 { -1.0 } else { 1.0 }; // slip+ ⇒ r'T = −s
                    mat[(row_t, rt)] = 1.0;
                    match (coulomb, tresca) {
                        (Some(mu), _) => mat[(row_t, rn)] = sign * mu, // r'T + sign μ r'N = 0 ⇒ r'T = −sign μ r'N
                        (_, Some(s)) => rhs[row_t] = sign * s,
                        _ => unreachable!(),
                    }
                }
            }
        }
        if skip {
            continue;
        }
        let Some(x) = mat.clone().lu().solve(&rhs) else { continue };
        let u: Vec<f64> = x.rows(0, n).iter().copied().collect();
        let rc: Vec<f64> = x.rows(n, n).iter().copied().collect();
        let r: Vec<f64> = (0..n).map(|j| rc[j] + o[j] - k[j] * (u[j] - gt[j] + a[j])).collect();
        let tol = 1e-10;
        let ok = (0..m).all(|i| {
            let md = &mods[i];
            if !md.contact {
                return true;
            }
            let un = u[2 * i] + c[2 * i] * (rc[2 * i] + o[2 * i]);
            let ut = u[2 * i + 1] + c[2 * i + 1] * (rc[2 * i + 1] + o[2 * i + 1]);
            let (closed, tangential) = (state(i) / 3 == 1, state(i) % 3);
            let normal_ok = if closed { rc[2 * i] <= tol } else { un - gap[i] <= tol };
            let s = match md.friction {
                PointFriction::Coulomb(mu) => mu * (-rc[2 * i]).max(0.0),
                PointFriction::Tresca(s) => s,
                PointFriction::None => 0.0,
            };
            let tangential_ok = match tangential {
                0 => rc[2 * i + 1].abs() <= s + tol,
                1 => ut >= -tol,
                _ => ut <= tol,
            };
            normal_ok && tangential_ok
        });
        if ok {
            found.push((r, rc, u));
        }
    }
    assert!(!found.is_empty(), "no admissible state combination");
    for f in &found[1..] {
        close(&f.0, &found[0].0, 1e-8, "two admissible answers");
    }
    found.swap_remove(0)
}

fn compare_with_brute_force(m: usize, seed: u64, mods: &[PointModification], friction_name: &str) {
    let mut rng = Lcg(seed);
    let w = random_w(m, &mut rng);
    let uf: Vec<f64> = (0..2 * m).map(|_| rng.next()).collect();
    let gap: Vec<f64> = (0..m).map(|_| 0.15 * (rng.next() + 1.0)).collect();
    let base =
        CondensedProblem::new(Delassus::Dense(w.clone()), uf.clone(), gap.clone(), FrictionLaw::None, None).unwrap();
    let (r, rc, u) = solve_modified(&base, mods);
    let (r_ref, rc_ref, u_ref) = brute_force(&w, &uf, &gap, mods);
    let what = format!("{friction_name}, m = {m}, seed {seed}");
    close(&r, &r_ref, 1e-8, &format!("{what}: total force"));
    close(&rc, &rc_ref, 1e-8, &format!("{what}: contact force"));
    close(&u, &u_ref, 1e-8, &format!("{what}: displacement"));
}

#[test]
fn three_points_tresca_series_springs_and_bonded_match_the_original_equations() {
    let mods = [
        PointModification { compliance: [0.4, 0.3], ..PointModification::plain(PointFriction::Tresca(0.2)) },
        PointModification {
            stiffness: [2.0, 1.5],
            spring_offset: [0.1, -0.05],
            ..PointModification::plain(PointFriction::Tresca(0.1))
        },
        PointModification {
            stiffness: [1.0, 1.0],
            spring_offset: [0.0, 0.02],
            contact: false,
            ..PointModification::plain(PointFriction::None)
        },
    ];
    for seed in 1..=8 {
        compare_with_brute_force(3, seed, &mods, "Tresca");
    }
}

#[test]
fn four_points_coulomb_with_force_offset_match_the_original_equations() {
    let mods = [
        PointModification::plain(PointFriction::Coulomb(0.2)),
        PointModification {
            compliance: [0.3, 0.5],
            force_offset: [0.05, 0.0],
            ..PointModification::plain(PointFriction::Coulomb(0.2))
        },
        PointModification {
            stiffness: [0.8, 0.4],
            force_offset: [0.05, 0.0],
            ..PointModification::plain(PointFriction::Coulomb(0.2))
        },
        PointModification { stiffness: [5.0, 2.0], contact: false, ..PointModification::plain(PointFriction::None) },
    ];
    for seed in 11..=16 {
        compare_with_brute_force(4, seed, &mods, "Coulomb");
    }
}

#[test]
fn frictionless_and_all_bonded_match_the_original_equations() {
    let frictionless = [
        PointModification { compliance: [0.2, 0.1], ..PointModification::plain(PointFriction::None) },
        PointModification { stiffness: [3.0, 0.0], ..PointModification::plain(PointFriction::None) },
        PointModification::plain(PointFriction::None),
    ];
    let bonded: Vec<PointModification> = (0..3)
        .map(|i| PointModification {
            stiffness: [1.0 + i as f64, 0.5],
            spring_offset: [0.01, 0.0],
            contact: false,
            ..PointModification::plain(PointFriction::None)
        })
        .collect();
    for seed in 21..=25 {
        compare_with_brute_force(3, seed, &frictionless, "frictionless");
        compare_with_brute_force(3, seed, &bonded, "bonded");
    }
}

#[test]
fn very_stiff_springs_tie_the_point() {
    // k → ∞ on every component without contact: u → g̃ − a (the springs' rest state), and
    // W' = (W⁻¹ + D)⁻¹ is computed without cancellation.
    let mut rng = Lcg(7);
    let w = random_w(2, &mut rng);
    let base =
        CondensedProblem::new(Delassus::Dense(w), vec![0.3, -0.2, 0.1, 0.4], vec![0.05, 0.0], FrictionLaw::None, None)
            .unwrap();
    let mods = vec![
        PointModification {
            stiffness: [1e12, 1e12],
            spring_offset: [0.02, -0.01],
            contact: false,
            ..PointModification::plain(PointFriction::None)
        };
        2
    ];
    let (r, _, u) = solve_modified(&base, &mods);
    close(&u, &[0.05 - 0.02, 0.01, -0.02, 0.01], 1e-7, "tied displacement");
    assert!(r.iter().all(|v| v.is_finite()));
}

// ---------------------------------------------------------------------------------------------
// The staggered loop (interface_law::staggered::staggered) on condensed problems
// ---------------------------------------------------------------------------------------------

use signorini::interface_law::staggered::{staggered, InterfaceLaws, InterfaceState, InterfaceStep};
use signorini::interface_law::{InterfaceLaw, InterfaceOutputs, InterfacePoint, PointSolution};

/// A softening spring with memory: `k(κ) = k0 / (1 + κ/δ)` along N beside the contact,
/// `κ = max(κ_committed, opening)` (the largest opening so far).
#[derive(Debug)]
struct Softening {
    k0: f64,
    delta: f64,
}

impl InterfaceLaw for Softening {
    fn name(&self) -> &'static str {
        "softening"
    }
    fn has_memory(&self) -> bool {
        true
    }
    fn initial(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn modification(
        &self,
        _: &InterfacePoint,
        f: PointFriction,
        trial: &[f64],
        _: Option<&PointSolution>,
    ) -> PointModification {
        PointModification { stiffness: [self.k0 / (1.0 + trial[0] / self.delta), 0.0], ..PointModification::plain(f) }
    }
    fn update(&self, _: &InterfacePoint, committed: &[f64], s: &PointSolution, _: f64) -> Vec<f64> {
        vec![committed[0].max(s.opening)]
    }
    fn residual(&self, _: &InterfacePoint, committed: &[f64], state: &[f64], s: &PointSolution, _: f64) -> f64 {
        let expected = committed[0].max(s.opening);
        (state[0] - expected).abs() / expected.abs().max(1e-300)
    }
    fn outputs(&self, state: &[f64]) -> InterfaceOutputs {
        InterfaceOutputs { damage: Some(state[0] / (state[0] + self.delta)), adhesion: None }
    }
}

/// A law whose variable flips with the force it sees: the staggered loop cannot converge.
#[derive(Debug)]
struct Flipping;

impl InterfaceLaw for Flipping {
    fn name(&self) -> &'static str {
        "flipping"
    }
    fn has_memory(&self) -> bool {
        true
    }
    fn initial(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn modification(
        &self,
        _: &InterfacePoint,
        f: PointFriction,
        trial: &[f64],
        _: Option<&PointSolution>,
    ) -> PointModification {
        PointModification {
            stiffness: [if trial[0] == 0.0 { 0.1 } else { 10.0 }, 0.0],
            contact: false,
            ..PointModification::plain(f)
        }
    }
    fn update(&self, _: &InterfacePoint, _: &[f64], s: &PointSolution, _: f64) -> Vec<f64> {
        vec![if s.force[0].abs() > 0.2 { 0.0 } else { 1.0 }]
    }
    fn residual(&self, _: &InterfacePoint, _: &[f64], _: &[f64], _: &PointSolution, _: f64) -> f64 {
        1.0
    }
    fn outputs(&self, _: &[f64]) -> InterfaceOutputs {
        InterfaceOutputs::default()
    }
}

fn one_law(law: Box<dyn InterfaceLaw>, points: Vec<InterfacePoint>, friction: Vec<PointFriction>) -> InterfaceLaws {
    let m = points.len();
    InterfaceLaws::new(vec![(law, "bottom".into())], vec![Some(0); m], vec!["test".into()], points, friction).unwrap()
}

fn run_staggered(
    laws: &InterfaceLaws,
    base: &CondensedProblem,
    state: &InterfaceState,
) -> signorini::Result<InterfaceStep> {
    staggered(laws, state, 1.0, 1e-9, |mods, last| {
        let md = ModifiedProblem::new(base, mods, last)?;
        let contact_force = match md.problem() {
            Some(p) => md.expand(&solve(p, &ContactSolver::SemismoothNewton, &tight())?.force),
            None => vec![0.0; 2 * base.points()],
        };
        let answer = md.answer(&contact_force);
        Ok((answer.force, answer.displacement, ()))
    })
    .map(|((), step)| step)
}

#[test]
fn staggered_loop_converges_to_the_softening_fixed_point() {
    // One point pulled away (open): r = −k(κ) v, v = z/(1 + W_NN k(κ)), κ = −v; the fixed
    // point of κ = −z / (1 + W k0/(1 + κ/δ)) by bisection is the oracle.
    let (w, z, k0, delta) = (2.0, -0.4, 3.0, 0.05);
    let base = CondensedProblem::new(Delassus::Dense(w2()), vec![z, 0.0], vec![0.0], FrictionLaw::None, None).unwrap();
    let laws = one_law(
        Box::new(Softening { k0, delta }),
        vec![InterfacePoint { weight: 1.0, gap: 0.0, slip_before: 0.0, traction_scale: 0.0, displacement_scale: 0.0 }],
        vec![PointFriction::None],
    );
    let step = run_staggered(&laws, &base, &laws.initial_state()).unwrap();
    let g = |kappa: f64| kappa + z / (1.0 + w * k0 / (1.0 + kappa / delta));
    let (mut lo, mut hi) = (0.0, -z);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let kappa = 0.5 * (lo + hi);
    let got = step.state.committed[0][0];
    assert!((got - kappa).abs() <= 1e-9 * kappa, "κ = {got}, expected {kappa}");
    assert!(step.iterations > 2, "{} iterations", step.iterations);
    let expected_force = -k0 / (1.0 + kappa / delta) * (-kappa);
    assert!((step.solutions[0].force[0] - expected_force).abs() <= 1e-8 * expected_force.abs());
    assert!(step.law_residuals[0] <= 1e-9);
    let snapshot = laws.snapshot(&[[0.0, 0.0]], &step, 1.0);
    assert_eq!(snapshot.points[0].damage, Some(got / (got + delta)));
}

#[test]
fn staggered_loop_solves_mixed_tresca_and_coulomb_points() {
    // Two plain points, Tresca at one and Coulomb at the other: the loop iterates the
    // Coulomb point's threshold; the answer is the original equations' (enumeration).
    let mut rng = Lcg(31);
    let w = random_w(2, &mut rng);
    let uf = vec![0.4, 0.3, 0.5, -0.35];
    let gap = vec![0.05, 0.02];
    let friction = vec![PointFriction::Tresca(0.05), PointFriction::Coulomb(0.3)];
    let base =
        CondensedProblem::new(Delassus::Dense(w.clone()), uf.clone(), gap.clone(), FrictionLaw::None, None).unwrap();
    let points: Vec<InterfacePoint> = gap
        .iter()
        .map(|&g| InterfacePoint {
            weight: 1.0,
            gap: g,
            slip_before: 0.0,
            traction_scale: 0.0,
            displacement_scale: 0.0,
        })
        .collect();
    let laws =
        InterfaceLaws::new(vec![], vec![None, None], vec!["signorini".into()], points, friction.clone()).unwrap();
    let step = run_staggered(&laws, &base, &laws.initial_state()).unwrap();
    let mods: Vec<PointModification> = friction.iter().map(|&f| PointModification::plain(f)).collect();
    let (r_ref, _, _) = brute_force(&w, &uf, &gap, &mods);
    let r: Vec<f64> = step.solutions.iter().flat_map(|s| s.force).collect();
    close(&r, &r_ref, 1e-8, "mixed friction");
    assert!(step.iterations > 1, "{} iterations", step.iterations);
    assert!(r_ref[2] < 0.0 && r_ref[3] != 0.0, "the Coulomb point is closed with friction: {r_ref:?}");
}

#[test]
fn staggered_loop_that_cannot_converge_or_fails_its_law_check_is_an_error() {
    // k = 0.1 gives |rN| = 0.08 (< 0.2: stiffen), k = 10 gives 0.48 (> 0.2: soften), and so on.
    let base =
        CondensedProblem::new(Delassus::Dense(w2()), vec![-1.0, 0.0], vec![0.0], FrictionLaw::None, None).unwrap();
    let point =
        vec![InterfacePoint { weight: 1.0, gap: 0.0, slip_before: 0.0, traction_scale: 0.0, displacement_scale: 0.0 }];
    let laws = one_law(Box::new(Flipping), point.clone(), vec![PointFriction::None]);
    match run_staggered(&laws, &base, &laws.initial_state()) {
        Err(signorini::Error::SolverDiverged { reason, iterations, .. }) => {
            assert_eq!(iterations, signorini::interface_law::staggered::MAX_STAGGERED);
            assert!(reason.contains("still change"), "{reason}");
        }
        other => panic!("expected a divergence, got {other:?}"),
    }
    // Converged (the force stays below the flip) but the law's own check fails.
    let calm =
        CondensedProblem::new(Delassus::Dense(w2()), vec![-0.001, 0.0], vec![0.0], FrictionLaw::None, None).unwrap();
    match run_staggered(&laws, &calm, &laws.initial_state()) {
        Err(signorini::Error::SolverDiverged { solver, reason, .. }) => {
            assert!(solver.contains("flipping") && solver.contains("bottom"), "{solver}");
            assert!(reason.contains("own residual at contact point 0"), "{reason}");
        }
        other => panic!("expected the law check to fail, got {other:?}"),
    }
}
