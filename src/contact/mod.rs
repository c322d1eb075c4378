//! Contacts between contact bodies (wheels, gliders) and the track: the
//! beam's top surface, or rigid ground before and after the beam.
//!
//! The foot point d of the perpendicular from the body's centre on the
//! deformed neutral axis, the contact frame (t, n) there, the gap error g and
//! the velocity error e of METHOD.md.
//!
//! Kinematics and loads form the *exact pair* of METHOD.md: the normal row is
//! the time derivative of the exact gap g = n·(centre − d) − (r + h), so the
//! normal force passes through the neutral axis and puts no moment on the
//! section; the tangential row is the paper's small-deformation surface
//! velocity (eq. 7) rotated into the frame. The beam load is the transpose of
//! the same rows (`ContactFrame::beam_rows`), so the contact does no work
//! whenever e = 0.

use nalgebra::{DVector, Vector2, Vector3};

use crate::beam::{Beam, Shape};
use crate::body::{is_centre, BodyState, ContactRotations};
use crate::contact_law::LawKind;
use crate::profile::Profile;

#[macro_use]
pub mod law_spec;
pub mod law;
pub mod loads;

/// What touches the track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactKind {
    /// Rigid disc rolling without slip: a tangential and a normal row.
    Wheel { radius: f64 },
    /// Point body gliding at the surface (r = 0): a normal row only; its
    /// tangential force is exactly zero.
    Glider,
}

/// One contact: a contact body and how it touches the track.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Prefix of the contact's outputs (`contact`, `vehicle1.wheelset2`, ...).
    pub name: String,
    /// Index of the contact body in `System::bodies`.
    pub body: usize,
    pub kind: ContactKind,
    /// A massless follower: the force is the suspension's, not a
    /// constraint's (`None` for a contact body with mass).
    pub follower: Option<Follower>,
}

/// The massless follower of the moving-oscillator literature: a contact
/// point without mass under a body's vertical spring–damper. Having no
/// inertia it moves with the surface, so its normal force is whatever the
/// suspension transmits, P = preload − k (g − rest) − c ġ, with g the
/// gap between the body's centre and the surface. It is computed from the
/// state wherever loads are (each integrator stage), not solved by the
/// contact iteration: it is a known function of the state, so the
/// iteration holds it open (no rows) rather than adding a force-law row.
/// The follower cannot pull: where the law gives tension the force is 0
/// (the suspension goes slack; exact for c = 0, where the massless point
/// hangs at the spring's length and lands again where the law turns
/// compressive; with c > 0 it neglects the damper's relaxation in flight).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Follower {
    pub stiffness: f64,
    pub damping: f64,
    pub preload: f64,
    /// The gap at which the suspension carries exactly its preload (m).
    pub rest: f64,
    /// Where the suspension meets its body, in body coordinates (m): the
    /// body's centre for a sprung mass, a bogie's axle or a car body's
    /// magnet station for the presets. Its gap, rate and force are that
    /// point's, so the force also puts a torque on a pitching body.
    pub attachment: Vector2<f64>,
    /// The law: the suspension's, or a compliant contact law of a body
    /// with mass (`contact_law`).
    pub kind: LawKind,
}

impl Follower {
    /// Normal force (N, compression positive) at gap `gap` and gap rate `rate`.
    pub fn force(&self, gap: f64, rate: f64) -> f64 {
        self.law(gap, rate).max(0.0)
    }

    /// The suspension's law before the cut at zero: negative where the
    /// suspension would pull (the follower is slack, its contact open).
    pub fn law(&self, gap: f64, rate: f64) -> f64 {
        self.kind.force(self, gap, rate)
    }

    /// Potential energy of its spring at gap `gap` (J), zero at rest
    /// (each law's beside its force, `LawKind::potential_energy`).
    pub fn potential_energy(&self, gap: f64) -> f64 {
        self.kind.potential_energy(self, gap)
    }

    /// Power its damper dissipates at gap `gap` and rate `rate`: what the
    /// follower's work leaves after its spring's share, so that spring
    /// energy plus dissipation change by exactly that work (P ġ taken
    /// from the bodies). With E = preload − k δ the spring's force (its
    /// potential is flat where E < 0): (max(E, 0) − P) ġ. Carrying load
    /// with E ≥ 0 that is c ġ²; with E < 0 (c > 0, closing) −P ġ; slack
    /// it is max(E, 0) ġ, the compressed spring's energy that the damper's
    /// relaxation, which the force law neglects, takes. Never negative.
    pub fn dissipation(&self, gap: f64, rate: f64) -> f64 {
        let elastic = self.kind.elastic_force(self, gap);
        (elastic.max(0.0) - self.force(gap, rate)) * rate
    }
}

