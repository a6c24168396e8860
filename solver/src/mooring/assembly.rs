//! Global assembly of a line: residual R = M q̈ + f_int(q) − f_ext(q, q̇, q̈, t) and iteration
//! matrix S = ∂R/∂q + γ' ∂R/∂q̇ + β' ∂R/∂q̈ into a band matrix, element by element, plus the
//! handling of the prescribed unknowns (fairlead and anchor positions) and the energies used by
//! the verification tests.
//!
//! The rows of the prescribed unknowns keep the support reactions: at equilibrium R restricted
//! to the fairlead DOFs is the force the floater applies on the line, so the line pulls the
//! floater with −R there.

use nalgebra::Vector3;

use super::banded::BandMatrix;
use super::bar_element::{bar_potential, bar_residual, bar_system};
use super::cable_element::{
    cable_kinetic, cable_potential, cable_residual, cable_system, ElementContext, ElementValues,
    CABLE_POINTS,
};
use super::hermite::{hermite, GAUSS3};
use super::line::{ElementKind, LineModel};
use super::loads::Coefficients;
use crate::waves::{FluidKinematics, SeaKinematics};

/// Water kinematics at the quadrature points of every element (bars use the first two, at
/// their nodes).
pub(crate) type WaterCache = Vec<[FluidKinematics; CABLE_POINTS]>;

fn vec3(x: &[f64], d: usize) -> Vector3<f64> {
    Vector3::new(x[d], x[d + 1], x[d + 2])
}

/// Quadrature-point positions of element `k` of `model` in state `q`.
fn quadrature_points(model: &LineModel, k: usize, q: &[f64]) -> [Vector3<f64>; CABLE_POINTS] {
    let e = &model.elements()[k];
    let d = model.element_dofs(e);
    let mut p = [Vector3::zeros(); CABLE_POINTS];
    match e.kind {
        ElementKind::Cable => {
            for (g, &(xi, _)) in GAUSS3.iter().enumerate() {
                let s = hermite(xi, e.length_m);
                for (&dof, &n) in d.iter().zip(&s.n) {
                    p[g] += vec3(q, dof) * n;
                }
            }
        }
        ElementKind::Bar => {
            p[0] = vec3(q, d[0]);
            p[1] = vec3(q, d[1]);
            p[2] = p[1];
        }
    }
    p
}

/// Samples the sea at every quadrature point of the line in state `q` at time `t_s`.
pub(crate) fn update_water(
    model: &LineModel,
    q: &[f64],
    t_s: f64,
    sea: &dyn SeaKinematics,
    water: &mut WaterCache,
) {
    water.resize(
        model.elements().len(),
        [FluidKinematics::default(); CABLE_POINTS],
    );
    for (k, w) in water.iter_mut().enumerate() {
        let p = quadrature_points(model, k, q);
        let points = if model.elements()[k].kind == ElementKind::Bar {
            2
        } else {
            CABLE_POINTS
        };
        for g in 0..points {
            w[g] = sea.kinematics(&p[g], t_s);
        }
    }
}

/// Current values of the whole line passed to [`assemble`].
#[derive(Debug, Clone, Copy)]
pub struct StateView<'a> {
    /// Positions and gradients.
    pub q: &'a [f64],
    /// Their rates.
    pub v: &'a [f64],
    /// Their second rates.
    pub a: &'a [f64],
}

