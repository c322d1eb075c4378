//! The variable table: every exported variable of a scene, with its value
//! reference, causality, variability, type, unit, start value, bounds,
//! display unit, nominal magnitude and dependencies.
//!
//! One table feeds modelDescription.xml, the getters and setters and the
//! FMU's documentation page, so they cannot disagree.

use crate::outputs::QuantityKind;
use crate::scene::fields::{self, Access, Field, Rule, FIELDS};
use crate::scene::{BodyKind, Scene, MAX_MAGNITUDE};
use crate::simulation::{OutputInfo, OutputKind};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
}

impl Causality {
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    Fixed,
    Discrete,
    Continuous,
}

impl Variability {
    pub fn as_str(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
}

impl VarType {
    pub fn as_str(self) -> &'static str {
        match self {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
        }
    }
}

/// A scene value that is exported as a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Param {
    /// Row `field` of the scene's field table (`scene::fields::FIELDS`) of
    /// holder `holder`: the scene itself, sensor `holder` or vehicle
    /// `holder` (0: `[body]`, k: `vehicles[k-1]`), as the row's access says.
    Field { field: usize, holder: usize },
    /// The initial speed of every vehicle at once (a train's speed; no
    /// field of the scene file, so no row of the table).
    TrainSpeed,
}

/// Which input a variable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// Component `axis` (0: x, 1: y) of the applied force on vehicle
    /// `vehicle` (`scene.vehicles[vehicle]`'s `force_x`, `force_y`).
    Force { vehicle: usize, axis: usize },
    /// Component `axis` (0: force x, 1: force y, 2: moment) of the
    /// additional load on coupling point `port` (`scene.couplings[port]`).
    Coupling { port: usize, axis: usize },
}

impl Input {
    /// Where the input's value is held in the model's input vector of a
    /// scene of `vehicles` vehicles: two forces per vehicle, then three
    /// loads per coupling port.
    pub fn index(self, vehicles: usize) -> usize {
        match self {
            Input::Force { vehicle, axis } => 2 * vehicle + axis,
            Input::Coupling { port, axis } => 2 * vehicles + 3 * port + axis,
        }
    }
}

/// The inputs' start values in the order of `Input::index`: each
/// vehicle's applied force from the scene, no coupling load.
pub fn start_inputs(scene: &Scene) -> Vec<f64> {
    let forces = scene.vehicles.iter().flat_map(|v| [v.force_x, v.force_y]);
    let loads = std::iter::repeat_n(0.0, 3 * scene.couplings.len());
    forces.chain(loads).collect()
}

/// A parameter of the FMU itself, not of the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Setting {
    /// Wall-clock seconds one fmi2DoStep may take.
    WallTimeBudget,
}

/// What a variable is bound to in the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Parameter(Param),
    Setting(Setting),
    Input(Input),
    /// Index into the simulation's outputs.
    Output(usize),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

/// A unit engineers read a quantity in: shown = factor × value in `unit`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayUnit {
    pub name: &'static str,
    pub factor: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    pub name: String,
    pub value_reference: u32,
    pub causality: Causality,
    pub variability: Variability,
    pub ty: VarType,
    /// SI unit, as declared in UnitDefinitions; `None` for dimensionless.
    pub unit: Option<String>,
    pub description: String,
    /// Start value (parameters and inputs); outputs are calculated.
    pub start: Option<Value>,
    pub role: Role,
    /// How to show it, when not in `unit`.
    pub display_unit: Option<DisplayUnit>,
    /// Inclusive bounds of the values accepted (parameters).
    pub min: Option<Value>,
    pub max: Option<Value>,
    /// Typical magnitude (a power of ten), where it is far from 1.
    pub nominal: Option<f64>,
    /// Outputs: the variables (value references) the output depends on
    /// directly at a communication point; `None`: undeclared (all inputs).
    pub dependencies: Option<Vec<u32>>,
    /// Outputs: the parameters and inputs its value when initialization
    /// mode is left depends on; `None`: undeclared (all of them).
    pub initial_dependencies: Option<Vec<u32>>,
}

