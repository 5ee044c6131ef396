//! Tests of the threshold incomplete Cholesky (`cargo test --release --lib sparse`).
use super::*;

/// A matrix in owned CSR (full symmetric storage).
struct Owned {
    n: usize,
    indptr: Vec<usize>,
    indices: Vec<usize>,
    values: Vec<f64>,
}

impl Owned {
    fn from_rows(rows: Vec<Vec<(usize, f64)>>) -> Owned {
        let n = rows.len();
        let mut indptr = vec![0];
        let (mut indices, mut values) = (Vec::new(), Vec::new());
        for mut row in rows {
            row.sort_by_key(|e| e.0);
            for (c, v) in row {
                indices.push(c);
                values.push(v);
            }
            indptr.push(indices.len());
        }
        Owned { n, indptr, indices, values }
    }
    fn view(&self) -> CsrMatrix<'_> {
        CsrMatrix {
            num_rows: self.n,
            num_cols: self.n,
            indptr: &self.indptr,
            indices: &self.indices,
            values: &self.values,
        }
    }
    fn dense(&self) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; self.n]; self.n];
        for (i, row) in d.iter_mut().enumerate() {
            for p in self.indptr[i]..self.indptr[i + 1] {
                row[self.indices[p]] = self.values[p];
            }
        }
        d
    }
    fn multiply(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|i| (self.indptr[i]..self.indptr[i + 1]).map(|p| self.values[p] * x[self.indices[p]]).sum())
            .collect()
    }
}

/// The 5-point Laplacian on an m × m grid of interior points.
fn laplacian(m: usize) -> Owned {
    let id = |i: usize, j: usize| i * m + j;
    let mut rows = Vec::new();
    for i in 0..m {
        for j in 0..m {
            let mut row = vec![(id(i, j), 4.0)];
            if i > 0 {
                row.push((id(i - 1, j), -1.0));
            }
            if i + 1 < m {
                row.push((id(i + 1, j), -1.0));
            }
            if j > 0 {
                row.push((id(i, j - 1), -1.0));
            }
            if j + 1 < m {
                row.push((id(i, j + 1), -1.0));
            }
            rows.push(row);
        }
    }
    Owned::from_rows(rows)
}

/// A small linear congruential generator (reproducible, no dependency).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random sparse SPD matrix of order n with entries of both signs (not an M-matrix): about
/// `per_row` random couplings per row, diagonal = row sum of |off-diagonal| + 0.1, scaled rows
/// (the diagonal varies over four orders of magnitude).
fn random_spd(n: usize, per_row: usize, seed: u64) -> Owned {
    let mut g = Lcg(seed);
    let mut dense = vec![std::collections::BTreeMap::<usize, f64>::new(); n];
    for i in 0..n {
        for _ in 0..per_row {
            let j = (g.next() * n as f64) as usize % n;
            if j != i {
                let v = 2.0 * g.next() - 1.0;
                dense[i].insert(j, v);
                dense[j].insert(i, v);
            }
        }
    }
    let weights: Vec<f64> = (0..n).map(|_| 10f64.powf(4.0 * g.next() - 2.0)).collect();
    let mut rows = Vec::new();
    for i in 0..n {
        let sum: f64 = dense[i].values().map(|v| v.abs()).sum();
        let mut row: Vec<(usize, f64)> =
            dense[i].iter().map(|(&j, &v)| (j, v * weights[i].sqrt() * weights[j].sqrt())).collect();
        row.push((i, (sum + 0.1) * weights[i]));
        rows.push(row);
    }
    Owned::from_rows(rows)
}

/// max |(L Lᵀ − A)_ij| / max |a_ij|.
fn factor_error(a: &Owned, f: &IncompleteCholesky) -> f64 {
    let (start, rows, vals) = f.lower_factor();
    let n = a.n;
    let mut l = vec![vec![0.0; n]; n];
    for j in 0..n {
        for p in start[j]..start[j + 1] {
            l[rows[p]][j] = vals[p];
        }
    }
    let d = a.dense();
    let scale = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut err = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let llt: f64 = (0..n).map(|k| l[i][k] * l[j][k]).sum();
            err = err.max((llt - d[i][j]).abs());
        }
    }
    err / scale
}

