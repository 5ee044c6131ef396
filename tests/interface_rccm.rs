//! The RCCM law's local parts (src/interface_law/rccm.rs), without PETSc: the update of β against
//! its closed forms (the rate-independent pull-off curve, the implicit Euler step, an accurate
//! integration of the viscous ODE), the modification it asks of the contact solve, and its
//! residual at exact and perturbed states.
use signorini::interface_law::rccm::Rccm;
use signorini::interface_law::{InterfaceLaw, InterfacePoint, PointFriction, PointSolution};
use signorini::scene::RccmSpec;

const C_N: f64 = 1.0e12; // Pa/m
const C_T: f64 = 0.5e12; // Pa/m
const W: f64 = 2.0; // J/m²
const MU: f64 = 0.3;

fn law(viscosity: f64, initial_adhesion: f64) -> Rccm {
    Rccm::new(&RccmSpec {
        normal_stiffness: C_N,
        tangential_stiffness: C_T,
        adhesion_energy: W,
        viscosity,
        mu: MU,
        initial_adhesion,
    })
}

fn point(weight: f64, slip_before: f64) -> InterfacePoint {
    InterfacePoint { weight, gap: 0.0, slip_before, traction_scale: 0.0, displacement_scale: 0.0 }
}

/// The traction of a glued point pulled open by `u` (never more before), b = 0: `C_N u` up to
/// `√(w/C_N)`, then `w²/(C_N u³)` (the rate-independent RCCM response, module documentation).
fn pull_off_traction(u: f64) -> f64 {
    let uc = (W / C_N).sqrt();
    if u <= uc {
        C_N * u
    } else {
        W * W / (C_N * u * u * u)
    }
}

#[test]
fn rate_independent_pull_off_follows_the_closed_form_and_unloads_on_the_secant() {
    let law = law(0.0, 1.0);
    let uc = law.critical_opening();
    assert!((uc - (W / C_N).sqrt()).abs() < 1e-20);
    assert!((law.peak_traction() - (C_N * W).sqrt()).abs() < 1e-6);
    let p = point(1.0, 0.0);
    let mut beta = law.initial();
    // Load to 4 u_c, unload to 0.5 u_c, reload to 6 u_c.
    let mut path: Vec<f64> = (1..=40).map(|k| 0.1 * k as f64 * uc).collect();
    path.extend((0..=35).map(|k| (4.0 - 0.1 * k as f64) * uc));
    path.extend((0..=55).map(|k| (0.5 + 0.1 * k as f64) * uc));
    let mut max_opening: f64 = 0.0;
    let mut checked_unloading = 0;
    for &u in &path {
        let solution = PointSolution { opening: u, force: [0.0; 2], ..Default::default() };
        let next = law.update(&p, &beta, &solution, 0.37);
        assert!(next[0] <= beta[0], "β increased: {} -> {}", beta[0], next[0]);
        beta = next;
        let traction = C_N * beta[0] * beta[0] * u;
        if u >= max_opening {
            max_opening = u;
            let exact = pull_off_traction(u);
            assert!((traction - exact).abs() <= 1e-12 * exact, "u = {u:e}: {traction:e} against {exact:e}");
        } else {
            // Unloading and reloading below the largest opening: the secant through the largest.
            let secant = pull_off_traction(max_opening) / max_opening * u;
            assert!((traction - secant).abs() <= 1e-12 * secant);
            checked_unloading += 1;
        }
    }
    assert!(checked_unloading > 40);
    assert!(max_opening > 5.9 * uc);
}

#[test]
fn viscous_step_solves_the_implicit_euler_equation() {
    for &b in &[1.0e-3, 1.0, 50.0] {
        let law = law(b, 1.0);
        for &(beta0, energy, dt) in &[
            (1.0, 3.0 * W, 0.1),
            (0.8, 10.0 * W, 1.0e-3),
            (0.3, 1.0e3 * W, 2.0),
            (0.5, 1.9 * W, 0.5),
            (0.5, 1.5 * W, 0.5), // β0 E < w: nothing breaks
            (0.0, 1.0e6 * W, 1.0),
        ] {
            let beta = law.beta_update(beta0, energy, dt);
            let negative_part = (-(W - beta * energy)).max(0.0);
            let equation = b * (beta - beta0) / dt + negative_part;
            assert!(
                equation.abs() <= 1e-12 * (W + beta0 * energy),
                "b = {b}, β0 = {beta0}, E = {energy}: residual {equation:e}"
            );
            assert!((0.0..=beta0).contains(&beta));
        }
    }
    // b → 0: the viscous step tends to the rate-independent w/E.
    let (beta0, energy, dt) = (1.0, 4.0 * W, 1.0);
    let rate_independent = law(0.0, 1.0).beta_update(beta0, energy, dt);
    assert_eq!(rate_independent, 0.25);
    let near = law(1.0e-9, 1.0).beta_update(beta0, energy, dt);
    assert!((near - 0.25).abs() < 1e-9);
}

