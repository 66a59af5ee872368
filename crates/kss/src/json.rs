//! Reading and writing scenario files: the JSON text of the contract,
//! version 1, specified in `docs/scenario-format.md` (a top-level object
//! with `version`, `until`, `on_collision`, `polygons` and the optional
//! `flight_plan_changes`, `insertions` and `removals`). Only with the
//! `serde` feature of the crate.
//!
//! Text in, text out: this module reads no file and writes none.
//! [`parse_scenario`] turns a file's text into a [`Scenario`] and
//! [`write_scenario`] turns a [`Scenario`] into a file's text, every
//! number reading back to the identical double; [`json_f64`] and
//! [`json_str`] format a number and a string as the contract prints them.
//!
//! Reading takes a well-formed file straight into typed records (numbers
//! parsed with correct rounding: the crate enables serde_json's
//! `float_roundtrip`). Any file that this direct reading does not take
//! goes through [`serde_json::Value`], whose tree is walked by hand, so
//! that every error names the entry it is about (`polygons[2] (id "b")`,
//! `flight_plan_changes[0]`, ...); the direct reading takes a file only
//! where the walk reads the same scenario from it (a unit test compares
//! the two on edited files). Only the syntax and
//! the types are checked here; the semantic rules (convexity, disjointness,
//! unique ids, change times, ...) are checked by [`Scenario::validate`],
//! and by [`crate::run`] before it simulates.
//!
//! Writing uses serde structs and serde_json's number formatting, which prints
//! the shortest decimal that reads back to the identical double.
//!
//! ```
//! use kss::json::{parse_scenario, write_scenario};
//!
//! let text = r#"{"version": 1, "until": 4, "on_collision": "bounce", "polygons": [
//!     {"id": "a", "vertices": [[0,0],[1,0],[0,1]], "position": [0, 0], "velocity": [1, 0]},
//!     {"id": "b", "vertices": [[0,0],[1,0],[0,1]], "position": [3, 0], "fixed": true}]}"#;
//! let scenario = parse_scenario(text)?;
//! assert_eq!(scenario.polygons.len(), 2);
//! assert!(scenario.polygons[1].fixed);
//! // written and read again: the identical scenario
//! assert_eq!(parse_scenario(&write_scenario(&scenario)?)?, scenario);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use serde::Serialize;
use serde_json::{Map, Value};

use crate::scenario::{CollisionMode, FlightPlanChange, Insertion, PolygonSpec, Removal, Scenario};

/// Why a scenario file could not be read. Every message names the entry.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioJsonError {
    /// The text is not JSON.
    #[error("malformed JSON at line {line}, column {column}: {message}")]
    Syntax {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde_json's description.
        message: String,
    },
    /// A number literal too large for a double (like `1e999`).
    #[error("number out of range at line {line}, column {column}: every number must be a finite double (at most about 1.8e308)")]
    NumberOutOfRange {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// A required field is absent.
    #[error("{entry}: missing required field \"{field}\"")]
    MissingField {
        /// The entry (`scenario`, `polygons[1] (id "b")`, ...).
        entry: String,
        /// The field.
        field: &'static str,
    },
    /// A field has the wrong JSON type.
    #[error("{entry}: field \"{field}\" must be {expected}, found {found}")]
    WrongType {
        /// The entry.
        entry: String,
        /// The field (or `entry` itself for a whole entry of the wrong type).
        field: String,
        /// What was expected.
        expected: &'static str,
        /// What was found.
        found: String,
    },
    /// `on_collision` is not one of the three modes.
    #[error(
        "scenario: unknown on_collision value {value:?}; use \"stop\", \"remove\" or \"bounce\""
    )]
    UnknownMode {
        /// The value found.
        value: String,
    },
    /// `version` is not 1.
    #[error("scenario: unsupported version {found}; this program reads version 1")]
    BadVersion {
        /// The value found.
        found: String,
    },
    /// A point is not an array of exactly two numbers.
    #[error("{entry}: {field} must be a point [x, y] (an array of 2 numbers), found {found}")]
    BadPoint {
        /// The entry.
        entry: String,
        /// The field (`position`, `vertices[2]`, ...).
        field: String,
        /// What was found.
        found: String,
    },
}