impl Contact {
    /// Whether it is a follower attached off its body's centre (several
    /// may share the body).
    pub fn is_attached(&self) -> bool {
        self.attachment().is_some()
    }

    /// A follower's attachment point off its body's centre, in body
    /// coordinates; `None` at the centre or for a contact body.
    #[inline]
    fn attachment(&self) -> Option<&Vector2<f64>> {
        match &self.follower {
            Some(f) if !is_centre(&f.attachment) => Some(&f.attachment),
            _ => None,
        }
    }

    /// The state of the point that touches the track: the body's own, or
    /// a follower's attachment point (its velocity v + ω × r).
    pub fn point(&self, body: &BodyState) -> BodyState {
        match self.attachment() {
            Some(local) => point_at(body, &body.offset_of(local)),
            None => *body,
        }
    }

    /// `point` of `body` (this contact's body, in the configuration
    /// `rotations` is kept for), its rotation taken from `rotations`: the
    /// same bits, one sine and cosine per body in a pass over contacts.
    #[inline]
    pub fn point_turned(&self, body: &BodyState, rotations: &mut ContactRotations) -> BodyState {
        match self.attachment() {
            Some(local) => point_at(body, &rotations.offset_of(self.body, body, local)),
            None => *body,
        }
    }

    /// The torque about the body's centre of a force `force` at the
    /// contact point (nonzero for a follower attached off the centre).
    pub fn torque(&self, body: &BodyState, force: &Vector2<f64>) -> f64 {
        match self.attachment() {
            Some(local) => moment(&body.offset_of(local), force),
            None => 0.0,
        }
    }

    /// `torque` with the rotation from `rotations` (see `point_turned`).
    #[inline]
    pub fn torque_turned(
        &self,
        body: &BodyState,
        force: &Vector2<f64>,
        rotations: &mut ContactRotations,
    ) -> f64 {
        match self.attachment() {
            Some(local) => moment(&rotations.offset_of(self.body, body, local), force),
            None => 0.0,
        }
    }

    pub fn radius(&self) -> f64 {
        match self.kind {
            ContactKind::Wheel { radius } => radius,
            ContactKind::Glider => 0.0,
        }
    }
    /// Whether the contact has a tangential (no-slip) row.
    pub fn rolls(&self) -> bool {
        matches!(self.kind, ContactKind::Wheel { .. })
    }
    /// Its rows in the iteration: tangential (wheels) then normal.
    pub fn rows(&self) -> usize {
        if self.rolls() {
            2
        } else {
            1
        }
    }
}

/// The state of the point of `body` at world offset `r` from its centre.
#[inline]
fn point_at(body: &BodyState, r: &Vector2<f64>) -> BodyState {
    BodyState {
        position: body.position + r,
        velocity: body.velocity + body.angular_velocity * Vector2::new(-r.y, r.x),
        ..*body
    }
}

/// The moment r × f about the centre of a force `f` at offset `r`.
#[inline]
fn moment(r: &Vector2<f64>, force: &Vector2<f64>) -> f64 {
    r.x * force.y - r.y * force.x
}

/// Contact force on the body in the contact frame (N): tangential and normal
/// components. The beam receives the opposite force.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ContactForce {
    pub tangential: f64,
    pub normal: f64,
}

impl ContactForce {
    pub fn as_vector(&self) -> Vector2<f64> {
        Vector2::new(self.tangential, self.normal)
    }
    pub fn from_vector(v: Vector2<f64>) -> ContactForce {
        ContactForce {
            tangential: v.x,
            normal: v.y,
        }
    }
}

/// The contact frame at the foot point, and the constraint rows there.
#[derive(Debug, Clone, Copy)]
pub struct ContactFrame {
    /// Abscissa x_d of the foot point (m).
    pub x: f64,
    pub shape: Shape,
    /// w(x_d), w'(x_d), w''(x_d) of the deformed neutral axis.
    pub deflection: f64,
    pub slope: f64,
    pub curvature: f64,
    pub cos: f64,
    pub sin: f64,
    /// False on rigid ground: the shape is then empty (no beam DOFs).
    pub on_beam: bool,
}