/// All variables of one scene, ordered by value reference (= index).
#[derive(Debug, Clone, PartialEq)]
pub struct VariableTable {
    variables: Vec<Variable>,
}

impl VariableTable {
    /// Build the table of `scene`, whose simulation has `outputs`: the
    /// scene's own parameters of the field table, the train's speed, each
    /// vehicle's parameters (every vehicle alike, in the table's order),
    /// the inputs, the outputs and the FMU's own setting, in the order of
    /// their value references (a public interface: a change is a new
    /// version).
    pub fn new(scene: &Scene, outputs: &[OutputInfo]) -> VariableTable {
        let mut b = Builder {
            vars: Vec::new(),
            scene,
        };
        b.scene_params();
        if scene.vehicles.len() > 1 {
            b.train_speed();
        }
        for vehicle in 0..scene.vehicles.len() {
            b.vehicle_params(vehicle);
        }
        // Moving forces are prescribed (their magnitude is the vehicle's
        // weight or train's axle loads): there is no body to push.
        if !crate::moving_load::is_moving_force_scene(scene) {
            for vehicle in 0..scene.vehicles.len() {
                b.force_inputs(vehicle);
            }
        }
        for (port, name) in scene.couplings.iter().enumerate() {
            let turns = outputs
                .iter()
                .any(|o| o.name == format!("{name}.angular_velocity"));
            b.coupling_inputs(name, port, turns);
        }
        b.outputs(outputs);
        // Last, so that the value references of the scene's variables do
        // not depend on it.
        b.wall_time_budget();
        let mut table = VariableTable { variables: b.vars };
        table.set_starts(scene);
        table
    }

    /// Start values (parameters, inputs) from `scene`, and the nominal
    /// magnitudes of the Reals among them.
    fn set_starts(&mut self, scene: &Scene) {
        for v in &mut self.variables {
            if let Role::Parameter(p) = v.role {
                v.start = Some(param_value(scene, p));
            }
            if let Role::Input(i) = v.role {
                v.start = Some(Value::Real(input_start(scene, i)));
            }
            if let Some(Value::Real(x)) = v.start {
                v.nominal = nominal(x);
            }
        }
    }

    /// Declare the nominal magnitudes of the outputs from their values at
    /// the start (`values[k]` of output `k`).
    pub fn set_output_nominals(&mut self, values: &[f64]) {
        for v in &mut self.variables {
            if let (Role::Output(k), VarType::Real) = (v.role, v.ty) {
                v.nominal = values.get(k).copied().and_then(nominal);
            }
        }
    }

    /// Declare what each output depends on when initialization mode is
    /// left: `deps[k]` for output `k`, as value references.
    pub fn set_initial_dependencies(&mut self, deps: &[Vec<u32>]) {
        for v in &mut self.variables {
            if let Role::Output(k) = v.role {
                v.initial_dependencies = deps.get(k).cloned();
            }
        }
    }

    pub fn variables(&self) -> &[Variable] {
        &self.variables
    }

    pub fn get(&self, vr: u32) -> Option<&Variable> {
        self.variables.get(vr as usize)
    }

