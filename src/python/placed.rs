//! How a batch's worlds look apart from their states: geoms and sites placed per world
//! (`Batch.set_geom_pos`, `set_site_pos`: targets and markers whose place changes from world to
//! world, drawn there and read back) and the surfaces of height fields a world has of its own.

use glam::DVec3;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use std::sync::Arc;

use crate::batch::Batch;
use crate::model::Model;
use crate::render::{Placed, Renderer, Surfaces};

/// Each placed geom or site with its position in its body's frame in every world, and the
/// worlds' own height-field surfaces.
#[derive(Default)]
pub struct Placements(Vec<(Placed, Vec<DVec3>)>, Vec<Option<Surfaces>>);

/// What one world draws differently: placed geoms and sites, its own surfaces.
pub type WorldLook = (Vec<(Placed, DVec3)>, Option<Surfaces>);

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

    /// What world `i` draws differently, for its frame.
    pub fn of_world(&self, i: usize) -> WorldLook {
        (self.0.iter().map(|(k, p)| (*k, p[i])).collect(), self.1.get(i).cloned().flatten())
    }

    /// Gives the worlds `which` of `b` the surfaces they are drawn with: their own where their
    /// height fields are (from `renderer`, asked for only then), else the model's.
    pub fn redraw(&mut self, b: &Batch, renderer: impl FnOnce() -> Arc<Renderer>, which: &[usize]) {
        if b.model.hfields.is_empty() {
            return;
        }
        let r = renderer();
        self.1.resize(b.len(), None);
        for &i in which {
            let own = b.model_of(i);
            // shared heights are the model's; a world's own copy may still equal them
            let differ = !std::sync::Arc::ptr_eq(&own.hfields, &b.model.hfields) && own.hfields != b.model.hfields;
            self.1[i] = differ.then(|| r.surfaces_for(own));
        }
    }

    /// The placed geoms and sites.
    pub fn placed(&self) -> impl Iterator<Item = Placed> + '_ {
        self.0.iter().map(|(k, _)| *k)
    }
}
