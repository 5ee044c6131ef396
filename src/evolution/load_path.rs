//! A load path: the pseudo-times of the increments and the factor each load is multiplied by.
//!
//! ```text
//!   factor                      a named load follows its table, piecewise linear in t
//!     1 |      ____________     (`[evolution.factor] name = [[t, f], ...]`);
//!       |     /            \    an unnamed load is ramped: f(t) = t / t_end
//!       |    /              \
//!     0 |___/________________\___ t
//!        t_0  t_1 ...          t_N      increments end at t_1 < ... < t_N
//! ```
//!
//! The path starts from rest at `t_0` (no displacement, no contact force); a load whose
//! factor is not zero at `t_0` is applied in the first increment.
use std::collections::BTreeMap;

use crate::error::{Error, Result};

/// The increments of a path and the factors of its loads (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct LoadPath {
    /// The pseudo-time the path starts from (at rest).
    pub start: f64,
    /// The increments' end times, strictly increasing, all after `start`.
    pub times: Vec<f64>,
    /// The piecewise-linear tables of the named loads: `[t, factor]` rows, t increasing.
    pub tables: BTreeMap<String, Vec<[f64; 2]>>,
    /// The boundary part whose mean displacement the history records (the contact part if
    /// `None`).
    pub monitor: Option<String>,
    /// The times at which the contact profiles are kept (none if empty).
    pub profiles: Vec<f64>,
    /// The `t_end` of the unnamed loads' ramp `t / t_end` (the last table time; the path's end
    /// if `None`).
    pub ramp_end: Option<f64>,
}

impl LoadPath {
    /// `steps` equal increments from 0 to 1, every load ramped proportionally (`t = k/steps`).
    pub fn proportional(steps: usize) -> Result<LoadPath> {
        if steps == 0 {
            return Err(Error::Usage("a load path needs at least one increment (steps >= 1)".into()));
        }
        Self::at_times(0.0, (1..=steps).map(|k| k as f64 / steps as f64).collect())
    }

    /// Increments ending at `times` (strictly increasing, after `start`), loads ramped, the
    /// profile kept at the end.
    pub fn at_times(start: f64, times: Vec<f64>) -> Result<LoadPath> {
        let profiles = times.last().copied().into_iter().collect();
        let path = LoadPath { start, times, tables: BTreeMap::new(), monitor: None, profiles, ramp_end: None };
        path.validated()
    }

    /// The same path with a table for the loads named `name`.
    pub fn with_table(mut self, name: &str, rows: &[[f64; 2]]) -> Result<LoadPath> {
        self.tables.insert(name.to_string(), rows.to_vec());
        self.validated()
    }

    /// Check the times and tables ([`Error::Usage`] naming what is wrong).
    pub fn validated(self) -> Result<LoadPath> {
        if self.times.is_empty() {
            return Err(Error::Usage("a load path needs at least one increment".into()));
        }
        let mut previous = self.start;
        for (k, &t) in self.times.iter().enumerate() {
            if !t.is_finite() || t <= previous {
                return Err(Error::Usage(format!(
                    "load path: increment {} ends at t = {t}, not after {previous}: times must increase strictly",
                    k + 1
                )));
            }
            previous = t;
        }
        for (name, rows) in &self.tables {
            if rows.len() < 2 {
                return Err(Error::Usage(format!("load path: the table of `{name}` needs at least two rows")));
            }
            if rows.iter().any(|r| !r[0].is_finite() || !r[1].is_finite()) {
                return Err(Error::Usage(format!("load path: the table of `{name}` has a value that is not finite")));
            }
            if rows.windows(2).any(|w| w[1][0] <= w[0][0]) {
                return Err(Error::Usage(format!("load path: the times of the table of `{name}` must increase")));
            }
        }
        Ok(self)
    }

    /// The load path a scene asks for (`[evolution]`, checked when the scene was read), `None`
    /// for a single static solve.
    pub fn of_scene(scene: &crate::scene::Scene) -> Result<Option<LoadPath>> {
        let Some(e) = &scene.evolution else { return Ok(None) };
        let path = LoadPath {
            start: e.start(),
            times: e.times.clone(),
            tables: e.factors.iter().map(|f| (f.name.clone(), f.points.clone())).collect(),
            monitor: e.monitor.clone(),
            profiles: e.profiles.clone(),
            ramp_end: Some(e.ramp_end()),
        };
        path.validated().map(Some)
    }

    /// The last time of the path.
    pub fn end(&self) -> f64 {
        *self.times.last().expect("a validated path has an increment")
    }

    /// The factor of the loads named `name` (`None`: unnamed, ramped `t / t_end`) at `t`
    /// (the rules of `[evolution]`: [`crate::scene::EvolutionSpec::factor`]).
    /// A named load without a table is ramped too; outside its table a factor stays at the
    /// table's first or last value.
    pub fn factor(&self, name: Option<&str>, t: f64) -> f64 {
        match name.and_then(|n| self.tables.get(n)) {
            Some(rows) => crate::scene::piecewise_linear(rows, t),
            None => t / self.ramp_end.unwrap_or_else(|| self.end()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportional_path_ramps_every_load() {
        let path = LoadPath::proportional(4).unwrap();
        assert_eq!(path.times, vec![0.25, 0.5, 0.75, 1.0]);
        assert_eq!(path.factor(None, 0.5), 0.5);
        assert!(LoadPath::proportional(0).is_err());
    }

    #[test]
    fn tables_interpolate_and_hold_beyond_their_ends() {
        let path = LoadPath::at_times(0.0, vec![1.0, 2.0, 3.0])
            .unwrap()
            .with_table("q", &[[0.0, 0.0], [2.0, 1.0], [3.0, -1.0]])
            .unwrap();
        assert_eq!(path.factor(Some("q"), 1.0), 0.5);
        assert_eq!(path.factor(Some("q"), 2.5), 0.0);
        assert_eq!(path.factor(Some("q"), 4.0), -1.0);
        assert_eq!(path.factor(Some("other"), 1.5), 0.5);
        assert!(LoadPath::at_times(0.0, vec![1.0, 1.0]).is_err());
        assert!(LoadPath::at_times(0.0, vec![1.0]).unwrap().with_table("q", &[[1.0, 0.0], [0.5, 1.0]]).is_err());
    }
}
