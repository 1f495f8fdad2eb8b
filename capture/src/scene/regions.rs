//! Parts by region: name a vehicle's triangles by *where* they are.
//!
//! Real models rarely come with meaningful part names (`node4_prim0`,
//! `Color_001`), and one body mesh often holds hood, cab and tank alike. The
//! scene file's `vehicle.parts` lists rules that relabel triangles by their
//! centroid in the vehicle frame (x forward, y left, z up, metres — after
//! `axes`, so after scale and origin):
//!
//! ```json
//! "parts": [
//!   {"name": "windows", "from": ["glass", "window_trim"]},
//!   {"name": "hood", "from": "body", "box": {"min": [1.6, -2, 0.6], "max": [3, 2, 1.5]}},
//!   {"name": "door_front_left", "where": [{"normal": [0, 1, 0], "offset": 0.8},
//!                                         {"normal": [1, 0, 0], "offset": 0.5}]},
//!   {"split": "tank", "plane": {"normal": [1, 0, 0], "offset": -1.0},
//!    "names": ["tank_front", "tank_rear"]},
//!   {"name": "others"}
//! ]
//! ```
//!
//! * A **region rule** (`name`) matches a triangle when its centroid lies in
//!   the `box` (bounds inclusive) *and* on the positive side of every
//!   half-space in `where` (`normal · p ≥ offset`; the normal is normalised,
//!   so `offset` is in metres). `from` (a name or a list) limits the rule to
//!   triangles whose part, after `rename`, is listed. A rule without `from`
//!   takes only triangles of parts that `rename` did not name: what a
//!   researcher named by hand is never swallowed by a region (list the
//!   renamed part in `from` to cut it). A rule with neither box nor `where`
//!   matches every triangle of its `from` parts (or every triangle not
//!   renamed: `{"name": "others"}` as the last rule collects the rest).
//! * A **split rule** (`split`) cuts one part by a plane: centroids on the
//!   normal's side (`normal · p ≥ offset`) go to `names[0]`, the others to
//!   `names[1]`.
//!
//! Rules are tried in order against each triangle's part *as it was after
//! `rename`* (one rule never sees another's result); the first that matches
//! wins. Triangles that no rule matches **keep their part** — add
//! `{"name": "others"}` last to put them in an `others` part instead. Parts
//! left with no triangles disappear. Every rule reports how many triangles
//! and how much surface it took, so that a rule matching nothing is noticed.
//!
//! Before the rules are tried, every triangle that a rule's boundary (a face
//! of its box, a `where` plane, a split's plane) crosses is cut along it
//! ([`crate::scene::cut`]): a region's area is the surface inside it, not the
//! triangles whose centroid happens to be (a model of few large triangles
//! would otherwise give a "roof" box wedges of the side walls). The report
//! counts the triangles cut.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::scene::cut::{CutPlane, ON_PLANE_M};
use crate::scene::region_pieces::{Pieces, RuleCut, cut_into_pieces};

/// The most triangles cutting may add (beyond it, crossed triangles stay
/// whole and a warning names them): a bound on memory whatever the rules.
pub(crate) const MAX_NEW_TRIANGLES: usize = 4_000_000;
use crate::scene::mesh::{Mesh, triangle_area};

/// One value or a list of them (`"from": "body"` or `"from": ["a", "b"]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum OneOrMany<T> {
    One(T),
    Many(Vec<T>),
}

impl<T> OneOrMany<T> {
    /// The values as a slice.
    pub fn as_slice(&self) -> &[T] {
        match self {
            OneOrMany::One(value) => std::slice::from_ref(value),
            OneOrMany::Many(values) => values,
        }
    }
}

/// An axis-aligned box in the vehicle frame (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// The half-space `normal · p ≥ offset` (normal normalised, offset in metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HalfSpace {
    pub normal: [f64; 3],
    pub offset: f64,
}