/// A short description of a JSON value for error messages.
fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".to_string(),
        Value::Bool(b) => format!("the boolean {b}"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => {
            let short: String = s.chars().take(40).collect();
            if short.len() < s.len() {
                format!("the string {short:?}...")
            } else {
                format!("the string {s:?}")
            }
        }
        Value::Array(a) => match a.len() {
            1 => "an array of 1 element".to_string(),
            n => format!("an array of {n} elements"),
        },
        Value::Object(_) => "an object".to_string(),
    }
}

fn syntax_error(e: serde_json::Error) -> ScenarioJsonError {
    let text = e.to_string();
    if text.starts_with("number out of range") {
        ScenarioJsonError::NumberOutOfRange {
            line: e.line(),
            column: e.column(),
        }
    } else {
        let message = match text.rfind(" at line ") {
            Some(i) => text[..i].to_string(),
            None => text,
        };
        ScenarioJsonError::Syntax {
            line: e.line(),
            column: e.column(),
            message,
        }
    }
}

/// Parses a scenario file's text into a [`Scenario`] (not yet validated).
///
/// ```
/// let sc = kss::json::parse_scenario(
///     r#"{"version": 1, "until": 2.5, "polygons": [
///         {"id": "a", "vertices": [[0,0],[1,0],[0,1]], "position": [0.1, 0]}]}"#,
/// ).unwrap();
/// assert_eq!(sc.until, 2.5);
/// assert_eq!(sc.polygons[0].position, [0.1, 0.0]);
/// assert_eq!(sc.polygons[0].velocity, [0.0, 0.0]);
/// ```
pub fn parse_scenario(text: &str) -> Result<Scenario, ScenarioJsonError> {
    if let Some(s) = serde_json::from_str::<direct::File>(text)
        .ok()
        .and_then(direct::File::scenario)
    {
        return Ok(s);
    }
    let root: Value = serde_json::from_str(text).map_err(syntax_error)?;
    scenario_from_value(&root)
}

/// Builds a [`Scenario`] (not yet validated) from an already parsed JSON
/// value, the whole file's top-level object; errors as [`parse_scenario`]'s
/// except [`ScenarioJsonError::Syntax`] and
/// [`ScenarioJsonError::NumberOutOfRange`], which are the parser's.
pub fn scenario_from_value(root: &Value) -> Result<Scenario, ScenarioJsonError> {
    let top = "scenario";
    let obj = root
        .as_object()
        .ok_or_else(|| ScenarioJsonError::WrongType {
            entry: top.to_string(),
            field: "(the whole file)".to_string(),
            expected: "a JSON object",
            found: describe(root),
        })?;

    let version = required(obj, top, "version")?;
    if version.as_f64() != Some(1.0) {
        return Err(ScenarioJsonError::BadVersion {
            found: match version {
                Value::Number(n) => n.to_string(),
                other => describe(other),
            },
        });
    }
    let until = number(obj, top, "until")?;
    let on_collision = match obj.get("on_collision") {
        None => CollisionMode::Stop,
        Some(Value::String(s)) => {
            collision_mode(s).ok_or_else(|| ScenarioJsonError::UnknownMode { value: s.clone() })?
        }
        Some(other) => {
            return Err(wrong(top, "on_collision", "a string", other));
        }
    };

    let polys = match required(obj, top, "polygons")? {
        Value::Array(a) => a,
        other => return Err(wrong(top, "polygons", "an array of polygons", other)),
    };
    let mut polygons = Vec::with_capacity(polys.len());
    for (i, p) in polys.iter().enumerate() {
        polygons.push(polygon(i, p)?);
    }

    let mut flight_plan_changes = Vec::new();
    match obj.get("flight_plan_changes") {
        None => {}
        Some(Value::Array(a)) => {
            for (i, c) in a.iter().enumerate() {
                flight_plan_changes.push(change(i, c)?);
            }
        }
        Some(other) => {
            return Err(wrong(
                top,
                "flight_plan_changes",
                "an array of changes",
                other,
            ))
        }
    }

    let insertions = entries(obj, "insertions", "an array of insertions", insertion)?;
    let removals = entries(obj, "removals", "an array of removals", removal)?;

    Ok(Scenario {
        until,
        on_collision,
        polygons,
        flight_plan_changes,
        insertions,
        removals,
    })
}