    pub fn by_name(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    pub fn outputs(&self) -> impl Iterator<Item = &Variable> {
        self.variables
            .iter()
            .filter(|v| v.causality == Causality::Output)
    }

    /// Distinct units used by the variables, in order of first use, each
    /// with the display units its variables use.
    pub fn units(&self) -> Vec<(&str, Vec<DisplayUnit>)> {
        let mut units: Vec<(&str, Vec<DisplayUnit>)> = Vec::new();
        for v in &self.variables {
            let Some(u) = v.unit.as_deref() else { continue };
            let k = match units.iter().position(|(name, _)| *name == u) {
                Some(k) => k,
                None => {
                    units.push((u, Vec::new()));
                    units.len() - 1
                }
            };
            if let Some(d) = v.display_unit {
                if !units[k].1.iter().any(|e| e.name == d.name) {
                    units[k].1.push(d);
                }
            }
        }
        units
    }
}

fn unit(u: &str) -> Option<String> {
    match u.trim() {
        "" | "1" | "-" => None,
        u => Some(u.to_string()),
    }
}

/// The unit engineers read a quantity in, where it is not the SI unit:
/// loads in kN, travel speeds in km/h (the outputs the catalogue types as
/// a nominal speed or a horizontal velocity; the parameters named
/// `*speed`), sensor deflections in mm.
fn display_unit(name: &str, unit: &str) -> Option<DisplayUnit> {
    let output = crate::outputs::classify(name).map(|n| n.kind);
    let travel_speed = matches!(output, Some(QuantityKind::NominalSpeed | QuantityKind::Vx))
        || (name.ends_with("speed") && !name.starts_with("solver."));
    let (name, factor) = match unit {
        "N" => ("kN", 1e-3),
        "m/s" if travel_speed => ("km/h", 3.6),
        "m" if output == Some(QuantityKind::Sensor) => ("mm", 1e3),
        _ => return None,
    };
    Some(DisplayUnit { name, factor })
}

/// The power of ten of `x`, if it is at least three orders of magnitude
/// from 1 (where a solver or a plot would need to know the scale).
fn nominal(x: f64) -> Option<f64> {
    let m = x.abs();
    if !m.is_finite() || m == 0.0 || (1e-3..1e3).contains(&m) {
        return None;
    }
    let p = 10f64.powi(libm::log10(m).floor() as i32);
    (p.is_finite() && p > 0.0).then_some(p)
}

struct Builder<'a> {
    vars: Vec<Variable>,
    /// The scene whose variables these are (some rules depend on it).
    scene: &'a Scene,
}