/// Preconditioned CG from x = 0: the iterations to reach ‖r‖ ≤ 1e-10 ‖b‖ (None after `max`).
fn pcg_iterations(a: &Owned, f: &IncompleteCholesky, b: &[f64], max: usize) -> Option<usize> {
    let n = a.n;
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let bnorm = dot(b, b).sqrt();
    let mut x = vec![0.0; n];
    let mut r = b.to_vec();
    let mut z = vec![0.0; n];
    f.apply(&r, &mut z).unwrap();
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    for it in 1..=max {
        let q = a.multiply(&p);
        let alpha = rz / dot(&p, &q);
        for k in 0..n {
            x[k] += alpha * p[k];
            r[k] -= alpha * q[k];
        }
        if dot(&r, &r).sqrt() <= 1e-10 * bnorm {
            return Some(it);
        }
        f.apply(&r, &mut z).unwrap();
        let rz_new = dot(&r, &z);
        for k in 0..n {
            p[k] = z[k] + rz_new / rz * p[k];
        }
        rz = rz_new;
    }
    None
}

fn exact() -> IctOptions {
    IctOptions { drop_tolerance: 0.0, fill: None, reverse_cuthill_mckee: false, ..IctOptions::default() }
}

#[test]
fn tau_zero_gives_the_exact_cholesky_factor_of_the_laplacian() {
    let a = laplacian(10);
    let f = IncompleteCholesky::factor(&a.view(), &exact()).unwrap();
    assert_eq!(f.shift(), 0.0);
    let err = factor_error(&a, &f);
    assert!(err < 1e-12, "L Lᵀ − A: {err:e}");
    // The exact factor of a banded matrix fills the band: more entries than A's lower triangle.
    assert!(f.nnz() > (a.indices.len() + a.n) / 2);
    // One application solves the system.
    let b: Vec<f64> = (0..a.n).map(|i| (i as f64).sin()).collect();
    assert_eq!(pcg_iterations(&a, &f, &b, 5), Some(1));
}

#[test]
fn tau_zero_gives_the_exact_cholesky_factor_of_a_random_spd_matrix() {
    let a = random_spd(120, 3, 7);
    let f = IncompleteCholesky::factor(&a.view(), &exact()).unwrap();
    assert_eq!(f.shift(), 0.0);
    let err = factor_error(&a, &f);
    assert!(err < 1e-12, "L Lᵀ − A: {err:e}");
}

#[test]
fn reverse_cuthill_mckee_order_gives_the_exact_factor_of_the_permuted_matrix() {
    let a = random_spd(120, 3, 11);
    let f = IncompleteCholesky::factor(&a.view(), &IctOptions { reverse_cuthill_mckee: true, ..exact() }).unwrap();
    let perm = f.permutation().expect("reordered").to_vec();
    // P A Pᵀ in owned CSR.
    let d = a.dense();
    let permuted = Owned::from_rows(
        (0..a.n)
            .map(|i| (0..a.n).filter(|&j| d[perm[i]][perm[j]] != 0.0).map(|j| (j, d[perm[i]][perm[j]])).collect())
            .collect(),
    );
    let err = factor_error(&permuted, &f);
    assert!(err < 1e-12, "L Lᵀ − P A Pᵀ: {err:e}");
    // Applied to A (in its own order), one application solves the system.
    let b: Vec<f64> = (0..a.n).map(|i| (i as f64).cos()).collect();
    assert_eq!(pcg_iterations(&a, &f, &b, 5), Some(1));
    // On a grid it keeps fewer entries than the natural order for the same τ.
    let grid = laplacian(30);
    let natural = IncompleteCholesky::factor(&grid.view(), &exact()).unwrap();
    let rcm = IncompleteCholesky::factor(&grid.view(), &IctOptions { reverse_cuthill_mckee: true, ..exact() }).unwrap();
    assert!(rcm.nnz() <= natural.nnz(), "RCM {} entries, natural {}", rcm.nnz(), natural.nnz());
}

