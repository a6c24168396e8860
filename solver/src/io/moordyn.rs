//! MoorDyn v2 input decks ([MoorDyn input file documentation], "The V2 Input File") read into a
//! global-stage [`CaseSpec`].
//!
//! A deck is split into sections by header lines of dashes around a key phrase (`LINE TYPES`,
//! `POINTS`, `LINES`, `OPTIONS`, …). Table sections start with a row of column names and a row
//! of units, then one entry per row; `!`, `#` and `%` start a comment. OPTIONS rows are
//! `value key [description]`.
//!
//! What maps:
//! - **Line types** → [`LineTypeSpec`]: mass, EA, EI (EI > 0 makes a rope, else a chain),
//!   the volume-equivalent diameter `Diam` as hydrodynamic diameter, the submerged weight
//!   (m − ρ π d²/4) g, `Cd` and `Ca` as they are, the tangential drag `CdAx` × π (MoorDyn
//!   refers it to the surface area π d per metre, moorfret to d) and `CaAx` as it is.
//! - **Points**: `Fixed`/`Anchor` are anchors; `Coupled`/`Vessel`/`CpldPin` (and `Body#`
//!   points of an unrotated body at the origin) are fairleads; `Free`/`Connect`/`Point` join two
//!   lines. A free point's mass and volume become an extra mass (with its volume) spread over
//!   the first element of the anchor-side line.
//! - **Lines**: each chain of lines from a fairlead to an anchor becomes one moorfret line;
//!   `NumSegs` is the element count. moorfret lines share one make-up and a radial layout
//!   (fairleads on a circle, anchors radially outward at one distance): a deck that breaks
//!   this is refused, naming its row.
//! - **Options**: `WtrDpth`, `rho`/`rhoW`/`WtrDnsty`, `g`, `kBot` (× the diameter of the
//!   anchor-side line type, since moorfret's seabed stiffness is per metre of line) and
//!   `FrictionCoefficient`.
//!
//! What does not map is reported as a [`DeckNote`] naming the row and the value chosen: internal
//! damping `BA` (moorfret damps each element's axial mode at a fixed ratio), seabed damping
//! `cBot`, the time step `dtM` (moorfret integrates implicitly), wave kinematics (the case is
//! calm water), a free point's drag and added mass, VIV coefficients, pinned joints between
//! ropes (moorfret's rope is C¹ through its segments), outputs. Rods, non-linear EA, bodies
//! away from the origin and v1 decks are refused.
//!
//! [MoorDyn input file documentation]: https://moordyn.readthedocs.io/en/latest/inputs.html

use std::collections::BTreeMap;
use std::f64::consts::PI;

use crate::global::case::{
    CaseSpec, FloaterSource, HotSpotSpec, LineLayoutSpec, MooringSpec, SeaStateSpec, SiteSpec,
    TimingSpec, WindSpec,
};
use crate::mooring::spec::{default_gravity, LineTypeSpec, SeabedSpec, SegmentSpec};

/// A deck that cannot be read or mapped, with the 1-based row of the deck it concerns (0 when
/// it concerns the deck as a whole).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{reason}", row_prefix(*row))]
pub struct DeckError {
    /// 1-based row of the deck.
    pub row: usize,
    /// What is wrong.
    pub reason: String,
}

/// Something of the deck that moorfret does not represent, and the value it uses instead.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckNote {
    /// 1-based row of the deck.
    pub row: usize,
    /// What was not mapped and what is used.
    pub message: String,
}

impl std::fmt::Display for DeckNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", row_prefix(self.row), self.message)
    }
}

fn row_prefix(row: usize) -> String {
    if row == 0 {
        String::new()
    } else {
        format!("deck row {row}: ")
    }
}

fn refuse(row: usize, reason: impl Into<String>) -> DeckError {
    DeckError {
        row,
        reason: reason.into(),
    }
}

/// One table entry: its row and its fields.
#[derive(Debug, Clone, PartialEq)]
struct Entry {
    row: usize,
    fields: Vec<String>,
}

impl Entry {
    fn text(&self, column: usize, name: &str) -> Result<&str, DeckError> {
        self.fields.get(column).map(String::as_str).ok_or_else(|| {
            refuse(
                self.row,
                format!("column {} ({name}) is missing", column + 1),
            )
        })
    }

    fn number(&self, column: usize, name: &str) -> Result<f64, DeckError> {
        let text = self.text(column, name)?;
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                let why = if text.contains('|') {
                    "a non-linear or viscoelastic value (with '|') is not supported"
                } else {
                    "is not a finite number"
                };
                refuse(self.row, format!("{name} '{text}': {why}"))
            })
    }

    /// Checks that the ID column of the `k`-th entry (from 0) of a table of `what`s is k + 1.
    fn sequential_id(&self, k: usize, what: &str) -> Result<(), DeckError> {
        let id = self.number(0, "ID")?;
        if id == (k + 1) as f64 {
            Ok(())
        } else {
            Err(refuse(
                self.row,
                format!(
                    "{what} IDs must run 1, 2, … in order (found {id} at position {})",
                    k + 1
                ),
            ))
        }
    }

    fn optional_number(&self, column: usize, name: &str) -> Result<f64, DeckError> {
        if column < self.fields.len() {
            self.number(column, name)
        } else {
            Ok(0.0)
        }
    }
}