/// The mode named `s` in `on_collision`, if it is one.
fn collision_mode(s: &str) -> Option<CollisionMode> {
    match s {
        "stop" => Some(CollisionMode::Stop),
        "remove" => Some(CollisionMode::Remove),
        "bounce" => Some(CollisionMode::Bounce),
        _ => None,
    }
}

/// The optional array `field` of the top-level object, each entry read by
/// `read` (absent means empty).
fn entries<T>(
    obj: &serde_json::Map<String, Value>,
    field: &str,
    expected: &'static str,
    read: fn(usize, &Value) -> Result<T, ScenarioJsonError>,
) -> Result<Vec<T>, ScenarioJsonError> {
    match obj.get(field) {
        None => Ok(Vec::new()),
        Some(Value::Array(a)) => a.iter().enumerate().map(|(i, v)| read(i, v)).collect(),
        Some(other) => Err(wrong("scenario", field, expected, other)),
    }
}

fn insertion(index: usize, v: &Value) -> Result<Insertion, ScenarioJsonError> {
    let entry = format!("insertions[{index}]");
    let obj = v.as_object().ok_or_else(|| ScenarioJsonError::WrongType {
        entry: entry.clone(),
        field: entry.clone(),
        expected: "an object {\"time\", \"polygon\"}",
        found: describe(v),
    })?;
    let time = number(obj, &entry, "time")?;
    let polygon = polygon_in(&entry, required(obj, &entry, "polygon")?)?;
    Ok(Insertion { time, polygon })
}

fn removal(index: usize, v: &Value) -> Result<Removal, ScenarioJsonError> {
    let entry = format!("removals[{index}]");
    let obj = v.as_object().ok_or_else(|| ScenarioJsonError::WrongType {
        entry: entry.clone(),
        field: entry.clone(),
        expected: "an object {\"time\", \"id\"}",
        found: describe(v),
    })?;
    let time = number(obj, &entry, "time")?;
    let id = string(obj, &entry, "id")?;
    Ok(Removal { time, id })
}

fn polygon(index: usize, v: &Value) -> Result<PolygonSpec, ScenarioJsonError> {
    polygon_in(&format!("polygons[{index}]"), v)
}

/// A polygon object; `bare` names where it is (`polygons[3]`,
/// `insertions[0].polygon`'s entry).
fn polygon_in(bare: &str, v: &Value) -> Result<PolygonSpec, ScenarioJsonError> {
    let bare = if bare.starts_with("insertions") {
        format!("{bare}.polygon")
    } else {
        bare.to_string()
    };
    let obj = v.as_object().ok_or_else(|| ScenarioJsonError::WrongType {
        entry: bare.clone(),
        field: bare.clone(),
        expected: "an object",
        found: describe(v),
    })?;
    let id = string(obj, &bare, "id")?;
    let entry = format!("{bare} (id {id:?})");
    let vertices = match required(obj, &entry, "vertices")? {
        Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(k, p)| point(&entry, &format!("vertices[{k}]"), p))
            .collect::<Result<Vec<_>, _>>()?,
        other => return Err(wrong(&entry, "vertices", "an array of points", other)),
    };
    let position = point_field(obj, &entry, "position")?;
    let velocity = match obj.get("velocity") {
        None => [0.0, 0.0],
        Some(_) => point_field(obj, &entry, "velocity")?,
    };
    let fixed = match obj.get("fixed") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(other) => return Err(wrong(&entry, "fixed", "true or false", other)),
    };
    Ok(PolygonSpec {
        id,
        vertices,
        position,
        velocity,
        fixed,
    })
}

fn change(index: usize, v: &Value) -> Result<FlightPlanChange, ScenarioJsonError> {
    let entry = format!("flight_plan_changes[{index}]");
    let obj = v.as_object().ok_or_else(|| ScenarioJsonError::WrongType {
        entry: entry.clone(),
        field: entry.clone(),
        expected: "an object {\"time\", \"id\", \"velocity\"}",
        found: describe(v),
    })?;
    let time = number(obj, &entry, "time")?;
    let id = string(obj, &entry, "id")?;
    let velocity = point_field(obj, &entry, "velocity")?;
    Ok(FlightPlanChange { time, id, velocity })
}

fn wrong(entry: &str, field: &str, expected: &'static str, found: &Value) -> ScenarioJsonError {
    ScenarioJsonError::WrongType {
        entry: entry.to_string(),
        field: field.to_string(),
        expected,
        found: describe(found),
    }
}

