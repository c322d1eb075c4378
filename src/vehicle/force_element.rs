//! Force elements: linear spring–dampers between attachment points of two
//! bodies, acting along a fixed direction (vertical or longitudinal), with a
//! preload so that a vehicle can start in static equilibrium.
//!
//! The elongation is δ = (p_a − p_b)·d − δ₀ with p the attachment points in
//! the world, d the direction and δ₀ its value in the initial configuration.
//! The force on body a along d is f = preload − k δ − c δ̇, body b receives
//! −f: a preloaded suspension between a car body (a) above a bogie (b)
//! carries the car body's weight with preload = its weight.

use nalgebra::{Vector2, Vector3};

use crate::body::BodyState;
pub use crate::vehicle::element_sweep::{
    add_element_forces, dissipation_power, power_and_energy, spring_energy, ForceElements,
};

/// The direction a force element acts along.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Vertical,
    Longitudinal,
}

impl Direction {
    pub fn unit(self) -> Vector2<f64> {
        match self {
            Direction::Vertical => Vector2::new(0.0, 1.0),
            Direction::Longitudinal => Vector2::new(1.0, 0.0),
        }
    }
}

/// A linear spring–damper between point `point_a` of body `body_a` and
/// point `point_b` of body `body_b` (points in body coordinates).
#[derive(Debug, Clone, PartialEq)]
pub struct ForceElement {
    pub name: String,
    pub body_a: usize,
    pub point_a: Vector2<f64>,
    pub body_b: usize,
    pub point_b: Vector2<f64>,
    pub direction: Direction,
    pub stiffness: f64,
    pub damping: f64,
    pub preload: f64,
    /// (p_a − p_b)·d in the configuration where the force is the preload.
    pub rest: f64,
}

/// What a force element does at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementForces {
    /// Generalized forces (F_x, F_y, torque) on body a and on body b.
    pub on_a: Vector3<f64>,
    pub on_b: Vector3<f64>,
    /// Elongation δ (m) and its rate (m/s).
    pub elongation: f64,
    pub rate: f64,
    /// Power dissipated by the damper, c δ̇² (W).
    pub dissipation: f64,
}

fn point_velocity(state: &BodyState, offset: &Vector2<f64>) -> Vector2<f64> {
    state.velocity + state.angular_velocity * Vector2::new(-offset.y, offset.x)
}

fn torque(offset: &Vector2<f64>, force: &Vector2<f64>) -> f64 {
    offset.x * force.y - offset.y * force.x
}

impl ForceElement {
    /// (p_a − p_b)·d for the given body states.
    pub fn separation(&self, a: &BodyState, b: &BodyState) -> f64 {
        let pa = a.position + a.offset_of(&self.point_a);
        let pb = b.position + b.offset_of(&self.point_b);
        (pa - pb).dot(&self.direction.unit())
    }

    /// The element's forces on its bodies: the general formula, which
    /// `element_sweep`'s plan follows bit for bit (and its tests check).
    pub fn forces(&self, bodies: &[BodyState]) -> ElementForces {
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let d = self.direction.unit();
        let ra = a.offset_of(&self.point_a);
        let rb = b.offset_of(&self.point_b);
        let elongation = ((a.position + ra) - (b.position + rb)).dot(&d) - self.rest;
        let rate = (point_velocity(a, &ra) - point_velocity(b, &rb)).dot(&d);
        let magnitude = self.preload - self.stiffness * elongation - self.damping * rate;
        let force = magnitude * d;
        ElementForces {
            on_a: Vector3::new(force.x, force.y, torque(&ra, &force)),
            on_b: Vector3::new(-force.x, -force.y, -torque(&rb, &force)),
            elongation,
            rate,
            dissipation: self.damping * rate * rate,
        }
    }