/// The sections of a deck that the import reads.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Deck {
    line_types: Vec<Entry>,
    bodies: Vec<Entry>,
    points: Vec<Entry>,
    lines: Vec<Entry>,
    options: Vec<Entry>,
    /// Sections present but not imported, with their header row.
    ignored: Vec<(usize, String)>,
    /// Rods or rod types (refused when mapping).
    rods: Option<usize>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Section {
    FrontMatter,
    LineTypes,
    RodTypes,
    Bodies,
    Rods,
    Points,
    Lines,
    Options,
    Other,
}

/// Header rows: dashes, a key phrase, dashes.
fn header(line: &str) -> Option<String> {
    let t = line.trim();
    if !t.starts_with("---") {
        return None;
    }
    let name = t.trim_matches('-').trim();
    Some(name.to_ascii_uppercase())
}

fn strip_comment(line: &str) -> &str {
    match line.find(['!', '#', '%']) {
        Some(i) => &line[..i],
        None => line,
    }
}

impl Deck {
    /// Splits the deck text into its sections.
    pub(crate) fn parse(text: &str) -> Result<Self, DeckError> {
        let mut deck = Deck::default();
        let mut section = Section::FrontMatter;
        // Rows of column names and units still to skip in the current table.
        let mut skip = 0;
        let mut seen_lines = false;
        for (i, line) in text.lines().enumerate() {
            let row = i + 1;
            if let Some(name) = header(line) {
                section = match name.as_str() {
                    "LINE TYPES" => Section::LineTypes,
                    "ROD TYPES" => Section::RodTypes,
                    "BODIES" | "BODY LIST" => Section::Bodies,
                    "RODS" | "ROD LIST" => Section::Rods,
                    "POINTS" | "POINT LIST" => Section::Points,
                    "LINES" | "LINE LIST" => Section::Lines,
                    "OPTIONS" => Section::Options,
                    "LINE DICTIONARY"
                    | "NODE PROPERTIES"
                    | "CONNECTION PROPERTIES"
                    | "LINE PROPERTIES"
                    | "SOLVER OPTIONS" => {
                        return Err(refuse(
                            row,
                            format!(
                                "section '{name}' belongs to a MoorDyn v1 deck; moorfret reads \
                                 v2 decks (LINE TYPES, POINTS, LINES, OPTIONS)"
                            ),
                        ))
                    }
                    _ if section == Section::FrontMatter && !seen_lines => Section::FrontMatter,
                    n if n.contains("NEED THIS LINE") || n.is_empty() => Section::Other,
                    _ => {
                        deck.ignored.push((row, name.clone()));
                        Section::Other
                    }
                };
                if matches!(section, Section::RodTypes | Section::Rods) {
                    deck.rods.get_or_insert(row);
                }
                if section == Section::Lines {
                    seen_lines = true;
                }
                skip = match section {
                    Section::FrontMatter | Section::Options | Section::Other => 0,
                    _ => 2,
                };
                continue;
            }
            let body = strip_comment(line);
            if body.trim().is_empty() {
                continue;
            }
            if skip > 0 {
                skip -= 1;
                continue;
            }
            let entry = Entry {
                row,
                fields: body.split_whitespace().map(str::to_owned).collect(),
            };
            match section {
                Section::LineTypes => deck.line_types.push(entry),
                Section::Bodies => deck.bodies.push(entry),
                Section::Points => deck.points.push(entry),
                Section::Lines => deck.lines.push(entry),
                Section::Options => deck.options.push(entry),
                Section::RodTypes | Section::Rods => {}
                Section::FrontMatter | Section::Other => {}
            }
        }
        if deck.lines.is_empty() {
            return Err(refuse(0, "the deck has no LINES entries"));
        }
        Ok(deck)
    }
}

/// What the deck does not say and the case needs.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportSettings {
    /// Case name.
    pub name: String,
    /// Where the floater motion comes from (a prescribed table or a rigid-body file).
    pub floater: FloaterSource,
    /// Time step of the implicit integration and output interval (s).
    pub time_step_s: f64,
    /// Recorded duration (s), from t = 0 (no transient).
    pub duration_s: f64,
    /// Hot spots, by moorfret line id (the MoorDyn id of the line at the fairlead).
    pub hot_spots: Vec<HotSpotSpec>,
}

/// A case read from a deck, with what did not map.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// The case (calm water: the deck's waves are not imported).
    pub case: CaseSpec,
    /// Deck content moorfret does not represent, and the values used instead.
    pub notes: Vec<DeckNote>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Role {
    Anchor,
    Fairlead,
    Free,
}

