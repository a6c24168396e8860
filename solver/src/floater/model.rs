//! The floater as seen by a time integrator: mass matrix, external loads, their Jacobians and
//! the kinematics of body points (fairleads).
//!
//! Equation of motion about the reference point, global axes (see [`super::body`]):
//!
//! ```text
//! (M_rb(Λ) + M_a(Λ)) (a, α) = f(q, ν, t) = F_ext(q, ν, t) − b(ν)
//! F_ext = gravity + buoyancy (at z = 0) + strip-theory wave and drag loads
//!       + rotor thrust T along +x at the hub + (−B ν)
//! ```
//!
//! with M_a = T M_a,b Tᵀ (T = diag(Λ, Λ)) the constant strip-theory added mass rotated with the
//! body and B the spec's linear damping rotated likewise. Mooring forces are added by the caller.
//!
//! [`Floater::load_jacobians`] returns ∂f/∂ν analytically (drag, linear damping, gyroscopic
//! terms) and ∂f/∂q by central differences of f, the position variation being a translation
//! of the reference point and a spatial rotation Λ ← exp(δθ̂) Λ; the velocities are held
//! fixed in global axes while q varies. [`JacobianSteps::include_wave_terms`] = false restricts
//! the differences to the sea-independent loads (12 sea evaluations fewer per call). The
//! dependence of the mass matrix on Λ is not differentiated. Typical use in a Newton loop:
//! residual r = M(q) ν̇ − f(q, ν, t) − Σ fairlead loads ([`super::body::fairlead_load`]),
//! iteration matrix M − β'h² (∂f/∂q + Σ ∂F_line/∂q) − γ'h ∂f/∂ν.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use super::body::{point_kinematics, BodyState, MassProperties, PointKinematics, Wrench};
use super::error::FloaterError;
use super::hydrostatics::{
    submerged_cylinder, waterplane_section, Buoyancy, HydrostaticProperties,
};
use super::members::{Member, MemberId};
use super::spec::FloaterSpec;
use crate::beam::rotation::exp_so3;
use crate::waves::SeaKinematics;

/// How the position Jacobian is formed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianSteps {
    /// Translation step (m).
    pub translation_m: f64,
    /// Rotation step (rad).
    pub rotation_rad: f64,
    /// Whether the position derivative of the wave and drag loads (through the sampling points
    /// of the wave kinematics) is included. Without it, ∂f/∂q differentiates only gravity,
    /// buoyancy, thrust, linear damping and the inertial terms, which avoids 12 evaluations of
    /// the sea per call; Newton then converges linearly but to the same solution.
    pub include_wave_terms: bool,
}

impl Default for JacobianSteps {
    fn default() -> Self {
        Self {
            translation_m: 1e-3,
            rotation_rad: 1e-5,
            include_wave_terms: true,
        }
    }
}

/// External loads split by origin, each about the reference point in global axes (F, M).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoadBreakdown {
    /// Weight of the body (N, N m).
    pub gravity: Vector6<f64>,
    /// Buoyancy on the still water level.
    pub hydrostatic: Vector6<f64>,
    /// Strip-theory wave loads (Froude–Krylov, diffraction, end pressures, axial inertia).
    pub wave_inertia: Vector6<f64>,
    /// Quadratic drag (transverse and axial) with the relative velocity.
    pub drag: Vector6<f64>,
    /// Rotor thrust.
    pub wind: Vector6<f64>,
    /// Additional linear damping.
    pub linear_damping: Vector6<f64>,
}

impl LoadBreakdown {
    /// Sum of all parts.
    pub fn total(&self) -> Vector6<f64> {
        self.gravity
            + self.hydrostatic
            + self.wave_inertia
            + self.drag
            + self.wind
            + self.linear_damping
    }
}

/// Derivatives of the right-hand side f = F_ext − b.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadJacobians {
    /// ∂f/∂q (translation, spatial rotation) (N/m, N/rad, N m/m, N m/rad).
    pub position: Matrix6<f64>,
    /// ∂f/∂ν (N s/m, ...).
    pub velocity: Matrix6<f64>,
}