fn required<'a>(
    obj: &'a Map<String, Value>,
    entry: &str,
    field: &'static str,
) -> Result<&'a Value, ScenarioJsonError> {
    obj.get(field)
        .ok_or_else(|| ScenarioJsonError::MissingField {
            entry: entry.to_string(),
            field,
        })
}

fn number(
    obj: &Map<String, Value>,
    entry: &str,
    field: &'static str,
) -> Result<f64, ScenarioJsonError> {
    match required(obj, entry, field)? {
        Value::Number(n) => n
            .as_f64()
            .ok_or_else(|| wrong(entry, field, "a number", &Value::Number(n.clone()))),
        other => Err(wrong(entry, field, "a number", other)),
    }
}

fn string(
    obj: &Map<String, Value>,
    entry: &str,
    field: &'static str,
) -> Result<String, ScenarioJsonError> {
    match required(obj, entry, field)? {
        Value::String(s) => Ok(s.clone()),
        other => Err(wrong(entry, field, "a string", other)),
    }
}

fn point_field(
    obj: &Map<String, Value>,
    entry: &str,
    field: &'static str,
) -> Result<[f64; 2], ScenarioJsonError> {
    let v = required(obj, entry, field)?;
    if !v.is_array() {
        return Err(wrong(entry, field, "a point [x, y]", v));
    }
    point(entry, field, v)
}

fn point(entry: &str, field: &str, v: &Value) -> Result<[f64; 2], ScenarioJsonError> {
    let bad = || ScenarioJsonError::BadPoint {
        entry: entry.to_string(),
        field: field.to_string(),
        found: describe(v),
    };
    let a = v.as_array().ok_or_else(bad)?;
    if a.len() != 2 {
        return Err(bad());
    }
    let coordinate = |k: usize| -> Result<f64, ScenarioJsonError> {
        match &a[k] {
            Value::Number(n) => n.as_f64().ok_or_else(bad),
            other => Err(ScenarioJsonError::BadPoint {
                entry: entry.to_string(),
                field: field.to_string(),
                found: format!(
                    "an array whose {} coordinate is {}",
                    if k == 0 { "x" } else { "y" },
                    describe(other)
                ),
            }),
        }
    };
    Ok([coordinate(0)?, coordinate(1)?])
}

// ---------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------

/// One polygon as written.
#[derive(Serialize)]
struct PolygonOut<'a> {
    id: &'a str,
    vertices: &'a [[f64; 2]],
    position: [f64; 2],
    velocity: [f64; 2],
    fixed: bool,
}

/// One flight-plan change as written.
#[derive(Serialize)]
struct ChangeOut<'a> {
    time: f64,
    id: &'a str,
    velocity: [f64; 2],
}

/// Why a scenario cannot be written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot write the scenario: {what} is not a finite number ({value})")]
pub struct WriteError {
    /// Where the number is.
    pub what: String,
    /// The value.
    pub value: f64,
}

fn finite(what: impl Fn() -> String, values: &[f64]) -> Result<(), WriteError> {
    match values.iter().find(|x| !x.is_finite()) {
        Some(&value) => Err(WriteError {
            what: what(),
            value,
        }),
        None => Ok(()),
    }
}

/// One insertion as written (the polygon's fields inline).
#[derive(Serialize)]
struct InsertionOut<'a> {
    time: f64,
    polygon: PolygonOut<'a>,
}

/// One removal as written.
#[derive(Serialize)]
struct RemovalOut<'a> {
    time: f64,
    id: &'a str,
}

/// A polygon's numbers checked finite; `what` names it in the error.
fn polygon_out<'a>(
    p: &'a PolygonSpec,
    what: impl Fn() -> String,
) -> Result<PolygonOut<'a>, WriteError> {
    finite(&what, &p.position)?;
    finite(&what, &p.velocity)?;
    for v in &p.vertices {
        finite(&what, v)?;
    }
    Ok(PolygonOut {
        id: &p.id,
        vertices: &p.vertices,
        position: p.position,
        velocity: p.velocity,
        fixed: p.fixed,
    })
}

/// Appends `"  "name": [` and one serialized entry per line, then `]` and
/// `tail`.
fn push_array(out: &mut String, name: &str, lines: &[String], tail: &str) {
    out.push_str(&format!("  \"{name}\": ["));
    for (i, line) in lines.iter().enumerate() {
        out.push_str(if i == 0 { "\n    " } else { ",\n    " });
        out.push_str(line);
    }
    out.push_str(if lines.is_empty() { "]" } else { "\n  ]" });
    out.push_str(tail);
}

