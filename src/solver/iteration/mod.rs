//! The contact-force iteration of Lee (1994), section 3.3, over all
//! contacts at once.
//!
//! Per step: hold trial contact forces p over the step, integrate, measure
//! the stacked velocity errors e of every contact at the end (tangential for
//! wheels, normal for all), correct p ← p − C⁻¹ e with C the step's block
//! Delassus operator, until every contact's |e| is within tolerance; then
//! the position stage corrects the normal forces with the gaps' block
//! operator until every |g| is within its tolerance. C couples contacts
//! through the beam (two wheels on one span load each other) and through a
//! body they share; it is built once per step, when a correction first needs
//! it (the gaps' operator only if the position stage corrects). A glider
//! (r = 0, J = 0) has no tangential row: its tangential force stays exactly
//! zero.

use nalgebra::{DMatrix, DVector, Vector4};

use crate::contact::{ContactForce, ContactFrame};
use crate::integrate::{
    contact_frames, DynamicState, ForceShape, IntegrationError, Integrator, KnownAtPrediction,
    StepStart,
};
use crate::system::System;

mod condensed;
mod followers;
mod laws;
mod low_rank;
mod operator;
mod responses;
mod turn;

pub use condensed::Work as CondensedWork;
use operator::{Assembly, ContactRows, Inverted};
pub use responses::Footprint;
use responses::{ElementResponse, ResponseCache};

/// Tolerances and caps of the iteration (the paper's: 1e-7 m/s, 1e-5 m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationSettings {
    pub velocity_tolerance: f64,
    pub gap_tolerance: f64,
    pub max_iterations: u32,
}

/// Converged step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepSolution {
    /// One force per contact, in the order of `System::contacts`.
    pub forces: Vec<ContactForce>,
    /// Integrations performed (velocity and position stages together).
    pub iterations: u32,
    /// Integrations of the position stage alone.
    pub position_iterations: u32,
    /// The largest contact's |e| at the end of the step (m/s).
    pub velocity_error: f64,
    /// The gap g of largest magnitude at the end of the step (m).
    pub gap_error: f64,
}

/// The name of the stage that settles the compliant laws' forces.
pub const FORCE_LAW_STAGE: &str = "force-law fixed-point";

/// Why a step failed.
#[derive(Debug, Clone, PartialEq)]
pub enum StepError {
    NotConverged {
        stage: &'static str,
        iterations: u32,
        residual: f64,
        tolerance: f64,
    },
    Diverged {
        stage: &'static str,
        iterations: u32,
        first: f64,
        last: f64,
    },
    NonFinite {
        stage: &'static str,
    },
    /// See `IntegrationError::LostContact`.
    LostContact {
        contact: usize,
        x: f64,
        centre: [f64; 2],
    },
    Factorization {
        step: f64,
        reason: String,
    },
    /// The step's wall-clock deadline passed (`crate::deadline`).
    OverBudget,
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StepError::OverBudget => write!(f, "the wall-time budget ran out inside the step"),
            StepError::NotConverged {
                stage,
                iterations,
                residual,
                tolerance,
            } => write!(
                f,
                "the {stage} stage of the contact iteration did not converge in {iterations} \
                 iterations (error {residual:.3e}, tolerance {tolerance:.3e}); \
                 raise solver.max_iterations, loosen the tolerance or shorten solver.step"
            ),
            StepError::Diverged {
                stage,
                iterations,
                first,
                last,
            } => write!(
                f,
                "the {stage} stage of the contact iteration diverged (error grew from \
                 {first:.3e} to {last:.3e} in {iterations} iterations); shorten solver.step"
            ),
            StepError::NonFinite { stage } => write!(
                f,
                "a non-finite value appeared in the {stage} stage; the step is beyond the \
                 integrator's stability limit or the scene is degenerate"
            ),
            StepError::LostContact { contact, x, .. } => write!(
                f,
                "no foot point of contact {} on the beam could be found (last abscissa \
                 {x:.6} m)",
                contact + 1
            ),
            StepError::Factorization { step, reason } => write!(
                f,
                "the implicit scheme could not factor its effective matrix for a step of \
                 {step:e} s: {reason}"
            ),
        }
    }
}

impl From<IntegrationError> for StepError {
    fn from(e: IntegrationError) -> StepError {
        match e {
            IntegrationError::LostContact { contact, x, centre } => {
                StepError::LostContact { contact, x, centre }
            }
            IntegrationError::Factorization { step, reason } => {
                StepError::Factorization { step, reason }
            }
        }
    }
}

/// The block Delassus operators of one step, ready to apply: one or two
/// rows per contact, each applied several times.
struct Delassus {
    /// (∂e/∂p)⁻¹ over the stacked rows (kg/s).
    velocity: Inverted,
    /// (∂g/∂p_n)⁻¹ over the contacts (N/m).
    gap: Inverted,
    /// Their matrices, assembled over the entries the contacts couple;
    /// boxed, so that a build takes one out and puts it back by pointer
    /// (moving the struct and dropping a default one cost a tenth of the
    /// paper's case's build).
    velocity_assembly: Option<Box<Assembly>>,
    gap_assembly: Option<Box<Assembly>>,
    /// Whether they hold this step's operators (velocity, gap).
    built: bool,
    gap_built: bool,
    /// The end frames the step's operators are measured in: those of the
    /// integration at which the first of them was built.
    frames: Vec<ContactFrame>,
    /// Per contact, the turn of its normal row there (`turn`); empty where
    /// the scheme holds the forces at the step's start.
    turns: Vec<f64>,
    /// Whether the steps solved share the operators built by the first of
    /// them (`share_operator`).
    shared: bool,
}

impl Delassus {
    /// One part's operator and its assembly.
    fn part_mut(&mut self, part: Part) -> (&mut Inverted, &mut Option<Box<Assembly>>) {
        match part {
            Part::Velocity => (&mut self.velocity, &mut self.velocity_assembly),
            Part::Gap => (&mut self.gap, &mut self.gap_assembly),
        }
    }

    /// Operators of `rows` stacked rows over `contacts` contacts, not yet
    /// built for any step.
    fn unbuilt(rows: usize, contacts: usize) -> Delassus {
        Delassus {
            velocity: Inverted::unbuilt(rows),
            gap: Inverted::unbuilt(contacts),
            velocity_assembly: Some(Box::default()),
            gap_assembly: Some(Box::default()),
            built: false,
            gap_built: false,
            frames: Vec::new(),
            turns: Vec::new(),
            shared: false,
        }
    }
}

/// Which of the two operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    Velocity,
    Gap,
}

/// A contact's beam rows (tangential, normal) in the frames it is measured
/// in and in those its force is applied in.
#[derive(Debug, Clone, Copy)]
struct BeamRows {
    measure: [Vector4<f64>; 2],
    apply: [Vector4<f64>; 2],
}

fn rows4((t, n): ([f64; 4], [f64; 4])) -> [Vector4<f64>; 2] {
    [Vector4::from(t), Vector4::from(n)]
}

/// A unit load on the beam, a row at an element's DOFs, and the length of
/// the step integrated under it: what a response of
/// `beam_compliance_integrated` depends on (the integrator and the beam
/// being the iteration's own), its reals as bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ResponseKey {
    dt: u64,
    dofs: [Option<usize>; 4],
    row: [u64; 4],
}

impl ResponseKey {
    fn new(dt: f64, dofs: &[Option<usize>; 4], row: &[f64; 4]) -> ResponseKey {
        ResponseKey {
            dt: dt.to_bits(),
            dofs: *dofs,
            row: row.map(f64::to_bits),
        }
    }
}