impl Builder<'_> {
    fn push(&mut self, mut v: Variable) {
        v.value_reference = self.vars.len() as u32;
        self.vars.push(v);
    }

    /// A parameter named `name` under rule `rule` (Integer under
    /// `Rule::Elements`, Real otherwise; bounds: the rule's).
    fn param(&mut self, name: &str, p: Param, rule: Rule, u: &str, description: &str) {
        let (lo, hi) = rule.bounds(self.scene.track.approach);
        let (ty, min, max) = match rule {
            Rule::Elements => (
                VarType::Integer,
                Value::Integer(lo as i32),
                Value::Integer(hi as i32),
            ),
            _ => (VarType::Real, Value::Real(lo), Value::Real(hi)),
        };
        self.push(Variable {
            name: name.to_string(),
            value_reference: 0,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            ty,
            unit: unit(u),
            description: description.to_string(),
            start: None,
            role: Role::Parameter(p),
            display_unit: display_unit(name, u),
            min: Some(min),
            max: Some(max),
            nominal: None,
            dependencies: None,
            initial_dependencies: None,
        });
    }

    /// Holder `holder` of table row `field` as a parameter.
    fn field_param(&mut self, field: usize, holder: usize) {
        let f = &FIELDS[field];
        let name = f.fmu_name(self.scene, holder);
        let p = Param::Field { field, holder };
        self.param(&name, p, f.rule, f.unit, f.doc);
    }

    /// The scene's own and its sensors' rows, in the table's order, each
    /// for every holder it exports.
    fn scene_params(&mut self) {
        for (field, f) in FIELDS.iter().enumerate() {
            let scene_row = matches!(
                f.access,
                Access::Scene(..) | Access::Beam(..) | Access::Sensor(..)
            );
            if !scene_row || f.doc.is_empty() {
                continue;
            }
            for holder in 0..f.holders(self.scene) {
                if exported(self.scene, f, holder) {
                    self.field_param(field, holder);
                }
            }
        }
    }

    /// Vehicle `k`'s exported fields, in the table's order.
    fn vehicle_params(&mut self, k: usize) {
        for (field, f) in FIELDS.iter().enumerate() {
            if matches!(f.access, Access::Vehicle(..)) && exported(self.scene, f, k) {
                self.field_param(field, k);
            }
        }
    }

    fn train_speed(&mut self) {
        self.param(
            "train.initial_speed",
            Param::TrainSpeed,
            Rule::Finite,
            "m/s",
            "initial travel speed of every vehicle at once (each vehicle's own \
             initial_speed, set after it, overrides it)",
        );
    }

    /// The applied force on the centre of vehicle `vehicle`'s first body
    /// (its `force_x`, `force_y`).
    fn force_inputs(&mut self, vehicle: usize) {
        let name = &self.scene.vehicles[vehicle].name;
        let x = format!("{name}.force_x");
        let y = format!("{name}.force_y");
        let force = |axis| Input::Force { vehicle, axis };
        self.input(&x, force(0), "horizontal force on the body's centre");
        self.input(&y, force(1), "vertical force on the body's centre");
    }

    /// The coupling port's inputs on body `name`: the force, and the
    /// moment on a body that turns.
    fn coupling_inputs(&mut self, name: &str, port: usize, turns: bool) {
        let axes = [
            ("coupling_force_x", "N", "additional horizontal force on the body's centre from a coupled model (global x, positive to the right)"),
            ("coupling_force_y", "N", "additional vertical force on the body's centre from a coupled model (global y, positive up; the body's weight is already applied)"),
            ("coupling_moment", "N.m", "additional moment on the body from a coupled model (counter-clockwise positive)"),
        ];
        for (axis, (suffix, u, description)) in axes.into_iter().enumerate() {
            if axis == 2 && !turns {
                continue;
            }
            let name = format!("{name}.{suffix}");
            self.input(&name, Input::Coupling { port, axis }, description);
            let v = self.vars.last_mut().expect("just pushed");
            v.unit = unit(u);
            v.display_unit = display_unit(&name, u);
        }
    }

    fn input(&mut self, name: &str, i: Input, description: &str) {
        self.push(Variable {
            name: name.to_string(),
            value_reference: 0,
            causality: Causality::Input,
            variability: Variability::Continuous,
            ty: VarType::Real,
            unit: Some("N".into()),
            description: description.to_string(),
            start: None,
            role: Role::Input(i),
            display_unit: display_unit(name, "N"),
            // Model::set refuses a force beyond the scene's magnitude rule.
            min: Some(Value::Real(-MAX_MAGNITUDE)),
            max: Some(Value::Real(MAX_MAGNITUDE)),
            nominal: None,
            dependencies: None,
            initial_dependencies: None,
        });
    }

    /// Every output of the simulation, in its order.
    fn outputs(&mut self, outputs: &[OutputInfo]) {
        for (i, o) in outputs.iter().enumerate() {
            let (ty, variability) = match o.kind {
                OutputKind::Real => (VarType::Real, Variability::Continuous),
                OutputKind::Integer => (VarType::Integer, Variability::Discrete),
            };
            self.push(Variable {
                name: o.name.clone(),
                value_reference: 0,
                causality: Causality::Output,
                variability,
                ty,
                unit: unit(o.unit),
                description: o.description.clone(),
                start: None,
                role: Role::Output(i),
                display_unit: display_unit(&o.name, o.unit),
                min: None,
                max: None,
                nominal: None,
                // A co-simulation output is the state at the communication
                // point: an input set there acts over the next step only.
                dependencies: Some(Vec::new()),
                initial_dependencies: None,
            });
        }
    }

    fn wall_time_budget(&mut self) {
        self.push(Variable {
            name: "solver.wall_time_budget".into(),
            value_reference: 0,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            ty: VarType::Real,
            unit: unit("s"),
            description: "wall-clock time one fmi2DoStep may take; beyond it the step is rolled \
                          back and discarded"
                .into(),
            start: Some(Value::Real(crate::model::DEFAULT_WALL_TIME_BUDGET)),
            role: Role::Setting(Setting::WallTimeBudget),
            display_unit: None,
            // "> 0", as Model::set checks it
            min: Some(Value::Real(f64::from_bits(1))),
            max: None,
            nominal: None,
            dependencies: None,
            initial_dependencies: None,
        });
    }
}