#[derive(Debug, Clone, PartialEq)]
struct Point {
    row: usize,
    role: Role,
    position_m: [f64; 3],
    mass_kg: f64,
    volume_m3: f64,
}

#[derive(Debug, Clone, PartialEq)]
struct Line {
    row: usize,
    id: u32,
    line_type: String,
    ends: [usize; 2],
    length_m: f64,
    elements: usize,
}

/// Where a chain of lines lies: its fairlead and anchor points and their radial geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Placed {
    fairlead: usize,
    anchor: usize,
    /// moorfret line id: the MoorDyn id of the line at the fairlead.
    id: u32,
    radius_m: f64,
    depth_m: f64,
    reach_m: f64,
    azimuth_rad: f64,
    anchor_z_m: f64,
}

/// One segment of a chain, with its row and the free point above it.
#[derive(Debug, Clone, PartialEq)]
struct ChainSegment {
    line: usize,
    /// Free point at the fairlead-side end, if any.
    joint: Option<usize>,
}

struct Options {
    depth_m: Option<f64>,
    density_kg_m3: f64,
    gravity_m_s2: f64,
    k_bot_pa_per_m: Option<(usize, f64)>,
    friction: f64,
}

fn read_options(deck: &Deck, notes: &mut Vec<DeckNote>) -> Result<Options, DeckError> {
    let mut o = Options {
        depth_m: None,
        density_kg_m3: 1025.0,
        gravity_m_s2: default_gravity(),
        k_bot_pa_per_m: None,
        friction: 0.0,
    };
    let mut gravity_given = false;
    for e in &deck.options {
        let key = e.text(1, "option name")?;
        let value = || e.number(0, key);
        match key.to_ascii_lowercase().as_str() {
            "wtrdpth" | "depth" => o.depth_m = Some(value()?),
            "rho" | "rhow" | "wtrdnsty" => o.density_kg_m3 = value()?,
            "g" | "gravity" => {
                o.gravity_m_s2 = value()?;
                gravity_given = true;
            }
            "kbot" => o.k_bot_pa_per_m = Some((e.row, value()?)),
            "frictioncoefficient" => o.friction = value()?,
            "cbot" => notes.push(DeckNote {
                row: e.row,
                message: format!(
                    "cBot {} Pa·s/m not used: the seabed damping is 0.2 of critical (site.seabed.damping_ratio)",
                    e.fields[0]
                ),
            }),
            "dtm" => notes.push(DeckNote {
                row: e.row,
                message: format!(
                    "dtM {} s not used: moorfret's implicit integrator takes timing.time_step_s",
                    e.fields[0]
                ),
            }),
            "wavekin" | "waterkin" | "currents" => {
                if e.fields[0] != "0" && !e.fields[0].is_empty() {
                    notes.push(DeckNote {
                        row: e.row,
                        message: format!(
                            "{key} {} not imported: the case is calm water; add a sea_state for waves",
                            e.fields[0]
                        ),
                    });
                }
            }
            _ => notes.push(DeckNote {
                row: e.row,
                message: format!("option {key} not used"),
            }),
        }
    }
    if !gravity_given {
        notes.push(DeckNote {
            row: 0,
            message: format!(
                "no g option: standard gravity {} m/s² used (MoorDyn's default is 9.81)",
                o.gravity_m_s2
            ),
        });
    }
    Ok(o)
}

fn read_line_types(
    deck: &Deck,
    opt: &Options,
    notes: &mut Vec<DeckNote>,
) -> Result<BTreeMap<String, (usize, LineTypeSpec)>, DeckError> {
    let mut types = BTreeMap::new();
    for e in &deck.line_types {
        let name = e.text(0, "TypeName")?.to_owned();
        let d = e.number(1, "Diam")?;
        let m = e.number(2, "Mass/m")?;
        let ea = e.number(3, "EA")?;
        let ba = e.number(4, "BA/-zeta")?;
        let ei = e.number(5, "EI")?;
        let (cd, ca, cd_ax, ca_ax) = (
            e.number(6, "Cd")?,
            e.number(7, "Ca")?,
            e.number(8, "CdAx")?,
            e.number(9, "CaAx")?,
        );
        if d <= 0.0 {
            return Err(refuse(
                e.row,
                format!("Diam of {name} must be > 0 (got {d})"),
            ));
        }
        let weight = (m - opt.density_kg_m3 * PI * d * d / 4.0) * opt.gravity_m_s2;
        if weight < 0.0 {
            return Err(refuse(
                e.row,
                format!(
                    "line type {name} floats (submerged weight {weight:.4e} N/m); moorfret \
                     lines must sink"
                ),
            ));
        }
        if ba != 0.0 {
            notes.push(DeckNote {
                row: e.row,
                message: format!(
                    "BA/-zeta {ba} of {name} not used: moorfret damps each element's axial mode \
                     at 0.5 of critical"
                ),
            });
        }
        if e.optional_number(10, "Cl")? != 0.0 {
            notes.push(DeckNote {
                row: e.row,
                message: format!("VIV coefficients of {name} not used"),
            });
        }
        let spec = LineTypeSpec {
            mass_kg_per_m: m,
            submerged_weight_n_per_m: weight,
            axial_stiffness_n: ea,
            bending_stiffness_nm2: ei,
            bending_stiffness_min_nm2: None,
            torsional_stiffness_nm2: None,
            hydrodynamic_diameter_m: d,
            drag_normal: cd,
            drag_tangential: PI * cd_ax,
            added_mass_normal: ca,
            added_mass_tangential: ca_ax,
            minimum_breaking_load_n: None,
        };
        if types.insert(name.clone(), (e.row, spec)).is_some() {
            return Err(refuse(e.row, format!("line type {name} is defined twice")));
        }
    }
    Ok(types)
}