/// A contact measured on the beam in a condensed build
/// (`beam_compliance_condensed`): its first row and its rows' kinds in the
/// operator, its beam rows as measured, and its DOFs' places among the
/// build's (`Condensed::places`).
struct MeasuredOnBeam {
    first: usize,
    contact: usize,
    kinds: &'static [usize],
    rows: [Vector4<f64>; 2],
    places: [usize; 4],
}

/// One (measured, applied) contact pair of the beam part of an operator.
struct PairEntry<'a> {
    /// The measured contact's rows, the applied one's.
    rows: (&'a [Vector4<f64>; 2], &'a [Vector4<f64>; 2]),
    /// Their row kinds (`row_kinds`).
    kinds: (&'static [usize], &'static [usize]),
    /// The contacts (the gap operator's entry).
    at: (usize, usize),
    /// Their first rows in the velocity operator.
    offsets: (usize, usize),
}

impl PairEntry<'_> {
    /// The pair's entries from the response of the measured contact's
    /// element to loads on the applied one's.
    fn fill(&self, r: &ElementResponse, part: Part, matrix: &mut DMatrix<f64>) {
        let block = match part {
            Part::Gap => &r.displacement,
            Part::Velocity => &r.velocity,
        };
        self.fill_part(block, part, matrix);
    }

    /// `fill` from the response block of `part` alone (displacements for
    /// the gap operator, velocities for the velocity operator).
    fn fill_part(&self, block: &nalgebra::Matrix4<f64>, part: Part, matrix: &mut DMatrix<f64>) {
        let (m, a) = self.rows;
        if part == Part::Gap {
            matrix[self.at] = m[1].dot(&(block * a[1]));
            return;
        }
        for (b, &kj) in self.kinds.1.iter().enumerate() {
            let response = block * a[kj];
            for (ai, &ki) in self.kinds.0.iter().enumerate() {
                matrix[(self.offsets.0 + ai, self.offsets.1 + b)] = m[ki].dot(&response);
            }
        }
    }
}

/// A lower bound of the wall time one beam integration takes per element,
/// for refusing a step up front (`deadline::foresee`): measured at about
/// 4e-7 s (20,000 elements, 21 magnets, HHT: two steps of some 170
/// integrations in 1.38 s, 2026-11-26 19:39 UTC, load 14) and 2e-6 s (200
/// magnets on 100,000 elements, 166 s, issue 30); taken 10 to 100 times
/// lower, so that only a step that cannot fit on a fast machine is refused.
const MIN_SECONDS_PER_ELEMENT_INTEGRATION: f64 = 2e-8;

/// The kinds of rows a contact has: 0 tangential, 1 normal.
fn row_kinds(rolls: bool) -> &'static [usize] {
    if rolls {
        &[0, 1]
    } else {
        &[1]
    }
}

/// The iteration's workspace: integrator scratch and unit-load responses.
pub struct ContactIteration {
    integrator: Integrator,
    load: DVector<f64>,
    response_u: Vec<DVector<f64>>,
    response_v: Vec<DVector<f64>>,
    /// Per column of `response_u`/`response_v`: the unit load and step
    /// length it holds the response to. A restart's trial steps and the
    /// step after them share their start and length, and so these.
    response_keys: Vec<Option<ResponseKey>>,
    /// Responses for steps of the nominal length, filled as the contacts
    /// reach the elements (`responses`): the Delassus operator then costs a
    /// few flops per entry instead of beam integrations. They depend only
    /// on the elements and the nominal step, never on the history, so a
    /// restored state continues bit-identically.
    element_responses: ResponseCache,
    /// HHT-α's responses on the nominal step from A⁻¹ at the contacts'
    /// DOFs (`condensed`), where its solve is the plain band factor's:
    /// then `element_responses` stays empty.
    condensed: condensed::Condensed,
    /// Whole-beam solves made for operators (responses integrated).
    delassus_beam_solves: u64,
    nominal_step: f64,
    offsets: Vec<usize>,
    rows: usize,
    start_frames: Vec<ContactFrame>,
    end_frames: Vec<ContactFrame>,
    forces: Vec<ContactForce>,
    error: DVector<f64>,
    gap_errors: DVector<f64>,
    correction: DVector<f64>,
    gap_correction: DVector<f64>,
    delassus: Delassus,
    measured_elements: Vec<usize>,
    beam_rows: Vec<BeamRows>,
    measured_on_beam: Vec<MeasuredOnBeam>,
    /// Per contact: open (no rows: its force is held at zero, its gap only
    /// measured), set by the caller for each step (`set_open`).
    open: Vec<bool>,
    /// Every contact's gap at the end of the last integration, open or not.
    contact_gaps: Vec<f64>,
    /// Per contact: the shape of its force over the next steps solved
    /// (`set_force_shapes`; held when empty).
    shapes: Vec<ForceShape>,
    /// The bodies at the end of the previous integration of the step.
    previous_bodies: Vec<crate::body::BodyState>,
    /// Whether the step being solved took an end handed on as its first
    /// prediction (`TimeIntegrator::seed_prediction`): `settled` then
    /// checks its bodies against that end's, even where every contact is
    /// closed.
    seeded: bool,
    /// Per contact: a massless follower (always open to the iteration).
    followers: Vec<bool>,
    /// Per body: its contacts, in increasing order.
    contacts_of_body: Vec<Vec<usize>>,
    /// The bodies' largest velocity change between the last two
    /// integrations of a step that re-integrates for its force laws.
    settle_change: f64,
    /// Whether `end_frames` are the frames of the integrator's prediction
    /// for the next integration (the last end, not moved since by
    /// `predict_bodies`): then they are handed over, not searched again.
    end_is_prediction: bool,
    /// The end frames of the last step solved, for the next step's start
    /// and the outputs.
    memo: crate::integrate::FrameMemo,
    /// Workspace of the force elements' anticipated lag (`laws`).
    law_lag: laws::LawLag,
    /// The compliant followers' secant step (`followers`).
    secant: followers::Secant,
}

impl ContactIteration {
    /// `nominal_step`: the fixed step whose unit-load responses are cached.
    pub fn new(mut integrator: Integrator, system: &System, nominal_step: f64) -> ContactIteration {
        let free_dofs = system.beam.coordinates();
        let (offsets, rows) = system.row_offsets();
        let followers: Vec<bool> = system
            .contacts
            .iter()
            .map(|c| c.follower.is_some())
            .collect();
        let mut contacts_of_body = vec![Vec::new(); system.bodies.len()];
        for (c, contact) in system.contacts.iter().enumerate() {
            contacts_of_body[contact.body].push(c);
        }
        let secant = followers::Secant::new(system, integrator.lags_force_laws());
        // Where every contact is a follower (compliant or a suspension),
        // whose laws and force elements the integrator evaluates at its
        // predicted end, a step gains an integration from a first
        // prediction nearer that end (`Secant::every`'s steps among them).
        let all_followers = !followers.is_empty() && !followers.contains(&false);
        integrator.predict_with_accelerations(integrator.lags_force_laws() && all_followers);
        ContactIteration {
            integrator,
            load: DVector::zeros(free_dofs),
            response_u: Vec::new(),
            response_v: Vec::new(),
            response_keys: Vec::new(),
            element_responses: ResponseCache::new(),
            condensed: Default::default(),
            delassus_beam_solves: 0,
            nominal_step,
            offsets,
            rows,
            start_frames: Vec::new(),
            end_frames: Vec::new(),
            forces: Vec::new(),
            error: DVector::zeros(rows),
            gap_errors: DVector::zeros(system.contacts.len()),
            correction: DVector::zeros(rows),
            gap_correction: DVector::zeros(system.contacts.len()),
            delassus: Delassus::unbuilt(rows, system.contacts.len()),
            measured_elements: Vec::new(),
            beam_rows: Vec::new(),
            measured_on_beam: Vec::new(),
            open: followers.clone(),
            contact_gaps: vec![0.0; system.contacts.len()],
            shapes: vec![ForceShape::default(); system.contacts.len()],
            previous_bodies: Vec::new(),
            seeded: false,
            followers,
            contacts_of_body,
            settle_change: 0.0,
            end_is_prediction: false,
            memo: Default::default(),
            law_lag: laws::LawLag::default(),
            secant,
        }
    }

