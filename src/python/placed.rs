//! Geoms and sites a batch places per world (`Batch.set_geom_pos`, `set_site_pos`): targets and
//! markers whose place changes from world to world, drawn there and read back.

use glam::DVec3;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::model::Model;
use crate::render::Placed;

/// Each placed geom or site with its position in its body's frame in every world.
#[derive(Default)]
pub struct Placements(Vec<(Placed, Vec<DVec3>)>);

impl Placements {
    /// A `ValueError` unless `what` is a geom or site of `m`.
    pub fn check(m: &Model, what: Placed) -> PyResult<()> {
        let (i, n, kind) = match what {
            Placed::Geom(g) => (g, m.ngeom, "geom"),
            Placed::Site(s) => (s, m.site_body.len(), "site"),
        };
        if i >= n {
            return Err(PyValueError::new_err(format!("{kind} {i} out of range for {n} {kind}s")));
        }
        Ok(())
    }

    /// Puts `what` at `rows` (3 numbers per world of `which`) in the worlds `which` of `n`.
    pub fn place(&mut self, m: &Model, n: usize, what: Placed, which: &[usize], rows: &[f64]) {
        let at = match self.0.iter().position(|(k, _)| *k == what) {
            Some(k) => k,
            None => {
                self.0.push((what, vec![what.model_pos(m); n]));
                self.0.len() - 1
            }
        };
        for (k, &i) in which.iter().enumerate() {
            self.0[at].1[i] = DVec3::from_slice(&rows[3 * k..3 * k + 3]);
        }
    }

    /// Where `what` sits in its body's frame in each of `n` worlds (n, 3).
    pub fn positions<'py>(&self, py: Python<'py>, m: &Model, n: usize, what: Placed) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<f64> = match self.0.iter().find(|(k, _)| *k == what) {
            Some((_, p)) => p.iter().flat_map(|v| v.to_array()).collect(),
            None => (0..n).flat_map(|_| what.model_pos(m).to_array()).collect(),
        };
        PyArray1::from_vec(py, rows).reshape([n, 3])
    }

    /// What world `i` places, for its frame.
    pub fn of_world(&self, i: usize) -> Vec<(Placed, DVec3)> {
        self.0.iter().map(|(k, p)| (*k, p[i])).collect()
    }

    /// The placed geoms and sites.
    pub fn placed(&self) -> impl Iterator<Item = Placed> + '_ {
        self.0.iter().map(|(k, _)| *k)
    }
}