/// Rigid 6-DOF floater with strip-theory hydrodynamics; immutable once built.
#[derive(Debug, Clone, PartialEq)]
pub struct Floater {
    members: Vec<Member>,
    mass: MassProperties,
    rho: f64,
    gravity: f64,
    hub_height_m: f64,
    linear_damping_body: Matrix6<f64>,
    added_mass_body: Matrix6<f64>,
    hydrostatics: HydrostaticProperties,
    steps: JacobianSteps,
}

fn diag(i: &super::spec::PrincipalInertia) -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(i.roll, i.pitch, i.yaw))
}

fn rotate6(m: &Matrix6<f64>, rot: &Matrix3<f64>) -> Matrix6<f64> {
    let mut t = Matrix6::zeros();
    t.fixed_view_mut::<3, 3>(0, 0).copy_from(rot);
    t.fixed_view_mut::<3, 3>(3, 3).copy_from(rot);
    t * m * t.transpose()
}

impl Floater {
    /// Builds the floater from a validated description.
    pub fn from_spec(spec: &FloaterSpec) -> Result<Self, FloaterError> {
        let resolved = spec.resolve_members()?;
        let members: Vec<Member> = resolved
            .iter()
            .map(|r| Member::new(r, spec.strip_length()))
            .collect();
        let mut parts = vec![(
            spec.mass_kg,
            Vector3::from(spec.centre_of_mass_m),
            diag(&spec.inertia_about_com_kg_m2),
        )];
        for m in &spec.attached_masses {
            let j = m
                .inertia_about_com_kg_m2
                .as_ref()
                .map(diag)
                .unwrap_or_else(Matrix3::zeros);
            parts.push((m.mass_kg, Vector3::from(m.centre_of_mass_m), j));
        }
        let mass = MassProperties::combine(&parts);
        let rho = spec.water_density();
        let linear_damping_body = spec
            .linear_damping
            .map(|b| Matrix6::from_fn(|i, j| b[i][j]))
            .unwrap_or_else(Matrix6::zeros);
        let mut added_mass_body = Matrix6::zeros();
        for m in &members {
            m.add_added_mass(rho, &mut added_mass_body);
        }
        let hydrostatics = hydrostatic_properties(&members);
        Ok(Self {
            members,
            mass,
            rho,
            gravity: spec.gravity(),
            hub_height_m: spec.hub_height_m.unwrap_or(0.0),
            linear_damping_body,
            added_mass_body,
            hydrostatics,
            steps: JacobianSteps::default(),
        })
    }

    /// Same floater with other finite-difference steps for [`Floater::load_jacobians`].
    pub fn with_jacobian_steps(mut self, steps: JacobianSteps) -> Self {
        self.steps = steps;
        self
    }

    /// Same floater with the MacCamy–Fuchs correction of every member's transverse wave inertia
    /// for waves of period `period_s` in water of depth `depth_m` (see [`super::diffraction`]).
    pub fn with_maccamy_fuchs(mut self, period_s: f64, depth_m: f64) -> Result<Self, FloaterError> {
        if !(period_s.is_finite() && period_s > 0.0) {
            return Err(FloaterError::field(
                "maccamy_fuchs.period_s",
                period_s,
                "must be > 0",
            ));
        }
        if !(depth_m.is_finite() && depth_m > 0.0) {
            return Err(FloaterError::field(
                "maccamy_fuchs.depth_m",
                depth_m,
                "must be > 0",
            ));
        }
        let k = super::diffraction::wave_number(
            2.0 * std::f64::consts::PI / period_s,
            depth_m,
            self.gravity,
        );
        for m in &mut self.members {
            m.inertia_factor =
                0.5 * super::diffraction::inertia_coefficient(0.5 * k * m.diameter_m);
        }
        Ok(self)
    }

    /// Members.
    pub fn members(&self) -> &[Member] {
        &self.members
    }

    /// One member.
    pub fn member(&self, id: MemberId) -> Option<&Member> {
        self.members.get(id.0)
    }