#[test]
fn larger_tolerance_keeps_fewer_entries_and_a_positive_factor() {
    let a = laplacian(30);
    let b: Vec<f64> = (0..a.n).map(|i| 1.0 + (i % 7) as f64).collect();
    let mut last = (usize::MAX, 0);
    for tau in [0.0, 1e-4, 1e-3, 1e-2, 1e-1] {
        let f = IncompleteCholesky::factor(&a.view(), &IctOptions { drop_tolerance: tau, ..exact() }).unwrap();
        assert_eq!(f.shift(), 0.0, "τ = {tau}: a Laplacian (M-matrix) needs no shift");
        let (start, _, vals) = f.lower_factor();
        assert!((0..a.n).all(|j| vals[start[j]] > 0.0), "τ = {tau}: a non-positive diagonal");
        // M⁻¹ is positive definite: rᵀ M⁻¹ r > 0.
        let mut z = vec![0.0; a.n];
        f.apply(&b, &mut z).unwrap();
        assert!(b.iter().zip(&z).map(|(x, y)| x * y).sum::<f64>() > 0.0);
        let its = pcg_iterations(&a, &f, &b, 500).expect("PCG converges");
        assert!(f.nnz() < last.0, "τ = {tau}: {} entries, not fewer than {}", f.nnz(), last.0);
        assert!(its >= last.1, "τ = {tau}: {its} iterations, fewer than with a smaller τ ({})", last.1);
        last = (f.nnz(), its);
    }
    // A fill limit bounds every column: p = 0 keeps at most A's count.
    let f = IncompleteCholesky::factor(&a.view(), &IctOptions { fill: Some(0), ..exact() }).unwrap();
    assert!(f.nnz() <= (a.indices.len() + a.n) / 2, "{} entries", f.nnz());
    let f2 = IncompleteCholesky::factor(&a.view(), &IctOptions { fill: Some(2), ..exact() }).unwrap();
    assert!(f2.nnz() > f.nnz() && f2.nnz() <= f.nnz() + 2 * a.n);
    assert!(pcg_iterations(&a, &f2, &b, 500).unwrap() < pcg_iterations(&a, &f, &b, 500).unwrap());
}

/// Kershaw's matrix: symmetric positive definite (eigenvalues 3 ± 2√2 ± ..., all > 0) but not
/// an M-matrix (positive off-diagonal entries); its IC(0) meets a negative pivot.
fn kershaw() -> Owned {
    let d = [[3.0, -2.0, 0.0, 2.0], [-2.0, 3.0, -2.0, 0.0], [0.0, -2.0, 3.0, -2.0], [2.0, 0.0, -2.0, 3.0]];
    Owned::from_rows((0..4).map(|i| (0..4).filter(|&j| d[i][j] != 0.0).map(|j| (j, d[i][j])).collect()).collect())
}

#[test]
fn shift_cures_a_breakdown_on_an_spd_matrix_that_is_not_an_m_matrix() {
    // Kershaw's matrix repeated along the diagonal with weak couplings between the blocks.
    let k = kershaw().dense();
    let blocks = 25;
    let n = 4 * blocks;
    let mut rows = vec![Vec::new(); n];
    for b in 0..blocks {
        for (i, ki) in k.iter().enumerate() {
            for (j, &kij) in ki.iter().enumerate() {
                if kij != 0.0 {
                    rows[4 * b + i].push((4 * b + j, kij + if i == j { 0.2 } else { 0.0 }));
                }
            }
        }
        if b + 1 < blocks {
            rows[4 * b + 3].push((4 * b + 4, -0.1));
            rows[4 * b + 4].push((4 * b + 3, -0.1));
        }
    }
    let a = Owned::from_rows(rows);
    // IC(0)-like: no fill beyond A's count per column, no restart: breakdown, a typed error.
    let ic0 = IctOptions { drop_tolerance: 0.0, fill: Some(0), max_restarts: 0, reverse_cuthill_mckee: false };
    match IncompleteCholesky::factor(&a.view(), &ic0) {
        Err(Error::Factorization { message, .. }) => assert!(message.contains("breakdown"), "{message}"),
        other => panic!("expected a breakdown, got {other:?}"),
    }
    // With restarts the shift is found, reported, and the factor preconditions CG.
    let f = IncompleteCholesky::factor(&a.view(), &IctOptions { max_restarts: 60, ..ic0 }).unwrap();
    assert!(f.shift() > 0.0 && f.restarts() >= 1, "shift {} after {} restarts", f.shift(), f.restarts());
    assert_eq!(f.shift(), 1e-3 * 2f64.powi(f.restarts() as i32 - 1));
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
    let its = pcg_iterations(&a, &f, &b, n).expect("shifted ICT preconditions CG");
    assert!(its < n / 2, "{its} iterations");
    // The exact factor (τ = 0, no limit) needs no shift: A is positive definite.
    let f = IncompleteCholesky::factor(&a.view(), &exact()).unwrap();
    assert_eq!(f.shift(), 0.0);
    assert!(factor_error(&a, &f) < 1e-12);
}