/// Why the foot point could not be found.
#[derive(Debug, Clone, PartialEq)]
pub struct FootPointError {
    pub last_x: f64,
}

impl ContactFrame {
    /// Unit tangent t = (cos φ, sin φ).
    pub fn tangent(&self) -> Vector2<f64> {
        Vector2::new(self.cos, self.sin)
    }
    /// Unit normal n = (−sin φ, cos φ).
    pub fn normal(&self) -> Vector2<f64> {
        Vector2::new(-self.sin, self.cos)
    }

    /// Rows over the element's four DOFs giving the beam surface velocity at
    /// the contact in the frame: (v_ct, v_cn) = (t_row · u̇, n_row · u̇).
    pub fn beam_rows(&self, surface_offset: f64) -> ([f64; 4], [f64; 4]) {
        let s = &self.shape;
        let mut t_row = [0.0; 4];
        let mut n_row = [0.0; 4];
        for k in 0..4 {
            t_row[k] = self.sin * s.n[k] - surface_offset * self.cos * s.dn[k];
            n_row[k] = self.cos * s.n[k];
        }
        (t_row, n_row)
    }

    /// Rows over (ẋ, ẏ, θ̇) giving the rim point's velocity in the frame.
    pub fn body_rows(&self, radius: f64) -> (Vector3<f64>, Vector3<f64>) {
        (
            Vector3::new(self.cos, self.sin, radius),
            Vector3::new(-self.sin, self.cos, 0.0),
        )
    }

    /// Velocity error e = rim velocity − surface velocity, in the frame (m/s).
    #[inline]
    pub fn velocity_error(
        &self,
        beam: &Beam,
        radius: f64,
        state: &BodyState,
        beam_velocity: &DVector<f64>,
    ) -> Vector2<f64> {
        let (bt, bn) = self.body_rows(radius);
        let q = Vector3::new(state.velocity.x, state.velocity.y, state.angular_velocity);
        let (vt, vn) = self.surface_velocity(beam, beam_velocity);
        Vector2::new(bt.dot(&q) - vt, bn.dot(&q) - vn)
    }

    /// A follower's gap and gap rate: `gap` and `velocity_error(..).y` of
    /// the point `state` without radius, the tangential error not formed
    /// (the same bits; the iteration asks this of every follower at every
    /// integration).
    #[inline]
    pub fn gap_and_rate(
        &self,
        beam: &Beam,
        state: &BodyState,
        beam_velocity: &DVector<f64>,
    ) -> (f64, f64) {
        let gap = self.gap(beam, 0.0, &state.position);
        let (_, bn) = self.body_rows(0.0);
        let q = Vector3::new(state.velocity.x, state.velocity.y, state.angular_velocity);
        let vn = self.surface_normal_velocity(beam, beam_velocity);
        (gap, bn.dot(&q) - vn)
    }

    /// `surface_velocity(..).1` alone: the normal row and its product with
    /// the field, the same operations (`Beam::dot` is `Beam::dot_rows`'
    /// second product), without the tangential row a follower drops (a
    /// quarter of its gap rate's cost).
    #[inline(always)]
    fn surface_normal_velocity(&self, beam: &Beam, beam_velocity: &DVector<f64>) -> f64 {
        if self.shape.dofs.iter().all(Option::is_none) && beam.modal().is_none() {
            return std::iter::empty::<f64>().sum();
        }
        let n_row = self.shape.n.map(|n| self.cos * n);
        beam.dot(&self.shape, &n_row, beam_velocity)
    }

    /// The surface's velocity along the frame's rows (t_row · u̇, n_row · u̇).
    #[inline(always)]
    fn surface_velocity(&self, beam: &Beam, beam_velocity: &DVector<f64>) -> (f64, f64) {
        // On rigid ground (no DOFs) the rows are not built: `Shape::dot`
        // would sum nothing, and the empty sum is taken for the same bits.
        if self.shape.dofs.iter().all(Option::is_none) && beam.modal().is_none() {
            let nothing: f64 = std::iter::empty::<f64>().sum();
            (nothing, nothing)
        } else {
            let (t_row, n_row) = self.beam_rows(beam.surface_offset);
            beam.dot_rows(&self.shape, (&t_row, &n_row), beam_velocity)
        }
    }

    /// Gap error g = n·(centre − d) − (r + h) (m); negative is penetration.
    pub fn gap(&self, beam: &Beam, radius: f64, centre: &Vector2<f64>) -> f64 {
        let d = Vector2::new(self.x, self.deflection);
        self.normal().dot(&(centre - d)) - (radius + beam.surface_offset)
    }