/// One entry of `vehicle.parts` as written in the scene file; see the module
/// documentation for what each field means.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartRule {
    /// The part a region rule assigns.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Only triangles whose part (after `rename`) is one of these.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<OneOrMany<String>>,
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub region_box: Option<RegionBox>,
    /// Half-spaces, all of which must hold (AND).
    #[serde(default, rename = "where", skip_serializing_if = "Option::is_none")]
    pub half_spaces: Option<OneOrMany<HalfSpace>>,
    /// The part a split rule cuts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<String>,
    /// The cutting plane of a split.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<HalfSpace>,
    /// The two parts of a split: the normal's side first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub names: Option<Vec<String>>,
}

/// A checked rule.
#[derive(Debug, Clone, PartialEq)]
enum Rule {
    Region {
        name: String,
        from: Vec<String>,
        region_box: Option<(DVec3, DVec3)>,
        half_spaces: Vec<(DVec3, f64)>,
    },
    Split {
        part: String,
        plane: (DVec3, f64),
        names: [String; 2],
    },
}

impl Rule {
    /// The rule's label in reports.
    fn label(&self) -> String {
        match self {
            Rule::Region { name, .. } => name.clone(),
            Rule::Split { part, names, .. } => format!("split {part} → {} | {}", names[0], names[1]),
        }
    }

    /// The planes that bound this rule's region (a box's six faces, the
    /// `where` half-spaces, a split's plane), each with the box beyond which
    /// it bounds nothing.
    fn boundaries(&self) -> Vec<CutPlane> {
        let everywhere = (DVec3::NEG_INFINITY, DVec3::INFINITY);
        match self {
            Rule::Region { region_box, half_spaces, .. } => {
                let within = region_box.map_or(everywhere, |(min, max)| {
                    (min - DVec3::splat(ON_PLANE_M), max + DVec3::splat(ON_PLANE_M))
                });
                let mut planes: Vec<CutPlane> =
                    half_spaces.iter().map(|&(normal, offset)| CutPlane { normal, offset, within }).collect();
                if let Some((min, max)) = region_box {
                    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                        planes.push(CutPlane { normal: axis, offset: axis.dot(*min), within });
                        planes.push(CutPlane { normal: -axis, offset: -axis.dot(*max), within });
                    }
                }
                planes
            }
            Rule::Split { plane: (normal, offset), .. } => {
                vec![CutPlane { normal: *normal, offset: *offset, within: everywhere }]
            }
        }
    }

    /// The part a triangle of `part` with centroid `c` gets, if this rule
    /// matches; `renamed` are the parts `rename` named, which only a rule
    /// listing them in `from` may take.
    fn assign<'a>(&'a self, part: &str, c: DVec3, renamed: &BTreeSet<&str>) -> Option<&'a str> {
        match self {
            Rule::Region { name, from, region_box, half_spaces } => {
                let in_from =
                    if from.is_empty() { !renamed.contains(part) } else { from.iter().any(|f| f == part) };
                let in_box = region_box.is_none_or(|(min, max)| c.cmpge(min).all() && c.cmple(max).all());
                let in_half_spaces = half_spaces.iter().all(|(n, d)| n.dot(c) >= *d);
                (in_from && in_box && in_half_spaces).then_some(name.as_str())
            }
            Rule::Split { part: cut, plane: (n, d), names } => {
                (part == cut).then(|| if n.dot(c) >= *d { names[0].as_str() } else { names[1].as_str() })
            }
        }
    }
}

/// What one rule did.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleReport {
    /// The part name (region) or `split PART → A | B`.
    pub label: String,
    pub triangles: usize,
    /// Surface area taken, m².
    pub area_m2: f64,
}

/// What the rules did to a vehicle.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RegionReport {
    pub rules: Vec<RuleReport>,
    /// Triangles no rule matched (they kept their part).
    pub unmatched_triangles: usize,
    /// Triangles cut along a rule's boundary before the rules were tried
    /// (each became two or three).
    pub cut_triangles: usize,
    /// Rules whose boundary crosses triangles left whole (the budget of
    /// [`MAX_NEW_TRIANGLES`] ran out), with those triangles' parts.
    pub left_whole: Vec<(String, Vec<String>)>,
}