    /// Potential energy ½ k δ² − preload δ (J), zero in the rest configuration.
    pub fn potential_energy(&self, bodies: &[BodyState]) -> f64 {
        let delta = self.separation(&bodies[self.body_a], &bodies[self.body_b]) - self.rest;
        0.5 * self.stiffness * delta * delta - self.preload * delta
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(x: f64, y: f64, angle: f64, vy: f64, omega: f64) -> BodyState {
        BodyState {
            position: Vector2::new(x, y),
            velocity: Vector2::new(0.3, vy),
            angle,
            angular_velocity: omega,
        }
    }

    fn element() -> ForceElement {
        ForceElement {
            name: "spring".into(),
            body_a: 0,
            point_a: Vector2::new(2.5, -0.4),
            body_b: 1,
            point_b: Vector2::new(0.1, 0.3),
            direction: Direction::Vertical,
            stiffness: 2e5,
            damping: 3e3,
            preload: 4e4,
            rest: 1.2,
        }
    }

    #[test]
    fn forces_are_minus_the_gradient_of_the_potential() {
        // Undamped: the generalized force on each coordinate is −∂V/∂q.
        let mut e = element();
        e.damping = 0.0;
        let bodies = [
            state(1.0, 2.0, 0.05, 0.0, 0.0),
            state(1.4, 0.5, -0.02, 0.0, 0.0),
        ];
        let f = e.forces(&bodies);
        let h = 1e-6;
        for body in 0..2 {
            for k in 0..3 {
                let shifted = |s: f64| {
                    let mut b = bodies;
                    match k {
                        0 => b[body].position.x += s,
                        1 => b[body].position.y += s,
                        _ => b[body].angle += s,
                    }
                    e.potential_energy(&b)
                };
                let gradient = (shifted(h) - shifted(-h)) / (2.0 * h);
                let force = if body == 0 { f.on_a[k] } else { f.on_b[k] };
                assert!(
                    (force + gradient).abs() < 1e-6 * e.preload,
                    "body {body} coordinate {k}: {force} vs {}",
                    -gradient
                );
            }
        }
    }

    #[test]
    fn loads_of_one_direction_are_the_general_forces_bit_for_bit() {
        // `add_element_forces` computes only the element's direction; the
        // general `forces_with` must give the same bits, turned bodies and
        // attachment points off the centre included.
        let bodies = [
            state(1.0, 2.0, 0.05, 0.7, 0.2),
            state(1.4, 0.5, -0.02, -0.1, -0.3),
            state(-7.0, 0.3, 0.0, 0.0, 0.0),
        ];
        let mut elements = Vec::new();
        for direction in [Direction::Vertical, Direction::Longitudinal] {
            let mut e = element();
            e.direction = direction;
            elements.push(e.clone());
            e.point_b = Vector2::zeros();
            e.body_b = 2;
            elements.push(e.clone());
            e.point_a = Vector2::new(-1.7, 0.0);
            e.body_a = 1;
            elements.push(e);
        }
        let mut loads = [Vector3::new(1.0, -2.0, 0.5); 3];
        let elements = ForceElements::from(elements);
        let power = add_element_forces(&elements, &bodies, &mut loads);
        let mut expected = [Vector3::new(1.0, -2.0, 0.5); 3];
        let mut expected_power = 0.0;
        for e in elements.iter() {
            let f = e.forces(&bodies);
            expected[e.body_a] += f.on_a;
            expected[e.body_b] += f.on_b;
            expected_power += f.dissipation;
        }
        let bits = |l: &[Vector3<f64>; 3]| l.map(|v| v.map(f64::to_bits));
        assert_eq!(bits(&loads), bits(&expected));
        assert_eq!(power.to_bits(), expected_power.to_bits());
        // The dampers' power and the potential energy alone, likewise.
        let general_power: f64 = elements.iter().map(|e| e.forces(&bodies).dissipation).sum();
        let power_alone = dissipation_power(&elements, &bodies);
        assert_eq!(power_alone.to_bits(), general_power.to_bits());
        let general_energy: f64 = elements.iter().map(|e| e.potential_energy(&bodies)).sum();
        let energy = spring_energy(&elements, &bodies);
        assert_eq!(energy.to_bits(), general_energy.to_bits());
        assert!(energy != 0.0 && power_alone > 0.0);
    }

    #[test]
    fn damper_power_is_the_dissipation() {
        // The power of the element's forces on both bodies is −(dV/dt) − c δ̇².
        let e = element();
        let bodies = [
            state(1.0, 2.0, 0.05, 0.7, 0.2),
            state(1.4, 0.5, -0.02, -0.1, -0.3),
        ];
        let f = e.forces(&bodies);
        let power = f.on_a.dot(&bodies[0].generalized_velocity())
            + f.on_b.dot(&bodies[1].generalized_velocity());
        let h = 1e-6;
        let at = |s: f64| {
            let moved: Vec<BodyState> = bodies
                .iter()
                .map(|b| BodyState {
                    position: b.position + s * b.velocity,
                    angle: b.angle + s * b.angular_velocity,
                    ..*b
                })
                .collect();
            e.potential_energy(&moved)
        };
        let potential_rate = (at(h) - at(-h)) / (2.0 * h);
        assert!(f.dissipation > 0.0);
        assert!(
            (power + potential_rate + f.dissipation).abs() < 1e-6 * f.dissipation.max(1.0),
            "{power} + {potential_rate} + {}",
            f.dissipation
        );
    }
}