fn line<T: Serialize>(value: &T) -> String {
    serde_json::to_string(value).expect("finite numbers and strings always serialize")
}

/// Writes `scenario` as a scenario file (version 1), one polygon,
/// flight-plan change, insertion and removal per line. Every number reads
/// back to the identical double. The `insertions` and `removals` arrays are
/// written only when they are not empty (absent means empty), so a scenario
/// without them is written as before they existed. Non-finite numbers
/// cannot be written.
pub fn write_scenario(scenario: &Scenario) -> Result<String, WriteError> {
    finite(|| "until".to_string(), &[scenario.until])?;
    let mut out = String::new();
    out.push_str("{\n  \"version\": 1,\n");
    out.push_str(&format!(
        "  \"until\": {},\n  \"on_collision\": \"{}\",\n",
        json_f64(scenario.until),
        scenario.on_collision.name()
    ));
    let polygons = scenario
        .polygons
        .iter()
        .map(|p| Ok(line(&polygon_out(p, || format!("polygon {:?}", p.id))?)))
        .collect::<Result<Vec<_>, WriteError>>()?;
    push_array(&mut out, "polygons", &polygons, ",\n");
    let changes = scenario
        .flight_plan_changes
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let what = || format!("flight_plan_changes[{i}]");
            finite(what, &[c.time])?;
            finite(what, &c.velocity)?;
            Ok(line(&ChangeOut {
                time: c.time,
                id: &c.id,
                velocity: c.velocity,
            }))
        })
        .collect::<Result<Vec<_>, WriteError>>()?;
    let insertions = scenario
        .insertions
        .iter()
        .enumerate()
        .map(|(i, ins)| {
            let what = || format!("insertions[{i}] (polygon {:?})", ins.polygon.id);
            finite(what, &[ins.time])?;
            Ok(line(&InsertionOut {
                time: ins.time,
                polygon: polygon_out(&ins.polygon, what)?,
            }))
        })
        .collect::<Result<Vec<_>, WriteError>>()?;
    let removals = scenario
        .removals
        .iter()
        .enumerate()
        .map(|(i, r)| {
            finite(|| format!("removals[{i}] (polygon {:?})", r.id), &[r.time])?;
            Ok(line(&RemovalOut {
                time: r.time,
                id: &r.id,
            }))
        })
        .collect::<Result<Vec<_>, WriteError>>()?;
    let mut arrays: Vec<(&str, Vec<String>)> = vec![("flight_plan_changes", changes)];
    if !insertions.is_empty() {
        arrays.push(("insertions", insertions));
    }
    if !removals.is_empty() {
        arrays.push(("removals", removals));
    }
    let last = arrays.len() - 1;
    for (k, (name, lines)) in arrays.iter().enumerate() {
        push_array(&mut out, name, lines, if k == last { "\n" } else { ",\n" });
    }
    out.push_str("}\n");
    Ok(out)
}

/// A finite double as JSON (shortest text that reads back identically).
pub fn json_f64(x: f64) -> String {
    serde_json::to_string(&x).expect("a finite double serializes")
}

/// A string as a JSON string literal (quoted and escaped).
pub fn json_str(s: &str) -> String {
    serde_json::to_string(s).expect("a string serializes")
}

/// The common case of [`parse_scenario`]: a well-formed file read straight
/// into typed records, without a tree of values. It takes a file only where
/// the tree walk would read the same scenario from it: every entry must be
/// a JSON object (no array in its place), every field present must have its
/// type (`null` for an optional one included in what is refused), a field
/// may not repeat and a key may not contain an escape. Anything else goes
/// to the walk, which reads the file again and says what is wrong. Both
/// read numbers with the same parser (correctly rounded); unknown fields
/// are skipped by both.
mod direct {
    use serde::de::{Error, IgnoredAny, MapAccess, Visitor};
    use serde::{Deserialize, Deserializer};

    use crate::scenario::{
        CollisionMode, FlightPlanChange, Insertion, PolygonSpec, Removal, Scenario,
    };