/// Whether holder `k` of row `f` is a parameter of `scene`: present, with
/// an FMU description, and read by the scene's physics. A moving force is
/// prescribed: it reads its place, its speed and (without a train, whose
/// axle loads are fixed) its mass, whose weight is its force; it has no
/// body's fields and no contact iteration to tolerate errors of.
fn exported(scene: &Scene, f: &Field, k: usize) -> bool {
    if f.doc.is_empty() || f.value(scene, k).is_none() {
        return false;
    }
    let moving_force = match f.access {
        Access::Vehicle(..) => {
            fields::vehicle(scene, k).expect("present").kind == BodyKind::MovingForce
        }
        _ => crate::moving_load::is_moving_force_scene(scene),
    };
    if !moving_force {
        return true;
    }
    match f.path {
        "solver.velocity_tolerance" | "solver.gap_tolerance" => false,
        "body.initial_position" | "body.initial_speed" => true,
        "body.mass" => fields::vehicle(scene, k).is_some_and(|v| v.train.is_none()),
        path => !path.starts_with("body."),
    }
}

/// The rule of parameter `p` (the field table's).
fn rule(p: Param) -> Rule {
    match p {
        Param::Field { field, .. } => FIELDS[field].rule,
        Param::TrainSpeed => Rule::Finite,
    }
}

/// Current value of a parameter in `scene` (Integer for an element count).
pub fn param_value(scene: &Scene, p: Param) -> Value {
    let x = match p {
        Param::Field { field, holder } => FIELDS[field].value(scene, holder).unwrap_or(0.0),
        // Every vehicle's is the same until one is set on its own.
        Param::TrainSpeed => scene.vehicles.first().map_or(0.0, |v| v.initial_speed),
    };
    match rule(p) {
        Rule::Elements => Value::Integer(x.min(i32::MAX as f64) as i32),
        _ => Value::Real(x),
    }
}

/// Check `value` against the rule of parameter `p` (the field table's, in
/// its words), then write it into `scene`. On error the scene is unchanged
/// and the message states the rule.
pub fn set_param(scene: &mut Scene, p: Param, value: Value) -> Result<(), String> {
    let rule = rule(p);
    let x = match (rule, value) {
        (Rule::Elements, Value::Integer(n)) => f64::from(n),
        (Rule::Elements, _) => return Err("must be an Integer".into()),
        (_, Value::Real(x)) => x,
        _ => return Err("must be a Real".into()),
    };
    if let Some(words) = rule.problem(x, scene.track.approach) {
        return Err(words);
    }
    match p {
        Param::Field { field, holder } => {
            if !FIELDS[field].set(scene, holder, x) {
                return Err("is not a field of this scene".into());
            }
        }
        Param::TrainSpeed => {
            let set = fields::initial_speed_setter();
            scene.vehicles.iter_mut().for_each(|v| set(v, x));
        }
    }
    Ok(())
}