fn read_points(deck: &Deck, notes: &mut Vec<DeckNote>) -> Result<Vec<Point>, DeckError> {
    // Bodies: only a coupled body at the origin, unrotated, whose points are then global.
    let mut bodies = Vec::new();
    for e in &deck.bodies {
        let pose: Vec<f64> = (2..8)
            .map(|c| e.number(c, "X0/Y0/Z0/r0/p0/y0"))
            .collect::<Result<_, _>>()?;
        if pose.iter().any(|v| *v != 0.0) {
            return Err(refuse(
                e.row,
                "a body away from the origin or rotated is not supported: the floater's \
                 reference point is the origin, at the still water level",
            ));
        }
        notes.push(DeckNote {
            row: e.row,
            message: "body mass, volume and drag not used: the floater is the prescribed \
                      motion or rigid-body file given to the import"
                .into(),
        });
        bodies.push(e.text(0, "ID")?.to_owned());
    }
    let mut points = Vec::new();
    for (k, e) in deck.points.iter().enumerate() {
        e.sequential_id(k, "point")?;
        let attachment = e.text(1, "Attachment")?.to_ascii_lowercase();
        let role = match attachment.as_str() {
            "fixed" | "anchor" | "fix" => Role::Anchor,
            "coupled" | "vessel" | "cpldpin" | "vessel_pinned" => Role::Fairlead,
            "free" | "connect" | "point" => Role::Free,
            a if a.starts_with("body") || a.starts_with("turbine") => {
                let n = a.trim_start_matches(char::is_alphabetic);
                if a.starts_with("body") && !bodies.iter().any(|b| b == n) {
                    return Err(refuse(
                        e.row,
                        format!("attachment {a} names no body of BODIES"),
                    ));
                }
                Role::Fairlead
            }
            other => return Err(refuse(e.row, format!("attachment '{other}' is not known"))),
        };
        let position_m = [e.number(2, "X")?, e.number(3, "Y")?, e.number(4, "Z")?];
        let mass_kg = e.optional_number(5, "Mass")?;
        let volume_m3 = e.optional_number(6, "Volume")?;
        let (cda, ca) = (e.optional_number(7, "CdA")?, e.optional_number(8, "Ca")?);
        if role == Role::Free && (cda != 0.0 || ca != 0.0) {
            notes.push(DeckNote {
                row: e.row,
                message: format!(
                    "drag area {cda} m² and added mass coefficient {ca} of point {} not used",
                    k + 1
                ),
            });
        }
        if role != Role::Free && (mass_kg != 0.0 || volume_m3 != 0.0) {
            notes.push(DeckNote {
                row: e.row,
                message: format!(
                    "mass and volume of point {} not used: it is fixed or moves with the floater",
                    k + 1
                ),
            });
        }
        points.push(Point {
            row: e.row,
            role,
            position_m,
            mass_kg,
            volume_m3,
        });
    }
    Ok(points)
}

fn read_lines(
    deck: &Deck,
    points: &[Point],
    types: &BTreeMap<String, (usize, LineTypeSpec)>,
) -> Result<Vec<Line>, DeckError> {
    let mut lines = Vec::new();
    for (k, e) in deck.lines.iter().enumerate() {
        e.sequential_id(k, "line")?;
        let line_type = e.text(1, "LineType")?.to_owned();
        if !types.contains_key(&line_type) {
            return Err(refuse(
                e.row,
                format!("LineType {line_type} is not in LINE TYPES"),
            ));
        }
        let mut ends = [0; 2];
        for (j, name) in [(2, "AttachA"), (3, "AttachB")] {
            let text = e.text(j, name)?;
            if text.to_ascii_uppercase().starts_with('R') {
                return Err(refuse(
                    e.row,
                    format!("{name} {text} is a rod end; rods are not supported"),
                ));
            }
            let p = text
                .parse::<usize>()
                .ok()
                .filter(|p| (1..=points.len()).contains(p))
                .ok_or_else(|| refuse(e.row, format!("{name} {text} names no point")))?;
            ends[j - 2] = p - 1;
        }
        let length_m = e.number(4, "UnstrLen")?;
        let segs = e.number(5, "NumSegs")?;
        if length_m <= 0.0 {
            return Err(refuse(
                e.row,
                format!("UnstrLen must be > 0 (got {length_m})"),
            ));
        }
        if !(segs >= 1.0 && segs.fract() == 0.0 && segs <= 1e5) {
            return Err(refuse(
                e.row,
                format!("NumSegs must be a whole number >= 1 (got {segs})"),
            ));
        }
        lines.push(Line {
            row: e.row,
            id: (k + 1) as u32,
            line_type,
            ends,
            length_m,
            elements: segs as usize,
        });
    }
    Ok(lines)
}