    /// A record read from a JSON object only, each field optional here
    /// (required ones are checked when the scenario is assembled).
    macro_rules! object {
        ($(#[$doc:meta])* $name:ident { $($field:ident: $ty:ty),* $(,)? }) => {
            $(#[$doc])*
            #[derive(Default)]
            pub(super) struct $name {
                $($field: Option<$ty>),*
            }

            impl<'de> Deserialize<'de> for $name {
                fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                    struct Fields;
                    impl<'de> Visitor<'de> for Fields {
                        type Value = $name;
                        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                            f.write_str("an object")
                        }
                        fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<$name, A::Error> {
                            let mut out = $name::default();
                            while let Some(key) = m.next_key::<&'de str>()? {
                                match key {
                                    $(stringify!($field) => {
                                        if out.$field.is_some() {
                                            return Err(A::Error::custom("repeated field"));
                                        }
                                        out.$field = Some(m.next_value()?);
                                    })*
                                    _ => {
                                        m.next_value::<IgnoredAny>()?;
                                    }
                                }
                            }
                            Ok(out)
                        }
                    }
                    d.deserialize_map(Fields)
                }
            }
        };
    }

    object!(
        /// The whole file.
        File {
            version: f64,
            until: f64,
            on_collision: String,
            polygons: Vec<Polygon>,
            flight_plan_changes: Vec<Change>,
            insertions: Vec<Entering>,
            removals: Vec<Leaving>,
        }
    );
    object!(Polygon {
        id: String,
        vertices: Vec<[f64; 2]>,
        position: [f64; 2],
        velocity: [f64; 2],
        fixed: bool,
    });
    object!(Change {
        time: f64,
        id: String,
        velocity: [f64; 2],
    });
    object!(Entering {
        time: f64,
        polygon: Polygon,
    });
    object!(Leaving {
        time: f64,
        id: String
    });

    impl Polygon {
        fn spec(self) -> Option<PolygonSpec> {
            Some(PolygonSpec {
                id: self.id?,
                vertices: self.vertices?,
                position: self.position?,
                velocity: self.velocity.unwrap_or([0.0, 0.0]),
                fixed: self.fixed.unwrap_or(false),
            })
        }
    }

    /// Every record of an optional array (absent: none) made into its
    /// entry, unless one lacks a required field.
    fn each<T, U>(v: Option<Vec<T>>, entry: impl Fn(T) -> Option<U>) -> Option<Vec<U>> {
        v.unwrap_or_default().into_iter().map(entry).collect()
    }

    impl File {
        /// The scenario, unless a required field is missing or the version
        /// or the mode is one the walk refuses.
        pub(super) fn scenario(self) -> Option<Scenario> {
            if self.version? != 1.0 {
                return None;
            }
            let on_collision = match self.on_collision.as_deref() {
                None => CollisionMode::Stop,
                Some(s) => super::collision_mode(s)?,
            };
            Some(Scenario {
                until: self.until?,
                on_collision,
                polygons: self
                    .polygons?
                    .into_iter()
                    .map(Polygon::spec)
                    .collect::<Option<_>>()?,
                flight_plan_changes: each(self.flight_plan_changes, |c: Change| {
                    Some(FlightPlanChange {
                        time: c.time?,
                        id: c.id?,
                        velocity: c.velocity?,
                    })
                })?,
                insertions: each(self.insertions, |e: Entering| {
                    Some(Insertion {
                        time: e.time?,
                        polygon: e.polygon?.spec()?,
                    })
                })?,
                removals: each(self.removals, |r: Leaving| {
                    Some(Removal {
                        time: r.time?,
                        id: r.id?,
                    })
                })?,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree walk alone (what [`parse_scenario`] falls back to).
    fn walk(text: &str) -> Result<Scenario, ScenarioJsonError> {
        let root: Value = serde_json::from_str(text).map_err(syntax_error)?;
        scenario_from_value(&root)
    }

    /// Whatever the direct reading takes, the walk reads the same.
    fn agree(text: &str) -> bool {
        let direct = serde_json::from_str::<direct::File>(text)
            .ok()
            .and_then(direct::File::scenario);
        if let Some(s) = &direct {
            assert_eq!(walk(text).as_ref(), Ok(s), "{text}");
        }
        assert_eq!(parse_scenario(text), walk(text), "{text}");
        direct.is_some()
    }

    const BASE: &str = r#"{"version": 1, "until": 4.5, "on_collision": "bounce",
        "polygons": [
          {"id": "a", "vertices": [[0,0],[1,0],[0,1]], "position": [0.1, -0], "velocity": [1, 0]},
          {"id": "b", "vertices": [[0,0],[1,0],[0,1]], "position": [3, 0], "fixed": true, "note": [1]}],
        "flight_plan_changes": [{"time": 1, "id": "a", "velocity": [0.5, 0]}],
        "insertions": [{"time": 2, "polygon": {"id": "c", "vertices": [[0,0],[1,0],[0,1]],
                        "position": [9, 9]}}],
        "removals": [{"time": 3, "id": "b"}]}"#;

    #[test]
    fn the_direct_reading_takes_only_what_the_walk_reads_alike() {
        assert!(agree(BASE));
        // each of these changes the base; the two readings must agree on
        // every result (the direct one may refuse more)
        let edits: &[(&str, &str)] = &[
            (r#""version": 1"#, r#""version": 1.0"#),
            (r#""version": 1"#, r#""version": 1e0"#),
            (r#""version": 1"#, r#""version": 2"#),
            (r#""version": 1"#, r#""version": "1""#),
            (r#""version": 1, "#, ""),
            (r#""until": 4.5"#, r#""until": null"#),
            (r#""until": 4.5"#, r#""until": 18446744073709551617"#),
            (r#""until": 4.5"#, r#""until": 1e400"#),
            (r#""until": 4.5"#, r#""until": -0"#),
            (r#""on_collision": "bounce""#, r#""on_collision": null"#),
            (
                r#""on_collision": "bounce""#,
                r#""on_collision": "bounces""#,
            ),
            (r#""on_collision": "bounce""#, r#""on_collision": "remove""#),
            (r#""on_collision": "bounce","#, ""),
            (r#""position": [0.1, -0]"#, r#""position": [0.1]"#),
            (r#""position": [0.1, -0]"#, r#""position": [0.1, -0, 1]"#),
            (
                r#""position": [0.1, -0]"#,
                r#""position": {"x": 0.1, "y": 0}"#,
            ),
            (r#""velocity": [1, 0]"#, r#""velocity": null"#),
            (r#""velocity": [1, 0]"#, r#""velocity": [1, "0"]"#),
            (r#", "velocity": [1, 0]"#, ""),
            (r#""fixed": true"#, r#""fixed": null"#),
            (r#""fixed": true"#, r#""fixed": 1"#),
            (r#""fixed": true"#, r#""fixed": true, "fixed": false"#),
            (r#""id": "a""#, r#""id": "a", "id": "z""#),
            (r#""id": "a""#, r#""i\u0064": "a""#),
            (r#""id": "a""#, r#""id": "\u0061""#),
            (r#""id": "a""#, r#""id": 7"#),
            (
                r#"{"id": "a", "vertices": [[0,0],[1,0],[0,1]], "position": [0.1, -0], "velocity": [1, 0]}"#,
                r#"["a", [[0,0],[1,0],[0,1]], [0.1, 0], [1, 0]]"#,
            ),
            (r#"{"time": 3, "id": "b"}"#, r#"[3, "b"]"#),
            (
                r#"{"time": 1, "id": "a", "velocity": [0.5, 0]}"#,
                r#"[1, "a", [0.5, 0]]"#,
            ),
            (
                r#""flight_plan_changes": ["#,
                r#""flight_plan_changes": null, "x": ["#,
            ),
            (
                r#""removals": [{"time": 3, "id": "b"}]"#,
                r#""removals": {}"#,
            ),
            (
                r#""removals": [{"time": 3, "id": "b"}]"#,
                r#""removals": []"#,
            ),
            (r#""polygon": {"#, r#""polygon": null, "p": {"#),
            (
                r#""id": "c", "vertices": [[0,0],[1,0],[0,1]],"#,
                r#""id": "c","#,
            ),
            (r#""polygons": ["#, r#""polygons": [], "polygons": ["#),
        ];
        let mut direct = 0;
        for (from, to) in edits {
            assert!(BASE.contains(from), "{from}");
            direct += usize::from(agree(&BASE.replacen(from, to, 1)));
        }
        // (the well-formed variants go the direct way)
        assert!(direct >= 8, "{direct}");
        assert!(!agree("[]"));
        assert!(!agree("null"));
        assert!(!agree(r#"{"version": 1}"#));
    }
}