    /// Nominal travel speed V = ẋ_centre + (r + h) φ̇ (METHOD.md, eq. 24), with
    /// φ̇ the total rate of the surface angle at the moving foot point.
    pub fn nominal_speed(
        &self,
        beam: &Beam,
        radius: f64,
        state: &BodyState,
        beam_velocity: &DVector<f64>,
    ) -> f64 {
        let s = &self.shape;
        let (w_rate, slope_rate) = beam.dot_rows(s, (&s.n, &s.dn), beam_velocity);
        let height = state.position.y - self.deflection;
        // d/dt of the foot-point condition (X − x) + (Y − w(x)) w'(x) = 0.
        let foot_speed =
            (state.velocity.x + (state.velocity.y - w_rate) * self.slope + height * slope_rate)
                / (1.0 + self.slope * self.slope - height * self.curvature);
        let angle_rate =
            (slope_rate + self.curvature * foot_speed) / (1.0 + self.slope * self.slope);
        state.velocity.x + (radius + beam.surface_offset) * angle_rate
    }

    /// The frame at a corner of the track: the point (`x`, 0) (a beam end,
    /// held by its support) seen from `centre`; no beam DOFs.
    pub fn at_corner(x: f64, centre: &Vector2<f64>) -> ContactFrame {
        let offset = centre - Vector2::new(x, 0.0);
        let distance = offset.norm();
        // A point body on the neutral axis (r + h = 0) has no corner to
        // turn about.
        if distance.is_nan() || distance <= 1e-9 * x.abs().max(1.0) || offset.y <= 0.0 {
            return ContactFrame::on_ground(centre);
        }
        let n = offset / distance;
        ContactFrame {
            x,
            slope: -n.x / n.y,
            cos: n.y,
            sin: -n.x,
            ..ContactFrame::on_ground(centre)
        }
    }

    /// The frame on rigid ground (level with the undeformed beam's neutral
    /// axis, surface at h) below `centre`: no beam DOFs.
    pub fn on_ground(centre: &Vector2<f64>) -> ContactFrame {
        ContactFrame {
            x: centre.x,
            shape: Shape {
                element: 0,
                dofs: [None; 4],
                n: [0.0; 4],
                dn: [0.0; 4],
                ddn: [0.0; 4],
            },
            deflection: 0.0,
            slope: 0.0,
            curvature: 0.0,
            cos: 1.0,
            sin: 0.0,
            on_beam: false,
        }
    }

    /// The frame on rigid ground carrying the irregularity `profile`: the
    /// foot of the perpendicular from `centre` on y = r(x), found by
    /// Newton's method from below the centre.
    pub fn on_profile(
        profile: &Profile,
        centre: &Vector2<f64>,
    ) -> Result<ContactFrame, FootPointError> {
        let mut x = centre.x;
        for _ in 0..50 {
            let [r, slope, curvature, _] = profile.at(x);
            let height = centre.y - r;
            let residual = (centre.x - x) + height * slope;
            let derivative = -1.0 - slope * slope + height * curvature;
            if !(derivative.is_finite() && residual.is_finite()) || derivative.abs() < 1e-12 {
                return Err(FootPointError { last_x: x });
            }
            // The foot lies within |height × slope| of the centre's abscissa.
            let trust = height.abs().max(1e-3);
            let dx = (-residual / derivative).clamp(-trust, trust);
            if dx.abs() <= 1e-14 * x.abs().max(1.0) {
                let secant = (1.0 + slope * slope).sqrt();
                return Ok(ContactFrame {
                    x,
                    deflection: r,
                    slope,
                    curvature,
                    cos: 1.0 / secant,
                    sin: slope / secant,
                    ..ContactFrame::on_ground(centre)
                });
            }
            x += dx;
        }
        Err(FootPointError { last_x: x })
    }

    /// `at_corner` on a track carrying `profile`: the corner is the point
    /// (`x`, r(x)); where there is no corner to turn about, the ground.
    pub fn at_profile_corner(
        profile: &Profile,
        x: f64,
        centre: &Vector2<f64>,
    ) -> Result<ContactFrame, FootPointError> {
        let height = profile.at(x)[0];
        let offset = centre - Vector2::new(x, height);
        let distance = offset.norm();
        if distance.is_nan() || distance <= 1e-9 * x.abs().max(1.0) || offset.y <= 0.0 {
            return ContactFrame::on_profile(profile, centre);
        }
        let n = offset / distance;
        Ok(ContactFrame {
            x,
            deflection: height,
            slope: -n.x / n.y,
            cos: n.y,
            sin: -n.x,
            ..ContactFrame::on_ground(centre)
        })
    }
}