#[test]
fn every_bad_input_is_a_typed_error() {
    let expect = |r: Result<IncompleteCholesky>, what: &str| match r {
        Err(Error::Factorization { message, .. }) => {
            assert!(message.contains(what), "expected '{what}' in: {message}")
        }
        other => panic!("{what}: expected a Factorization error, got {other:?}"),
    };
    let o = IctOptions::default();
    let a = laplacian(3);
    // Not square.
    expect(IncompleteCholesky::factor(&CsrMatrix { num_cols: 10, ..a.view() }, &o), "not square");
    // Inconsistent arrays.
    expect(IncompleteCholesky::factor(&CsrMatrix { values: &a.values[1..], ..a.view() }, &o), "disagree");
    // Pattern not symmetric: (0, 2) without (2, 0).
    let unsym = Owned::from_rows(vec![vec![(0, 2.0), (2, -1.0)], vec![(1, 2.0)], vec![(2, 2.0)]]);
    expect(IncompleteCholesky::factor(&unsym.view(), &o), "pattern is not symmetric");
    // Values not symmetric.
    let unsym = Owned::from_rows(vec![vec![(0, 2.0), (1, -1.0)], vec![(0, -0.5), (1, 2.0)]]);
    expect(IncompleteCholesky::factor(&unsym.view(), &o), "not symmetric");
    // Negative and zero (missing) diagonal.
    let neg = Owned::from_rows(vec![vec![(0, 2.0)], vec![(1, -1.0)]]);
    expect(IncompleteCholesky::factor(&neg.view(), &o), "diagonal entry (1, 1) is -1");
    let zero = Owned::from_rows(vec![vec![(0, 2.0), (1, 1.0)], vec![(0, 1.0)]]);
    expect(IncompleteCholesky::factor(&zero.view(), &o), "diagonal entry (1, 1) is 0");
    // Out of range, repeated, not finite.
    let bad = Owned { n: 2, indptr: vec![0, 1, 2], indices: vec![0, 5], values: vec![1.0, 1.0] };
    expect(IncompleteCholesky::factor(&bad.view(), &o), "out of range");
    let bad = Owned { n: 1, indptr: vec![0, 2], indices: vec![0, 0], values: vec![1.0, 1.0] };
    expect(IncompleteCholesky::factor(&bad.view(), &o), "twice");
    let bad = Owned { n: 1, indptr: vec![0, 1], indices: vec![0], values: vec![f64::NAN] };
    expect(IncompleteCholesky::factor(&bad.view(), &o), "not finite");
    // Bad options.
    for tau in [-1.0, f64::NAN, f64::INFINITY] {
        expect(
            IncompleteCholesky::factor(&a.view(), &IctOptions { drop_tolerance: tau, ..o.clone() }),
            "drop tolerance",
        );
    }
    // An indefinite matrix (positive diagonal) breaks down whatever the shift allowed.
    let indef = Owned::from_rows(vec![vec![(0, 1.0), (1, 2.0)], vec![(0, 2.0), (1, 1.0)]]);
    expect(IncompleteCholesky::factor(&indef.view(), &IctOptions { max_restarts: 0, ..exact() }), "breakdown");
    // Apply with the wrong length.
    let f = IncompleteCholesky::factor(&a.view(), &o).unwrap();
    let mut z = vec![0.0; 8];
    expect(f.apply(&[0.0; 9], &mut z).map(|_| f.clone()), "apply");
}