impl RegionReport {
    /// One line per rule that matched no triangle, and per rule whose
    /// boundary crosses triangles that could not be cut.
    pub fn warnings(&self) -> Vec<String> {
        let unmatched = self
            .rules
            .iter()
            .filter(|rule| rule.triangles == 0)
            .map(|rule| format!("part rule {:?} matched no triangle", rule.label));
        let whole = self.left_whole.iter().map(|(rule, parts)| {
            format!(
                "part rule {rule:?} crosses triangles of {} that were not cut (more than {MAX_NEW_TRIANGLES} new triangles): each goes wholly to the side of its centroid, so that rule's parts are approximate; use fewer rules or cut the mesh in a modelling tool",
                parts.join(", ")
            )
        });
        unmatched.chain(whole).collect()
    }
}

fn half_space(text: &str, h: &HalfSpace) -> Result<(DVec3, f64), String> {
    let normal = DVec3::from(h.normal);
    if !normal.is_finite() || normal.length() < 1e-12 || !h.offset.is_finite() {
        return Err(format!("{text}: the normal must be a finite, non-zero vector and the offset finite"));
    }
    Ok((normal.normalize(), h.offset))
}

/// Checks the rules against the vehicle's part names.
fn compile(rules: &[PartRule], parts: &[String]) -> Result<Vec<Rule>, String> {
    let known = |what: &str, name: &str| {
        if parts.iter().any(|p| p == name) {
            Ok(())
        } else {
            Err(format!(
                "{what} names part {name:?}, but the vehicle's parts (after rename) are: {}",
                parts.join(", ")
            ))
        }
    };
    let mut compiled = Vec::with_capacity(rules.len());
    for (index, rule) in rules.iter().enumerate() {
        let what = match (&rule.name, &rule.split) {
            (Some(name), _) => format!("parts[{index}] ({name})"),
            (None, Some(split)) => format!("parts[{index}] (split {split})"),
            (None, None) => format!("parts[{index}]"),
        };
        compiled.push(match (&rule.name, &rule.split) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(format!(
                    "{what}: give either \"name\" (a region) or \"split\" (a plane cut), not both or neither"
                ));
            }
            (Some(name), None) => compile_region(&what, rule, name, &known)?,
            (None, Some(part)) => compile_split(&what, rule, part, &known)?,
        });
    }
    Ok(compiled)
}

/// A region rule (`"name"`), checked; `what` names it in errors, `known`
/// checks that a part name is the vehicle's.
fn compile_region(
    what: &str,
    rule: &PartRule,
    name: &str,
    known: &dyn Fn(&str, &str) -> Result<(), String>,
) -> Result<Rule, String> {
    if rule.plane.is_some() || rule.names.is_some() {
        return Err(format!("{what}: \"plane\" and \"names\" belong to a split rule"));
    }
    if name.trim().is_empty() {
        return Err(format!("{what}: empty part name"));
    }
    let from: Vec<String> = rule.from.as_ref().map_or(Vec::new(), |f| f.as_slice().to_vec());
    for part in &from {
        known(&format!("{what}: \"from\""), part)?;
    }
    let region_box = match &rule.region_box {
        Some(b) => {
            let (min, max) = (DVec3::from(b.min), DVec3::from(b.max));
            if !(min.is_finite() && max.is_finite() && min.cmple(max).all()) {
                return Err(format!("{what}: the box needs finite min ≤ max on every axis"));
            }
            Some((min, max))
        }
        None => None,
    };
    let half_spaces = match &rule.half_spaces {
        Some(list) => list
            .as_slice()
            .iter()
            .map(|h| half_space(&format!("{what}: \"where\""), h))
            .collect::<Result<Vec<_>, _>>()?,
        None => Vec::new(),
    };
    Ok(Rule::Region { name: name.to_string(), from, region_box, half_spaces })
}

