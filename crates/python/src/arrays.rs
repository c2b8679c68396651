//! A run's last frame, its joints and their state as dicts of numpy arrays: float64 `(n, 2)`
//! for vectors and `(m, 4)` for stresses (sxx, syy, sxy, szz), int64 `(m, 3)` triangles,
//! int32 ids, the very values the run writes into its `.vtu` files.

use numpy::ndarray::Array2;
use numpy::{Element, IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use fdem_fracture::state::JointState;
use fdem_solver::output::{FrameData, JointFrame};

/// `v` as a numpy array of shape `(len, K)`.
fn rows<'py, T: Element + Copy, const K: usize>(
    py: Python<'py>,
    v: &[[T; K]],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<T> = v.iter().flatten().copied().collect();
    let a = Array2::from_shape_vec((v.len(), K), flat)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py).into_any())
}

/// `v` as a one-dimensional numpy array.
fn column<'py, T: Element + Copy>(py: Python<'py>, v: &[T]) -> Bound<'py, PyAny> {
    PyArray1::from_slice(py, v).into_any()
}

/// `v` as a numpy array of shape `(len, K)`, or None when `v` is empty (an array the frame
/// does not carry).
fn rows_or_none<'py, const K: usize>(
    py: Python<'py>,
    v: &[[f64; K]],
) -> PyResult<Bound<'py, PyAny>> {
    if v.is_empty() {
        Ok(py.None().into_bound(py))
    } else {
        rows(py, v)
    }
}

/// The frame's arrays: `time`, `points`, `triangles` (int64), `displacement`, `velocity`,
/// `force`, `reaction`, `stress`, `principal_stress`, `von_mises`,
/// `strain_energy_density`, `material`, `body` (int32), `nodal_stress`,
/// `nodal_principal_stress`, `nodal_von_mises` (None when absent), and `point_extra` /
/// `cell_extra`: dicts of the further arrays (`contact_force`, `contact_active`, `young`).
pub fn frame<'py>(py: Python<'py>, f: &FrameData) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("time", f.time)?;
    d.set_item("points", rows(py, &f.points)?)?;
    let tri: Vec<[i64; 3]> = f.triangles.iter().map(|t| t.map(i64::from)).collect();
    d.set_item("triangles", rows(py, &tri)?)?;
    d.set_item("displacement", rows(py, &f.displacement)?)?;
    d.set_item("velocity", rows(py, &f.velocity)?)?;
    d.set_item("force", rows(py, &f.force)?)?;
    d.set_item("reaction", rows(py, &f.reaction)?)?;
    d.set_item("stress", rows(py, &f.stress)?)?;
    d.set_item("principal_stress", rows(py, &f.principal)?)?;
    d.set_item("von_mises", column(py, &f.von_mises))?;
    d.set_item("strain_energy_density", column(py, &f.energy_density))?;
    d.set_item("material", column(py, &f.material))?;
    d.set_item("body", column(py, &f.body))?;
    d.set_item("nodal_stress", rows_or_none(py, &f.nodal_stress)?)?;
    d.set_item(
        "nodal_principal_stress",
        rows_or_none(py, &f.nodal_principal)?,
    )?;
    d.set_item(
        "nodal_von_mises",
        if f.nodal_von_mises.is_empty() {
            py.None().into_bound(py)
        } else {
            column(py, &f.nodal_von_mises)
        },
    )?;
    let point_extra = PyDict::new(py);
    for (name, v) in &f.extra_point_vectors {
        point_extra.set_item(name, rows(py, v)?)?;
    }
    d.set_item("point_extra", point_extra)?;
    let cell_extra = PyDict::new(py);
    for (name, v) in &f.extra_cell_scalars {
        cell_extra.set_item(name, column(py, v))?;
    }
    d.set_item("cell_extra", cell_extra)?;
    Ok(d)
}

/// The joints of the frame, one entry per joint, as the `joints_NNNN.vtu` series holds them:
/// `points` (`(2 n, 2)`: the line of joint `j` from row `2 j` to `2 j + 1`), `damage`,
/// `mode`, `mode_mix`, `broken`, `time_of_failure`, `opening`, `sliding`, `normal_traction`,
/// `shear_traction` and, where the joints differ in material, `tensile_strength`, `cohesion`,
/// `fracture_energy_i`, `fracture_energy_ii`.
pub fn joints<'py>(py: Python<'py>, j: &JointFrame) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("points", rows(py, &j.points)?)?;
    d.set_item("damage", column(py, &j.damage))?;
    d.set_item("mode", column(py, &j.mode))?;
    d.set_item("mode_mix", column(py, &j.mode_mix))?;
    d.set_item("broken", column(py, &j.broken))?;
    d.set_item("time_of_failure", column(py, &j.time_of_failure))?;
    d.set_item("opening", column(py, &j.opening))?;
    d.set_item("sliding", column(py, &j.sliding))?;
    d.set_item("normal_traction", column(py, &j.normal_traction))?;
    d.set_item("shear_traction", column(py, &j.shear_traction))?;
    if let Some(p) = &j.properties {
        d.set_item("tensile_strength", column(py, &p.tensile_strength))?;
        d.set_item("cohesion", column(py, &p.cohesion))?;
        d.set_item("fracture_energy_i", column(py, &p.fracture_energy_i))?;
        d.set_item("fracture_energy_ii", column(py, &p.fracture_energy_ii))?;
    }
    Ok(d)
}

/// The joints' committed history at the end of the run, one row per joint:
/// `point_damage` and `point_mode_mix` (`(n, 2)`: the joint's two integration points),
/// `broken` (bool), `broken_at` (the time of the break [s], NaN while intact), `work`,
/// `stored`, `dissipated` [J].
pub fn joint_state<'py>(py: Python<'py>, s: &JointState) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let b = s.books();
    let (damage, mix) = (&s.history.damage, &s.history.mode_mix);
    let broken: Vec<bool> = s.intact.iter().map(|i| !i).collect();
    let broken_at: Vec<f64> = s.broken_at.iter().map(|t| t.unwrap_or(f64::NAN)).collect();
    d.set_item("point_damage", rows(py, damage)?)?;
    d.set_item("point_mode_mix", rows(py, mix)?)?;
    d.set_item("broken", column(py, &broken))?;
    d.set_item("broken_at", column(py, &broken_at))?;
    d.set_item("work", column(py, &b.work))?;
    d.set_item("stored", column(py, &b.stored))?;
    d.set_item("dissipated", column(py, &b.dissipated))?;
    Ok(d)
}
