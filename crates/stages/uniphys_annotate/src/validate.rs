//! Validation of the model's answers against the schema of [`crate::schema`]. Every violation is
//! collected with the path of the offending value (`parts[3].density: "7.8 kg" is not in
//! g/cm^3`), so one repair turn can list them all; nothing is dropped silently.
//!
//! Checked: types and presence of every key, labels 1..n each exactly once, material categories
//! of the table, finite numbers in plausible ranges (wider than the material priors: a value
//! outside its prior is kept and flagged later by the verifier), units that parse, neighbour
//! labels that exist, B/C neighbours with parent, child, damping and a range of the right kind,
//! and for the articulation answer colours of the legends, the direction and the pivot.

use serde_json::{Map, Value};
use uniphys_types::Material;

use crate::colours::colour_index;
use crate::quantities::{MotionRange, density_kg_per_m3, dimensions_m, mass_kg, motion_range};
use crate::schema::{
    ArticulationAnswer, DescriptionsAnswer, MotionDirection, MovementType, NeighbourAnswer,
    PartAnswer, PropertiesAnswer,
};

/// Plausible density, kg/m^3 (aerogel to osmium, with margin).
pub const DENSITY_KG_PER_M3: (f64, f64) = (1.0, 25_000.0);
/// Plausible Young's modulus, GPa.
pub const YOUNGS_MODULUS_GPA: (f64, f64) = (1e-6, 1_200.0);
/// Plausible Vickers hardness, HV.
pub const HARDNESS_HV: (f64, f64) = (1e-4, 10_000.0);
/// Poisson's ratio.
pub const POISSON_RATIO: (f64, f64) = (0.0, 0.5);
/// Friction coefficient.
pub const FRICTION: (f64, f64) = (0.0, 2.0);
/// Affordance rank.
pub const AFFORDANCE_RANK: (u64, u64) = (1, 10);
/// Object mass, kg.
pub const OBJECT_MASS_KG: (f64, f64) = (1e-4, 1e5);
/// One object dimension, metres.
pub const DIMENSION_M: (f64, f64) = (1e-4, 100.0);
/// Joint damping coefficient (N m s/rad or N s/m).
pub const DAMPING: (f64, f64) = (0.0, 100.0);
/// Largest magnitude of a slide limit, metres.
pub const MAX_SLIDE_M: f64 = 10.0;
/// Largest magnitude of a rotation limit, radians (one full turn).
pub const MAX_TURN_RAD: f64 = std::f64::consts::TAU;

/// One way an answer breaks the schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Violation {
    /// JSON path of the value, e.g. `parts[3].density` (`$` for the whole answer).
    pub path: String,
    /// What is wrong with it.
    pub message: String,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

#[derive(Default)]
struct Checker {
    violations: Vec<Violation>,
}

fn show(value: &Value) -> String {
    let text = value.to_string();
    if text.chars().count() > 60 {
        format!("{}...", text.chars().take(57).collect::<String>())
    } else {
        text
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_owned()
    } else {
        format!("{path}.{key}")
    }
}

impl Checker {
    fn fail(&mut self, path: impl Into<String>, message: impl Into<String>) {
        self.violations.push(Violation {
            path: path.into(),
            message: message.into(),
        });
    }