/// A split rule (`"split"`), checked; `what` names it in errors, `known`
/// checks that a part name is the vehicle's.
fn compile_split(
    what: &str,
    rule: &PartRule,
    part: &str,
    known: &dyn Fn(&str, &str) -> Result<(), String>,
) -> Result<Rule, String> {
    if rule.from.is_some() || rule.region_box.is_some() || rule.half_spaces.is_some() {
        return Err(format!(
            "{what}: a split takes \"plane\" and \"names\", not \"from\", \"box\" or \"where\""
        ));
    }
    known(what, part)?;
    let Some(plane) = &rule.plane else {
        return Err(format!("{what}: a split needs a \"plane\" {{\"normal\": [x, y, z], \"offset\": d}}"));
    };
    let plane = half_space(&format!("{what}: \"plane\""), plane)?;
    let names = match rule.names.as_deref() {
        Some([a, b]) if !a.trim().is_empty() && !b.trim().is_empty() => [a.clone(), b.clone()],
        _ => {
            return Err(format!("{what}: a split needs \"names\": two part names, the normal's side first"));
        }
    };
    Ok(Rule::Split { part: part.to_string(), plane, names })
}

/// Cuts the triangles that the rules' boundaries cross (within
/// [`MAX_NEW_TRIANGLES`]) into convex pieces, rule by rule, leaving the
/// pieces a rule takes uncut by later rules
/// ([`crate::scene::region_pieces`]): how many cuts were made, the work, and
/// the rules (labels) that left crossed triangles whole, with their parts.
fn cut_along(mesh: &mut Mesh, compiled: &[Rule], renamed: &BTreeSet<&str>) -> Pieces {
    let everywhere = (DVec3::NEG_INFINITY, DVec3::INFINITY);
    let rules: Vec<RuleCut> = compiled
        .iter()
        .map(|rule| RuleCut {
            label: rule.label(),
            planes: rule.boundaries(),
            within: match rule {
                Rule::Region { region_box: Some((min, max)), .. } => {
                    (*min - DVec3::splat(ON_PLANE_M), *max + DVec3::splat(ON_PLANE_M))
                }
                _ => everywhere,
            },
            takes: Box::new(move |part: &str, c: DVec3| rule.assign(part, c, renamed).is_some()),
        })
        .collect();
    cut_into_pieces(mesh, &rules, MAX_NEW_TRIANGLES)
}

/// The centroid of triangle `t`, in f64.
fn centroid(mesh: &Mesh, t: usize) -> DVec3 {
    let corners = mesh.corners(t);
    (corners[0].as_dvec3() + corners[1].as_dvec3() + corners[2].as_dvec3()) / 3.0
}