/// Find the foot of the perpendicular from `centre` on the deformed neutral
/// axis by Newton's method, starting at `guess` and moving across elements.
/// Beyond the beam's ends the end elements' cubics are extended, so that the
/// exit instant can be found by interpolation.
///
/// Each Newton move is limited to a trust radius of the larger of the
/// current element's length, the centre's height over the axis (≈ r + h)
/// and its horizontal distance from the iterate: the foot point lies within
/// height × slope of the centre's abscissa, so the search reaches it in a
/// few moves however many elements a step's travel spans, while on coarse
/// meshes the limit stays one element as before. The element is found from
/// the previous one (a short walk, bisection for a long move), never by a
/// scan of the mesh.
pub fn foot_point(
    beam: &Beam,
    u: &DVector<f64>,
    centre: &Vector2<f64>,
    guess: f64,
) -> Result<ContactFrame, FootPointError> {
    foot_point_on(beam, None, u, centre, guess)
}

/// `foot_point` on the deformed neutral axis raised by the irregularity
/// `profile`, y = w(x) + r(x): the frame's height, slope and curvature are
/// then those of the sum, so its normal, gap and velocity rows carry the
/// irregularity (the travel-induced surface velocity V r' enters the
/// normal row through the tilted normal).
#[inline]
pub fn foot_point_on(
    beam: &Beam,
    profile: Option<&Profile>,
    u: &DVector<f64>,
    centre: &Vector2<f64>,
    guess: f64,
) -> Result<ContactFrame, FootPointError> {
    let mut x = guess;
    let mut element = beam.element_at(x);
    // The element's field, gathered again only when the search moves on.
    let mut field = (element, beam.element_field(element, u));
    // Converged: the remaining correction is at round-off level.
    let tolerance = 1e-14 * beam.length.max(1.0);
    for _ in 0..50 {
        let axis = beam.axis_of_field(element, x, &field.1);
        let [w, slope, curvature, third] = surface(axis, profile, x);
        let height = centre.y - w;
        // f(x) = (X − x) + (Y − w) w' = 0 and its first two derivatives.
        let residual = (centre.x - x) + height * slope;
        let derivative = -1.0 - slope * slope + height * curvature;
        let second = -3.0 * slope * curvature + height * third;
        if !(derivative.is_finite() && residual.is_finite()) || derivative.abs() < 1e-12 {
            return Err(FootPointError { last_x: x });
        }
        let newton = -residual / derivative;
        // The last iterate only confirms: Halley's step is at most twice
        // Newton's (`halley_step`), so below half the tolerance the test
        // below would pass; its correction and trust are not formed.
        if newton.abs() <= 0.5 * tolerance {
            return Ok(frame_on_beam(beam, element, x, [w, slope, curvature]));
        }
        let step = halley_step(newton, derivative, second);
        let trust = beam
            .element_length(element)
            .max(height.abs())
            .max((centre.x - x).abs());
        let dx = step.clamp(-trust, trust);
        if dx.abs() <= tolerance {
            return Ok(frame_on_beam(beam, element, x, [w, slope, curvature]));
        }
        x += dx;
        // From the last element (at the guess, `element_at`'s answer is
        // already `element_near`'s: one walk fewer a search).
        element = beam.element_near(x, element);
        if field.0 != element {
            field = (element, beam.element_field(element, u));
        }
    }
    Err(FootPointError { last_x: x })
}

/// The surface's height and its three derivatives at `x`: the axis raised
/// by the profile (without a profile the axis untouched, the same bits).
#[inline(always)]
fn surface(axis: [f64; 4], profile: Option<&Profile>, x: f64) -> [f64; 4] {
    match profile {
        None => axis,
        Some(profile) => {
            let r = profile.at(x);
            [
                axis[0] + r[0],
                axis[1] + r[1],
                axis[2] + r[2],
                axis[3] + r[3],
            ]
        }
    }
}