    fn field<'v>(
        &mut self,
        obj: &'v Map<String, Value>,
        path: &str,
        key: &str,
    ) -> Option<&'v Value> {
        let value = obj.get(key);
        if value.is_none_or(Value::is_null) {
            self.fail(join(path, key), "is missing");
            return None;
        }
        value
    }

    fn object<'v>(&mut self, value: &'v Value, path: &str) -> Option<&'v Map<String, Value>> {
        let obj = value.as_object();
        if obj.is_none() {
            self.fail(
                if path.is_empty() { "$" } else { path },
                format!("{} is not a JSON object", show(value)),
            );
        }
        obj
    }

    fn string(&mut self, obj: &Map<String, Value>, path: &str, key: &str) -> Option<String> {
        let value = self.field(obj, path, key)?;
        match value.as_str() {
            Some(s) => Some(s.to_owned()),
            None => {
                self.fail(join(path, key), format!("{} is not a string", show(value)));
                None
            }
        }
    }

    /// A string that must parse with `parse`; `unit` says what was expected.
    fn quantity<T>(
        &mut self,
        obj: &Map<String, Value>,
        path: &str,
        key: &str,
        unit: &str,
        parse: impl Fn(&str) -> Option<T>,
    ) -> Option<(String, T)> {
        let value = self.field(obj, path, key)?;
        let Some(text) = value.as_str() else {
            self.fail(
                join(path, key),
                format!("{} is not a string with a unit like {unit}", show(value)),
            );
            return None;
        };
        match parse(text) {
            Some(parsed) => Some((text.to_owned(), parsed)),
            None => {
                self.fail(join(path, key), format!("{text:?} is not in {unit}"));
                None
            }
        }
    }

    fn number(
        &mut self,
        obj: &Map<String, Value>,
        path: &str,
        key: &str,
        range: (f64, f64),
    ) -> Option<f64> {
        let value = self.field(obj, path, key)?;
        let Some(x) = value.as_f64() else {
            self.fail(join(path, key), format!("{} is not a number", show(value)));
            return None;
        };
        self.in_range(&join(path, key), x, range).then_some(x)
    }

    fn in_range(&mut self, path: &str, x: f64, range: (f64, f64)) -> bool {
        if x.is_finite() && x >= range.0 && x <= range.1 {
            true
        } else {
            self.fail(
                path,
                format!(
                    "{x} is outside the plausible range [{}, {}]",
                    range.0, range.1
                ),
            );
            false
        }
    }

    fn integer(
        &mut self,
        obj: &Map<String, Value>,
        path: &str,
        key: &str,
        range: (u64, u64),
    ) -> Option<u64> {
        let value = self.field(obj, path, key)?;
        let Some(x) = value.as_u64() else {
            self.fail(
                join(path, key),
                format!("{} is not a non-negative integer", show(value)),
            );
            return None;
        };
        if x < range.0 || x > range.1 {
            self.fail(
                join(path, key),
                format!("{x} is outside [{}, {}]", range.0, range.1),
            );
            return None;
        }
        Some(x)
    }

    fn boolean(&mut self, obj: &Map<String, Value>, path: &str, key: &str) -> Option<bool> {
        let value = self.field(obj, path, key)?;
        let b = value.as_bool();
        if b.is_none() {
            self.fail(
                join(path, key),
                format!("{} is not true or false", show(value)),
            );
        }
        b
    }

    fn finish<T>(self, value: Option<T>) -> Result<T, Vec<Violation>> {
        match value {
            Some(v) if self.violations.is_empty() => Ok(v),
            _ => Err(if self.violations.is_empty() {
                vec![Violation {
                    path: "$".into(),
                    message: "the answer could not be read".into(),
                }]
            } else {
                self.violations
            }),
        }
    }
}

/// Checks a properties answer for an object of `part_count` parts.
///
/// # Errors
/// Every violation found, in document order (label coverage last).
pub fn validate_properties(
    value: &Value,
    part_count: usize,
) -> Result<PropertiesAnswer, Vec<Violation>> {
    let mut c = Checker::default();
    let answer = properties(&mut c, value, part_count);
    c.finish(answer)
}

fn properties(c: &mut Checker, value: &Value, part_count: usize) -> Option<PropertiesAnswer> {
    let obj = c.object(value, "")?;
    let object_name = c.string(obj, "", "object_name");
    let category = c.string(obj, "", "category");
    let dimensions = c
        .quantity(obj, "", "dimensions", "\"L*W*H cm\"", dimensions_m)
        .filter(|(_, dims)| {
            dims.iter()
                .all(|d| c.in_range("dimensions", *d, DIMENSION_M))
        });
    let mass = c
        .quantity(obj, "", "mass", "kg", mass_kg)
        .filter(|(_, kg)| c.in_range("mass", *kg, OBJECT_MASS_KG));
    let labels_max = u64::try_from(part_count).unwrap_or(u64::MAX);
    let mut parts = Vec::new();
    let mut labels: Vec<Option<u64>> = Vec::new();
    match c.field(obj, "", "parts").map(|v| (v, v.as_array())) {
        Some((_, Some(items))) => {
            if items.len() != part_count {
                c.fail(
                    "parts",
                    format!(
                        "has {} entries; the object has {part_count} parts (one per image)",
                        items.len()
                    ),
                );
            }
            for (i, item) in items.iter().enumerate() {
                labels.push(item.get("label").and_then(Value::as_u64));
                if let Some(p) = part(c, item, &format!("parts[{i}]"), labels_max) {
                    parts.push(p);
                }
            }
        }
        Some((v, None)) => c.fail("parts", format!("{} is not an array", show(v))),
        None => {}
    }
    let all_read = labels.iter().all(Option::is_some);
    let mut seen = vec![0usize; part_count];
    for label in labels.iter().flatten() {
        if let Some(count) = usize::try_from(*label)
            .ok()
            .and_then(|l| l.checked_sub(1))
            .and_then(|i| seen.get_mut(i))
        {
            *count += 1;
        }
    }
    for (i, count) in seen.iter().enumerate() {
        match count {
            1 => {}
            0 if !all_read || labels.is_empty() => {}
            0 => c.fail("parts", format!("label {} is missing", i + 1)),
            n => c.fail("parts", format!("label {} appears {n} times", i + 1)),
        }
    }
    parts.sort_by_key(|p| p.label);
    Some(PropertiesAnswer {
        object_name: object_name?,
        category: category?,
        dimensions: dimensions?.0,
        mass: mass?.0,
        parts,
    })
}