    /// The most the unit-load response cache held at once: its memory is
    /// linear in the elements (`responses`).
    pub fn response_cache_peak(&self) -> Footprint {
        self.element_responses.peak()
    }

    /// What the operator builds cost: whole-beam solves for responses,
    /// and the condensed builds' work (`condensed`).
    pub fn delassus_work(&self) -> (u64, CondensedWork) {
        let cached = self.element_responses.integrations();
        (self.delassus_beam_solves + cached, self.condensed.work())
    }

    /// The end frames of the last step solved, with the configuration they
    /// belong to.
    pub fn frame_memo(&self) -> &crate::integrate::FrameMemo {
        &self.memo
    }

    /// The time integrator, for its capabilities.
    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }

    /// The time integrator (its energy bookkeeping is switched from outside).
    pub fn integrator_mut(&mut self) -> &mut Integrator {
        &mut self.integrator
    }

    /// Which contacts are open in the next steps solved.
    pub fn set_open(&mut self, open: &[bool]) {
        self.open.clear();
        self.open.extend_from_slice(open);
        // A follower's force is a function of the state, evaluated with
        // the loads: the iteration has nothing to solve for it.
        for (open, &follower) in self.open.iter_mut().zip(&self.followers) {
            *open |= follower;
        }
    }

    /// Each contact's force shape over the next steps solved; the
    /// iteration's unknown stays the force's mean over the step.
    pub fn set_force_shapes(&mut self, shapes: &[ForceShape]) {
        self.shapes.clear();
        self.shapes.extend_from_slice(shapes);
    }

    /// From `share_operator(true)` to `share_operator(false)`, the steps
    /// solved keep the operators the first of them built, for steps from
    /// one state with one length and one open set (a restart's trial steps:
    /// the caller's promise). Each step still converges to the tolerances;
    /// only the way there changes. Their ends are the caller's to discard:
    /// they are not finished (`TimeIntegrator::finish_step`: no energy
    /// books, no end products kept).
    pub fn share_operator(&mut self, shared: bool) {
        self.delassus.shared = shared;
        self.delassus.built = false;
        self.delassus.gap_built = false;
    }

    /// Every contact's gap g at the end of the last step solved (m).
    pub fn contact_gaps(&self) -> &[f64] {
        &self.contact_gaps
    }

    /// Make sure `response_u`/`response_v` hold at least `count` vectors.
    fn reserve_responses(&mut self, count: usize) {
        let n = self.load.len();
        while self.response_u.len() < count {
            self.response_u.push(DVector::zeros(n));
            self.response_v.push(DVector::zeros(n));
            self.response_keys.push(None);
        }
    }

    /// Beam parts of ∂e/∂p (into `velocity`) and ∂g/∂p_n (into `gap`) for
    /// steps of the nominal length, from the cached element responses.
    fn beam_compliance_cached(
        &mut self,
        system: &System,
        (measure_frames, start_frames): (&[ContactFrame], &[ContactFrame]),
        part: Part,
        matrix: &mut DMatrix<f64>,
    ) {
        if self.integrator.nominal_band_response().is_some() {
            let frames = (measure_frames, start_frames);
            return self.beam_compliance_condensed(system, frames, part, matrix);
        }
        let h = system.beam.surface_offset;
        // The elements the contacts are measured on: where a loaded
        // element's responses are read when they cannot be kept whole.
        let on_beam = |frames: &[ContactFrame], elements: &mut Vec<usize>| {
            elements.clear();
            elements.extend(frames.iter().filter(|f| f.on_beam).map(|f| f.shape.element));
            elements.sort_unstable();
            elements.dedup();
        };
        let mut measured = std::mem::take(&mut self.measured_elements);
        on_beam(measure_frames, &mut measured);
        self.element_responses.begin_build();
        // Each contact's rows once, not once per pair.
        let mut rows = std::mem::take(&mut self.beam_rows);
        rows.clear();
        let pairs = measure_frames.iter().zip(start_frames).enumerate();
        rows.extend(pairs.map(|(i, (measure, apply))| BeamRows {
            measure: self.measured_beam_rows(i, measure, h, part),
            apply: rows4(apply.beam_rows(h)),
        }));
        for (j, apply) in start_frames.iter().enumerate() {
            // Four beam integrations per loaded element: on a huge beam
            // the deadline passes here (`build_delassus` then gives up).
            if !apply.on_beam || crate::deadline::passed() {
                continue;
            }
            let kinds_j = row_kinds(system.contacts[j].rolls());
            self.element_responses.touch(apply.shape.element);
            for (i, measure) in measure_frames.iter().enumerate() {
                if !measure.on_beam {
                    continue;
                }
                let key = (measure.shape.element, apply.shape.element);
                let pair = PairEntry {
                    rows: (&rows[i].measure, &rows[j].apply),
                    kinds: (row_kinds(system.contacts[i].rolls()), kinds_j),
                    at: (i, j),
                    offsets: (self.offsets[i], self.offsets[j]),
                };
                let integrate = (&mut self.integrator, system, self.nominal_step);
                let fill = |response: &ElementResponse| pair.fill(response, part, matrix);
                (self.element_responses).pair(integrate, key, &measured, fill);
            }
        }
        self.element_responses.end_build();
        self.beam_rows = rows;
        self.measured_elements = measured;
    }

    /// `beam_compliance_cached` where HHT-α's nominal solve is the plain
    /// band factor's: the blocks from A⁻¹ at the contacts' DOFs, taken in
    /// one pass for all of them (`condensed`).
    fn beam_compliance_condensed(
        &mut self,
        system: &System,
        (measure_frames, start_frames): (&[ContactFrame], &[ContactFrame]),
        part: Part,
        matrix: &mut DMatrix<f64>,
    ) {
        let h = system.beam.surface_offset;
        let measured = self.prepare_condensed(system, (measure_frames, start_frames), part);
        let n = matrix.nrows();
        let entries = matrix.as_mut_slice();
        for (j, apply) in start_frames.iter().enumerate().filter(|(_, f)| f.on_beam) {
            let loaded = self.condensed.places(apply.shape.element);
            let rows = rows4(apply.beam_rows(h));
            // `PairEntry::fill_part`'s entries, each loaded row's responses
            // found once for every measured contact.
            let (first, kinds_j) = self.operator_rows(system, j, part);
            for (b, &kj) in kinds_j.iter().enumerate() {
                self.condensed.respond(loaded, &rows[kj], part);
                let column = &mut entries[(first + b) * n..][..n];
                for m in &measured {
                    let response = self.condensed.response_at(m.places);
                    for (a, &ki) in m.kinds.iter().enumerate() {
                        column[m.first + a] = m.rows[ki].dot(&response);
                    }
                }
            }
        }
        self.measured_on_beam = measured;
    }

    /// The condensed blocks at the DOFs of the contacts on the beam in
    /// `frames` (measured, applied), and the measured ones
    /// (`measure_on_beam`) in `self.measured_on_beam`'s storage, which the
    /// caller hands back.
    fn prepare_condensed(
        &mut self,
        system: &System,
        (measure_frames, start_frames): (&[ContactFrame], &[ContactFrame]),
        part: Part,
    ) -> Vec<MeasuredOnBeam> {
        let on_beam = |f: &&ContactFrame| f.on_beam;
        let elements = (measure_frames.iter().chain(start_frames))
            .filter(on_beam)
            .map(|f| f.shape.element);
        let response = self.integrator.nominal_band_response();
        let response = response.expect("the caller checked it");
        self.condensed.prepare(response, system, elements);
        let mut measured = std::mem::take(&mut self.measured_on_beam);
        self.measure_on_beam(system, measure_frames, part, &mut measured);
        measured
    }

    /// The contacts of `frames` on the beam, into `measured`: their rows
    /// in `part`'s operator, their measured beam rows (turned, `turn`) and
    /// their DOFs' places in the condensed build.
    fn measure_on_beam(
        &self,
        system: &System,
        frames: &[ContactFrame],
        part: Part,
        measured: &mut Vec<MeasuredOnBeam>,
    ) {
        let h = system.beam.surface_offset;
        measured.clear();
        for (i, frame) in frames.iter().enumerate().filter(|(_, f)| f.on_beam) {
            let rows = self.measured_beam_rows(i, frame, h, part);
            let (first, kinds) = self.operator_rows(system, i, part);
            let places = self.condensed.places(frame.shape.element);
            measured.push(MeasuredOnBeam {
                first,
                contact: i,
                kinds,
                rows,
                places,
            });
        }
    }

    /// Contact c's first row in `part`'s operator and its rows' kinds
    /// there (`row_kinds`; the gap operator has the normal row alone).
    fn operator_rows(&self, system: &System, c: usize, part: Part) -> (usize, &'static [usize]) {
        match part {
            Part::Gap => (c, &[1]),
            Part::Velocity => (self.offsets[c], row_kinds(system.contacts[c].rolls())),
        }
    }

    /// Beam parts of ∂e/∂p and ∂g/∂p_n for other step lengths (the
    /// shortened steps before an event or a communication point): the beam's
    /// responses to each applied row, integrated directly.
    fn beam_compliance_integrated(
        &mut self,
        system: &System,
        (measure_frames, start_frames): (&[ContactFrame], &[ContactFrame]),
        (dt, part): (f64, Part),
        matrix: &mut DMatrix<f64>,
    ) {
        let beam = &system.beam;
        let h = beam.surface_offset;
        self.reserve_responses(self.rows);
        for (j, apply) in start_frames.iter().enumerate() {
            if !apply.on_beam {
                continue;
            }
            let (t, n) = apply.beam_rows(h);
            let rows = [t, n];
            let kinds_j = row_kinds(system.contacts[j].rolls());
            for (b, &kj) in kinds_j.iter().enumerate() {
                let column = self.offsets[j] + b;
                // The same unit load on a step of the same length: the
                // same response, bit for bit.
                let key = ResponseKey::new(dt, &apply.shape.dofs, &rows[kj]);
                if self.response_keys[column] == Some(key) {
                    continue;
                }
                self.response_keys[column] = Some(key);
                self.load.fill(0.0);
                beam.scatter(&apply.shape, &rows[kj], 1.0, &mut self.load);
                let (u, v) = (&mut self.response_u[column], &mut self.response_v[column]);
                self.integrator.beam_response(system, &self.load, dt, u, v);
                self.delassus_beam_solves += 1;
            }
            let normal_column = self.offsets[j] + kinds_j.len() - 1;
            for (i, measure) in measure_frames.iter().enumerate() {
                if !measure.on_beam {
                    continue;
                }
                let (mt, mut mn) = measure.beam_rows(h);
                if let Some(&turn) = self.turns(part).get(i) {
                    turn::add_turn(&mut mn, measure, turn);
                }
                let measure_rows = [mt, mn];
                let kinds_i = row_kinds(system.contacts[i].rolls());
                if part == Part::Gap {
                    matrix[(i, j)] = beam.dot(
                        &measure.shape,
                        &measure_rows[1],
                        &self.response_u[normal_column],
                    );
                    continue;
                }
                for (a, &ki) in kinds_i.iter().enumerate() {
                    for b in 0..kinds_j.len() {
                        let column = self.offsets[j] + b;
                        matrix[(self.offsets[i] + a, column)] =
                            beam.dot(&measure.shape, &measure_rows[ki], &self.response_v[column]);
                    }
                }
            }
        }
    }

    /// The turns of the measured rows of `part`'s operator (`turn`):
    /// none in the gap operator, nor where the scheme holds the forces at
    /// the step's start.
    fn turns(&self, part: Part) -> &[f64] {
        match part {
            Part::Velocity => &self.delassus.turns,
            Part::Gap => &[],
        }
    }

    /// Contact c's beam rows as `part`'s operator measures them at
    /// `frame`: its normal row turned (`turn`) where `part` turns it.
    fn measured_beam_rows(
        &self,
        c: usize,
        frame: &ContactFrame,
        h: f64,
        part: Part,
    ) -> [Vector4<f64>; 2] {
        let mut rows = rows4(frame.beam_rows(h));
        if let Some(&turn) = self.turns(part).get(c) {
            turn::add_turn(rows[1].iter_mut(), frame, turn);
        }
        rows
    }

    /// Body parts: contacts on the same body move it together.
    fn add_body_compliance(
        &self,
        system: &System,
        frames: (&[ContactFrame], &[ContactFrame]),
        (dt, part): (f64, Part),
        matrix: &mut DMatrix<f64>,
    ) {
        let n = matrix.nrows();
        let entries = matrix.as_mut_slice();
        self.body_entries(system, frames, (dt, part), |row, column, x| {
            entries[column * n + row] += x;
        });
    }

    /// Each body part's entry (row, column, value) of `part`'s operator:
    /// every pair of contacts on one body, column by column of a measured
    /// contact, the applied contacts' rows in their order.
    fn body_entries(
        &self,
        system: &System,
        (measure_frames, start_frames): (&[ContactFrame], &[ContactFrame]),
        (dt, part): (f64, Part),
        mut entry_at: impl FnMut(usize, usize, f64),
    ) {
        let (velocity_weight, position_weight) = self.integrator.body_weights(dt);
        for (i, ci) in system.contacts.iter().enumerate() {
            let body = &system.bodies[ci.body];
            let inverse_inertia = body.inverse_inertia();
            let measure = &measure_frames[i];
            let (mbt, mbn) = measure.body_rows(ci.radius());
            let measure_rows = [mbt, mbn];
            let (first_i, kinds_i) = self.operator_rows(system, i, part);
            for &j in &self.contacts_of_body[ci.body] {
                let apply = &start_frames[j];
                let (bt, bn) = apply.body_rows(system.contacts[j].radius());
                let rows = [bt, bn];
                let (first_j, kinds_j) = self.operator_rows(system, j, part);
                let entry = |ki: usize, kj: usize| match part {
                    Part::Gap => {
                        position_weight * body.compliance(&measure.normal(), &apply.normal())
                    }
                    Part::Velocity => {
                        let (m, r) = (&measure_rows[ki], &rows[kj]);
                        velocity_weight
                            * (body.compliance(&m.xy(), &r.xy()) + m.z * r.z * inverse_inertia)
                    }
                };
                for (b, &kj) in kinds_j.iter().enumerate() {
                    for (a, &ki) in kinds_i.iter().enumerate() {
                        entry_at(first_i + a, first_j + b, entry(ki, kj));
                    }
                }
            }
        }
    }

    /// Build and invert one block Delassus operator of the step (measured
    /// in the end frames of the integration `end` that first needed either,
    /// applied where the scheme holds the forces: in those frames or the
    /// start's) into `self.delassus`. Each is built only when its stage
    /// corrects: most steps end without the position stage, and the gap
    /// operator was half of the building.
    fn build_delassus(
        &mut self,
        system: &System,
        (start_frames, end): (&[ContactFrame], &DynamicState),
        dt: f64,
        part: Part,
    ) -> Result<(), StepError> {
        let at_end = self.integrator.holds_forces_at_end();
        if !self.delassus.built && !self.delassus.gap_built {
            self.delassus.frames.clone_from(&self.end_frames);
            if at_end {
                let measured = (self.end_frames.as_slice(), end.bodies.as_slice());
                let weights = self.integrator.body_weights(dt);
                turn::turn_rates(system, measured, weights, &mut self.delassus.turns);
            }
        }
        let measured = std::mem::take(&mut self.delassus.frames);
        let applied = if at_end { &measured } else { start_frames };
        let frames = (measured.as_slice(), applied);
        if part == Part::Velocity && self.low_rank_applies(system, applied, dt) {
            let previous = std::mem::replace(&mut self.delassus.velocity, Inverted::unbuilt(0));
            if let Some(inverted) = self.build_low_rank(system, frames, dt, previous) {
                self.delassus.frames = measured;
                (self.delassus.velocity, self.delassus.built) = (inverted, true);
                return Ok(());
            }
        }
        let mut assembly = self.delassus.part_mut(part).1.take().unwrap_or_default();
        let written = self.assemble(system, frames, (dt, part), &mut assembly);
        self.delassus.frames = measured;
        let (operator, kept) = self.delassus.part_mut(part);
        let inverted = match written {
            Ok(()) => assembly.invert(std::mem::replace(operator, Inverted::unbuilt(0))),
            Err(error) => {
                assembly.clean();
                *kept = Some(assembly);
                return Err(error);
            }
        };
        *kept = Some(assembly);
        let Some(inverted) = inverted else {
            return Err(StepError::NonFinite {
                stage: match part {
                    Part::Velocity => "velocity",
                    Part::Gap => "position",
                },
            });
        };
        match part {
            Part::Velocity => (self.delassus.velocity, self.delassus.built) = (inverted, true),
            Part::Gap => (self.delassus.gap, self.delassus.gap_built) = (inverted, true),
        }
        Ok(())
    }

    /// Lists and writes one operator's entries into `assembly`'s matrix
    /// (zero before): the beam's part, then the bodies'.
    fn assemble(
        &mut self,
        system: &System,
        frames: (&[ContactFrame], &[ContactFrame]),
        (dt, part): (f64, Part),
        assembly: &mut Assembly,
    ) -> Result<(), StepError> {
        let n = match part {
            Part::Velocity => self.rows,
            Part::Gap => system.contacts.len(),
        };
        let places = (self.offsets.as_slice(), self.open.as_slice());
        list_entries(
            system,
            frames,
            (part, n),
            places,
            &self.contacts_of_body,
            assembly,
        );
        let matrix = &mut assembly.matrix;
        // Grid steps differ from the nominal step by round-off only.
        let nominal = crate::solver::parameters::is_nominal_step(dt, self.nominal_step);
        if !self.within_deadline(system, frames.1, nominal) {
            return Err(StepError::OverBudget);
        }
        if nominal {
            self.beam_compliance_cached(system, frames, part, matrix);
        } else {
            self.beam_compliance_integrated(system, frames, (dt, part), matrix);
        }
        if crate::deadline::passed() {
            return Err(StepError::OverBudget);
        }
        self.add_body_compliance(system, frames, (dt, part), matrix);
        Ok(())
    }

    /// Whether the step's deadline still allows the beam integrations an
    /// operator applied in `start_frames` needs (`foresee_beam_integrations`
    /// refuses it up front where they cannot fit).
    fn within_deadline(
        &self,
        system: &System,
        start_frames: &[ContactFrame],
        nominal: bool,
    ) -> bool {
        if crate::deadline::is_set() {
            self.foresee_beam_integrations(system, start_frames, nominal);
        }
        !crate::deadline::passed()
    }

    /// Refuse the operator up front (`deadline::foresee`) when the beam
    /// integrations it needs, at `MIN_SECONDS_PER_ELEMENT_INTEGRATION` for
    /// each element, cannot end before the step's deadline: four per loaded
    /// element missing from the cache on grid steps, one per row applied on
    /// the beam on other steps.
    fn foresee_beam_integrations(
        &self,
        system: &System,
        start_frames: &[ContactFrame],
        nominal: bool,
    ) {
        let loaded = || {
            let mut e: Vec<usize> = start_frames
                .iter()
                .filter(|f| f.on_beam)
                .map(|f| f.shape.element)
                .collect();
            e.sort_unstable();
            e.dedup();
            e
        };
        let integrations = if nominal && self.integrator.nominal_band_response().is_some() {
            0
        } else if nominal {
            let missing = loaded()
                .into_iter()
                .filter(|&le| self.element_responses.misses(le))
                .count();
            4 * missing
        } else {
            (start_frames.iter().zip(&system.contacts))
                .filter(|(f, _)| f.on_beam)
                .map(|(_, c)| row_kinds(c.rolls()).len())
                .sum()
        };
        let elements = system.beam.elements();
        let seconds = (integrations * elements) as f64 * MIN_SECONDS_PER_ELEMENT_INTEGRATION;
        crate::deadline::foresee(seconds, || {
            format!(
                "its contact operator needs {integrations} integrations of the beam's \
                 {elements} elements, at least {} s",
                crate::numbers::fmt_number(seconds)
            )
        });
    }

    fn integrate_and_measure(
        &mut self,
        system: &System,
        from: &StepStart,
        end: &mut DynamicState,
    ) -> Result<(), StepError> {
        // The last end is this integration's prediction: where the
        // residual test (every contact compliant) evaluated the laws
        // there, they and its frames (on the same parts of the track) are
        // handed over. Not on rigid contacts: their frames too differ by
        // rounding from a search of their own, and the chattering rigid
        // wheelsets of `tests/vehicles/no_tension.rs` ended elsewhere.
        let laws = self.secant.laws_at_end();
        if let (true, Some(laws)) = (self.end_is_prediction, laws) {
            let known = KnownAtPrediction {
                frames: &self.end_frames,
                laws,
            };
            self.integrator.know_prediction(known);
        }
        self.end_is_prediction = false;
        self.secant.forget_laws_at_end();
        self.integrator.step(system, from, &self.forces, end)?;
        let (u, bodies) = (&end.beam_displacement, &end.bodies);
        let located = (end.contact_x.as_slice(), from.parts);
        contact_frames(system, u, bodies, located, &mut self.end_frames)?;
        self.end_is_prediction = self.integrator.lags_force_laws();
        for (x, frame) in end.contact_x.iter_mut().zip(&self.end_frames) {
            *x = frame.x;
        }
        Ok(())
    }

    /// Stack every contact's velocity error into `self.error`; return the
    /// largest contact's |e|.
    fn velocity_errors(&mut self, system: &System, end: &DynamicState) -> f64 {
        // Every contact open (every one a follower): every error is zero,
        // as the loop below would write them one by one.
        if self.open.iter().all(|&open| open) {
            self.error.fill(0.0);
            return 0.0;
        }
        let mut largest: f64 = 0.0;
        for (c, contact) in system.contacts.iter().enumerate() {
            // An open contact has no rows: nothing to drive to zero (its
            // error is not even measured: a follower's always is zero).
            let e = if self.open[c] {
                nalgebra::Vector2::zeros()
            } else {
                let frame = &self.end_frames[c];
                let state = &end.bodies[contact.body];
                frame.velocity_error(&system.beam, contact.radius(), state, &end.beam_velocity)
            };
            let offset = self.offsets[c];
            let norm = if contact.rolls() {
                self.error[offset] = e.x;
                self.error[offset + 1] = e.y;
                e.norm()
            } else {
                self.error[offset] = e.y;
                e.y.abs()
            };
            // NaN must win the maximum so that it is reported.
            largest = if norm.is_nan() {
                norm
            } else {
                largest.max(norm)
            };
        }
        largest
    }

    /// Every contact's gap into `gap_errors`; return the one of largest
    /// magnitude.
    fn gaps(&mut self, system: &System, end: &DynamicState) -> f64 {
        let mut worst: f64 = 0.0;
        for (c, contact) in system.contacts.iter().enumerate() {
            let centre = &contact.point(&end.bodies[contact.body]).position;
            let mut g = self.end_frames[c].gap(&system.beam, contact.radius(), centre);
            self.contact_gaps[c] = g;
            if self.open[c] {
                g = 0.0;
            }
            self.gap_errors[c] = g;
            if g.is_nan() || g.abs() > worst.abs() {
                worst = g;
            }
        }
        worst
    }

    /// Advance `start` by `dt` into `end`, finding the contact forces from
    /// the initial guesses `guess`. `applied`: the constant generalized force
    /// on each body (applied forces and weight).
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        system: &System,
        start: &DynamicState,
        parts: &[crate::system::TrackPart],
        guess: &[ContactForce],
        applied: &[nalgebra::Vector3<f64>],
        dt: f64,
        settings: &IterationSettings,
        end: &mut DynamicState,
    ) -> Result<StepSolution, StepError> {
        // Taken out of the workspace for the step: `from` lends them to the
        // integrator while the workspace is borrowed mutably.
        let mut start_frames = std::mem::take(&mut self.start_frames);
        let mut shapes = std::mem::take(&mut self.shapes);
        self.end_is_prediction = false;
        let (u, bodies) = (&start.beam_displacement, &start.bodies);
        let located = (start.contact_x.as_slice(), parts);
        self.memo
            .contact_frames(system, u, bodies, located, &mut start_frames)?;
        self.integrator.begin_step(system, dt)?;
        if self.secant.any() {
            // The first integration takes the laws at its prediction.
            self.secant.reset();
            self.integrator.hold_followers(&[]);
        }
        self.forces.clear();
        self.forces.extend_from_slice(guess);
        for ((force, contact), &open) in
            self.forces.iter_mut().zip(&system.contacts).zip(&self.open)
        {
            if !contact.rolls() {
                force.tangential = 0.0;
            }
            if open {
                *force = ContactForce::default();
            }
        }
        // An open contact's force is zero all through the step.
        for (shape, &open) in shapes.iter_mut().zip(&self.open) {
            if open {
                *shape = ForceShape::default();
            }
        }
        let from = StepStart {
            state: start,
            frames: &start_frames,
            parts,
            applied,
            dt,
            shapes: &shapes,
        };
        let solution = self.iterate(system, &from, settings, end);
        self.start_frames = start_frames;
        self.shapes = shapes;
        solution
    }

    /// Both stages of the step from `from`.
    fn iterate(
        &mut self,
        system: &System,
        from: &StepStart,
        settings: &IterationSettings,
        end: &mut DynamicState,
    ) -> Result<StepSolution, StepError> {
        // Built once per step, on the first correction that needs it.
        if !self.delassus.shared {
            self.delassus.built = false;
            self.delassus.gap_built = false;
        }
        self.previous_bodies.clear();
        // A seeded step's first integration is compared with the seed.
        let seed = (self.integrator.seeded_bodies())
            .filter(|bodies| bodies.len() == from.state.bodies.len());
        self.seeded = seed.is_some();
        self.previous_bodies
            .extend_from_slice(seed.unwrap_or_default());
        let (mut iterations, mut velocity_error) =
            self.velocity_stage(system, from, settings, end)?;
        let (position_iterations, gap_error) = self.position_stage(system, from, settings, end)?;
        iterations += position_iterations;
        // A restart's trial step is discarded but for its forces: its
        // books and end products would only displace the last accepted
        // step's, which the step after the restart starts from.
        if !self.delassus.shared {
            self.integrator.finish_step(system, from, end);
        }
        let configuration = (&end.beam_displacement, end.bodies.as_slice());
        self.memo
            .keep(system, configuration, from.parts, &self.end_frames);
        // The velocity stage measured the end state it converged at; the
        // position stage integrates again (finishing the step moves nothing).
        if position_iterations > 0 {
            velocity_error = self.velocity_errors(system, end);
        }
        let mut forces = self.forces.clone();
        match self.secant.laws_at_end() {
            // Every contact compliant and the residual test evaluated the
            // laws at this end (no integration since): their forces, the
            // same bits as `follower_forces` gives there.
            Some(_) if self.secant.every() => forces.copy_from_slice(self.secant.forces_at_end()),
            _ => crate::integrate::follower_forces(
                system,
                &self.end_frames,
                &end.bodies,
                &end.beam_velocity,
                &mut forces,
            ),
        }
        Ok(StepSolution {
            forces,
            iterations,
            position_iterations,
            velocity_error,
            gap_error,
        })
    }

    /// Velocity stage (eq. 16); returns the integrations it took and the
    /// largest contact's |e| at its end.
    fn velocity_stage(
        &mut self,
        system: &System,
        from: &StepStart,
        settings: &IterationSettings,
        end: &mut DynamicState,
    ) -> Result<(u32, f64), StepError> {
        let mut iterations = 0;
        let mut first_residual = None;
        loop {
            if crate::deadline::passed() {
                return Err(StepError::OverBudget);
            }
            self.integrate_and_measure(system, from, end)?;
            iterations += 1;
            let residual = self.velocity_errors(system, end);
            if !residual.is_finite() {
                return Err(StepError::NonFinite { stage: "velocity" });
            }
            if residual <= settings.velocity_tolerance {
                if self.laws_settled_after(system, from, settings, end, iterations)? {
                    return Ok((iterations, residual));
                }
                continue;
            }
            let first = *first_residual.get_or_insert(residual);
            velocity_progress(settings, iterations, first, residual)?;
            self.correct_velocity_forces(system, from, end)?;
        }
    }

    /// With the contacts' velocities converged: whether the force laws'
    /// fixed point has settled too; refused once `max_iterations` are spent
    /// (the bodies' last velocity change reported).
    fn laws_settled_after(
        &mut self,
        system: &System,
        from: &StepStart,
        settings: &IterationSettings,
        end: &mut DynamicState,
        iterations: u32,
    ) -> Result<bool, StepError> {
        let tolerance = settings.velocity_tolerance;
        let settled = self.settled(system, end, tolerance);
        if self.laws_settled(system, (from.dt, tolerance), end, (settled, iterations)) {
            return Ok(true);
        }
        if iterations >= settings.max_iterations {
            return Err(StepError::NotConverged {
                stage: FORCE_LAW_STAGE,
                iterations,
                residual: self.settle_change,
                tolerance,
            });
        }
        Ok(false)
    }

    /// One correction of the contact forces by the velocity operator (eq.
    /// 16), anticipating the force laws' change where they lag.
    fn correct_velocity_forces(
        &mut self,
        system: &System,
        from: &StepStart,
        end: &mut DynamicState,
    ) -> Result<(), StepError> {
        if !self.delassus.built {
            let at = (from.frames, &*end);
            self.build_delassus(system, at, from.dt, Part::Velocity)?;
        }
        let lags = self.lags_laws(system, from.dt);
        self.delassus
            .velocity
            .apply(&self.error, &mut self.correction);
        if lags {
            self.anticipate_laws(system, from.dt, end);
            self.delassus
                .velocity
                .apply(&self.error, &mut self.correction);
        }
        let correction = &self.correction;
        for (c, contact) in system.contacts.iter().enumerate() {
            let offset = self.offsets[c];
            if contact.rolls() {
                self.forces[c].tangential -= correction[offset];
                self.forces[c].normal -= correction[offset + 1];
            } else {
                self.forces[c].normal -= correction[offset];
            }
        }
        if lags {
            self.predict_bodies(system, from.dt, end);
            // The next integration's prediction is no longer this end.
            self.end_is_prediction = false;
        }
        Ok(())
    }

    /// Whether the bodies' end velocities have settled. HHT-α evaluates the
    /// force elements at the end configuration predicted by the previous
    /// integration, which the contact iteration refines as it goes; a
    /// vehicle whose contacts are all open has no contact rows to iterate
    /// on, so the step is integrated again until its velocities change by
    /// no more than `tolerance` (a fixed point, implicit as the scheme
    /// needs). A massless follower's force law is iterated the same way.
    /// RK4 and systems without force elements or followers need no
    /// prediction.
    fn settled(&mut self, system: &System, end: &DynamicState, tolerance: f64) -> bool {
        let laws = !system.force_elements.is_empty() || self.followers.contains(&true);
        // A seeded step's force elements were first taken at the seed,
        // not near this step's own end: checked as where a contact is open.
        let checked = self.open.contains(&true) || self.seeded;
        let predicted = self.integrator.lags_force_laws() && laws && checked;
        if !predicted {
            return true;
        }
        let first = self.previous_bodies.is_empty();
        let change = end
            .bodies
            .iter()
            .zip(&self.previous_bodies)
            .map(|(a, b)| (a.generalized_velocity() - b.generalized_velocity()).amax())
            .fold(0.0, f64::max);
        self.previous_bodies.clear();
        self.previous_bodies.extend_from_slice(&end.bodies);
        self.settle_change = change;
        !first && change <= tolerance
    }

    /// Position stage (eq. 17); returns its integrations and the final gap
    /// of largest magnitude.
    fn position_stage(
        &mut self,
        system: &System,
        from: &StepStart,
        settings: &IterationSettings,
        end: &mut DynamicState,
    ) -> Result<(u32, f64), StepError> {
        let mut gap = self.gaps(system, end);
        let mut iterations = 0;
        while gap.abs() > settings.gap_tolerance || gap.is_nan() {
            if !gap.is_finite() {
                return Err(StepError::NonFinite { stage: "position" });
            }
            if iterations >= settings.max_iterations {
                return Err(StepError::NotConverged {
                    stage: "position",
                    iterations,
                    residual: gap.abs(),
                    tolerance: settings.gap_tolerance,
                });
            }
            if !self.delassus.gap_built {
                let at = (from.frames, &*end);
                self.build_delassus(system, at, from.dt, Part::Gap)?;
            }
            let correction = &mut self.gap_correction;
            self.delassus.gap.apply(&self.gap_errors, correction);
            for (force, dp) in self.forces.iter_mut().zip(correction.iter()) {
                force.normal -= dp;
            }
            self.integrate_and_measure(system, from, end)?;
            gap = self.gaps(system, end);
            iterations += 1;
        }
        Ok((iterations, gap))
    }
}