/// Newton's step `newton` on f with Halley's correction (cubic
/// convergence: one iterate fewer from a warm start) where it is a small
/// change of Newton's: |ratio| < 1/2, so the step is at most twice
/// Newton's.
#[inline(always)]
fn halley_step(newton: f64, derivative: f64, second: f64) -> f64 {
    let ratio = 0.5 * newton * second / derivative;
    if ratio.abs() < 0.5 {
        newton / (1.0 + ratio)
    } else {
        newton
    }
}

/// The converged frame at `x` on `element`, from the surface's height,
/// slope and curvature there.
#[inline(always)]
fn frame_on_beam(beam: &Beam, element: usize, x: f64, surface: [f64; 3]) -> ContactFrame {
    let [w, slope, curvature] = surface;
    let secant = (1.0 + slope * slope).sqrt();
    ContactFrame {
        x,
        shape: beam.shape(element, x),
        deflection: w,
        slope,
        curvature,
        cos: 1.0 / secant,
        sin: slope / secant,
        on_beam: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structure::beam::BeamSpec;

    const RADIUS: f64 = 0.3;

    /// A wheel rolling down a slope, and a vibrating beam under it.
    fn moving_wheel(beam: &Beam) -> (BodyState, DVector<f64>) {
        let state = BodyState {
            position: Vector2::new(9.1, 0.95),
            velocity: Vector2::new(10.0, -0.4),
            angle: 0.0,
            angular_velocity: -31.0,
        };
        let v = DVector::from_fn(beam.free_dofs(), |i, _| 0.3 * libm::cos((i as f64) * 0.7));
        (state, v)
    }

    fn deformed_beam() -> (Beam, DVector<f64>) {
        let beam = Beam::new(&BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements: 3,
            ..BeamSpec::default()
        })
        .unwrap();
        let n = beam.free_dofs();
        // A smooth, clearly non-trivial shape.
        let u = DVector::from_fn(n, |i, _| 0.05 * libm::sin((i as f64) * 1.3));
        (beam, u)
    }

    #[test]
    fn ground_velocity_error_is_the_general_rows_bit_for_bit() {
        // Without DOFs the beam rows are skipped; they would give the same.
        let (beam, _) = deformed_beam();
        let (state, v) = moving_wheel(&beam);
        for centre in [Vector2::new(-3.0, 0.4), Vector2::new(30.0, -0.0)] {
            let frame = ContactFrame::on_ground(&centre);
            let (t_row, n_row) = frame.beam_rows(beam.surface_offset);
            let (vt, vn) = beam.dot_rows(&frame.shape, (&t_row, &n_row), &v);
            let (bt, bn) = frame.body_rows(RADIUS);
            let q = Vector3::new(state.velocity.x, state.velocity.y, state.angular_velocity);
            let general = [bt.dot(&q) - vt, bn.dot(&q) - vn];
            let e = frame.velocity_error(&beam, RADIUS, &state, &v);
            assert_eq!(e.x.to_bits(), general[0].to_bits());
            assert_eq!(e.y.to_bits(), general[1].to_bits());
            // A body at rest: the signs of the zeros agree too.
            let rest = BodyState {
                velocity: Vector2::zeros(),
                angular_velocity: 0.0,
                ..state
            };
            let e = frame.velocity_error(&beam, 0.0, &rest, &v);
            let (bt, bn) = frame.body_rows(0.0);
            let general = [
                bt.dot(&Vector3::zeros()) - vt,
                bn.dot(&Vector3::zeros()) - vn,
            ];
            assert_eq!(e.x.to_bits(), general[0].to_bits());
            assert_eq!(e.y.to_bits(), general[1].to_bits());
        }
    }

    /// A follower of body `body` attached at `attachment`.
    fn follower_at(body: usize, attachment: Vector2<f64>) -> Contact {
        Contact {
            name: "contact".into(),
            body,
            kind: ContactKind::Glider,
            follower: Some(Follower {
                stiffness: 1e6,
                damping: 2e4,
                preload: 5e4,
                rest: 0.5,
                attachment,
                kind: LawKind::Suspension,
            }),
        }
    }

    #[test]
    fn a_pass_with_shared_rotations_gives_each_contacts_point_torque_and_gap_bit_for_bit() {
        // Two followers of one pitched bogie (the second finds its rotation
        // kept), one of another body (the slot changes hands), a centre
        // attachment and a contact body: `point_turned`, `torque_turned`
        // and `gap_and_rate` against `point`, `torque`, `gap` and
        // `velocity_error`, each computed alone.
        let (beam, u) = deformed_beam();
        let (wheel, v) = moving_wheel(&beam);
        let bodies = [
            BodyState {
                angle: 0.031,
                ..wheel
            },
            BodyState {
                angle: -0.017,
                angular_velocity: 0.8,
                ..wheel
            },
        ];
        let contacts = [
            follower_at(0, Vector2::new(1.25, -0.4)),
            follower_at(0, Vector2::new(-1.25, -0.4)),
            follower_at(1, Vector2::new(0.0, -0.7)),
            follower_at(1, Vector2::zeros()),
            Contact {
                follower: None,
                ..follower_at(0, Vector2::zeros())
            },
        ];
        let force = Vector2::new(-3.0e3, 7.0e4);
        let mut rotations = ContactRotations::default();
        let bits = |s: &BodyState| s.numbers().map(f64::to_bits);
        for contact in &contacts {
            let body = &bodies[contact.body];
            let alone = contact.point(body);
            let turned = contact.point_turned(body, &mut rotations);
            assert_eq!(bits(&turned), bits(&alone), "{contact:?}");
            let torque = contact.torque_turned(body, &force, &mut rotations);
            assert_eq!(torque.to_bits(), contact.torque(body, &force).to_bits());
            let frame = foot_point(&beam, &u, &alone.position, alone.position.x).unwrap();
            let (gap, rate) = frame.gap_and_rate(&beam, &turned, &v);
            assert_eq!(
                gap.to_bits(),
                frame.gap(&beam, 0.0, &alone.position).to_bits()
            );
            let error = frame.velocity_error(&beam, 0.0, &alone, &v);
            assert_eq!(rate.to_bits(), error.y.to_bits());
        }
        assert!(
            contacts[0].point(&bodies[0]) != bodies[0],
            "an attached point moved"
        );
    }

    #[test]
    fn foot_point_is_perpendicular_and_crosses_elements() {
        let (beam, u) = deformed_beam();
        // Start the search two elements away from the answer.
        let centre = Vector2::new(17.3, 1.2);
        let frame = foot_point(&beam, &u, &centre, 1.0).unwrap();
        let d = Vector2::new(frame.x, frame.deflection);
        let along = frame.tangent().dot(&(centre - d));
        assert!(along.abs() < 1e-12, "tangential offset {along}");
        assert_eq!(frame.shape.element, beam.element_at(frame.x));
        assert!((frame.x - 17.3).abs() < 0.2);
    }

    #[test]
    fn foot_point_reaches_across_thousands_of_elements() {
        // 65,536 elements of 0.37 mm and a smooth deflection; the search
        // starts 2 m (5,461 elements) from the answer, on either side, and
        // past the end of the beam.
        let beam = Beam::new(&BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements: 65_536,
            ..BeamSpec::default()
        })
        .unwrap();
        let mut u = DVector::zeros(beam.free_dofs());
        for (node, &x) in beam.node_x.iter().enumerate() {
            let shape = beam.shape(beam.element_at(x), x);
            // w = −0.17 sin(πx/L): write w and w' into the node's free DOFs.
            let k = std::f64::consts::PI / 24.0;
            let (w, slope) = (-0.17 * libm::sin(k * x), -0.17 * k * libm::cos(k * x));
            let local = if node + 1 == beam.node_x.len() { 2 } else { 0 };
            if let Some(i) = shape.dofs[local] {
                u[i] = w;
            }
            if let Some(i) = shape.dofs[local + 1] {
                u[i] = slope;
            }
        }
        for (centre_x, guess) in [(12.0f64, 10.0), (3.0, 5.0), (23.5, 24.5)] {
            let centre = Vector2::new(centre_x, 0.9 - 0.17 * libm::sin(centre_x * 0.1309));
            let frame = foot_point(&beam, &u, &centre, guess).unwrap();
            let d = Vector2::new(frame.x, frame.deflection);
            let along = frame.tangent().dot(&(centre - d));
            assert!(along.abs() < 1e-10, "tangential offset {along}");
            assert_eq!(frame.shape.element, beam.element_at(frame.x));
            assert!(
                (frame.x - centre_x).abs() < 0.1,
                "{} for {centre_x}",
                frame.x
            );
        }
    }

    #[test]
    fn contact_power_is_force_times_velocity_error() {
        // The loads are the transposes of the constraint rows, so the power
        // the contact force puts into body and beam together is p · e.
        let (beam, u) = deformed_beam();
        let (state, v) = moving_wheel(&beam);
        let frame = foot_point(&beam, &u, &state.position, 9.0).unwrap();
        let p = ContactForce {
            tangential: 1.5e4,
            normal: 6e5,
        };
        let force = frame.tangent() * p.tangential + frame.normal() * p.normal;
        let body_power =
            force.dot(&state.velocity) + p.tangential * RADIUS * state.angular_velocity;
        let (t_row, n_row) = frame.beam_rows(beam.surface_offset);
        let mut load = DVector::zeros(beam.free_dofs());
        frame.shape.scatter(&t_row, -p.tangential, &mut load);
        frame.shape.scatter(&n_row, -p.normal, &mut load);
        let beam_power = load.dot(&v);
        let e = frame.velocity_error(&beam, RADIUS, &state, &v);
        let expected = p.as_vector().dot(&e);
        assert!(
            (body_power + beam_power - expected).abs() < 1e-9 * body_power.abs(),
            "{} vs {expected}",
            body_power + beam_power
        );
    }

    #[test]
    fn normal_velocity_error_is_the_rate_of_the_gap() {
        // The normal row is the exact derivative of g: check by finite differences.
        let (beam, u) = deformed_beam();
        let (state, v) = moving_wheel(&beam);
        let gap_at = |h: f64| {
            let u_h = &u + &v * h;
            let c = state.position + state.velocity * h;
            foot_point(&beam, &u_h, &c, 9.0)
                .unwrap()
                .gap(&beam, RADIUS, &c)
        };
        let h = 1e-6;
        let rate = (gap_at(h) - gap_at(-h)) / (2.0 * h);
        let frame = foot_point(&beam, &u, &state.position, 9.0).unwrap();
        let e = frame.velocity_error(&beam, RADIUS, &state, &v);
        assert!((rate - e.y).abs() < 1e-7, "{rate} vs {}", e.y);
    }
}

