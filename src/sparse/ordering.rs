//! Reverse Cuthill–McKee ordering of a symmetric sparsity pattern (A. George and J. W. H. Liu,
//! *Computer Solution of Large Sparse Positive Definite Systems*, Prentice-Hall 1981, §4.3).
//!
//! 1. In each connected component, start from a pseudo-peripheral node: from a node of minimum
//!    degree, repeat a breadth-first search from a node of minimum degree in the last level while
//!    the number of levels grows (George–Liu's heuristic).
//! 2. Number the component breadth first, the neighbours of each node by increasing degree.
//! 3. Reverse the whole numbering: the reversed order has the same bandwidth and less profile
//!    (less fill in a Cholesky factor).

/// `perm[new] = old`: the RCM order of the graph whose node `i` has the neighbours
/// `adjacency[i]` (symmetric; self loops ignored).
pub fn reverse_cuthill_mckee(adjacency: &[Vec<usize>]) -> Vec<usize> {
    let n = adjacency.len();
    let degree: Vec<usize> = adjacency.iter().enumerate().map(|(i, a)| a.iter().filter(|&&j| j != i).count()).collect();
    let mut numbered = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|&i| degree[i]);
    let mut seen = vec![usize::MAX; n];
    let mut stamp = 0;
    for &seed in &by_degree {
        if numbered[seed] {
            continue;
        }
        // 1. A pseudo-peripheral start in the component of `seed`.
        let mut start = seed;
        let mut levels = 0;
        for _ in 0..8 {
            stamp += 1;
            let (depth, last) = bfs_last_level(adjacency, start, &mut seen, stamp);
            let candidate = last.into_iter().min_by_key(|&i| degree[i]).unwrap_or(start);
            if depth <= levels {
                break;
            }
            levels = depth;
            start = candidate;
        }
        // 2. Cuthill–McKee numbering from there.
        let first = order.len();
        numbered[start] = true;
        order.push(start);
        let mut head = first;
        let mut neighbours = Vec::new();
        while head < order.len() {
            let i = order[head];
            head += 1;
            neighbours.clear();
            neighbours.extend(adjacency[i].iter().copied().filter(|&j| !numbered[j]));
            neighbours.sort_by_key(|&j| degree[j]);
            neighbours.dedup();
            for &j in &neighbours {
                if !numbered[j] {
                    numbered[j] = true;
                    order.push(j);
                }
            }
        }
    }
    // 3. Reverse.
    order.reverse();
    order
}

/// Breadth-first search from `start`: (number of levels, nodes of the last level).
fn bfs_last_level(adjacency: &[Vec<usize>], start: usize, seen: &mut [usize], stamp: usize) -> (usize, Vec<usize>) {
    let mut level = vec![start];
    seen[start] = stamp;
    let mut depth = 1;
    loop {
        let mut next = Vec::new();
        for &i in &level {
            for &j in &adjacency[i] {
                if seen[j] != stamp {
                    seen[j] = stamp;
                    next.push(j);
                }
            }
        }
        if next.is_empty() {
            return (depth, level);
        }
        depth += 1;
        level = next;
    }
}

#[cfg(test)]
mod tests {
    use super::reverse_cuthill_mckee;

    #[test]
    fn rcm_is_a_permutation_and_shrinks_the_bandwidth_of_a_shuffled_grid() {
        // A 20 × 20 grid graph numbered in a scrambled order, plus an isolated node.
        let m = 20;
        let n = m * m + 1;
        let scramble = |k: usize| if k == m * m { k } else { (k * 151) % (m * m) };
        let mut adjacency = vec![Vec::new(); n];
        for i in 0..m {
            for j in 0..m {
                let a = scramble(i * m + j);
                if i + 1 < m {
                    let b = scramble((i + 1) * m + j);
                    adjacency[a].push(b);
                    adjacency[b].push(a);
                }
                if j + 1 < m {
                    let b = scramble(i * m + j + 1);
                    adjacency[a].push(b);
                    adjacency[b].push(a);
                }
            }
        }
        let perm = reverse_cuthill_mckee(&adjacency);
        let mut sorted = perm.clone();
        sorted.sort();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        let mut inverse = vec![0; n];
        for (new, &old) in perm.iter().enumerate() {
            inverse[old] = new;
        }
        let bandwidth = |pos: &dyn Fn(usize) -> usize| {
            (0..n)
                .flat_map(|a| adjacency[a].iter().map(move |&b| (a, b)))
                .map(|(a, b)| pos(a).abs_diff(pos(b)))
                .max()
                .unwrap()
        };
        let before = bandwidth(&|k| k);
        let after = bandwidth(&|k| inverse[k]);
        assert!(after <= m + 1 && after < before / 4, "bandwidth {before} → {after}");
    }
}