fn input_start(scene: &Scene, i: Input) -> f64 {
    start_inputs(scene)[i.index(scene.vehicles.len())]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::fake::FakeDynamics;
    use crate::model::Dynamics;
    use crate::scene::MIN_MAGNITUDE;
    use crate::simulation::Steppable;

    fn table(kind: BodyKind) -> VariableTable {
        let scene = Scene::lee1994(kind, 10.0, 0.0025);
        let sim = FakeDynamics::build(&scene).unwrap();
        VariableTable::new(&scene, sim.outputs())
    }

    #[test]
    fn value_references_are_indices_and_names_unique() {
        let t = table(BodyKind::Wheel);
        for (i, v) in t.variables().iter().enumerate() {
            assert_eq!(v.value_reference as usize, i);
            assert_eq!(
                t.by_name(&v.name).unwrap().value_reference,
                v.value_reference
            );
        }
    }

    #[test]
    fn glider_has_no_wheel_only_variables() {
        let t = table(BodyKind::Glider);
        assert!(t.by_name("glider.radius").is_none());
        assert!(t.by_name("glider.inertia").is_none());
        assert!(t.by_name("glider.mass").is_some());
        let w = table(BodyKind::Wheel);
        assert!(w.by_name("wheel.radius").is_some());
        assert!(w.by_name("wheel.inertia").is_some());
    }

    #[test]
    fn starts_come_from_the_scene() {
        let t = table(BodyKind::Wheel);
        assert_eq!(
            t.by_name("beam.length").unwrap().start,
            Some(Value::Real(24.0))
        );
        assert_eq!(
            t.by_name("beam.elements").unwrap().start,
            Some(Value::Integer(2))
        );
        assert_eq!(
            t.by_name("wheel.force_y").unwrap().start,
            Some(Value::Real(-600e3))
        );
        assert_eq!(
            t.by_name("sensor.midspan.position").unwrap().start,
            Some(Value::Real(12.0))
        );
    }

    /// The declared bounds are the rule: the bound itself is accepted, the
    /// next value beyond it refused.
    #[test]
    fn declared_bounds_are_the_rules_of_set_param() {
        let t = table(BodyKind::Wheel);
        let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        for v in t.variables() {
            let Role::Parameter(p) = v.role else { continue };
            let ok = |x: Value| set_param(&mut scene.clone(), p, x).is_ok();
            match (v.min, v.max) {
                (Some(Value::Real(lo)), Some(Value::Real(hi))) => {
                    assert!(ok(Value::Real(lo)) && ok(Value::Real(hi)), "{}", v.name);
                    assert!(!ok(Value::Real(lo.next_down())), "{}", v.name);
                    assert!(!ok(Value::Real(hi.next_up())), "{}", v.name);
                }
                (Some(Value::Integer(lo)), Some(Value::Integer(hi))) => {
                    assert!(ok(Value::Integer(lo)) && ok(Value::Integer(hi)));
                    assert!(!ok(Value::Integer(lo - 1)) && !ok(Value::Integer(hi + 1)));
                }
                (None, None) => assert!(ok(Value::Real(-1e300)) && ok(Value::Real(1e300))),
                bounds => panic!("{}: unexpected bounds {bounds:?}", v.name),
            }
        }
        assert_eq!(
            t.by_name("wheel.mass").unwrap().min,
            Some(Value::Real(MIN_MAGNITUDE))
        );
        assert_eq!(
            t.by_name("wheel.initial_speed").unwrap().max,
            Some(Value::Real(MAX_MAGNITUDE))
        );
        assert_eq!(
            t.by_name("beam.surface_offset").unwrap().min,
            Some(Value::Real(0.0))
        );
    }

    #[test]
    fn display_units_and_nominals() {
        let t = table(BodyKind::Wheel);
        let shown = |n: &str| {
            t.by_name(n)
                .unwrap()
                .display_unit
                .map(|d| (d.name, d.factor))
        };
        assert_eq!(shown("wheel.force_y"), Some(("kN", 1e-3)));
        assert_eq!(shown("wheel.initial_speed"), Some(("km/h", 3.6)));
        assert_eq!(shown("sensor.midspan.deflection"), Some(("mm", 1e3)));
        assert_eq!(shown("solver.velocity_tolerance"), None);
        assert_eq!(shown("beam.length"), None);
        let nominal = |n: &str| t.by_name(n).unwrap().nominal;
        assert_eq!(nominal("beam.bending_stiffness"), Some(1e9));
        assert_eq!(nominal("wheel.force_y"), Some(1e5));
        assert_eq!(nominal("solver.velocity_tolerance"), Some(1e-7));
        assert_eq!(nominal("beam.length"), None);
        let units = t.units();
        let n = units.iter().find(|(u, _)| *u == "N").unwrap();
        assert_eq!(n.1.len(), 1);
    }

    #[test]
    fn outputs_declare_no_direct_dependency() {
        let t = table(BodyKind::Wheel);
        for v in t.outputs() {
            assert_eq!(v.dependencies.as_deref(), Some(&[][..]), "{}", v.name);
        }
    }

    #[test]
    fn bad_values_are_refused_and_leave_the_scene_alone() {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let before = scene.clone();
        let mass = table(BodyKind::Wheel).by_name("wheel.mass").unwrap().role;
        let Role::Parameter(mass) = mass else {
            panic!("wheel.mass is a parameter")
        };
        assert!(set_param(&mut scene, mass, Value::Real(-1.0))
            .unwrap_err()
            .contains("> 0"));
        let t = table(BodyKind::Wheel);
        let length = param_of(&t, "beam.length");
        let elements = param_of(&t, "beam.elements");
        let refused = |scene: &mut Scene, p, x| set_param(scene, p, x).unwrap_err();
        assert!(refused(&mut scene, length, Value::Real(f64::NAN)).contains("finite"));
        assert!(refused(&mut scene, length, Value::Integer(3)).contains("a Real"));
        assert!(refused(&mut scene, elements, Value::Integer(0)).contains(">= 1"));
        assert!(refused(&mut scene, elements, Value::Real(8.0)).contains("an Integer"));
        assert_eq!(scene, before);
        set_param(&mut scene, elements, Value::Integer(8)).unwrap();
        assert_eq!(scene.beam.elements, 8);
    }

    fn param_of(t: &VariableTable, name: &str) -> Param {
        match t.by_name(name).map(|v| v.role) {
            Some(Role::Parameter(p)) => p,
            other => panic!("{name}: {other:?}"),
        }
    }

    /// Issue 27 item 2: every vehicle's numeric fields are parameters, each
    /// writing its own vehicle only; a train's speed moves every vehicle.
    #[test]
    fn every_vehicle_has_its_parameters_and_a_train_one_speed() {
        let scene = Scene::load("train-3-coaches-2x25-5").unwrap();
        let t = VariableTable::new(&scene, &[]);
        let stiffness = param_of(&t, "coach2.bogie.primary_stiffness");
        let mut changed = scene.clone();
        set_param(&mut changed, stiffness, Value::Real(2.5e6)).unwrap();
        let bogie = |s: &Scene, k: usize| s.vehicles[k + 1].bogie.unwrap();
        assert_eq!(bogie(&changed, 0).primary_stiffness, 2.5e6);
        assert_eq!(bogie(&changed, 1), bogie(&scene, 1));
        assert_eq!(changed.vehicles[0], scene.vehicles[0]);
        // refused by its rule, the scene left alone
        let before = changed.clone();
        assert!(set_param(&mut changed, stiffness, Value::Real(-1.0)).is_err());
        assert_eq!(changed, before);
        // the train's speed, then one vehicle's own
        set_param(
            &mut changed,
            param_of(&t, "train.initial_speed"),
            Value::Real(7.0),
        )
        .unwrap();
        set_param(
            &mut changed,
            param_of(&t, "coach3.initial_speed"),
            Value::Real(6.0),
        )
        .unwrap();
        let speeds: Vec<f64> = changed.vehicles.iter().map(|v| v.initial_speed).collect();
        assert_eq!(speeds, [7.0, 7.0, 6.0]);
        let names: Vec<&str> = t.variables().iter().map(|v| v.name.as_str()).collect();
        for (i, n) in names.iter().enumerate() {
            assert!(!names[..i].contains(n), "{n} twice");
        }
    }

    /// Every vehicle's parameters in the table's order, the same rows for
    /// vehicles of one kind, and force inputs on each (issue 23: the first
    /// vehicle is not special).
    #[test]
    fn every_vehicle_has_the_same_rows_in_the_table_s_order() {
        let scene = Scene::load("train-3-coaches-2x25-5").unwrap();
        let t = VariableTable::new(&scene, &[]);
        let rows = |vehicle: usize| -> Vec<usize> {
            let rows = t.variables().iter().filter_map(|v| match v.role {
                Role::Parameter(Param::Field { field, holder }) if holder == vehicle => {
                    matches!(FIELDS[field].access, Access::Vehicle(..)).then_some(field)
                }
                _ => None,
            });
            rows.collect()
        };
        let first = rows(0);
        assert!(first.windows(2).all(|w| w[0] < w[1]), "{first:?}");
        assert!(first.len() > 5, "{first:?}");
        assert_eq!(rows(1), first);
        assert_eq!(rows(2), first);
        for v in &scene.vehicles {
            for (axis, force) in [(0, v.force_x), (1, v.force_y)] {
                let name = format!("{}.{}", v.name, ["force_x", "force_y"][axis]);
                let input = t.by_name(&name).unwrap_or_else(|| panic!("{name}"));
                assert_eq!(input.causality, Causality::Input, "{name}");
                assert_eq!(input.start, Some(Value::Real(force)), "{name}");
            }
        }
    }

    /// Every built-in scene and every scene file shipped in `scenes/` (a
    /// sprung mass, a maglev vehicle and a train on the rail among them).
    fn every_shipped_scene() -> Vec<Scene> {
        let builtins = crate::scene::builtins().iter();
        let mut scenes: Vec<Scene> = builtins
            .map(|(name, _)| crate::scene::builtin(name).unwrap())
            .collect();
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        for file in std::fs::read_dir(dir).unwrap() {
            let path = file.unwrap().path();
            scenes.push(Scene::load(path.to_str().unwrap()).unwrap());
        }
        scenes
    }

    /// The field table and the FMU cannot drift apart (issue 23, step 9):
    /// every parameter of every shipped scene is a row of the table, named,
    /// in units, described and bounded as the row says (or the train's
    /// speed, or the FMU's own setting), and every row with a description
    /// and an access is a parameter of some shipped scene.
    #[test]
    fn parameters_are_the_rows_of_the_field_table() {
        let mut exported = vec![false; FIELDS.len()];
        for scene in every_shipped_scene() {
            let t = VariableTable::new(&scene, &[]);
            for v in t.variables() {
                let (field, holder) = match v.role {
                    Role::Parameter(Param::Field { field, holder }) => (field, holder),
                    Role::Parameter(Param::TrainSpeed) => {
                        assert_eq!(v.name, "train.initial_speed");
                        continue;
                    }
                    Role::Setting(_) => continue,
                    Role::Input(_) | Role::Output(_) => {
                        assert_ne!(v.causality, Causality::Parameter, "{}", v.name);
                        continue;
                    }
                };
                let f = &FIELDS[field];
                exported[field] = true;
                assert_eq!(v.name, f.fmu_name(&scene, holder), "{}", scene.name);
                assert!(v.name.ends_with(f.path.rsplit('.').next().unwrap()));
                assert_eq!(v.unit, unit(f.unit), "{}", v.name);
                assert_eq!(v.description, f.doc, "{}", v.name);
                let (lo, hi) = f.rule.bounds(scene.track.approach);
                let bounds = match (v.min, v.max) {
                    (Some(Value::Real(a)), Some(Value::Real(b))) => (a, b),
                    (Some(Value::Integer(a)), Some(Value::Integer(b))) => (a.into(), b.into()),
                    other => panic!("{}: bounds {other:?}", v.name),
                };
                assert_eq!(bounds, (lo, hi), "{}", v.name);
                let start = param_value(&scene, Param::Field { field, holder });
                assert_eq!(v.start, Some(start), "{}", v.name);
            }
        }
        for (f, seen) in FIELDS.iter().zip(exported) {
            let documented = !f.doc.is_empty() && !matches!(f.access, Access::None);
            assert_eq!(seen, documented, "{}: a parameter of some scene", f.path);
        }
    }
}