/// The chain of lines from fairlead point `start` to an anchor.
fn chain_from(
    start: usize,
    points: &[Point],
    lines: &[Line],
) -> Result<(Vec<ChainSegment>, usize), DeckError> {
    let attached = |p: usize| -> Vec<usize> {
        (0..lines.len())
            .filter(|&l| lines[l].ends.contains(&p))
            .collect()
    };
    let first = attached(start);
    if first.len() != 1 {
        return Err(refuse(
            points[start].row,
            format!(
                "fairlead point {} holds {} lines; a moorfret line runs from one fairlead to one anchor",
                start + 1,
                first.len()
            ),
        ));
    }
    let mut chain = vec![ChainSegment {
        line: first[0],
        joint: None,
    }];
    let mut at = start;
    loop {
        let l = chain.last().map(|s| s.line).unwrap_or(first[0]);
        let ends = lines[l].ends;
        let next = if ends[0] == at { ends[1] } else { ends[0] };
        if next == at {
            return Err(refuse(
                lines[l].row,
                "a line must join two different points",
            ));
        }
        match points[next].role {
            Role::Anchor => return Ok((chain, next)),
            Role::Fairlead => {
                return Err(refuse(
                    lines[l].row,
                    format!("line {} joins two fairlead points", lines[l].id),
                ))
            }
            Role::Free => {
                let others: Vec<usize> = attached(next).into_iter().filter(|&o| o != l).collect();
                if others.len() != 1 {
                    return Err(refuse(
                        points[next].row,
                        format!(
                            "free point {} joins {} lines; moorfret lines are single chains \
                             (two lines per free point)",
                            next + 1,
                            others.len() + 1
                        ),
                    ));
                }
                if chain.len() > lines.len() {
                    return Err(refuse(points[next].row, "the lines form a loop"));
                }
                chain.push(ChainSegment {
                    line: others[0],
                    joint: Some(next),
                });
                at = next;
            }
        }
    }
}

/// The segments of a chain, fairlead first; a free point's mass goes on the first element of
/// the line below it.
fn segments_of(
    chain: &[ChainSegment],
    points: &[Point],
    lines: &[Line],
    types: &BTreeMap<String, (usize, LineTypeSpec)>,
    notes: Option<&mut Vec<DeckNote>>,
) -> Vec<(usize, SegmentSpec)> {
    let mut out = Vec::new();
    let mut notes = notes;
    for (k, s) in chain.iter().enumerate() {
        let line = &lines[s.line];
        let segment = |length_m: f64, elements: usize, name: String| SegmentSpec {
            name,
            line_type: line.line_type.clone(),
            length_m,
            elements,
            extra_mass_kg: None,
            extra_volume_m3: None,
        };
        let clump = s
            .joint
            .map(|p| &points[p])
            .filter(|p| p.mass_kg != 0.0 || p.volume_m3 != 0.0);
        if let (Some(joint), Some(notes)) = (s.joint, notes.as_deref_mut()) {
            let above = &types[&lines[chain[k - 1].line].line_type].1;
            let below = &types[&line.line_type].1;
            if above.is_rope() && below.is_rope() {
                notes.push(DeckNote {
                    row: points[joint].row,
                    message: format!(
                        "point {} is a pin between two ropes; moorfret's rope stays C¹ through it",
                        joint + 1
                    ),
                });
            }
        }
        match clump {
            Some(p) => {
                let element_m = line.length_m / line.elements as f64;
                let mut first = segment(element_m, 1, format!("line-{}-clump", line.id));
                first.extra_mass_kg = Some(p.mass_kg);
                first.extra_volume_m3 = Some(p.volume_m3);
                if let Some(notes) = notes.as_deref_mut() {
                    notes.push(DeckNote {
                        row: p.row,
                        message: format!(
                            "point mass {} kg, volume {} m³ spread over the first element \
                             ({element_m} m) of line {}",
                            p.mass_kg, p.volume_m3, line.id
                        ),
                    });
                }
                out.push((line.row, first));
                if line.elements > 1 {
                    out.push((
                        line.row,
                        segment(
                            line.length_m - element_m,
                            line.elements - 1,
                            format!("line-{}", line.id),
                        ),
                    ));
                }
            }
            None => out.push((
                line.row,
                segment(line.length_m, line.elements, format!("line-{}", line.id)),
            )),
        }
    }
    out
}

