//! Planning (ARCHITECTURE.md, "Data flow of a campaign"): scatter diagram → sea states → jobs.
//!
//! Every non-zero cell becomes a sea state with Hs at the centre of its bin and Tp of its
//! column; its occurrence fraction of the year is `cell / 100` for joint-percent tables and
//! `cell / 100 × share / 100` for a sector table. Realisation seeds are drawn once, here, from
//! the campaign seed (SplitMix64, Steele, Lea & Flood 2014) and stored with the sea state, so a
//! resume never changes them.
//!
//! Jobs: one `global` per (sea state, seed), then one `strand` per (sea state, seed, hot spot)
//! depending on it. Strand jobs have the higher priority so that started sea states finish (and
//! count as covered) before new ones start. With `simulation.extra_seeds`, every sea state also
//! gets the jobs of its extra seeds, gated on the first seeds' strand results
//! (`moorfret_campaign::seeds`); their seeds are drawn after every sea state's first ones.
//!
//! Expected costs (s, on one core of a 2-core machine) are rough, for the scheduler only:
//! global 0.03 s per time step (`cargo bench --bench global`: 27 ms per 0.1 s step of the
//! paper case); strand 5 ms per wire per load sample, which is the target of a 1000 s
//! six-layer history in 10 min (`docs/benchmarks.md`) at 0.1 s sampling.

use moorfret_solver::waves::scatter::ScatterTable;

use moorfret_campaign::fidelity::StrandFidelity;
use moorfret_campaign::payload::{
    cache_key, CalibratePayload, CampaignInputs, GlobalPayload, StrandPayload,
};
use moorfret_campaign::spec::ScatterReading;
use moorfret_campaign::ResolvedCampaign;
use moorfret_store::{CampaignId, JobId, NewCampaign, Store, StoreError};
use moorfret_store::{JobKind, NewSeaState, PlannedJob, SeaStateId};

/// Cost of one global time step (s).
const GLOBAL_STEP_COST_S: f64 = 0.03;
/// Cost of one strand load sample per wire (s).
const STRAND_SAMPLE_WIRE_COST_S: f64 = 5e-3;
/// Cost of a calibration of the reduced strand response, as a fraction of an FE strand job's
/// (six-layer strand: 9.4 min against 12-17 min, docs/reduced-strand.md).
const CALIBRATION_COST_FRACTION: f64 = 0.7;
/// Cost of a reduced strand job, as a fraction of an FE strand job's (≈ 2 s against 12-17 min).
const REDUCED_COST_FRACTION: f64 = 3e-3;

/// Occurrence fraction of the year of a cell value.
pub fn occurrence_fraction(value: f64, reading: ScatterReading) -> f64 {
    match reading {
        ScatterReading::JointPercent => value / 100.0,
        ScatterReading::Sector { share_percent } => value / 100.0 * share_percent / 100.0,
    }
}

/// SplitMix64 step: the next state and its output.
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The sea states of a scatter diagram: non-zero cells in table order, seeds drawn from
/// `campaign_seed`: first `seeds_per_sea_state` for every sea state in turn, then
/// `extra_seeds` more for every sea state in turn (so the first seeds do not depend on them).
pub fn sea_states(
    table: &ScatterTable,
    reading: ScatterReading,
    seeds_per_sea_state: u32,
    extra_seeds: u32,
    campaign_seed: u64,
) -> Vec<NewSeaState> {
    let climate = [ClimateTable {
        table,
        reading,
        heading_deg: 0.0,
        sector: None,
    }];
    climate_sea_states(&climate, seeds_per_sea_state, extra_seeds, campaign_seed)
}

/// One table of a campaign's climate, as planned.
#[derive(Debug, Clone, Copy)]
pub struct ClimateTable<'a> {
    /// The table.
    pub table: &'a ScatterTable,
    /// How its cells are read.
    pub reading: ScatterReading,
    /// Heading of its sea states (deg).
    pub heading_deg: f64,
    /// Its sector's label, if the climate is directional.
    pub sector: Option<&'a str>,
}