#[cfg(test)]
mod profile_tests {
    use super::*;
    use crate::profile::Profile;
    use crate::structure::beam::BeamSpec;
    use crate::structure::profile::IrregularitySpec;

    fn sine() -> Profile {
        let spec = IrregularitySpec::Sine {
            amplitude: 0.01,
            wavelength: 3.0,
            phase: 0.2,
        };
        Profile::new(&[spec]).unwrap().unwrap()
    }

    #[test]
    fn with_a_profile_the_normal_velocity_error_is_still_the_rate_of_the_gap() {
        // On the beam and on rigid ground: the travel over the profile's
        // slope (V r') is in the normal row.
        let beam = Beam::new(&BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements: 3,
            ..BeamSpec::default()
        })
        .unwrap();
        let u = DVector::from_fn(beam.free_dofs(), |i, _| 0.05 * libm::sin((i as f64) * 1.3));
        let v = DVector::from_fn(beam.free_dofs(), |i, _| 0.3 * libm::cos((i as f64) * 0.7));
        let profile = sine();
        let state = BodyState {
            position: Vector2::new(9.1, 0.95),
            velocity: Vector2::new(10.0, -0.4),
            angle: 0.0,
            angular_velocity: -31.0,
        };
        let frame_at = |u: &DVector<f64>, c: &Vector2<f64>, ground: bool| {
            if ground {
                ContactFrame::on_profile(&profile, c).unwrap()
            } else {
                foot_point_on(&beam, Some(&profile), u, c, 9.0).unwrap()
            }
        };
        for ground in [false, true] {
            let gap_at = |h: f64| {
                let u_h = &u + &v * h;
                let c = state.position + state.velocity * h;
                frame_at(&u_h, &c, ground).gap(&beam, 0.3, &c)
            };
            let h = 1e-6;
            let rate = (gap_at(h) - gap_at(-h)) / (2.0 * h);
            let frame = frame_at(&u, &state.position, ground);
            let e = frame.velocity_error(&beam, 0.3, &state, &v);
            assert!(
                (rate - e.y).abs() < 1e-7,
                "ground {ground}: {rate} vs {}",
                e.y
            );
            // The profile tilts the frame: its slope is w' + r'.
            let r_slope = profile.at(frame.x)[1];
            let w_slope = if ground {
                0.0
            } else {
                beam.axis(frame.shape.element, frame.x, &u)[1]
            };
            assert!((frame.slope - w_slope - r_slope).abs() < 1e-12);
            assert!(r_slope.abs() > 1e-3, "the test point must be on a slope");
        }
    }
}