    /// Combined mass properties (platform and attached masses), body axes.
    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }

    /// Water density (kg/m³).
    pub fn water_density(&self) -> f64 {
        self.rho
    }

    /// Gravity (m/s²).
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// Hub height above the reference point (m).
    pub fn hub_height_m(&self) -> f64 {
        self.hub_height_m
    }

    /// Strip-theory added mass about the reference point, body axes (undisplaced, still water).
    pub fn added_mass_body(&self) -> &Matrix6<f64> {
        &self.added_mass_body
    }

    /// Waterplane and displacement of the undisplaced body.
    pub fn hydrostatics(&self) -> &HydrostaticProperties {
        &self.hydrostatics
    }

    /// Linear hydrostatic-and-gravity restoring matrix of the undisplaced body.
    pub fn restoring_matrix(&self) -> Matrix6<f64> {
        self.hydrostatics.restoring_matrix(
            self.rho,
            self.gravity,
            self.mass.mass_kg,
            &self.mass.centre_of_mass_m,
        )
    }

    /// Total (rigid + added) mass matrix about the reference point, global axes.
    pub fn mass_matrix(&self, state: &BodyState) -> Matrix6<f64> {
        self.mass.mass_matrix(&state.rotation) + rotate6(&self.added_mass_body, &state.rotation)
    }

    /// Submerged volume and centre of buoyancy below z = 0 in the current pose.
    pub fn buoyancy(&self, state: &BodyState) -> Buoyancy {
        let mut total = Buoyancy::default();
        for m in &self.members {
            let (a, b) = m.global_ends(state);
            total.add(&submerged_cylinder(&a, &b, 0.5 * m.diameter_m));
        }
        total
    }

    /// All external loads, split by origin, for the state at time `t` in the sea `sea` with
    /// rotor thrust `wind_thrust_n` (N, along +x at the hub).
    pub fn loads<S: SeaKinematics + ?Sized>(
        &self,
        state: &BodyState,
        sea: &S,
        t: f64,
        wind_thrust_n: f64,
    ) -> LoadBreakdown {
        self.loads_and_velocity_jacobian(state, sea, t, wind_thrust_n, None)
    }

    fn loads_and_velocity_jacobian<S: SeaKinematics + ?Sized>(
        &self,
        state: &BodyState,
        sea: &S,
        t: f64,
        wind_thrust_n: f64,
        mut jac: Option<&mut Matrix6<f64>>,
    ) -> LoadBreakdown {
        let mut out = LoadBreakdown::default();
        let g = self.gravity;

        let mut w = Wrench::default();
        let weight = Vector3::new(0.0, 0.0, -self.mass.mass_kg * g);
        w.add_at(&weight, &(state.rotation * self.mass.centre_of_mass_m));
        out.gravity = w.to_vector6();

        let buoy = self.buoyancy(state);
        let mut w = Wrench::default();
        if buoy.volume_m3 > 0.0 {
            w.add_at(
                &Vector3::new(0.0, 0.0, self.rho * g * buoy.volume_m3),
                &(buoy.centre_m - state.position_m),
            );
        }
        out.hydrostatic = w.to_vector6();

        let (mut inertia, mut drag) = (Wrench::default(), Wrench::default());
        for m in &self.members {
            m.add_hydrodynamic_loads(
                state,
                sea,
                t,
                self.rho,
                &mut inertia,
                &mut drag,
                jac.as_deref_mut(),
            );
        }
        out.wave_inertia = inertia.to_vector6();
        out.drag = drag.to_vector6();

        let mut w = Wrench::default();
        w.add_at(
            &Vector3::new(wind_thrust_n, 0.0, 0.0),
            &(state.rotation * Vector3::new(0.0, 0.0, self.hub_height_m)),
        );
        out.wind = w.to_vector6();

        let b = rotate6(&self.linear_damping_body, &state.rotation);
        out.linear_damping = -(b * state.velocity6());
        if let Some(j) = jac {
            *j -= b;
        }
        out
    }

    /// Velocity-dependent inertial terms b(ν) of the rigid body.
    pub(crate) fn inertial_bias(&self, state: &BodyState) -> Vector6<f64> {
        self.mass.inertial_bias(state)
    }

    /// Right-hand side f = F_ext − b of the equation of motion.
    pub fn net_forces<S: SeaKinematics + ?Sized>(
        &self,
        state: &BodyState,
        sea: &S,
        t: f64,
        wind_thrust_n: f64,
    ) -> Vector6<f64> {
        self.loads(state, sea, t, wind_thrust_n).total() - self.inertial_bias(state)
    }

    /// The part of f that does not sample the sea: gravity, buoyancy, thrust, linear damping,
    /// minus the inertial terms.
    fn sea_independent_forces(&self, state: &BodyState, wind_thrust_n: f64) -> Vector6<f64> {
        let mut w = Wrench::default();
        let g = self.gravity;
        w.add_at(
            &Vector3::new(0.0, 0.0, -self.mass.mass_kg * g),
            &(state.rotation * self.mass.centre_of_mass_m),
        );
        let buoy = self.buoyancy(state);
        if buoy.volume_m3 > 0.0 {
            w.add_at(
                &Vector3::new(0.0, 0.0, self.rho * g * buoy.volume_m3),
                &(buoy.centre_m - state.position_m),
            );
        }
        w.add_at(
            &Vector3::new(wind_thrust_n, 0.0, 0.0),
            &(state.rotation * Vector3::new(0.0, 0.0, self.hub_height_m)),
        );
        let b = rotate6(&self.linear_damping_body, &state.rotation);
        w.to_vector6() - b * state.velocity6() - self.inertial_bias(state)
    }

    /// ∂f/∂q (central differences) and ∂f/∂ν (analytic) of [`Floater::net_forces`].
    pub fn load_jacobians<S: SeaKinematics + ?Sized>(
        &self,
        state: &BodyState,
        sea: &S,
        t: f64,
        wind_thrust_n: f64,
    ) -> LoadJacobians {
        let mut velocity = Matrix6::zeros();
        self.loads_and_velocity_jacobian(state, sea, t, wind_thrust_n, Some(&mut velocity));
        velocity -= self.mass.inertial_bias_velocity_jacobian(state);
        let mut position = Matrix6::zeros();
        for j in 0..6 {
            let h = if j < 3 {
                self.steps.translation_m
            } else {
                self.steps.rotation_rad
            };
            let perturb = |sign: f64| {
                let mut s = *state;
                if j < 3 {
                    s.position_m[j] += sign * h;
                } else {
                    let mut th = Vector3::zeros();
                    th[j - 3] = sign * h;
                    s.rotation = exp_so3(&th) * state.rotation;
                }
                if self.steps.include_wave_terms {
                    self.net_forces(&s, sea, t, wind_thrust_n)
                } else {
                    self.sea_independent_forces(&s, wind_thrust_n)
                }
            };
            let col = (perturb(1.0) - perturb(-1.0)) / (2.0 * h);
            position.set_column(j, &col);
        }
        LoadJacobians { position, velocity }
    }

    /// Position, velocity and acceleration of a body point (fairlead) for the state and the
    /// generalised acceleration (a, α).
    pub fn point_kinematics(
        &self,
        state: &BodyState,
        acceleration: &Vector6<f64>,
        body_point: &Vector3<f64>,
    ) -> PointKinematics {
        point_kinematics(state, acceleration, body_point)
    }
}

fn hydrostatic_properties(members: &[Member]) -> HydrostaticProperties {
    let mut buoy = Buoyancy::default();
    let mut wp = [0.0; 6];
    for m in members {
        buoy.add(&submerged_cylinder(&m.from_m, &m.to_m, 0.5 * m.diameter_m));
        if let Some(s) = waterplane_section(&m.from_m, &m.to_m, 0.5 * m.diameter_m) {
            wp[0] += s[0];
            wp[1] += s[0] * s[1];
            wp[2] += s[0] * s[2];
            for k in 3..6 {
                wp[k] += s[k];
            }
        }
    }
    let area = wp[0];
    let centroid = if area > 0.0 {
        [wp[1] / area, wp[2] / area]
    } else {
        [0.0, 0.0]
    };
    HydrostaticProperties {
        volume_m3: buoy.volume_m3,
        centre_of_buoyancy_m: buoy.centre_m,
        waterplane_area_m2: area,
        waterplane_centroid_m: centroid,
        waterplane_moments_m4: [wp[3], wp[4], wp[5]],
    }
}
