//! Which integrator a scene runs, and why (for `auto`).

use super::{Hht, Integrator, Rk4};
use crate::scene::{IntegratorKind, SolverSpec};
use crate::system::System;

/// The largest step explicit RK4 is stable at for this beam (s): its
/// stability region reaches 2√2 on the imaginary axis.
pub fn rk4_step_limit(system: &System) -> f64 {
    2.0 * std::f64::consts::SQRT_2 / system.beam.highest_frequency()
}

/// The least numerical damping `auto` runs HHT-α with.
pub const AUTO_MIN_DAMPING: f64 = 0.1;

/// The integrator of `solver` for `system`, and what runs in words.
pub fn choose_integrator(
    system: &System,
    solver: &SolverSpec,
) -> Result<(Integrator, String), String> {
    let step = solver.step;
    let damping = solver.numerical_damping;
    let hht = |damping: f64, why: String| -> Result<(Integrator, String), String> {
        let integrator = Hht::new(system, damping, step)?;
        Ok((
            Integrator::Hht(Box::new(integrator)),
            format!("hht (implicit HHT-α, α = {}){why}", 0.0 - damping),
        ))
    };
    match solver.integrator {
        IntegratorKind::Hht => hht(damping, String::new()),
        IntegratorKind::Rk4 | IntegratorKind::Auto => {
            let limit = rk4_step_limit(system);
            let free = system.beam.free_dofs();
            if step <= limit {
                let why = if solver.integrator == IntegratorKind::Auto {
                    format!("; auto: the step is within RK4's stability limit {limit:.3e} s")
                } else {
                    String::new()
                };
                return Ok((
                    Integrator::Rk4(Box::new(Rk4::new(free, system.bodies.len()))),
                    format!("rk4 (explicit){why}"),
                ));
            }
            if solver.integrator == IntegratorKind::Auto {
                // Undamped HHT lets the contact force oscillate from step to
                // step at high speed (a spurious early lift-off at 150 m/s on
                // 8 elements, report/stress.md): auto damps at least a little.
                return hht(
                    damping.max(AUTO_MIN_DAMPING),
                    format!("; auto: RK4 would need a step of at most {limit:.3e} s for this mesh"),
                );
            }
            Err(format!(
                "solver.step = {step} s is beyond the stability limit of explicit RK4 \
                 for this mesh: elements of {:.4} m give the beam a highest frequency of \
                 {:.1} rad/s, so the step must not exceed {limit:.3e} s; shorten solver.step, \
                 use fewer elements, or set solver.integrator = \"hht\" or \"auto\"",
                system.beam.min_element_length(),
                2.0 * std::f64::consts::SQRT_2 / limit
            ))
        }
    }
}