/// The sea states of a climate's tables, in table order and each table's cell order, numbered
/// through; seeds drawn from `campaign_seed` as [`sea_states`] does, over all tables: a
/// climate of one table plans exactly what [`sea_states`] plans from it.
pub fn climate_sea_states(
    climate: &[ClimateTable<'_>],
    seeds_per_sea_state: u32,
    extra_seeds: u32,
    campaign_seed: u64,
) -> Vec<NewSeaState> {
    let mut rng = campaign_seed;
    // Seeds stay below 2^63 so they survive databases with signed 64-bit integers.
    let mut draw = |n: u32| -> Vec<u64> { (0..n).map(|_| splitmix64(&mut rng) >> 1).collect() };
    let mut states: Vec<NewSeaState> = climate
        .iter()
        .flat_map(|t| {
            t.table
                .cells()
                .into_iter()
                .filter(|c| c.value > 0.0)
                .map(move |c| (t, c))
        })
        .enumerate()
        .map(|(index, (t, c))| NewSeaState {
            index: index as i64,
            hs_m: 0.5 * (c.hs_lower_m + c.hs_upper_m),
            tp_s: c.tp_s,
            occurrence_fraction: occurrence_fraction(c.value, t.reading),
            seeds: draw(seeds_per_sea_state),
            heading_deg: t.heading_deg,
            sector: t.sector.map(str::to_owned),
            wave_energy_kept: None,
        })
        .collect();
    for state in &mut states {
        state.seeds.extend(draw(extra_seeds));
    }
    states
}

/// The heading a global job's payload carries: none when its sea state runs at the campaign's
/// `simulation.heading_deg` (so one-direction campaigns keep their cache keys), else the
/// sector's.
fn payload_heading(inputs: &CampaignInputs, sea_state: &NewSeaState) -> Option<f64> {
    (sea_state.heading_deg != inputs.spec.simulation.heading_deg).then_some(sea_state.heading_deg)
}

/// Extra seeds per sea state of the campaign's `simulation.extra_seeds` (0 without the rule).
pub fn extra_seeds_per_sea_state(inputs: &CampaignInputs) -> u32 {
    let sim = &inputs.spec.simulation;
    sim.extra_seeds
        .map_or(0, |e| e.seeds.saturating_sub(sim.seeds_per_sea_state))
}

/// Expected cost of a global job (s).
pub fn global_cost_s(inputs: &CampaignInputs) -> f64 {
    let sim = &inputs.spec.simulation;
    (sim.transient_s + sim.duration_s) / sim.time_step_s * GLOBAL_STEP_COST_S
}

/// Expected cost of a strand job (s).
pub fn strand_cost_s(inputs: &CampaignInputs) -> f64 {
    let wires = 1 + inputs
        .profile
        .layers
        .as_ref()
        .map_or(0, |l| l.iter().map(|l| l.wires.unwrap_or(0)).sum::<usize>());
    let samples = inputs.spec.simulation.duration_s / inputs.spec.strand.load_interval_s;
    samples * wires as f64 * STRAND_SAMPLE_WIRE_COST_S
}

/// The jobs of a campaign; `ids` are the stored ids of `sea_states`, in order.
///
/// `strand.fidelity = fe`: per (sea state, seed) a global job and one FE strand job per hot
/// spot. `reduced`: every global job, then per hot spot a calibration job depending on all of
/// them, then one reduced strand job per (sea state, seed, hot spot) depending on its global
/// job and its hot spot's calibration. `auto`: as `reduced`, plus one FE strand job per
/// (sea state, seed, hot spot) depending on every reduced job of its hot spot, which runs only
/// if the reduced results select its sea state (`moorfret_campaign::fidelity`).
///
/// With `simulation.extra_seeds`, the seeds of a sea state beyond the first
/// `seeds_per_sea_state` are extra seeds (`moorfret_campaign::seeds`), planned after every
/// other job: per (sea state, extra seed) a global job depending on every first-seed strand job
/// whose rows the selection reads (FE strand jobs with `fe`, reduced ones with `reduced` and
/// `auto`), and per hot spot a strand job of that kind depending on it (and on its hot spot's
/// calibration). All carry `extra_seed`; the global job's cache key is over every campaign
/// input, as whether it runs depends on them.
pub fn jobs(
    inputs: &CampaignInputs,
    inputs_sha256: &str,
    sea_states: &[NewSeaState],
    ids: &[SeaStateId],
) -> Vec<PlannedJob> {
    let hot_spots = inputs.spec.hot_spots.len();
    let seeds: usize = sea_states.iter().map(|s| s.seeds.len()).sum();
    let mut out = Vec::with_capacity(seeds * (1 + 2 * hot_spots) + hot_spots);
    let (global_cost, strand_cost) = (global_cost_s(inputs), strand_cost_s(inputs));
    let max_attempts = inputs.spec.jobs.max_attempts;
    let fidelity = inputs.spec.strand.fidelity;
    let global_sha256 = inputs.global_sha256();
    let first_seeds = if inputs.spec.simulation.extra_seeds.is_some() {
        inputs.spec.simulation.seeds_per_sea_state as usize
    } else {
        usize::MAX
    };
    // (index in `out`, sea state id, payload, cache key) of every global job
    let mut globals = Vec::with_capacity(seeds);
    // first-seed strand jobs whose rows select the extra seeds' sea states
    let mut first_strand = Vec::new();
    for (sea_state, &id) in sea_states.iter().zip(ids) {
        for (seed_index, &seed) in sea_state.seeds.iter().enumerate().take(first_seeds) {
            let global = GlobalPayload {
                sea_state_index: sea_state.index as usize,
                hs_m: sea_state.hs_m,
                tp_s: sea_state.tp_s,
                seed_index,
                seed,
                extra_seed: false,
                heading_deg: payload_heading(inputs, sea_state),
            };
            let global_json = serde_json::to_value(&global).unwrap_or_default();
            let global_key = cache_key("global", &global_sha256, &global_json.to_string());
            let global_index = out.len();
            globals.push((global_index, id, global.clone(), global_key.clone()));
            out.push(PlannedJob {
                sea_state: Some(id),
                priority: 0,
                expected_cost_s: global_cost,
                max_attempts,
                cache_key: Some(global_key.clone()),
                ..PlannedJob::new(JobKind::Global, global_json)
            });
            if fidelity.uses_reduced() {
                continue;
            }
            for hot_spot_index in 0..hot_spots {
                let strand = StrandPayload {
                    global: global.clone(),
                    hot_spot_index,
                    global_cache_key: global_key.clone(),
                    calibration_cache_key: None,
                    if_selected: false,
                };
                first_strand.push(out.len());
                out.push(strand_job(
                    JobKind::Strand,
                    &strand,
                    inputs_sha256,
                    strand_cost,
                    max_attempts,
                    Some(id),
                    vec![global_index],
                ));
            }
        }
    }
    if !fidelity.uses_reduced() {
        push_extra_seeds(
            &mut out,
            inputs,
            inputs_sha256,
            sea_states,
            ids,
            &first_strand,
            &[],
        );
        return out;
    }
    let early = early_calibration_globals(&globals, inputs.spec.strand.calibration_hs_fraction);
    if early.len() < globals.len() {
        // the globals the calibration waits for run first
        for &g in &early {
            out[globals[g].0].priority = 1;
        }
    }
    let calibration_job = |out: &mut Vec<PlannedJob>, payload: CalibratePayload, deps| {
        let json = serde_json::to_value(&payload).unwrap_or_default();
        let key = cache_key("calibrate", inputs_sha256, &json.to_string());
        out.push(PlannedJob {
            sea_state: None,
            priority: 2,
            expected_cost_s: CALIBRATION_COST_FRACTION * strand_cost,
            max_attempts,
            cache_key: Some(key.clone()),
            depends_on: deps,
            ..PlannedJob::new(JobKind::Calibrate, json)
        });
        (out.len() - 1, key)
    };
    // (indices in `out`, cache keys) of the global jobs at `positions` in `globals`
    let keys_of = |positions: &[usize]| -> (Vec<usize>, Vec<String>) {
        positions
            .iter()
            .map(|&g| (globals[g].0, globals[g].3.clone()))
            .unzip()
    };
    let (global_indices, global_keys) = keys_of(&(0..globals.len()).collect::<Vec<_>>());
    let mut calibrations = Vec::with_capacity(hot_spots);
    // with a shared calibration, hot spot 0's calibration covers every hot spot's range
    let shared = inputs.spec.strand.shared_calibration && hot_spots > 1;
    let calibrated = if shared { 1 } else { hot_spots };
    for hot_spot_index in 0..calibrated {
        let shared_with: Vec<usize> = if shared {
            (1..hot_spots).collect()
        } else {
            Vec::new()
        };
        let everything = CalibratePayload {
            hot_spot_index,
            global_cache_keys: global_keys.clone(),
            shared_with: shared_with.clone(),
            check_of: None,
        };
        if early.len() == globals.len() {
            calibrations.push(calibration_job(
                &mut out,
                everything,
                global_indices.clone(),
            ));
            continue;
        }
        let (early_indices, early_keys) = keys_of(&early);
        let first = CalibratePayload {
            hot_spot_index,
            global_cache_keys: early_keys,
            shared_with,
            check_of: None,
        };
        let (first_index, first_key) = calibration_job(&mut out, first, early_indices);
        let check = CalibratePayload {
            check_of: Some(first_key),
            ..everything
        };
        let mut deps = global_indices.clone();
        deps.push(first_index);
        calibrations.push(calibration_job(&mut out, check, deps));
    }
    if shared {
        let one = calibrations[0].clone();
        calibrations.resize(hot_spots, one);
    }
    let mut reduced_of_hot_spot = vec![Vec::with_capacity(globals.len()); hot_spots];
    for (global_index, id, global, global_key) in &globals {
        for (hot_spot_index, (calibration_index, calibration_key)) in
            calibrations.iter().enumerate()
        {
            let strand = StrandPayload {
                global: global.clone(),
                hot_spot_index,
                global_cache_key: global_key.clone(),
                calibration_cache_key: Some(calibration_key.clone()),
                if_selected: false,
            };
            reduced_of_hot_spot[hot_spot_index].push(out.len());
            first_strand.push(out.len());
            out.push(strand_job(
                JobKind::StrandReduced,
                &strand,
                inputs_sha256,
                REDUCED_COST_FRACTION * strand_cost,
                max_attempts,
                Some(*id),
                vec![*global_index, *calibration_index],
            ));
        }
    }
    if fidelity == StrandFidelity::Auto {
        push_auto_fe(
            &mut out,
            inputs,
            inputs_sha256,
            &globals,
            &reduced_of_hot_spot,
        );
    }
    push_extra_seeds(
        &mut out,
        inputs,
        inputs_sha256,
        sea_states,
        ids,
        &first_strand,
        &calibrations,
    );
    out
}

/// The first-seed global jobs (positions in `globals`) whose load range the calibration of
/// the reduced response starts from: those of the sea states with Hs ≥ `hs_fraction` × the
/// largest Hs, and those of the smallest Hs (every one with 0). The largest seas set the
/// dynamic extremes of tension and curvature; the mildest sit at the mooring's static
/// equilibrium, where the hot spot's tension is lowest on average and, near the touch-down,
/// its curvature highest (a short demo campaign's mild cell reaches 1.6× the curvature of its
/// largest seas). The others run beside the calibration; a check job tests them against it.
fn early_calibration_globals(
    globals: &[(usize, SeaStateId, GlobalPayload, String)],
    hs_fraction: f64,
) -> Vec<usize> {
    let hs = |g: usize| globals[g].2.hs_m;
    let largest = (0..globals.len()).map(hs).fold(0.0, f64::max);
    let smallest = (0..globals.len()).map(hs).fold(f64::INFINITY, f64::min);
    (0..globals.len())
        .filter(|&g| hs(g) >= hs_fraction * largest || hs(g) == smallest)
        .collect()
}

/// The FE strand jobs of an `auto` campaign (see [`jobs`]).
fn push_auto_fe(
    out: &mut Vec<PlannedJob>,
    inputs: &CampaignInputs,
    inputs_sha256: &str,
    globals: &[(usize, SeaStateId, GlobalPayload, String)],
    reduced_of_hot_spot: &[Vec<usize>],
) {
    let (strand_cost, max_attempts) = (strand_cost_s(inputs), inputs.spec.jobs.max_attempts);
    for (global_index, id, global, global_key) in globals {
        for (hot_spot_index, reduced) in reduced_of_hot_spot.iter().enumerate() {
            let strand = StrandPayload {
                global: global.clone(),
                hot_spot_index,
                global_cache_key: global_key.clone(),
                calibration_cache_key: None,
                if_selected: true,
            };
            let mut depends_on = Vec::with_capacity(1 + reduced.len());
            depends_on.push(*global_index);
            depends_on.extend(reduced);
            out.push(strand_job(
                JobKind::Strand,
                &strand,
                inputs_sha256,
                strand_cost,
                max_attempts,
                Some(*id),
                depends_on,
            ));
        }
    }
}

/// The jobs of the extra seeds (see [`jobs`]): `first_strand` are the first-seed strand jobs
/// the selection reads, `calibrations` the (index, cache key) of each hot spot's calibration
/// (empty with `fe`).
fn push_extra_seeds(
    out: &mut Vec<PlannedJob>,
    inputs: &CampaignInputs,
    inputs_sha256: &str,
    sea_states: &[NewSeaState],
    ids: &[SeaStateId],
    first_strand: &[usize],
    calibrations: &[(usize, String)],
) {
    if inputs.spec.simulation.extra_seeds.is_none() {
        return;
    }
    let first_seeds = inputs.spec.simulation.seeds_per_sea_state as usize;
    let max_attempts = inputs.spec.jobs.max_attempts;
    let (global_cost, strand_cost) = (global_cost_s(inputs), strand_cost_s(inputs));
    let reduced = inputs.spec.strand.fidelity.uses_reduced();
    for (sea_state, &id) in sea_states.iter().zip(ids) {
        for (seed_index, &seed) in sea_state.seeds.iter().enumerate().skip(first_seeds) {
            let global = GlobalPayload {
                sea_state_index: sea_state.index as usize,
                hs_m: sea_state.hs_m,
                tp_s: sea_state.tp_s,
                seed_index,
                seed,
                extra_seed: true,
                heading_deg: payload_heading(inputs, sea_state),
            };
            let global_json = serde_json::to_value(&global).unwrap_or_default();
            let global_key = cache_key("global", inputs_sha256, &global_json.to_string());
            let global_index = out.len();
            out.push(PlannedJob {
                sea_state: Some(id),
                priority: 0,
                expected_cost_s: global_cost,
                max_attempts,
                cache_key: Some(global_key.clone()),
                depends_on: first_strand.to_vec(),
                ..PlannedJob::new(JobKind::Global, global_json)
            });
            for hot_spot_index in 0..inputs.spec.hot_spots.len() {
                let calibration = calibrations.get(hot_spot_index);
                let strand = StrandPayload {
                    global: global.clone(),
                    hot_spot_index,
                    global_cache_key: global_key.clone(),
                    calibration_cache_key: calibration.map(|c| c.1.clone()),
                    if_selected: false,
                };
                let (kind, cost) = if reduced {
                    (JobKind::StrandReduced, REDUCED_COST_FRACTION * strand_cost)
                } else {
                    (JobKind::Strand, strand_cost)
                };
                let mut depends_on = vec![global_index];
                depends_on.extend(calibration.map(|c| c.0));
                out.push(strand_job(
                    kind,
                    &strand,
                    inputs_sha256,
                    cost,
                    max_attempts,
                    Some(id),
                    depends_on,
                ));
            }
        }
    }
}

/// A strand job (FE or reduced) of `payload`.
fn strand_job(
    kind: JobKind,
    payload: &StrandPayload,
    inputs_sha256: &str,
    expected_cost_s: f64,
    max_attempts: i64,
    sea_state: Option<SeaStateId>,
    depends_on: Vec<usize>,
) -> PlannedJob {
    let json = serde_json::to_value(payload).unwrap_or_default();
    PlannedJob {
        sea_state,
        priority: 1,
        expected_cost_s,
        max_attempts,
        cache_key: Some(cache_key(kind.as_str(), inputs_sha256, &json.to_string())),
        depends_on,
        ..PlannedJob::new(kind, json)
    }
}

/// The sea states of a resolved campaign, in plan order: its tables in turn.
pub fn campaign_sea_states(resolved: &ResolvedCampaign) -> Vec<NewSeaState> {
    let inputs = &resolved.inputs;
    let climate: Vec<ClimateTable<'_>> = resolved
        .sectors
        .iter()
        .map(|s| ClimateTable {
            table: &s.table,
            reading: s.source.reading,
            heading_deg: s.source.heading_deg,
            sector: s.source.label.as_deref(),
        })
        .collect();
    let mut states = climate_sea_states(
        &climate,
        inputs.spec.simulation.seeds_per_sea_state,
        extra_seeds_per_sea_state(inputs),
        inputs.spec.seed,
    );
    // Resolution checked every planned cell in the same order (tables in turn, each row by
    // row): each sea state stores the energy its wave cut-off keeps.
    for (state, limits) in states.iter_mut().zip(resolved.planned_limits()) {
        if state.hs_m == limits.hs_m && state.tp_s == limits.tp_s {
            state.wave_energy_kept = Some(limits.energy_kept);
        }
    }
    states
}

/// Stores `resolved` with its sea states and jobs in one transaction; returns the campaign and
/// its job ids.
pub async fn create(
    store: &Store,
    resolved: &ResolvedCampaign,
) -> Result<(CampaignId, Vec<JobId>), StoreError> {
    let inputs = &resolved.inputs;
    let (spec, spec_sha256) = resolved.stored_spec();
    let sea_states = campaign_sea_states(resolved);
    let inputs_sha256 = inputs.results_sha256();
    let campaign = NewCampaign {
        name: inputs.spec.name.clone(),
        spec,
        spec_sha256,
    };
    store
        .create_planned_campaign(&campaign, &sea_states, |ids| {
            jobs(inputs, &inputs_sha256, &sea_states, ids)
        })
        .await
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = "lower\tupper\t5\t7\ttotal\n0\t1\t0\t2,5\t2,5\n1\t2\t1,5\t0\t1,5\n";

    #[test]
    fn non_zero_cells_become_sea_states_at_bin_centres() {
        let table = ScatterTable::parse(TABLE).unwrap();
        let states = sea_states(&table, ScatterReading::JointPercent, 2, 0, 7);
        assert_eq!(states.len(), 2);
        assert_eq!((states[0].hs_m, states[0].tp_s), (0.5, 7.0));
        assert_eq!((states[1].hs_m, states[1].tp_s), (1.5, 5.0));
        assert!((states[0].occurrence_fraction - 0.025).abs() < 1e-15);
        assert_eq!(states[0].seeds.len(), 2);
        assert_ne!(states[0].seeds[0], states[0].seeds[1]);
        assert_ne!(states[0].seeds[0], states[1].seeds[0]);
        // drawn once from the campaign seed: the same seed gives the same plan
        assert_eq!(
            states,
            sea_states(&table, ScatterReading::JointPercent, 2, 0, 7)
        );
    }

    #[test]
    fn sector_cells_are_scaled_by_the_sector_share() {
        let f = occurrence_fraction(
            10.0,
            ScatterReading::Sector {
                share_percent: 43.758,
            },
        );
        assert!((f - 0.043758).abs() < 1e-15);
    }

    /// The demo campaign's inputs with `fidelity`, and its planned jobs over its sea states.
    fn planned(fidelity: StrandFidelity) -> Vec<PlannedJob> {
        planned_from(fidelity, 0.0)
    }

    /// The demo campaign, two seeds per sea state, with `fidelity` and the calibration's Hs
    /// fraction, planned.
    fn planned_from(fidelity: StrandFidelity, hs_fraction: f64) -> Vec<PlannedJob> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/demo.json");
        let mut resolved = moorfret_campaign::resolve(&path).unwrap();
        resolved.inputs.spec.strand.fidelity = fidelity;
        resolved.inputs.spec.strand.calibration_hs_fraction = hs_fraction;
        let inputs = &resolved.inputs;
        let states = sea_states(
            &resolved.sectors[0].table,
            resolved.sectors[0].source.reading,
            2,
            0,
            1,
        );
        let ids: Vec<SeaStateId> = (0..states.len() as i64).map(SeaStateId).collect();
        jobs(inputs, &inputs.results_sha256(), &states, &ids)
    }

    #[test]
    fn each_fidelity_plans_its_jobs_with_their_dependencies() {
        // demo: three sea states, here two seeds each, one hot spot
        let fe = planned(StrandFidelity::Fe);
        let kinds = |jobs: &[PlannedJob], k: JobKind| jobs.iter().filter(|j| j.kind == k).count();
        assert_eq!(
            (kinds(&fe, JobKind::Global), kinds(&fe, JobKind::Strand)),
            (6, 6)
        );
        for (i, j) in fe.iter().enumerate() {
            if j.kind == JobKind::Strand {
                assert_eq!(j.depends_on, [i - 1]);
            }
        }
        let auto = planned(StrandFidelity::Auto);
        assert_eq!(kinds(&auto, JobKind::Global), 6);
        assert_eq!(kinds(&auto, JobKind::Calibrate), 1);
        assert_eq!(kinds(&auto, JobKind::StrandReduced), 6);
        assert_eq!(kinds(&auto, JobKind::Strand), 6);
        let globals: Vec<usize> = (0..auto.len())
            .filter(|&i| auto[i].kind == JobKind::Global)
            .collect();
        let calibration = auto
            .iter()
            .position(|j| j.kind == JobKind::Calibrate)
            .unwrap();
        assert_eq!(auto[calibration].depends_on, globals);
        assert_eq!(auto[calibration].sea_state, None);
        let reduced: Vec<usize> = (0..auto.len())
            .filter(|&i| auto[i].kind == JobKind::StrandReduced)
            .collect();
        for (k, &i) in reduced.iter().enumerate() {
            assert_eq!(auto[i].depends_on, [globals[k], calibration]);
            let p: StrandPayload = serde_json::from_value(auto[i].payload.clone()).unwrap();
            assert!(p.calibration_cache_key.is_some() && !p.if_selected);
        }
        for j in auto.iter().filter(|j| j.kind == JobKind::Strand) {
            let p: StrandPayload = serde_json::from_value(j.payload.clone()).unwrap();
            assert!(p.if_selected && p.calibration_cache_key.is_none());
            assert_eq!(j.depends_on.len(), 1 + reduced.len());
            assert!(reduced.iter().all(|r| j.depends_on.contains(r)));
        }
        // global jobs do not depend on the strand settings: both plans share their keys
        let global_keys = |jobs: &[PlannedJob]| -> Vec<String> {
            jobs.iter()
                .filter(|j| j.kind == JobKind::Global)
                .filter_map(|j| j.cache_key.clone())
                .collect()
        };
        assert_eq!(global_keys(&fe), global_keys(&auto));
        assert!(fe
            .iter()
            .filter(|j| j.kind == JobKind::Strand)
            .all(|j| !auto.iter().any(|a| a.cache_key == j.cache_key)));
        // every job has a cache key of its own; the FE plan's keys are not the auto plan's
        let mut keys: Vec<&String> = auto.iter().filter_map(|j| j.cache_key.as_ref()).collect();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), auto.len());
        let reduced_only = planned(StrandFidelity::Reduced);
        assert_eq!(kinds(&reduced_only, JobKind::Strand), 0);
        assert_eq!(reduced_only.len(), 6 + 1 + 6);
    }

    #[test]
    fn a_shared_calibration_serves_every_hot_spot() {
        use moorfret_campaign::screening::HotSpots;
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/demo.json");
        let mut resolved = moorfret_campaign::resolve(&path).unwrap();
        let spec = &mut resolved.inputs.spec;
        spec.strand.fidelity = StrandFidelity::Reduced;
        let first = spec.hot_spots[0].clone();
        spec.hot_spots = HotSpots::Listed(vec![first.clone(), first.clone(), first]);
        let states = sea_states(
            &resolved.sectors[0].table,
            resolved.sectors[0].source.reading,
            1,
            0,
            1,
        );
        let ids: Vec<SeaStateId> = (0..states.len() as i64).map(SeaStateId).collect();
        let plan = |inputs: &CampaignInputs| jobs(inputs, &inputs.results_sha256(), &states, &ids);
        let calibrations = |jobs: &[PlannedJob]| -> Vec<(usize, CalibratePayload)> {
            (0..jobs.len())
                .filter(|&i| jobs[i].kind == JobKind::Calibrate)
                .map(|i| (i, serde_json::from_value(jobs[i].payload.clone()).unwrap()))
                .collect()
        };
        // one per hot spot by default, with keys unchanged by the new setting
        let own = plan(&resolved.inputs);
        assert_eq!(calibrations(&own).len(), 3);
        assert!(calibrations(&own)
            .iter()
            .all(|(_, c)| c.shared_with.is_empty()));
        let own_json = serde_json::to_string(&resolved.inputs.spec.strand).unwrap();
        assert!(!own_json.contains("shared_calibration"));
        resolved.inputs.spec.strand.shared_calibration = true;
        let shared = plan(&resolved.inputs);
        let one = calibrations(&shared);
        assert_eq!(one.len(), 1);
        let (index, payload) = &one[0];
        assert_eq!(
            (payload.hot_spot_index, &payload.shared_with[..]),
            (0, &[1, 2][..])
        );
        let key = shared[*index].cache_key.clone();
        let reduced: Vec<StrandPayload> = shared
            .iter()
            .filter(|j| j.kind == JobKind::StrandReduced)
            .map(|j| {
                assert!(j.depends_on.contains(index));
                serde_json::from_value(j.payload.clone()).unwrap()
            })
            .collect();
        assert_eq!(reduced.len(), 3 * states.len());
        assert!(reduced.iter().all(|p| p.calibration_cache_key == key));
        for h in 0..3 {
            assert_eq!(
                reduced.iter().filter(|p| p.hot_spot_index == h).count(),
                states.len()
            );
        }
        // with an early calibration, the first and its check are both shared
        resolved.inputs.spec.strand.calibration_hs_fraction = 0.9;
        let early = calibrations(&plan(&resolved.inputs));
        assert_eq!(early.len(), 2);
        assert!(early.iter().all(|(_, c)| c.shared_with == [1, 2]));
    }

    #[test]
    fn the_calibration_starts_from_the_largest_seas_and_a_check_follows_every_global_job() {
        // demo: Hs 2.25, 4.25 and 6.25 m, two seeds each; with 0.9 the first calibration waits
        // for the global jobs of Hs >= 5.625 m and of the smallest Hs only
        let auto = planned_from(StrandFidelity::Auto, 0.9);
        let of_kind =
            |k: JobKind| -> Vec<usize> { (0..auto.len()).filter(|&i| auto[i].kind == k).collect() };
        let globals = of_kind(JobKind::Global);
        let hs = |i: usize| {
            serde_json::from_value::<GlobalPayload>(auto[i].payload.clone())
                .unwrap()
                .hs_m
        };
        let early: Vec<usize> = globals
            .iter()
            .copied()
            .filter(|&g| hs(g) > 6.0 || hs(g) < 2.5)
            .collect();
        assert_eq!((globals.len(), early.len()), (6, 4));
        for &g in &globals {
            assert_eq!(
                auto[g].priority,
                i64::from(early.contains(&g)),
                "global {g}"
            );
        }
        let calibrations = of_kind(JobKind::Calibrate);
        assert_eq!(calibrations.len(), 2);
        let (first, check) = (calibrations[0], calibrations[1]);
        let payload = |i: usize| -> CalibratePayload {
            serde_json::from_value(auto[i].payload.clone()).unwrap()
        };
        let key = |i: usize| auto[i].cache_key.clone().unwrap();
        assert_eq!(auto[first].depends_on, early);
        assert_eq!(
            payload(first).global_cache_keys,
            early.iter().map(|&g| key(g)).collect::<Vec<_>>()
        );
        assert_eq!(payload(first).check_of, None);
        let mut after_all = globals.clone();
        after_all.push(first);
        assert_eq!(auto[check].depends_on, after_all);
        assert_eq!(payload(check).check_of, Some(key(first)));
        assert_eq!(payload(check).global_cache_keys.len(), 6);
        // every reduced job reads the check's calibration
        for (k, &i) in of_kind(JobKind::StrandReduced).iter().enumerate() {
            assert_eq!(auto[i].depends_on, [globals[k], check]);
            let p: StrandPayload = serde_json::from_value(auto[i].payload.clone()).unwrap();
            assert_eq!(p.calibration_cache_key, Some(key(check)));
        }
        // 1: the largest and the smallest sea state; a fraction that leaves out only the
        // smallest sea state: one calibration
        let largest = planned_from(StrandFidelity::Reduced, 1.0);
        let c = largest
            .iter()
            .position(|j| j.kind == JobKind::Calibrate)
            .unwrap();
        assert_eq!(largest[c].depends_on.len(), 4);
        let all = planned_from(StrandFidelity::Reduced, 0.5);
        assert_eq!(
            all.iter().filter(|j| j.kind == JobKind::Calibrate).count(),
            1
        );
        assert!(all
            .iter()
            .filter(|j| j.kind == JobKind::Global)
            .all(|j| j.priority == 0));
    }

    /// The demo campaign (one seed per sea state) with `fidelity` and the extra-seed rule
    /// `seeds` (3 in all, or none), planned: its sea states and jobs.
    fn planned_with_extra(
        fidelity: StrandFidelity,
        extra: Option<u32>,
    ) -> (Vec<NewSeaState>, Vec<PlannedJob>) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/demo.json");
        let mut resolved = moorfret_campaign::resolve(&path).unwrap();
        resolved.inputs.spec.strand.fidelity = fidelity;
        resolved.inputs.spec.simulation.extra_seeds =
            extra.map(|seeds| moorfret_campaign::seeds::ExtraSeeds {
                seeds,
                damage_share: 0.8,
            });
        let inputs = &resolved.inputs;
        assert!(inputs.spec.validate().is_ok());
        let states = sea_states(
            &resolved.sectors[0].table,
            resolved.sectors[0].source.reading,
            inputs.spec.simulation.seeds_per_sea_state,
            extra_seeds_per_sea_state(inputs),
            1,
        );
        let ids: Vec<SeaStateId> = (0..states.len() as i64).map(SeaStateId).collect();
        let jobs = jobs(inputs, &inputs.results_sha256(), &states, &ids);
        (states, jobs)
    }

    #[test]
    fn extra_seeds_are_planned_gated_on_the_first_seeds_strand_jobs() {
        let payload = |j: &PlannedJob| -> GlobalPayload {
            match j.kind {
                JobKind::Global => serde_json::from_value(j.payload.clone()).unwrap(),
                _ => {
                    let p: StrandPayload = serde_json::from_value(j.payload.clone()).unwrap();
                    p.global
                }
            }
        };
        for fidelity in [
            StrandFidelity::Fe,
            StrandFidelity::Reduced,
            StrandFidelity::Auto,
        ] {
            let (plain_states, plain) = planned_with_extra(fidelity, None);
            let (states, jobs) = planned_with_extra(fidelity, Some(3));
            // the first seed of every sea state is the one of the plan without the rule; two
            // more follow
            for (a, b) in plain_states.iter().zip(&states) {
                assert_eq!(b.seeds.len(), 3);
                assert_eq!(a.seeds[..], b.seeds[..1]);
            }
            // the plan without the rule comes first, job for job (strand keys differ: the rule
            // is a campaign input; global keys do not)
            assert_eq!(&jobs[..plain.len()].len(), &plain.len());
            for (a, b) in plain.iter().zip(&jobs) {
                assert_eq!((a.kind, &a.depends_on), (b.kind, &b.depends_on));
                if a.kind == JobKind::Global {
                    assert_eq!(a.cache_key, b.cache_key);
                }
                if b.kind != JobKind::Calibrate {
                    assert!(!payload(b).extra_seed);
                }
            }
            let first_kind = if fidelity == StrandFidelity::Fe {
                JobKind::Strand
            } else {
                JobKind::StrandReduced
            };
            let first_strand: Vec<usize> = (0..plain.len())
                .filter(|&i| jobs[i].kind == first_kind)
                .collect();
            assert_eq!(first_strand.len(), 3);
            let extra = &jobs[plain.len()..];
            // per sea state and extra seed: a global job and one strand job (one hot spot)
            assert_eq!(extra.len(), 3 * 2 * 2, "{fidelity:?}");
            // the extra seeds read the calibration the first seeds' reduced jobs read (the check)
            let calibration = jobs.iter().rposition(|j| j.kind == JobKind::Calibrate);
            for (k, pair) in extra.chunks(2).enumerate() {
                let global_index = plain.len() + 2 * k;
                let (g, st) = (&pair[0], &pair[1]);
                assert_eq!(g.kind, JobKind::Global);
                assert_eq!(g.depends_on, first_strand, "{fidelity:?}");
                let gp = payload(g);
                assert!(gp.extra_seed);
                assert_eq!(gp.seed_index, 1 + k % 2);
                assert_eq!(gp.seed, states[k / 2].seeds[gp.seed_index]);
                assert_eq!(st.kind, first_kind, "extra seeds of auto run reduced only");
                let sp: StrandPayload = serde_json::from_value(st.payload.clone()).unwrap();
                assert!(sp.global.extra_seed && !sp.if_selected);
                assert_eq!(Some(&sp.global_cache_key), g.cache_key.as_ref());
                let mut want = vec![global_index];
                want.extend(calibration);
                assert_eq!(st.depends_on, want);
                assert_eq!(
                    sp.calibration_cache_key.is_some(),
                    fidelity != StrandFidelity::Fe
                );
            }
            // the FE jobs of auto still wait for the first seeds' reduced jobs only
            if fidelity == StrandFidelity::Auto {
                for j in jobs[..plain.len()]
                    .iter()
                    .filter(|j| j.kind == JobKind::Strand)
                {
                    assert!(j.depends_on[1..] == first_strand[..]);
                }
            }
            let mut keys: Vec<&String> = jobs.iter().filter_map(|j| j.cache_key.as_ref()).collect();
            keys.sort();
            keys.dedup();
            assert_eq!(keys.len(), jobs.len());
        }
    }

    #[test]
    fn splitmix_matches_the_reference_sequence() {
        // First outputs for state 0 of the reference implementation (Vigna, splitmix64.c).
        let mut s = 0;
        assert_eq!(splitmix64(&mut s), 0xE220_A839_7B1D_CDAF);
        assert_eq!(splitmix64(&mut s), 0x6E78_9E6A_A1B9_65F4);
    }
}