fn part(c: &mut Checker, value: &Value, path: &str, labels_max: u64) -> Option<PartAnswer> {
    let obj = c.object(value, path)?;
    let label = c.integer(obj, path, "label", (1, labels_max));
    let name = c.string(obj, path, "name");
    let material = c.string(obj, path, "material").filter(|m| {
        let ok = Material::parse(m).is_ok();
        if !ok {
            c.fail(
                join(path, "material"),
                format!(
                    "{m:?} does not start with a category of the table (metal, plastic, fabric, leather, foam, rubber, glass, stone, ceramics, wood, concrete, other)"
                ),
            );
        }
        ok
    });
    let density = c
        .quantity(obj, path, "density", "g/cm^3", density_kg_per_m3)
        .filter(|(_, d)| c.in_range(&join(path, "density"), *d, DENSITY_KG_PER_M3));
    let young = c.number(obj, path, "youngs_modulus_gpa", YOUNGS_MODULUS_GPA);
    let hardness = c.number(obj, path, "hardness_hv", HARDNESS_HV);
    let poisson = c.number(obj, path, "poisson_ratio", POISSON_RATIO);
    let friction = c.number(obj, path, "friction_coefficient", FRICTION);
    let rank = c.integer(obj, path, "affordance_rank", AFFORDANCE_RANK);
    let graspable = c.boolean(obj, path, "graspable");
    let neighbours = match c.field(obj, path, "neighbours") {
        Some(Value::Array(items)) => {
            let own = label.unwrap_or(0);
            let mut out = Vec::new();
            let mut ok = true;
            for (i, item) in items.iter().enumerate() {
                let npath = format!("{path}.neighbours[{i}]");
                match neighbour(c, item, &npath, own, labels_max) {
                    Some(n) => out.push(n),
                    None => ok = false,
                }
            }
            ok.then_some(out)
        }
        Some(other) => {
            c.fail(
                join(path, "neighbours"),
                format!("{} is not an array", show(other)),
            );
            None
        }
        None => None,
    };
    let descriptions = c
        .field(obj, path, "descriptions")
        .and_then(|v| descriptions(c, v, &join(path, "descriptions")));
    Some(PartAnswer {
        label: u32::try_from(label?).ok()?,
        name: name?,
        material: material?,
        density: density?.0,
        youngs_modulus_gpa: young?,
        hardness_hv: hardness?,
        poisson_ratio: poisson?,
        friction_coefficient: friction?,
        affordance_rank: u8::try_from(rank?).ok()?,
        graspable: graspable?,
        neighbours: neighbours?,
        descriptions: descriptions?,
    })
}