/// Relabels `mesh`'s triangles by the rules, after cutting the triangles
/// their boundaries cross; `rename` is the map already applied (its targets
/// are taken only by rules that list them in `from`). An error names the bad
/// rule. Without rules the mesh is left exactly as it was.
pub(crate) fn apply(
    mesh: &mut Mesh,
    rules: &[PartRule],
    rename: &BTreeMap<String, String>,
) -> Result<RegionReport, String> {
    if rules.is_empty() {
        return Ok(RegionReport { unmatched_triangles: mesh.triangles.len(), ..RegionReport::default() });
    }
    let compiled = compile(rules, &mesh.parts)?;
    let renamed: BTreeSet<&str> = rename.values().map(String::as_str).collect();
    let Pieces { cut: cut_triangles, left_whole, .. } = cut_along(mesh, &compiled, &renamed);
    let mut reports: Vec<RuleReport> =
        compiled.iter().map(|rule| RuleReport { label: rule.label(), triangles: 0, area_m2: 0.0 }).collect();
    // New names: those the rules give, in rule order, then the parts kept.
    let mut names: Vec<String> = Vec::new();
    let name_index = |name: &str, names: &mut Vec<String>| match names.iter().position(|n| n == name) {
        Some(i) => i,
        None => {
            names.push(name.to_string());
            names.len() - 1
        }
    };
    for rule in &compiled {
        match rule {
            Rule::Region { name, .. } => {
                name_index(name, &mut names);
            }
            Rule::Split { names: [a, b], .. } => {
                name_index(a, &mut names);
                name_index(b, &mut names);
            }
        }
    }
    for part in &mesh.parts {
        name_index(part, &mut names);
    }
    let mut unmatched = 0;
    let mut assigned = Vec::with_capacity(mesh.triangles.len());
    for t in 0..mesh.triangles.len() {
        let corners = mesh.corners(t);
        let centroid = centroid(mesh, t);
        let part = mesh.parts[mesh.triangle_part[t] as usize].as_str();
        let hit = compiled
            .iter()
            .enumerate()
            .find_map(|(r, rule)| rule.assign(part, centroid, &renamed).map(|n| (r, n)));
        let name = match hit {
            Some((r, name)) => {
                reports[r].triangles += 1;
                reports[r].area_m2 += triangle_area(corners);
                name
            }
            None => {
                unmatched += 1;
                part
            }
        };
        assigned.push(name_index(name, &mut names));
    }
    // Keep only names that own triangles, in the order above.
    let mut used = vec![false; names.len()];
    for &i in &assigned {
        used[i] = true;
    }
    let mut remap = vec![u32::MAX; names.len()];
    let mut parts = Vec::new();
    for (i, name) in names.into_iter().enumerate() {
        if used[i] {
            remap[i] = parts.len() as u32;
            parts.push(name);
        }
    }
    mesh.parts = parts;
    mesh.triangle_part = assigned.into_iter().map(|i| remap[i]).collect();
    Ok(RegionReport { rules: reports, unmatched_triangles: unmatched, cut_triangles, left_whole })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, vec3};

    /// A 4 m × 2 m × 2 m box vehicle centred on x = 0, standing on z = 0, as
    /// two parts: `body` (sides, top, bottom) and `ends` (front and back),
    /// each face split into a 4 × 4 grid so that regions cut through faces.
    fn boxy() -> Mesh {
        boxy_grid(4)
    }

    /// [`boxy`] with each face an `n` × `n` grid of quads.
    fn boxy_grid(n: usize) -> Mesh {
        let mut mesh = Mesh::default();
        let (min, max) = (vec3(-2.0, -1.0, 0.0), vec3(2.0, 1.0, 2.0));
        let lerp = |a: f32, b: f32, i: usize| a + (b - a) * i as f32 / n as f32;
        // Faces as (part, origin corner, u edge, v edge).
        let size = max - min;
        let faces: [(&str, Vec3, Vec3, Vec3); 6] = [
            ("ends", vec3(max.x, min.y, min.z), Vec3::Y * size.y, Vec3::Z * size.z),
            ("ends", vec3(min.x, min.y, min.z), Vec3::Z * size.z, Vec3::Y * size.y),
            ("body", vec3(min.x, max.y, min.z), Vec3::Z * size.z, Vec3::X * size.x),
            ("body", vec3(min.x, min.y, min.z), Vec3::X * size.x, Vec3::Z * size.z),
            ("body", vec3(min.x, min.y, max.z), Vec3::X * size.x, Vec3::Y * size.y),
            ("body", vec3(min.x, min.y, min.z), Vec3::Y * size.y, Vec3::X * size.x),
        ];
        for (part, origin, u, v) in faces {
            for i in 0..n {
                for j in 0..n {
                    let at = |a: usize, b: usize| origin + u * lerp(0.0, 1.0, a) + v * lerp(0.0, 1.0, b);
                    mesh.add_quad(part, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                }
            }
        }
        mesh
    }

    fn rules(json: &str) -> Vec<PartRule> {
        serde_json::from_str(json).unwrap()
    }

    fn area_of(mesh: &Mesh, name: &str) -> f64 {
        let Some(part) = mesh.parts.iter().position(|p| p == name) else { return 0.0 };
        (0..mesh.triangles.len())
            .filter(|&t| mesh.triangle_part[t] as usize == part)
            .map(|t| triangle_area(mesh.corners(t)))
            .sum()
    }

    #[test]
    fn first_match_wins_and_unmatched_triangles_keep_their_part() {
        let mut mesh = boxy();
        let total = mesh.area();
        let report = apply(
            &mut mesh,
            &rules(
                r#"[
                {"name": "front", "box": {"min": [1.0, -5, -5], "max": [5, 5, 5]}},
                {"name": "roof", "where": {"normal": [0, 0, 2], "offset": 1.9}},
                {"name": "left_rear", "from": "body",
                 "where": [{"normal": [0, 1, 0], "offset": 0.1}, {"normal": [-1, 0, 0], "offset": 0.0}]}
            ]"#,
            ),
            &BTreeMap::new(),
        )
        .unwrap();
        // Front: centroids with x ≥ 1 — the front end (2 × 2 m²) and the
        // front quarter of each of the body's four 8 m² faces.
        let front = 4.0 + 4.0 * 8.0 / 4.0;
        assert!((area_of(&mesh, "front") - front).abs() < 1e-6, "{}", area_of(&mesh, "front"));
        // Roof: z ≥ 1.9 (the normal [0, 0, 2] is normalised, so the offset
        // is in metres) outside the front: the top face minus its front
        // quarter (6 m²) and the 0.1 m strips the plane cuts off the sides
        // (2 × 3 m × 0.1 m) and the rear end (2 m × 0.1 m).
        let roof = 6.0 + 2.0 * 0.3 + 0.2;
        assert!((area_of(&mesh, "roof") - roof).abs() < 1e-6, "{}", area_of(&mesh, "roof"));
        // Left rear: y ≥ 0.1 and x ≤ 0 among `body`: the left side's rear
        // half below the roof strip (2 m × 1.9 m) and the bottom's rear-left
        // part cut at y = 0.1 (2 m × 0.9 m); the top is already roof.
        let left_rear = 2.0 * 1.9 + 2.0 * 0.9;
        assert!((area_of(&mesh, "left_rear") - left_rear).abs() < 1e-6, "{}", area_of(&mesh, "left_rear"));
        // The rest keep their parts; nothing is lost.
        assert!((area_of(&mesh, "ends") - 3.8).abs() < 1e-6);
        let sum: f64 = mesh.parts.iter().map(|p| area_of(&mesh, p)).sum();
        assert!((sum - total).abs() < 1e-6);
        assert_eq!(mesh.parts, ["front", "roof", "left_rear", "ends", "body"]);
        assert_eq!(report.rules.len(), 3);
        assert!((report.rules[1].area_m2 - roof).abs() < 1e-6);
        assert!(report.cut_triangles > 0);
        let matched: usize = report.rules.iter().map(|r| r.triangles).sum();
        assert_eq!(matched + report.unmatched_triangles, mesh.triangles.len());
        assert!(report.warnings().is_empty());
    }

    #[test]
    fn splits_cut_one_part_and_others_collects_the_rest() {
        let mut mesh = boxy();
        let report = apply(
            &mut mesh,
            &rules(
                r#"[
                {"split": "body", "plane": {"normal": [1, 0, 0], "offset": 0.0}, "names": ["body_front", "body_rear"]},
                {"name": "nothing", "box": {"min": [10, 10, 10], "max": [11, 11, 11]}},
                {"name": "others"}
            ]"#,
            ),
            &BTreeMap::new(),
        )
        .unwrap();
        assert!((area_of(&mesh, "body_front") - 16.0).abs() < 1e-6);
        assert!((area_of(&mesh, "body_rear") - 16.0).abs() < 1e-6);
        assert!((area_of(&mesh, "others") - 8.0).abs() < 1e-6);
        // Parts without triangles disappear; the rule that matched nothing is reported.
        assert_eq!(mesh.parts, ["body_front", "body_rear", "others"]);
        assert_eq!(report.unmatched_triangles, 0);
        assert_eq!(report.warnings(), ["part rule \"nothing\" matched no triangle"]);
    }

    #[test]
    fn a_catch_all_rule_leaves_renamed_parts_alone() {
        let mut mesh = boxy();
        let rename = BTreeMap::from([("body".to_string(), "shell".to_string())]);
        mesh.rename_parts(&rename);
        let report = apply(
            &mut mesh,
            &rules(
                r#"[
                {"name": "front", "box": {"min": [1.0, -5, -5], "max": [5, 5, 5]}},
                {"name": "roof", "from": "shell", "box": {"min": [-5, -5, 2.0], "max": [5, 5, 5]}},
                {"name": "others"}
            ]"#,
            ),
            &rename,
        )
        .unwrap();
        // Neither the box without `from` nor the catch-all takes the renamed
        // shell; only the rule that lists it does (the 4 × 2 m² top).
        assert!((area_of(&mesh, "front") - 4.0).abs() < 1e-6, "{}", area_of(&mesh, "front"));
        assert!((area_of(&mesh, "roof") - 8.0).abs() < 1e-6);
        assert!((area_of(&mesh, "shell") - 24.0).abs() < 1e-6);
        assert!((area_of(&mesh, "others") - 4.0).abs() < 1e-6, "the rear end, not renamed");
        assert_eq!(report.rules[2].triangles, 32, "the rear end's 4 × 4 × 2 triangles");
    }

    #[test]
    fn boundaries_cut_large_triangles_so_regions_get_their_exact_area() {
        // Each face two triangles: the centroid test alone would give whole
        // half-walls to whichever side their centroid falls.
        let mut mesh = boxy_grid(1);
        let total = mesh.area();
        let report = apply(
            &mut mesh,
            &rules(
                r#"[
                {"name": "roof", "box": {"min": [-5, -5, 1.5], "max": [5, 5, 5]}},
                {"split": "body", "plane": {"normal": [1, 0, 0], "offset": 0.3}, "names": ["front", "rear"]},
                {"name": "others"}
            ]"#,
            ),
            &BTreeMap::new(),
        )
        .unwrap();
        // Roof: the top (4 × 2) and a 0.5 m band around the walls (perimeter 12 m).
        assert!((area_of(&mesh, "roof") - (8.0 + 12.0 * 0.5)).abs() < 1e-5, "{}", area_of(&mesh, "roof"));
        // The body's sides below 1.5 m and its bottom, cut at x = 0.3:
        // front 1.7 m of x, rear 2.3 m.
        let front = 2.0 * 1.7 * 1.5 + 1.7 * 2.0;
        let rear = 2.0 * 2.3 * 1.5 + 2.3 * 2.0;
        assert!((area_of(&mesh, "front") - front).abs() < 1e-5, "{}", area_of(&mesh, "front"));
        assert!((area_of(&mesh, "rear") - rear).abs() < 1e-5, "{}", area_of(&mesh, "rear"));
        assert!((area_of(&mesh, "others") - 2.0 * 2.0 * 1.5).abs() < 1e-5, "the ends below the roof");
        assert!((mesh.area() - total).abs() < 1e-5, "cutting keeps the surface");
        // Every piece lies on one side of every boundary that could change its part: no triangle
        // spans z = 1.5, and none below the roof spans x = 0.3 (the roof, taken first, is not cut
        // by the later split).
        for t in 0..mesh.triangles.len() {
            let c = mesh.corners(t);
            let roof = mesh.parts[mesh.triangle_part[t] as usize] == "roof";
            for (value, axis) in [(1.5, 2), (0.3, 0)].into_iter().filter(|&(_, axis)| !(roof && axis == 0)) {
                let above = c.iter().any(|p| f64::from(p[axis]) > value + 1e-4);
                let below = c.iter().any(|p| f64::from(p[axis]) < value - 1e-4);
                assert!(!(above && below), "triangle {t} spans {value} on axis {axis}: {c:?}");
            }
        }
        assert!(report.cut_triangles >= 8, "{}", report.cut_triangles);
    }

    #[test]
    fn no_rules_change_nothing() {
        let mut mesh = boxy();
        let before = mesh.clone();
        let report = apply(&mut mesh, &[], &BTreeMap::new()).unwrap();
        assert_eq!(mesh, before);
        assert_eq!(report.unmatched_triangles, mesh.triangles.len());
    }

    #[test]
    fn bad_rules_are_named() {
        let cases = [
            (r#"[{"name": "a", "split": "body"}]"#, "parts[0] (a): give either"),
            (r#"[{"name": "a", "from": "chassis"}]"#, "names part \"chassis\""),
            (
                r#"[{"name": "a"}, {"split": "body", "plane": {"normal": [1, 0, 0], "offset": 0}}]"#,
                "parts[1] (split body): a split needs \"names\"",
            ),
            (r#"[{"split": "body", "names": ["a", "b"]}]"#, "needs a \"plane\""),
            (r#"[{"name": "a", "where": {"normal": [0, 0, 0], "offset": 1}}]"#, "non-zero"),
            (r#"[{"name": "a", "box": {"min": [1, 0, 0], "max": [0, 1, 1]}}]"#, "min ≤ max"),
        ];
        for (json, expected) in cases {
            let mut mesh = boxy();
            let error = apply(&mut mesh, &rules(json), &BTreeMap::new()).unwrap_err();
            assert!(error.contains(expected), "{json}: {error}");
            assert_eq!(mesh, boxy(), "a failed rule set must leave the mesh alone");
        }
        assert!(serde_json::from_str::<Vec<PartRule>>(r#"[{"name": "a", "bx": {}}]"#).is_err());
    }

    /// `count` region rules: boxes about half the cube's side, scattered
    /// over it by a fixed LCG, each crossing several faces.
    fn scattered_boxes(count: usize) -> Vec<Rule> {
        let mut state = 12345u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..count)
            .map(|i| {
                let centre = DVec3::new(next(), next(), next()) * 2.4 - 1.2;
                let half = DVec3::new(next(), next(), next()) * 0.3 + 0.15;
                let region_box = Some((centre - half, centre + half));
                Rule::Region { name: format!("r{i}"), from: Vec::new(), region_box, half_spaces: Vec::new() }
            })
            .collect()
    }

    /// `count` slabs across the cube, each taking the strip beside the last (`x ≤ −0.9 + 0.012 i`).
    fn slabs(count: usize) -> Vec<Rule> {
        (0..count)
            .map(|i| Rule::Region {
                name: format!("s{i}"),
                from: Vec::new(),
                region_box: Some((DVec3::splat(-2.0), DVec3::new(-0.9 + 0.012 * i as f64, 2.0, 2.0))),
                half_spaces: Vec::new(),
            })
            .collect()
    }

    #[test]
    fn many_region_rules_on_a_small_model_cost_work_near_linear_in_the_rules() {
        // A 2 m cube of 12 triangles and 35, 70 and 140 rules: cutting every piece by every later
        // boundary, triangle by triangle, made the pieces multiply (slabs: 532, 1852, 6892
        // triangles at 10, 20, 40 rules; scattered boxes 28,332 at 140, 12 s in a debug build).
        // Convex pieces, settled once taken, grow with the rules, and so does the work.
        let mut cube = Mesh::default();
        cube.add_box(Vec3::splat(-1.0), Vec3::ONE, [Some("body"); 6]);
        let renamed = BTreeSet::new();
        for (what, rules) in [("slabs", slabs as fn(usize) -> Vec<Rule>), ("boxes", scattered_boxes)] {
            let mut work = Vec::new();
            for count in [35, 70, 140] {
                let mut mesh = cube.clone();
                let pieces = cut_along(&mut mesh, &rules(count), &renamed);
                assert!(pieces.left_whole.is_empty(), "{count} rules ran out of the budget");
                assert!((mesh.area() - 24.0).abs() < 1e-3, "cutting keeps the surface");
                eprintln!(
                    "{what}, {count} rules: {} triangles, {} tests",
                    mesh.triangles.len(),
                    pieces.tests
                );
                work.push((count, mesh.triangles.len(), pieces.tests));
            }
            for &(count, triangles, tests) in &work {
                assert!(triangles <= 12 + 40 * count, "{what}, {count} rules: {triangles} triangles");
                assert!(tests <= 400 * count, "{what}, {count} rules: {tests} tests");
            }
            // Doubling the rules at most about doubles the pieces (measured: slabs 572, 1132,
            // 2252 triangles and 2812, 5612, 11212 tests; boxes 744, 1248, 2104 and 7296, 18791,
            // 45939).
            for pair in work.windows(2) {
                assert!(pair[1].1 <= 5 * pair[0].1 / 2, "{what}: {work:?}");
            }
        }
    }
}