/// Lists in `assembly` the entries of an n-row operator of `part` that the
/// beam and the bodies write (the contacts measured and applied on the
/// beam, and those on one body), each contact at its first row (`offsets`)
/// and open or not (`open`).
fn list_entries(
    system: &System,
    (measure_frames, start_frames): (&[ContactFrame], &[ContactFrame]),
    (part, n): (Part, usize),
    (offsets, open): (&[usize], &[bool]),
    contacts_of_body: &[Vec<usize>],
    assembly: &mut Assembly,
) {
    assembly.contacts.clear();
    for (c, contact) in system.contacts.iter().enumerate() {
        let (first, count) = match part {
            Part::Velocity => (offsets[c], contact.rows()),
            Part::Gap => (c, 1),
        };
        assembly.contacts.push(ContactRows {
            first,
            count,
            body: contact.body,
            measured_on_beam: measure_frames[c].on_beam,
            applied_on_beam: start_frames[c].on_beam,
            open: open[c],
        });
    }
    assembly.list(n, contacts_of_body);
}

/// The velocity stage refused when it diverges (after three integrations,
/// ten times its first residual) or spends `max_iterations`.
fn velocity_progress(
    settings: &IterationSettings,
    iterations: u32,
    first: f64,
    residual: f64,
) -> Result<(), StepError> {
    if iterations >= 3 && residual > 10.0 * first {
        return Err(StepError::Diverged {
            stage: "velocity",
            iterations,
            first,
            last: residual,
        });
    }
    if iterations >= settings.max_iterations {
        return Err(StepError::NotConverged {
            stage: "velocity",
            iterations,
            residual,
            tolerance: settings.velocity_tolerance,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assemble::assemble;
    use crate::integrate::{Integrator, Rk4};
    use crate::system::TrackPart;
    use nalgebra::{DVector, Vector3};

    /// Two paper wheels on a four-element beam, in different elements.
    fn two_wheels() -> (System, Vec<ContactFrame>) {
        let assembly = assemble(&crate::integrate::fixtures::two_paper_wheels()).unwrap();
        let system = assembly.system;
        let u = DVector::from_fn(system.beam.free_dofs(), |i, _| 1e-3 * libm::sin(i as f64));
        let mut frames = Vec::new();
        let guesses = [3.0, 15.5];
        let parts = [TrackPart::Beam; 2];
        contact_frames(
            &system,
            &u,
            &assembly.bodies,
            (&guesses, &parts),
            &mut frames,
        )
        .unwrap();
        (system, frames)
    }

    #[test]
    fn cached_element_pair_responses_give_the_integrated_coupling() {
        // The cached path (nominal step) and the direct integration (any
        // step) must build the same beam blocks, off-diagonal ones included.
        let (system, frames) = two_wheels();
        assert_ne!(frames[0].shape.element, frames[1].shape.element);
        let dt = 0.0025;
        let n = system.beam.free_dofs();
        let rk4 = Integrator::Rk4(Box::new(Rk4::new(n, system.bodies.len())));
        let mut iteration = ContactIteration::new(rk4, &system, dt);
        let (rows, contacts) = (iteration.rows, system.contacts.len());
        let mut cached = (
            DMatrix::zeros(rows, rows),
            DMatrix::zeros(contacts, contacts),
        );
        let both = (frames.as_slice(), frames.as_slice());
        iteration.beam_compliance_cached(&system, both, Part::Velocity, &mut cached.0);
        iteration.beam_compliance_cached(&system, both, Part::Gap, &mut cached.1);
        let mut direct = (
            DMatrix::zeros(rows, rows),
            DMatrix::zeros(contacts, contacts),
        );
        let (velocity, gap) = ((dt, Part::Velocity), (dt, Part::Gap));
        iteration.beam_compliance_integrated(&system, both, velocity, &mut direct.0);
        iteration.beam_compliance_integrated(&system, both, gap, &mut direct.1);
        let scale = direct.0.amax();
        assert!(scale > 0.0);
        assert!(
            (&cached.0 - &direct.0).amax() <= 1e-12 * scale,
            "{cached:?} vs {direct:?}"
        );
        assert!((&cached.1 - &direct.1).amax() <= 1e-12 * direct.1.amax());
        // The wheels load each other through the beam.
        assert!(
            direct.0[(1, 3)].abs() > 1e-6 * direct.0[(1, 1)].abs(),
            "{direct:?}"
        );
        assert!(direct.1[(0, 1)].abs() > 1e-6 * direct.1[(0, 0)].abs());
        // Reciprocity: the beam's response is symmetric in load and measure
        // (same frames at both ends here).
        assert!((direct.1[(0, 1)] - direct.1[(1, 0)]).abs() <= 1e-9 * direct.1[(0, 1)].abs());
    }

    #[test]
    fn condensed_hht_blocks_give_the_integrated_coupling_without_a_beam_solve() {
        // HHT-α on the nominal step: the blocks from A⁻¹ at the contacts'
        // DOFs against whole-beam solves of each applied row, on a mesh
        // beyond the band factor's dense size (wheels 12.5 m apart).
        let mut scene = crate::integrate::fixtures::two_paper_wheels();
        scene.beam.elements = 40;
        let assembly = assemble(&scene).unwrap();
        let system = assembly.system;
        let mut frames = Vec::new();
        let u = DVector::from_fn(system.beam.free_dofs(), |i, _| 1e-3 * libm::sin(i as f64));
        let located = (&[3.0, 15.5][..], &[TrackPart::Beam; 2][..]);
        contact_frames(&system, &u, &assembly.bodies, located, &mut frames).unwrap();
        let dt = 0.0025;
        let hht = crate::integrate::Hht::new(&system, 0.1, dt).unwrap();
        let mut iteration = ContactIteration::new(Integrator::Hht(Box::new(hht)), &system, dt);
        assert!(iteration.integrator.nominal_band_response().is_some());
        let (rows, contacts) = (iteration.rows, system.contacts.len());
        let both = (frames.as_slice(), frames.as_slice());
        let mut walked = Vec::new();
        for (part, size) in [(Part::Velocity, rows), (Part::Gap, contacts)] {
            let mut condensed = DMatrix::zeros(size, size);
            let solves = iteration.delassus_work().0;
            iteration.beam_compliance_cached(&system, both, part, &mut condensed);
            assert_eq!(iteration.delassus_work().0, solves, "no beam solve");
            walked.push(iteration.delassus_work().1.rows_walked);
            let mut direct = DMatrix::zeros(size, size);
            iteration.beam_compliance_integrated(&system, both, (dt, part), &mut direct);
            let scale = direct.amax();
            assert!(
                (&condensed - &direct).amax() <= 1e-12 * scale,
                "{condensed} vs {direct}"
            );
            // The wheels load each other through the beam.
            assert!(direct[(0, size - 1)].abs() > 1e-6 * direct[(0, 0)].abs());
        }
        // The direct path's solves alone (2 wheels × 2 rows, once: the gap
        // operator's unit loads and step are the velocity operator's); one
        // band of A⁻¹ for both condensed builds.
        let (solves, work) = iteration.delassus_work();
        assert_eq!((solves, work.bands, work.builds), (4, 1, 2));
        // The second build, on the same elements, keeps the first's entries.
        assert!(walked[0] > 0 && walked[1] == walked[0], "{walked:?}");
        // Another step length integrates them again, and is another operator.
        let mut shorter = DMatrix::zeros(contacts, contacts);
        iteration.beam_compliance_integrated(&system, both, (0.5 * dt, Part::Gap), &mut shorter);
        assert_eq!(iteration.delassus_work().0, 8);
        let mut again = DMatrix::zeros(contacts, contacts);
        iteration.beam_compliance_integrated(&system, both, (dt, Part::Gap), &mut again);
        assert_eq!(iteration.delassus_work().0, 12);
        assert!((&again - &shorter).amax() > 0.1 * again.amax());
    }

    /// Two gliders 2.5 m apart at 83 m/s on a 40-element beam at rest,
    /// integrated by HHT-α on steps of `dt`; the start state and the
    /// iteration.
    fn fast_gliders_on_hht(dt: f64) -> (System, DynamicState, ContactIteration) {
        let mut scene = crate::integrate::fixtures::two_paper_wheels();
        scene.beam.elements = 40;
        // A bogie's two wheelsets apart.
        scene.vehicles[1].initial_position = 5.5;
        for vehicle in &mut scene.vehicles {
            vehicle.kind = crate::scene::BodyKind::Glider;
            vehicle.inertia = None;
            vehicle.radius = None;
        }
        moving_on_hht(&scene, 83.0, dt)
    }

    /// `scene`'s bodies moving at `speed` (its wheels rolling) on the
    /// undeformed beam at rest, and an iteration under HHT-α (α = 0.1) of
    /// nominal step `dt`.
    pub(super) fn moving_on_hht(
        scene: &crate::Scene,
        speed: f64,
        dt: f64,
    ) -> (System, DynamicState, ContactIteration) {
        let assembly = assemble(scene).unwrap();
        let system = assembly.system;
        let n = system.beam.free_dofs();
        let mut bodies = assembly.bodies;
        for body in &mut bodies {
            body.velocity.x = speed;
        }
        for contact in system.contacts.iter().filter(|c| c.rolls()) {
            bodies[contact.body].angular_velocity = -speed / contact.radius();
        }
        let zeros = || DVector::zeros(n);
        let start = DynamicState {
            beam_displacement: zeros(),
            beam_velocity: zeros(),
            beam_acceleration: zeros(),
            body_accelerations: vec![Vector3::zeros(); bodies.len()],
            beam_load: zeros(),
            body_loads: vec![Vector3::zeros(); bodies.len()],
            contact_x: bodies.iter().map(|b| b.position.x).collect(),
            bodies,
            dissipated: 0.0,
            beam_dissipated: 0.0,
            tractive_work: 0.0,
            numerical_dissipation: 0.0,
        };
        let hht = crate::integrate::Hht::new(&system, 0.1, dt).unwrap();
        let iteration = ContactIteration::new(Integrator::Hht(Box::new(hht)), &system, dt);
        (system, start, iteration)
    }

    #[test]
    fn hht_velocity_operator_is_the_steps_jacobian() {
        // Finite differences of whole integrations (each a linear function
        // of the held forces) against the operator, on the nominal step
        // (condensed blocks) and a shortened one (integrated responses):
        // W⁻¹ J = I. Without the frames' turn (`turn`) the same measure
        // is off by more than 1e-4: at 83 m/s it is what the first
        // correction left.
        let nominal = 1e-3;
        for dt in [nominal, 0.37 * nominal] {
            let (system, start, mut iteration) = fast_gliders_on_hht(nominal);
            let parts = [TrackPart::Beam; 2];
            let applied = vec![Vector3::zeros(); system.bodies.len()];
            let loose = IterationSettings {
                velocity_tolerance: f64::INFINITY,
                gap_tolerance: f64::INFINITY,
                max_iterations: 1,
            };
            let base = [ContactForce {
                tangential: 0.0,
                normal: 2e4,
            }; 2];
            let mut end = start.clone();
            let mut errors = |iteration: &mut ContactIteration, forces: &[ContactForce]| {
                let step = (&applied[..], dt, &loose);
                iteration
                    .solve(
                        &system, &start, &parts, forces, step.0, step.1, step.2, &mut end,
                    )
                    .unwrap();
                iteration.velocity_errors(&system, &end);
                iteration.error.clone()
            };
            let mut jacobian = DMatrix::zeros(2, 2);
            let e0 = errors(&mut iteration, &base);
            for j in 0..2 {
                let mut pushed = base;
                pushed[j].normal += 1.0;
                let column = errors(&mut iteration, &pushed) - &e0;
                jacobian.set_column(j, &column);
            }
            // The operator in the frames of the base integration's end.
            errors(&mut iteration, &base);
            let deviation = |iteration: &mut ContactIteration| {
                iteration.delassus.built = false;
                let frames = iteration.start_frames.clone();
                iteration
                    .build_delassus(&system, (&frames, &end), dt, Part::Velocity)
                    .unwrap();
                let mut product = DMatrix::<f64>::zeros(2, 2);
                let mut out = DVector::zeros(2);
                for j in 0..2 {
                    iteration
                        .delassus
                        .velocity
                        .apply(&jacobian.column(j).into(), &mut out);
                    product.set_column(j, &out);
                }
                (product - DMatrix::<f64>::identity(2, 2)).amax()
            };
            let exact = deviation(&mut iteration);
            assert!(iteration.delassus.turns.iter().all(|&k| k > 0.0));
            assert!(exact < 1e-7, "dt {dt}: {exact:e}");
            // The same frames (the gap operator's flag keeps them), unturned.
            iteration.delassus.turns.clear();
            iteration.delassus.gap_built = true;
            let unturned = deviation(&mut iteration);
            assert!(unturned > 1e-4, "dt {dt}: {unturned:e}");
        }
    }
}