/// β of a point opened at the constant rate `u = v t` with `b > 0`, integrated accurately:
/// `b β̇ = −(w − β C_N v² t²)⁻`, classical Runge–Kutta with 20 000 steps from the time the bond
/// starts breaking (`β = 1` before).
fn viscous_ramp_reference(b: f64, v: f64, t_end: f64) -> f64 {
    let t0 = (W / C_N).sqrt() / v;
    if t_end <= t0 {
        return 1.0;
    }
    let f = |t: f64, beta: f64| -((-(W - beta * C_N * v * v * t * t)).max(0.0)) / b;
    let n = 20_000;
    let h = (t_end - t0) / n as f64;
    let mut beta = 1.0;
    let mut t = t0;
    for _ in 0..n {
        let k1 = f(t, beta);
        let k2 = f(t + 0.5 * h, beta + 0.5 * h * k1);
        let k3 = f(t + 0.5 * h, beta + 0.5 * h * k2);
        let k4 = f(t + h, beta + h * k3);
        beta += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        t += h;
    }
    beta
}

#[test]
fn viscous_ramp_converges_to_the_ode_at_order_one() {
    let b = 2.0; // J·s/m²
    let uc = (W / C_N).sqrt();
    let v = uc; // u_c per second
    let t_end = 4.0;
    let reference = viscous_ramp_reference(b, v, t_end);
    assert!(reference < 0.9 && reference > 0.05, "reference β = {reference}");
    let law = law(b, 1.0);
    let p = point(1.0, 0.0);
    let mut errors = Vec::new();
    for &steps in &[40usize, 80, 160, 320] {
        let dt = t_end / steps as f64;
        let mut beta = law.initial();
        for k in 1..=steps {
            let solution = PointSolution { opening: v * dt * k as f64, ..Default::default() };
            beta = law.update(&p, &beta, &solution, dt);
        }
        errors.push((beta[0] - reference).abs());
    }
    eprintln!("viscous ramp: reference β = {reference:.10}, errors at 40, 80, 160, 320 steps: {errors:?}");
    for pair in errors.windows(2) {
        let rate = (pair[0] / pair[1]).log2();
        assert!((rate - 1.0).abs() < 0.1, "observed rate {rate} (errors {errors:?})");
    }
}

#[test]
fn beta_never_increases_and_stays_in_the_unit_interval() {
    for &b in &[0.0, 0.5] {
        let law = law(b, 0.9);
        let p = point(1.0e-3, 0.0);
        let mut beta = law.initial();
        // A deterministic sequence of openings and slips, growing and shrinking.
        let uc = law.critical_opening();
        for k in 0..500 {
            let phase = k as f64 * 0.37;
            let solution = PointSolution {
                opening: (3.0 * phase.sin() * uc).max(0.0),
                slip: 2.5 * (0.7 * phase).cos() * uc,
                ..Default::default()
            };
            let next = law.update(&p, &beta, &solution, 0.05);
            assert!(next[0] <= beta[0] && next[0] >= 0.0 && next[0] <= 1.0);
            beta = next;
        }
        assert!(beta[0] < 0.5, "the bond should have broken: β = {}", beta[0]);
    }
}

#[test]
fn modification_is_beta_weighted_springs_beside_coulomb_with_the_debonded_fraction() {
    let law = law(0.0, 1.0);
    let weight = 2.0e-3;
    let p = point(weight, 3.0e-7);
    let m = law.modification(&p, PointFriction::Tresca(5.0), &[0.6], None);
    assert!((m.stiffness[0] - C_N * 0.36 * weight).abs() <= 1e-6 * C_N * weight);
    assert!((m.stiffness[1] - C_T * 0.36 * weight).abs() <= 1e-6 * C_T * weight);
    assert_eq!(m.spring_offset, [0.0, 3.0e-7]);
    assert_eq!(m.compliance, [0.0; 2]);
    assert_eq!(m.force_offset, [0.0; 2]);
    assert!(m.contact);
    match m.friction {
        PointFriction::Coulomb(mu) => assert!((mu - MU * 0.4).abs() < 1e-15),
        other => panic!("expected Coulomb, got {other:?}"),
    }
    let glued = law.modification(&p, PointFriction::None, &[1.0], None);
    assert_eq!(glued.friction, PointFriction::Coulomb(0.0));
    let free = law.modification(&p, PointFriction::None, &[0.0], None);
    assert_eq!(free.stiffness, [0.0, 0.0]);
    assert_eq!(free.friction, PointFriction::Coulomb(MU));
    assert_eq!(law.outputs(&[0.25]).adhesion, Some(0.25));
    assert_eq!(law.outputs(&[0.25]).damage, None);
    assert_eq!(law.name(), "rccm");
    assert!(law.has_memory());
}