fn neighbour(
    c: &mut Checker,
    value: &Value,
    path: &str,
    own: u64,
    labels_max: u64,
) -> Option<NeighbourAnswer> {
    let obj = c.object(value, path)?;
    let label = c.integer(obj, path, "label", (1, labels_max));
    if label.is_some_and(|l| l == own) {
        c.fail(join(path, "label"), format!("{own} is the part itself"));
    }
    let kind = c.string(obj, path, "movement_type").and_then(|t| {
        let parsed = MovementType::parse(&t);
        if parsed.is_none() {
            c.fail(
                join(path, "movement_type"),
                format!("{t:?} is not one of A, B, C, D"),
            );
        }
        parsed
    });
    let kind = kind?;
    if !kind.is_motion() {
        return Some(NeighbourAnswer {
            label: u32::try_from(label.filter(|l| *l != own)?).ok()?,
            movement_type: kind,
            parent: None,
            child: None,
            damping: None,
            range: None,
        });
    }
    let parent = c.integer(obj, path, "parent", (1, labels_max));
    let child = c.integer(obj, path, "child", (1, labels_max));
    if let (Some(l), Some(p), Some(ch)) = (label, parent, child) {
        let mut pair = [p, ch];
        pair.sort_unstable();
        let mut expected = [own, l];
        expected.sort_unstable();
        if pair != expected {
            c.fail(
                path,
                format!("parent {p} and child {ch} must be the pair {own} and {l}"),
            );
        }
    }
    let damping = c.number(obj, path, "damping", DAMPING);
    let range = c.quantity(
        obj,
        path,
        "range",
        "\"0-30 cm\" or \"0-110 degrees\"",
        motion_range,
    );
    let range = range.filter(|(text, r)| {
        let rpath = join(path, "range");
        let (lower, upper) = r.bounds();
        let mut ok = true;
        match (kind, r) {
            (MovementType::B, MotionRange::Angle { .. }) => {
                c.fail(&rpath, format!("{text:?} is an angle; a B (slide) range is a length like \"0-30 cm\""));
                ok = false;
            }
            (MovementType::C, MotionRange::Length { .. }) => {
                c.fail(&rpath, format!("{text:?} is a length; a C (rotation) range is an angle like \"0-110 degrees\""));
                ok = false;
            }
            _ => {}
        }
        if ok && upper <= lower {
            c.fail(&rpath, format!("{text:?} does not go from a lower to a higher value"));
            ok = false;
        }
        let limit = if r.is_angle() { MAX_TURN_RAD } else { MAX_SLIDE_M };
        if ok && (lower.abs() > limit + 1e-9 || upper.abs() > limit + 1e-9) {
            c.fail(&rpath, format!("{text:?} is beyond the plausible range (one turn, or 10 m)"));
            ok = false;
        }
        ok
    });
    Some(NeighbourAnswer {
        label: u32::try_from(label.filter(|l| *l != own)?).ok()?,
        movement_type: kind,
        parent: Some(u32::try_from(parent?).ok()?),
        child: Some(u32::try_from(child?).ok()?),
        damping: Some(damping?),
        range: Some(range?.0),
    })
}

fn descriptions(c: &mut Checker, value: &Value, path: &str) -> Option<DescriptionsAnswer> {
    let obj = c.object(value, path)?;
    let basic = c.string(obj, path, "basic");
    let functional = c.string(obj, path, "functional");
    let movement = c.string(obj, path, "movement");
    let grasp = c.string(obj, path, "grasp");
    Some(DescriptionsAnswer {
        basic: basic?,
        functional: functional?,
        movement: movement?,
        grasp: grasp?,
    })
}

/// Checks an articulation answer. `revolute` says whether a pivot is required; `axis_legend`
/// and `pivot_legend` are the colour names the images show.
///
/// # Errors
/// Every violation found.
pub fn validate_articulation(
    value: &Value,
    revolute: bool,
    axis_legend: &[&str],
    pivot_legend: &[&str],
) -> Result<ArticulationAnswer, Vec<Violation>> {
    let mut c = Checker::default();
    let answer = articulation(&mut c, value, revolute, axis_legend, pivot_legend);
    c.finish(answer)
}

fn optional_text(obj: &Map<String, Value>, key: &str) -> String {
    obj.get(key)
        .and_then(Value::as_str)
        .unwrap_or_default()
        .to_owned()
}

fn articulation(
    c: &mut Checker,
    value: &Value,
    revolute: bool,
    axis_legend: &[&str],
    pivot_legend: &[&str],
) -> Option<ArticulationAnswer> {
    let obj = c.object(value, "")?;
    let axis = c.string(obj, "", "axis_colour").filter(|colour| {
        let ok = colour_index(colour, axis_legend).is_some();
        if !ok {
            c.fail(
                "axis_colour",
                format!(
                    "{colour:?} is not a colour of the legend ({})",
                    axis_legend.join(", ")
                ),
            );
        }
        ok
    });
    let direction = c.string(obj, "", "motion_direction").and_then(|d| {
        match d.trim().to_ascii_lowercase().as_str() {
            "positive" => Some(MotionDirection::Positive),
            "negative" => Some(MotionDirection::Negative),
            _ => {
                c.fail(
                    "motion_direction",
                    format!("{d:?} is not \"positive\" or \"negative\""),
                );
                None
            }
        }
    });
    let pivot = if revolute {
        c.string(obj, "", "pivot")
            .filter(|p| {
                let ok = p.trim().eq_ignore_ascii_case("average")
                    || colour_index(p, pivot_legend).is_some();
                if !ok {
                    c.fail(
                        "pivot",
                        format!(
                            "{p:?} is neither \"average\" nor a colour of the pivot legend ({})",
                            pivot_legend.join(", ")
                        ),
                    );
                }
                ok
            })
            .map(Some)
    } else {
        Some(None)
    };
    Some(ArticulationAnswer {
        part_description: optional_text(obj, "part_description"),
        axis_description: optional_text(obj, "axis_description"),
        axis_colour: axis?,
        motion_direction: direction?,
        pivot: pivot?,
        justification: optional_text(obj, "justification"),
    })
}