/// Assembles the residual (overwritten) and, when given, the iteration matrix (overwritten);
/// without a matrix the element tangents are not computed at all.
/// `dynamic = false` drops inertia and hydrodynamic loads (statics).
pub fn assemble(
    model: &LineModel,
    x: StateView<'_>,
    water: &WaterCache,
    coef: Coefficients,
    dynamic: bool,
    residual: &mut [f64],
    mut matrix: Option<&mut BandMatrix>,
) {
    residual.fill(0.0);
    if let Some(m) = matrix.as_deref_mut() {
        m.clear();
    }
    let env = model.environment();
    let still = [FluidKinematics::default(); CABLE_POINTS];
    for (k, e) in model.elements().iter().enumerate() {
        let ctx = ElementContext {
            sec: model.section(e),
            length_m: e.length_m,
            bed: &env.seabed,
            depth_m: env.water_depth_m,
            coef,
            dynamic,
        };
        let d = model.element_dofs(e);
        let w = water.get(k).unwrap_or(&still);
        match e.kind {
            ElementKind::Cable => {
                let vals = ElementValues {
                    q: d.map(|i| vec3(x.q, i)),
                    v: d.map(|i| vec3(x.v, i)),
                    a: d.map(|i| vec3(x.a, i)),
                };
                match matrix.as_deref_mut() {
                    Some(m) => {
                        let sys = cable_system(&ctx, &vals, w);
                        scatter(&d, &sys.r, &sys.k, residual, Some(m));
                    }
                    None => scatter_residual(&d, &cable_residual(&ctx, &vals, w), residual),
                }
            }
            ElementKind::Bar => {
                let dd = [d[0], d[1]];
                let vals = ElementValues {
                    q: dd.map(|i| vec3(x.q, i)),
                    v: dd.map(|i| vec3(x.v, i)),
                    a: dd.map(|i| vec3(x.a, i)),
                };
                match matrix.as_deref_mut() {
                    Some(m) => {
                        let sys = bar_system(&ctx, &vals, w);
                        scatter(&dd, &sys.r, &sys.k, residual, Some(m));
                    }
                    None => scatter_residual(&dd, &bar_residual(&ctx, &vals, w), residual),
                }
            }
        }
    }
}

fn scatter_residual<const NC: usize>(
    dofs: &[usize; NC],
    r: &[Vector3<f64>; NC],
    residual: &mut [f64],
) {
    for (&dof, ra) in dofs.iter().zip(r) {
        for i in 0..3 {
            residual[dof + i] += ra[i];
        }
    }
}

fn scatter<const NC: usize>(
    dofs: &[usize; NC],
    r: &[Vector3<f64>; NC],
    k: &[[nalgebra::Matrix3<f64>; NC]; NC],
    residual: &mut [f64],
    matrix: Option<&mut BandMatrix>,
) {
    for a in 0..NC {
        for i in 0..3 {
            residual[dofs[a] + i] += r[a][i];
        }
    }
    if let Some(m) = matrix {
        for a in 0..NC {
            for b in 0..NC {
                let blk = &k[a][b];
                for i in 0..3 {
                    m.add_row(
                        dofs[a] + i,
                        dofs[b],
                        &[blk[(i, 0)], blk[(i, 1)], blk[(i, 2)]],
                    );
                }
            }
        }
    }
}

/// Index and value of the largest |component| of the residual over the free unknowns.
pub(crate) fn free_residual_max(model: &LineModel, residual: &[f64]) -> (usize, f64) {
    let mut worst = (0, 0.0);
    for (i, &r) in residual.iter().enumerate() {
        if model.is_constrained(i) {
            continue;
        }
        if !r.is_finite() {
            return (i, f64::INFINITY);
        }
        if r.abs() > worst.1 {
            worst = (i, r.abs());
        }
    }
    worst
}

/// Elastic energy plus the potential of weight and seabed springs of state `q` (J).
pub fn potential_energy(model: &LineModel, q: &[f64]) -> f64 {
    let env = model.environment();
    model
        .elements()
        .iter()
        .map(|e| {
            let ctx = ElementContext {
                sec: model.section(e),
                length_m: e.length_m,
                bed: &env.seabed,
                depth_m: env.water_depth_m,
                coef: Coefficients::default(),
                dynamic: false,
            };
            let d = model.element_dofs(e);
            match e.kind {
                ElementKind::Cable => cable_potential(&ctx, &d.map(|i| vec3(q, i))),
                ElementKind::Bar => bar_potential(&ctx, &[vec3(q, d[0]), vec3(q, d[1])]),
            }
        })
        .sum()
}

/// Kinetic energy of the structural mass (added mass excluded) at rates `v` (J).
pub fn kinetic_energy(model: &LineModel, v: &[f64]) -> f64 {
    model
        .elements()
        .iter()
        .map(|e| {
            let sec = model.section(e);
            let d = model.element_dofs(e);
            match e.kind {
                ElementKind::Cable => cable_kinetic(sec, e.length_m, &d.map(|i| vec3(v, i))),
                ElementKind::Bar => {
                    0.25 * sec.mass_kg_per_m
                        * e.length_m
                        * (vec3(v, d[0]).norm_squared() + vec3(v, d[1]).norm_squared())
                }
            }
        })
        .sum()
}