fn same_segment(a: &SegmentSpec, b: &SegmentSpec) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0);
    let opt = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => close(x, y),
        (None, None) => true,
        _ => false,
    };
    a.line_type == b.line_type
        && a.elements == b.elements
        && close(a.length_m, b.length_m)
        && opt(a.extra_mass_kg, b.extra_mass_kg)
        && opt(a.extra_volume_m3, b.extra_volume_m3)
}

/// Reads the deck into a case; the notes list what did not map.
pub fn import(text: &str, settings: &ImportSettings) -> Result<Imported, DeckError> {
    let deck = Deck::parse(text)?;
    if let Some(row) = deck.rods {
        return Err(refuse(row, "rods are not supported"));
    }
    let mut notes = Vec::new();
    for (row, name) in &deck.ignored {
        notes.push(DeckNote {
            row: *row,
            message: format!("section {name} not imported"),
        });
    }
    let opt = read_options(&deck, &mut notes)?;
    let types = read_line_types(&deck, &opt, &mut notes)?;
    let points = read_points(&deck, &mut notes)?;
    let lines = read_lines(&deck, &points, &types)?;

    let fairleads: Vec<usize> = (0..points.len())
        .filter(|&p| points[p].role == Role::Fairlead)
        .collect();
    if fairleads.is_empty() {
        return Err(refuse(0, "no Coupled, Vessel or Body point: no fairlead"));
    }
    let mut chains = Vec::new();
    for &f in &fairleads {
        chains.push((f, chain_from(f, &points, &lines)?));
    }
    let used: usize = chains.iter().map(|(_, (c, _))| c.len()).sum();
    if used != lines.len() {
        let free = (0..lines.len())
            .find(|l| {
                !chains
                    .iter()
                    .any(|(_, (c, _))| c.iter().any(|s| s.line == *l))
            })
            .unwrap_or(0);
        return Err(refuse(
            lines[free].row,
            format!(
                "line {} is not on a path from a fairlead to an anchor",
                lines[free].id
            ),
        ));
    }

    // One make-up for all lines.
    let (f0, (c0, _)) = &chains[0];
    let makeup = segments_of(c0, &points, &lines, &types, Some(&mut notes));
    for (_, (c, _)) in &chains[1..] {
        let other = segments_of(c, &points, &lines, &types, None);
        if other.len() != makeup.len() {
            return Err(refuse(
                lines[c[0].line].row,
                format!(
                    "this line's chain has {} segments, the first line's (from fairlead point {}) \
                     {} (moorfret lines share one make-up)",
                    other.len(),
                    f0 + 1,
                    makeup.len()
                ),
            ));
        }
        for ((_, a), (row, b)) in makeup.iter().zip(&other) {
            if !same_segment(a, b) {
                return Err(refuse(
                    *row,
                    format!(
                        "this line differs from the first line's make-up ({} {} m × {} elements \
                         against {} {} m × {}); moorfret lines share one make-up",
                        b.line_type, b.length_m, b.elements, a.line_type, a.length_m, a.elements
                    ),
                ));
            }
        }
    }

    // Radial layout.
    let mut layout = Vec::new();
    for (f, (c, anchor)) in &chains {
        let fp = points[*f].position_m;
        let ap = points[*anchor].position_m;
        let radius = fp[0].hypot(fp[1]);
        let (dx, dy) = (ap[0] - fp[0], ap[1] - fp[1]);
        let reach = dx.hypot(dy);
        let azimuth = if radius > 1e-9 {
            fp[1].atan2(fp[0])
        } else {
            dy.atan2(dx)
        };
        let outward = dy.atan2(dx);
        let mut turn = (outward - azimuth).rem_euclid(2.0 * PI);
        if turn > PI {
            turn -= 2.0 * PI;
        }
        if reach <= 0.0 || turn.abs() > 1e-6 {
            return Err(refuse(
                points[*anchor].row,
                format!(
                    "the anchor of the line from point {} is not radially outward from its \
                     fairlead ({:.4}° off); moorfret places anchors radially",
                    f + 1,
                    turn.to_degrees()
                ),
            ));
        }
        layout.push(Placed {
            fairlead: *f,
            anchor: *anchor,
            id: lines[c[0].line].id,
            radius_m: radius,
            depth_m: -fp[2],
            reach_m: reach,
            azimuth_rad: azimuth,
            anchor_z_m: ap[2],
        });
    }
    let first = &layout[0];
    let (a0, radius, depth, reach, anchor_z) = (
        first.anchor,
        first.radius_m,
        first.depth_m,
        first.reach_m,
        first.anchor_z_m,
    );
    for p in &layout[1..] {
        let (f, a, r, d, h, z) = (
            p.fairlead,
            p.anchor,
            p.radius_m,
            p.depth_m,
            p.reach_m,
            p.anchor_z_m,
        );
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1.0);
        if !close(r, radius) || !close(d, depth) {
            return Err(refuse(
                points[f].row,
                format!(
                    "fairlead at radius {r} m, depth {d} m; the first is at {radius} m, {depth} m \
                     (moorfret fairleads share one radius and depth)"
                ),
            ));
        }
        if !close(h, reach) || !close(z, anchor_z) {
            return Err(refuse(
                points[a].row,
                format!(
                    "anchor {h} m from its fairlead at z = {z} m; the first is {reach} m at z = \
                     {anchor_z} m (moorfret anchors share one distance and lie on the seabed)"
                ),
            ));
        }
    }
    let water_depth_m = match opt.depth_m {
        Some(d) => {
            if (d + anchor_z).abs() > 1e-6 * d.max(1.0) {
                return Err(refuse(
                    points[a0].row,
                    format!("anchor at z = {anchor_z} m is not on the seabed (WtrDpth {d} m)"),
                ));
            }
            d
        }
        None => {
            notes.push(DeckNote {
                row: 0,
                message: format!(
                    "no WtrDpth option: the depth of the anchors, {} m, used",
                    -anchor_z
                ),
            });
            -anchor_z
        }
    };

    // Seabed: MoorDyn's kBot is per unit area of line (Pa/m), moorfret's per metre of line.
    let bottom_type = &makeup
        .last()
        .map(|(_, s)| s.line_type.clone())
        .unwrap_or_default();
    let bottom_d = types[bottom_type].1.hydrodynamic_diameter_m;
    let (k_row, k_bot) = opt.k_bot_pa_per_m.unwrap_or((0, 3.0e6));
    let seabed = SeabedSpec {
        normal_stiffness_n_per_m2: k_bot * bottom_d,
        friction_coefficient: opt.friction,
        ..SeabedSpec::default()
    };
    notes.push(DeckNote {
        row: k_row,
        message: format!(
            "seabed stiffness kBot {k_bot} Pa/m × Diam {bottom_d} m of {bottom_type} (the \
             anchor-side type) = {} N/m² for every line type",
            seabed.normal_stiffness_n_per_m2
        ),
    });

    let used_types: BTreeMap<String, LineTypeSpec> = makeup
        .iter()
        .map(|(_, s)| (s.line_type.clone(), types[&s.line_type].1.clone()))
        .collect();
    let case = CaseSpec {
        about: Some(format!(
            "Imported from a MoorDyn v2 deck: {} line(s) of {} segment(s); moorfret line ids are \
             the MoorDyn ids of the lines at the fairleads.",
            chains.len(),
            makeup.len()
        )),
        name: settings.name.clone(),
        site: SiteSpec {
            water_depth_m,
            water_density_kg_m3: opt.density_kg_m3,
            gravity_m_s2: opt.gravity_m_s2,
            seabed,
        },
        sea_state: SeaStateSpec::default(),
        timing: TimingSpec {
            transient_s: 0.0,
            duration_s: settings.duration_s,
            time_step_s: settings.time_step_s,
            output_interval_s: settings.time_step_s,
            wave_ramp_s: 0.0,
            spectral_radius: crate::mooring::dynamics::DynamicParams::default().spectral_radius,
        },
        floater: settings.floater.clone(),
        mooring: MooringSpec {
            line_types: used_types,
            segments: makeup.into_iter().map(|(_, s)| s).collect(),
            fairlead_radius_m: radius,
            fairlead_depth_m: depth,
            anchor_horizontal_distance_m: reach,
            lines: layout
                .iter()
                .map(|p| LineLayoutSpec {
                    id: p.id,
                    fairlead_azimuth_deg: p.azimuth_rad.to_degrees(),
                })
                .collect(),
        },
        hot_spots: settings.hot_spots.clone(),
        wind: WindSpec {
            law: None,
            wind_speed_m_s: Some(0.0),
            thrust_table: None,
            thrust_scale: 1.0,
        },
    };
    case.validate()
        .map_err(|e| refuse(0, format!("the imported case is not valid: {e}")))?;
    notes.sort_by_key(|n| n.row);
    Ok(Imported { case, notes })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two lines of chain – rope – chain joined by free points, the lower joint with a clump.
    const DECK: &str = "\
--------------------- MoorDyn Input File ------------------------------------
two-line test deck
---------------------- LINE TYPES --------------------------------------------
TypeName  Diam   Mass/m  EA      BA/-zeta  EI    Cd   Ca   CdAx  CaAx
(name)    (m)    (kg/m)  (N)     (N-s/-)   (N-m^2) (-) (-) (-)   (-)
chain     0.13   110.0   4.9e8   -1        0     2.4  1.0  0.4   0.5
rope      0.05   16.0    3.6e8   0         8e4   1.2  1.0  0.008 0.0
---------------------- POINTS ------------------------------------------------
ID  Attachment  X      Y     Z      Mass   Volume  CdA  Ca
(#) (-)         (m)    (m)   (m)    (kg)   (m^3)   (m^2) (-)
1   Fixed       520    0     -100   0      0       0    0
2   Free        200    0     -60    1000   0.2     0    0
3   Free        60     0     -20    0      0       0    0
4   Vessel      20     0     -14    0      0       0    0
5   Fixed       0      520   -100   0      0       0    0
6   Free        0      200   -60    1000   0.2     0    0
7   Free        0      60    -20    0      0       0    0
8   Vessel      0      20    -14    0      0       0    0
---------------------- LINES -------------------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
1   chain     1        2        330       20       -
2   rope      2        3        150       10       -
3   chain     3        4        50        5        -
4   chain     5        6        330       20       -
5   rope      6        7        150       10       -
6   chain     7        8        50        5        -
---------------------- OPTIONS -----------------------------------------------
0.001    dtM       ! time step
100      WtrDpth
1025     rho
9.80665  g
3.0e6    kBot
3.0e5    cBot
----------------------- OUTPUTS ----------------------------------------------
FAIRTEN1
------------------------- need this line -------------------------------------
";

    fn settings() -> ImportSettings {
        ImportSettings {
            name: "deck".into(),
            floater: FloaterSource::PrescribedMotion {
                csv_path: "motion.csv".into(),
            },
            time_step_s: 0.1,
            duration_s: 10.0,
            hot_spots: vec![],
        }
    }

    #[test]
    fn deck_maps_onto_one_makeup_and_a_radial_layout() {
        let imported = import(DECK, &settings()).unwrap();
        let c = &imported.case;
        assert_eq!(c.validate(), Ok(()));
        assert!(c.sea_state.is_calm());
        let m = &c.mooring;
        assert_eq!(m.lines.len(), 2);
        assert_eq!((m.lines[0].id, m.lines[1].id), (3, 6));
        assert!((m.lines[1].fairlead_azimuth_deg - 90.0).abs() < 1e-12);
        assert_eq!((m.fairlead_radius_m, m.fairlead_depth_m), (20.0, 14.0));
        assert_eq!(m.anchor_horizontal_distance_m, 500.0);
        // Fairlead first: chain 50, rope 150, clump element of chain 330/20, chain rest.
        let kinds: Vec<(&str, f64, usize)> = m
            .segments
            .iter()
            .map(|s| (s.line_type.as_str(), s.length_m, s.elements))
            .collect();
        assert_eq!(
            kinds,
            [
                ("chain", 50.0, 5),
                ("rope", 150.0, 10),
                ("chain", 16.5, 1),
                ("chain", 313.5, 19)
            ]
        );
        assert_eq!(m.segments[2].extra_mass_kg, Some(1000.0));
        assert_eq!(m.segments[2].extra_volume_m3, Some(0.2));
        let chain = &m.line_types["chain"];
        let w = (110.0 - 1025.0 * PI * 0.13 * 0.13 / 4.0) * 9.80665;
        assert!((chain.submerged_weight_n_per_m - w).abs() < 1e-9);
        assert!((chain.drag_tangential - 0.4 * PI).abs() < 1e-12);
        assert_eq!(c.site.seabed.normal_stiffness_n_per_m2, 3.0e6 * 0.13);
        let text: Vec<String> = imported.notes.iter().map(ToString::to_string).collect();
        let has = |row: usize, what: &str| {
            assert!(
                text.iter()
                    .any(|n| n.starts_with(&format!("deck row {row}: ")) && n.contains(what)),
                "no note '{what}' at row {row} in {text:#?}"
            );
        };
        has(6, "BA/-zeta -1");
        has(12, "point mass 1000 kg");
        has(29, "dtM");
        has(34, "cBot");
        has(35, "OUTPUTS not imported");
    }

    #[test]
    fn unsupported_features_are_refused_by_their_row() {
        let refused = |from: &str, to: &str| {
            import(&DECK.replacen(from, to, 1), &settings())
                .unwrap_err()
                .to_string()
        };
        let e = refused("4.9e8 ", "4.9e8|5e8 ");
        assert!(
            e.starts_with("deck row 6: EA '4.9e8|5e8': a non-linear"),
            "{e}"
        );
        let e = refused("2   rope      2        3", "2   rope      2        R1A");
        assert!(
            e.starts_with("deck row 23: AttachB R1A is a rod end"),
            "{e}"
        );
        // A different make-up on the second line.
        let e = refused(
            "5   rope      6        7        150",
            "5   rope      6        7        151",
        );
        assert!(e.starts_with("deck row 26: this line differs"), "{e}");
        // An anchor off the radial direction.
        let e = refused("5   Fixed       0      520", "5   Fixed       10     520");
        assert!(e.starts_with("deck row 15: the anchor"), "{e}");
        let e = refused("LINE TYPES", "LINE DICTIONARY");
        assert!(
            e.starts_with("deck row 3: section 'LINE DICTIONARY' belongs to a MoorDyn v1"),
            "{e}"
        );
        let e = refused("1   Fixed       520", "1   Moving      520");
        assert!(e.starts_with("deck row 11: attachment 'moving'"), "{e}");
    }
}