/// Exact states of a point at the end of an increment: open (β broken by the opening), stuck
/// (pressed and sheared below the threshold) and slipping (at the threshold, opposite the slip).
fn exact_states(law: &Rccm) -> Vec<(InterfacePoint, [f64; 1], [f64; 1], PointSolution)> {
    let weight = 1.0e-3;
    let uc = law.critical_opening();
    let dt = 0.1;
    let mut states = Vec::new();
    // Open: opening 2 u_c, no slip, r' = 0.
    {
        let p = point(weight, 0.0);
        let committed = [1.0];
        let opening = 2.0 * uc;
        let beta = law.beta_update(1.0, law.energy(opening, 0.0), dt);
        let r_n = C_N * beta * beta * weight * opening;
        let solution =
            PointSolution { opening, slip: 0.0, slip_increment: 0.0, force: [r_n, 0.0], contact_force: [0.0, 0.0] };
        states.push((p, committed, [beta], solution));
    }
    // Stuck: closed, pressed by p, slip 1.5 u_c from before, no slip increment.
    {
        let p = point(weight, 1.5 * uc);
        let committed = [0.8];
        let slip = 1.5 * uc;
        let beta = law.beta_update(0.8, law.energy(0.0, slip), dt);
        let pressure = 3.0 * law.peak_traction() * weight;
        let contact_t = 0.5 * MU * (1.0 - beta) * pressure;
        let r_t = contact_t - C_T * beta * beta * weight * slip;
        let solution = PointSolution {
            opening: 0.0,
            slip,
            slip_increment: 0.0,
            force: [-pressure, r_t],
            contact_force: [-pressure, contact_t],
        };
        states.push((p, committed, [beta], solution));
    }
    // Slipping: closed, pressed, slip increment +u_c, r'_T = −μ(1−β) p.
    {
        let p = point(weight, 2.0 * uc);
        let committed = [0.7];
        let slip = 3.0 * uc;
        let beta = law.beta_update(0.7, law.energy(0.0, slip), dt);
        assert!(beta < 0.7);
        let pressure = 2.0 * law.peak_traction() * weight;
        let contact_t = -MU * (1.0 - beta) * pressure;
        let r_t = contact_t - C_T * beta * beta * weight * slip;
        let solution = PointSolution {
            opening: 0.0,
            slip,
            slip_increment: uc,
            force: [-pressure, r_t],
            contact_force: [-pressure, contact_t],
        };
        states.push((p, committed, [beta], solution));
    }
    states
}

#[test]
fn residual_vanishes_at_exact_states() {
    for &b in &[0.0, 3.0] {
        let law = law(b, 1.0);
        for (p, committed, state, solution) in exact_states(&law) {
            let residual = law.residual(&p, &committed, &state, &solution, 0.1);
            assert!(residual < 1e-12, "b = {b}: residual {residual:e} at {solution:?}");
        }
    }
}

#[test]
fn residual_detects_each_perturbation() {
    let law = law(0.0, 1.0);
    let states = exact_states(&law);
    let check = |what: &str, p: &InterfacePoint, committed: &[f64], state: &[f64], solution: &PointSolution| {
        let residual = law.residual(p, committed, state, solution, 0.1);
        assert!(residual > 1e-3, "{what}: residual {residual:e} too small");
    };
    let (p_open, c_open, s_open, open) = states[0];
    let (p_stick, c_stick, s_stick, stick) = states[1];
    let (p_slip, c_slip, s_slip, slip) = states[2];
    // β not the update's.
    check("β off", &p_open, &c_open, &[s_open[0] * 1.1], &open);
    // β above the committed value (healing).
    check("β > β0", &p_stick, &[0.1], &s_stick, &stick);
    // β outside [0, 1].
    check("β > 1", &p_stick, &[1.5], &[1.5], &stick);
    check("β < 0", &p_stick, &c_stick, &[-0.2], &stick);
    // Penetration.
    let mut penetrating = stick;
    penetrating.opening = -0.1 * law.critical_opening();
    check("penetration", &p_stick, &c_stick, &s_stick, &penetrating);
    // Tension in the unilateral part (reported and recomputed alike).
    let mut pulled = open;
    let extra = 0.2 * open.force[0];
    pulled.force[0] += extra;
    pulled.contact_force[0] += extra;
    check("tensile r'", &p_open, &c_open, &s_open, &pulled);
    // Open and pressed at once.
    let mut open_pressed = open;
    open_pressed.force[0] -= 2.0 * open.force[0];
    open_pressed.contact_force[0] -= 2.0 * open.force[0];
    check("open and pressed", &p_open, &c_open, &s_open, &open_pressed);
    // The reported contact force disagrees with the total force minus the springs.
    let mut split = stick;
    split.contact_force[1] *= 1.5;
    check("split", &p_stick, &c_stick, &s_stick, &split);
    // Above the friction threshold.
    let mut above = stick;
    above.force[1] += 2.0 * stick.contact_force[1];
    above.contact_force[1] *= 3.0;
    check("above threshold", &p_stick, &c_stick, &s_stick, &above);
    // Slipping below the threshold.
    let mut slow = slip;
    slow.force[1] -= 0.5 * slip.contact_force[1];
    slow.contact_force[1] *= 0.5;
    check("slip below threshold", &p_slip, &c_slip, &s_slip, &slow);
    // Slipping in the direction of the friction force.
    let mut wrong_way = slip;
    wrong_way.slip_increment = -slip.slip_increment;
    check("friction along the slip", &p_slip, &c_slip, &s_slip, &wrong_way);
}
